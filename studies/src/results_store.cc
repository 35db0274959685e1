#include "hcpf/studies/results_store.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>
#include <sqlite3.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>
#include <span>
#include <sstream>

#include "hcpf/core/check.h"
#include "hcpf/core/error.h"
#include "hcpf/core/names.h"
#include "hcpf/core/text_file.h"
#include "hcpf/scenarios/output_folder.h"
#include "hcpf/scenarios/version.h"
#include "hcpf/studies/file_keys.h"
#include "hcpf/studies/metric_catalogue.h"
#include "sweep_plan.h"
#include "text.h"

namespace hcpf::studies {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string Quote(const std::string& identifier) {
  std::string out = "\"";
  for (char c : identifier) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

// The column of swept key `key`: the key itself, except a swept `seed`
// (a sweep of explicit seeds), whose name the run's own seed column has.
std::string SweptColumn(const std::string& key) {
  return Quote(key == "seed" ? "swept.seed" : key);
}

std::string StorePath(sqlite3* db) {
  const char* name = sqlite3_db_filename(db, "main");
  return name != nullptr && *name != '\0' ? name : "results store";
}

// An SQLite failure as the error a user can act on: a damaged file is bad
// input (exit 2: delete it to recompute); a file or folder the process may not
// read or write is an I/O error (exit 1) that says so; the rest is a run error.
[[noreturn]] void ThrowStoreError(sqlite3* db, int rc, const std::string& doing) {
  const std::string path = StorePath(db);
  const std::string message = sqlite3_errmsg(db);
  switch (rc & 0xff) {
    case SQLITE_CORRUPT:
    case SQLITE_NOTADB:
      throw InputError(SourceLocation{path, 0, 0, ""}, "a results store written by hcpf sweep",
                       fmt::format("a damaged database ({})", message),
                       "delete it and its runs/ folder, then rerun the sweep to recompute");
    case SQLITE_READONLY:
    case SQLITE_PERM:
    case SQLITE_CANTOPEN:
    case SQLITE_AUTH:
      throw RunError(fmt::format(
          "results store {}: cannot {} ({}): check the permissions of the file and its folder",
          path, doing, message));
    case SQLITE_ERROR:
      // "no such table" / "no such column": not a store of this version.
      throw InputError(SourceLocation{path, 0, 0, ""},
                       "a results store written by this version of hcpf sweep",
                       fmt::format("a database whose tables differ ({})", message),
                       "rerun the sweep with --out pointing to a new folder");
    default:
      throw RunError(fmt::format("results store {}: cannot {}: {}", path, doing, message));
  }
}

// A prepared statement that finalises itself.
class Statement {
 public:
  Statement(sqlite3* db, const std::string& sql) : db_(db) {
    const int rc = sqlite3_prepare_v2(db, sql.c_str(), -1, &stmt_, nullptr);
    if (rc != SQLITE_OK) ThrowStoreError(db, rc, "read its tables");
  }
  ~Statement() { sqlite3_finalize(stmt_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  void Bind(int i, const std::string& text) {
    sqlite3_bind_text(stmt_, i, text.c_str(), static_cast<int>(text.size()), SQLITE_TRANSIENT);
  }
  void Bind(int i, int64_t value) { sqlite3_bind_int64(stmt_, i, value); }
  void BindNull(int i) { sqlite3_bind_null(stmt_, i); }
  void BindReal(int i, double value) {
    if (std::isfinite(value)) {
      sqlite3_bind_double(stmt_, i, value);
    } else {
      sqlite3_bind_null(stmt_, i);
    }
  }
  bool Step() {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    ThrowStoreError(db_, rc, "read or write a row");
  }
  std::string Text(int i) const {
    const unsigned char* t = sqlite3_column_text(stmt_, i);
    return t == nullptr ? std::string() : std::string(reinterpret_cast<const char*>(t));
  }
  int64_t Int(int i) const { return sqlite3_column_int64(stmt_, i); }
  bool Integer(int i) const { return sqlite3_column_type(stmt_, i) == SQLITE_INTEGER; }
  bool Null(int i) const { return sqlite3_column_type(stmt_, i) == SQLITE_NULL; }
  bool Number(int i) const {
    const int type = sqlite3_column_type(stmt_, i);
    return type == SQLITE_FLOAT || type == SQLITE_INTEGER;
  }
  double Real(int i) const {
    return sqlite3_column_type(stmt_, i) == SQLITE_NULL ? kNaN : sqlite3_column_double(stmt_, i);
  }

 private:
  sqlite3* db_;
  sqlite3_stmt* stmt_ = nullptr;
};

// A file name as an SQLite URI path: every byte outside the unreserved set
// (and '/') percent-encoded.
std::string UriPath(const std::string& path) {
  std::string out;
  for (unsigned char c : fs::absolute(path).string()) {
    if (std::isalnum(c) || c == '/' || c == '-' || c == '_' || c == '.' || c == '~') {
      out += static_cast<char>(c);
    } else {
      out += fmt::format("%{:02X}", c);
    }
  }
  return out;
}

sqlite3* OpenDb(const std::string& path, StoreAccess access, bool create) {
  std::string name = path;
  int flags = SQLITE_OPEN_FULLMUTEX;
  if (access == StoreAccess::kReadOnly) {
    flags |= SQLITE_OPEN_READONLY;
    // A reader of a store in WAL mode needs to create the -shm file beside
    // it. When the folder cannot be written no sweep can be writing the store
    // either, so it is opened as immutable (no locks, no -shm).
    std::string folder = fs::path(path).parent_path().string();
    if (folder.empty()) folder = ".";
    if (::access(folder.c_str(), W_OK) != 0) {
      name = "file:" + UriPath(path) + "?immutable=1";
      flags |= SQLITE_OPEN_URI;
    }
  } else {
    flags |= SQLITE_OPEN_READWRITE | (create ? SQLITE_OPEN_CREATE : 0);
  }
  sqlite3* db = nullptr;
  const int rc = sqlite3_open_v2(name.c_str(), &db, flags, nullptr);
  if (rc != SQLITE_OK) {
    const std::string message = db ? sqlite3_errmsg(db) : "out of memory";
    sqlite3_close(db);
    if (rc == SQLITE_CANTOPEN || rc == SQLITE_PERM || rc == SQLITE_READONLY) {
      throw RunError(fmt::format(
          "results store {}: cannot open it ({}): check the permissions of the file and its "
          "folder",
          path, message));
    }
    throw InputError(SourceLocation{path, 0, 0, ""}, "a results store (results.sqlite)",
                     "a file SQLite cannot open: " + message);
  }
  sqlite3_busy_timeout(db, 10000);
  // WAL with synchronous=NORMAL: a committed run survives the process being
  // killed (SIGKILL included); only an OS crash or power loss can drop the
  // last commits, which a resumed sweep then recomputes.
  if (access == StoreAccess::kReadWrite) {
    sqlite3_exec(db, "PRAGMA synchronous=NORMAL", nullptr, nullptr, nullptr);
  }
  return db;
}

// `text` read whole as a decimal seed (below 2^64), else nullopt.
std::optional<uint64_t> DecimalSeed(std::string_view text) {
  uint64_t seed = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), seed);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return seed;
}

// A seed as the sweep writes it (std::to_string): no leading zero or sign.
std::optional<uint64_t> WrittenSeed(std::string_view text) {
  const std::optional<uint64_t> seed = DecimalSeed(text);
  return seed && std::to_string(*seed) == text ? seed : std::nullopt;
}

// The top-level `seed` of a resolved scenario (the store's base_resolved),
// nullopt where it has none that reads as a seed.
std::optional<uint64_t> SeedOfResolved(const std::string& yaml) {
  try {
    const YAML::Node root = YAML::Load(yaml);
    if (!root.IsMap() || !root["seed"].IsScalar()) return std::nullopt;
    return DecimalSeed(root["seed"].Scalar());
  } catch (const YAML::Exception&) {
    return std::nullopt;
  }
}

// Each base scenario's seed, by the value naming it, from a grid.base
// sweep's base_resolved (ResolvedBases). A base whose text is not found, or
// has no seed that reads as one, is left out (its rows' seeds unchecked).
std::map<std::string, uint64_t> SeedsOfBases(const StoreMeta& meta) {
  std::map<std::string, uint64_t> out;
  for (const auto& [value, text] : ResolvedBases(meta)) {
    if (const auto seed = SeedOfResolved(text)) out.emplace(value, *seed);
  }
  return out;
}

json ExpansionToJson(const StoredExpansion& e) {
  const auto axes = [](const std::vector<StoredExpansion::Axis>& list) {
    json out = json::array();
    for (const StoredExpansion::Axis& a : list)
      out.push_back({{"key", a.key}, {"values", a.values}});
    return out;
  };
  return {{"grid", axes(e.grid)}, {"zip", axes(e.zip)}, {"seeds", e.seeds}};
}

json ReportToJson(const ReportSpec& r) {
  json j = {{"x", r.x}, {"y", r.y}, {"series", r.series}};
  if (!r.x_metric.empty()) j["x_metric"] = r.x_metric;
  if (!r.pool.empty()) j["pool"] = r.pool;
  if (!r.panels.empty()) j["panels"] = r.panels;
  if (!r.reference.empty()) j["reference"] = r.reference;
  return j;
}

double JsonNumber(const json& j, const std::vector<std::string>& path) {
  const json* node = &j;
  for (const std::string& p : path) {
    if (!node->is_object() || !node->contains(p)) return kNaN;
    node = &(*node)[p];
  }
  return node->is_number() ? node->get<double>() : kNaN;  // "nan"/"inf" strings -> NaN
}

}  // namespace

ResultsStore::ResultsStore(std::string path, sqlite3* db) : path_(std::move(path)), db_(db) {}

ResultsStore::~ResultsStore() {
  if (sqlite3_db_readonly(db_, "main") == 0) {
    // Back to a rollback journal once the writer is done, so the finished
    // store is one file and read-only readers (report, export, merge) create
    // no -wal or -shm beside it. Needs the only connection: with a reader
    // still open the switch fails at once (no busy wait) and the store stays
    // in WAL mode, readable as before.
    sqlite3_busy_timeout(db_, 0);
    sqlite3_exec(db_, "PRAGMA journal_mode=DELETE", nullptr, nullptr, nullptr);
  }
  sqlite3_close(db_);
}

void ResultsStore::Exec(const std::string& sql) const {
  const int rc = sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, nullptr);
  if (rc != SQLITE_OK) ThrowStoreError(db_, rc, "write to it");
}

