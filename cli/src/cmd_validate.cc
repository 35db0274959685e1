// hcpf validate FILE.yaml [--set key=value ...] [--print]

#include <spdlog/spdlog.h>

#include <iostream>
#include <memory>

#include "command.h"
#include "hcpf/scenarios/scenario.h"

namespace hcpf::cli {

Command AddValidateCommand(CLI::App& parent) {
  struct Options {
    std::string file;
    std::vector<std::string> sets;
    bool print = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand(
      "validate", "Check a scenario file: every key, type and range; exit 0 if valid, 2 if not");
  app->add_option("file", options->file, "Scenario YAML file")->required();
  app->add_option("--set", options->sets,
                  "Override a key before validating, e.g. --set tracker.particles=1000 "
                  "(repeatable; list items by index: targets.0.path.speed_mps=4)");
  app->add_flag("--print", options->print,
                "Print the resolved scenario (every default and seed filled in) to stdout");
  return {app, [options] {
            std::vector<scenarios::Override> overrides;
            for (const auto& s : options->sets) overrides.push_back(scenarios::ParseOverride(s));
            const scenarios::Scenario scenario =
                scenarios::LoadScenarioFile(options->file, overrides);
            if (options->print) std::cout << scenarios::ToResolvedYaml(scenario);
            spdlog::info("{}: valid scenario \"{}\" ({} frames, {} targets)", options->file,
                         scenario.name, scenario.world.frames, scenario.world.targets.size());
            if (const std::string note = scenarios::LargeScenarioNote(scenario); !note.empty()) {
              spdlog::warn("{}", note);
            }
            return 0;
          }};
}

}  // namespace hcpf::cli
