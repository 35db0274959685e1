// `hcpf regress`: run golden scenes, compare their metrics with a baseline.

#include "hcpf/studies/regress.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>

#include "hcpf/config/file_lookup.h"
#include "hcpf/config/overrides.h"
#include "hcpf/config/yaml_reader.h"
#include "hcpf/core/check.h"
#include "hcpf/core/names.h"
#include "hcpf/core/parallel.h"
#include "hcpf/core/text_file.h"
#include "hcpf/scenarios/output_folder.h"
#include "hcpf/scenarios/run.h"
#include "hcpf/studies/file_keys.h"
#include "hcpf/studies/metric_catalogue.h"
#include "hcpf/studies/results_store.h"
#include "hcpf/studies/run_queue.h"
#include "hcpf/studies/statistics.h"
#include "hcpf/studies/sweep.h"
#include "text.h"

namespace hcpf::studies {

using scenarios::ConfigHash;
using scenarios::LoadScenarioFile;
using scenarios::RunOptions;
using scenarios::RunScenario;
using scenarios::Scenario;

using config::FlowText;
using config::YamlContext;
using config::YamlReader;

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json JsonNumber(double v) { return std::isfinite(v) ? json(v) : json("nan"); }
double FromJson(const json& j) { return j.is_number() ? j.get<double>() : kNaN; }

}  // namespace

bool IsRegressSuiteFile(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return false;
  try {
    const YAML::Node root = YamlReader::ParseFile(path);
    if (!root.IsMap()) return false;
    const YAML::Node scenes = root["scenes"];
    return scenes && scenes.IsSequence();
  } catch (const InputError&) {
    return false;
  }
}

RegressSuite LoadRegressSuite(const std::string& path) {
  YAML::Node root = YamlReader::ParseFile(path);
  auto context = std::make_shared<YamlContext>();
  context->file = path;
  if (!root.IsMap()) {
    throw InputError(SourceLocation{path, 1, 1, ""}, "a suite mapping (scenes:, metrics:)",
                     "no mapping");
  }
  const std::string dir =
      fs::path(path).parent_path().empty() ? "." : fs::path(path).parent_path().string();
  YamlReader r(root, "", context);
  RegressSuite suite;
  suite.file = path;
  std::set<std::string> names;
  for (YamlReader item : r.Child("scenes").Items()) {
    item.ExpectMap();
    RegressScene scene;
    YamlReader scenario_node = item.Child("scenario");
    scene.scenario_path = config::FindFileOrFail(
        scenario_node.Where(), item.String("scenario", std::nullopt), dir,
        "a scenario file (looked next to the suite, in the current folder and in the project "
        "folder)");
    scene.name = item.String("name", fs::path(scene.scenario_path).stem().string());
    // The name is the scene's folder under --work: "../x" would escape it
    // and replace a folder there.
    if (const std::string problem = FolderNameProblem(scene.name); !problem.empty()) {
      const std::string expected =
          "a scene name that can name one folder (no '/', '\\', \".\", \"..\" or control "
          "characters)";
      if (item.Has("name")) item.Child("name").Fail(expected, "it is " + problem);
      throw InputError(SourceLocation{path, 0, 0, "scenes.name"},
                       expected + " (the scenario file's name, by default)", problem);
    }
    if (!names.insert(scene.name).second)
      item.Child("name").Fail("a scene name used once in the suite");
    // Where each override is written in the suite, for errors in its value.
    std::vector<SourceLocation> override_at;
    if (auto set = item.Optional("set")) {
      set->ExpectMap();
      for (auto it = set->node().begin(); it != set->node().end(); ++it) {
        const std::string key = it->first.Scalar();
        override_at.push_back(set->Child(key).Where());  // and marks it read
        // `tracker` and `tracker.particles` together: the later one wins
        // while the suite reads as if both applied (a bad-input audit).
        for (const config::Override& o : scene.overrides) {
          if (config::IsKeyInside(key, o.key) || config::IsKeyInside(o.key, key)) {
            set->Key(it->first).Fail(
                fmt::format("keys set once, none inside another ({} is "
                            "set too)",
                            o.key));
          }
        }
        scene.overrides.push_back({key, FlowText(it->second)});
      }
    }
    if (item.Has("seed")) {
      scene.overrides.push_back({"seed", std::to_string(item.Seed("seed", std::nullopt))});
      override_at.push_back(item.Child("seed").Where());
    }
    if (item.Has("seeds"))
      scene.seeds = static_cast<int>(item.Integer("seeds", 0, kMinSuiteSeeds, kMaxSuiteSeeds));
    item.Finish();
    // Validate now, so a bad override is reported before anything runs.
    uint64_t scene_seed = 0;
    try {
      const Scenario scenario = LoadScenarioFile(scene.scenario_path, scene.overrides);
      scene_seed = scenario.seed;
      scene.rendered = scenario.observation.source == scenarios::ObservationSource::kRendered;
    } catch (const InputError& e) {
      // A bad-input audit: "suite.yaml: scene "a": --set tracker.particle=5: ..."
      // named no line. An error in a `set:` value is reported where that
      // value is written; one in the scenario file where it is, naming the
      // scene.
      const std::string in_scene =
          fmt::format("in the suite's scene \"{}\" ({}:{}:{})", scene.name, item.Where().file,
                      item.Where().line, item.Where().column);
      const std::string hint = e.hint().empty() ? in_scene : e.hint() + "; " + in_scene;
      const int i = e.where().override_index;
      if (i >= 0 && static_cast<size_t>(i) < override_at.size()) {
        const SourceLocation& at = override_at[static_cast<size_t>(i)];
        throw InputError(SourceLocation{at.file, at.line, at.column, e.where().key}, e.expected(),
                         e.found(), hint);
      }
      throw InputError(e.where(), e.expected(), e.found(), hint);
    }
    for (int i = 0; i < scene.seeds; ++i) scene.run_seeds.push_back(SweepSeed(scene_seed, i));
    suite.scenes.push_back(std::move(scene));
  }
  if (suite.scenes.empty()) r.Child("scenes").Fail("a non-empty list of scenes");
  YamlReader metrics = r.Child("metrics");
  metrics.ExpectMap();
  // The key nodes as written (their marks locate a misspelt metric; a node
  // made from the key's text had none: a bad-input audit).
  std::vector<YAML::Node> keys;
  for (auto it = metrics.node().begin(); it != metrics.node().end(); ++it)
    keys.push_back(it->first);
  const auto& known = MetricNames();
  for (const YAML::Node& key_node : keys) {
    const std::string key = key_node.Scalar();
    YamlReader m = metrics.Child(key);
    if (std::find(known.begin(), known.end(), key) == known.end()) {
      const std::string close = ClosestMatch(key, known);
      metrics.Key(key_node).Fail(fmt::format("a metric name ({})", fmt::join(known, ", ")),
                                 close.empty() ? "" : "did you mean \"" + close + "\"?");
    }
    m.ExpectMap();
    RegressTolerance t;
    t.metric = key;
    t.tolerance = m.Number("tolerance", std::nullopt, 0.0, kMaxTolerance);
    // The direction is the catalogue's; a suite may state it, but not the
    // opposite of it.
    const bool higher = FindMetric(key)->higher_is_better;
    const std::string direction = higher ? "higher_is_better" : "lower_is_better";
    if (m.Enum("direction", direction, {"higher_is_better", "lower_is_better"}) != direction) {
      m.Child("direction").Fail(direction + " (the metric catalogue's direction of " + key + ")");
    }
    t.higher_is_better = higher;
    m.Finish();
    suite.metrics.push_back(t);
  }
  if (suite.metrics.empty()) metrics.Fail("a mapping of metric names to {tolerance, direction}");
  r.Finish();
  return suite;
}

