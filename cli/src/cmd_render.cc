// hcpf render SCENARIO.yaml --out DIR [--set key=value ...] [--cache DIR] [--sheet-frames N]
//   [--threads N]

#include <spdlog/spdlog.h>

#include <memory>

#include "cache_limit.h"
#include "command.h"
#include "hcpf/scenarios/frames.h"
#include "hcpf/scenarios/render_folder.h"
#include "hcpf/scenarios/scenario.h"
#include "interrupt.h"

namespace hcpf::cli {

Command AddRenderCommand(CLI::App& parent) {
  struct Options {
    std::string file;
    std::string out;
    std::vector<std::string> sets;
    std::string cache = scenarios::DefaultFrameCacheDir();
    bool no_cache = false;
    int sheet_frames = 16;
    int threads = 1;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand(
      "render",
      "Render a scenario's frames with pixel-exact ground truth into --out: frames/*.png, "
      "gt/gt.txt, seqinfo.ini, gt.json, contact_sheet.png");
  app->add_option("scenario", options->file, "Scenario YAML file")->required();
  app->add_option("--out", options->out,
                  "Output folder (created; an earlier output folder is replaced)")
      ->required();
  app->add_option("--set", options->sets,
                  "Override a key, e.g. --set world.sun.azimuth_deg=90 (repeatable)");
  app->add_option("--cache", options->cache,
                  "Frame cache folder: frames already rendered for the same pixels are read, "
                  "new ones stored (keyed by a hash of everything that affects pixels)")
      ->capture_default_str();
  app->add_flag("--no-cache", options->no_cache, "Render every frame, read and write no cache");
  app->add_option("--threads", options->threads,
                  "Threads for the frames' sensor effects, cache writes and PNG files (outputs "
                  "identical for any value)")
      ->check(CLI::Range(1, 256))
      ->capture_default_str();
  app->add_option("--sheet-frames", options->sheet_frames, "Frames sampled into contact_sheet.png")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  return {
      app, [options, app] {
        std::vector<scenarios::Override> overrides;
        for (const auto& s : options->sets) overrides.push_back(scenarios::ParseOverride(s));
        const scenarios::Scenario scenario = scenarios::LoadScenarioFromCommandLine(
            options->file, overrides, scenarios::ScenarioUse::kRender);
        for (const std::string& note : scenarios::SceneNotes(scenario)) spdlog::warn("{}", note);
        scenarios::RenderFolderOptions render_options;
        render_options.out_dir = options->out;
        render_options.cache_dir =
            FrameCacheFolder(options->cache, app->count("--cache") > 0, options->no_cache);
        render_options.sheet_frames = options->sheet_frames;
        render_options.threads = options->threads;
        const CacheLimit cache_limit(render_options.cache_dir);  // $HCPF_CACHE_MAX_SIZE
        AnnounceInterrupts(InterruptedMessage("render", options->out, render_options.cache_dir));
        const auto summary = scenarios::RenderToFolder(scenario, render_options);
        StopAnnouncingInterrupts();  // the folder is in place
        spdlog::info("rendered \"{}\": {} frames ({} from the cache) in {:.2f} s", scenario.name,
                     summary.frames, summary.frames_from_cache, summary.wall_time_s);
        spdlog::info("outputs in {} (contact_sheet.png for a quick look)", summary.out_dir);
        cache_limit.Apply();
        return 0;
      }};
}

}  // namespace hcpf::cli
