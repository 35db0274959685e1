// Results store, RunSweep (parallel = serial, resume, failures, shards + merge).

#include "hcpf/studies/results_store.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <vector>

#include "hcpf/metrics/report.h"
#include "hcpf/scenarios/models.h"
#include "hcpf/scenarios/run.h"
#include "hcpf/studies/metric_catalogue.h"
#include "hcpf/studies/report.h"
#include "hcpf/studies/sweep.h"
#include "sweep_fixture.h"

namespace hcpf::studies {

namespace {

namespace fs = std::filesystem;
using testing::SweepFolder;
using testing::WriteSweep;

// 2 particle counts x 2 resamplers x 2 seeds = 8 tiny runs (20 frames).
const char* kSweep =
    "base: base.yaml\n"
    "seeds: 2\n"
    "grid:\n"
    "  tracker.particles: [20, 60]\n"
    "  tracker.resampling.method: [systematic, charged]\n"
    "report: {x: tracker.particles, series: tracker.resampling.method, y: [da_accuracy, idf1]}\n";

// The deterministic part of a row (timings excluded).
std::string RowText(const RunRecord& r) {
  std::string s = r.key + " " + std::to_string(r.index) + " " + std::to_string(r.seed) +
                  (r.ok ? " ok" : " failed");
  for (const auto& v : r.values) s += " " + v;
  for (const auto& [m, v] : r.metrics) {
    if (m == "ms_per_frame" || m == "wall_time_s") continue;
    s += " " + m + "=" + (std::isfinite(v) ? std::to_string(v) : "nan");
  }
  return s + " build=" + r.build.value_or("(none)");
}

std::vector<std::string> StoreRows(const fs::path& dir) {
  std::vector<std::string> rows;
  for (const RunRecord& r : ResultsStore::Open((dir / "results.sqlite").string())->Runs())
    rows.push_back(RowText(r));
  return rows;
}

SweepOptions Options(const fs::path& out, int jobs) {
  SweepOptions o;
  o.out_dir = out.string();
  o.jobs = jobs;
  o.progress = false;
  return o;
}

// The meta of a sweep of two runs over tracker.particles, reported by IDF1.
StoreMeta TwoRunMeta() {
  StoreMeta meta;
  meta.sweep_hash = "abc";
  meta.sweep_file = "s.yaml";
  meta.swept_keys = {"tracker.particles"};
  meta.report = {"tracker.particles", {"idf1"}, ""};
  meta.run_count = 2;
  return meta;
}

// The meta of a sweep with no swept key, reported by IDF1 (hand stores).
StoreMeta UnsweptMeta() {
  StoreMeta meta;
  meta.sweep_hash = "abc";
  meta.sweep_file = "s.yaml";
  meta.report = {"", {"idf1"}, ""};
  return meta;
}

// Runs `sql` on the store at `path` (hand edits).
void ExecSql(const std::string& path, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK)
      << sql << ": " << sqlite3_errmsg(db);
  sqlite3_close(db);
}

// Puts the store `good` back at `path`, runs `sql` on it, and expects the
// store opened (with `rows`: its rows read too) to be refused as bad input
// whose message holds `expected`.
void ExpectRefusedAfterEdit(const std::string& good, const std::string& path,
                            const std::string& sql, const std::string& expected, bool rows) {
  fs::copy_file(good, path, fs::copy_options::overwrite_existing);
  ExecSql(path, sql);
  try {
    const auto store = ResultsStore::Open(path);
    if (rows) store->Runs();
    ADD_FAILURE() << sql << " was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
  }
}

TEST(ResultsStore, PutRunsRoundTripAndRefusesAnotherSweep) {
  const auto dir = SweepFolder("store");
  StoreMeta meta = TwoRunMeta();
  const std::string path = (dir / "results.sqlite").string();
  {
    auto store = ResultsStore::OpenOrCreate(path, meta);
    RunRecord r;
    r.key = "k2";
    r.index = 1;
    r.seed = 18446744073709551615ULL;  // 2^64 - 1 survives (stored as text)
    r.values = {"50"};
    r.ok = true;
    r.metrics = {{"idf1", 0.75}, {"hota", std::nan("")}};
    store->Put(r);
    r.key = "k1";
    r.index = 0;
    r.ok = false;
    r.error = "boom";
    r.metrics.clear();
    store->Put(r);
  }
  auto store = ResultsStore::Open(path);
  EXPECT_EQ(store->meta().report.y, std::vector<std::string>{"idf1"});
  const auto runs = store->Runs();
  ASSERT_EQ(runs.size(), 2U);
  EXPECT_EQ(runs[0].key, "k1");  // sorted by run index
  EXPECT_FALSE(runs[0].ok);
  EXPECT_EQ(runs[0].error, "boom");
  EXPECT_EQ(runs[1].seed, 18446744073709551615ULL);
  EXPECT_DOUBLE_EQ(runs[1].metrics.at("idf1"), 0.75);
  EXPECT_TRUE(std::isnan(runs[1].metrics.at("hota")));
  store.reset();
  // A store of another sweep is refused and left byte for byte as it was (a
  // bad-input audit: the refusal rewrote its header, switching its journal).
  const auto bytes = [&path] {
    std::ifstream in(path, std::ios::binary);
    return std::string(std::istreambuf_iterator<char>(in), {});
  };
  const std::string before = bytes();
  meta.sweep_hash = "other";
  EXPECT_THROW(ResultsStore::OpenOrCreate(path, meta), InputError);
  EXPECT_EQ(bytes(), before);
}

// A store that cannot be made (a full disk: RLIMIT_FSIZE 0 in a child
// process) fails and leaves nothing: a sweep on a full disk left an empty
// results.sqlite.new beside its lock for good.
TEST(ResultsStore, AStoreThatCannotBeMadeLeavesNoFile) {
  const auto dir = SweepFolder("store-full");
  const StoreMeta meta = TwoRunMeta();
  const std::string path = (dir / "results.sqlite").string();
  const int code = hcpf::testing::InChildWithFileSizeLimit(0, [&] {
    try {
      ResultsStore::OpenOrCreate(path, meta);
    } catch (const std::exception&) {
      return 0;
    }
    return 4;  // no error
  });
  EXPECT_EQ(code, 0) << "4: the store was made";
  std::set<std::string> left;
  for (const auto& e : fs::directory_iterator(dir)) left.insert(e.path().filename().string());
  EXPECT_EQ(left, std::set<std::string>{"base.yaml"});  // the fixture's
  ResultsStore::OpenOrCreate(path, meta);               // and without the limit, made
  EXPECT_TRUE(fs::exists(path));
}

// A store whose meta table was edited after the sweep wrote it is bad input
// naming the meta entry, before anything reads the runs (a second bad-input
// audit: an unknown metric in report.y failed the report with "map::at",
// exit 1; format hcpf-results/99, an empty report.y and a swept key without
// its column were read as if nothing were wrong).
TEST(ResultsStore, HandEditedMetaIsBadInputNamingTheEntry) {
  const auto dir = SweepFolder("store-meta");
  StoreMeta meta;
  meta.sweep_hash = "abc";
  meta.sweep_file = "s.yaml";
  meta.swept_keys = {"tracker.particles", "tracker.resampling.method"};
  meta.report = {"tracker.particles", {"idf1", "hota"}, "tracker.resampling.method"};
  const std::string path = (dir / "results.sqlite").string();
  ResultsStore::OpenOrCreate(path, meta);
  const std::string good = (dir / "good.sqlite").string();
  fs::copy_file(path, good);
  const std::string report_of =
      R"({"x":"tracker.particles","series":"tracker.resampling.method","y":)";
  const std::vector<std::tuple<std::string, std::string, std::string>> edits = {
      {"format", "hcpf-results/99",
       R"(meta.format: expected a results store of this hcpf sweep (format "hcpf-results/1"), found format "hcpf-results/99")"},
      {"report", report_of + R"(["idf1","nosuch"]})",
       R"(meta.report.y[1]: expected a results store of hcpf sweep: a metric name (da_accuracy, )"},
      {"report", report_of + R"(["idf1","idf1"]})",
       R"(meta.report.y[1]: expected a results store of hcpf sweep: a metric listed once in report.y, found "idf1")"},
      {"report", report_of + "[]}",
       "meta.report.y: expected a results store of hcpf sweep: a non-empty list of metric names, "
       "found an empty list"},
      {"report", R"({"x":"nosuch","y":["idf1"]})",
       R"(meta.report.x: expected a results store of hcpf sweep: a swept key (tracker.particles, tracker.resampling.method), found "nosuch")"},
      {"report", R"({"x":"tracker.particles","series":"s","y":["idf1"]})", "meta.report.series"},
      {"report", R"({"x":"tracker.particles","pool":["p"],"y":["idf1"]})", "meta.report.pool[0]"},
      // The rules of the sweep file's report: block that the store's check
      // had not restated (one CheckReportRules serves both now).
      {"report", R"({"x":"tracker.particles","series":"tracker.particles","y":["idf1"]})",
       "meta.report.series: expected a results store of hcpf sweep: a swept key other than "
       "report.x"},
      {"report", report_of + R"(["idf1"],"pool":["tracker.particles"]})",
       "meta.report.pool[0]: expected a results store of hcpf sweep: a swept key other than "
       "report.x and report.series, listed once"},
      {"report", report_of + R"(["idf1"],"panels":"tracker.resampling.method"})",
       "meta.report.panels: expected a results store of hcpf sweep: a swept key other than "
       "report.x, report.series and the pooled keys"},
      {"report", R"({"x":"tracker.particles","reference":"charged","y":["idf1"]})",
       "meta.report.reference: expected a results store of hcpf sweep: no report.reference "
       "without report.series"},
      {"report", R"({"x":"tracker.particles","x_metric":"nosuch","y":["idf1"]})",
       "meta.report.x_metric"},
      {"swept_keys", R"(["tracker.particles","tracker.resampling.method","zzz"])",
       R"(meta.swept_keys: expected a results store of hcpf sweep: swept keys listed once, each a column of the runs table, found "zzz")"},
      // A third audit: std::stoll's and the JSON library's texts, no key;
      // a negative count reported as "8 of -5 runs".
      {"run_count", "abc",
       R"(meta.run_count: expected a results store of hcpf sweep: a whole number of runs, 0 or more, found "abc")"},
      {"run_count", "-5",
       R"(meta.run_count: expected a results store of hcpf sweep: a whole number of runs, 0 or more, found "-5")"},
      {"swept_keys", "[\"tracker.particles\"",
       R"(meta.swept_keys: expected a results store of hcpf sweep: a JSON list of the swept keys, found "["tracker.particles"")"},
      {"swept_keys", "[1, 2]",
       "meta.swept_keys: expected a results store of hcpf sweep: a JSON list of the swept keys"},
      {"report", "[1]",
       R"(meta.report: expected a results store of hcpf sweep: the sweep file's report: block as a JSON object, found "[1]")"},
      // A fourth audit: the JSON library's "type must be string" naming
      // only meta; an unknown key ignored.
      {"report", R"({"x": "tracker.particles", "y": ["idf1"], "series": 5})",
       R"(meta.report.series: expected a results store of hcpf sweep: text, found 5)"},
      {"report", R"({"x": "tracker.particles", "y": "idf1"})",
       R"(meta.report.y: expected a results store of hcpf sweep: a list of text, found "idf1")"},
      {"report", R"({"x": "tracker.particles", "y": ["idf1"], "extra": 1})",
       R"(meta.report: expected a results store of hcpf sweep: the keys panels, pool, reference, series, x, x_metric, y, found "extra")"},
  };
  for (const auto& [name, value, expected] : edits) {
    fs::copy_file(good, path, fs::copy_options::overwrite_existing);
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    sqlite3_stmt* s = nullptr;
    ASSERT_EQ(sqlite3_prepare_v2(db, "UPDATE meta SET value = ? WHERE name = ?", -1, &s, nullptr),
              SQLITE_OK);
    sqlite3_bind_text(s, 1, value.c_str(), -1, SQLITE_TRANSIENT);
    sqlite3_bind_text(s, 2, name.c_str(), -1, SQLITE_TRANSIENT);
    ASSERT_EQ(sqlite3_step(s), SQLITE_DONE);
    sqlite3_finalize(s);
    sqlite3_close(db);
    try {
      ResultsStore::Open(path, StoreAccess::kReadOnly);
      ADD_FAILURE() << name << " = " << value << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
  // The store as written opens.
  fs::copy_file(good, path, fs::copy_options::overwrite_existing);
  EXPECT_EQ(ResultsStore::Open(path)->meta().report.y, (std::vector<std::string>{"idf1", "hota"}));
}

// The journal mode a fresh connection finds in the file (persistent for WAL).
std::string JournalMode(const std::string& path) {
  sqlite3* db = nullptr;
  EXPECT_EQ(sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  sqlite3_stmt* s = nullptr;
  EXPECT_EQ(sqlite3_prepare_v2(db, "PRAGMA journal_mode", -1, &s, nullptr), SQLITE_OK);
  std::string mode;
  if (sqlite3_step(s) == SQLITE_ROW)
    mode = reinterpret_cast<const char*>(sqlite3_column_text(s, 0));
  sqlite3_finalize(s);
  sqlite3_close(db);
  return mode;
}

// A writer works in WAL mode (readers do not block it); once it is done the
// store is one file again, and reading it (report, export, merge) leaves no
// -wal or -shm beside it. A reader still open when the writer finishes keeps
// the store in WAL mode, readable; the next writer finishes the switch.
TEST(ResultsStore, AFinishedStoreIsOneFileThatReadersLeaveAlone) {
  const auto dir = SweepFolder("journal");
  StoreMeta meta;
  meta.sweep_hash = "abc";
  meta.swept_keys = {"tracker.particles"};
  meta.report = {"tracker.particles", {"idf1"}, ""};
  const std::string path = (dir / "results.sqlite").string();
  const auto sidecars = [&] {
    return static_cast<int>(fs::exists(path + "-wal")) +
           static_cast<int>(fs::exists(path + "-shm"));
  };
  RunRecord r;
  r.key = "k";
  r.values = {"50"};
  r.ok = true;
  r.metrics = {{"idf1", 0.5}};
  {
    auto store = ResultsStore::OpenOrCreate(path, meta);
    store->Put(r);
    EXPECT_EQ(JournalMode(path), "wal");
    EXPECT_TRUE(fs::exists(path + "-wal"));
  }
  EXPECT_EQ(JournalMode(path), "delete");
  EXPECT_EQ(sidecars(), 0);
  EXPECT_EQ(ResultsStore::Open(path)->Runs().size(), 1U);
  EXPECT_EQ(sidecars(), 0) << "a read-only open left files beside the store";
  // Resumed: WAL again while writing, one file again after.
  {
    auto store = ResultsStore::OpenOrCreate(path, meta);
    EXPECT_EQ(JournalMode(path), "wal");
    r.key = "k2";
    r.index = 1;  // each run of a sweep has its own index
    store->Put(r);
  }
  EXPECT_EQ(JournalMode(path), "delete");
  EXPECT_EQ(sidecars(), 0);
  // A reader open while the writer finishes: the store stays in WAL mode,
  // with both rows readable.
  {
    auto writer = ResultsStore::OpenOrCreate(path, meta);
    auto reader = ResultsStore::Open(path);
    EXPECT_EQ(reader->Runs().size(), 2U);
    writer.reset();
    EXPECT_EQ(JournalMode(path), "wal");
    EXPECT_EQ(reader->Runs().size(), 2U);
  }
  EXPECT_EQ(ResultsStore::Open(path)->Runs().size(), 2U);
  ResultsStore::OpenOrCreate(path, meta).reset();
  EXPECT_EQ(JournalMode(path), "delete");
  EXPECT_EQ(sidecars(), 0);
}

// Runs the fixture's base scenario (its one run) into DIR/run.
fs::path RunBase(const fs::path& dir) {
  const std::vector<SweepRun> runs =
      ExpandSweep(LoadSweepFile(WriteSweep(dir, "base: base.yaml\n")));
  EXPECT_EQ(runs.size(), 1u);
  scenarios::RunOptions options;
  options.out_dir = (dir / "run").string();
  options.show_progress = false;
  scenarios::RunScenario(runs.at(0).scenario(), options);
  return options.out_dir;
}

// Every catalogue metric is found in a real run folder: a field renamed in
// metrics.json or manifest.json would otherwise become a column of NaNs.
TEST(MetricCatalogue, EveryEntryIsReadFromARealRunFolder) {
  const auto dir = SweepFolder("catalogue");
  const fs::path run = RunBase(dir);
  const std::map<std::string, double> m = ReadRunMetrics(run.string());
  ASSERT_EQ(m.size(), MetricCatalogue().size());
  // Detection quality exists only for rendered runs: its entries are checked
  // on the metrics.json the run writer makes with a detection block (one
  // frame, one exact detection: precision = recall = F1 = 1; its box is
  // 10 x 10 px, at visible fraction 1 so it also counts at >= 0.75; labelled
  // with its target, so its label accuracy is 1 as well).
  metrics::RunMetrics with_detection;
  metrics::DetectionFrame frame;
  frame.truth = {{ObjectId{1}, BoxPx{0, 0, 10, 10}, 1.0}};
  frame.detections = {{.box = BoxPx{0, 0, 10, 10}, .target = ObjectId{1}}};
  with_detection.detection = metrics::ScoreDetections(std::vector<metrics::DetectionFrame>{frame});
  // The base scene's two targets never meet, so its hijack rate is of no
  // encounter (null); the rate is checked on filter metrics with two
  // encounters, one hijacked.
  metrics::FilterMetrics filters;
  filters.encounters.resize(2);
  filters.hijacked_encounters = 1;
  filters.hijack_rate = 0.5;
  with_detection.filters = filters;
  const fs::path rendered = dir / "rendered";
  fs::create_directories(rendered);
  std::ofstream(rendered / "metrics.json") << metrics::RunMetricsToJson(with_detection);
  fs::copy_file(run / "manifest.json", rendered / "manifest.json");
  const std::map<std::string, double> d = ReadRunMetrics(rendered.string());
  for (const CatalogueMetric& c : MetricCatalogue()) {
    const std::string name(c.name);
    ASSERT_TRUE(m.count(name)) << name;
    if (name.rfind("det_", 0) == 0) {
      EXPECT_TRUE(std::isnan(m.at(name))) << name << ": a detection-level run has no detection";
      // Ratios are 1; the size is the target's sqrt(10 x 10) = 10 px.
      EXPECT_EQ(d.at(name), name == "det_size_px" ? 10.0 : 1.0)
          << name << " (" << c.file << c.pointer << ")";
    } else if (name == "hijack_rate") {
      EXPECT_TRUE(std::isnan(m.at(name))) << name << ": the base scene has no encounter";
      EXPECT_EQ(d.at(name), 0.5) << name << " (" << c.file << c.pointer << ")";
    } else if (name.rfind("reacqui", 0) == 0) {
      EXPECT_TRUE(std::isnan(m.at(name))) << name << ": the run does not re-acquire";
    } else {
      EXPECT_TRUE(std::isfinite(m.at(name))) << name << " (" << c.file << c.pointer << ")";
    }
    EXPECT_EQ(FindMetric(name), &c);
  }
  EXPECT_EQ(FindMetric("no_such_metric"), nullptr);
}

// A run folder is reused or merged only whole: its manifest lists every file
// the run wrote, by size, and a file deleted, cut short, emptied or grown
// makes it damaged (determinism audit D2: a folder without tracks.txt, or
// with gt/gt.txt emptied, was reused as ok and then failed `hcpf export`).
TEST(RunFolderIntact, AFileDeletedCutEmptiedOrGrownIsDamage) {
  const auto dir = SweepFolder("intact");
  const fs::path run = RunBase(dir);
  nlohmann::json manifest;
  std::ifstream(run / "manifest.json") >> manifest;
  RunRecord record;
  record.key = manifest["config_hash"];  // a row's key is its run's configuration hash
  record.metrics = ReadRunMetrics(run.string());
  ASSERT_TRUE(RunFolderIntact(run.string(), record));
  // A row whose run folder holds another configuration's run (a fourth
  // bad-input audit: merged as ok and reused).
  RunRecord other = record;
  other.key = "0123456789abcdef";
  EXPECT_FALSE(RunFolderIntact(run.string(), other));

  std::set<std::string> listed;
  for (const auto& [name, bytes] : manifest["files"].items()) listed.insert(name);
  std::set<std::string> written;
  for (const auto& e : fs::recursive_directory_iterator(run)) {
    if (e.is_regular_file() && e.path().filename() != "manifest.json")
      written.insert(e.path().lexically_relative(run).generic_string());
  }
  EXPECT_EQ(listed, written);
  EXPECT_TRUE(listed.count("gt/gt.txt") && listed.count("tracks.txt")) << manifest["files"];

  struct Damage {
    const char* what;
    std::function<void(const fs::path&)> apply;
  };
  const std::vector<Damage> damages = {
      {"tracks.txt deleted", [](const fs::path& d) { fs::remove(d / "tracks.txt"); }},
      {"gt/gt.txt emptied", [](const fs::path& d) { fs::resize_file(d / "gt" / "gt.txt", 0); }},
      {"gt.json cut short",
       [](const fs::path& d) { fs::resize_file(d / "gt.json", fs::file_size(d / "gt.json") / 2); }},
      {"detections.txt grown",
       [](const fs::path& d) { std::ofstream(d / "detections.txt", std::ios::app) << "1\n"; }},
      {"seqinfo.ini a folder",
       [](const fs::path& d) {
         fs::remove(d / "seqinfo.ini");
         fs::create_directory(d / "seqinfo.ini");
       }},
  };
  for (const Damage& damage : damages) {
    const fs::path copy = dir / "damaged";
    fs::remove_all(copy);
    fs::copy(run, copy, fs::copy_options::recursive);
    ASSERT_TRUE(RunFolderIntact(copy.string(), record)) << damage.what;
    damage.apply(copy);
    EXPECT_FALSE(RunFolderIntact(copy.string(), record)) << damage.what;
  }
  // A folder from an hcpf before the list is asked only for the files every
  // run writes.
  manifest.erase("files");
  std::ofstream(run / "manifest.json") << manifest.dump(2);
  EXPECT_TRUE(RunFolderIntact(run.string(), record));
  fs::remove(run / "tracks.txt");
  EXPECT_FALSE(RunFolderIntact(run.string(), record));
}

// A store made before a metric joined the catalogue (its column dropped here)
// gets the column when opened for writing, and reads it as missing when
// opened read-only.
TEST(ResultsStore, StoresOfAnOlderCatalogueAreMigrated) {
  const auto dir = SweepFolder("migrate");
  const StoreMeta meta = UnsweptMeta();
  const std::string path = (dir / "results.sqlite").string();
  {
    auto store = ResultsStore::OpenOrCreate(path, meta);
    RunRecord r;
    r.key = "k";
    r.ok = true;
    r.metrics = {{"idf1", 0.5}};
    store->Put(r);
  }
  const auto drop = [&path] {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(db, "ALTER TABLE runs DROP COLUMN det_f1", nullptr, nullptr, nullptr),
              SQLITE_OK)
        << sqlite3_errmsg(db);
    sqlite3_close(db);
  };
  drop();
  {
    const auto store = ResultsStore::Open(path, StoreAccess::kReadOnly);
    const auto runs = store->Runs();
    ASSERT_EQ(runs.size(), 1u);
    EXPECT_DOUBLE_EQ(runs[0].metrics.at("idf1"), 0.5);
    EXPECT_TRUE(std::isnan(runs[0].metrics.at("det_f1")));
  }
  {
    auto store = ResultsStore::Open(path, StoreAccess::kReadWrite);
    RunRecord r = store->Runs()[0];
    r.metrics["det_f1"] = 0.25;
    store->Put(r);
  }
  EXPECT_DOUBLE_EQ(ResultsStore::Open(path)->Runs()[0].metrics.at("det_f1"), 0.25);
}

// The build column: a row keeps the build it is given ("" too), and a row
// put without one reads back without one. A store made before the column
// (dropped here) reads every row without a build when opened read-only, and
// gains the column when opened for writing.
TEST(ResultsStore, KeepsEachRunsBuildAndMigratesStoresWithoutTheColumn) {
  const auto dir = SweepFolder("migrate-build");
  const StoreMeta meta = UnsweptMeta();
  const std::string path = (dir / "results.sqlite").string();
  {
    auto store = ResultsStore::OpenOrCreate(path, meta);
    RunRecord r;
    r.ok = true;
    for (const auto& [key, build] : std::vector<std::pair<std::string, std::optional<std::string>>>{
             {"a", "1.0 at 0123456789ab"}, {"b", ""}, {"c", std::nullopt}}) {
      r.key = key;
      r.build = build;
      store->Put(r);
      ++r.index;  // each run of a sweep has its own index
    }
  }
  {
    const auto runs = ResultsStore::Open(path)->Runs();
    ASSERT_EQ(runs.size(), 3u);
    EXPECT_EQ(runs[0].build, "1.0 at 0123456789ab");
    EXPECT_EQ(runs[1].build, "");
    EXPECT_FALSE(runs[2].build.has_value());
  }
  ExecSql(path, "ALTER TABLE runs DROP COLUMN build");
  for (const RunRecord& r : ResultsStore::Open(path, StoreAccess::kReadOnly)->Runs()) {
    EXPECT_FALSE(r.build.has_value()) << r.key;
  }
  {
    auto store = ResultsStore::Open(path, StoreAccess::kReadWrite);
    RunRecord r = store->Runs()[0];
    EXPECT_FALSE(r.build.has_value());
    r.build = "1.1 at 89abcdef0123";
    store->Put(r);
  }
  const auto runs = ResultsStore::Open(path)->Runs();
  EXPECT_EQ(runs[0].build, "1.1 at 89abcdef0123");
  EXPECT_FALSE(runs[1].build.has_value());
}

// Rows edited after the sweep wrote them are bad input naming the row and
// column (a third bad-input audit: a metric given as text was read as 0 and
// halved a cell's mean, an unknown status counted as neither ok nor failed,
// a seed that is not a number failed with std::stoull's text).
TEST(ResultsStore, HandEditedRowsAreBadInputNamingTheRowAndColumn) {
  const auto dir = SweepFolder("store-rows");
  const StoreMeta meta = UnsweptMeta();
  const std::string path = (dir / "results.sqlite").string();
  {
    auto store = ResultsStore::OpenOrCreate(path, meta);
    RunRecord r;
    r.key = "k1";
    r.run_dir = "runs/k1";
    r.ok = true;
    r.metrics = {{"idf1", 0.5}};
    store->Put(r);
  }
  const std::string good = (dir / "good.sqlite").string();
  fs::copy_file(path, good);
  for (
      const auto& [sql, expected] : std::vector<std::pair<std::string, std::string>>{
          {"UPDATE runs SET idf1 = 'abc'",
           R"(runs[k1].idf1: expected a results store of hcpf sweep: a finite number or NULL, found the text "abc")"},
          // A fourth audit: an Inf left out of a cell's mean (the sweep
          // stores what is not finite as NULL), a negative run index kept.
          {"UPDATE runs SET idf1 = 9e999",
           R"(runs[k1].idf1: expected a results store of hcpf sweep: a finite number or NULL, found inf)"},
          {"UPDATE runs SET run_index = -3",
           R"(runs[k1].run_index: expected a results store of hcpf sweep: a run index of its own, 0 or more, found -3)"},
          {"UPDATE runs SET status = 'weird'",
           R"(runs[k1].status: expected a results store of hcpf sweep: "ok" or "failed", found "weird")"},
          {"UPDATE runs SET seed = 'x1'",
           R"(runs[k1].seed: expected a results store of hcpf sweep: a seed (a whole number, as decimal text), found "x1")"},
          // A store without its expansion (written before it was recorded)
          // still holds a seed index to what a sweep can have: 2^40 was cut
          // to an int.
          {"UPDATE runs SET seed_index = 1099511627776",
           R"(runs[k1].seed_index: expected a results store of hcpf sweep: a seed index, 0 to 99999, found 1099511627776)"},
          {"UPDATE runs SET seed_index = -1",
           R"(runs[k1].seed_index: expected a results store of hcpf sweep: a seed index, 0 to 99999, found -1)"}}) {
    ExpectRefusedAfterEdit(good, path, sql, expected, true);
  }
  // A number written as an integer is a number; the store as written reads.
  fs::copy_file(good, path, fs::copy_options::overwrite_existing);
  ExecSql(path, "UPDATE runs SET idf1 = 1");
  EXPECT_EQ(ResultsStore::Open(path)->Runs()[0].metrics.at("idf1"), 1.0);
  // Two rows of one run index.
  {
    auto store = ResultsStore::Open(path, StoreAccess::kReadWrite);
    RunRecord r;
    r.key = "k2";
    r.index = 1;
    r.run_dir = "runs/k2";
    r.ok = true;
    r.metrics = {{"idf1", 0.25}};
    store->Put(r);
  }
  EXPECT_EQ(ResultsStore::Open(path)->Runs().size(), 2U);
  ExecSql(path, "UPDATE runs SET run_index = 0");
  try {
    ResultsStore::Open(path)->Runs();
    ADD_FAILURE() << "two rows of run index 0 were accepted";
  } catch (const InputError& e) {
    EXPECT_NE(
        std::string(e.what()).find(
            R"(runs[k2].run_index: expected a results store of hcpf sweep: a run index of its own, 0 or more, found 0, the index of run k1 too)"),
        std::string::npos)
        << e.what();
  }
}

TEST(RunSweep, ParallelEqualsSerialAndResumeReusesEverything) {
  const auto dir = SweepFolder("parallel");
  const SweepSpec spec = LoadSweepFile(WriteSweep(dir, kSweep));
  const auto runs = ExpandSweep(spec);
  const SweepResult serial = RunSweep(spec, runs, Options(dir / "serial", 1));
  EXPECT_EQ(serial.total, 8);
  EXPECT_EQ(serial.computed, 8);
  EXPECT_EQ(serial.failed, 0);
  const SweepResult parallel = RunSweep(spec, runs, Options(dir / "parallel", 3));
  EXPECT_EQ(parallel.computed, 8);
  EXPECT_EQ(StoreRows(dir / "serial"), StoreRows(dir / "parallel"));
  // Every run has its folder with the run's outputs, named by its key.
  for (const SweepRun& r : runs)
    EXPECT_TRUE(fs::exists(dir / "serial" / "runs" / r.key / "metrics.json"));
  // Metrics in the store are those of the run's metrics.json, read here
  // without the catalogue (the store is filled through it).
  const auto stored = ResultsStore::Open((dir / "serial" / "results.sqlite").string())->Runs();
  std::ifstream metrics_file(dir / "serial" / "runs" / stored[3].key / "metrics.json");
  const auto metrics = nlohmann::json::parse(metrics_file);
  EXPECT_EQ(stored[3].metrics.at("idf1"), metrics.at("mot").at("IDF1").get<double>());
  EXPECT_EQ(stored[3].metrics.at("da_accuracy"),
            metrics.at("filters").at("da_accuracy").get<double>());
  {
    // Another sweep writing to the folder (holding its lock) is refused.
    const int fd = ::open((dir / "serial" / "sweep.lock").c_str(), O_RDWR);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
    EXPECT_THROW(RunSweep(spec, runs, Options(dir / "serial", 2)), InputError);
    ::close(fd);
  }
  const SweepResult again = RunSweep(spec, runs, Options(dir / "serial", 2));
  EXPECT_EQ(again.reused, 8);
  EXPECT_EQ(again.computed, 0);
  EXPECT_EQ(StoreRows(dir / "serial"), StoreRows(dir / "parallel"));
}

TEST(RunSweep, AFailingRunIsRecordedAndTheOthersFinish) {
  const auto dir = SweepFolder("failing");
  const SweepSpec spec = LoadSweepFile(WriteSweep(dir, kSweep));
  const auto runs = ExpandSweep(spec);
  // Run 5's folder already holds a file that is not a run's: RunScenario
  // refuses to overwrite it (a real failure mode, nothing faked).
  fs::create_directories(dir / "out" / "runs" / runs[5].key);
  std::ofstream(dir / "out" / "runs" / runs[5].key / "notes.txt") << "mine\n";
  const SweepResult r = RunSweep(spec, runs, Options(dir / "out", 2));
  EXPECT_EQ(r.failed, 1);
  EXPECT_EQ(r.computed, 7);
  const auto stored = ResultsStore::Open((dir / "out" / "results.sqlite").string())->Runs();
  ASSERT_EQ(stored.size(), 8U);
  for (const RunRecord& s : stored) {
    EXPECT_EQ(s.ok, s.index != 5) << s.index;
  }
  EXPECT_NE(stored[5].error.find("a folder with other files in it"), std::string::npos)
      << stored[5].error;
  EXPECT_TRUE(std::isnan(stored[5].metrics.at("idf1")));
  // Resuming retries only the failed run; once the cause is gone it succeeds.
  fs::remove_all(dir / "out" / "runs" / runs[5].key);
  const SweepResult resumed = RunSweep(spec, runs, Options(dir / "out", 2));
  EXPECT_EQ(resumed.reused, 7);
  EXPECT_EQ(resumed.computed, 1);
  EXPECT_EQ(resumed.failed, 0);
}

// A row edited by hand no longer says what the sweep says of its run: a
// bad-input audit changed run 3's swept particle count to 999, and the report
// drew a cell of 999 particles that resume kept. The key names the run, so
// resume rewrites the row's labels from the sweep and keeps the run (its
// folder is whole); a row whose key no run has is refused.
TEST(RunSweep, AStoreRowEditedByHandIsRelabelledOrRefused) {
  const auto dir = SweepFolder("edited-row");
  const SweepSpec spec = LoadSweepFile(WriteSweep(dir, kSweep));
  const auto runs = ExpandSweep(spec);
  ASSERT_EQ(RunSweep(spec, runs, Options(dir / "out", 2)).computed, 8);
  const std::string path = (dir / "out" / "results.sqlite").string();
  const std::vector<std::string> before = StoreRows(dir / "out");
  const auto resume = [&] {
    const SweepResult r = RunSweep(spec, runs, Options(dir / "out", 2));
    EXPECT_EQ(r.reused, 8);
    EXPECT_EQ(r.computed, 0);
    EXPECT_EQ(StoreRows(dir / "out"), before);
  };
  ExecSql(path, "UPDATE runs SET \"tracker.particles\" = '999' WHERE run_index = 3");
  ASSERT_EQ(ResultsStore::Open(path)->RunsAsStored()[3].values[0], "999");
  resume();
  EXPECT_EQ(ResultsStore::Open(path)->Runs()[3].values[0], runs[3].values[0]);
  // A seed and a seed index: the same. (A folder other than runs/<key> the
  // store's reader refuses itself.)
  ExecSql(path, "UPDATE runs SET seed = '12345' WHERE run_index = 6");
  resume();
  ExecSql(path, "UPDATE runs SET seed_index = 1 WHERE run_index = 0");
  resume();
  // A row of a key no run has: refused before the store is written to,
  // here by the same sweep under another file name (which a resume records
  // in the store's meta, and which switched it to write-ahead logging).
  ExecSql(path,
          "UPDATE runs SET key = '0123456789abcdef', run_dir = 'runs/0123456789abcdef' "
          "WHERE run_index = 5");
  const std::string edited = hcpf::testing::ReadFile(path);
  const SweepSpec renamed = LoadSweepFile(WriteSweep(dir, kSweep, "renamed.yaml"));
  try {
    RunSweep(renamed, ExpandSweep(renamed), Options(dir / "out", 2));
    ADD_FAILURE() << "a row of no run of the sweep was kept";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("runs[0123456789abcdef]: expected a row of a run of this "
                                         "sweep"),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("found run 5, whose key no run of the sweep has"),
              std::string::npos)
        << e.what();
  }
  // Compared whole, not printed: a store's bytes fill a screen.
  EXPECT_TRUE(hcpf::testing::ReadFile(path) == edited) << "the refused store was written to";
  EXPECT_EQ(fs::path(ResultsStore::Open(path)->meta().sweep_file).filename(), "sweep.yaml");
}

// A row's seed index, seed and swept values follow from its run index and
// the sweep's expansion, which the store records: a reader refuses a row
// that says otherwise, naming it (a bad-input audit: a swept value changed
// to text drew a fifth cell of one run in the report, and a seed index past
// the sweep's seeds was reported as a seed). The meta is held to the
// expansion too, and a store without run_count is refused.
TEST(ResultsStore, RowsAreHeldToTheSweepsExpansion) {
  const auto dir = SweepFolder("expansion");
  const SweepSpec spec = LoadSweepFile(WriteSweep(dir, kSweep));
  const auto runs = ExpandSweep(spec);
  ASSERT_EQ(RunSweep(spec, runs, Options(dir / "out", 2)).computed, 8);
  const std::string path = (dir / "out" / "results.sqlite").string();
  const std::string good = (dir / "good.sqlite").string();
  fs::copy_file(path, good);
  ASSERT_TRUE(ResultsStore::Open(path)->meta().expansion.has_value());
  EXPECT_EQ(ResultsStore::Open(path)->Runs().size(), 8U);
  const auto refused = [&](const std::string& sql, const std::string& expected) {
    ExpectRefusedAfterEdit(good, path, sql, expected, true);
  };
  // Run 3 is particles 20, charged, seed index 1 (index = cell * 2 + seed).
  refused("UPDATE runs SET \"tracker.particles\" = 'abc' WHERE run_index = 3",
          fmt::format("runs[{}].tracker.particles: expected \"20\" (what the sweep's expansion "
                      "says of run 3), found \"abc\"",
                      runs[3].key));
  refused("UPDATE runs SET \"tracker.resampling.method\" = 'systematic' WHERE run_index = 3",
          fmt::format("runs[{}].tracker.resampling.method: expected \"charged\"", runs[3].key));
  refused("UPDATE runs SET seed_index = 7 WHERE run_index = 3",
          fmt::format("runs[{}].seed_index: expected 1 (what the sweep's expansion says of run 3), "
                      "found 7",
                      runs[3].key));
  refused("UPDATE runs SET seed = '12345' WHERE run_index = 6",
          fmt::format("runs[{}].seed: expected {} (what the sweep's expansion says of run 6), "
                      "found 12345",
                      runs[6].key, runs[6].seed));
  // The sweep itself reads the rows as stored (it rewrites them).
  EXPECT_EQ(ResultsStore::Open(path)->RunsAsStored()[6].seed, 12345U);
  const auto meta_refused = [&](const std::string& sql, const std::string& expected) {
    ExpectRefusedAfterEdit(good, path, sql, expected, false);
  };
  meta_refused("DELETE FROM meta WHERE name = 'run_count'",
               "meta.run_count: expected a results store of hcpf sweep: the sweep's number of "
               "runs, found no run_count");
  meta_refused("UPDATE meta SET value = '9' WHERE name = 'run_count'",
               "meta.expansion: expected a results store of hcpf sweep: an expansion of run_count "
               "(9) runs, found 8");
  meta_refused("UPDATE meta SET value = '{\"grid\": 3}' WHERE name = 'expansion'",
               "meta.expansion: expected a results store of hcpf sweep: the sweep's expansion as "
               "JSON");
  meta_refused(
      "UPDATE meta SET value = replace(value, '\"tracker.particles\"', '\"camera.fov_deg\"') "
      "WHERE name = 'expansion'",
      "meta.expansion: expected a results store of hcpf sweep: the swept keys "
      "[tracker.particles, tracker.resampling.method], found [camera.fov_deg, "
      "tracker.resampling.method]");
  meta_refused(
      "UPDATE meta SET value = replace(value, '\"seeds\":2', '\"seeds\":-2') "
      "WHERE name = 'expansion'",
      "meta.expansion: expected a results store of hcpf sweep: seeds from 0 to 100000, "
      "found -2");
  // 2^32 + 2 and 2.5 were read by the JSON library as 2.
  meta_refused(
      "UPDATE meta SET value = replace(value, '\"seeds\":2', '\"seeds\":4294967298') "
      "WHERE name = 'expansion'",
      "seeds from 0 to 100000, found 4294967298");
  meta_refused(
      "UPDATE meta SET value = replace(value, '\"seeds\":2', '\"seeds\":2.5') "
      "WHERE name = 'expansion'",
      "seeds from 0 to 100000, found 2.5");
  // Its root seed is held to what the sweep writes (a second audit: "abc"
  // and a deleted root were read, and switched the rows' seed check off).
  meta_refused("UPDATE meta SET value = 'abc' WHERE name = 'root_seed'",
               "meta.root_seed: expected a results store of hcpf sweep: the root of the runs' "
               "seeds (a whole number below 2^64), found \"abc\"");
  meta_refused("UPDATE meta SET value = '18446744073709551616' WHERE name = 'root_seed'",
               "meta.root_seed: expected");
  meta_refused("DELETE FROM meta WHERE name = 'root_seed'", "meta.root_seed: expected");
  // A valid root seed, but not the sweep's: every row's seed then differs,
  // and the root is blamed, not the first row (an audit: the message said
  // the runs table was changed). One row edited the same way is the row's.
  {
    const std::string root = ResultsStore::Open(good)->meta().root_seed;
    const uint64_t other = std::stoull(root) + 1;
    ExpectRefusedAfterEdit(
        good, path, fmt::format("UPDATE meta SET value = '{}' WHERE name = 'root_seed'", other),
        fmt::format("meta.root_seed: expected the root seed the runs' seeds follow from (none "
                    "of the 8 rows' seeds follows from this one: run 0 at seed index 0 has seed "
                    "{}, where it would give {}), found {}",
                    runs[0].seed, SweepSeed(other, 0), other),
        true);
    ExpectRefusedAfterEdit(
        good, path,
        fmt::format("UPDATE runs SET seed = '{}' WHERE run_index = 0", SweepSeed(other, 0)),
        fmt::format("runs[{}].seed: expected {}", runs[0].key, runs[0].seed), true);
  }
  // A sweep's limit holds for an expansion that fits its run_count: 100 ×
  // 2 values × 100000 seeds (2·10^7 runs) was reported as "8 of 20000000".
  {
    std::vector<std::string> many;
    for (int i = 0; i < 100; ++i) many.push_back(std::to_string(i + 1));
    nlohmann::json e = nlohmann::json::parse(R"({"zip": [], "seeds": 100000})");
    e["grid"] = {{{"key", "tracker.particles"}, {"values", many}},
                 {{"key", "tracker.resampling.method"}, {"values", {"systematic", "charged"}}}};
    meta_refused("UPDATE meta SET value = '" + e.dump() +
                     "' WHERE name = 'expansion'; UPDATE meta SET value = '20000000' WHERE name "
                     "= 'run_count'",
                 "meta.expansion: expected a results store of hcpf sweep: an expansion of at most "
                 "10000000 runs (a sweep's limit), found 20000000 runs");
  }
  // Whole numbers where the sweep writes them (3.5 was read as 3, 'x' as 0,
  // a seed with a leading zero as the seed).
  refused("UPDATE runs SET run_index = 3.5 WHERE run_index = 3",
          fmt::format("runs[{}].run_index: expected a results store of hcpf sweep: a run index (a "
                      "whole number), found \"3.5\"",
                      runs[3].key));
  refused("UPDATE runs SET seed_index = 'x' WHERE run_index = 2",
          fmt::format("runs[{}].seed_index: expected a results store of hcpf sweep: a seed index "
                      "(a whole number), found \"x\"",
                      runs[2].key));
  refused(fmt::format("UPDATE runs SET seed = '0{}' WHERE run_index = 2", runs[2].seed),
          fmt::format("runs[{}].seed: expected a results store of hcpf sweep: a seed (a whole "
                      "number, as decimal text), found \"0{}\"",
                      runs[2].key, runs[2].seed));
  // A resume repairs a meta edited to fit itself (run_count 12 and a third
  // particle count): it rewrites run_count with the expansion (a second
  // audit: it wrote the expansion alone, and no command opened the store).
  fs::copy_file(good, path, fs::copy_options::overwrite_existing);
  ExecSql(path,
          "UPDATE meta SET value = '12' WHERE name = 'run_count'; UPDATE meta SET value = "
          "replace(value, '[\"20\",\"60\"]', '[\"20\",\"60\",\"90\"]') WHERE name = "
          "'expansion'");
  EXPECT_EQ(ResultsStore::Open(path)->meta().run_count, 12);
  EXPECT_EQ(RunSweep(spec, runs, Options(dir / "out", 2)).reused, 8);
  EXPECT_EQ(ResultsStore::Open(path)->meta().run_count, 8);
  EXPECT_EQ(ResultsStore::Open(path)->Runs().size(), 8U);
  // A store written before the expansion was recorded is read as it was.
  fs::copy_file(good, path, fs::copy_options::overwrite_existing);
  ExecSql(path, "DELETE FROM meta WHERE name = 'expansion'");
  ExecSql(path, "UPDATE runs SET \"tracker.particles\" = 'abc' WHERE run_index = 3");
  EXPECT_FALSE(ResultsStore::Open(path)->meta().expansion.has_value());
  EXPECT_EQ(ResultsStore::Open(path)->Runs()[3].values[0], "abc");
  // ... and report and export warn that its labels are unchecked.
  EXPECT_NE(UncheckedLabelsSentence(*ResultsStore::Open(path)).find("records no expansion"),
            std::string::npos);
  EXPECT_EQ(UncheckedLabelsSentence(*ResultsStore::Open(good)), "");
}

// Shards of one sweep run from files that write a value otherwise (40 and
// 40.0 are one run, so one sweep) merge into rows labelled as the merged
// store's expansion says, which a reader then accepts.
TEST(MergeStores, RowsAreLabelledAsTheMergedStoresExpansion) {
  const auto dir = SweepFolder("merge-spelling");
  std::vector<std::string> shards;
  for (int i = 0; i < 2; ++i) {
    const SweepSpec spec =
        LoadSweepFile(WriteSweep(dir,
                                 i == 0 ? "base: base.yaml\ngrid: {camera.fov_deg: [40, 45]}\n"
                                        : "base: base.yaml\ngrid: {camera.fov_deg: [40.0, 45.0]}\n",
                                 fmt::format("s{}.yaml", i)));
    SweepOptions o = Options(dir / fmt::format("shard{}", i), 1);
    o.shard_index = i;
    o.shard_count = 2;
    RunSweep(spec, ExpandSweep(spec), o);
    shards.push_back((dir / fmt::format("shard{}", i)).string());
  }
  EXPECT_EQ(MergeStores((dir / "merged").string(), shards).added, 2);
  const auto merged = ResultsStore::Open((dir / "merged" / "results.sqlite").string())->Runs();
  ASSERT_EQ(merged.size(), 2U);
  EXPECT_EQ(merged[0].values, std::vector<std::string>{"40"});
  EXPECT_EQ(merged[1].values, std::vector<std::string>{"45"});
  // A first shard of an older hcpf (no expansion) takes the expansion of the
  // next (a second bad-input audit: the merged store had none, and kept
  // both spellings).
  ExecSql(shards[0] + "/results.sqlite", "DELETE FROM meta WHERE name = 'expansion'");
  EXPECT_EQ(MergeStores((dir / "merged-older").string(), shards).added, 2);
  const auto older = ResultsStore::Open((dir / "merged-older" / "results.sqlite").string());
  EXPECT_TRUE(older->meta().expansion.has_value());
  const auto relabelled = older->Runs();
  ASSERT_EQ(relabelled.size(), 2U);
  EXPECT_EQ(relabelled[0].values, std::vector<std::string>{"40.0"});
  EXPECT_EQ(relabelled[1].values, std::vector<std::string>{"45.0"});
}

// A sweep of explicit seeds (grid: {seed: [...]}, no seeds:) is allowed by
// the sweep file; its store failed on "duplicate column name: seed" (a
// bad-input audit). The swept values go to their own column, and each run's
// seed column holds its seed.
TEST(RunSweep, ASweptSeedIsStoredBesideTheRunSeed) {
  const auto dir = SweepFolder("swept-seed");
  const SweepSpec spec = LoadSweepFile(WriteSweep(dir,
                                                  "base: base.yaml\n"
                                                  "grid:\n"
                                                  "  seed: [11, 12]\n"
                                                  "  tracker.particles: [20]\n"));
  const auto runs = ExpandSweep(spec);
  const SweepResult r = RunSweep(spec, runs, Options(dir / "out", 2));
  EXPECT_EQ(r.computed, 2);
  EXPECT_EQ(r.failed, 0);
  const std::string path = (dir / "out" / "results.sqlite").string();
  const auto stored = ResultsStore::Open(path)->Runs();
  ASSERT_EQ(stored.size(), 2U);
  for (size_t i = 0; i < 2; ++i) {
    ASSERT_EQ(stored[i].values.size(), 2U);
    EXPECT_EQ(stored[i].values[0], i == 0 ? "11" : "12");
    EXPECT_EQ(stored[i].seed, i == 0 ? 11U : 12U);
    EXPECT_TRUE(stored[i].ok) << stored[i].error;
  }
  // Without `seeds:` a run's seed is its swept seed (a second bad-input
  // audit: an edited seed was reported; a swept seed's error named the
  // run's seed column).
  const std::string good = (dir / "good.sqlite").string();
  fs::copy_file(path, good);
  // Run `index` of the store at `path` (a copy of `good`) given seed
  // `found`: refused, naming the row (`key`) and the seed it must have.
  const auto seed_refused = [](const std::string& good, const std::string& path, int index,
                               const std::string& key, uint64_t want, uint64_t found) {
    ExpectRefusedAfterEdit(
        good, path, fmt::format("UPDATE runs SET seed = '{}' WHERE run_index = {}", found, index),
        fmt::format("runs[{}].seed: expected {} (what the sweep's expansion says of run {}), "
                    "found {}",
                    key, want, index, found),
        true);
  };
  seed_refused(good, path, 0, stored[0].key, 11, 8);
  ExpectRefusedAfterEdit(good, path, "UPDATE runs SET \"swept.seed\" = '13' WHERE run_index = 0",
                         fmt::format("runs[{}].swept.seed: expected \"11\"", stored[0].key), true);
  // ... or, not swept, its base scenario's (kMinimal's seed: 7).
  const SweepSpec plain = LoadSweepFile(
      WriteSweep(dir, "base: base.yaml\ngrid: {tracker.particles: [20]}\n", "p.yaml"));
  RunSweep(plain, ExpandSweep(plain), Options(dir / "plain", 1));
  const std::string plain_path = (dir / "plain" / "results.sqlite").string();
  EXPECT_EQ(ResultsStore::Open(plain_path)->Runs().at(0).seed, 7U);
  const std::string plain_good = (dir / "plain-good.sqlite").string();
  fs::copy_file(plain_path, plain_good);
  seed_refused(plain_good, plain_path, 0, ResultsStore::Open(plain_path)->Runs().at(0).key, 7, 8);
  // ... and under grid.base, the seed of the row's own base scenario (the
  // forty-eighth sitting left a row's seed unchecked there): a second base
  // of seed 9, whose rows are refused with base.yaml's seed 7 and base.yaml's
  // rows with 9.
  std::string second = hcpf::testing::ReadFile(dir / "base.yaml");
  second.replace(second.find("seed: 7\n"), 8, "seed: 9\n");
  std::ofstream(dir / "second.yaml") << second;
  const SweepSpec bases = LoadSweepFile(WriteSweep(
      dir, "grid:\n  base: [base.yaml, second.yaml]\n  tracker.particles: [20]\n", "b.yaml"));
  RunSweep(bases, ExpandSweep(bases), Options(dir / "bases", 1));
  const std::string bases_path = (dir / "bases" / "results.sqlite").string();
  const auto base_rows = ResultsStore::Open(bases_path)->Runs();
  ASSERT_EQ(base_rows.size(), 2U);
  EXPECT_EQ(base_rows[0].seed, 7U);
  EXPECT_EQ(base_rows[1].seed, 9U);
  const std::string bases_good = (dir / "bases-good.sqlite").string();
  fs::copy_file(bases_path, bases_good);
  seed_refused(bases_good, bases_path, 0, base_rows[0].key, 7, 9);
  seed_refused(bases_good, bases_path, 1, base_rows[1].key, 9, 7);
}

// Resuming with an edited report: block (the same runs) takes the new
// settings: a second bad-input audit found the first sweep's kept without a
// word, so `hcpf report` drew what the file no longer said.
TEST(RunSweep, ResumingWithAnEditedReportBlockTakesTheNewSettings) {
  const auto dir = SweepFolder("report-edit");
  const SweepSpec first = LoadSweepFile(WriteSweep(dir, kSweep, "first.yaml"));
  RunSweep(first, ExpandSweep(first), Options(dir / "out", 2));
  std::string edited = kSweep;
  edited.replace(edited.find("report:"), std::string::npos,
                 "report: {x: tracker.particles, y: [hota]}\n");
  const SweepSpec second = LoadSweepFile(WriteSweep(dir, edited, "second.yaml"));
  const SweepResult r = RunSweep(second, ExpandSweep(second), Options(dir / "out", 2));
  EXPECT_EQ(r.computed, 0);
  EXPECT_EQ(r.reused, 8);
  const StoreMeta meta = ResultsStore::Open((dir / "out" / "results.sqlite").string())->meta();
  EXPECT_EQ(meta.report.y, std::vector<std::string>{"hota"});
  EXPECT_EQ(meta.report.series, "");
  EXPECT_EQ(fs::path(meta.sweep_file).filename(), "second.yaml");
}

// The sweep's file is recorded by where it is, not as it was typed: a
// relative path started from the file's folder records the absolute path
// (outside the project), so a resume started elsewhere keeps the same name
// and a merge of shards started in different folders does not depend on
// their order (a determinism audit). Inside the project: relative to it.
TEST(RunSweep, RecordsTheSweepFileByWhereItIs) {
  const auto dir = SweepFolder("sweep-file-name");
  const fs::path file = WriteSweep(dir, kSweep, "named.yaml");
  const fs::path kept = fs::current_path();
  fs::current_path(dir);
  const SweepSpec spec = LoadSweepFile("named.yaml");
  RunSweep(spec, ExpandSweep(spec), Options(dir / "out", 2));
  fs::current_path(kept);
  EXPECT_EQ(ResultsStore::Open((dir / "out" / "results.sqlite").string())->meta().sweep_file,
            fs::weakly_canonical(file).string());
  EXPECT_EQ(scenarios::ProjectRelativePath(std::string(HCPF_SOURCE_DIR) +
                                           "/scenarios/sweeps/../sweeps/default.yaml"),
            "scenarios/sweeps/default.yaml");
}

// --out takes a new, empty or earlier sweep folder; a run folder or a
// folder of someone else's files is refused before anything is written (a
// bad-input audit found a sweep writing its store and runs/ into both).
TEST(RunSweep, OutMustBeASweepFolder) {
  const auto dir = SweepFolder("sweep-out");
  const SweepSpec spec = LoadSweepFile(
      WriteSweep(dir, "base: base.yaml\ngrid: {tracker.particles: [20]}\n", "one.yaml"));
  const auto runs = ExpandSweep(spec);
  fs::create_directories(dir / "notes");
  std::ofstream(dir / "notes" / "todo.txt") << "mine\n";
  fs::create_directories(dir / "run");
  std::ofstream(dir / "run" / "manifest.json") << R"({"format": "hcpf-run/1"})";
  const auto refused = [&](const fs::path& out, const std::string& found) {
    try {
      RunSweep(spec, runs, Options(out, 1));
      ADD_FAILURE() << out << " was accepted";
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("--out"), std::string::npos) << m;
      EXPECT_NE(m.find(found), std::string::npos) << m;
    }
    EXPECT_FALSE(fs::exists(out / "runs")) << out;
    EXPECT_FALSE(fs::exists(out / "results.sqlite")) << out;
  };
  refused(dir / "notes", "a folder with other files in it (\"todo.txt\")");
  refused(dir / "run", "an output folder of hcpf run");
  // A folder a sweep left before its store (runs/, sweep.lock) is taken.
  fs::create_directories(dir / "stopped" / "runs");
  std::ofstream(dir / "stopped" / "sweep.lock");
  EXPECT_EQ(RunSweep(spec, runs, Options(dir / "stopped", 1)).computed, 1);
  // And merge's OUT follows the same rule.
  EXPECT_THROW(MergeStores((dir / "notes").string(), {(dir / "stopped").string()}), InputError);
  EXPECT_FALSE(fs::exists(dir / "notes" / "results.sqlite"));
}

// Merge copies a run folder beside its name and renames it, and carries the
// shards' contact sheet (determinism audit D3, D5). A copy that fails part-way
// (a FIFO stands in for a kill or a full disk) leaves no folder under the
// run's name: it used to stay there, half copied, looking finished. Staging
// folders of merges no longer running are removed.
TEST(MergeStores, CopiesRunFoldersWholeOrNotAtAllAndCarriesTheContactSheet) {
  const auto dir = SweepFolder("merge-whole");
  const SweepSpec spec = LoadSweepFile(WriteSweep(dir, kSweep));
  const auto runs = ExpandSweep(spec);
  SweepOptions o = Options(dir / "shard0", 2);
  o.shard_count = 2;
  RunSweep(spec, runs, o);
  o = Options(dir / "shard1", 2);
  o.shard_index = 1;
  o.shard_count = 2;
  RunSweep(spec, runs, o);
  // Shard 1 holds runs 1, 3, 5, 7; shard 0 left no contact sheet.
  std::ofstream(dir / "shard1" / "contact_sheet.png") << "the sheet's bytes";
  const fs::path fifo = dir / "shard1" / "runs" / runs[3].key / "fifo";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  fs::create_directories(dir / "merged" / "runs" / (runs[1].key + ".partial-999999999"));
  try {
    MergeStores((dir / "merged").string(), {(dir / "shard0").string(), (dir / "shard1").string()});
    ADD_FAILURE() << "a FIFO was copied";
  } catch (const RunError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot copy"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "merged" / "runs" / runs[3].key));
  for (const auto& e : fs::directory_iterator(dir / "merged" / "runs")) {
    EXPECT_EQ(e.path().filename().string().find(".partial-"), std::string::npos) << e.path();
  }
  fs::remove(fifo);
  const MergeResult m = MergeStores((dir / "merged").string(),
                                    {(dir / "shard0").string(), (dir / "shard1").string()});
  EXPECT_TRUE(m.contact_sheet);
  EXPECT_EQ(StoreRows(dir / "merged").size(), 8u);
  EXPECT_TRUE(fs::exists(dir / "merged" / "runs" / runs[3].key / "tracks.txt"));
  std::ifstream sheet(dir / "merged" / "contact_sheet.png");
  EXPECT_EQ(std::string(std::istreambuf_iterator<char>(sheet), {}), "the sheet's bytes");
  EXPECT_FALSE(MergeStores((dir / "merged").string(), {(dir / "shard1").string()}).contact_sheet)
      << "OUT already has the sheet";
}

// --video on a finished sweep computed without it: the video is not part of
// a run's key, so the runs were all reused and no video written, silently
// (determinism audit D6). The runs it asks a video of (each cell's first
// seed) are computed again, with the same results; then all are reused.
TEST(RunSweep, VideoAskedOnResumeComputesTheRunsWithoutOne) {
  const auto dir = SweepFolder("video-resume");
  const SweepSpec spec = LoadSweepFile(WriteSweep(dir, kSweep));
  const auto runs = ExpandSweep(spec);
  RunSweep(spec, runs, Options(dir / "out", 2));
  const std::vector<std::string> rows = StoreRows(dir / "out");
  SweepOptions o = Options(dir / "out", 2);
  o.video = true;
  const SweepResult with_video = RunSweep(spec, runs, o);
  EXPECT_EQ(with_video.computed, 4);
  EXPECT_EQ(with_video.reused, 4);
  for (const SweepRun& r : runs) {
    EXPECT_EQ(fs::exists(dir / "out" / "runs" / r.key / "overlay.mp4"), r.seed_index == 0)
        << r.index;
  }
  EXPECT_EQ(StoreRows(dir / "out"), rows);
  const SweepResult again = RunSweep(spec, runs, o);
  EXPECT_EQ(again.reused, 8);
  EXPECT_EQ(again.computed, 0);
  // The report links each cell's video and says how to see it beside its
  // run's timeline (an audit: the links led to bare mp4s alone).
  const std::string html = [&] {
    std::ifstream in(WriteReport({.dir = (dir / "out").string()}).html_path);
    return std::string(std::istreambuf_iterator<char>(in), {});
  }();
  EXPECT_NE(html.find("<h2>Overlay videos (first seed)</h2>"), std::string::npos);
  EXPECT_NE(html.find("Its run's own report plays it beside the timeline"), std::string::npos);
  EXPECT_NE(html.find("<code>hcpf report " + (dir / "out" / "runs").string() + "/"),
            std::string::npos)
      << html.substr(html.find("Overlay videos"), 2000);
}

TEST(RunSweep, ShardsMergedEqualTheUnshardedSweep) {
  const auto dir = SweepFolder("shards");
  const SweepSpec spec = LoadSweepFile(WriteSweep(dir, kSweep));
  const auto runs = ExpandSweep(spec);
  RunSweep(spec, runs, Options(dir / "all", 2));
  std::vector<std::string> shard_dirs;
  int64_t total = 0;
  for (int i = 0; i < 3; ++i) {
    SweepOptions o = Options(dir / ("shard" + std::to_string(i)), 1);
    o.shard_index = i;
    o.shard_count = 3;
    const SweepResult r = RunSweep(spec, runs, o);
    // 8 runs, index % 3: shard 0 has 0,3,6; shard 1 has 1,4,7; shard 2 has 2,5.
    EXPECT_EQ(r.total, i == 2 ? 2 : 3);
    for (const RunRecord& s :
         ResultsStore::Open((dir / ("shard" + std::to_string(i)) / "results.sqlite").string())
             ->Runs()) {
      EXPECT_EQ(s.index % 3, i);
    }
    total += r.total;
    shard_dirs.push_back((dir / ("shard" + std::to_string(i))).string());
  }
  EXPECT_EQ(total, 8);
  const MergeResult m = MergeStores((dir / "merged").string(), shard_dirs);
  EXPECT_EQ(m.added, 8);
  EXPECT_EQ(m.duplicates, 0);
  EXPECT_EQ(StoreRows(dir / "merged"), StoreRows(dir / "all"));
  EXPECT_TRUE(fs::exists(dir / "merged" / "runs" / runs[4].key / "tracks.txt"));
  // Merging again does not double count.
  const MergeResult again = MergeStores((dir / "merged").string(), shard_dirs);
  EXPECT_EQ(again.added, 0);
  EXPECT_EQ(again.duplicates, 8);
  EXPECT_EQ(StoreRows(dir / "merged"), StoreRows(dir / "all"));
  // A third bad-input audit: merge took a shard still being swept as
  // complete, and wrote into a folder a sweep was writing to. A held
  // sweep.lock (the sweep's flock, held here by the test) is refused either
  // way, before OUT is written.
  const auto refused_while_locked = [&](const fs::path& lock, const fs::path& out,
                                        const std::string& expected) {
    const int fd = ::open(lock.c_str(), O_RDWR | O_CLOEXEC);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
    try {
      MergeStores(out.string(), shard_dirs);
      ADD_FAILURE() << "merged while " << lock << " was held";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
    ::close(fd);
  };
  refused_while_locked(dir / "shard1" / "sweep.lock", dir / "merged3",
                       "shard1: DIR: expected a shard folder no sweep is writing to");
  EXPECT_FALSE(fs::exists(dir / "merged3"));
  refused_while_locked(dir / "merged" / "sweep.lock", dir / "merged",
                       "merged: OUT: expected a folder no other hcpf sweep or merge is writing to");
  // A store of another sweep is refused.
  const SweepSpec other = LoadSweepFile(
      WriteSweep(dir, "base: base.yaml\ngrid: {tracker.particles: [30]}\n", "other.yaml"));
  RunSweep(other, ExpandSweep(other), Options(dir / "other", 1));
  EXPECT_THROW(MergeStores((dir / "merged2").string(), {shard_dirs[0], (dir / "other").string()}),
               InputError);
  // And so is resuming into a folder of another sweep.
  EXPECT_THROW(RunSweep(other, ExpandSweep(other), Options(dir / "all", 1)), InputError);
  // A shard whose runs table is gone is bad input, found before anything is
  // written: a bad-input audit found a merged store holding the two shards
  // read before it, which a report then took for the whole sweep.
  fs::copy(dir / "shard2", dir / "broken", fs::copy_options::recursive);
  {
    sqlite3* db = nullptr;
    const std::string path = (dir / "broken" / "results.sqlite").string();
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(db, "DROP TABLE runs", nullptr, nullptr, nullptr), SQLITE_OK);
    sqlite3_close(db);
  }
  EXPECT_THROW(MergeStores((dir / "merged3").string(),
                           {shard_dirs[0], shard_dirs[1], (dir / "broken").string()}),
               InputError);
  EXPECT_FALSE(fs::exists(dir / "merged3"));
  // A row whose key leads out of the folder (a store edited by hand: merge
  // copied that run beside OUT, a second bad-input audit) is bad input.
  fs::remove_all(dir / "broken");
  fs::copy(dir / "shard2", dir / "broken", fs::copy_options::recursive);
  {
    sqlite3* db = nullptr;
    const std::string path = (dir / "broken" / "results.sqlite").string();
    ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(db,
                           "UPDATE runs SET key = '../../victim', run_dir = 'runs/../../victim' "
                           "WHERE run_index = 2",
                           nullptr, nullptr, nullptr),
              SQLITE_OK);
    sqlite3_close(db);
  }
  try {
    MergeStores((dir / "merged4").string(), {(dir / "broken").string()});
    ADD_FAILURE() << "a key leading out of the folder was merged";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("key \"../../victim\""), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "victim"));
}

}  // namespace
}  // namespace hcpf::studies
