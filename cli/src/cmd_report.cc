// hcpf report DIR [--out FOLDER]

#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <memory>

#include "command.h"
#include "hcpf/studies/report.h"

namespace hcpf::cli {

Command AddReportCommand(CLI::App& parent) {
  auto options = std::make_shared<studies::ReportOptions>();
  CLI::App* app = parent.add_subcommand(
      "report",
      "Write DIR/report.html (plots, table, base scenario) and DIR/summary.csv from a sweep");
  app->add_option("dir", options->dir, "A sweep's --out folder")->required();
  app->add_option("--out", options->out_dir,
                  "Write report.html and summary.csv here instead of DIR (the store is only "
                  "read, so a sweep on read-only media can be reported)");
  app->add_option("--gnuplot", options->gnuplot, "The gnuplot executable")->capture_default_str();
  return {app, [options] {
            const auto start = std::chrono::steady_clock::now();
            const studies::ReportResult r = studies::WriteReport(*options);
            const double s =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            spdlog::info("report: {} plots, {} cells in {:.2f} s; {}", r.plots, r.cells, s,
                         r.csv_path);
            std::printf("%s\n", r.html_path.c_str());
            return 0;
          }};
}

}  // namespace hcpf::cli
