#pragma once
// The regression gate: `hcpf regress SUITE.yaml --baseline BASELINE.json`.
// A suite lists scenes (a scenario file, optional overrides and seed) and
// per-metric tolerances; each scene is run and its metrics compared with the
// baseline (docs/sweeps.md, "Regression gate").
//
//   RegressResult r = RunRegress({.suite_path = "suite.yaml", .baseline_path = "baseline.json"});
//   exit code: r.worse > 0 ? 1 : 0   (bad suite or baseline: InputError -> 2)

#include <string>
#include <vector>

#include "hcpf/scenarios/scenario.h"

namespace hcpf::studies {

struct RegressScene {
  std::string name;
  std::string scenario_path;                // resolved to an existing file
  std::vector<config::Override> overrides;  // from `set:`, then `seed:`
};

struct RegressTolerance {
  std::string metric;      // a HeadlineMetrics() name
  double tolerance = 0.0;  // absolute, >= 0
  bool higher_is_better = true;
};

struct RegressSuite {
  std::string file;
  std::vector<RegressScene> scenes;
  std::vector<RegressTolerance> metrics;
};

// Loads and validates a suite (InputError with file:line:col, key, expected, found).
RegressSuite LoadRegressSuite(const std::string& path);

enum class RegressVerdict { kSame, kBetter, kWorse };
const char* RegressVerdictName(RegressVerdict verdict);  // "ok" | "better" | "WORSE"
// Worse when the change in the bad direction exceeds the tolerance; better when
// the change in the good direction does; same otherwise. NaN against a number
// is worse; NaN against NaN is the same.
RegressVerdict CompareMetric(double baseline, double current, const RegressTolerance& tolerance);

struct RegressRow {
  std::string scene;
  std::string metric;
  double baseline = 0.0;
  double current = 0.0;
  double tolerance = 0.0;
  bool higher_is_better = true;
  RegressVerdict verdict = RegressVerdict::kSame;
};

struct RegressOptions {
  std::string suite_path;
  std::string baseline_path;
  bool update_baseline = false;  // write the baseline from this run instead of comparing
  std::string junit_path;        // optional JUnit XML
  std::string markdown_path;     // optional Markdown summary
  std::string work_dir;          // run folders; "" = a temporary folder, removed afterwards
  int jobs = 1;                  // scenes run in parallel
  void Validate() const;
};

struct RegressResult {
  std::vector<RegressRow> rows;  // scene-major, metrics in suite order
  int worse = 0;
  int better = 0;
  bool baseline_written = false;
  std::string table;  // the printed table
};

// Runs every scene and compares (or, with update_baseline, writes the
// baseline). Throws InputError on a bad suite, a missing/unreadable baseline or
// a scene/metric absent from it.
RegressResult RunRegress(const RegressOptions& options);

// Renderings of the result (exposed for tests).
std::string FormatRegressTable(const std::vector<RegressRow>& rows);
std::string FormatRegressJunit(const std::vector<RegressRow>& rows);
std::string FormatRegressMarkdown(const RegressResult& result);

}  // namespace hcpf::studies
