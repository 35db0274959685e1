// hcpf sweep SWEEP.yaml --out DIR [--jobs N] [--threads T] [--seed S] [--shard i/n]
// [--reuse OTHER ...] [--move-aside]; under mpirun
// -n R, the MPI executor (studies/include/hcpf/studies/mpi_sweep.h).

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "cache_limit.h"
#include "command.h"
#include "hcpf/core/error.h"
#include "hcpf/scenarios/frames.h"
#include "hcpf/studies/mpi_sweep.h"
#include "hcpf/studies/sweep.h"
#include "interrupt.h"

namespace hcpf::cli {

namespace {

// "i/n" -> (i, n); throws InputError.
std::pair<int, int> ParseShard(const std::string& text) {
  const size_t slash = text.find('/');
  int i = -1, n = -1;
  bool ok = slash != std::string::npos;
  if (ok) {
    const auto a = std::from_chars(text.data(), text.data() + slash, i);
    const auto b = std::from_chars(text.data() + slash + 1, text.data() + text.size(), n);
    ok = a.ec == std::errc() && a.ptr == text.data() + slash && b.ec == std::errc() &&
         b.ptr == text.data() + text.size() && n >= 1 && i >= 0 && i < n;
  }
  if (!ok) {
    throw InputError(SourceLocation{"hcpf sweep", 0, 0, "--shard"}, "i/n with 0 <= i < n, e.g. 0/4",
                     "\"" + text + "\"");
  }
  return {i, n};
}

}  // namespace

Command AddSweepCommand(CLI::App& parent) {
  struct Options {
    std::string file;
    std::string out;
    int jobs = 0;
    int threads = 1;
    std::string shard;
    std::string seed;
    std::string cache = scenarios::DefaultFrameCacheDir();
    bool no_cache = false;
    bool video = false;
    bool isolate = false;
    bool move_aside = false;
    std::vector<std::string> reuse;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand(
      "sweep",
      "Run a sweep (base scenario x grid x zip x seeds) into --out: results.sqlite + runs/");
  app->add_option("sweep", options->file, "Sweep YAML file (docs/sweeps.md)")->required();
  app->add_option("--out", options->out,
                  "Output folder; re-running resumes (finished runs are reused)")
      ->required();
  app->add_option("--jobs", options->jobs,
                  "Parallel runs (default: all cores); under mpirun one run per rank instead")
      ->check(CLI::Range(0, 1024));
  app->add_option("--threads", options->threads,
                  "Threads inside each run, as hcpf run --threads (outputs identical for any "
                  "value): for few, long runs that --jobs alone leaves cores idle for")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  CLI::Option* seed_option = app->add_option(
      "--seed", options->seed,
      "Root seed of the runs' seeds instead of the file's seed: (a replication on new "
      "seeds; needs seeds: N; another seed is another sweep, so another --out)");
  app->add_option("--shard", options->shard,
                  "Run only runs with index % n == i (i/n), for batch arrays");
  app->add_option(
         "--cache", options->cache,
         "Frame cache for rendered scenarios, shared by every run: frames are rendered once")
      ->capture_default_str();
  app->add_flag("--video", options->video,
                "Write overlay.mp4 in the first-seed run of every cell (linked from the report)");
  app->add_option("--reuse", options->reuse,
                  "Another sweep folder (any sweep's; repeatable): a run it holds finished, "
                  "with its folder intact, is copied from there instead of computed (the same "
                  "resolved scenario gives the same files), e.g. after raising seeds: or adding "
                  "a grid value")
      ->allow_extra_args(false);
  app->add_flag("--move-aside", options->move_aside,
                "When --out holds another sweep's store (runs keyed by another hcpf, or a sweep "
                "file, scenario or model edited since), rename it DIR.before-<UTC time> and copy "
                "its runs that are still this sweep's, instead of refusing");
  app->add_flag("--isolate", options->isolate,
                "Run each run in a child process: a run that crashes is recorded as failed");
  app->add_flag("--no-cache", options->no_cache,
                "Render every run's frames, read and write no cache");
  return {
      app, [options, seed_option, app] {
        studies::SweepOptions sweep_options;
        sweep_options.out_dir = options->out;
        sweep_options.jobs =
            options->jobs > 0 ? options->jobs
                              : static_cast<int>(std::max(1U, std::thread::hardware_concurrency()));
        if (!options->shard.empty()) {
          std::tie(sweep_options.shard_index, sweep_options.shard_count) =
              ParseShard(options->shard);
        }
        sweep_options.run_threads = options->threads;
        sweep_options.frame_cache_dir =
            FrameCacheFolder(options->cache, app->count("--cache") > 0, options->no_cache);
        sweep_options.video = options->video;
        sweep_options.reuse_dirs = options->reuse;
        sweep_options.move_aside = options->move_aside;
        if (options->isolate) {
          std::error_code ec;
          sweep_options.isolate_exe = std::filesystem::read_symlink("/proc/self/exe", ec).string();
          if (ec) throw RunError("--isolate: cannot find the hcpf executable (/proc/self/exe)");
        }
        sweep_options.Validate();
        studies::SweepSpec spec = studies::LoadSweepFile(options->file);
        if (seed_option->count() > 0) {
          studies::SetRootSeed(spec, options->seed, "--seed");
          if (studies::IsFirstLaunchedRank()) {
            spdlog::info("sweep: runs seeded from root seed {} (--seed; the sweep file's seed: {})",
                         spec.seed, spec.file_seed);
          }
        }
        const std::vector<studies::SweepRun> runs = studies::ExpandSweep(spec);
        // $HCPF_CACHE_MAX_SIZE: read now, applied by this process once every
        // run is done (rank 0 under MPI), not by --isolate's children.
        const bool rendered = std::any_of(runs.begin(), runs.end(),
                                          [](const studies::SweepRun& r) { return r.rendered(); });
        // Several rendered runs at once, outside MPI: each in a process of
        // its own (SweepOptions::render_exe).
        if (rendered && sweep_options.jobs > 1 && sweep_options.isolate_exe.empty() &&
            studies::LaunchedRankCount() <= 1) {
          std::error_code ec;
          sweep_options.render_exe = std::filesystem::read_symlink("/proc/self/exe", ec).string();
          if (ec) {
            spdlog::warn(
                "sweep: the hcpf executable was not found (/proc/self/exe): rendered runs share "
                "this process, where they render in turn (docs/sweeps.md)");
          } else {
            spdlog::info(
                "sweep: each rendered run in a process of its own (--jobs {}), so that they "
                "render side by side; one whose frames are all in the frame cache renders nothing "
                "and stays in a worker thread (docs/sweeps.md)",
                sweep_options.jobs);
          }
        }
        const CacheLimit cache_limit(rendered ? sweep_options.frame_cache_dir : "");
        CacheLimit::HideFromChildren();
        // Said once: by rank 0 under an MPI launcher (the others make none).
        if (studies::IsFirstLaunchedRank()) {
          for (const std::string& note :
               {studies::ZippedPoolNote(spec), studies::SeedsForHolmNote(spec),
                studies::CameraTurnNote(spec, runs), studies::TargetOverlapNote(spec, runs)}) {
            if (!note.empty()) spdlog::warn("{}", note);
          }
        }
        // Ctrl-C (or a batch system's SIGTERM) still ends the sweep at once,
        // losing the runs in flight; it now also says how to go on. Under
        // mpirun the launcher reports, not each rank.
        if (studies::LaunchedRankCount() <= 1) {
          AnnounceInterrupts(fmt::format(
              "hcpf sweep: interrupted; the runs finished so far are kept in {}/results.sqlite "
              "and the same command again resumes the sweep",
              options->out));
        }
        // The thread pool, or MPI ranks when mpirun started several.
        const std::optional<studies::SweepResult> result =
            studies::RunSweepMpi(spec, runs, sweep_options);
        if (!result) return 0;  // an MPI worker rank: rank 0 reports
        const studies::SweepResult& r = *result;
        cache_limit.Apply();
        spdlog::info(
            "sweep finished: {} runs, {} reused{}, {} computed, {} failed; results in "
            "{}/results.sqlite",
            r.total, r.reused,
            r.copied > 0 ? fmt::format(" ({} copied from --reuse)", r.copied) : std::string(),
            r.computed, r.failed, options->out);
        if (r.failed > 0) {
          spdlog::error("{} run(s) failed (see the error column of results.sqlite)", r.failed);
          return 1;
        }
        return 0;
      }};
}

}  // namespace hcpf::cli
