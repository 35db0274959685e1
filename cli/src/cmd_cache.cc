// hcpf cache [--cache DIR] [--max-size SIZE [--dry-run]] [--verbose]

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "command.h"
#include "hcpf/core/error.h"
#include "hcpf/scenarios/cache.h"
#include "hcpf/scenarios/frames.h"
#include "hcpf/scenarios/output_folder.h"

namespace hcpf::cli {

Command AddCacheCommand(CLI::App& parent) {
  struct Options {
    std::string cache = scenarios::DefaultFrameCacheDir();
    std::string max_size;
    bool dry_run = false;
    bool verbose = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand(
      "cache",
      "Show what the frame and detection caches hold; with --max-size, remove the entries used "
      "least recently until the rest fits");
  CLI::Option* cache =
      app->add_option("--cache", options->cache, "The cache folder (as for hcpf run and sweep)")
          ->capture_default_str();
  CLI::Option* max_size =
      app->add_option("--max-size", options->max_size,
                      "Keep at most this much: bytes or a number with K, M, G or T (500M, 20G)");
  app->add_flag("--dry-run", options->dry_run,
                "With --max-size: list what would be removed, remove nothing")
      ->needs(max_size);
  app->add_flag("--verbose", options->verbose,
                "Also list every detector output, one line each (they are listed together "
                "otherwise)");
  return {
      app, [options, cache, max_size] {
        // Pruning only when --max-size is given (an empty value never
        // reaches here: app.cc refuses empty option values).
        const bool prune = max_size->count() > 0;
        const uint64_t max_bytes =
            prune ? scenarios::ParseSize(options->max_size, "--max-size") : 0;
        // A folder named with --cache must exist: a misspelt path read as
        // an empty cache. The default may not exist yet (nothing cached).
        std::error_code ec;
        const auto status = std::filesystem::status(options->cache, ec);
        // The folder's source as the error names it: --cache, or where its
        // default came from (a bad-input audit: HCPF_CACHE_DIR naming a file
        // was reported as --cache, not given).
        const std::string key =
            cache->count() > 0 ? std::string("--cache") : scenarios::DefaultFrameCacheSource();
        if (std::filesystem::exists(status) && !std::filesystem::is_directory(status)) {
          throw InputError(SourceLocation{options->cache, 0, 0, key}, "a cache folder",
                           "an existing file");
        }
        // A folder below a file can never be created: said so (it was "no
        // such folder", and a default there "not created yet: nothing
        // cached", exit 0).
        if (!std::filesystem::exists(status)) scenarios::CheckFolderArgument(options->cache, key);
        if (!std::filesystem::exists(status) && cache->count() > 0) {
          throw InputError(
              SourceLocation{options->cache, 0, 0, key}, "an existing cache folder",
              "no such folder",
              "hcpf run and sweep create it; the default is " + scenarios::DefaultFrameCacheDir());
        }
        // $HCPF_CACHE_MAX_SIZE, said when set (a bad value is bad input here too).
        const std::optional<uint64_t> limit = scenarios::CacheMaxSizeFromEnvironment();
        const scenarios::CacheContents contents = scenarios::ScanCache(options->cache);
        std::printf("%s%s\n", options->cache.c_str(),
                    std::filesystem::exists(status) ? "" : " (not created yet: nothing cached)");
        std::printf("  %d scene(s) of rendered frames: %s\n", contents.scenes,
                    scenarios::FormatSize(contents.scene_bytes).c_str());
        std::printf("  %d detector output(s): %s\n", contents.detections,
                    scenarios::FormatSize(contents.detection_bytes).c_str());
        if (!contents.entries.empty()) {
          std::printf("  used from %s to %s (UTC)\n",
                      scenarios::FormatLastUsed(contents.entries.front().last_used).c_str(),
                      scenarios::FormatLastUsed(contents.entries.back().last_used).c_str());
        }
        if (limit) {
          const char* set = std::getenv(scenarios::kCacheMaxSizeVariable);
          const std::string source =
              set != nullptr
                  ? fmt::format("{}={}", scenarios::kCacheMaxSizeVariable, set)
                  : fmt::format("{} unset: the default", scenarios::kCacheMaxSizeVariable);
          std::printf(
              "  limit: %s after each hcpf run, render and sweep (%s), what they used kept\n",
              scenarios::FormatSize(*limit).c_str(), source.c_str());
        }
        // One line per scene (last used, size, what it is, its folder) and
        // one for the detector outputs together: a cache of 1440 detector
        // outputs listed 1440 lines before its total (an audit).
        const auto list = [&options](const std::vector<scenarios::CacheEntry>& entries) {
          for (const std::string& line :
               scenarios::ListCacheEntries(entries, options->verbose, "    ")) {
            std::printf("%s\n", line.c_str());
          }
        };
        if (!prune) {
          if (!contents.entries.empty()) {
            std::printf("  least recently used first (last used, UTC; size; scene; folder):\n");
            list(contents.entries);
          }
          return 0;
        }
        if (!contents.foreign.empty()) {
          throw InputError(
              SourceLocation{options->cache, 0, 0, key},
              "a cache folder of hcpf (scene folders of NNNNNN.frame and .json files, "
              "detections/*.det of hcpf)",
              fmt::format("{}, which is not a cache entry{}", contents.foreign.front().string(),
                          contents.foreign.size() > 1
                              ? fmt::format(" (and {} more)", contents.foreign.size() - 1)
                              : std::string()),
              "nothing was removed; name the cache folder itself, or move what is not the "
              "cache's");
        }
        const std::vector<scenarios::CacheEntry> remove =
            scenarios::PruneOrder(contents, max_bytes);
        uint64_t freed = 0;
        int scenes = 0;
        for (const scenarios::CacheEntry& e : remove) {
          freed += e.bytes;
          scenes += e.kind == scenarios::CacheEntry::Kind::kScene;
        }
        // Described before they go (a scene's note is in its folder).
        const std::vector<std::string> lines =
            scenarios::ListCacheEntries(remove, options->verbose, "    ");
        if (!options->dry_run) scenarios::RemoveCacheEntries(remove);
        std::printf(
            "  %s %d scene(s) and %d detector output(s), %s, least recently used "
            "first: %s left (--max-size %s)\n",
            options->dry_run ? "would remove" : "removed", scenes,
            static_cast<int>(remove.size()) - scenes, scenarios::FormatSize(freed).c_str(),
            scenarios::FormatSize(contents.bytes() - freed).c_str(), options->max_size.c_str());
        for (const std::string& line : lines) std::printf("%s\n", line.c_str());
        return 0;
      }};
}

}  // namespace hcpf::cli