void ResultsStore::ReadMeta() {
  Statement s(db_, "SELECT name, value FROM meta");
  std::map<std::string, std::string> m;
  while (s.Step()) m[s.Text(0)] = s.Text(1);
  if (!m.count("sweep_hash")) {
    throw InputError(SourceLocation{path_, 0, 0, "meta.sweep_hash"},
                     "a results store of hcpf sweep", "a database without the sweep's hash");
  }
  // A second bad-input audit: a store of another format version was read as
  // this one's.
  if (m["format"] != kStoreFormat) {
    throw InputError(
        SourceLocation{path_, 0, 0, "meta.format"},
        fmt::format("a results store of this hcpf sweep (format \"{}\")", kStoreFormat),
        m.count("format") ? fmt::format("format \"{}\"", m["format"]) : std::string("no format"),
        "a store of another hcpf version is read by that version");
  }
  meta_.sweep_hash = m["sweep_hash"];
  meta_.sweep_file = m["sweep_file"];
  meta_.base_resolved = m["base_resolved"];
  // A bad-input audit: a damaged run_count was read by std::stoll ("found
  // unreadable metadata: stoll", no key), a negative one reported as "8 of
  // -5 runs".
  const auto damaged = [&](const std::string& key, const std::string& expected) {
    return InputError(SourceLocation{path_, 0, 0, "meta." + key},
                      "a results store of hcpf sweep: " + expected, fmt::format("\"{}\"", m[key]),
                      "the store's meta table was changed after the sweep wrote it");
  };
  // Every sweep has written run_count (a bad-input audit: a store without it
  // was reported without a word, no run counted as missing).
  if (m.count("run_count") == 0) {
    throw InputError(SourceLocation{path_, 0, 0, "meta.run_count"},
                     "a results store of hcpf sweep: the sweep's number of runs", "no run_count",
                     "the store's meta table was changed after the sweep wrote it");
  }
  {
    const std::string& text = m["run_count"];
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), meta_.run_count);
    if (ec != std::errc() || end != text.data() + text.size() || meta_.run_count < 0) {
      throw damaged("run_count", "a whole number of runs, 0 or more");
    }
  }
  meta_.root_seed = m["root_seed"];  // "" in a store written before they were recorded
  meta_.root_seed_from = m["root_seed_from"];
  meta_.root_file_seed = m["root_file_seed"];
  const auto parse = [&](const std::string& key, const std::string& expected) {
    try {
      json j = json::parse(m[key]);
      if (key == "swept_keys" ? !j.is_array() : !j.is_object()) throw damaged(key, expected);
      return j;
    } catch (const json::exception&) {
      throw damaged(key, expected);
    }
  };
  try {
    meta_.swept_keys =
        parse("swept_keys", "a JSON list of the swept keys").get<std::vector<std::string>>();
  } catch (const json::exception&) {
    throw damaged("swept_keys", "a JSON list of the swept keys");
  }
  const json report = parse("report", "the sweep file's report: block as a JSON object");
  // Each entry of its type, and no other (a bad-input audit: a number as
  // series gave the JSON library's "type must be string" naming only meta,
  // an unknown key was ignored).
  const auto text = [&](const char* key) -> std::string {
    if (!report.contains(key)) return "";
    if (!report[key].is_string()) {
      throw InputError(SourceLocation{path_, 0, 0, fmt::format("meta.report.{}", key)},
                       "a results store of hcpf sweep: text", report[key].dump(),
                       "the store's meta table was changed after the sweep wrote it");
    }
    return report[key].get<std::string>();
  };
  const auto list = [&](const char* key) -> std::vector<std::string> {
    if (!report.contains(key)) return {};
    const json& j = report[key];
    if (!j.is_array() ||
        !std::all_of(j.begin(), j.end(), [](const json& e) { return e.is_string(); })) {
      throw InputError(SourceLocation{path_, 0, 0, fmt::format("meta.report.{}", key)},
                       "a results store of hcpf sweep: a list of text", j.dump(),
                       "the store's meta table was changed after the sweep wrote it");
    }
    return j.get<std::vector<std::string>>();
  };
  static const std::set<std::string> kReportKeys = {"x",    "y",      "series",   "x_metric",
                                                    "pool", "panels", "reference"};
  for (const auto& [key, value] : report.items()) {
    if (kReportKeys.count(key) == 0) {
      throw InputError(
          SourceLocation{path_, 0, 0, "meta.report"},
          fmt::format("a results store of hcpf sweep: the keys {}", fmt::join(kReportKeys, ", ")),
          fmt::format("\"{}\"", key),
          "the store's meta table was changed after the sweep wrote it");
    }
  }
  meta_.report.x = text("x");
  meta_.report.y = list("y");
  meta_.report.series = text("series");
  meta_.report.x_metric = text("x_metric");
  meta_.report.pool = list("pool");
  meta_.report.panels = text("panels");
  meta_.report.reference = text("reference");
  meta_.expansion.reset();
  root_seed_.reset();
  base_seed_.reset();
  base_seeds_.clear();
  if (!m["expansion"].empty()) {
    meta_.expansion = ReadExpansion(m["expansion"]);
    // The root seed a store with an expansion records (the sweep writes both):
    // a whole number with `seeds:`, "base scenario" without (a bad-input
    // audit: "abc" was shown as the root seed and switched the rows' seed
    // check off).
    if (meta_.expansion->seeds > 0) {
      root_seed_ = WrittenSeed(meta_.root_seed);
      if (!root_seed_) {
        throw damaged("root_seed", "the root of the runs' seeds (a whole number below 2^64)");
      }
    } else if (meta_.root_seed_from != "base scenario" || !meta_.root_seed.empty()) {
      throw InputError(
          SourceLocation{path_, 0, 0, "meta.root_seed_from"},
          "a results store of hcpf sweep: \"base scenario\" and no root_seed (the "
          "sweep has no seeds:)",
          fmt::format("\"{}\" with root_seed \"{}\"", meta_.root_seed_from, meta_.root_seed),
          "the store's meta table was changed after the sweep wrote it");
    } else if (std::find(meta_.swept_keys.begin(), meta_.swept_keys.end(), kSweptBaseKey) ==
               meta_.swept_keys.end()) {
      // Without `seeds:` every run keeps the one base scenario's seed.
      base_seed_ = SeedOfResolved(meta_.base_resolved);
    } else {
      // With `grid.base`, its base scenario's (an audit: a row's seed was
      // not checked under grid.base).
      base_seeds_ = SeedsOfBases(meta_);
    }
  }
  CheckStoredMeta();
}