const char* RegressVerdictName(RegressVerdict verdict) {
  switch (verdict) {
    case RegressVerdict::kSame:
      return "ok";
    case RegressVerdict::kBetter:
      return "better";
    case RegressVerdict::kWorse:
      return "WORSE";
  }
  return "?";
}

namespace {

// What rounding adds to a change of exactly the tolerance (0.9375 − 0.9575
// is −0.020000000000000018): a change "exceeds" the tolerance only beyond
// it, or a drop of exactly 0.02 was WORSE or not by the digits' luck (an
// audit: 204 of the 295 drops of 6/300).
double RoundingSlack(double baseline, double current) {
  return kRoundingRelative * std::max({1.0, std::abs(baseline), std::abs(current)});
}

}  // namespace

RegressVerdict CompareMetric(double baseline, double current, const RegressTolerance& t) {
  const bool b_nan = !std::isfinite(baseline), c_nan = !std::isfinite(current);
  if (b_nan || c_nan) return b_nan && c_nan ? RegressVerdict::kSame : RegressVerdict::kWorse;
  const double gain = t.higher_is_better ? current - baseline : baseline - current;
  const double allowed = t.tolerance + RoundingSlack(baseline, current);
  if (gain < -allowed) return RegressVerdict::kWorse;
  if (gain > allowed) return RegressVerdict::kBetter;
  return RegressVerdict::kSame;
}

RegressRow CompareSeeds(std::span<const double> baseline, std::span<const double> current,
                        const RegressTolerance& t) {
  HCPF_CHECK(baseline.size() == current.size()) << baseline.size() << " vs " << current.size();
  RegressRow row;
  row.metric = t.metric;
  row.tolerance = t.tolerance;
  row.higher_is_better = t.higher_is_better;
  row.seeds = static_cast<int>(baseline.size());
  for (size_t i = 0; i < baseline.size(); ++i)
    row.nan_mismatches += std::isfinite(baseline[i]) != std::isfinite(current[i]);
  // The paired difference current − baseline (statistics.h: pairs with a NaN
  // are left out; the interval is cut to the range of a difference).
  const CatalogueMetric* metric = FindMetric(t.metric);
  const PairedComparison c = ComparePaired(
      current, baseline, metric != nullptr ? metric->range : MetricRange::Unbounded());
  row.pairs = c.pairs;
  std::vector<double> b, v;
  for (size_t i = 0; i < baseline.size(); ++i) {
    if (!std::isfinite(baseline[i]) || !std::isfinite(current[i])) continue;
    b.push_back(baseline[i]);
    v.push_back(current[i]);
  }
  row.baseline = Mean(b);
  row.current = Mean(v);
  if (b.empty()) {
    // No seed has both: each side's own mean, so the table shows what the
    // current run measured (an audit of valid input: a hijack rate of NaN
    // on every baseline seed and 1, 1, 0 now read "nan nan" beside WORSE).
    row.baseline = Mean(Finite(baseline));
    row.current = Mean(Finite(current));
  }
  row.difference = c.difference.mean;
  row.lower = c.difference.lower;
  row.upper = c.difference.upper;
  if (row.nan_mismatches > 0) {
    row.verdict = RegressVerdict::kWorse;
  } else if (row.pairs == 0) {
    row.verdict = RegressVerdict::kSame;
  } else if (row.pairs == 1) {
    row.verdict = CompareMetric(b[0], v[0], t);
  } else {
    // The gain (positive = better) and its interval.
    const double sign = t.higher_is_better ? 1.0 : -1.0;
    const double gain = sign * row.difference;
    const double gain_lower = t.higher_is_better ? row.lower : -row.upper;
    const double gain_upper = t.higher_is_better ? row.upper : -row.lower;
    const double allowed = t.tolerance + RoundingSlack(row.baseline, row.current);
    if (gain < -allowed && gain_upper < 0.0) {
      row.verdict = RegressVerdict::kWorse;
    } else if (gain > allowed && gain_lower > 0.0) {
      row.verdict = RegressVerdict::kBetter;
    } else {
      row.verdict = RegressVerdict::kSame;
    }
  }
  return row;
}

