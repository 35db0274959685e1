// hcpf regress SUITE.yaml --baseline BASELINE.json [--update-baseline] [--junit FILE] [--markdown
// FILE]

#include <spdlog/spdlog.h>

#include <cstdio>
#include <memory>

#include "command.h"
#include "hcpf/studies/regress.h"

namespace hcpf::cli {

Command AddRegressCommand(CLI::App& parent) {
  auto options = std::make_shared<studies::RegressOptions>();
  CLI::App* app = parent.add_subcommand("regress",
                                        "Run a suite of golden scenes and compare their metrics "
                                        "with a baseline (exit 1 on a regression)");
  app->add_option("suite", options->suite_path, "Suite YAML (scenes and per-metric tolerances)")
      ->required();
  app->add_option("--baseline", options->baseline_path, "Baseline JSON")->required();
  app->add_flag("--update-baseline", options->update_baseline,
                "Write the baseline from this run instead of comparing");
  app->add_option("--junit", options->junit_path, "Also write JUnit XML here");
  app->add_option("--markdown", options->markdown_path, "Also write a Markdown summary here");
  app->add_option("--work", options->work_dir,
                  "Keep the scenes' run folders here (default: a temporary folder)");
  app->add_option("--jobs", options->jobs, "Runs in parallel (scenes, and seeds of seeded scenes)")
      ->check(CLI::Range(1, 1024))
      ->capture_default_str();
  return {app, [options] {
            const studies::RegressResult r = studies::RunRegress(*options);
            std::fputs(r.table.c_str(), stdout);
            std::fflush(stdout);
            if (r.baseline_written) {
              spdlog::info("regress: baseline written to {}", options->baseline_path);
              return 0;
            }
            if (r.worse > 0) {
              spdlog::error("regress: {} metric(s) worse than the baseline beyond tolerance",
                            r.worse);
              return 1;
            }
            if (r.better > 0) {
              spdlog::info(
                  "regress: no regression; {} metric(s) better than the baseline - refresh it with "
                  "--update-baseline",
                  r.better);
            } else {
              spdlog::info("regress: no regression");
            }
            return 0;
          }};
}

}  // namespace hcpf::cli