// The meta's "expansion" (ExpansionToJson), held to the store: its keys are
// the swept keys in column order, each with values, the zip's of one length,
// and it expands to run_count runs.
StoredExpansion ResultsStore::ReadExpansion(const std::string& text) const {
  const auto damaged = [&](const std::string& expected, const std::string& found) {
    return InputError(SourceLocation{path_, 0, 0, "meta.expansion"},
                      "a results store of hcpf sweep: " + expected, found,
                      "the store's meta table was changed after the sweep wrote it");
  };
  const std::string shape =
      "the sweep's expansion as JSON: {\"grid\": [{\"key\": ..., \"values\": [...]}, ...], "
      "\"zip\": [...], \"seeds\": n}";
  StoredExpansion e;
  try {
    const json j = json::parse(text);
    const auto axes = [&](const char* name, std::vector<StoredExpansion::Axis>& out) {
      for (const json& a : j.at(name)) {
        StoredExpansion::Axis axis{a.at("key").get<std::string>(),
                                   a.at("values").get<std::vector<std::string>>()};
        if (axis.values.empty() || static_cast<int64_t>(axis.values.size()) > kMaxSweepRuns) {
          throw damaged(fmt::format("1 to {} values of {}", kMaxSweepRuns, axis.key),
                        fmt::format("{}", axis.values.size()));
        }
        out.push_back(std::move(axis));
      }
    };
    axes("grid", e.grid);
    axes("zip", e.zip);
    const json& seeds = j.at("seeds");
    if (!seeds.is_number_integer() || seeds.get<int64_t>() < 0 ||
        seeds.get<int64_t>() > kMaxSweepSeeds) {
      throw damaged(fmt::format("seeds from 0 to {}", kMaxSweepSeeds), seeds.dump());
    }
    e.seeds = seeds.get<int>();
  } catch (const json::exception&) {
    throw damaged(shape, fmt::format("\"{}\"", text.substr(0, 80)));
  }
  std::vector<std::string> keys;
  for (const auto& a : e.grid) keys.push_back(a.key);
  for (const auto& a : e.zip) keys.push_back(a.key);
  if (keys != meta_.swept_keys) {
    throw damaged(fmt::format("the swept keys [{}]", fmt::join(meta_.swept_keys, ", ")),
                  fmt::format("[{}]", fmt::join(keys, ", ")));
  }
  for (const auto& a : e.zip) {
    if (a.values.size() != e.zip.front().values.size()) {
      throw damaged(fmt::format("zip lists of one length ({} values, as {})",
                                e.zip.front().values.size(), e.zip.front().key),
                    fmt::format("{} values of {}", a.values.size(), a.key));
    }
  }
  if (e.RunCount() > kMaxSweepRuns) {
    throw damaged(fmt::format("an expansion of at most {} runs (a sweep's limit)", kMaxSweepRuns),
                  e.RunCount() == std::numeric_limits<int64_t>::max()
                      ? std::string("more than 2^63 runs")
                      : fmt::format("{} runs", e.RunCount()));
  }
  if (e.RunCount() != meta_.run_count) {
    throw damaged(fmt::format("an expansion of run_count ({}) runs", meta_.run_count),
                  fmt::format("{}", e.RunCount()));
  }
  return e;
}

void ResultsStore::CheckStoredMeta() const {
  // A second bad-input audit: a store's meta edited by hand (or by another
  // program) gave "map::at" (exit 1) for an unknown metric, an empty report,
  // and a swept key without a column read as its own name (SQLite takes a
  // quoted unknown identifier for a string). What the sweep file's report:
  // block is held to (sweep.cc) holds here too.
  std::set<std::string> columns;
  {
    Statement s(db_, "PRAGMA table_info(runs)");
    while (s.Step()) columns.insert(s.Text(1));
  }
  const auto fail = [&](const std::string& key, const std::string& expected,
                        const std::string& found) {
    throw InputError(SourceLocation{path_, 0, 0, "meta." + key},
                     "a results store of hcpf sweep: " + expected, found,
                     "the store's meta table was changed after the sweep wrote it");
  };
  const std::vector<std::string>& swept = meta_.swept_keys;
  std::set<std::string> seen;
  for (const std::string& key : swept) {
    const std::string column = key == "seed" ? "swept.seed" : key;
    if (columns.count(column) == 0 || !seen.insert(key).second) {
      fail("swept_keys", "swept keys listed once, each a column of the runs table",
           fmt::format("\"{}\"", key));
    }
  }
  // The rules the sweep file's report: block is held to (CheckReportRules).
  const ReportSpec& report = meta_.report;
  if (const auto broken = CheckReportRules(report, swept)) {
    const std::string key = broken->item >= 0
                                ? fmt::format("report.{}[{}]", broken->entry, broken->item)
                                : "report." + broken->entry;
    fail(key, broken->expected,
         broken->entry == "y" && broken->item < 0 ? "an empty list"
                                                  : fmt::format("\"{}\"", broken->value));
  }
}