void RegressOptions::Validate() const {
  if (suite_path.empty())
    throw InputError(SourceLocation{"hcpf regress", 0, 0, "SUITE"}, "a suite file", "nothing");
  if (baseline_path.empty()) {
    throw InputError(SourceLocation{"hcpf regress", 0, 0, "--baseline"}, "a baseline JSON path",
                     "nothing");
  }
  if (jobs < 1)
    throw InputError(SourceLocation{"hcpf regress", 0, 0, "--jobs"}, "an integer >= 1",
                     std::to_string(jobs));
}

namespace {

// The row's change current − baseline: the value difference, or the seeds'
// mean paired difference.
double Delta(const RegressRow& r) { return r.seeds > 0 ? r.difference : r.current - r.baseline; }

// "[lower, upper]" of a seeded row with an interval; `none` otherwise.
std::string IntervalText(const RegressRow& r, const char* none) {
  if (r.seeds == 0 || r.pairs < 2) return none;
  return fmt::format("[{}, {}]", Number(r.lower), Number(r.upper));
}

std::string SeedsText(const RegressRow& r) {
  if (r.seeds == 0) return "1";
  return r.pairs == r.seeds ? std::to_string(r.seeds) : fmt::format("{}/{}", r.pairs, r.seeds);
}

// One sentence saying what was compared and how it came out.
std::string Describe(const RegressRow& r) {
  const std::string rule = fmt::format(
      "{} is better, tolerance {}", r.higher_is_better ? "higher" : "lower", Number(r.tolerance));
  if (r.seeds == 0) {
    return fmt::format("{} {}: {} against baseline {} ({})", r.scene, r.metric, Number(r.current),
                       Number(r.baseline), rule);
  }
  std::string out = fmt::format(
      "{} {}: mean paired difference {} (current − baseline), 95 % interval {}, over {} of {} "
      "seeds; current mean {} against baseline mean {} ({})",
      r.scene, r.metric, Number(r.difference), IntervalText(r, "none (fewer than 2 pairs)"),
      r.pairs, r.seeds, Number(r.current), Number(r.baseline), rule);
  if (r.nan_mismatches > 0)
    out += fmt::format("; {} seed(s) with a number on one side and NaN on the other",
                       r.nan_mismatches);
  return out;
}

}  // namespace

std::string FormatRegressTable(const std::vector<RegressRow>& rows) {
  size_t w = 5, wi = 12;
  for (const RegressRow& r : rows) {
    w = std::max(w, r.scene.size());
    wi = std::max(wi, IntervalText(r, "-").size());
  }
  std::string out = fmt::format(
      "{:<{}}  {:<17}  {:>10}  {:>10}  {:>10}  {:<{}}  {:>5}  {:>9}  {}\n", "scene", w, "metric",
      "baseline", "current", "delta", "95% interval", wi, "seeds", "tolerance", "verdict");
  for (const RegressRow& r : rows) {
    out += fmt::format("{:<{}}  {:<17}  {:>10}  {:>10}  {:>10}  {:<{}}  {:>5}  {:>9}  {}\n",
                       r.scene, w, r.metric, Number(r.baseline), Number(r.current),
                       Number(Delta(r)), IntervalText(r, "-"), wi, SeedsText(r),
                       fmt::format("{}{}", r.higher_is_better ? "-" : "+", Number(r.tolerance)),
                       RegressVerdictName(r.verdict));
  }
  return out;
}

std::string FormatRegressJunit(const std::vector<RegressRow>& rows) {
  int failures = 0;
  for (const RegressRow& r : rows) failures += r.verdict == RegressVerdict::kWorse;
  std::string out = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  out += fmt::format(
      "<testsuites name=\"hcpf regress\" tests=\"{0}\" failures=\"{1}\">\n"
      "  <testsuite name=\"hcpf regress\" tests=\"{0}\" failures=\"{1}\" errors=\"0\">\n",
      rows.size(), failures);
  for (const RegressRow& r : rows) {
    out += fmt::format("    <testcase classname=\"{}\" name=\"{}\"", EscapeMarkup(r.scene),
                       EscapeMarkup(r.metric));
    const bool worse = r.verdict == RegressVerdict::kWorse;
    if (!worse && r.seeds == 0) {
      out += "/>\n";
      continue;
    }
    out += ">\n";
    const std::string message = EscapeMarkup(Describe(r));
    if (worse) out += fmt::format("      <failure message=\"{0}\">{0}</failure>\n", message);
    // Seeded cases say their difference, interval and seeds whatever the verdict.
    if (r.seeds > 0) out += fmt::format("      <system-out>{}</system-out>\n", message);
    out += "    </testcase>\n";
  }
  out += "  </testsuite>\n</testsuites>\n";
  return out;
}

std::string FormatRegressMarkdown(const RegressResult& result) {
  std::string out = "## hcpf regress\n\n";
  if (result.worse > 0) {
    out +=
        fmt::format("**{} metric(s) worse than the baseline beyond tolerance.**\n\n", result.worse);
  } else if (result.better > 0) {
    out += fmt::format(
        "No regression; {} metric(s) better than the baseline: refresh it with "
        "`--update-baseline`.\n\n",
        result.better);
  } else {
    out += "No regression: every metric within tolerance of the baseline.\n\n";
  }
  const bool seeded = std::any_of(result.rows.begin(), result.rows.end(),
                                  [](const RegressRow& r) { return r.seeds > 0; });
  if (seeded) {
    out +=
        "Scenes run with several seeds show the means over the seeds and the mean paired "
        "difference current − baseline with its 95 % t interval: such a metric is WORSE only "
        "when the difference is beyond the tolerance and the interval excludes zero.\n\n";
  }
  out +=
      "| scene | metric | baseline | current | delta | 95 % interval | seeds | tolerance | verdict "
      "|\n|---|---|---:|---:|---:|---|---:|---:|---|\n";
  for (const RegressRow& r : result.rows) {
    out += fmt::format(
        "| {} | {} | {} | {} | {} | {} | {} | {}{} | {} |\n", r.scene, r.metric, Number(r.baseline),
        Number(r.current), Number(Delta(r)), IntervalText(r, "—"), SeedsText(r),
        r.higher_is_better ? "−" : "+", Number(r.tolerance),
        r.verdict == RegressVerdict::kWorse ? "**WORSE**" : RegressVerdictName(r.verdict));
  }
  return out;
}

