#pragma once
// The regression gate: `hcpf regress SUITE.yaml --baseline BASELINE.json`.
// A suite lists scenes (a scenario file, optional overrides and seed) and
// per-metric tolerances; each scene is run and its metrics compared with the
// baseline (docs/sweeps.md, "Regression gate").
//
// Two modes per scene. Without `seeds:` the scene runs once and each metric is
// compared with the absolute tolerance (exact mode: for determinism checks).
// With `seeds: N` (N >= 2) it runs N derived seeds, the baseline keeps the N
// values, and a metric is WORSE only when the mean paired difference is worse
// than the tolerance and its 95 % t interval excludes zero on the bad side.
//
//   RegressResult r = RunRegress({.suite_path = "suite.yaml", .baseline_path = "baseline.json"});
//   exit code: r.worse > 0 ? 1 : 0   (bad suite or baseline: InputError -> 2)

#include <cstdint>
#include <filesystem>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "hcpf/scenarios/scenario.h"

namespace hcpf::studies {

struct RegressScene {
  std::string name;
  std::string scenario_path;                // resolved to an existing file
  std::vector<config::Override> overrides;  // from `set:`, then `seed:`
  // `seeds: N`: 0 when absent (one run, exact mode); else N >= 2 runs with
  // run_seeds[i] = SweepSeed(scene seed, i), the scene seed being `seed:` or
  // the scenario's own (the derivation sweeps use, sweep.h).
  int seeds = 0;
  std::vector<uint64_t> run_seeds;
  bool rendered = false;  // observation.source: rendered
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

// Whether `path` reads as a regression suite rather than a scenario or a
// baseline: a YAML mapping whose `scenes:` is a list (a scenario has no
// `scenes:`, and may have `metrics:`; a baseline's `scenes:` is a mapping).
// False when it cannot be read as YAML (the scenario loader reports why).
bool IsRegressSuiteFile(const std::string& path);

enum class RegressVerdict { kSame, kBetter, kWorse };
const char* RegressVerdictName(RegressVerdict verdict);  // "ok" | "better" | "WORSE"
// Worse when the change in the bad direction exceeds the tolerance; better when
// the change in the good direction does; same otherwise. NaN against a number
// is worse; NaN against NaN is the same.
RegressVerdict CompareMetric(double baseline, double current, const RegressTolerance& tolerance);

struct RegressRow {
  std::string scene;
  std::string metric;
  // Exact mode: the two values. Seeded: the means over the `pairs` seeds
  // where both values are finite; with no such seed, each side's mean over
  // its finite values (NaN when it has none).
  double baseline = 0.0;
  double current = 0.0;
  double tolerance = 0.0;
  bool higher_is_better = true;
  RegressVerdict verdict = RegressVerdict::kSame;
  // Seeded scenes only (seeds == 0 in exact mode): the mean of
  // current_i − baseline_i over the pairs and its 95 % Student t interval
  // [lower, upper] (statistics.h, StudentInterval95; equal to the mean when
  // pairs < 2), and the seeds with a number on one side and NaN on the other.
  int seeds = 0;
  int pairs = 0;
  int nan_mismatches = 0;
  double difference = 0.0;
  double lower = 0.0;
  double upper = 0.0;
};

// The seeded verdict of one metric; baseline[i] and current[i] are seed i's
// values (same length). With gain g_i = current_i − baseline_i when higher is
// better, baseline_i − current_i when lower is (pairs with a NaN left out):
//   WORSE  when some seed has a number on one side and NaN on the other, or
//          mean(g) < −tolerance and the interval's upper end < 0;
//   better when mean(g) > tolerance and the interval's lower end > 0;
//   ok     otherwise (so identical values, g_i = 0, are always ok).
// With fewer than two pairs there is no interval: one pair is judged like
// CompareMetric, none is ok. The row's scene is left empty.
RegressRow CompareSeeds(std::span<const double> baseline, std::span<const double> current,
                        const RegressTolerance& tolerance);

struct RegressOptions {
  std::string suite_path;
  std::string baseline_path;
  bool update_baseline = false;  // write the baseline from this run instead of comparing
  std::string junit_path;        // optional JUnit XML
  std::string markdown_path;     // optional Markdown summary
  std::string work_dir;          // run folders; "" = a temporary folder, removed afterwards
  int jobs = 1;                  // runs (scenes, seeds of seeded scenes) in parallel
  // The hcpf executable. When set and jobs > 1, each rendered run is
  // `hcpf run` in a child process of its own: a process's GL contexts share
  // llvmpipe's one rasteriser, so rendered runs in worker threads render in
  // turn (docs/sweeps.md, "Regression gate"). Runs at detection level stay in worker threads.
  std::string render_exe;
  // Called once every run has ended and the temporary folder is removed,
  // before any file is written (hcpf regress stops announcing interrupts).
  std::function<void()> runs_done;
  void Validate() const;
  // Where the runs go: work_dir, or the temporary folder
  // TMPDIR/hcpf-regress.partial-<pid> (one that a killed regress left is
  // removed by the next RunRegress).
  std::filesystem::path RunsFolder() const;
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