void ResultsStore::AddMissingColumns(StoreAccess access) {
  std::set<std::string> present;
  {
    Statement s(db_, "PRAGMA table_info(runs)");
    while (s.Step()) present.insert(s.Text(1));
  }
  for (const std::string& m : MetricNames()) {
    if (present.count(m)) continue;
    if (access == StoreAccess::kReadWrite) {
      Exec("ALTER TABLE runs ADD COLUMN " + Quote(m) + " REAL");
    } else {
      absent_metrics_.insert(m);
    }
  }
  if (present.count("build") == 0) {
    if (access == StoreAccess::kReadWrite) {
      Exec("ALTER TABLE runs ADD COLUMN build TEXT");
    } else {
      build_absent_ = true;
    }
  }
}

std::unique_ptr<ResultsStore> ResultsStore::Open(const std::string& path, StoreAccess access) {
  std::error_code ec;
  if (!fs::exists(path, ec)) {
    // What the folder is instead (a fourth bad-input audit: a file given
    // as a sweep folder, and a run folder, were both "no such file").
    const fs::path folder = fs::path(path).parent_path();
    std::string found = "no such file";
    if (!folder.empty() && fs::exists(folder, ec) && !fs::is_directory(folder, ec)) {
      found = fmt::format("no such file: {} is a file, not a sweep folder", folder.string());
    } else if (!folder.empty() && fs::is_regular_file(folder / "manifest.json", ec)) {
      found = fmt::format(
          "no such file: {} is a run or render folder (manifest.json), not a sweep folder",
          folder.string());
    }
    throw InputError(SourceLocation{path, 0, 0, ""}, "a results store written by hcpf sweep",
                     found);
  }
  // A directory, FIFO or device is bad input; a file we may not read is an I/O error.
  CheckRegularFile(path, "a results store written by hcpf sweep");
  // An empty file (a copy cut short, `touch`) was "a database whose tables
  // differ (no such table: meta)" (a bad-input audit).
  if (fs::file_size(path, ec) == 0 && !ec) {
    throw InputError(SourceLocation{path, 0, 0, ""}, "a results store written by hcpf sweep",
                     "an empty file",
                     "delete it and its runs/ folder, then rerun the sweep to recompute");
  }
  if (::access(path.c_str(), access == StoreAccess::kReadOnly ? R_OK : R_OK | W_OK) != 0) {
    throw RunError(fmt::format("results store {}: cannot {} it ({}): check its permissions", path,
                               access == StoreAccess::kReadOnly ? "read" : "write",
                               std::strerror(errno)));
  }
  std::unique_ptr<ResultsStore> store(new ResultsStore(path, OpenDb(path, access, false)));
  if (access == StoreAccess::kReadWrite) {
    // Writers use WAL: readers (a report while the sweep runs) do not block
    // them. The destructor switches back. Where WAL cannot be had (a reader
    // holding the file past the busy timeout, a file system without shared
    // memory) the store stays in rollback mode, slower for readers, as valid.
    sqlite3_exec(store->db_, "PRAGMA journal_mode=WAL", nullptr, nullptr, nullptr);
  }
  try {
    store->ReadMeta();
    store->AddMissingColumns(access);
  } catch (const json::exception& e) {
    throw InputError(SourceLocation{path, 0, 0, "meta"}, "a results store of hcpf sweep",
                     std::string("unreadable metadata: ") + e.what());
  } catch (const std::logic_error& e) {  // std::stoll of a damaged run_count
    throw InputError(SourceLocation{path, 0, 0, "meta"}, "a results store of hcpf sweep",
                     std::string("unreadable metadata: ") + e.what());
  }
  return store;
}

namespace {

// The meta entries that describe a sweep without changing its runs (not in
// the sweep hash): a resumed sweep writes its own over the store's.
std::vector<std::pair<std::string, std::string>> DescriptiveMeta(const StoreMeta& meta) {
  return {{"report", ReportToJson(meta.report).dump()},
          // With its expansion: a resume rewrites both (a bad-input audit: an
          // edited run_count the expansion was made to fit was left beside
          // the sweep's own expansion, and no command opened the store again).
          {"run_count", std::to_string(meta.run_count)},
          {"expansion", meta.expansion ? ExpansionToJson(*meta.expansion).dump() : ""},
          {"sweep_file", meta.sweep_file},
          {"root_seed", meta.root_seed},
          {"root_seed_from", meta.root_seed_from},
          {"root_file_seed", meta.root_file_seed}};
}

}  // namespace

std::unique_ptr<ResultsStore> ResultsStore::OpenOrCreate(
    const std::string& path, const StoreMeta& meta,
    const std::function<void(const ResultsStore&)>& check) {
  if (fs::exists(path)) {
    // Checked on a read-only connection first: a store of another sweep is
    // refused untouched (a bad-input audit: the refusal had already switched
    // its journal mode, which rewrote its header, and would have added
    // columns to an older one).
    if (const auto store = Open(path, StoreAccess::kReadOnly);
        store->meta().sweep_hash != meta.sweep_hash) {
      throw InputError(
          SourceLocation{path, 0, 0, "meta.sweep_hash"},
          fmt::format("a store of this sweep (hash {}); name another output folder (sweep "
                      "--out, merge OUT)",
                      meta.sweep_hash),
          fmt::format("a store of another sweep (hash {}, from {}{})", store->meta().sweep_hash,
                      store->meta().sweep_file,
                      // Another root seed (hcpf sweep --seed) is another sweep: said.
                      OfOtherRootSeeds(store->meta(), meta)
                          ? fmt::format(" with root seed {}, this sweep's is {}",
                                        store->meta().root_seed, meta.root_seed)
                          : std::string()));
    } else if (check) {
      check(*store);
    }
    auto store = Open(path, StoreAccess::kReadWrite);
    // The report: block, the file's name and where the root seed came from
    // change no run (they are not in the sweep hash): the file resumed from
    // now says how the store is reported. A second bad-input audit found an
    // edited report: block kept from the first sweep without a word. (The
    // root seed itself is in the hash: another one is another sweep.)
    const std::vector<std::pair<std::string, std::string>> described = DescriptiveMeta(meta);
    if (described != DescriptiveMeta(store->meta())) {
      store->Exec("BEGIN IMMEDIATE");
      for (const auto& [name, value] : described) {
        // INSERT OR REPLACE: a store written before the root seed was
        // recorded has no row for it.
        Statement s(store->db_, "INSERT OR REPLACE INTO meta(name, value) VALUES (?, ?)");
        s.Bind(1, name);
        s.Bind(2, value);
        s.Step();
      }
      store->Exec("COMMIT");
      store->ReadMeta();
      spdlog::info(
          "{}: the report: block, the file's name and the root seed's source taken from {} (the "
          "runs are unchanged)",
          path, meta.sweep_file);
    }
    return store;
  }
  const std::string temp = path + ".new";
  fs::remove(temp);
  // A store that cannot be made (a full disk) leaves no half-made file, nor
  // its journal (once renamed, there is nothing left to remove).
  struct RemoveTemp {
    const std::string& temp;
    ~RemoveTemp() {
      std::error_code ec;
      for (const char* suffix : {"", "-journal", "-wal", "-shm"}) fs::remove(temp + suffix, ec);
    }
  } cleanup{temp};
  {
    ResultsStore store(temp, OpenDb(temp, StoreAccess::kReadWrite, true));
    std::string columns;
    for (const std::string& k : meta.swept_keys) columns += ", " + SweptColumn(k) + " TEXT";
    for (const std::string& m : MetricNames()) columns += ", " + Quote(m) + " REAL";
    columns += ", build TEXT";
    store.Exec("BEGIN");
    store.Exec("CREATE TABLE meta(name TEXT PRIMARY KEY, value TEXT NOT NULL)");
    store.Exec(
        "CREATE TABLE runs(key TEXT PRIMARY KEY, run_index INTEGER NOT NULL, seed_index INTEGER "
        "NOT "
        "NULL, seed TEXT NOT NULL, status TEXT NOT NULL, error TEXT, run_dir TEXT" +
        columns + ")");
    std::vector<std::pair<std::string, std::string>> rows = {
        {"format", kStoreFormat},
        {"sweep_hash", meta.sweep_hash},
        {"swept_keys", json(meta.swept_keys).dump()},
        {"base_resolved", meta.base_resolved}};
    for (auto& entry : DescriptiveMeta(meta)) rows.push_back(std::move(entry));
    for (const auto& [name, value] : rows) {
      Statement s(store.db_, "INSERT INTO meta(name, value) VALUES (?, ?)");
      s.Bind(1, name);
      s.Bind(2, value);
      s.Step();
    }
    store.Exec("COMMIT");
  }
  // Created under a temporary name and renamed: a store never exists without its meta.
  fs::rename(temp, path);
  return Open(path, StoreAccess::kReadWrite);
}

