#pragma once
// A sweep: one base scenario varied over a grid (cartesian product) and zip
// (parallel lists) of dotted scenario keys, times a number of seeds; or
// several base scenarios, swept like a key by `grid: {base: [a.yaml, b.yaml]}`
// (kSweptBaseKey: each grid combination's runs start from that file). Loaded
// from YAML (docs/sweeps.md is the schema), expanded into runs, each run a
// validated Scenario keyed by ConfigHash of its resolved YAML.
//
//   SweepSpec spec = LoadSweepFile("scenarios/sweeps/default.yaml");
//   std::vector<SweepRun> runs = ExpandSweep(spec);    // every scenario validated
//   SweepResult r = RunSweep(spec, runs, {.out_dir = "out", .jobs = 2});
//
// Expansion order (the run index): grid keys vary like nested loops in file
// order, the last grid key fastest; then the zip position; then the seed
// (innermost). index = ((grid_combination * zip_length) + zip_position) * seeds + seed_index.

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hcpf/core/error.h"
#include "hcpf/scenarios/scenario.h"

namespace hcpf::studies {

// One swept key with its values as YAML text (flow style), each with the
// place in the sweep file where it is written.
struct SweepAxis {
  std::string key;  // dotted scenario key, e.g. "tracker.particles"
  std::vector<std::string> values;
  std::vector<SourceLocation> where;
};

// What `hcpf report` plots: y metrics against x, one line per series value.
struct ReportSpec {
  std::string x;               // a swept key ("" = the first grid key)
  std::vector<std::string> y;  // metric names (MetricNames(), metric_catalogue.h)
  std::string series;          // a swept key or "" (one line)
  // A catalogue metric to place each cell at on the x axis (its mean over the
  // cell's runs) instead of the swept value of `x`, which still orders the
  // points of a line: e.g. recall against the measured target size in px
  // while the camera altitude is swept. "" = the swept value.
  std::string x_metric;
  // Swept keys (not x, not series) whose values are pooled: a cell holds the
  // runs of every value of these keys, like more seeds ("all" in tables).
  std::vector<std::string> pool;
  // A swept key (not x, series or pooled) drawn as panels: every y metric
  // gets one plot per value of this key, its lines the cells of that value
  // (e.g. `base`: one figure per base scenario). "" = one plot per metric.
  std::string panels;
  // A value of `series` (as written in the sweep file) that the others are
  // compared with, seed by seed: the report's paired differences (each other
  // series value minus this one at every x). "" = the first series value.
  std::string reference;
};

// The first rule a report block breaks, or nullopt. `entry` is the report
// key ("x", "series", "x_metric", "y", "pool", "panels", "reference"),
// `item` the index in y or pool (-1: the entry itself), `value` the value
// that broke it ("" for an empty y), `expected` what it should have been. The sweep file's report:
// block (which adds locations and "did you mean" hints, and checks that reference is a value of the
// series key) and a results store's stored meta are both held to these rules.
struct ReportRuleBreak {
  std::string entry;
  int item = -1;
  std::string value;
  std::string expected;
};
std::optional<ReportRuleBreak> CheckReportRules(const ReportSpec& report,
                                                const std::vector<std::string>& swept);

// The grid key that sweeps the base scenario itself: its values are scenario
// files (found like `base:`), and the runs of each grid combination start
// from that file. Swept in `grid` only, and instead of a top-level `base:`.
inline constexpr const char* kSweptBaseKey = "base";

struct SweepSpec {
  std::string file;  // the sweep file ("" for text)
  std::string
      base_path;  // the base scenario, resolved to an existing file (the first of base_paths)
  // With `grid.base`: every value's scenario file, resolved, in the order of
  // the grid's values; else the one base_path.
  std::vector<std::string> base_paths;
  uint64_t seed = 1;  // root of the derived run seeds
  // Where `seed` comes from: the sweep file's `seed:` (1 when absent) or a
  // command's option (SetRootSeed), e.g. "--seed".
  std::string seed_from = "sweep file";
  uint64_t file_seed = 1;      // the file's own `seed:` (1 when absent), kept beside an override
  int seeds = 0;               // 0 = `seeds` absent: every run keeps the base scenario's seed
  SourceLocation seeds_where;  // where `seeds` is written (line 0 when absent)
  std::vector<SweepAxis> grid;
  std::vector<SweepAxis> zip;
  ReportSpec report;

