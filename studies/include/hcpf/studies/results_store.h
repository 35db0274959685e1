#pragma once
// The results store of a sweep: DIR/results.sqlite (SQLite, WAL journal).
//
//   table meta(name TEXT PRIMARY KEY, value TEXT): sweep_hash, sweep_file,
//       swept_keys (JSON list), report (JSON), base_resolved (YAML), run_count,
//       root_seed, root_seed_from, expansion (JSON) (StoreMeta)
//   table runs: key TEXT PRIMARY KEY (ConfigHash of the resolved scenario),
//       run_index, seed_index, seed (decimal text: seeds are 64-bit unsigned),
//       one TEXT column per swept key (named by the key, e.g. "tracker.particles"),
//       status ('ok' | 'failed'), error, run_dir, one REAL column per
//       HeadlineMetrics() name (NULL when failed or not a number), build
//       (RunRecord::build; NULL in rows put before the column existed)
//
// Every Put() is one transaction, so a killed process loses at most the runs
// it had not yet put. Thread-safe (one connection behind a mutex).

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "hcpf/studies/sweep.h"

struct sqlite3;

namespace hcpf::studies {

// The format of the stores this version writes and reads (meta "format").
inline constexpr const char* kStoreFormat = "hcpf-results/1";

// The sweep's expansion as a store records it (meta "expansion"): every grid
// key's and zip key's values, as YAML text the way the rows hold them, and
// `seeds`. A row's seed index and swept values follow from its run index, so
// a reader can tell a row edited by hand (a swept value changed to a value
// the sweep does not have drew a cell of its own) from one the sweep wrote.
struct StoredExpansion {
  struct Axis {
    std::string key;
    std::vector<std::string> values;
  };
  std::vector<Axis> grid;  // in file order, the last varying fastest
  std::vector<Axis> zip;   // lists of one length
  int seeds = 0;           // 0: every run keeps its base scenario's seed

