#pragma once
// The report of a sweep: DIR/report.html (one self-contained file: inline
// SVG plots made by gnuplot, a table of every cell, the resolved base
// scenario, links to overlay videos) and DIR/summary.csv.
//
//   ReportResult r = WriteReport({.dir = "out"});   // reads out/results.sqlite
//
// The report of one run (a folder written by `hcpf run`): DIR/report.html
// with the run's headline metrics and, when camera_motion.csv has rows, the
// per-frame camera-motion error (and the scene filter's ESS) against the frame.
//
//   ReportResult r = WriteReport({.dir = "out/climb"});   // reads its metrics.json
//
// Statistics (statistics.h, docs/sweeps.md): a cell is one combination of
// swept values; its n values are the seeds whose run finished with a finite
// metric. The band is the 95 % confidence interval of the mean: a Wilson
// score interval over the n seeds for proportions (the metric catalogue's
// range), else mean ± t(0.975, n−1) · s / √n cut to the metric's range.
// With report.series, every other series value is compared with the
// reference value (report.reference, else the first) seed by seed at each x:
// the mean paired difference with its t interval and a Wilcoxon signed-rank
// test, in a table and one plot per metric.

#include <cstdint>
#include <string>
#include <vector>

#include "hcpf/studies/statistics.h"

namespace hcpf::studies {

struct ReportOptions {
  std::string dir;                  // a sweep's --out folder (results.sqlite) or a run's folder
  std::string out_dir;              // where report.html and summary.csv go ("" = dir)
  std::string gnuplot = "gnuplot";  // the gnuplot executable
  // With a sweep folder as `dir`: another sweep folder over the same swept
  // keys (the same sweep on another root seed: hcpf sweep --seed): every
  // paired comparison is made again on its runs with this report's settings,
  // and report.html (section "Replication"), findings.md and replication.csv
  // say which findings replicate; every cell mean is set against the other
  // store's interval of the same cell (replication_cells.csv).
  // With a run folder as `dir`: another run folder (run B; `dir` is run A):
  // the resolved keys they differ in, which files are the same, the headline
  // metrics side by side, and over one ground truth both runs' filters on one
  // timeline and compared target by target, frame by frame. Or, with a run
  // folder as `dir`, a sweep folder: run A set beside its cell's seeds (the
  // cell whose runs' resolved scenario is A's, seeds aside, else the
  // nearest, with the keys it differs in), and the cell's run of A's seed
  // checked to give A's metrics. "" = none.
  std::string against;
  // With a run folder as `dir` and `against` set: more run folders (runs C,
  // D, ..., at most 24), each set beside A in the headline table (its value
  // and A − X) and in a table of who it is and the resolved keys it differs
  // from A in. The comparison frame by frame, the files, the timeline and
  // the videos stay A's with B. Bad input with a sweep folder as `dir`.
  std::vector<std::string> more_against;
  void Validate() const;
};

struct ReportResult {
  std::string html_path;
  std::string csv_path;             // "" for a run's report (it has no cells)
  int plots = 0;                    // plots of the metrics (with their panels)
  int difference_plots = 0;         // plots of the paired differences
  int comparisons = 0;              // rows of the paired-difference table
  int findings = 0;                 // sentences of the findings (also in findings.md)
  int replication_comparisons = 0;  // with `against`: comparisons made in both stores
  int replication_cells = 0;        // with `against`: cell means with an interval in both
  int differing_keys = 0;           // a run with `against`: resolved keys that differ between them
  int compared_targets = 0;         // a run with `against`: targets compared frame by frame
  int more_runs = 0;                // a run with `more_against`: the runs set beside A and B
  // A run with a sweep as `against`: set beside a cell of it; the cell's
  // finished runs set beside it (the run's own aside when it is one of the
  // sweep's).
  bool beside_cell = false;
  int cell_runs = 0;
  // ... and the resolved keys, seeds aside, in which that cell differs from
  // the run (0: the run's own cell).
  int cell_differing_keys = 0;
  int cells = 0;
  int builds = 0;                  // a sweep's report: builds of hcpf that made its finished runs
  int64_t missing_runs = 0;        // a sweep's report: runs of the sweep not in the store
  int64_t absent_run_folders = 0;  // a sweep's report: finished runs whose folder is gone
};

// What `hcpf report DIR` was given.
enum class ReportFolder {
  kSweep,  // DIR/results.sqlite exists (hcpf sweep --out DIR)
  kRun,    // DIR/manifest.json is a run manifest, "format": "hcpf-run/1" (hcpf run --out DIR)
};

// Which kind of folder `dir` is. Throws InputError naming `dir`, what was
// expected (a sweep folder or a run folder, and the file that marks each) and
// what was found (no such folder, a file, a render folder, a manifest that is
// not JSON, a folder with neither file).
ReportFolder ClassifyReportFolder(const std::string& dir);

// The report of a sweep or of a run, by ClassifyReportFolder(options.dir).
// Throws InputError when DIR is neither, when its files are malformed (the
// message names the file, line and column); RunError when gnuplot fails or the
// output folder cannot be written (the message suggests --out). The folder is
// only read (report.html goes to --out when given): a sweep on read-only media
// can be reported elsewhere.
ReportResult WriteReport(const ReportOptions& options);

// The run's report: `options.dir` must be a run folder (else InputError).
// report.html holds the headline metrics (the metric catalogue's values read
// from metrics.json and manifest.json), the camera-motion summary of
// metrics.json and, when camera_motion.csv has rows, a plot of error_px per
// frame whose legend names the camera-motion mode, with the scene filter's
// ESS on a second axis when the file has it; then the resolved scenario.
ReportResult WriteRunReport(const ReportOptions& options);

}  // namespace hcpf::studies