namespace {

constexpr const char* kBaselineFormat = "hcpf-regress-baseline/2";
// A baseline of 1,000 seeded scenes of every metric is a few MB.
constexpr uint64_t kMaxBaselineBytes = uint64_t{256} << 20;

// A baseline value: a number, or the string "nan" (how NaN is written).
bool IsBaselineValue(const json& j) { return j.is_number() || j == json("nan"); }

// Refuses a key of `object` (at dotted key `at`) that is not one of `known`:
// a misspelt "config_hash" was ignored, and the hash check with it.
void CheckKeys(const json& object, const std::string& path, const std::string& at,
               const std::vector<std::string>& known) {
  for (auto it = object.begin(); it != object.end(); ++it) {
    if (std::find(known.begin(), known.end(), it.key()) != known.end()) continue;
    const std::string close = ClosestMatch(it.key(), known);
    throw InputError(SourceLocation{path, 0, 0, at.empty() ? it.key() : at + "." + it.key()},
                     fmt::format("one of the keys {}", fmt::join(known, ", ")),
                     fmt::format("\"{}\"", it.key()),
                     close.empty() ? "" : "did you mean \"" + close + "\"?");
  }
}

// Checks the form of every scene of `baseline` (parsed from `path`), whether
// or not the suite compares it: known keys, hashes as strings, metric names
// of the catalogue and values a number ("nan") in the metric's range, or a
// list of them.
void CheckBaselineForm(const json& baseline, const std::string& path) {
  if (!baseline.is_object() || !baseline.contains("scenes") || !baseline["scenes"].is_object()) {
    // What was there instead (a bad-input audit: "found something else").
    const auto kind = [](const json& j) -> std::string {
      switch (j.type()) {
        case json::value_t::object:
          return "an object";
        case json::value_t::array:
          return j.empty() ? "an empty list" : "a list";
        case json::value_t::string:
          return "a string";
        case json::value_t::null:
          return "null";
        case json::value_t::boolean:
          return "a boolean";
        default:
          return "a number";
      }
    };
    throw InputError(SourceLocation{path, 0, 0, "scenes"},
                     "an object {\"scenes\": {name: {\"metrics\": {...}}}}",
                     !baseline.is_object() ? kind(baseline)
                     : !baseline.contains("scenes")
                         ? std::string("an object without \"scenes\"")
                         : "\"scenes\" holding " + kind(baseline["scenes"]));
  }
  CheckKeys(baseline, path, "", {"format", "suite", "scenes"});
  if (baseline.contains("format")) {
    const json& format = baseline["format"];
    if (format != json("hcpf-regress-baseline/1") && format != json(kBaselineFormat)) {
      throw InputError(SourceLocation{path, 0, 0, "format"},
                       fmt::format("hcpf-regress-baseline/1 or {}", kBaselineFormat),
                       format.dump());
    }
  }
  if (baseline.contains("suite") && !baseline["suite"].is_string()) {
    throw InputError(SourceLocation{path, 0, 0, "suite"}, "the suite's file name (a string)",
                     baseline["suite"].dump());
  }
  for (auto scene = baseline["scenes"].begin(); scene != baseline["scenes"].end(); ++scene) {
    const std::string at = "scenes." + scene.key();
    if (!scene->is_object()) {
      throw InputError(SourceLocation{path, 0, 0, at}, "an object {\"metrics\": {...}}",
                       scene->dump());
    }
    // Format 1 holds exact scenes only (seeded scenes came with format 2):
    // a seeded scene in it is another format's (a fourth bad-input audit).
    const bool exact_only =
        baseline.contains("format") && baseline["format"] == json("hcpf-regress-baseline/1");
    CheckKeys(*scene, path, at,
              exact_only
                  ? std::vector<std::string>{"config_hash", "metrics"}
                  : std::vector<std::string>{"config_hash", "config_hashes", "seeds", "metrics"});
    if (scene->contains("config_hash") && !(*scene)["config_hash"].is_string()) {
      throw InputError(SourceLocation{path, 0, 0, at + ".config_hash"},
                       "a configuration hash (a string)", (*scene)["config_hash"].dump());
    }
    for (const char* list : {"config_hashes", "seeds"}) {
      if (!scene->contains(list)) continue;
      const json& v = (*scene)[list];
      if (!v.is_array() ||
          !std::all_of(v.begin(), v.end(), [](const json& item) { return item.is_string(); })) {
        throw InputError(SourceLocation{path, 0, 0, at + "." + list},
                         "a list of strings, one per seed", v.dump());
      }
    }
    if (!scene->contains("metrics")) continue;  // reported below if the suite runs it
    const json& metrics = (*scene)["metrics"];
    if (!metrics.is_object()) continue;
    CheckKeys(metrics, path, at + ".metrics", MetricNames());
    for (auto m = metrics.begin(); m != metrics.end(); ++m) {
      const MetricRange range = FindMetric(m.key())->range;
      const auto in_range = [&](const json& v) {
        if (!IsBaselineValue(v)) return false;
        const double x = FromJson(v);
        return std::isnan(x) || (x >= range.lower && x <= range.upper);
      };
      const bool ok = m->is_array() ? std::all_of(m->begin(), m->end(), in_range) : in_range(*m);
      if (!ok) {
        throw InputError(SourceLocation{path, 0, 0, at + ".metrics." + m.key()},
                         fmt::format("a number in [{}, {}] (or \"nan\"), or a list of them, one "
                                     "per seed",
                                     range.lower, range.upper),
                         m->dump());
      }
    }
  }
}

// Checks that `baseline` (parsed from `path`) holds what `suite` compares:
// for an exact scene a value per metric, for a seeded one the suite's seeds
// and a list of one value per seed for each metric.
void CheckBaseline(const json& baseline, const std::string& path, const RegressSuite& suite) {
  CheckBaselineForm(baseline, path);
  const std::string refresh = "refresh the baseline with --update-baseline";
  const json& scenes = baseline["scenes"];
  for (const RegressScene& scene : suite.scenes) {
    const std::string at = "scenes." + scene.name;
    if (!scenes.contains(scene.name) || !scenes[scene.name].is_object() ||
        !scenes[scene.name].contains("metrics") || !scenes[scene.name]["metrics"].is_object()) {
      throw InputError(SourceLocation{path, 0, 0, at + ".metrics"},
                       "a baseline value for every scene and metric of the suite", "none", refresh);
    }
    const json& s = scenes[scene.name];
    if (scene.seeds > 0) {
      std::vector<std::string> seeds;
      for (uint64_t seed : scene.run_seeds) seeds.push_back(std::to_string(seed));
      if (!s.contains("seeds") || s["seeds"] != json(seeds)) {
        throw InputError(
            SourceLocation{path, 0, 0, at + ".seeds"},
            fmt::format("the scene's {} derived seeds [{}]", scene.seeds, fmt::join(seeds, ", ")),
            s.contains("seeds") ? s["seeds"].dump() : "none (a baseline made without seeds:)",
            refresh);
      }
    } else if (s.contains("seeds")) {
      throw InputError(SourceLocation{path, 0, 0, at + ".seeds"},
                       "no seeds (the suite runs this scene once)", s["seeds"].dump(), refresh);
    }
    for (const RegressTolerance& t : suite.metrics) {
      const std::string key = at + ".metrics." + t.metric;
      if (!s["metrics"].contains(t.metric)) {
        throw InputError(SourceLocation{path, 0, 0, key},
                         "a baseline value for every scene and metric of the suite", "none",
                         refresh);
      }
      const json& v = s["metrics"][t.metric];
      const bool ok = scene.seeds > 0 ? v.is_array() && static_cast<int>(v.size()) == scene.seeds &&
                                            std::all_of(v.begin(), v.end(), IsBaselineValue)
                                      : IsBaselineValue(v);
      if (!ok) {
        throw InputError(SourceLocation{path, 0, 0, key},
                         scene.seeds > 0 ? fmt::format("a list of {} numbers (or \"nan\"), one "
                                                       "per seed",
                                                       scene.seeds)
                                         : "a number (or \"nan\")",
                         v.dump(), refresh);
      }
    }
  }
}

// One run of the suite: scene `scene`, seed index `seed` (0 for exact scenes).
struct SceneRun {
  size_t scene = 0;
  int seed = 0;
};

}  // namespace