void ResultsStore::Put(const RunRecord& r) {
  std::lock_guard lock(mutex_);
  HCPF_CHECK(r.values.size() == meta_.swept_keys.size());
  std::string columns = "key, run_index, seed_index, seed, status, error, run_dir";
  std::string marks = "?, ?, ?, ?, ?, ?, ?";
  for (const std::string& k : meta_.swept_keys) {
    columns += ", " + SweptColumn(k);
    marks += ", ?";
  }
  for (const std::string& m : MetricNames()) {
    columns += ", " + Quote(m);
    marks += ", ?";
  }
  columns += ", build";
  marks += ", ?";
  Statement s(db_, "INSERT OR REPLACE INTO runs(" + columns + ") VALUES (" + marks + ")");
  int i = 1;
  s.Bind(i++, r.key);
  s.Bind(i++, r.index);
  s.Bind(i++, static_cast<int64_t>(r.seed_index));
  s.Bind(i++, std::to_string(r.seed));
  s.Bind(i++, std::string(r.ok ? "ok" : "failed"));
  s.Bind(i++, r.error);
  s.Bind(i++, r.run_dir);
  for (const std::string& v : r.values) s.Bind(i++, v);
  for (const std::string& m : MetricNames()) {
    const auto it = r.metrics.find(m);
    s.BindReal(i++, it == r.metrics.end() ? kNaN : it->second);
  }
  if (r.build) {
    s.Bind(i++, *r.build);
  } else {
    s.BindNull(i++);
  }
  Exec("BEGIN IMMEDIATE");
  try {
    s.Step();
  } catch (...) {
    Exec("ROLLBACK");
    throw;
  }
  Exec("COMMIT");
}

std::vector<RunRecord> ResultsStore::Runs() const { return ReadRuns(true); }

std::vector<RunRecord> ResultsStore::RunsAsStored() const { return ReadRuns(false); }

int64_t ResultsStore::RowsIfNoSeedFollows(uint64_t root) const {
  Statement s(db_, "SELECT seed_index, seed FROM runs");
  int64_t rows = 0;
  while (s.Step()) {
    if (s.Integer(0) && s.Int(0) >= 0 && s.Int(0) < kMaxSweepSeeds &&
        WrittenSeed(s.Text(1)) == SweepSeed(root, static_cast<int>(s.Int(0)))) {
      return 0;
    }
    ++rows;
  }
  return rows;
}

