#pragma once
// The report of a sweep: DIR/report.html (one self-contained file: inline
// SVG plots made by gnuplot, a table of every cell, the resolved base
// scenario, links to overlay videos) and DIR/summary.csv.
//
//   ReportResult r = WriteReport({.dir = "out"});   // reads out/results.sqlite
//
// Statistics: a cell is one combination of swept values; its n values are the
// seeds whose run finished with a finite metric. The band is the 95 %
// confidence interval of the mean, mean ± t(0.975, n−1) · s / √n (Student t;
// s the sample standard deviation); no band when n < 2.

#include <string>
#include <vector>

namespace hcpf::studies {

struct ReportOptions {
  std::string dir;                  // a sweep's --out folder (holds results.sqlite)
  std::string out_dir;              // where report.html and summary.csv go ("" = dir)
  std::string gnuplot = "gnuplot";  // the gnuplot executable
  void Validate() const;
};

struct ReportResult {
  std::string html_path;
  std::string csv_path;
  int plots = 0;
  int cells = 0;
};

// Throws InputError when DIR has no results store; RunError when gnuplot fails
// or the output folder cannot be written (the message suggests --out). The
// store is only read: a sweep on read-only media can be reported elsewhere.
ReportResult WriteReport(const ReportOptions& options);

// Mean and 95 % confidence half-width of `values` (t distribution, above).
// half_width is 0 when there are fewer than two values; mean is NaN when none.
struct MeanCi {
  int n = 0;
  double mean = 0.0;
  double half_width = 0.0;
};
MeanCi MeanConfidence95(const std::vector<double>& values);

// The 0.975 quantile of Student's t with `dof` >= 1 degrees of freedom
// (table for dof <= 30, Cornish–Fisher expansion above; error < 1e-3).
double StudentT975(int dof);

}  // namespace hcpf::studies