  // The runs it expands to: product of grid lengths * zip length * max(seeds, 1).
  int64_t RunCount() const;
  // The seed index of run `index`.
  int SeedIndex(int64_t index) const;
  // The swept values of run `index` (grid keys, then zip keys).
  std::vector<std::string> Values(int64_t index) const;
};
StoredExpansion ExpansionOf(const SweepSpec& spec);

struct StoreMeta {
  std::string sweep_hash;
  std::string sweep_file;
  std::vector<std::string> swept_keys;
  ReportSpec report;
  std::string base_resolved;  // the resolved base scenario (YAML)
  int64_t run_count = 0;      // runs of the whole sweep (all shards)
  // Absent in a store written before it was recorded (2026-12-06): its rows'
  // labels are then read as they are.
  std::optional<StoredExpansion> expansion;
  // The root of the runs' derived seeds (decimal) and where it came from:
  // "sweep file" (its `seed:`) or an option ("--seed"), with the file's own
  // seed then (root_file_seed). Without `seeds:` root_seed_from is "base
  // scenario" (every run keeps its seed) and the others are empty; all
  // three are empty in a store written before they were recorded.
  std::string root_seed;
  std::string root_seed_from;
  std::string root_file_seed;
};

// The meta of the sweep's seeds (StoreMeta::root_seed...), from its spec.
void SetRootSeedMeta(const SweepSpec& spec, StoreMeta& meta);
// Whether both stores name a root seed and they differ (another replication
// of the sweep file: another sweep, said as such).
bool OfOtherRootSeeds(const StoreMeta& a, const StoreMeta& b);
// A sentence for reports on where the runs' seeds come from, e.g. "The runs'
// seeds are derived from root seed 3, given by `hcpf sweep --seed 3` (the
// sweep file's `seed:` is 1)." Markdown (backticks for code).
std::string RootSeedSentence(const StoreMeta& meta);

// Each base scenario's resolved YAML, by the value naming it, from a
// grid.base sweep's base_resolved (every base's text headed by
// "# base: VALUE", in the order of the expansion's values). Empty when the
// store sweeps no base, records no expansion, or its text lacks a head.
std::map<std::string, std::string> ResolvedBases(const StoreMeta& meta);

// When a store holds fewer rows than the sweep has runs (a sweep stopped
// before its end, one shard of several): a sentence saying how many are
// missing and how to get them, for reports and exports made of the rest.
// "" when every run is there. Markdown (backticks for code).
std::string MissingRunsSentence(const StoreMeta& meta, size_t stored_runs);

// A warning for readers of a store that records no expansion (written
// before 2026-12-06): its rows' labels are read unchecked. "" when it has one.
class ResultsStore;
std::string UncheckedLabelsSentence(const ResultsStore& store);

struct RunRecord {
  std::string key;
  int64_t index = 0;
  int seed_index = 0;
  uint64_t seed = 0;
  std::vector<std::string> values;  // per StoreMeta::swept_keys
  bool ok = false;
  std::string error;
  std::string run_dir;                    // relative to the store's folder, e.g. "runs/<key>"
  std::map<std::string, double> metrics;  // HeadlineMetrics() names; NaN = missing
  // The build that made the run, as its manifest names it ("<hcpf_version>
  // at <git_revision>", "" when it names none): the sweep report's "which
  // builds made the runs" without reading every manifest. Absent in rows of
  // a store written before the column (ReadRunBuild reads the manifest then).
  std::optional<std::string> build;
};

// How a store is opened: report and merge only read theirs (a store on
// read-only media or in a folder the user may not write can still be read).
enum class StoreAccess { kReadOnly, kReadWrite };

class ResultsStore {
 public:
  // Opens an existing store. Throws InputError when `path` is missing, not a
  // store or damaged (the message says to delete it to recompute), RunError
  // when permissions forbid the access asked for.
  static std::unique_ptr<ResultsStore> Open(const std::string& path,
                                            StoreAccess access = StoreAccess::kReadOnly);
  // Opens `path`, creating it with `meta` when absent. Throws InputError when
  // it exists and holds a different sweep (another sweep_hash). An existing
  // store of the sweep is first shown to `check` on a read-only connection,
  // before anything is written to it (the descriptive meta, the journal
  // mode): a store `check` refuses by throwing is left byte for byte as it was.
  static std::unique_ptr<ResultsStore> OpenOrCreate(
      const std::string& path, const StoreMeta& meta,
      const std::function<void(const ResultsStore&)>& check = {});

  ~ResultsStore();
  ResultsStore(const ResultsStore&) = delete;
  ResultsStore& operator=(const ResultsStore&) = delete;

  const StoreMeta& meta() const { return meta_; }
  const std::string& path() const { return path_; }
  // Inserts or replaces the row of record.key in one transaction.
  void Put(const RunRecord& record);
  // Every row, sorted by run index. Throws InputError naming the row and
  // column when a row's seed index, seed or swept values are not what the
  // store's expansion (when it has one) says of its run index.
  std::vector<RunRecord> Runs() const;
  // Every row with its labels as stored: for the sweep, which rewrites a
  // row's labels from its own expansion (resuming a store edited by hand, or
  // a sweep file that writes a value otherwise, 0.10 for 0.1).
  std::vector<RunRecord> RunsAsStored() const;

 private:
  ResultsStore(std::string path, sqlite3* db);
  void Exec(const std::string& sql) const;
  void ReadMeta();
  std::vector<RunRecord> ReadRuns(bool check_labels) const;
  // The runs table's number of rows when none of their seeds follows from
  // `root` at its seed index (SweepSeed); 0 when one does.
  int64_t RowsIfNoSeedFollows(uint64_t root) const;
  StoredExpansion ReadExpansion(const std::string& text) const;
  // InputError when the meta read does not fit the store: a swept key
  // without its column, a report naming an unknown metric or key.
  void CheckStoredMeta() const;
  // A store written before a metric joined the catalogue, or before the
  // build column, lacks the column: added (empty) when the store is
  // writable, read as missing when not.
  void AddMissingColumns(StoreAccess access);

