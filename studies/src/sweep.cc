// Sweep files: loading, validation and expansion into runs (docs/sweeps.md).

#include "hcpf/studies/sweep.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <set>

#include "hcpf/config/file_lookup.h"
#include "hcpf/config/overrides.h"
#include "hcpf/config/yaml_reader.h"
#include "hcpf/core/rng.h"
#include "hcpf/renderer/renderer.h"
#include "hcpf/scenarios/frames.h"
#include "hcpf/scenarios/output_folder.h"
#include "hcpf/scenarios/progress.h"
#include "hcpf/studies/file_keys.h"
#include "hcpf/studies/metric_catalogue.h"
#include "hcpf/studies/statistics.h"
#include "text.h"

namespace hcpf::studies {

using scenarios::ConfigHash;
using scenarios::LoadScenarioFile;

using config::FlowText;
using config::YamlContext;
using config::YamlReader;

namespace fs = std::filesystem;

std::optional<ReportRuleBreak> CheckReportRules(const ReportSpec& report,
                                                const std::vector<std::string>& swept) {
  const auto is_swept = [&](const std::string& key) {
    return std::find(swept.begin(), swept.end(), key) != swept.end();
  };
  const std::vector<std::string>& metrics = MetricNames();
  const auto is_metric = [&](const std::string& name) {
    return std::find(metrics.begin(), metrics.end(), name) != metrics.end();
  };
  const std::string swept_list = fmt::format("{}", fmt::join(swept, ", "));
  const std::string a_swept_key =
      swept.empty() ? "nothing (no key is swept)" : "a swept key (" + swept_list + ")";
  const std::string a_metric = fmt::format("a metric name ({})", fmt::join(metrics, ", "));
  if (!report.x.empty() && !is_swept(report.x))
    return ReportRuleBreak{"x", -1, report.x, a_swept_key};
  if (!report.series.empty() && !is_swept(report.series))
    return ReportRuleBreak{"series", -1, report.series, a_swept_key};
  if (!report.x_metric.empty() && !is_metric(report.x_metric))
    return ReportRuleBreak{"x_metric", -1, report.x_metric, a_metric};
  std::set<std::string> seen;
  for (size_t i = 0; i < report.y.size(); ++i) {
    if (!is_metric(report.y[i]))
      return ReportRuleBreak{"y", static_cast<int>(i), report.y[i], a_metric};
    // Listed twice, a metric was plotted twice (a second bad-input audit).
    if (!seen.insert(report.y[i]).second) {
      return ReportRuleBreak{"y", static_cast<int>(i), report.y[i],
                             "a metric listed once in report.y"};
    }
  }
  if (report.y.empty()) return ReportRuleBreak{"y", -1, "", "a non-empty list of metric names"};
  if (!report.series.empty() && report.series == report.x)
    return ReportRuleBreak{"series", -1, report.series, "a swept key other than report.x"};
  seen.clear();
  for (size_t i = 0; i < report.pool.size(); ++i) {
    const std::string& key = report.pool[i];
    if (!is_swept(key) || key == report.x || key == report.series || !seen.insert(key).second) {
      return ReportRuleBreak{
          "pool", static_cast<int>(i), key,
          "a swept key other than report.x and report.series, listed once (" + swept_list + ")"};
    }
  }
  if (!report.panels.empty()) {
    if (!is_swept(report.panels)) return ReportRuleBreak{"panels", -1, report.panels, a_swept_key};
    if (report.panels == report.x || report.panels == report.series || seen.count(report.panels)) {
      return ReportRuleBreak{"panels", -1, report.panels,
                             "a swept key other than report.x, report.series and the pooled keys"};
    }
  }
  if (!report.reference.empty() && report.series.empty()) {
    return ReportRuleBreak{"reference", -1, report.reference,
                           "no report.reference without report.series (it names a series value)"};
  }
  return std::nullopt;
}

namespace {

std::string ResolveBase(const YamlReader& where, const std::string& base, const std::string& dir) {
  return config::FindFileOrFail(where.Where(), base, dir,
                                "a scenario file (looked next to the sweep file, in the current "
                                "folder and in the project folder)");
}

// Reads a `grid:`/`zip:` mapping of dotted keys to non-empty lists. The
// grid's `base` (kSweptBaseKey) lists scenario files: each is resolved like
// `base:` into `base_paths`.
std::vector<SweepAxis> ReadAxes(YamlReader& parent, const std::string& name, const std::string& dir,
                                std::vector<std::string>* base_paths) {
  std::vector<SweepAxis> axes;
  auto section = parent.Optional(name);
  if (!section) return axes;
  section->ExpectMap();
  std::vector<std::string> keys;
  for (auto it = section->node().begin(); it != section->node().end(); ++it) {
    keys.push_back(it->first.Scalar());
  }
  for (const std::string& key : keys) {
    YamlReader list = section->Child(key);
    if (!list.node().IsSequence() || list.node().size() == 0) {
      list.Fail("a non-empty list of values for the dotted scenario key");
    }
    SweepAxis axis;
    axis.key = key;
    const bool base = key == kSweptBaseKey;
    if (base && name != "grid") {
      list.Fail("no `base` here (base scenarios are swept in grid: {base: [a.yaml, b.yaml]})");
    }
    for (const YamlReader& item : list.Items()) {
      if (!item.node().IsScalar() && !item.node().IsSequence() && !item.node().IsMap()) {
        item.Fail("a value");
      }
      if (base) {
        if (!item.node().IsScalar()) item.Fail("a scenario file");
        base_paths->push_back(ResolveBase(item, item.node().Scalar(), dir));
      }
      axis.values.push_back(FlowText(item.node()));
      axis.where.push_back(item.Where());
    }
    axes.push_back(std::move(axis));
  }
  section->Finish();
  return axes;
}

// Whether the mapping `root` has one of the keys that make a sweep file
// (scenarios::kSweepFileKeys).
bool HasSweepFileKey(const YAML::Node& root) {
  return std::any_of(scenarios::kSweepFileKeys.begin(), scenarios::kSweepFileKeys.end(),
                     [&root](std::string_view key) { return root[std::string(key)].IsDefined(); });
}

SweepSpec ReadSweep(YAML::Node root, const std::string& file, const std::string& dir) {
  auto context = std::make_shared<YamlContext>();
  context->file = file;
  if (!root.IsDefined() || root.IsNull() || !root.IsMap()) {
    throw InputError(SourceLocation{file, 1, 1, ""},
                     "a sweep mapping (base:, grid:, zip:, seeds:, report:)",
                     root.IsSequence()                      ? "a list"
                     : (!root.IsDefined() || root.IsNull()) ? config::DescribeNullRoot(root)
                                                            : "a single value");
  }
  // None of the keys that make a sweep (a scenario file given to hcpf sweep,
  // say): said as such, not as a missing `base:` at the file's first key
  // (an audit: "sweep.yaml:2:1: base: expected the required key").
  if (!HasSweepFileKey(root)) {
    throw InputError(SourceLocation{file, 1, 1, ""},
                     "a sweep file: base: (or grid.base) and, as needed, grid:, zip:, seeds: "
                     "and report:",
                     "none of base, grid or zip",
                     "a scenario file is run by hcpf run FILE --out DIR; docs/sweeps.md");
  }
  YamlReader r(root, "", context);
  SweepSpec spec;
  spec.file = file;
  spec.seed = r.Seed("seed", 1);
  spec.file_seed = spec.seed;
  spec.seeds = static_cast<int>(r.Integer("seeds", 0, kMinSweepSeeds, kMaxSweepSeeds));
  spec.seeds_where =
      r.Has("seeds") ? r.Child("seeds").Where() : SourceLocation{file, 0, 0, "seeds"};
  spec.grid = ReadAxes(r, "grid", dir, &spec.base_paths);
  spec.zip = ReadAxes(r, "zip", dir, &spec.base_paths);
  if (spec.base_paths.empty()) {
    YamlReader base = r.Child("base");
    spec.base_path = ResolveBase(base, r.String("base", std::nullopt), dir);
    spec.base_paths = {spec.base_path};
  } else {
    if (auto base = r.Optional("base")) {
      base->Fail("no top-level base: when grid.base sweeps the base scenarios");
    }
    spec.base_path = spec.base_paths.front();
  }

  // Keys are swept once; zip lists have one length; `seed` is not swept with `seeds`.
  std::set<std::string> seen;
  for (const auto* axes : {&spec.grid, &spec.zip}) {
    for (const SweepAxis& a : *axes) {
      const SourceLocation& at = a.where.front();
      if (!seen.insert(a.key).second) {
        throw InputError(SourceLocation{at.file, at.line, at.column, a.key},
                         "each key swept once (in grid or zip)", "a key swept twice");
      }
      // A key and one inside it (`tracker` and `tracker.particles`): the
      // runs take whichever override comes last while the store labels them
      // with both (a bad-input audit found plots against values no run used).
      for (const std::string& other : seen) {
        if (config::IsKeyInside(a.key, other) || config::IsKeyInside(other, a.key)) {
          throw InputError(SourceLocation{at.file, at.line, at.column, a.key},
                           "each key swept once (in grid or zip), and no key inside another "
                           "swept key",
                           fmt::format("{} with {} also swept", a.key, other));
        }
      }
      if (a.key == "seed" && spec.seeds > 0) {
        throw InputError(SourceLocation{at.file, at.line, at.column, a.key},
                         "`seed` swept only without `seeds: N` (which derives the seed)",
                         "both `seed` swept and `seeds`");
      }
    }
  }
  for (const SweepAxis& a : spec.zip) {
    if (a.values.size() != spec.zip.front().values.size()) {
      const SourceLocation& at = a.where.front();
      throw InputError(SourceLocation{at.file, at.line, at.column, "zip." + a.key},
                       fmt::format("a list of {} values, like zip.{}",
                                   spec.zip.front().values.size(), spec.zip.front().key),
                       fmt::format("{} values", a.values.size()));
    }
  }

  const std::vector<std::string> swept = spec.SweptKeys();
  spec.report.y = {"da_accuracy", "hijack_rate", "idf1", "hota", "mota", "ms_per_frame"};
  spec.report.x = swept.empty() ? "" : swept.front();
  if (auto report = r.Optional("report")) {
    report->ExpectMap();
    // Read the whole block, keeping where each entry and item is, then hold
    // it to the rules every report is held to (CheckReportRules).
    const auto scalar = [](const YamlReader& item) {
      return item.node().IsScalar() ? item.node().Scalar() : std::string();
    };
    spec.report.x = report->String("x", spec.report.x);
    spec.report.series = report->String("series", "");
    // A present x_metric or reference is a non-empty text: CheckReportRules
    // reads "" as absent, so a list or an empty value is refused here.
    const auto present_text = [&](const std::string& key, const std::string& expected) {
      std::string value;
      if (auto node = report->Optional(key)) {
        value = report->String(key, std::nullopt);
        if (value.empty()) node->Fail(expected);
      }
      return value;
    };
    spec.report.x_metric = present_text("x_metric", "a metric name");
    // y and pool: a list, or its one item written alone (`y: hota`, `pool:
    // world.sun.azimuth_deg`; until 2026-12-06 pool refused the second: an
    // audit).
    const auto items_or_one = [](const YamlReader& node) {
      return node.node().IsSequence() ? node.Items() : std::vector<YamlReader>{node};
    };
    std::vector<YamlReader> y_items;
    std::optional<YamlReader> y = report->Optional("y");
    if (y) {
      spec.report.y.clear();
      y_items = items_or_one(*y);
      for (const YamlReader& item : y_items) spec.report.y.push_back(scalar(item));
    }
    std::vector<YamlReader> pool_items;
    if (auto pool = report->Optional("pool")) pool_items = items_or_one(*pool);
    for (const YamlReader& item : pool_items) spec.report.pool.push_back(scalar(item));
    spec.report.panels = report->String("panels", "");
    spec.report.reference = present_text("reference", "a value of report.series");
    if (const auto broken = CheckReportRules(spec.report, swept)) {
      const YamlReader at = broken->item >= 0
                                ? (broken->entry == "y" ? y_items : pool_items)[broken->item]
                            : broken->entry == "y" ? *y
                                                   : report->Child(broken->entry);
      // The names the value that broke it may have meant (none when it is
      // one of them, in the wrong place).
      const std::vector<std::string>& names =
          broken->entry == "y" || broken->entry == "x_metric" ? MetricNames() : swept;
      const bool known = std::find(names.begin(), names.end(), broken->value) != names.end();
      const std::string close = ClosestMatch(broken->value, names);
      at.Fail(broken->expected, close.empty() || known ? "" : "did you mean \"" + close + "\"?");
    }
    if (!spec.report.reference.empty()) {
      // A value of the series key, compared as the sweep file writes it.
      const YamlReader reference = report->Child("reference");
      const SweepAxis* series = nullptr;
      for (const auto* axes : {&spec.grid, &spec.zip}) {
        for (const SweepAxis& a : *axes) {
          if (a.key == spec.report.series) series = &a;
        }
      }
      if (series == nullptr) {
        reference.Fail("no report.reference without report.series (it names a series value)");
      }
      const std::string& value = spec.report.reference;
      if (std::find(series->values.begin(), series->values.end(), value) == series->values.end()) {
        const std::string close = ClosestMatch(value, series->values);
        reference.Fail(fmt::format("a value of report.series {} ({})", spec.report.series,
                                   fmt::join(series->values, ", ")),
                       close.empty() ? "" : "did you mean \"" + close + "\"?");
      }
    }
    report->Finish();
  }
  r.Finish();
  try {
    CheckedRunCount(spec);
  } catch (const InputError& e) {
    // At the first swept key's line (the count is the product of all of them).
    const SourceLocation at = !spec.grid.empty()  ? spec.grid.front().where.front()
                              : !spec.zip.empty() ? spec.zip.front().where.front()
                                                  : SourceLocation{file, 0, 0, ""};
    throw InputError(SourceLocation{file, at.line, 0, "grid"}, e.expected(), e.found(), e.hint());
  }
  return spec;
}

// Re-locates an InputError raised by a swept value's `--set` text at the
// sweep file line of that value.
[[noreturn]] void Relocate(const InputError& e, const SourceLocation& at) {
  throw InputError(SourceLocation{at.file, at.line, at.column, e.where().key}, e.expected(),
                   e.found(), e.hint());
}

// A det.txt (observation.detector: file) describes the frames of one
// rendering; `seeds: N` renders other frames for each seed unless the world
// and renderer seeds are pinned, and the detections would describe frames
// that are not there.
void CheckDetectionFileSeeds(const SweepSpec& spec, const scenarios::Scenario& s,
                             const std::vector<std::string>& values) {
  constexpr uint8_t kFrames =
      scenarios::Scenario::kPinnedWorld | scenarios::Scenario::kPinnedRenderer;
  if (spec.seeds <= 1 || !s.observation.from_file() || (s.pinned_seeds & kFrames) == kFrames) {
    return;
  }
  throw InputError(
      spec.seeds_where,
      "seeds.world and seeds.renderer pinned (in the base, or swept) with observation.detector: "
      "file: the det.txt was made on one rendering, and every other seed renders other frames",
      fmt::format("seeds: {} with the run {} reading {} and its seeds.world or seeds.renderer "
                  "derived from each seed",
                  spec.seeds,
                  values.empty() ? "of the base" : fmt::format("({})", fmt::join(values, ", ")),
                  s.observation.file.path),
      "copy seeds.world and seeds.renderer from the scenario.resolved.yaml of the hcpf render "
      "folder the detector ran on; seeds: N then varies the tracker and observation seeds");
}

// Whether report.pool lists `key`.
bool Pooled(const ReportSpec& report, const std::string& key) {
  return std::find(report.pool.begin(), report.pool.end(), key) != report.pool.end();
}

// The cells the zip's positions make in the report: positions with the same
// values of the zip keys report.pool does not list share one (their pooled
// keys read "all"). The zip's length when none is pooled; 1 when all are (or
// without a zip).
size_t ZipCells(const SweepSpec& spec) {
  if (spec.zip.empty()) return 1;
  std::set<std::vector<std::string>> cells;
  for (size_t i = 0; i < spec.zip.front().values.size(); ++i) {
    std::vector<std::string> kept;
    for (const SweepAxis& a : spec.zip) {
      if (!Pooled(spec.report, a.key)) kept.push_back(a.values[i]);
    }
    cells.insert(std::move(kept));
  }
  return cells.size();
}

// What a sweep's notes begin with: its file, or "sweep" for one made in code.
std::string NoteSubject(const SweepSpec& spec) {
  return spec.file.empty() ? std::string("sweep") : spec.file;
}

// `run`'s cell, "key = value" for each swept key, in the sweep's order.
std::vector<std::string> CellValues(const SweepSpec& spec, const SweepRun& run) {
  const std::vector<std::string> keys = spec.SweptKeys();
  std::vector<std::string> cell;
  for (size_t k = 0; k < keys.size() && k < run.values.size(); ++k) {
    cell.push_back(fmt::format("{} = {}", keys[k], run.values[k]));
  }
  return cell;
}

}  // namespace

std::string SeedsForHolmNote(const SweepSpec& spec) {
  const ReportSpec& report = spec.report;
  if (report.series.empty() || report.y.empty()) return {};
  const auto is_series = [&](const SweepAxis& a) { return a.key == report.series; };
  // The series is a grid key, or a zip key (each zip position then a series
  // value, the other zip keys following it: they pair with the reference's).
  const SweepAxis* series = nullptr;
  if (const auto g = std::find_if(spec.grid.begin(), spec.grid.end(), is_series);
      g != spec.grid.end()) {
    series = &*g;
  } else if (const auto z = std::find_if(spec.zip.begin(), spec.zip.end(), is_series);
             z != spec.zip.end()) {
    series = &*z;
  }
  if (series == nullptr || series->values.size() < 2) return {};
  const double zip_length = spec.zip.empty() ? 1.0 : static_cast<double>(spec.zip[0].values.size());
  double cells = zip_length, pooled = 1.0;
  for (const SweepAxis& a : spec.grid) {
    cells *= static_cast<double>(a.values.size());
    if (Pooled(report, a.key)) pooled *= static_cast<double>(a.values.size());
  }
  // The zip's pooled keys pool the positions that share their values of the
  // keys it does not pool (ZipCells): all of them when every zip key is
  // pooled, none when those values differ at every position (the series
  // zipped, say). Until 2026-12-06 a pooled zip key counted all its values
  // as pooled beside an unpooled one, and a series zipped beside one made
  // the note say nothing.
  pooled *= zip_length / static_cast<double>(ZipCells(spec));
  const double values = static_cast<double>(series->values.size());
  // Timings are not tested (MachineDependent): not in the family.
  const auto tested = std::count_if(report.y.begin(), report.y.end(),
                                    [](const std::string& m) { return !MachineDependent(m); });
  const double comparisons = cells / pooled * (values - 1.0) / values * static_cast<double>(tested);
  // A pooled cell's runs of one seed are averaged (one pair of means per
  // seed): pooled values add no pairs. Without `seeds:` each cell runs once,
  // on the base file's seed: one pair, as with `seeds: 1`.
  const double pairs = static_cast<double>(std::max(spec.seeds, 1));
  if (comparisons < 1.0 || pairs > 1000.0) return {};
  const int m = static_cast<int>(std::min(comparisons, 1e9));
  const int n = static_cast<int>(pairs);
  const double floor = SignedRankFloor(n);
  if (floor < 0.05 / m) return {};
  const int needed = PairsForHolm(m, 0.05);
  const std::string file = NoteSubject(spec);
  const std::string reference =
      report.reference.empty() ? series->values.front() : report.reference;
  if (n == 1) {
    // One run per cell: no spread to give an interval, no pairs to test.
    return fmt::format(
        "{}: {} each cell of the report runs once, so it has no interval and its paired "
        "comparisons ({} against {}) one pair each: none can be a finding, whatever the data. "
        "{} seeds at least are needed (more where some seeds tie or differ the other way); "
        "docs/sweeps.md, \"Seeds enough for Holm\"",
        file,
        spec.seeds == 1 ? std::string("with 1 seed")
                        : std::string("without `seeds:` (the base file's seed alone)"),
        report.series, reference, needed);
  }
  // Tarone's K for m comparisons of this floor (every pair differing): the
  // smallest k with none below 0.05 / k, the first step's multiplier
  // (counted here, not by TaroneFamilyOf: m can be a billion).
  int tarone_k = 1;
  while (tarone_k < m && floor < 0.05 / tarone_k) ++tarone_k;
  const std::string why =
      floor >= 0.05
          ? fmt::format(
                "the signed-rank test cannot give p below {:.3g}, so no comparison can be "
                "a finding",
                floor)
          : fmt::format(
                "the signed-rank test cannot give p below {:.3g}, and Holm's correction "
                "over the report's {} paired comparisons needs p < {:.3g} for its first "
                "(Tarone's rule: K = {}), so none can survive it unless ties (seeds where "
                "both runs have the same value) leave {} or fewer comparisons at this floor",
                floor, m, 0.05 / tarone_k, tarone_k, static_cast<int>(std::ceil(0.05 / floor)) - 1);
  return fmt::format(
      "{}: with {} seeds each paired comparison of the report ({} against {}) has {} pairs{}: "
      "{}, whatever the data. {} seeds at least are needed (more where some seeds tie or "
      "differ the other way); docs/sweeps.md, \"Seeds enough for Holm\"",
      file, spec.seeds, report.series, reference, n,
      pooled > 1.0 ? fmt::format(" (the runs of its {} pooled values are averaged in each seed)",
                                 static_cast<int>(pooled))
                   : "",
      why, needed);
}

std::string ZippedPoolNote(const SweepSpec& spec) {
  std::vector<std::string> in, out;
  for (const SweepAxis& a : spec.zip) (Pooled(spec.report, a.key) ? in : out).push_back(a.key);
  if (in.empty() || out.empty()) return {};
  const size_t positions = spec.zip.front().values.size(), cells = ZipCells(spec);
  if (cells == 1) return {};  // the unpooled keys never change: everything is pooled
  const auto list = [](const std::vector<std::string>& keys) {
    if (keys.size() == 1) return keys.front();
    return fmt::format("{} and {}", fmt::join(keys.begin(), keys.end() - 1, ", "), keys.back());
  };
  const bool one = in.size() == 1;
  const std::string what =
      cells == positions
          ? fmt::format(
                "each zip position is still its own cell, holding the one value of {} "
                "that its position gives, so the report pools nothing of {}",
                one ? "it" : "each", one ? "it" : "them")
          : fmt::format(
                "only zip positions with the same values of {} share a cell ({} cells "
                "of {} positions), so the report pools {} only there",
                list(out), cells, positions, one ? "it" : "them");
  // Pooling the other zip keys too is advice only where report.pool may list
  // them (not x, the series or the panels).
  const bool poolable = std::none_of(out.begin(), out.end(), [&](const std::string& k) {
    return k == spec.report.x || k == spec.report.series || k == spec.report.panels;
  });
  return fmt::format(
      "{}: report.pool lists {} but not {}, zipped with {}: {}. {}weep {} as a key of grid: to "
      "pool {} within each cell (each cell then holds every value of {}, with every "
      "combination of the other keys)",
      NoteSubject(spec), list(in), list(out), one ? "it" : "them", what,
      poolable ? fmt::format("Pool {} too, or s", list(out)) : std::string("S"), list(in),
      one ? "its values" : "their values", one ? "it" : "them");
}

std::string CameraTurnNote(const SweepSpec& spec, const std::vector<SweepRun>& runs) {
  // The turn depends on the frame count and the camera's keyframes alone:
  // each distinct path is evaluated once (most sweeps have one).
  std::map<std::vector<double>, scenarios::CameraTurn> turn_of_path;
  int64_t cells = 0, turning = 0;
  scenarios::CameraTurn worst;
  const SweepRun* worst_run = nullptr;
  for (const SweepRun& run : runs) {
    if (run.seed_index != 0 || !run.cell) continue;  // a cell's seeds share its camera
    ++cells;
    const WorldSpec& world = run.cell->world;
    std::vector<double> path = {static_cast<double>(world.frames)};
    for (const CameraKeyframe& k : world.camera.path) {
      path.push_back(k.frame);
      path.insert(path.end(), k.position_m.data(), k.position_m.data() + 3);
      path.insert(path.end(), k.look_at_m.data(), k.look_at_m.data() + 3);
    }
    auto it = turn_of_path.find(path);
    if (it == turn_of_path.end()) {
      it = turn_of_path.emplace(std::move(path), scenarios::StrongestCameraTurn(*run.cell)).first;
    }
    const scenarios::CameraTurn& turn = it->second;
    if (!(turn.degrees > scenarios::kCameraTurnNoteDeg)) continue;
    ++turning;
    if (!worst_run || turn.degrees > worst.degrees) {
      worst = turn;
      worst_run = &run;
    }
  }
  if (!worst_run) return {};
  const std::vector<std::string> cell = CellValues(spec, *worst_run);
  return fmt::format(
      "{}: in {} of {} cells the image turns by more than {:g} degrees about its centre between "
      "two frames; most, by {:.1f} degrees from frame {} to {} (camera.path), in the cell {}: {}",
      NoteSubject(spec), turning, cells, scenarios::kCameraTurnNoteDeg, worst.degrees,
      worst.frame - 1, worst.frame,
      cell.empty() ? std::string("of the base scenario") : fmt::format("{}", fmt::join(cell, ", ")),
      scenarios::CameraTurnReason());
}

std::string TargetOverlapNote(const SweepSpec& spec, const std::vector<SweepRun>& runs) {
  int64_t cells = 0, overlapping = 0;
  std::string first_note;  // the first overlapping cell's, and that cell
  std::vector<std::string> first_cell;
  for (const SweepRun& run : runs) {
    if (run.seed_index != 0 || !run.cell) continue;  // a cell's seeds share its paths
    ++cells;
    std::string note = scenarios::TargetOverlapNote(*run.cell);
    if (note.empty() || ++overlapping > 1) continue;
    first_note = std::move(note);
    first_cell = CellValues(spec, run);
  }
  if (overlapping == 0) return {};
  const std::string file = NoteSubject(spec);
  if (overlapping == cells) {
    return fmt::format("{}: in {}: {}", file,
                       cells == 1 ? std::string("its cell") : fmt::format("all {} cells", cells),
                       cells == 1 ? first_note : "the first says " + first_note);
  }
  return fmt::format(
      "{}: in {} of {} cells two targets drive through each other; the first, {}: {}", file,
      overlapping, cells, fmt::join(first_cell, ", "), first_note);
}

std::vector<std::string> SweepSpec::SweptKeys() const {
  std::vector<std::string> keys;
  for (const SweepAxis& a : grid) keys.push_back(a.key);
  for (const SweepAxis& a : zip) keys.push_back(a.key);
  return keys;
}

int64_t SweepSpec::RunCount() const { return CheckedRunCount(*this); }

int64_t CheckedRunCount(const SweepSpec& spec) {
  // Overflow-safe: a grid of a few long lists can exceed 2^63 runs.
  std::vector<std::string> factors;
  int64_t n = 1;
  bool overflow = false;
  const auto times = [&](int64_t factor, const std::string& what) {
    factors.push_back(fmt::format("{} {}", factor, what));
    overflow = overflow || __builtin_mul_overflow(n, factor, &n);
  };
  for (const SweepAxis& a : spec.grid) times(static_cast<int64_t>(a.values.size()), a.key);
  if (!spec.zip.empty()) times(static_cast<int64_t>(spec.zip.front().values.size()), "zip");
  times(std::max(spec.seeds, 1), "seeds");
  if (overflow || n > kMaxSweepRuns) {
    throw InputError(SourceLocation{spec.file, 0, 0, "grid"},
                     fmt::format("a sweep of at most {} runs", kMaxSweepRuns),
                     fmt::format("{} = {} runs", fmt::join(factors, " × "),
                                 overflow ? std::string("more than 2^63") : std::to_string(n)),
                     "split it into several sweep files, or use fewer values or seeds");
  }
  return n;
}

void SetRootSeed(SweepSpec& spec, const std::string& text, const std::string& option) {
  const std::optional<uint64_t> value = config::ParseSeed(text);
  if (!value) {
    throw InputError(SourceLocation{"hcpf sweep", 0, 0, option},
                     "a non-negative integer seed below 2^64", "\"" + text + "\"");
  }
  if (spec.seeds == 0) {
    throw InputError(
        SourceLocation{"hcpf sweep", 0, 0, option},
        fmt::format("a sweep with `seeds: N` (its runs' seeds are derived from the root seed {} "
                    "names)",
                    option),
        fmt::format("{} without `seeds:`: every run keeps its base scenario's seed",
                    spec.file.empty() ? std::string("a sweep") : spec.file),
        fmt::format("add `seeds: N` to the sweep file, or drop {}", option));
  }
  spec.seed = *value;
  spec.seed_from = option;
}

CellPlace PlaceOfCell(const std::vector<int64_t>& grid_lengths, int64_t zip_length, int64_t cell) {
  CellPlace place{std::vector<int64_t>(grid_lengths.size()), cell % zip_length};
  int64_t rest = cell / zip_length;
  for (size_t g = grid_lengths.size(); g-- > 0;) {
    place.digits[g] = rest % grid_lengths[g];
    rest /= grid_lengths[g];
  }
  return place;
}

uint64_t SweepSeed(uint64_t sweep_seed, int index) {
  return Rng(sweep_seed).Fork("sweep/seed", index).identity();
}

SweepSpec LoadSweepText(const std::string& text, const std::string& file_name,
                        const std::string& dir) {
  return ReadSweep(YamlReader::Parse(text, file_name), file_name, dir);
}

bool IsSweepFile(const std::string& path) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) return false;
  try {
    // The reader every sweep and scenario goes through (its guards against
    // yaml-cpp's hangs included).
    const YAML::Node root = YamlReader::ParseFile(path);
    return root.IsMap() && HasSweepFileKey(root);
  } catch (const InputError&) {
    return false;
  }
}