  // Every swept key in column order: grid keys, then zip keys.
  std::vector<std::string> SweptKeys() const;
  // Runs in the expansion: product of grid lengths * zip length * max(seeds, 1).
  // Throws InputError when that exceeds kMaxSweepRuns (or 2^63).
  int64_t RunCount() const;
};

// The most runs one sweep file may expand to (a store and a run list of this
// size take a few GB); larger studies are split into several sweep files.
inline constexpr int64_t kMaxSweepRuns = 10'000'000;
int64_t CheckedRunCount(const SweepSpec& spec);

// A cell's place in the sweep's lists: its position in each grid key's values
// (the last grid key varies fastest) and its zip position. `grid_lengths` are
// the grid keys' numbers of values, `zip_length` the zip's (1 without one);
// cell = run index / max(seeds, 1).
struct CellPlace {
  std::vector<int64_t> digits;
  int64_t zip_position = 0;
};
CellPlace PlaceOfCell(const std::vector<int64_t>& grid_lengths, int64_t zip_length, int64_t cell);

// One run of a sweep.
struct SweepRun {
  int64_t index = 0;
  int seed_index = 0;
  uint64_t seed = 0;                        // the scenario seed the run uses
  std::vector<std::string> values;          // per SweptKeys(), YAML text
  std::vector<config::Override> overrides;  // swept values, then `seed` (when seeds > 0)
  // The scenario of the run's cell, shared by the runs of the cell that were
  // reseeded from it (scenario() applies `seed`).
  std::shared_ptr<const scenarios::Scenario> cell;
  std::string key;  // ConfigHash(scenario())