namespace {

// The files regress writes (the baseline with --update-baseline, --junit,
// --markdown) and its --work folder, checked before anything runs: each
// output is a file in an existing folder, none is a file regress reads (the
// suite, a scene's scenario, the baseline it compares with) or another
// output. A bad-input audit found --junit naming the baseline replace it,
// and a missing folder fail with exit 1 after the whole suite had run.
void CheckOutputs(const RegressOptions& o, const RegressSuite& suite) {
  std::error_code ec;
  std::vector<FileRead> reads = {{suite.file, "the suite"}};
  if (!o.update_baseline) reads.push_back({o.baseline_path, "the baseline it compares with"});
  for (const RegressScene& scene : suite.scenes) {
    reads.push_back({scene.scenario_path, fmt::format("the scenario of scene \"{}\"", scene.name)});
  }
  std::vector<FileToWrite> writes;
  if (o.update_baseline) writes.push_back({o.baseline_path, "--baseline"});
  if (!o.junit_path.empty()) writes.push_back({o.junit_path, "--junit"});
  if (!o.markdown_path.empty()) writes.push_back({o.markdown_path, "--markdown"});
  CheckFilesToWrite(writes, reads, {}, "regress", "nothing was run or written");
  if (o.work_dir.empty()) return;
  scenarios::CheckFolderArgument(o.work_dir, "--work");
  // Each scene's run folder in --work must be one a run may replace: a
  // second bad-input audit found a folder of the user's there failing the
  // suite midway (exit 1) with an error that named --out.
  for (const RegressScene& scene : suite.scenes) {
    const fs::path dir = fs::path(o.work_dir) / scene.name;
    std::vector<fs::path> outs;
    if (scene.seeds > 0) {
      if (fs::exists(fs::symlink_status(dir, ec)) &&
          !fs::is_directory(fs::symlink_status(dir, ec))) {
        outs.push_back(dir);
      }
      for (int k = 0; k < scene.seeds; ++k) outs.push_back(dir / fmt::format("seed-{}", k));
    } else {
      outs.push_back(dir);
    }
    for (const fs::path& out : outs) {
      const std::string why = scenarios::WhyNotReplaceable(out);
      if (why.empty()) continue;
      throw InputError(
          SourceLocation{out.string(), 0, 0, "--work"},
          fmt::format("a folder for the run of scene \"{}\": new, empty, or an earlier "
                      "run's",
                      scene.name),
          why, "nothing was run; name another --work folder");
    }
  }
}

// The parser's input: the baseline's text, noting how far the parser has
// read (`*consumed`; a character past a number or literal, whose end it
// knows only then), so that a SAX handler knows where in the text it is (the
// JSON library gives positions only in its syntax errors).
class CountingIterator {
 public:
  using iterator_category = std::input_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;

