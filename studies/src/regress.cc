// `hcpf regress`: run golden scenes, compare their metrics with a baseline.

#include "hcpf/studies/regress.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <thread>

#include "hcpf/config/file_lookup.h"
#include "hcpf/config/yaml_reader.h"
#include "hcpf/core/parallel.h"
#include "hcpf/core/text_file.h"
#include "hcpf/scenarios/run.h"
#include "hcpf/studies/file_keys.h"
#include "hcpf/studies/metric_catalogue.h"
#include "hcpf/studies/results_store.h"
#include "hcpf/studies/sweep.h"
#include "text.h"

namespace hcpf::studies {

using scenarios::ConfigHash;
using scenarios::LoadScenarioFile;
using scenarios::RunOptions;
using scenarios::RunScenario;
using scenarios::Scenario;

using config::FindFile;
using config::FlowText;
using config::YamlContext;
using config::YamlReader;

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string ResolvePath(const YamlReader& where, const std::string& path, const std::string& dir) {
  if (auto found = FindFile(path, dir)) return *found;
  where.Fail(
      "a scenario file (looked next to the suite, in the current folder and in the project "
      "folder)");
}

std::string Num(double v) { return std::isfinite(v) ? fmt::format("{:.6g}", v) : "nan"; }

json JsonNumber(double v) { return std::isfinite(v) ? json(v) : json("nan"); }
double FromJson(const json& j) {
  return j.is_number() ? j.get<double>() : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

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
    scene.scenario_path = ResolvePath(scenario_node, item.String("scenario", std::nullopt), dir);
    scene.name = item.String("name", fs::path(scene.scenario_path).stem().string());
    if (!names.insert(scene.name).second)
      item.Child("name").Fail("a scene name used once in the suite");
    if (auto set = item.Optional("set")) {
      set->ExpectMap();
      for (auto it = set->node().begin(); it != set->node().end(); ++it) {
        const std::string key = it->first.Scalar();
        set->Child(key);  // mark as read
        scene.overrides.push_back({key, FlowText(it->second)});
      }
    }
    if (item.Has("seed"))
      scene.overrides.push_back({"seed", std::to_string(item.Seed("seed", std::nullopt))});
    item.Finish();
    // Validate now, so a bad override is reported before anything runs.
    try {
      LoadScenarioFile(scene.scenario_path, scene.overrides);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: scene \"{}\": {}", path, scene.name, e.what()));
    }
    suite.scenes.push_back(std::move(scene));
  }
  if (suite.scenes.empty()) r.Child("scenes").Fail("a non-empty list of scenes");
  YamlReader metrics = r.Child("metrics");
  metrics.ExpectMap();
  std::vector<std::string> keys;
  for (auto it = metrics.node().begin(); it != metrics.node().end(); ++it)
    keys.push_back(it->first.Scalar());
  const auto& known = MetricNames();
  for (const std::string& key : keys) {
    YamlReader m = metrics.Child(key);
    if (std::find(known.begin(), known.end(), key) == known.end()) {
      const std::string close = ClosestMatch(key, known);
      metrics.Key(YAML::Node(key))
          .Fail(fmt::format("a metric name ({})", fmt::join(known, ", ")),
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

RegressVerdict CompareMetric(double baseline, double current, const RegressTolerance& t) {
  const bool b_nan = !std::isfinite(baseline), c_nan = !std::isfinite(current);
  if (b_nan || c_nan) return b_nan && c_nan ? RegressVerdict::kSame : RegressVerdict::kWorse;
  const double gain = t.higher_is_better ? current - baseline : baseline - current;
  if (gain < -t.tolerance) return RegressVerdict::kWorse;
  if (gain > t.tolerance) return RegressVerdict::kBetter;
  return RegressVerdict::kSame;
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

std::string FormatRegressTable(const std::vector<RegressRow>& rows) {
  size_t w = 5;
  for (const RegressRow& r : rows) w = std::max(w, r.scene.size());
  std::string out = fmt::format("{:<{}}  {:<17}  {:>10}  {:>10}  {:>10}  {:>9}  {}\n", "scene", w,
                                "metric", "baseline", "current", "delta", "tolerance", "verdict");
  for (const RegressRow& r : rows) {
    out += fmt::format("{:<{}}  {:<17}  {:>10}  {:>10}  {:>10}  {:>9}  {}\n", r.scene, w, r.metric,
                       Num(r.baseline), Num(r.current), Num(r.current - r.baseline),
                       fmt::format("{}{}", r.higher_is_better ? "-" : "+", Num(r.tolerance)),
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
    if (r.verdict == RegressVerdict::kWorse) {
      const std::string message =
          fmt::format("{} {}: {} against baseline {} ({} is better, tolerance {})", r.scene,
                      r.metric, Num(r.current), Num(r.baseline),
                      r.higher_is_better ? "higher" : "lower", Num(r.tolerance));
      out += fmt::format(">\n      <failure message=\"{0}\">{0}</failure>\n    </testcase>\n",
                         EscapeMarkup(message));
    } else {
      out += "/>\n";
    }
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
  out +=
      "| scene | metric | baseline | current | delta | tolerance | verdict "
      "|\n|---|---|---:|---:|---:|---:|---|\n";
  for (const RegressRow& r : result.rows) {
    out += fmt::format(
        "| {} | {} | {} | {} | {} | {}{} | {} |\n", r.scene, r.metric, Num(r.baseline),
        Num(r.current), Num(r.current - r.baseline), r.higher_is_better ? "−" : "+",
        Num(r.tolerance),
        r.verdict == RegressVerdict::kWorse ? "**WORSE**" : RegressVerdictName(r.verdict));
  }
  return out;
}

RegressResult RunRegress(const RegressOptions& options) {
  options.Validate();
  const RegressSuite suite = LoadRegressSuite(options.suite_path);

  json baseline;
  if (!options.update_baseline) {
    std::ifstream in(options.baseline_path);
    if (!in) {
      throw InputError(SourceLocation{options.baseline_path, 0, 0, "--baseline"},
                       "a baseline JSON file", "no such file", "create it with --update-baseline");
    }
    try {
      baseline = json::parse(in);
    } catch (const json::exception& e) {
      throw InputError(SourceLocation{options.baseline_path, 0, 0, ""}, "a baseline JSON file",
                       e.what());
    }
    if (!baseline.is_object() || !baseline.contains("scenes") || !baseline["scenes"].is_object()) {
      throw InputError(SourceLocation{options.baseline_path, 0, 0, "scenes"},
                       "an object {\"scenes\": {name: {\"metrics\": {...}}}}", "something else");
    }
    for (const RegressScene& scene : suite.scenes) {
      for (const RegressTolerance& t : suite.metrics) {
        const json& s = baseline["scenes"];
        if (!s.contains(scene.name) || !s[scene.name].contains("metrics") ||
            !s[scene.name]["metrics"].contains(t.metric)) {
          throw InputError(SourceLocation{options.baseline_path, 0, 0,
                                          "scenes." + scene.name + ".metrics." + t.metric},
                           "a baseline value for every scene and metric of the suite", "none",
                           "refresh the baseline with --update-baseline");
        }
      }
    }
  }

  const bool temporary = options.work_dir.empty();
  const fs::path work = temporary
                            ? fs::temp_directory_path() / fmt::format("hcpf-regress-{}", ::getpid())
                            : fs::path(options.work_dir);
  std::error_code ec;
  fs::create_directories(work, ec);
  if (ec) throw RunError(fmt::format("cannot create {}: {}", work.string(), ec.message()));

  // Run the scenes (a small pool; each run is self-contained and deterministic).
  std::vector<std::map<std::string, double>> values(suite.scenes.size());
  std::vector<std::string> hashes(suite.scenes.size());
  std::vector<std::string> errors(suite.scenes.size());
  ParallelFor(suite.scenes.size(), options.jobs, [&](size_t i) {
    const RegressScene& scene = suite.scenes[i];
    try {
      const Scenario scenario = LoadScenarioFile(scene.scenario_path, scene.overrides);
      hashes[i] = ConfigHash(scenario);
      RunOptions run_options;
      run_options.out_dir = (work / scene.name).string();
      RunScenario(scenario, run_options);
      values[i] = ReadRunMetrics(run_options.out_dir);
    } catch (const std::exception& e) {
      errors[i] = e.what();
    }
  });
  if (temporary) fs::remove_all(work, ec);
  for (size_t i = 0; i < suite.scenes.size(); ++i) {
    if (!errors[i].empty())
      throw RunError(fmt::format("scene \"{}\" failed: {}", suite.scenes[i].name, errors[i]));
  }

  RegressResult result;
  if (options.update_baseline) {
    json out;
    out["format"] = "hcpf-regress-baseline/1";
    out["suite"] = fs::path(suite.file).filename().string();
    out["scenes"] = json::object();
    for (size_t i = 0; i < suite.scenes.size(); ++i) {
      json m = json::object();
      for (const RegressTolerance& t : suite.metrics)
        m[t.metric] = JsonNumber(values[i].at(t.metric));
      out["scenes"][suite.scenes[i].name] = {{"config_hash", hashes[i]}, {"metrics", m}};
    }
    WriteTextFile(options.baseline_path, out.dump(2) + "\n");
    result.baseline_written = true;
  }
  for (size_t i = 0; i < suite.scenes.size(); ++i) {
    const std::string& name = suite.scenes[i].name;
    if (!options.update_baseline) {
      const std::string base_hash = baseline["scenes"][name].value("config_hash", "");
      if (!base_hash.empty() && base_hash != hashes[i]) {
        spdlog::warn(
            "regress: scene \"{}\" resolves to config {} but the baseline was made from {}", name,
            hashes[i], base_hash);
      }
    }
    for (const RegressTolerance& t : suite.metrics) {
      RegressRow row;
      row.scene = name;
      row.metric = t.metric;
      row.current = values[i].at(t.metric);
      row.baseline = options.update_baseline
                         ? row.current
                         : FromJson(baseline["scenes"][name]["metrics"][t.metric]);
      row.tolerance = t.tolerance;
      row.higher_is_better = t.higher_is_better;
      row.verdict = CompareMetric(row.baseline, row.current, t);
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
