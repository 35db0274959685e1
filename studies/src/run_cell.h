#pragma once
// A run set beside its cell of a sweep: `hcpf report RUN --against SWEEP`.
// Is this run typical of its cell's seeds, and does the cell's run of its
// seed give its metrics again?

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "hcpf/config/yaml_leaves.h"
#include "hcpf/studies/metric_catalogue.h"
#include "hcpf/studies/results_store.h"

namespace hcpf::studies {

// The cell of a sweep whose resolved scenario, seeds aside, is a run's (or
// the nearest one).
struct RunCell {
  std::string sweep_dir;
  // The sweep's swept keys but `seed` (a swept seed replicates: its runs
  // share a cell), and the cell's values of them.
  std::vector<std::string> keys;
  std::vector<std::string> values;
  size_t cells = 0;  // the sweep's cells compared with the run
  // Cells with no run folder holding a readable resolved scenario: not
  // compared (their values, "k = v, ..." as text).
  std::vector<std::string> uncompared;
  // Other cells exactly as near as this one (their values as text).
  std::vector<std::string> as_near;
  // The leaves the cell's seeds are drawn over: `seed`, and each `seeds.X`
  // that both the run's resolved scenario and the cell's derive from their
  // `seed` (scenarios::DeriveSeed; a seed the base pins or the grid sweeps
  // is a key like any other).
  std::vector<std::string> drawn;
  // The cell's scenario.resolved.yaml that was compared with the run's.
  std::string compared_file;
  // Leaves of the run's resolved scenario (first) and the cell's (second)
  // that differ, the drawn leaves aside: empty when this is the run's own
  // cell.
  std::vector<config::LeafDifference> differences;
  std::vector<RunRecord> runs;  // the cell's rows, in run order
  // The cell's run whose folder is the run's own (the run reported is one
  // of the sweep's), an index into `runs`: left out of the seeds.
  std::optional<size_t> itself;
  // The cell's run with the run's seed (an index into `runs`), and the
  // leaves its folder's resolved scenario differs from the run's in, every
  // seed included (nullopt when its folder holds no readable file).
  std::optional<size_t> same_seed;
  std::optional<std::vector<config::LeafDifference>> same_seed_differences;
  // MissingRunsSentence of the store ("" when it holds every run).
  std::string missing_runs;
};

// The cell of the sweep folder `sweep_dir` (results.sqlite and runs/) whose
// runs' resolved scenario differs least from `run_resolved` (the
// scenario.resolved.yaml of the run in `run_dir`), the drawn leaves aside:
// each cell is compared through the first of its runs whose folder holds a
// readable, non-empty scenario.resolved.yaml; the first of the cells that
// tie, or the cell of `run_dir` itself when it is one of the sweep's runs. `run_seed`: the run's
// `seed`. Throws InputError at --against when the folder holds no store, or no run folder with a
// resolved scenario (runs/ removed: the cell is found by it).
RunCell FindRunCell(const std::string& sweep_dir, const std::string& run_dir,
                    const std::string& run_resolved, uint64_t run_seed);

// A catalogue metric's value as the run report's tables write it: a score
// of at most 1 with 3 decimals, a whole number as one, anything else with 4
// significant digits; with `sign`, signed and 0 unsigned; "–" when not
// finite.
std::string MetricValueText(const CatalogueMetric& m, double v, bool sign);

// The run report's section for `cell`: who the cell is, how it differs
// from run A, whether its run of A's seed gives A's metrics, and per
// catalogue metric A beside the cell's seeds (mean, 95 % interval, range,
// A's place among them). `headline`: A's catalogue metrics; `build`: the
// build that made A ("" when its manifest names none).
std::string RunCellSection(const RunCell& cell, const std::map<std::string, double>& headline,
                           const std::string& build);

}  // namespace hcpf::studies