  CountingIterator(const char* at, const char* begin, size_t* consumed)
      : at_(at), begin_(begin), consumed_(consumed) {}
  reference operator*() const { return *at_; }
  CountingIterator& operator++() {
    ++at_;
    *consumed_ = static_cast<size_t>(at_ - begin_);
    return *this;
  }
  CountingIterator operator++(int) {
    CountingIterator before = *this;
    ++*this;
    return before;
  }
  bool operator==(const CountingIterator& other) const { return at_ == other.at_; }

 private:
  const char* at_;
  const char* begin_;
  size_t* consumed_;
};

// A SAX handler (nlohmann::json::sax_parse) that notes where each key of a
// baseline begins, by its dotted name, and refuses a key twice in one object,
// as the suite's YAML refuses it (a bad-input audit: the JSON library keeps
// the last value, so "mota": 1.0, "mota": 0.2 compared with 0.2 without a
// word). A pass of its own before the plain parse that builds the document:
// the library's DOM parser with a callback walks an object's members at the
// end of each member object (to drop discarded values), which made a
// baseline of 20,000 scenes take 3.3 s, quadratic in the scenes. Offsets,
// not lines: counting lines from the start of the file for every key was
// quadratic too (a review); lines are worked out for an error only.
class BaselineKeys {
 public:
  BaselineKeys(const std::string& path, const std::string& text, const size_t& consumed)
      : path_(path), text_(text), consumed_(consumed) {}

  // Dotted key -> the offset of its opening quote.
  const std::map<std::string, size_t>& where() const { return where_; }
  // After a syntax error: its offset and the library's words.
  size_t error_byte() const { return error_byte_; }
  const std::string& error() const { return error_; }
  // Whether the error is a number too large for a double (1e999), not a
  // syntax error.
  bool number_out_of_range() const { return number_out_of_range_; }

  bool null() { return Value(); }
  bool boolean(bool) { return Value(); }
  bool number_integer(json::number_integer_t) { return Value(); }
  bool number_unsigned(json::number_unsigned_t) { return Value(); }
  bool number_float(json::number_float_t, const std::string&) { return Value(); }
  bool string(json::string_t&) { return Value(); }
  bool binary(json::binary_t&) { return Value(); }
  bool start_object(std::size_t) { return Open(true); }
  bool start_array(std::size_t) { return Open(false); }
  bool end_object() { return Close(); }
  bool end_array() { return Close(); }
  bool key(json::string_t& key) {
    const size_t at = KeyStart();
    if (!open_.back().keys.insert(key).second) {
      const TextPosition second = PositionOf(text_, at);
      throw InputError(SourceLocation{path_, second.line, second.column, Dotted(key)},
                       "each key once in its object", fmt::format("\"{}\" a second time", key));
    }
    open_.back().key = key;
    where_.emplace(Dotted(key), at);
    return true;
  }
  bool parse_error(std::size_t byte, const std::string&, const json::exception& e) {
    error_byte_ = byte;
    // The library's words without its "[json.exception.KIND.ID] " prefix.
    error_ = e.what();
    if (const size_t end = error_.find("] "); error_.starts_with("[json.") && end != error_.npos) {
      error_ = error_.substr(end + 2);
    }
    number_out_of_range_ = e.id == 406;
    return false;
  }

 private:
  static constexpr size_t kMaxDepth = 64;
  struct Level {
    bool object = false;
    std::set<std::string> keys;
    std::string key;
    int index = -1;
  };
  bool Value() {
    if (!open_.empty() && !open_.back().object) ++open_.back().index;
    return true;
  }
  bool Open(bool object) {
    Value();
    // A baseline is four levels deep; the dotted names of keys nested
    // thousands deep are long and many (a crafted 240 KB file took 20 s and
    // 1.9 GB: a review).
    if (open_.size() >= kMaxDepth) {
      const TextPosition at = PositionOf(text_, consumed_ > 0 ? consumed_ - 1 : 0);
      throw InputError(SourceLocation{path_, at.line, at.column, Dotted("")},
                       fmt::format("a baseline JSON file nested at most {} levels deep", kMaxDepth),
                       "a list or object nested deeper");
    }
    open_.push_back({.object = object});
    return true;
  }
  bool Close() {
    open_.pop_back();
    return true;
  }
  // The dotted key of `last` in the innermost container open (the
  // container itself when `last` is empty).
  std::string Dotted(const std::string& last) const {
    std::string at;
    for (const Level& o : open_) {
      if (&o == &open_.back()) break;
      at += o.object ? (at.empty() ? "" : ".") + o.key : fmt::format("[{}]", o.index);
    }
    if (last.empty()) return at;
    return at.empty() ? last : at + "." + last;
  }
  // Where the key the parser has just read begins: its opening quote, the
  // first unescaped one before its closing quote, the last character read.
  // Backslashes are counted only before a quote, so each is counted once (a
  // key of 500 KB of backslashes took 100 s: a review).
  size_t KeyStart() const {
    size_t at = std::min(consumed_, text_.size());
    if (at > 0) --at;  // the closing quote
    while (at > 0) {
      --at;
      if (text_[at] != '"') continue;
      size_t backslashes = 0;
      while (backslashes < at && text_[at - 1 - backslashes] == '\\') ++backslashes;
      if (backslashes % 2 == 0) break;
    }
    return at;
  }