std::vector<RunRecord> ResultsStore::ReadRuns(bool check_labels) const {
  std::lock_guard lock(mutex_);
  std::optional<size_t> swept_seed;  // a swept `seed` key's place among the values
  std::optional<size_t> base_place;  // grid.base's
  for (size_t k = 0; k < meta_.swept_keys.size(); ++k) {
    if (meta_.swept_keys[k] == "seed") swept_seed = k;
    if (meta_.swept_keys[k] == kSweptBaseKey) base_place = k;
  }
  std::string columns = "key, run_index, seed_index, seed, status, error, run_dir";
  for (const std::string& k : meta_.swept_keys) columns += ", " + SweptColumn(k);
  for (const std::string& m : MetricNames()) {
    columns += absent_metrics_.count(m) ? ", NULL AS " + Quote(m) : ", " + Quote(m);
  }
  columns += build_absent_ ? ", NULL AS build" : ", build";
  Statement s(db_, "SELECT " + columns + " FROM runs ORDER BY run_index, key");
  std::vector<RunRecord> out;
  while (s.Step()) {
    RunRecord r;
    int i = 0;
    r.key = s.Text(i++);
    // A bad-input audit: rows edited by hand were read silently (a metric
    // given as text counted as 0, an unknown status as neither ok nor
    // failed); a seed that is not a number threw std::stoull's text.
    const auto damaged = [&](const std::string& column, const std::string& expected,
                             const std::string& found) {
      return InputError(SourceLocation{path_, 0, 0, fmt::format("runs[{}].{}", r.key, column)},
                        "a results store of hcpf sweep: " + expected, found,
                        "the store's runs table was changed after the sweep wrote it");
    };
    // Whole numbers, as the sweep writes them (a bad-input audit: 3.5 was
    // read as 3, 'x' as 0).
    if (!s.Integer(i)) {
      throw damaged("run_index", "a run index (a whole number)", fmt::format("\"{}\"", s.Text(i)));
    }
    r.index = s.Int(i++);
    if (!s.Integer(i)) {
      throw damaged("seed_index", "a seed index (a whole number)",
                    fmt::format("\"{}\"", s.Text(i)));
    }
    const int64_t seed_index = s.Int(i++);
    // Each run of the sweep's expansion has its own index, below the run
    // count (a bad-input audit: -3 and a second row of one index were kept).
    if (r.index < 0 || (meta_.run_count > 0 && r.index >= meta_.run_count) ||
        (!out.empty() && out.back().index == r.index)) {
      throw damaged("run_index",
                    meta_.run_count > 0
                        ? fmt::format("a run index of its own, 0 to {}", meta_.run_count - 1)
                        : std::string("a run index of its own, 0 or more"),
                    fmt::format("{}{}", r.index,
                                !out.empty() && out.back().index == r.index
                                    ? fmt::format(", the index of run {} too", out.back().key)
                                    : ""));
    }
    if (seed_index < 0 || seed_index >= kMaxSweepSeeds) {
      throw damaged("seed_index", fmt::format("a seed index, 0 to {}", kMaxSweepSeeds - 1),
                    fmt::format("{}", seed_index));
    }
    r.seed_index = static_cast<int>(seed_index);
    const std::string seed = s.Text(i++);
    // As the sweep writes it: a leading zero or sign is an edit.
    if (const std::optional<uint64_t> written = WrittenSeed(seed)) {
      r.seed = *written;
    } else {
      throw damaged("seed", "a seed (a whole number, as decimal text)",
                    fmt::format("\"{}\"", seed));
    }
    const std::string status = s.Text(i++);
    if (status != "ok" && status != "failed") {
      throw damaged("status", "\"ok\" or \"failed\"", fmt::format("\"{}\"", status));
    }
    r.ok = status == "ok";
    r.error = s.Text(i++);
    r.run_dir = s.Text(i++);
    // Keys and run folders become paths under the sweep folder (merge copies
    // them, export and report read them): a key like "../../x" would reach
    // outside it (a second bad-input audit, on a store edited by hand).
    if (!FolderNameProblem(r.key).empty() || (!r.run_dir.empty() && r.run_dir != "runs/" + r.key)) {
      throw InputError(SourceLocation{path_, 0, 0, "runs"},
                       "rows whose key names one folder and whose run_dir is runs/<key> (or empty)",
                       fmt::format("key \"{}\" with run_dir \"{}\"", r.key, r.run_dir));
    }
    for (size_t k = 0; k < meta_.swept_keys.size(); ++k) r.values.push_back(s.Text(i++));
    // The labels of the run at its index (a bad-input audit: a swept value
    // edited to one the sweep does not have drew a cell of its own, and a
    // seed index past the sweep's seeds was reported as a seed).
    if (check_labels && meta_.expansion) {
      const StoredExpansion& e = *meta_.expansion;
      const auto mislabelled = [&](const std::string& column, const std::string& want,
                                   const std::string& found) {
        return InputError(
            SourceLocation{path_, 0, 0, fmt::format("runs[{}].{}", r.key, column)},
            fmt::format("{} (what the sweep's expansion says of run {})", want, r.index), found,
            "the store's runs table was changed after the sweep wrote it; `hcpf sweep` with its "
            "sweep file on this folder rewrites the row");
      };
      if (const int want = e.SeedIndex(r.index); r.seed_index != want) {
        throw mislabelled("seed_index", fmt::format("{}", want), fmt::format("{}", r.seed_index));
      }
      const std::vector<std::string> want = e.Values(r.index);
      for (size_t k = 0; k < want.size(); ++k) {
        if (r.values[k] != want[k]) {
          const std::string& key = meta_.swept_keys[k];
          throw mislabelled(key == "seed" ? "swept.seed" : key, fmt::format("\"{}\"", want[k]),
                            fmt::format("\"{}\"", r.values[k]));
        }
      }
      // The run's seed: derived from the root seed with `seeds:`; else a
      // swept `seed`'s value, or the one base scenario's seed.
      std::optional<uint64_t> want_seed;
      if (root_seed_) {
        want_seed = SweepSeed(*root_seed_, r.seed_index);
      } else if (swept_seed) {
        want_seed = DecimalSeed(want[*swept_seed]);
      } else if (base_place) {
        const auto seed = base_seeds_.find(want[*base_place]);
        if (seed != base_seeds_.end()) want_seed = seed->second;
      } else {
        want_seed = base_seed_;
      }
      if (want_seed && r.seed != *want_seed) {
        // A root seed edited by hand moves every row's seed, an edited row
        // only its own: when no row's seed follows from the root, the root
        // is what changed (an audit: 2 written for 1 was blamed on the
        // first row, with a hint to rewrite it).
        if (root_seed_) {
          if (const int64_t rows = RowsIfNoSeedFollows(*root_seed_); rows >= 2) {
            throw InputError(
                SourceLocation{path_, 0, 0, "meta.root_seed"},
                fmt::format("the root seed the runs' seeds follow from (none of the {} rows' seeds "
                            "follows from this one: run {} at seed index {} has seed {}, where "
                            "it would give {})",
                            rows, r.index, r.seed_index, r.seed, *want_seed),
                meta_.root_seed,
                "the store's meta.root_seed was changed after the sweep wrote it; write back the "
                "sweep's root seed (its file's seed:, or the --seed it ran with)");
          }
        }
        throw mislabelled("seed", fmt::format("{}", *want_seed), fmt::format("{}", r.seed));
      }
    }
    for (const std::string& m : MetricNames()) {
      if (!s.Null(i) && !s.Number(i)) {
        throw damaged(m, "a finite number or NULL", fmt::format("the text \"{}\"", s.Text(i)));
      }
      // The sweep stores a metric that is not finite as NULL (BindReal): an
      // Inf was left out of a cell's mean while a resume recomputed its run
      // (a bad-input audit).
      if (!s.Null(i) && !std::isfinite(s.Real(i))) {
        throw damaged(m, "a finite number or NULL", fmt::format("{}", s.Real(i)));
      }
      r.metrics[m] = s.Real(i++);
    }
    if (!s.Null(i)) r.build = s.Text(i);
    ++i;
    out.push_back(std::move(r));
  }
  return out;
}

namespace {

json ReadRunJson(const std::string& run_dir, const std::string& name) {
  std::ifstream in(fs::path(run_dir) / name);
  if (!in) throw RunError(fmt::format("cannot read {}/{}", run_dir, name));
  try {
    return json::parse(in);
  } catch (const json::exception& e) {
    throw RunError(fmt::format("{}/{}: {}", run_dir, name, e.what()));
  }
}

// Whether every file the manifest lists ("files": path -> bytes, written by
// RunScenario) is still a regular file of that size. A manifest of an hcpf
// from before the list asks only that the files every run writes are there.
bool RunFilesWhole(const std::string& run_dir, const json& manifest,
                   std::span<const char* const> files_before_the_list) {
  std::error_code ec;
  if (!manifest.contains("files")) {
    for (const char* name : files_before_the_list) {
      if (!fs::is_regular_file(fs::path(run_dir) / name, ec)) return false;
    }
    return true;
  }
  const json& files = manifest["files"];
  if (!files.is_object()) return false;
  for (const auto& [name, bytes] : files.items()) {
    const fs::path path = fs::path(run_dir) / name;
    if (!bytes.is_number_unsigned() || !fs::is_regular_file(path, ec) ||
        fs::file_size(path, ec) != bytes.get<uint64_t>() || ec) {
      return false;
    }
  }
  return true;
}

// "<hcpf_version> at <git_revision>" from a run's manifest, "" when it names
// no git revision.
std::string BuildOf(const json& manifest) {
  const auto text = [&manifest](const char* key) {
    return manifest.is_object() && manifest.contains(key) && manifest[key].is_string()
               ? manifest[key].get<std::string>()
               : std::string();
  };
  if (text("git_revision").empty()) return "";
  return scenarios::BuildName(text("hcpf_version"), text("git_revision"));
}

// The headline metrics of a run from its metrics.json and manifest.json.
std::map<std::string, double> RunMetricsOf(const json& metrics, const json& manifest) {
  std::map<std::string, double> m;
  for (const CatalogueMetric& c : MetricCatalogue()) {
    const json& source = c.file == "manifest.json" ? manifest : metrics;
    const json::json_pointer pointer{std::string(c.pointer)};
    const double value = source.contains(pointer) && source[pointer].is_number()
                             ? source[pointer].get<double>()
                             : kNaN;  // absent, or "nan"/"inf" strings
    if (c.per_frame_ms) {
      const double frames = JsonNumber(manifest, {"frames"});
      m[std::string(c.name)] = frames > 0 ? 1000.0 * value / frames : kNaN;
    } else {
      m[std::string(c.name)] = value;
    }
  }
  return m;
}

}  // namespace

