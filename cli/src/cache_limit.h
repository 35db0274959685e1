#pragma once
// $HCPF_CACHE_MAX_SIZE for the commands that use the frame cache (hcpf run,
// render, sweep): read when the command starts (a bad value is bad input
// before anything runs), applied when it ends (scenarios::PruneAfterCommand:
// the entries used least recently, none used since the command started, or
// in the two seconds before).

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>

namespace hcpf::cli {

// The frame cache folder a command uses: `cache` (--cache, or its default),
// "" with --no-cache. Both options given is bad input (a bad-input audit:
// --cache was ignored, exit 0). `cache_given`: --cache was on the command
// line.
std::string FrameCacheFolder(const std::string& cache, bool cache_given, bool no_cache);

class CacheLimit {
 public:
  // Reads the variable (throws InputError when it cannot); `cache_dir` ""
  // means the command uses no cache.
  explicit CacheLimit(std::string cache_dir);
  // Whether a limit applies (not `off`, and a cache in use).
  bool active() const { return max_bytes_.has_value() && !cache_dir_.empty(); }
  // Prunes and logs what was done (a warning when what is left is over the
  // limit, or when pruning failed: the command's own work is done and stays).
  void Apply() const;
  // Keeps child processes of this one (hcpf sweep --isolate) from pruning
  // as they end: the command that started them prunes once, after them.
  static void HideFromChildren();

 private:
  std::string cache_dir_;
  std::optional<uint64_t> max_bytes_;
  std::string max_text_;
  bool by_default_ = false;  // the variable unset: the default limit
  std::filesystem::file_time_type since_;
};

}  // namespace hcpf::cli
