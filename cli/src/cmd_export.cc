// hcpf export DIR --trackeval OUT [--benchmark NAME] [--split NAME]

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <memory>

#include "command.h"
#include "hcpf/studies/export.h"

namespace hcpf::cli {

Command AddExportCommand(CLI::App& parent) {
  auto options = std::make_shared<studies::TrackEvalExportOptions>();
  CLI::App* app = parent.add_subcommand(
      "export",
      "Lay a sweep's runs out for TrackEval (gt/ and trackers/mot_challenge/<BENCH>-<split>/)");
  app->add_option("dir", options->dir, "Sweep folder (with results.sqlite)")->required();
  app->add_option("--trackeval", options->out,
                  "Output folder (new or empty) for TrackEval's MOTChallenge layout")
      ->required();
  app->add_option("--benchmark", options->benchmark,
                  "TrackEval's BENCHMARK name (letters, digits, _)")
      ->capture_default_str();
  app->add_option("--split", options->split, "TrackEval's SPLIT_TO_EVAL name (letters, digits, _)")
      ->capture_default_str();
  return {app, [options] {
            const studies::TrackEvalExportResult r = studies::ExportTrackEval(*options);
            spdlog::info(
                "export: {} sequence(s) x {} tracker(s) ({} runs) written to {} as {}{}",
                r.sequences, r.trackers, r.runs, options->out, r.bench,
                r.skipped > 0
                    ? fmt::format("; {} run(s) left out with incomplete sequences", r.skipped)
                    : std::string());
            return 0;
          }};
}

}  // namespace hcpf::cli