int64_t StoredExpansion::RunCount() const {
  std::vector<int64_t> lengths;
  for (const Axis& a : grid) lengths.push_back(static_cast<int64_t>(a.values.size()));
  if (!zip.empty()) lengths.push_back(static_cast<int64_t>(zip.front().values.size()));
  int64_t runs = std::max(seeds, 1);
  for (const int64_t n : lengths) {
    if (__builtin_mul_overflow(runs, n, &runs)) return std::numeric_limits<int64_t>::max();
  }
  return runs;
}

int StoredExpansion::SeedIndex(int64_t index) const {
  return static_cast<int>(index % std::max(seeds, 1));
}

std::vector<std::string> StoredExpansion::Values(int64_t index) const {
  std::vector<int64_t> lengths;
  for (const Axis& a : grid) lengths.push_back(static_cast<int64_t>(a.values.size()));
  const int64_t zip_length = zip.empty() ? 1 : static_cast<int64_t>(zip.front().values.size());
  const CellPlace place = PlaceOfCell(lengths, zip_length, index / std::max(seeds, 1));
  std::vector<std::string> values;
  for (size_t g = 0; g < grid.size(); ++g) values.push_back(grid[g].values[place.digits[g]]);
  for (const Axis& a : zip) values.push_back(a.values[place.zip_position]);
  return values;
}

StoredExpansion ExpansionOf(const SweepSpec& spec) {
  StoredExpansion e;
  for (const SweepAxis& a : spec.grid) e.grid.push_back({a.key, a.values});
  for (const SweepAxis& a : spec.zip) e.zip.push_back({a.key, a.values});
  e.seeds = spec.seeds;
  return e;
}

void SetRootSeedMeta(const SweepSpec& spec, StoreMeta& meta) {
  if (spec.seeds == 0) {
    meta.root_seed.clear();
    meta.root_seed_from = "base scenario";
    meta.root_file_seed.clear();
    return;
  }
  meta.root_seed = std::to_string(spec.seed);
  meta.root_seed_from = spec.seed_from;
  meta.root_file_seed = std::to_string(spec.file_seed);
}

bool OfOtherRootSeeds(const StoreMeta& a, const StoreMeta& b) {
  return !a.root_seed.empty() && !b.root_seed.empty() && a.root_seed != b.root_seed;
}

std::string MissingRunsSentence(const StoreMeta& meta, size_t stored_runs) {
  const auto stored = static_cast<int64_t>(stored_runs);
  if (meta.run_count <= 0 || stored >= meta.run_count) return "";
  return fmt::format(
      "The store holds {} of the sweep's {} runs: {} are missing (a sweep stopped before its end, "
      "or one shard of several: resume it with the same `hcpf sweep` command, or `hcpf merge` "
      "the shards' folders), and everything here is of the runs it holds.",
      stored, meta.run_count, meta.run_count - stored);
}

std::string UncheckedLabelsSentence(const ResultsStore& store) {
  if (store.meta().expansion) return "";
  return fmt::format(
      "{} records no expansion (a store written before 2026-12-06, or edited): its rows' seed "
      "indices, seeds and swept values are read as they are, unchecked; `hcpf sweep` with its "
      "sweep file on its folder records one",
      store.path());
}

std::map<std::string, std::string> ResolvedBases(const StoreMeta& meta) {
  std::map<std::string, std::string> out;
  if (!meta.expansion) return out;
  const StoredExpansion::Axis* axis = nullptr;
  for (const StoredExpansion::Axis& a : meta.expansion->grid) {
    if (a.key == kSweptBaseKey) axis = &a;
  }
  if (axis == nullptr) return out;
  const std::string& text = meta.base_resolved;
  // Where each base's head begins: the text's start, then each after a
  // line break, in order.
  std::vector<size_t> heads;
  for (const std::string& value : axis->values) {
    const std::string head = internal::BaseResolvedHead(value);
    const size_t found = heads.empty() ? (text.starts_with(head) ? 0 : std::string::npos)
                                       : text.find("\n" + head, heads.back());
    if (found == std::string::npos) return out;
    heads.push_back(heads.empty() ? 0 : found + 1);
  }
  for (size_t b = 0; b < heads.size(); ++b) {
    const size_t begin = heads[b] + internal::BaseResolvedHead(axis->values[b]).size();
    const size_t end = b + 1 < heads.size() ? heads[b + 1] : text.size();
    out.emplace(axis->values[b], text.substr(begin, end - begin));
  }
  return out;
}

std::string RootSeedSentence(const StoreMeta& meta) {
  if (meta.root_seed_from.empty()) {
    return "The store does not record the sweep's root seed (it was written before hcpf "
           "recorded one).";
  }
  if (meta.root_seed_from == "base scenario") {
    return "Every run keeps its base scenario's seed (the sweep has no `seeds:`).";
  }
  if (meta.root_seed_from == "sweep file") {
    return fmt::format("The runs' seeds are derived from root seed {}, the sweep file's `seed:`.",
                       meta.root_seed);
  }
  return fmt::format(
      "The runs' seeds are derived from root seed {0}, given by `hcpf sweep {1} {0}` (the sweep "
      "file's `seed:` is {2}).",
      meta.root_seed, meta.root_seed_from, meta.root_file_seed);
}

std::map<std::string, double> ReadRunMetrics(const std::string& run_dir) {
  return RunMetricsOf(ReadRunJson(run_dir, "metrics.json"), ReadRunJson(run_dir, "manifest.json"));
}

void ReadRunFolderInto(const std::string& run_dir, RunRecord& record) {
  const json manifest = ReadRunJson(run_dir, "manifest.json");
  record.metrics = RunMetricsOf(ReadRunJson(run_dir, "metrics.json"), manifest);
  record.build = BuildOf(manifest);
}

std::string ReadRunBuild(const std::string& run_dir) {
  // Only the top level is kept (frame_digests and files, most of a
  // manifest, are parsed and dropped).
  const json::parser_callback_t top_level = [](int depth, json::parse_event_t, json&) {
    return depth <= 1;
  };
  try {
    return BuildOf(json::parse(ReadInputFile((fs::path(run_dir) / "manifest.json").string(),
                                             "a run manifest (JSON)", std::uint64_t{64} << 20),
                               top_level));
  } catch (const std::exception&) {
    return "";
  }
}

bool RunFolderIntact(const std::string& run_dir, const RunRecord& record,
                     std::span<const char* const> files_before_the_list) {
  std::map<std::string, double> now;
  try {
    const json manifest = ReadRunJson(run_dir, "manifest.json");
    if (!RunFilesWhole(run_dir, manifest, files_before_the_list)) return false;
    // The run of its row: a run's key is its configuration hash (a fourth
    // bad-input audit: a folder whose manifest names another configuration
    // was merged as ok and reused).
    if (manifest.is_object() && manifest.contains("config_hash") &&
        manifest["config_hash"] != json(record.key)) {
      return false;
    }
    now = RunMetricsOf(ReadRunJson(run_dir, "metrics.json"), manifest);
  } catch (const RunError&) {
    return false;
  }
  for (const auto& [name, value] : record.metrics) {
    const auto it = now.find(name);
    if (it == now.end()) return false;
    const bool same = (std::isnan(value) && std::isnan(it->second)) || value == it->second;
    if (!same) return false;
  }
  return true;
}

