// hcpf validate FILE.yaml [--set key=value ...] [--print]; or a sweep file

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <iostream>
#include <memory>

#include "command.h"
#include "hcpf/core/error.h"
#include "hcpf/scenarios/cache.h"
#include "hcpf/scenarios/scenario.h"
#include "hcpf/studies/regress.h"
#include "hcpf/studies/sweep.h"

namespace hcpf::cli {

Command AddValidateCommand(CLI::App& parent) {
  struct Options {
    std::string file;
    std::vector<std::string> sets;
    bool print = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand(
      "validate",
      "Check a scenario file (every key, type and range), a sweep file or a regression suite "
      "(and every scenario it names); exit 0 if valid, 2 if not");
  app->add_option("file", options->file, "Scenario, sweep or regression suite YAML file")
      ->required();
  app->add_option("--set", options->sets,
                  "Override a key before validating, e.g. --set tracker.particles=1000 "
                  "(repeatable; list items by index: targets.0.path.speed_mps=4)");
  app->add_flag("--print", options->print,
                "Print the resolved scenario (every default and seed filled in) to stdout");
  return {app, [options] {
            // $HCPF_CACHE_MAX_SIZE: hcpf run, render and sweep refuse a bad
            // value before anything runs, so validate does too (it accepts
            // what they accept).
            scenarios::CacheMaxSizeFromEnvironment();
            const bool sweep = studies::IsSweepFile(options->file);
            const bool suite = !sweep && studies::IsRegressSuiteFile(options->file);
            if ((sweep || suite) && (!options->sets.empty() || options->print)) {
              throw InputError(
                  SourceLocation{.file = "command line",
                                 .key = options->sets.empty() ? "--print" : "--set"},
                  "a scenario file (--set and --print apply to one scenario)",
                  sweep ? fmt::format("the sweep file {} (it has base, grid or zip)", options->file)
                        : fmt::format("the regression suite {} (its scenes: is a list)",
                                      options->file));
            }
            // A regression suite: the checks `hcpf regress` makes of it
            // before it runs anything (every scene's scenario, with its
            // `set:` and seed, loaded and validated), and what validate
            // warns of each scene.
            if (suite) {
              const studies::RegressSuite s = studies::LoadRegressSuite(options->file);
              size_t runs = 0;
              for (const studies::RegressScene& scene : s.scenes)
                runs += static_cast<size_t>(std::max(scene.seeds, 1));
              spdlog::info(
                  "{}: valid regression suite: {} scene{} ({} run{}), {} metric{}, every scenario "
                  "valid",
                  options->file, s.scenes.size(), s.scenes.size() == 1 ? "" : "s", runs,
                  runs == 1 ? "" : "s", s.metrics.size(), s.metrics.size() == 1 ? "" : "s");
              for (const studies::RegressScene& scene : s.scenes) {
                const scenarios::Scenario scenario =
                    scenarios::LoadScenarioFile(scene.scenario_path, scene.overrides);
                for (const std::string& note : scenarios::SceneNotes(scenario))
                  spdlog::warn("scene \"{}\": {}", scene.name, note);
              }
              return 0;
            }
            // A sweep file: the same checks `hcpf sweep` makes before it runs
            // anything (every cell's scenario loaded and validated).
            if (sweep) {
              const studies::SweepSpec spec = studies::LoadSweepFile(options->file);
              const std::vector<studies::SweepRun> runs = studies::ExpandSweep(spec);
              const int seeds = std::max(spec.seeds, 1);
              spdlog::info("{}: valid sweep: {} runs ({} cells x {} seed(s)), every scenario valid",
                           options->file, runs.size(), runs.size() / seeds, seeds);
              for (const std::string& note :
                   {studies::ZippedPoolNote(spec), studies::SeedsForHolmNote(spec),
                    studies::CameraTurnNote(spec, runs), studies::TargetOverlapNote(spec, runs)}) {
                if (!note.empty()) spdlog::warn("{}", note);
              }
              return 0;
            }
            std::vector<scenarios::Override> overrides;
            for (const auto& s : options->sets) overrides.push_back(scenarios::ParseOverride(s));
            const scenarios::Scenario scenario =
                scenarios::LoadScenarioFromCommandLine(options->file, overrides);
            if (options->print) std::cout << scenarios::ToResolvedYaml(scenario);
            spdlog::info("{}: valid scenario \"{}\" ({} frames, {} target{})", options->file,
                         scenario.name, scenario.world.frames, scenario.world.targets.size(),
                         scenario.world.targets.size() == 1 ? "" : "s");
            if (const std::string note = scenarios::LargeScenarioNote(scenario); !note.empty()) {
              spdlog::warn("{}", note);
            }
            for (const std::string& note : scenarios::SceneNotes(scenario)) {
              spdlog::warn("{}", note);
            }
            return 0;
          }};
}

}  // namespace hcpf::cli