  // The run's resolved scenario.
  scenarios::Scenario scenario() const;
  // Whether the run observes rendered frames (observation.source: rendered).
  bool rendered() const;
};

// hcpf sweep --seed S: the runs derive their seeds from S instead of the
// file's `seed:` (a replication on new seeds without a copy of the file; the
// runs, and so the sweep's hash, change with S). `option` names the option in
// errors and in the store ("--seed"). Throws InputError naming `option` when
// `text` is not a seed (a non-negative integer below 2^64), and when the sweep
// has no `seeds:` (its runs keep the base scenario's seed, which S would not
// change).
void SetRootSeed(SweepSpec& spec, const std::string& text, const std::string& option);

// The derived seed of seed index i: Rng(sweep_seed).Fork("sweep/seed", i).identity().
uint64_t SweepSeed(uint64_t sweep_seed, int index);

// Whether `path` reads as a sweep file rather than a scenario: a YAML mapping
// with `base`, `grid` or `zip` at the top, keys no scenario has. False when
// it cannot be read or parsed (the scenario reader then says why).
bool IsSweepFile(const std::string& path);

// Loads and validates a sweep file. `base` is looked for relative to the
// sweep file, then the current directory, then the project root. Throws
// InputError (file:line:col, key, expected, found, did-you-mean).
SweepSpec LoadSweepFile(const std::string& path);
// As LoadSweepFile for text; `dir` is where relative base paths start.
SweepSpec LoadSweepText(const std::string& text, const std::string& file_name,
                        const std::string& dir);

// Before anything runs: a warning when the sweep's seeds are too few for the
// report's paired comparisons (report.series against its reference at every
// other cell, times report.y) to survive Holm's correction whatever the data
// (SignedRankFloor, PairsForHolm in statistics.h), with the seeds that would
// be enough; "" when they are, without report.series or with fewer than 2
// seeds (one run per cell: nothing to pair). A series zipped with other keys
// counts a comparison per zip position but the reference's. Pooled values
// add no pairs (a seed's pooled runs are averaged into one value). The count
// is the most the report can make (a metric without pairs in a cell is not a
// comparison).
std::string SeedsForHolmNote(const SweepSpec& spec);

// Before anything runs: a warning when report.pool lists a zip key zipped
// with a key it does not list: only the zip positions that share their
// values of the unpooled keys share a cell, so the pooled key is pooled only
// there (nowhere when those values differ at every position). "" otherwise,
// and when the unpooled keys never change (everything is pooled).
std::string ZippedPoolNote(const SweepSpec& spec);

// Before anything runs, from ExpandSweep's runs: scenarios::CameraTurnNote
// for a sweep, a warning when the image turns by more than 5 degrees about
// its centre between two frames in any cell (a swept camera.path, or a swept
// key it depends on), counting those cells and naming the one that turns
// most; "" when none does. `hcpf validate` and `hcpf sweep` print it.
std::string CameraTurnNote(const SweepSpec& spec, const std::vector<SweepRun>& runs);

// Before anything runs: scenarios::TargetOverlapNote for a sweep, a warning
// when two targets drive through each other in any cell, counting those
// cells and naming the first with its note; "" when none. `hcpf validate`
// and `hcpf sweep` print it.
std::string TargetOverlapNote(const SweepSpec& spec, const std::vector<SweepRun>& runs);

// The run list in expansion order (see top). Every run's scenario is loaded
// and validated; a bad swept value throws InputError naming the sweep file
// line of that value.
std::vector<SweepRun> ExpandSweep(const SweepSpec& spec);

// Identity of a sweep: a hash of its run keys in order. Stores of the same
// sweep (shards, resumed runs) have the same hash.
std::string SweepHash(const std::vector<SweepRun>& runs);

struct SweepOptions {
  std::string out_dir;
  int jobs = 1;  // worker threads, one run each
  // Threads inside each run (scenarios::RunOptions::threads, `hcpf run
  // --threads`): the tracker's per-filter stages and the rendered frames'
  // sensor effects and cache writes. Outputs are identical for any value;
  // worth more than 1 when --jobs leaves cores idle (few, long runs).
  int run_threads = 1;
  int shard_index = 0;  // run only runs with index % shard_count == shard_index
  int shard_count = 1;
  bool progress = true;
  // Rendered scenarios: the frame cache shared by all runs ("" = none). Runs
  // that differ only in tracker settings render their frames once.
  std::string frame_cache_dir;
  // Write overlay.mp4 in the runs of the first seed (seed index 0) of every
  // cell; `hcpf report` links them.
  bool video = false;
  // When set: the `hcpf` executable to run each run in a child process
  // (`hcpf run <resolved scenario>`), so a run that crashes is recorded as
  // failed and the sweep goes on. "" = runs in worker threads of this process.
  std::string isolate_exe;
  // When set: the `hcpf` executable that runs each *rendered* run in a child
  // process, as isolate_exe does, when several run at once (jobs > 1); the
  // others stay in worker threads. `hcpf sweep` sets it outside MPI. The GL
  // contexts of one process share llvmpipe's one rasteriser, which each
  // process runs on the thread that draws (GlContext::Create: its threads
  // race on fences), so contexts on two threads would render in turn under
  // its lock; children render side by side, and a run that crashes fails
  // alone (docs/sweeps.md, docs/performance.md). A run whose frames are all
  // in the frame cache when it starts renders nothing (no GL context) and
  // stays in a worker thread, sparing a process's start. "" = rendered runs
  // in worker threads too (a library caller without the executable).
  std::string render_exe;
  // Other sweep folders (`hcpf sweep --reuse`, any sweep's): a run this sweep
  // has not finished whose key (the resolved scenario's hash) one of them
  // holds finished, with its folder intact, is copied from there instead of
  // computed; one resolved scenario gives the same files (docs/outputs.md).
  // The first folder that holds the run whole gives it; an external
  // tracker's runs are never copied (its program is in the key by path).
  std::vector<std::string> reuse_dirs;
  // `hcpf sweep --move-aside`: an out_dir holding another sweep's store (runs
  // keyed by another hcpf, or a sweep file, scenario or model edited since)
  // is renamed out_dir.before-<UTC time> and read as the first reuse_dirs
  // folder, instead of being refused.
  bool move_aside = false;
  void Validate() const;
  // Whether `run` is run in a child process: every run under isolate_exe;
  // a rendered one under render_exe when jobs > 1, unless FramesAllCached.
  // Asked when the run starts (a first wave caches the frames later runs
  // read).
  bool InChildProcess(const SweepRun& run) const;
  // Whether frame_cache_dir holds a file for each frame of `run` (rendered):
  // it then renders nothing, unless a file proves unreadable.
  bool FramesAllCached(const SweepRun& run) const;
  // The executable for InChildProcess's runs ("" when there are none).
  const std::string& ChildExe() const { return isolate_exe.empty() ? render_exe : isolate_exe; }
};

struct SweepResult {
  int64_t total = 0;     // runs of this shard
  int64_t reused = 0;    // already finished in the store, or copied from a --reuse folder
  int64_t copied = 0;    // of those, copied from a --reuse folder
  int64_t computed = 0;  // run now, successfully
  int64_t failed = 0;    // run now, failed (recorded with the message)
};

// Runs the sweep into options.out_dir: results.sqlite (one row per run,
// committed as each run finishes) and runs/<key>/ (each run's outputs).
// Runs already in the store with status ok are skipped. Throws InputError
// when out_dir holds a store of a different sweep.
SweepResult RunSweep(const SweepSpec& spec, const std::vector<SweepRun>& runs,
                     const SweepOptions& options);

}  // namespace hcpf::studies