SweepSpec LoadSweepFile(const std::string& path) {
  if (fs::is_directory(path)) {
    throw InputError(SourceLocation{path, 0, 0, ""}, "a sweep YAML file", "a directory");
  }
  const std::string dir = fs::path(path).parent_path().string();
  return ReadSweep(YamlReader::ParseFile(path), path, dir.empty() ? "." : dir);
}

std::vector<SweepRun> ExpandSweep(const SweepSpec& spec) {
  const int64_t total = CheckedRunCount(spec);
  const int seeds = std::max(spec.seeds, 1);
  const int64_t zip_length =
      spec.zip.empty() ? 1 : static_cast<int64_t>(spec.zip.front().values.size());
  // Each base file is read once; every cell parses its text with its overrides.
  const std::vector<std::string> base_paths =
      spec.base_paths.empty() ? std::vector<std::string>{spec.base_path} : spec.base_paths;
  std::vector<std::string> base_texts;
  for (const std::string& path : base_paths) base_texts.push_back(YamlReader::ReadFile(path));
  // The grid axis that picks the base file (kSweptBaseKey), if any.
  int base_axis = -1;
  for (size_t g = 0; g < spec.grid.size(); ++g) {
    if (spec.grid[g].key == kSweptBaseKey) base_axis = static_cast<int>(g);
  }
  const auto load = [&](const std::vector<config::Override>& overrides,
                        const std::vector<SourceLocation>& where, size_t base,
                        const std::string& cell_text) {
    try {
      return scenarios::LoadScenarioText(base_texts[base], base_paths[base], overrides);
    } catch (const InputError& e) {
      // An error in a swept value is reported at that value in the sweep file.
      const int i = e.where().override_index;
      if (i >= 0 && static_cast<size_t>(i) < where.size())
        Relocate(e, where[static_cast<size_t>(i)]);
      // One in the base file that only some cells make (a bad-input audit:
      // `camera.path[0].frame: expected an integer in [0, 9]` at a line that
      // is valid on its own, the swept `frames: 10` that made it so unnamed)
      // names the cell's swept values.
      if (cell_text.empty()) throw;
      // An error of the base file itself, which every cell makes (a review:
      // a plain typo was said to be "in the sweep's runs with ..."), is
      // reported as it is.
      try {
        scenarios::LoadScenarioText(base_texts[base], base_paths[base], {});
      } catch (const InputError&) {
        throw e;
      }
      const std::string in_cell = "in the sweep's runs with " + cell_text;
      throw InputError(e.where(), e.expected(), e.found(),
                       e.hint().empty() ? in_cell : e.hint() + "; " + in_cell);
    }
  };
  std::vector<SweepRun> runs;
  runs.reserve(static_cast<size_t>(total));
  std::map<std::string, int64_t> index_of_key;
  std::vector<int64_t> grid_lengths;
  for (const SweepAxis& a : spec.grid)
    grid_lengths.push_back(static_cast<int64_t>(a.values.size()));
  const auto place_of = [&](int64_t cell) { return PlaceOfCell(grid_lengths, zip_length, cell); };
  scenarios::Progress progress("expand", total, total >= 20000);
  for (int64_t cell = 0; cell < total / seeds; ++cell) {
    // A cell: one grid point and zip position, `seeds` runs that differ only in their seed.
    const CellPlace place = place_of(cell);
    const std::vector<int64_t>& digits = place.digits;
    const int64_t zip_position = place.zip_position;
    std::vector<std::string> values;
    std::vector<config::Override> overrides;
    std::vector<SourceLocation> where;
    size_t base = 0;
    for (size_t g = 0; g < spec.grid.size(); ++g) {
      values.push_back(spec.grid[g].values[digits[g]]);
      if (static_cast<int>(g) == base_axis) {
        // Not an override: it picks the file the overrides apply to.
        base = static_cast<size_t>(digits[g]);
        continue;
      }
      overrides.push_back({spec.grid[g].key, spec.grid[g].values[digits[g]]});
      where.push_back(spec.grid[g].where[digits[g]]);
    }
    for (const SweepAxis& a : spec.zip) {
      values.push_back(a.values[zip_position]);
      overrides.push_back({a.key, a.values[zip_position]});
      where.push_back(a.where[zip_position]);
    }
    std::string cell_text;
    for (size_t g = 0; g < spec.grid.size(); ++g) {
      const SourceLocation& at = spec.grid[g].where[digits[g]];
      cell_text += fmt::format("{}{} = {} ({}:{}:{})", cell_text.empty() ? "" : ", ",
                               spec.grid[g].key, values[g], at.file, at.line, at.column);
    }
    for (const SweepAxis& a : spec.zip) {
      const SourceLocation& at = a.where[zip_position];
      cell_text += fmt::format("{}{} = {} ({}:{}:{})", cell_text.empty() ? "" : ", ", a.key,
                               a.values[zip_position], at.file, at.line, at.column);
    }
    if (spec.seeds > 0) {
      overrides.push_back({"seed", ""});  // filled per seed below
      where.push_back(SourceLocation{spec.file, 0, 0, "seeds"});
    }
    // Seed indices 0 and 1 are loaded in full; the others are the seed-0
    // scenario reseeded (scenarios::Reseeded), which is much cheaper than
    // parsing and resolving the base file again, when the reseeded seed-1
    // scenario gives exactly the resolved YAML of the full load.
    std::shared_ptr<const scenarios::Scenario> first;
    std::string first_yaml;
    bool reseed = false;
    for (int k = 0; k < seeds; ++k) {
      const int64_t index = cell * seeds + k;
      SweepRun run;
      run.index = index;
      run.seed_index = k;
      run.values = values;
      std::string resolved;
      if (spec.seeds > 0) {
        run.seed = SweepSeed(spec.seed, k);
        overrides.back().value = std::to_string(run.seed);
      }
      run.overrides = overrides;
      if (reseed) {
        run.cell = first;
        resolved = scenarios::ReseedResolvedYaml(first_yaml, scenarios::Reseeded(*first, run.seed));
      } else {
        auto scenario =
            std::make_shared<const scenarios::Scenario>(load(overrides, where, base, cell_text));
        resolved = scenarios::ToResolvedYaml(*scenario);
        run.cell = scenario;
        if (k == 0) {
          first = scenario;
          first_yaml = resolved;
          CheckDetectionFileSeeds(spec, *scenario, values);
        } else if (k == 1) {
          reseed = scenarios::ReseedResolvedYaml(
                       first_yaml, scenarios::Reseeded(*first, scenario->seed)) == resolved;
        }
      }
      if (spec.seeds == 0) run.seed = run.cell->seed;
      run.key = scenarios::HashResolvedYaml(resolved);
      // Two runs of one scenario would share a folder and a row: a list that
      // names a value twice is a mistake in the sweep file.
      const auto [at_key, inserted] = index_of_key.emplace(run.key, index);
      if (!inserted) {
        // At the first list item in which this run's cell differs from the
        // earlier run's: the value that repeats a scenario (a base file
        // listed twice in grid.base has no override to point at: an audit
        // found that error without a line).
        const CellPlace earlier = place_of(at_key->second / seeds);
        SourceLocation at = where.empty() ? SourceLocation{spec.file, 0, 0, ""} : where.front();
        const auto differs = std::mismatch(digits.begin(), digits.end(), earlier.digits.begin());
        if (differs.first != digits.end()) {
          const auto g = static_cast<size_t>(differs.first - digits.begin());
          at = spec.grid[g].where[digits[g]];
        } else if (zip_position != earlier.zip_position) {
          at = spec.zip.front().where[zip_position];
        }
        throw InputError(SourceLocation{at.file, at.line, at.column, "grid/zip"},
                         "every run a different scenario (no value listed twice)",
                         fmt::format("runs {} and {} resolve to the same scenario ({})",
                                     at_key->second, index, fmt::join(run.values, ", ")));
      }
      runs.push_back(std::move(run));
    }
    progress.Advance(seeds);
  }
  progress.Finish();
  return runs;
}