  std::string path_;
  sqlite3* db_ = nullptr;
  StoreMeta meta_;
  // What each row's seed follows from, read with the expansion: with
  // `seeds:` the root seed (SweepSeed(root, seed index)); without `seeds:`
  // and `grid.base`, the base scenario's seed, every run's.
  std::optional<uint64_t> root_seed_;
  std::optional<uint64_t> base_seed_;
  // With `grid.base` and without `seeds:`: each base scenario's seed, by the
  // value that names it.
  std::map<std::string, uint64_t> base_seeds_;
  std::set<std::string> absent_metrics_;  // read-only stores of an older catalogue
  bool build_absent_ = false;             // a read-only store older than the build column
  mutable std::mutex mutex_;
};

// Reads the headline metrics of a finished run folder from its metrics.json
// and manifest.json (ms_per_frame = 1000 * timings.tracker_s / frames). Throws
// RunError when the files are missing or malformed.
std::map<std::string, double> ReadRunMetrics(const std::string& run_dir);

// Sets record.metrics (ReadRunMetrics) and record.build from the finished run
// folder `run_dir`, reading its manifest once. Throws as ReadRunMetrics.
void ReadRunFolderInto(const std::string& run_dir, RunRecord& record);

// The build a run folder's manifest.json names ("<hcpf_version> at
// <git_revision>"), "" when the manifest is missing, unreadable or names no
// git revision. Reads only the manifest's top level.
std::string ReadRunBuild(const std::string& run_dir);

// What RunFolderIntact asks by default of a folder written before manifests
// listed their files (2026-11-23): the files resume, --reuse and merge need.
// (Export asks only for the three it copies: the oldest folders lack
// camera_motion.csv.)
inline constexpr std::array<const char*, 7> kRunFilesBeforeTheList = {
    "scenario.resolved.yaml", "gt/gt.txt",  "seqinfo.ini",      "gt.json",
    "detections.txt",         "tracks.txt", "camera_motion.csv"};

// Whether a run folder still holds the run the store records: its
// metrics.json and manifest.json read back (ReadRunMetrics) to exactly the
// record's metrics, and every file the manifest lists under "files" is there
// with the size it was written with (a manifest without the list: every file
// of `files_before_the_list` is there). False when the folder was deleted or
// a file removed, cut short, emptied or damaged.
bool RunFolderIntact(const std::string& run_dir, const RunRecord& record,
                     std::span<const char* const> files_before_the_list = kRunFilesBeforeTheList);

// Checks that `dir` may take a sweep's outputs (`option` names the argument:
// "--out", "OUT"): a folder that does not exist yet, an empty one, or one a
// sweep or merge wrote (it holds results.sqlite, or only what a sweep writes
// before its store: runs/ and sweep.lock). Anything else, a run folder of
// hcpf run among them, is an InputError naming what it holds: a sweep there
// would mix its files with someone else's.
void CheckSweepFolder(const std::string& dir, const std::string& option);

struct MergeResult {
  int64_t added = 0;           // rows new to the output store
  int64_t duplicates = 0;      // rows whose key was already there (not counted twice)
  int64_t damaged = 0;         // ok rows whose run folder was missing or damaged: merged as failed
  bool contact_sheet = false;  // a shard's contact_sheet.png was copied to OUT
};
// Merges the stores (and run folders) of `input_dirs` into `out_dir`. Every
// store must be of the same sweep (else InputError naming the odd one out).
// A row already present with status ok is kept; a failed row is replaced by
// an ok one. An ok row whose run folder is missing or damaged (RunFolderIntact)
// is merged as failed, so resuming the sweep on `out_dir` recomputes it.
MergeResult MergeStores(const std::string& out_dir, const std::vector<std::string>& input_dirs);

}  // namespace hcpf::studies
