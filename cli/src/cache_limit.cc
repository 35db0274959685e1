#include "cache_limit.h"

#include <spdlog/spdlog.h>

#include <cstdlib>
#include <utility>

#include "hcpf/core/error.h"
#include "hcpf/scenarios/cache.h"
#include "hcpf/scenarios/frames.h"
#include "hcpf/scenarios/output_folder.h"

namespace hcpf::cli {

std::string FrameCacheFolder(const std::string& cache, bool cache_given, bool no_cache) {
  if (cache_given && no_cache) {
    throw InputError(SourceLocation{"command line", 0, 0, "--no-cache"},
                     "either --cache DIR or --no-cache", "both (--cache " + cache + ")");
  }
  // The default folder is checked here, naming where it came from: a
  // bad-input audit found HCPF_CACHE_DIR naming a file reported as
  // "--cache: expected a cache folder", an option not given.
  if (!no_cache && !cache_given) {
    scenarios::CheckFolderArgument(cache, scenarios::DefaultFrameCacheSource());
  }
  return no_cache ? "" : cache;
}

CacheLimit::CacheLimit(std::string cache_dir)
    : cache_dir_(std::move(cache_dir)),
      max_bytes_(scenarios::CacheMaxSizeFromEnvironment()),
      // Two seconds early: the kernel stamps a folder's changes with a
      // coarse clock (a tick behind), and an entry used at the start is the
      // command's.
      since_(std::filesystem::file_time_type::clock::now() - std::chrono::seconds(2)) {
  if (max_bytes_) max_text_ = scenarios::CacheMaxSizeText();
  by_default_ = std::getenv(scenarios::kCacheMaxSizeVariable) == nullptr;
}

void CacheLimit::Apply() const {
  if (!active()) return;
  try {
    const scenarios::AutoPrune result =
        scenarios::PruneAfterCommand(cache_dir_, *max_bytes_, since_);
    const std::string line =
        scenarios::DescribeAutoPrune(cache_dir_, result, *max_bytes_, max_text_);
    if (result.left > *max_bytes_ || !result.foreign.empty()) {
      spdlog::warn("{}", line);
    } else if (by_default_ && result.scenes + result.detections == 0) {
      spdlog::debug("{}", line);  // the default limit, nothing to do: every rendered run
    } else {
      spdlog::info("{}", line);
    }
  } catch (const RunError& e) {
    spdlog::warn("frame cache {}: not pruned to {} {}: {}", cache_dir_,
                 scenarios::kCacheMaxSizeVariable, max_text_, e.what());
  }
}

// "off", not unset: unset is the default limit.
void CacheLimit::HideFromChildren() { ::setenv(scenarios::kCacheMaxSizeVariable, "off", 1); }

}  // namespace hcpf::cli
