#include "hcpf/studies/results_store.h"

#include <fmt/format.h>
#include <sqlite3.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

#include "hcpf/core/check.h"
#include "hcpf/core/error.h"
#include "hcpf/studies/metric_catalogue.h"

namespace hcpf::studies {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string Quote(const std::string& identifier) {
  std::string out = "\"";
  for (char c : identifier) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

// A prepared statement that finalises itself.
class Statement {
 public:
  Statement(sqlite3* db, const std::string& sql) : db_(db) {
    if (sqlite3_prepare_v2(db, sql.c_str(), -1, &stmt_, nullptr) != SQLITE_OK) {
      throw RunError(
          fmt::format("results store: cannot prepare \"{}\": {}", sql, sqlite3_errmsg(db)));
    }
  }
  ~Statement() { sqlite3_finalize(stmt_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  void Bind(int i, const std::string& text) {
    sqlite3_bind_text(stmt_, i, text.c_str(), static_cast<int>(text.size()), SQLITE_TRANSIENT);
  }
  void Bind(int i, int64_t value) { sqlite3_bind_int64(stmt_, i, value); }
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
    throw RunError(fmt::format("results store: {}", sqlite3_errmsg(db_)));
  }
  std::string Text(int i) const {
    const unsigned char* t = sqlite3_column_text(stmt_, i);
    return t == nullptr ? std::string() : std::string(reinterpret_cast<const char*>(t));
  }
  int64_t Int(int i) const { return sqlite3_column_int64(stmt_, i); }
  double Real(int i) const {
    return sqlite3_column_type(stmt_, i) == SQLITE_NULL ? kNaN : sqlite3_column_double(stmt_, i);
  }

 private:
  sqlite3* db_;
  sqlite3_stmt* stmt_ = nullptr;
};

sqlite3* OpenDb(const std::string& path, bool create) {
  sqlite3* db = nullptr;
  const int flags =
      SQLITE_OPEN_READWRITE | SQLITE_OPEN_FULLMUTEX | (create ? SQLITE_OPEN_CREATE : 0);
  if (sqlite3_open_v2(path.c_str(), &db, flags, nullptr) != SQLITE_OK) {
    const std::string message = db ? sqlite3_errmsg(db) : "out of memory";
    sqlite3_close(db);
    throw InputError(SourceLocation{path, 0, 0, ""}, "a results store (results.sqlite)",
                     "a file SQLite cannot open: " + message);
  }
  sqlite3_busy_timeout(db, 10000);
  // WAL with synchronous=NORMAL: a committed run survives the process being
  // killed (SIGKILL included); only an OS crash or power loss can drop the
  // last commits, which a resumed sweep then recomputes.
  sqlite3_exec(db, "PRAGMA synchronous=NORMAL", nullptr, nullptr, nullptr);
  return db;
}

json ReportToJson(const ReportSpec& r) { return {{"x", r.x}, {"y", r.y}, {"series", r.series}}; }

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

ResultsStore::~ResultsStore() { sqlite3_close(db_); }

void ResultsStore::Exec(const std::string& sql) const {
  char* message = nullptr;
  if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &message) != SQLITE_OK) {
    const std::string text = message ? message : "unknown error";
    sqlite3_free(message);
    throw RunError(fmt::format("results store {}: {}", path_, text));
  }
}

void ResultsStore::ReadMeta() {
  Statement s(db_, "SELECT name, value FROM meta");
  std::map<std::string, std::string> m;
  while (s.Step()) m[s.Text(0)] = s.Text(1);
  if (!m.count("sweep_hash")) {
    throw InputError(SourceLocation{path_, 0, 0, "meta.sweep_hash"},
                     "a results store of hcpf sweep", "a database without the sweep's hash");
  }
  meta_.sweep_hash = m["sweep_hash"];
  meta_.sweep_file = m["sweep_file"];
  meta_.base_resolved = m["base_resolved"];
  meta_.run_count = m.count("run_count") ? std::stoll(m["run_count"]) : 0;
  meta_.swept_keys = json::parse(m["swept_keys"]).get<std::vector<std::string>>();
  const json report = json::parse(m["report"]);
  meta_.report.x = report.value("x", "");
  meta_.report.y = report.value("y", std::vector<std::string>{});
  meta_.report.series = report.value("series", "");
}

std::unique_ptr<ResultsStore> ResultsStore::Open(const std::string& path) {
  if (!fs::is_regular_file(path)) {
    throw InputError(SourceLocation{path, 0, 0, ""}, "a results store written by hcpf sweep",
                     "no such file");
  }
  std::unique_ptr<ResultsStore> store(new ResultsStore(path, OpenDb(path, false)));
  try {
    store->ReadMeta();
  } catch (const json::exception& e) {
    throw InputError(SourceLocation{path, 0, 0, "meta"}, "a results store of hcpf sweep",
                     std::string("unreadable metadata: ") + e.what());
  } catch (const RunError& e) {
    throw InputError(SourceLocation{path, 0, 0, "meta"}, "a results store of hcpf sweep", e.what());
  }
  return store;
}

std::unique_ptr<ResultsStore> ResultsStore::OpenOrCreate(const std::string& path,
                                                         const StoreMeta& meta) {
  if (fs::exists(path)) {
    auto store = Open(path);
    if (store->meta().sweep_hash != meta.sweep_hash) {
      throw InputError(
          SourceLocation{path, 0, 0, "meta.sweep_hash"},
          fmt::format("a store of this sweep (hash {}); use another --out", meta.sweep_hash),
          fmt::format("a store of another sweep (hash {}, from {})", store->meta().sweep_hash,
                      store->meta().sweep_file));
    }
    return store;
  }
  const std::string temp = path + ".new";
  fs::remove(temp);
  {
    ResultsStore store(temp, OpenDb(temp, true));
    std::string columns;
    for (const std::string& k : meta.swept_keys) columns += ", " + Quote(k) + " TEXT";
    for (const std::string& m : MetricNames()) columns += ", " + Quote(m) + " REAL";
    store.Exec("BEGIN");
    store.Exec("CREATE TABLE meta(name TEXT PRIMARY KEY, value TEXT NOT NULL)");
    store.Exec(
        "CREATE TABLE runs(key TEXT PRIMARY KEY, run_index INTEGER NOT NULL, seed_index INTEGER "
        "NOT "
        "NULL, seed TEXT NOT NULL, status TEXT NOT NULL, error TEXT, run_dir TEXT" +
        columns + ")");
    const std::vector<std::pair<std::string, std::string>> rows = {
        {"format", "hcpf-results/1"},
        {"sweep_hash", meta.sweep_hash},
        {"sweep_file", meta.sweep_file},
        {"swept_keys", json(meta.swept_keys).dump()},
        {"report", ReportToJson(meta.report).dump()},
        {"base_resolved", meta.base_resolved},
        {"run_count", std::to_string(meta.run_count)}};
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
  auto store = Open(path);
  store->Exec("PRAGMA journal_mode=WAL");
  return store;
}

void ResultsStore::Put(const RunRecord& r) {
  std::lock_guard lock(mutex_);
  HCPF_CHECK(r.values.size() == meta_.swept_keys.size());
  std::string columns = "key, run_index, seed_index, seed, status, error, run_dir";
  std::string marks = "?, ?, ?, ?, ?, ?, ?";
  for (const std::string& k : meta_.swept_keys) {
    columns += ", " + Quote(k);
    marks += ", ?";
  }
  for (const std::string& m : MetricNames()) {
    columns += ", " + Quote(m);
    marks += ", ?";
  }
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
  Exec("BEGIN IMMEDIATE");
  try {
    s.Step();
  } catch (...) {
    Exec("ROLLBACK");
    throw;
  }
  Exec("COMMIT");
}

std::vector<RunRecord> ResultsStore::Runs() const {
  std::lock_guard lock(mutex_);
  std::string columns = "key, run_index, seed_index, seed, status, error, run_dir";
  for (const std::string& k : meta_.swept_keys) columns += ", " + Quote(k);
  for (const std::string& m : MetricNames()) columns += ", " + Quote(m);
  Statement s(db_, "SELECT " + columns + " FROM runs ORDER BY run_index, key");
  std::vector<RunRecord> out;
  while (s.Step()) {
    RunRecord r;
    int i = 0;
    r.key = s.Text(i++);
    r.index = s.Int(i++);
    r.seed_index = static_cast<int>(s.Int(i++));
    r.seed = std::stoull(s.Text(i++));
    r.ok = s.Text(i++) == "ok";
    r.error = s.Text(i++);
    r.run_dir = s.Text(i++);
    for (size_t k = 0; k < meta_.swept_keys.size(); ++k) r.values.push_back(s.Text(i++));
    for (const std::string& m : MetricNames()) r.metrics[m] = s.Real(i++);
    out.push_back(std::move(r));
  }
  return out;
}

std::map<std::string, double> ReadRunMetrics(const std::string& run_dir) {
  const auto read = [&](const std::string& name) {
    std::ifstream in(fs::path(run_dir) / name);
    if (!in) throw RunError(fmt::format("cannot read {}/{}", run_dir, name));
    try {
      return json::parse(in);
    } catch (const json::exception& e) {
      throw RunError(fmt::format("{}/{}: {}", run_dir, name, e.what()));
    }
  };
  const json metrics = read("metrics.json");
  const json manifest = read("manifest.json");
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

MergeResult MergeStores(const std::string& out_dir, const std::vector<std::string>& input_dirs) {
  if (input_dirs.empty()) {
    throw InputError(SourceLocation{"hcpf merge", 0, 0, "DIR"}, "at least one shard folder",
                     "none");
  }
  std::vector<std::unique_ptr<ResultsStore>> inputs;
  for (const std::string& dir : input_dirs) {
    inputs.push_back(ResultsStore::Open((fs::path(dir) / "results.sqlite").string()));
    if (inputs.back()->meta().sweep_hash != inputs.front()->meta().sweep_hash) {
      throw InputError(SourceLocation{inputs.back()->path(), 0, 0, "meta.sweep_hash"},
                       fmt::format("a store of the same sweep as {} (hash {})",
                                   inputs.front()->path(), inputs.front()->meta().sweep_hash),
                       fmt::format("hash {} (from {})", inputs.back()->meta().sweep_hash,
                                   inputs.back()->meta().sweep_file));
    }
  }
  fs::create_directories(out_dir);
  auto out = ResultsStore::OpenOrCreate((fs::path(out_dir) / "results.sqlite").string(),
                                        inputs.front()->meta());
  std::map<std::string, bool> present;  // key -> ok
  for (const RunRecord& r : out->Runs()) present[r.key] = r.ok;
  MergeResult result;
  for (size_t i = 0; i < inputs.size(); ++i) {
    for (const RunRecord& r : inputs[i]->Runs()) {
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
        if (fs::exists(from, ec) && !fs::equivalent(from, to, ec)) {
          fs::remove_all(to, ec);
          fs::create_directories(to.parent_path(), ec);
          fs::copy(from, to, fs::copy_options::recursive, ec);
          if (ec)
            throw RunError(
                fmt::format("cannot copy {} to {}: {}", from.string(), to.string(), ec.message()));
        }
      }
      out->Put(r);
      present[r.key] = r.ok;
    }
  }
  return result;
}

}  // namespace hcpf::studies
