// hcpf regress SUITE.yaml --baseline BASELINE.json [--update-baseline] [--junit FILE] [--markdown
// FILE]

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "command.h"
#include "hcpf/studies/regress.h"
#include "interrupt.h"

namespace hcpf::cli {

namespace {

std::string RegressInterruptedMessage(const studies::RegressOptions& o) {
  std::vector<std::string> outputs;
  if (o.update_baseline) outputs.push_back(o.baseline_path);
  if (!o.junit_path.empty()) outputs.push_back(o.junit_path);
  if (!o.markdown_path.empty()) outputs.push_back(o.markdown_path);
  std::string message = "hcpf regress: interrupted before every scene had run; ";
  if (outputs.empty()) {
    message += "nothing was compared";
  } else {
    message += fmt::format("nothing was written to {} (an earlier file is kept)",
                           fmt::join(outputs, ", "));
  }
  if (o.work_dir.empty()) {
    message += fmt::format("; the temporary run folder {} is removed by the next hcpf regress",
                           o.RunsFolder().string());
  } else {
    message += fmt::format("; the run folders of the scenes that finished are in {}", o.work_dir);
  }
  return message;
}

}  // namespace

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
  app->add_option("--junit", options->junit_path,
                  "Also write JUnit XML here (- for standard output)")
      ->transform(DashIsStandardOutput);
  app->add_option("--markdown", options->markdown_path,
                  "Also write a Markdown summary here (- for standard output)")
      ->transform(DashIsStandardOutput);
  app->add_option("--work", options->work_dir,
                  "Keep the scenes' run folders here (default: a temporary folder)");
  app->add_option("--jobs", options->jobs, "Runs in parallel (scenes, and seeds of seeded scenes)")
      ->check(CLI::Range(1, 1024))
      ->capture_default_str();
  return {app, [options] {
            // Ctrl-C or a batch system's SIGTERM ends the suite at once; it
            // says what is left (the outputs are written after every run).
            AnnounceInterrupts(RegressInterruptedMessage(*options));
            options->runs_done = StopAnnouncingInterrupts;
            // Rendered scenes, several at once: each in a process of its own
            // (RegressOptions::render_exe); without the executable they share
            // this one, where they render in turn.
            std::error_code ec;
            options->render_exe = std::filesystem::read_symlink("/proc/self/exe", ec).string();
            if (ec) options->render_exe.clear();
            const studies::RegressResult r = studies::RunRegress(*options);
            // With --junit, --markdown or --update-baseline naming standard
            // output, that file is all it carries: the table goes to stderr
            // (a review: `--junit /dev/stdout > out.xml` held XML and table).
            TableStream({options->junit_path, options->markdown_path,
                         options->update_baseline ? options->baseline_path : ""})
                << r.table << std::flush;
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
