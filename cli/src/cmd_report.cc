// hcpf report DIR [--out FOLDER] [--against OTHER ...]: DIR is a sweep's or a run's folder,
// OTHER another of the same kind (several: runs beside a run).

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <memory>

#include "command.h"
#include "hcpf/studies/report.h"

namespace hcpf::cli {

Command AddReportCommand(CLI::App& parent) {
  auto options = std::make_shared<studies::ReportOptions>();
  auto against = std::make_shared<std::vector<std::string>>();
  CLI::App* app = parent.add_subcommand(
      "report",
      "Write DIR/report.html from a sweep (plots, cells, base scenario; and DIR/summary.csv) "
      "or from a run (headline metrics, per-frame camera-motion error, detection quality, a "
      "timeline of targets, detections and filters)");
  app->add_option("dir", options->dir, "A sweep's or a run's --out folder")->required();
  app->add_option("--out", options->out_dir,
                  "Write report.html (and a sweep's summary.csv) here instead of DIR (DIR is "
                  "only read, so a folder on read-only media can be reported)");
  app->add_option("--against", *against,
                  "For a sweep: another sweep folder over the same keys (e.g. the same sweep "
                  "with hcpf sweep --seed): which of this report's findings replicate there, and "
                  "each cell mean against its interval there (report.html, findings.md, "
                  "replication.csv, replication_cells.csv). For a run: another run folder, "
                  "compared with it (the keys they differ in, the same files, the metrics side by "
                  "side, and over one ground truth their filters frame by frame); repeated, "
                  "more runs set beside it in the headline metrics; or a sweep folder: the run "
                  "beside its cell's seeds")
      // One folder per --against: the words after it are DIR or another
      // option's (a review: a list took DIR, and `--against B C` took C).
      ->expected(1)
      ->allow_extra_args(false)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  app->add_option("--gnuplot", options->gnuplot, "The gnuplot executable")->capture_default_str();
  return {app, [options, against] {
            if (!against->empty()) {
              options->against = against->front();
              options->more_against.assign(against->begin() + 1, against->end());
            }
            const auto start = std::chrono::steady_clock::now();
            const studies::ReportResult r = studies::WriteReport(*options);
            const double s =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            if (r.beside_cell) {
              spdlog::info(
                  "report: {} plots in {:.2f} s; beside {} finished run{} of a cell of {}{}",
                  r.plots, s, r.cell_runs, r.cell_runs == 1 ? "" : "s", options->against,
                  r.cell_differing_keys == 0
                      ? std::string(" (its own)")
                      : fmt::format(" (the nearest: {} resolved key{} differ{})",
                                    r.cell_differing_keys, r.cell_differing_keys == 1 ? "" : "s",
                                    r.cell_differing_keys == 1 ? "s" : ""));
            } else if (r.csv_path.empty() && !options->against.empty()) {
              spdlog::info(
                  "report: {} plots in {:.2f} s; against {}: {} resolved key{} differ{}, {} "
                  "target{} compared frame by frame{}",
                  r.plots, s, options->against, r.differing_keys, r.differing_keys == 1 ? "" : "s",
                  r.differing_keys == 1 ? "s" : "", r.compared_targets,
                  r.compared_targets == 1 ? "" : "s",
                  r.more_runs > 0 ? fmt::format("; {} more run{} beside them", r.more_runs,
                                                r.more_runs == 1 ? "" : "s")
                                  : std::string());
            } else if (r.csv_path.empty()) {
              spdlog::info("report: {} plots in {:.2f} s", r.plots, s);
            } else {
              spdlog::info(
                  "report: {} plots, {} cells, {} compared cells ({} difference plots) in "
                  "{:.2f} s; {}",
                  r.plots, r.cells, r.comparisons, r.difference_plots, s, r.csv_path);
            }
            std::printf("%s\n", r.html_path.c_str());
            return 0;
          }};
}

}  // namespace hcpf::cli
