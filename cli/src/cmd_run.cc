// hcpf run SCENARIO.yaml --out DIR [--set key=value ...] [--video]

#include <spdlog/spdlog.h>

#include <memory>

#include "cache_limit.h"
#include "command.h"
#include "hcpf/scenarios/frames.h"
#include "hcpf/scenarios/run.h"
#include "hcpf/scenarios/scenario.h"
#include "interrupt.h"

namespace hcpf::cli {

Command AddRunCommand(CLI::App& parent) {
  struct Options {
    std::string file;
    std::string out;
    std::vector<std::string> sets;
    int threads = 1;
    std::string cache = scenarios::DefaultFrameCacheDir();
    bool no_cache = false;
    bool video = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand(
      "run", "Run one scenario: ground truth, observations, tracker and metrics into --out");
  app->add_option("scenario", options->file, "Scenario YAML file")->required();
  app->add_option("--out", options->out,
                  "Output folder (created; an earlier run's folder is replaced)")
      ->required();
  app->add_option("--set", options->sets,
                  "Override a key, e.g. --set tracker.particles=1000 (repeatable)");
  app->add_option("--threads", options->threads,
                  "Threads for the tracker's per-filter stages and the rendered frames' sensor "
                  "effects, cache writes and image files (outputs identical for any value)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  app->add_option("--cache", options->cache,
                  "Frame cache for rendered scenarios (frames keyed by a hash of everything "
                  "that affects pixels)")
      ->capture_default_str();
  app->add_flag("--no-cache", options->no_cache, "Render every frame, read and write no cache");
  app->add_flag("--video", options->video,
                "Also write overlay.mp4 (H.264, shown by hcpf report): frames, ground truth, "
                "detections, estimates, particles (tracker.keep_particles > 0) and each "
                "filter's state");
  return {app, [options, app] {
            std::vector<scenarios::Override> overrides;
            for (const auto& s : options->sets) overrides.push_back(scenarios::ParseOverride(s));
            const scenarios::Scenario scenario =
                scenarios::LoadScenarioFromCommandLine(options->file, overrides);
            if (const std::string note = scenarios::LargeScenarioNote(scenario); !note.empty()) {
              spdlog::warn("{}", note);
            }
            for (const std::string& note : scenarios::SceneNotes(scenario)) {
              spdlog::warn("{}", note);
            }
            scenarios::RunOptions run_options;
            run_options.out_dir = options->out;
            run_options.threads = options->threads;
            run_options.frame_cache_dir =
                FrameCacheFolder(options->cache, app->count("--cache") > 0, options->no_cache);
            run_options.video = options->video;
            const bool rendered =
                scenario.observation.source == scenarios::ObservationSource::kRendered;
            // $HCPF_CACHE_MAX_SIZE: read now, applied once the run is done.
            const CacheLimit cache_limit(rendered ? run_options.frame_cache_dir : "");
            // Ctrl-C or a batch system's SIGTERM ends the run at once; it says
            // what is left (the folder is renamed into place only at the end).
            AnnounceInterrupts(InterruptedMessage("run", options->out,
                                                  rendered ? run_options.frame_cache_dir : ""));
            const scenarios::RunSummary summary = scenarios::RunScenario(scenario, run_options);
            StopAnnouncingInterrupts();  // the folder is in place
            spdlog::info(
                "run \"{}\" finished in {:.2f} s: {} frames, {} ground-truth boxes, {} detections",
                scenario.name, summary.wall_time_s, summary.frames, summary.gt_boxes,
                summary.detections);
            // NaN (null in metrics.json): not measured (no filter metrics for
            // this tracker), or a rate of nothing (no filter-frame scored, no
            // two targets met).
            const auto rate = [](double v) {
              return std::isnan(v) ? std::string("n/a") : fmt::format("{:.3f}", v);
            };
            spdlog::info("MOTA {:.3f}  IDF1 {:.3f}  HOTA {:.3f}  DA accuracy {}  hijack rate {}",
                         summary.mota, summary.idf1, summary.hota, rate(summary.da_accuracy),
                         rate(summary.hijack_rate));
            spdlog::info(
                "outputs in {} (hcpf report on the folder writes its report.html: "
                "plots, a timeline, the video)",
                summary.out_dir);
            cache_limit.Apply();
            return 0;
          }};
}

}  // namespace hcpf::cli