scenarios::Scenario SweepRun::scenario() const {
  return cell->seed == seed ? *cell : scenarios::Reseeded(*cell, seed);
}

bool SweepRun::rendered() const {
  return cell->observation.source == scenarios::ObservationSource::kRendered;
}

std::string SweepHash(const std::vector<SweepRun>& runs) {
  // FNV-1a 64 over the run keys in order.
  uint64_t h = 14695981039346656037ULL;
  for (const SweepRun& r : runs) {
    for (const char c : r.key + "\n") {
      h ^= static_cast<unsigned char>(c);
      h *= 1099511628211ULL;
    }
  }
  return fmt::format("{:016x}", h);
}

void SweepOptions::Validate() const {
  if (out_dir.empty())
    throw InputError(SourceLocation{"hcpf sweep", 0, 0, "--out"}, "a folder", "nothing");
  if (!frame_cache_dir.empty()) scenarios::CheckFolderArgument(frame_cache_dir, "--cache");
  if (jobs < 1) {
    throw InputError(SourceLocation{"hcpf sweep", 0, 0, "--jobs"}, "an integer >= 1",
                     std::to_string(jobs));
  }
  if (run_threads < 1 || run_threads > 256) {
    throw InputError(SourceLocation{"hcpf sweep", 0, 0, "--threads"}, "an integer in [1, 256]",
                     std::to_string(run_threads));
  }
  if (shard_count < 1 || shard_index < 0 || shard_index >= shard_count) {
    throw InputError(SourceLocation{"hcpf sweep", 0, 0, "--shard"}, "i/n with 0 <= i < n",
                     fmt::format("{}/{}", shard_index, shard_count));
  }
}

bool SweepOptions::InChildProcess(const SweepRun& run) const {
  if (!isolate_exe.empty()) return true;
  if (render_exe.empty() || jobs <= 1 || !run.rendered()) return false;
  return !FramesAllCached(run);
}

bool SweepOptions::FramesAllCached(const SweepRun& run) const {
  if (frame_cache_dir.empty() || !run.rendered()) return false;
  const scenarios::Scenario scenario = run.scenario();
  const renderer::FrameCache cache(frame_cache_dir, scenarios::PixelHashOf(scenario));
  for (int f = 0; f < scenario.world.frames; ++f) {
    if (!cache.Contains(f)) return false;
  }
  return true;
}

}  // namespace hcpf::studies