  const std::string& path_;
  const std::string& text_;
  const size_t& consumed_;
  std::vector<Level> open_;
  std::map<std::string, size_t> where_;
  size_t error_byte_ = 0;
  std::string error_;
  bool number_out_of_range_ = false;
};

// Reads and checks the baseline file `path` against `suite`. Every error
// names the line and column of its key (or of the nearest key above it that
// the file has; a bad-input audit: value errors named the key but no line).
json ReadBaseline(const std::string& path, const RegressSuite& suite) {
  const std::string text = ReadInputFile(path, "a baseline JSON file", kMaxBaselineBytes);
  // The JSON library stops at a NUL byte as at the end of the text: what
  // follows it would go unread (a review).
  if (const size_t nul = text.find('\0'); nul != std::string::npos) {
    const TextPosition at = PositionOf(text, nul);
    throw InputError(SourceLocation{path, at.line, at.column, ""}, "a baseline JSON file",
                     "a NUL byte");
  }
  size_t consumed = 0;
  BaselineKeys keys(path, text, consumed);
  if (!json::sax_parse(CountingIterator(text.data(), text.data(), &consumed),
                       CountingIterator(text.data() + text.size(), text.data(), &consumed),
                       &keys)) {
    // At the file's line and column, with the parser's words after its own
    // position (a bad-input audit: both were inside the library's text).
    const TextPosition at = PositionOf(text, keys.error_byte() > 0 ? keys.error_byte() - 1 : 0);
    std::string why = keys.error();
    if (const size_t column = why.find("column"); column != std::string::npos) {
      if (const size_t colon = why.find(": ", column); colon != std::string::npos) {
        why = why.substr(colon + 2);
      }
    }
    throw InputError(SourceLocation{path, at.line, at.column, ""}, "a baseline JSON file",
                     keys.number_out_of_range() ? "a number out of range (" + why + ")"
                                                : "a JSON syntax error (" + why + ")");
  }
  const std::map<std::string, size_t>& where = keys.where();
  // The text the SAX pass accepted: the same parser accepts it here.
  const json baseline = json::parse(text);
  try {
    CheckBaseline(baseline, path, suite);
  } catch (const InputError& e) {
    if (e.where().line > 0) throw;
    // The key, or the nearest key above it that the file has (a value the
    // suite asks for and the file lacks: its scene's or its "metrics").
    std::string key = e.where().key;
    auto found = where.find(key);
    while (found == where.end() && !key.empty()) {
      const size_t cut = key.find_last_of(".[");
      key = cut == std::string::npos ? std::string() : key.substr(0, cut);
      found = where.find(key);
    }
    if (found == where.end()) throw;
    const TextPosition at = PositionOf(text, found->second);
    throw InputError(SourceLocation{path, at.line, at.column, e.where().key}, e.expected(),
                     e.found(), e.hint());
  }
  return baseline;
}

}  // namespace

fs::path RegressOptions::RunsFolder() const {
  if (!work_dir.empty()) return work_dir;
  std::error_code ec;
  fs::path temp = fs::temp_directory_path(ec);
  if (ec) temp = "/tmp";
  return temp / fmt::format("hcpf-regress.partial-{}", ::getpid());
}