void CheckSweepFolder(const std::string& dir, const std::string& option) {
  scenarios::CheckFolderArgument(dir, option);
  std::error_code ec;
  if (fs::exists(fs::path(dir) / "results.sqlite", ec)) return;
  const std::string foreign =
      scenarios::FirstForeignEntry(dir, [](const fs::directory_entry& entry) {
        // What a sweep writes before its store exists (a sweep stopped early).
        const std::string name = entry.path().filename().string();
        return name == "runs" || name == "sweep.lock" || name == "results.sqlite.new";
      });
  if (foreign.empty()) return;
  const bool run_folder = fs::exists(fs::path(dir) / "manifest.json", ec);
  throw InputError(SourceLocation{dir, 0, 0, option},
                   "a new or empty folder, or an earlier output folder of hcpf sweep or hcpf "
                   "merge (one with results.sqlite)",
                   run_folder ? std::string("an output folder of hcpf run or hcpf render "
                                            "(manifest.json)")
                              : fmt::format("a folder with other files in it (\"{}\")", foreign),
                   "nothing was changed; name another folder");
}

namespace internal {

void CopyWhole(const fs::path& from, const fs::path& to, const std::vector<std::string>& files) {
  const fs::path staging = to.string() + fmt::format(".partial-{}", ::getpid());
  std::error_code ec;
  fs::remove_all(staging, ec);
  if (files.empty()) {
    fs::copy(from, staging, fs::copy_options::recursive, ec);
  }
  for (const std::string& name : files) {
    if (!ec) fs::create_directories((staging / name).parent_path(), ec);
    if (!ec) fs::copy_file(from / name, staging / name, ec);
  }
  if (!ec && fs::is_directory(staging, ec)) fs::remove_all(to, ec);  // rename replaces a file
  if (!ec) fs::rename(staging, to, ec);
  if (ec) {
    const std::string message = ec.message();
    fs::remove_all(staging, ec);
    throw RunError(fmt::format("cannot copy {} to {}: {}", from.string(), to.string(), message));
  }
}

}  // namespace internal

MergeResult MergeStores(const std::string& out_dir, const std::vector<std::string>& input_dirs) {
  if (input_dirs.empty()) {
    throw InputError(SourceLocation{"hcpf merge", 0, 0, "DIR"}, "at least one shard folder",
                     "none");
  }
  CheckSweepFolder(out_dir, "OUT");
  std::vector<std::unique_ptr<ResultsStore>> inputs;
  for (const std::string& dir : input_dirs) {
    // A third bad-input audit: a shard still being swept was merged as if
    // complete, exit 0.
    if (internal::FolderLockHeld(dir)) {
      throw InputError(SourceLocation{dir, 0, 0, "DIR"},
                       "a shard folder no sweep is writing to (merge it when its sweep ends)",
                       "a sweep running there (its sweep.lock is held)");
    }
    inputs.push_back(
        ResultsStore::Open((fs::path(dir) / "results.sqlite").string(), StoreAccess::kReadOnly));
    if (inputs.back()->meta().sweep_hash != inputs.front()->meta().sweep_hash) {
      throw InputError(SourceLocation{inputs.back()->path(), 0, 0, "meta.sweep_hash"},
                       fmt::format("a store of the same sweep as {} (hash {})",
                                   inputs.front()->path(), inputs.front()->meta().sweep_hash),
                       fmt::format("hash {} (from {})", inputs.back()->meta().sweep_hash,
                                   inputs.back()->meta().sweep_file));
    }
  }
  // Every input is read in full before OUT is touched: a damaged shard (its
  // runs table gone) left a merged store holding the runs read before it.
  std::vector<std::vector<RunRecord>> rows;
  for (const auto& input : inputs) rows.push_back(input->Runs());
  std::error_code ec;
  fs::create_directories(out_dir, ec);
  if (ec) throw RunError(fmt::format("cannot create {}: {}", out_dir, ec.message()));
  // One writer per folder: a sweep running in OUT, or another merge.
  const internal::FolderLock lock(out_dir, out_dir, "OUT");
  // Run folders an earlier merge or sweep was killed while copying or writing.
  scenarios::RemoveStaleStagingFolders(fs::path(out_dir) / "runs", "");
  // The meta of the first input that records its expansion (a store of an
  // older hcpf records none; a bad-input audit: merged first, it left the
  // spellings of the others unlabelled, and their cells split in two).
  const auto described = std::find_if(inputs.begin(), inputs.end(), [](const auto& input) {
    return input->meta().expansion.has_value();
  });
  auto out =
      ResultsStore::OpenOrCreate((fs::path(out_dir) / "results.sqlite").string(),
                                 (described != inputs.end() ? *described : inputs.front())->meta());
  // An ok row counts as present only while its run folder still holds the
  // metrics the row records; a deleted or damaged one can be replaced.
  std::map<std::string, bool> present;  // key -> ok
  for (const RunRecord& r : out->Runs()) {
    present[r.key] = r.ok && RunFolderIntact((fs::path(out_dir) / r.run_dir).string(), r);
  }
  MergeResult result;
  const std::optional<StoredExpansion>& expansion = out->meta().expansion;
  for (size_t i = 0; i < inputs.size(); ++i) {
    for (RunRecord& r : rows[i]) {
      // Labelled as OUT's expansion says: a shard run from the sweep file
      // with a value written otherwise (0.10 for 0.1; the same runs, so the
      // same hash) holds that spelling.
      if (expansion) {
        r.seed_index = expansion->SeedIndex(r.index);
        r.values = expansion->Values(r.index);
      }
      if (r.ok && !RunFolderIntact((fs::path(input_dirs[i]) / r.run_dir).string(), r)) {
        // Kept as a failed row: resuming the sweep on the merged folder recomputes it.
        r.ok = false;
        r.error = fmt::format("run folder {} was missing or damaged when merged from {}", r.run_dir,
                              input_dirs[i]);
        for (auto& [name, value] : r.metrics) value = kNaN;
        ++result.damaged;
      }
      const auto it = present.find(r.key);
      if (it != present.end() && (it->second || !r.ok)) {
        ++result.duplicates;
        continue;
      }
      if (it == present.end())
        ++result.added;
      else
        ++result.duplicates;
      if (!r.run_dir.empty()) {
        const fs::path from = fs::path(input_dirs[i]) / r.run_dir;
        const fs::path to = fs::path(out_dir) / r.run_dir;
        std::error_code ec;
        if (r.ok && fs::exists(from, ec) && !fs::equivalent(from, to, ec)) {
          // As a sweep publishes a run: a merge killed part-way leaves a
          // staging folder the next merge or sweep removes, never a half
          // folder under the run's name.
          fs::create_directories(to.parent_path(), ec);
          internal::CopyWhole(from, to);
        }
      }
      out->Put(r);
      present[r.key] = r.ok;
    }
  }
  // The scene's contact sheet a shard's sweep left (every shard draws the
  // same one: the sweep's first rendered run), for the report of OUT.
  const fs::path sheet = fs::path(out_dir) / "contact_sheet.png";
  for (const std::string& dir : input_dirs) {
    const fs::path from = fs::path(dir) / "contact_sheet.png";
    if (fs::exists(sheet, ec) || !fs::is_regular_file(from, ec)) continue;
    internal::CopyWhole(from, sheet);
    result.contact_sheet = true;
  }
  return result;
}

}  // namespace hcpf::studies