RegressResult RunRegress(const RegressOptions& options) {
  options.Validate();
  const RegressSuite suite = LoadRegressSuite(options.suite_path);
  CheckOutputs(options, suite);

  json baseline;
  if (!options.update_baseline) {
    std::error_code exists_ec;
    if (!fs::exists(options.baseline_path, exists_ec)) {
      throw InputError(SourceLocation{options.baseline_path, 0, 0, "--baseline"},
                       "a baseline JSON file", "no such file", "create it with --update-baseline");
    }
    baseline = ReadBaseline(options.baseline_path, suite);
  }

  const bool temporary = options.work_dir.empty();
  const fs::path work = options.RunsFolder();
  std::error_code ec;
  // The temporary folders of regress runs that were killed (SIGKILL, or a
  // signal they announced: cli/src/cmd_regress.cc).
  if (temporary) scenarios::RemoveStaleStagingFolders(work.parent_path(), "hcpf-regress");
  fs::create_directories(work, ec);
  if (ec) throw RunError(fmt::format("cannot create {}: {}", work.string(), ec.message()));

  // Every (scene, seed) run, in a small pool; each run is self-contained and
  // deterministic, so the order they finish in does not matter.
  std::vector<SceneRun> runs;
  for (size_t i = 0; i < suite.scenes.size(); ++i) {
    for (int k = 0; k < std::max(1, suite.scenes[i].seeds); ++k) runs.push_back({i, k});
  }
  std::vector<std::map<std::string, double>> values(runs.size());
  std::vector<std::string> hashes(runs.size());
  std::vector<std::string> errors(runs.size());
  // Several rendered runs at once: each in a child process (render_exe), so
  // that they render side by side. Its input and log files go beside its run
  // folder (DIR/a.input.yaml, DIR/b/seed-1.input.yaml), as its staging folder
  // does (DIR/a.partial-<pid>).
  const bool any_rendered = std::any_of(suite.scenes.begin(), suite.scenes.end(),
                                        [](const RegressScene& scene) { return scene.rendered; });
  std::unique_ptr<ChildProcessExecutor> child;
  if (!options.render_exe.empty() && options.jobs > 1 && any_rendered) {
    child = std::make_unique<ChildProcessExecutor>(options.render_exe, work.string());
    spdlog::info(
        "regress: each rendered run in a process of its own (--jobs {}), so that they render "
        "side by side (docs/sweeps.md)",
        options.jobs);
  }
  ParallelFor(runs.size(), options.jobs, [&](size_t i) {
    const RegressScene& scene = suite.scenes[runs[i].scene];
    try {
      std::vector<config::Override> overrides = scene.overrides;
      fs::path out_dir = work / scene.name;
      if (scene.seeds > 0) {
        std::erase_if(overrides, [](const config::Override& o) { return o.key == "seed"; });
        overrides.push_back(
            {"seed", std::to_string(scene.run_seeds[static_cast<size_t>(runs[i].seed)])});
        out_dir /= fmt::format("seed-{}", runs[i].seed);
      }
      const Scenario scenario = LoadScenarioFile(scene.scenario_path, overrides);
      hashes[i] = ConfigHash(scenario);
      RunOptions run_options;
      run_options.out_dir = out_dir.string();
      if (child && scene.rendered) {
        child->ExecuteScenario(scenario, out_dir.string(), run_options);
      } else {
        RunScenario(scenario, run_options);
      }
      values[i] = ReadRunMetrics(run_options.out_dir);
    } catch (const std::exception& e) {
      errors[i] = e.what();
    }
  });
  if (temporary) fs::remove_all(work, ec);
  if (options.runs_done) options.runs_done();
  for (size_t i = 0; i < runs.size(); ++i) {
    if (errors[i].empty()) continue;
    const RegressScene& scene = suite.scenes[runs[i].scene];
    // A child's log was kept in the run folders, which a temporary one took.
    const bool log_removed = child && scene.rendered && temporary;
    throw RunError(fmt::format(
        "scene \"{}\"{} failed: {}{}", scene.name,
        scene.seeds > 0 ? fmt::format(" (seed {})", runs[i].seed) : "", errors[i],
        log_removed ? " (its log went with the temporary run folder; --work DIR keeps it)" : ""));
  }
  // The runs of scene i: first[i] .. first[i] + max(1, seeds) − 1.
  std::vector<size_t> first(suite.scenes.size());
  for (size_t i = runs.size(); i-- > 0;) first[runs[i].scene] = i;

  RegressResult result;
  if (options.update_baseline) {
    json out;
    out["format"] = kBaselineFormat;
    out["suite"] = fs::path(suite.file).filename().string();
    out["scenes"] = json::object();
    for (size_t i = 0; i < suite.scenes.size(); ++i) {
      const RegressScene& scene = suite.scenes[i];
      json m = json::object();
      if (scene.seeds == 0) {
        for (const RegressTolerance& t : suite.metrics)
          m[t.metric] = JsonNumber(values[first[i]].at(t.metric));
        out["scenes"][scene.name] = {{"config_hash", hashes[first[i]]}, {"metrics", m}};
        continue;
      }
      json seeds = json::array(), config_hashes = json::array();
      for (int k = 0; k < scene.seeds; ++k) {
        seeds.push_back(std::to_string(scene.run_seeds[static_cast<size_t>(k)]));
        config_hashes.push_back(hashes[first[i] + static_cast<size_t>(k)]);
      }
      for (const RegressTolerance& t : suite.metrics) {
        json list = json::array();
        for (int k = 0; k < scene.seeds; ++k)
          list.push_back(JsonNumber(values[first[i] + static_cast<size_t>(k)].at(t.metric)));
        m[t.metric] = list;
      }
      out["scenes"][scene.name] = {
          {"seeds", seeds}, {"config_hashes", config_hashes}, {"metrics", m}};
    }
    WriteTextFile(options.baseline_path, out.dump(2) + "\n");
    result.baseline_written = true;
  }
  for (size_t i = 0; i < suite.scenes.size(); ++i) {
    const RegressScene& scene = suite.scenes[i];
    const int n = std::max(1, scene.seeds);
    if (!options.update_baseline) {
      const json& b = baseline["scenes"][scene.name];
      for (int k = 0; k < n; ++k) {
        const std::string& hash = hashes[first[i] + static_cast<size_t>(k)];
        std::string base_hash;
        if (scene.seeds == 0) {
          base_hash = b.value("config_hash", "");
        } else if (b.contains("config_hashes") && b["config_hashes"].is_array() &&
                   static_cast<int>(b["config_hashes"].size()) == n &&
                   b["config_hashes"][static_cast<size_t>(k)].is_string()) {
          base_hash = b["config_hashes"][static_cast<size_t>(k)].get<std::string>();
        }
        if (!base_hash.empty() && base_hash != hash) {
          spdlog::warn(
              "regress: scene \"{}\"{} resolves to config {} but the baseline was made from {}",
              scene.name, scene.seeds > 0 ? fmt::format(" (seed {})", k) : "", hash, base_hash);
        }
      }
    }
    for (const RegressTolerance& t : suite.metrics) {
      std::vector<double> current(static_cast<size_t>(n)), base(static_cast<size_t>(n));
      for (int k = 0; k < n; ++k) {
        const size_t run = first[i] + static_cast<size_t>(k);
        current[static_cast<size_t>(k)] = values[run].at(t.metric);
        if (options.update_baseline) {
          base[static_cast<size_t>(k)] = current[static_cast<size_t>(k)];
        } else {
          const json& v = baseline["scenes"][scene.name]["metrics"][t.metric];
          base[static_cast<size_t>(k)] = FromJson(scene.seeds > 0 ? v[static_cast<size_t>(k)] : v);
        }
      }
      RegressRow row;
      if (scene.seeds > 0) {
        row = CompareSeeds(base, current, t);
      } else {
        row.metric = t.metric;
        row.current = current[0];
        row.baseline = base[0];
        row.tolerance = t.tolerance;
        row.higher_is_better = t.higher_is_better;
        row.verdict = CompareMetric(row.baseline, row.current, t);
      }
      row.scene = scene.name;
      result.worse += row.verdict == RegressVerdict::kWorse;
      result.better += row.verdict == RegressVerdict::kBetter;
      result.rows.push_back(row);
    }
  }
  result.table = FormatRegressTable(result.rows);
  if (!options.junit_path.empty())
    WriteTextFile(options.junit_path, FormatRegressJunit(result.rows));
  if (!options.markdown_path.empty())
    WriteTextFile(options.markdown_path, FormatRegressMarkdown(result));
  return result;
}

}  // namespace hcpf::studies
