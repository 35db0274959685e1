// `hcpf report DIR`: results.sqlite -> report.html (gnuplot SVG inline) + summary.csv.

#include "hcpf/studies/report.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <sys/wait.h>
#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>

#include "gnuplot.h"
#include "hcpf/core/check.h"
#include "hcpf/core/error.h"
#include "hcpf/core/text_file.h"
#include "hcpf/metrics/detection_truth.h"
#include "hcpf/scenarios/output_folder.h"
#include "hcpf/scenarios/scenario.h"
#include "hcpf/studies/metric_catalogue.h"
#include "hcpf/studies/results_store.h"
#include "hcpf/studies/sweep.h"
#include "scene_sketch.h"
#include "text.h"

namespace hcpf::studies {

namespace fs = std::filesystem;

namespace {

std::optional<double> ParseNumber(const std::string& text) {
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || ptr != text.data() + text.size()) return std::nullopt;
  return v;
}

// A cell: one combination of swept values.
struct Cell {
  std::vector<std::string> values;
  std::vector<const RunRecord*> runs;
  int failures = 0;
  std::map<std::string, Interval> stats;
  // With report.x_metric: where the cell sits on the x axis when that is not
  // its own stats' mean (a cell of paired differences sits at its compared
  // cell's place).
  std::optional<double> x_at;
  // A cell of paired differences (DifferenceCells), per metric: 1 when the
  // difference is a finding (VerdictOf), 2 when Holm's correction keeps it.
  std::map<std::string, int> finding;
  // The combinations of pooled values among its runs (report.pool; 1
  // without): a seed counts in the cell's statistics only with a finite
  // value at every one of them (SeedMean).
  int pooled_values = 1;
};

// The statistic of metric `m` over `values` (its catalogue range decides
// Wilson or t; an unknown name gets an unbounded t interval).
Interval CellInterval(const std::string& m, const std::vector<double>& values) {
  const CatalogueMetric* entry = FindMetric(m);
  return MeanInterval95(values, entry ? entry->range : MetricRange::Unbounded());
}

}  // namespace

void ReportOptions::Validate() const {
  if (dir.empty())
    throw InputError(SourceLocation{"hcpf report", 0, 0, "DIR"}, "a sweep folder", "nothing");
  CheckGnuplot(gnuplot);
}

namespace {

// The contact sheet the sweep wrote from its own frame cache (sweep_run.cc),
// embedded as a data: URI so the report stays one self-contained file. The
// report never renders: without that file there is no picture of the scene.
std::string SceneContactSheet(const fs::path& dir) {
  const fs::path png = dir / "contact_sheet.png";
  std::error_code ec;
  if (!fs::is_regular_file(png, ec)) return {};
  return "<h2>The scene (sampled frames with ground truth)</h2>\n"
         "<p>Frames of the first rendered run, each target drawn with its amodal box (yellow: "
         "the whole target, hidden parts included), its visible box (green: the part seen) and a "
         "label of its id and visible fraction.</p>\n"
         "<img alt=\"contact sheet\" style=\"max-width:100%\" src=\"data:image/png;base64," +
         Base64(ReadWholeFile(png)) + "\">\n";
}

}  // namespace

namespace {

// Whether a run's folder is there under the sweep folder `dir` (runs/
// deleted or moved, or results.sqlite copied alone, leave none: the report
// counts such runs and links to none of them).
bool HasRunFolder(const fs::path& dir, const RunRecord& r) {
  std::error_code ec;
  return !r.run_dir.empty() && fs::is_directory(dir / r.run_dir, ec);
}

// Per swept key, whether report.pool lists it.
std::vector<bool> PooledKeys(const StoreMeta& meta) {
  std::vector<bool> pooled(meta.swept_keys.size(), false);
  for (size_t k = 0; k < meta.swept_keys.size(); ++k) {
    pooled[k] = std::find(meta.report.pool.begin(), meta.report.pool.end(), meta.swept_keys[k]) !=
                meta.report.pool.end();
  }
  return pooled;
}

// A cell's finished runs grouped by seed, in order of first appearance.
std::vector<std::vector<const RunRecord*>> OkRunsBySeed(const std::vector<const RunRecord*>& runs) {
  std::vector<std::vector<const RunRecord*>> out;
  std::map<uint64_t, size_t> index;
  for (const RunRecord* r : runs) {
    if (!r->ok) continue;
    const auto [it, inserted] = index.emplace(r->seed, out.size());
    if (inserted) out.emplace_back();
    out[it->second].push_back(r);
  }
  return out;
}

// The mean of `values` (one seed's, finite), or NaN when there are fewer
// than `required`: a seed missing a pooled value (a failed run, a metric
// undefined there) is left out rather than averaged over the others, since
// the pooled values differ (SKS's recall at a 35° sun: 0.71 from 225°, 0.97
// from the other two azimuths). One value's mean is itself, −0 included.
double MeanOfSeed(const std::vector<double>& values, int required) {
  if (values.empty() || static_cast<int>(values.size()) < required) return kNaN;
  return values.size() == 1 ? values.front() : Mean(values);
}

// The mean of metric `m` over one seed's finished runs (MeanOfSeed of their
// finite values; `required`: the cell's Cell::pooled_values).
double SeedMean(const std::vector<const RunRecord*>& runs, const std::string& m, int required) {
  std::vector<double> values;
  for (const RunRecord* r : runs) {
    const double x = r->metrics.at(m);
    if (std::isfinite(x)) values.push_back(x);
  }
  return MeanOfSeed(values, required);
}

// Stage 1, cells: runs grouped by their swept values (in order of first
// appearance, which is the expansion order), each with every catalogue
// metric's mean and 95 % interval over its finished runs.
// Pooled keys (report.pool) read "all": their runs share a cell.
std::vector<Cell> CellsOf(const std::vector<RunRecord>& runs, const StoreMeta& meta) {
  const std::vector<bool> pooled = PooledKeys(meta);
  std::vector<Cell> cells;
  std::map<std::vector<std::string>, size_t> cell_of;
  for (const RunRecord& r : runs) {
    std::vector<std::string> values = r.values;
    for (size_t k = 0; k < values.size() && k < pooled.size(); ++k) {
      if (pooled[k]) values[k] = "all";
    }
    auto [it, inserted] = cell_of.emplace(values, cells.size());
    if (inserted) cells.push_back(Cell{values, {}, 0, {}});
    Cell& cell = cells[it->second];
    cell.runs.push_back(&r);
    if (!r.ok) ++cell.failures;
  }
  for (Cell& cell : cells) {
    std::set<std::vector<std::string>> combinations;
    for (const RunRecord* r : cell.runs) combinations.insert(r->values);
    cell.pooled_values = static_cast<int>(combinations.size());
  }
  // Stage 2, statistics over seeds. The runs of one seed in a pooled cell
  // (one per pooled value) share that seed's random streams (terrain,
  // noise, camera shake): they are averaged into one value per seed, and
  // the band is over those means, one independent unit per seed. Without
  // pooled keys a cell has one run per seed, whose mean is its value.
  for (Cell& cell : cells) {
    const std::vector<std::vector<const RunRecord*>> by_seed = OkRunsBySeed(cell.runs);
    for (const std::string& m : MetricNames()) {
      std::vector<double> v;
      for (const auto& seed_runs : by_seed) v.push_back(SeedMean(seed_runs, m, cell.pooled_values));
      cell.stats[m] = CellInterval(m, v);
    }
  }
  return cells;
}

// How the cells are drawn: one line per combination of the swept keys other
// than x, and the x axis.
struct Layout {
  int x_index = -1;
  std::vector<std::string> lines;  // labels, in order of first appearance
  std::map<std::string, std::vector<const Cell*>> line_cells;
  std::vector<std::string> x_values;
  bool numeric_x = false;
  bool log_x = false;
  double x_min = 0.0, x_max = 0.0;
  std::string x_label;
  std::string x_title;  // x in plot titles (x_label without its notes)

  std::string x_metric;  // ReportSpec::x_metric

  // The x coordinate of a cell: its mean of x_metric (NaN when it has none),
  // its number, or its category's index.
  double XPosition(const Cell& c) const {
    if (!x_metric.empty()) {
      if (c.x_at) return *c.x_at;
      const Interval& s = c.stats.at(x_metric);
      return s.n > 0 ? s.mean : kNaN;
    }
    const std::string v = x_index >= 0 ? c.values[x_index] : "";
    if (numeric_x) return *ParseNumber(v);
    return static_cast<double>(std::find(x_values.begin(), x_values.end(), v) - x_values.begin());
  }
};

// For each swept key whose value follows from the value of the key at
// `index` (zipped with it: an external tracker's tracker.type and
// tracker.command beside the `name` series that labels it, or a key zipped
// with x), its value at each value of that key; nullopt for the others (and
// for every key when index < 0: no such key).
using FollowingKeys = std::vector<std::optional<std::map<std::string, std::string>>>;

// Over `rows` (swept values, one vector per cell or run), key k's value at
// each value of key `index` when it follows from it; nullopt when it does
// not.
std::optional<std::map<std::string, std::string>> ValuesFollowing(
    const std::vector<const std::vector<std::string>*>& rows, size_t index, size_t k) {
  std::map<std::string, std::string> value_at;
  for (const std::vector<std::string>* row : rows) {
    const auto [it, inserted] = value_at.emplace((*row)[index], (*row)[k]);
    if (!inserted && it->second != (*row)[k]) return std::nullopt;
  }
  return value_at;
}

// Per swept key, whether the store's expansion zips it with key `index`
// (both zip keys). A store that records no expansion (written before
// 2026-12-06) cannot say: every key is taken as possibly zipped, and the
// runs' values alone decide whether it follows.
std::vector<bool> ZippedWith(const StoreMeta& meta, size_t index) {
  const size_t keys = meta.swept_keys.size();
  if (!meta.expansion) return std::vector<bool>(keys, true);
  const size_t grid = meta.expansion->grid.size();
  std::vector<bool> zipped(keys, false);
  for (size_t k = grid; k < keys && index >= grid; ++k) zipped[k] = k != index;
  return zipped;
}

FollowingKeys KeysFollowing(const std::vector<Cell>& cells, size_t keys, int index) {
  FollowingKeys out(keys);
  if (index < 0) return out;
  const auto si = static_cast<size_t>(index);
  std::vector<const std::vector<std::string>*> rows;
  for (const Cell& c : cells) rows.push_back(&c.values);
  for (size_t k = 0; k < keys; ++k) {
    if (k != si) out[k] = ValuesFollowing(rows, si, k);
  }
  return out;
}

Layout LayoutOf(const std::vector<Cell>& cells, const StoreMeta& meta) {
  const std::vector<std::string>& keys = meta.swept_keys;
  const auto key_index = [&](const std::string& k) -> int {
    const auto it = std::find(keys.begin(), keys.end(), k);
    return it == keys.end() ? -1 : static_cast<int>(it - keys.begin());
  };
  Layout layout;
  layout.x_index = key_index(meta.report.x);
  const int x_index = layout.x_index;
  const int series_index = key_index(meta.report.series);
  // Lines: every combination of the swept keys other than x (the series key
  // and any other swept key), labelled "value" or "key=value, ...".
  // Keys swept over a single value do not split lines.
  std::vector<bool> varies(keys.size(), false);
  for (const Cell& c : cells) {
    for (size_t k = 0; k < keys.size(); ++k)
      varies[k] = varies[k] || c.values[k] != cells.front().values[k];
  }
  // Nor do keys whose value follows from x's (zipped with it: they move
  // along the line with x), nor those that follow the series value (it names
  // the line).
  const FollowingKeys follow_x = KeysFollowing(cells, keys.size(), x_index);
  const FollowingKeys follow_series = KeysFollowing(cells, keys.size(), series_index);
  for (size_t k = 0; k < keys.size(); ++k) {
    if (follow_x[k] || follow_series[k]) varies[k] = false;
  }
  const auto line_label = [&](const Cell& c) {
    std::vector<std::string> parts;
    if (series_index >= 0) parts.push_back(c.values[series_index]);
    for (size_t k = 0; k < keys.size(); ++k) {
      if (static_cast<int>(k) == x_index || static_cast<int>(k) == series_index || !varies[k])
        continue;
      parts.push_back(keys[k] + "=" + c.values[k]);
    }
    return parts.empty() ? std::string("all") : fmt::format("{}", fmt::join(parts, ", "));
  };
  for (const Cell& c : cells) {
    const std::string label = line_label(c);
    if (!layout.line_cells.count(label)) layout.lines.push_back(label);
    layout.line_cells[label].push_back(&c);
  }

  // x positions: numbers when every x value is one, else category indices.
  for (const Cell& c : cells) {
    const std::string v = x_index >= 0 ? c.values[x_index] : "";
    if (std::find(layout.x_values.begin(), layout.x_values.end(), v) == layout.x_values.end())
      layout.x_values.push_back(v);
  }
  bool numeric_x = x_index >= 0;
  double x_min = std::numeric_limits<double>::infinity(), x_max = -x_min;
  for (const std::string& v : layout.x_values) {
    const auto d = ParseNumber(v);
    if (!d) {
      numeric_x = false;
      break;
    }
    x_min = std::min(x_min, *d);
    x_max = std::max(x_max, *d);
  }
  if (!meta.report.x_metric.empty()) {
    // Cells placed at a measured value: always a number axis.
    layout.x_metric = meta.report.x_metric;
    numeric_x = true;
    x_min = std::numeric_limits<double>::infinity();
    x_max = -x_min;
    for (const Cell& c : cells) {
      const double x = layout.XPosition(c);
      if (std::isnan(x)) continue;
      x_min = std::min(x_min, x);
      x_max = std::max(x_max, x);
    }
  }
  // No cell has a value (or no cell at all: a store stopped before its first
  // run; until 2026-12-06 a particle-count x then gave gnuplot "set xrange
  // [nan:nan]" on a log axis, and the report failed: an audit).
  if (!(x_min <= x_max)) x_min = x_max = 0.0;
  // Log axis for particle counts, and for any positive x spanning >= 20x.
  layout.log_x =
      numeric_x && x_min > 0 && (meta.report.x.ends_with("particles") || x_max / x_min >= 20.0);
  layout.numeric_x = numeric_x;
  layout.x_min = x_min;
  layout.x_max = x_max;
  layout.x_label = meta.report.x.empty() ? "run" : meta.report.x;
  layout.x_title = layout.x_label;
  if (const CatalogueMetric* m = FindMetric(meta.report.x_metric)) {
    layout.x_label = fmt::format("{}{}{} ({}; mean per cell, lines follow {})", m->label,
                                 m->unit.empty() ? "" : ", ", m->unit, m->name, meta.report.x);
    layout.x_title = m->name;
  }
  return layout;
}

// A cell's per-seed values of `metric` (the faint points behind a plot's
// means): each seed's mean over its finished runs (SeedMean; one run's
// value without pooled keys), finite, in order of first appearance. They
// are the values the cell's band is over.
std::vector<double> SeedValues(const Cell& c, const std::string& metric) {
  std::vector<double> out;
  for (const auto& seed_runs : OkRunsBySeed(c.runs)) {
    const double v = SeedMean(seed_runs, metric, c.pooled_values);
    if (std::isfinite(v)) out.push_back(v);
  }
  return out;
}

// The smallest and largest value the plots of `metric` laid out by
// `layouts` draw (means, band edges and, with `seeds`, every seed's value of
// the cells with an x position, as PlotSvg draws them): ±infinity when none.
std::pair<double, double> DrawnRange(const std::vector<Layout>& layouts, const std::string& metric,
                                     bool seeds) {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();
  for (const Layout& layout : layouts) {
    for (const std::string& line : layout.lines) {
      for (const Cell* c : layout.line_cells.at(line)) {
        const auto it = c->stats.find(metric);
        if (std::isnan(layout.XPosition(*c)) || it == c->stats.end() || it->second.n == 0) {
          continue;
        }
        for (const double v : {it->second.mean, it->second.lower, it->second.upper}) {
          if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
        }
        if (!seeds) continue;
        for (const double v : SeedValues(*c, metric)) lo = std::min(lo, v), hi = std::max(hi, v);
      }
    }
  }
  return {lo, hi};
}

// Where a plot of means draws each line's per-run points: for line l,
// {centre, width} of its slot, an offset from the cell's x (on a log axis in
// natural-log units, x · e^offset). The lines share a strip half as wide as
// the smallest gap between two x positions (capped on a log axis), each its own slot of it, so the
// points of two lines at one x do not fall on each other; a line's runs
// spread evenly over 80 % of its slot, in run order (deterministic).
std::vector<std::vector<double>> SeedOffsets(const Layout& layout) {
  std::vector<double> positions;
  for (const std::string& line : layout.lines) {
    for (const Cell* c : layout.line_cells.at(line)) {
      const double x = layout.XPosition(*c);
      if (std::isnan(x) || (layout.log_x && x <= 0.0)) continue;
      positions.push_back(layout.log_x ? std::log(x) : x);
    }
  }
  std::sort(positions.begin(), positions.end());
  double gap = std::numeric_limits<double>::infinity();
  for (size_t i = 1; i < positions.size(); ++i) {
    if (positions[i] > positions[i - 1]) gap = std::min(gap, positions[i] - positions[i - 1]);
  }
  // One x position: the axis spans x/2 to 2x (log) or x ± 1 (PlotSvg).
  if (!std::isfinite(gap)) gap = layout.log_x ? std::log(2.0) : 1.0;
  // On a log axis at most 2 ln 1.3 wide, so the points stay within a factor
  // 1.3 of their x and inside the axis's 1.4 past the ends (a review: with
  // 100 and 1000 the strip reached 0.61x to 1.64x, past the range).
  const double strip = layout.log_x ? std::min(0.5 * gap, 2.0 * std::log(1.3)) : 0.5 * gap;
  const auto lines = static_cast<double>(std::max<size_t>(layout.lines.size(), 1));
  std::vector<std::vector<double>> out;
  for (size_t l = 0; l < layout.lines.size(); ++l) {
    const double centre = ((static_cast<double>(l) + 0.5) / lines - 0.5) * strip;
    out.push_back({centre, 0.8 * strip / lines});
  }
  return out;
}

// Stage 3, plots: one inline SVG per metric (gnuplot on files in `work`).
// `panel` ("" = none) is added to the title: "key = value" of report.panels.
// `reference` ("" = a plot of the cells' means) makes it a plot of paired
// differences against that series value: the cells are PairedCells (their
// stats the differences), with a zero line.
// `y_range`: the values to fit the y axis to (a metric's panels share one,
// so a bump of 0.05 in one does not look as tall as a gap of 0.6 in
// another: an audit); by default the plot's own.
std::string PlotSvg(const Layout& layout, const std::string& metric, const std::string& p,
                    const fs::path& work, const std::string& gnuplot, const std::string& panel = "",
                    const std::string& reference = "",
                    std::optional<std::pair<double, double>> y_range = std::nullopt) {
  const auto& lines = layout.lines;
  const auto& x_values = layout.x_values;
  const bool numeric_x = layout.numeric_x;
  const bool log_x = layout.log_x;
  const double x_min = layout.x_min;
  const double x_max = layout.x_max;
  const std::string& x_label = layout.x_label;
  const fs::path data = work / fmt::format("plot_{}.dat", p);
  const fs::path svg = work / fmt::format("plot_{}.svg", p);
  const fs::path script = work / fmt::format("plot_{}.gp", p);
  std::string text;
  std::vector<bool> has_data(lines.size(), false);
  // The smallest and largest value drawn (means and band edges), for the y axis.
  double y_min = std::numeric_limits<double>::infinity();
  double y_max = -std::numeric_limits<double>::infinity();
  // Cells with values of the metric but none of report.x_metric, which
  // places them: an empty plot then names the x axis's metric, not the one
  // drawn (a panel of runs that do not measure it: an audit).
  // Cells placed but without the metric: with unplaced ones the message
  // names both (it named the x axis alone: a review).
  bool unplaced = false, placed_without_metric = false;
  for (size_t l = 0; l < lines.size(); ++l) {
    std::vector<std::pair<double, const Cell*>> points;
    for (const Cell* c : layout.line_cells.at(lines[l])) {
      const double x = layout.XPosition(*c);
      if (!std::isnan(x)) {
        points.push_back({x, c});
        placed_without_metric = placed_without_metric || c->stats.at(metric).n == 0;
      } else if (!layout.x_metric.empty() && c->stats.at(metric).n > 0) {
        unplaced = true;
      }
    }
    // A measured x (x_metric) keeps the order of the swept values along the
    // line; otherwise points go left to right.
    if (layout.x_metric.empty()) {
      std::sort(points.begin(), points.end(),
                [](const auto& a, const auto& b) { return a.first < b.first; });
    }
    text += fmt::format("# {}\n", lines[l]);
    for (const auto& [x, c] : points) {
      const Interval& s = c->stats.at(metric);
      if (s.n == 0) continue;
      has_data[l] = true;
      for (const double v : {s.mean, s.lower, s.upper}) {
        if (std::isfinite(v)) y_min = std::min(y_min, v), y_max = std::max(y_max, v);
      }
      text +=
          fmt::format("{} {} {} {}\n", Number(x), Number(s.mean), Number(s.lower), Number(s.upper));
    }
    // gnuplot needs at least one row per index block.
    if (!has_data[l]) text += "nan nan nan nan\n";
    text += "\n\n";
  }
  WriteTextFile(data.string(), text);
  // A plot of means also shows every seed's value (an audit: a cell of IDF1
  // 0.953 [0.91, 1.0] was most seeds at 1 and a few far below, which a mean
  // and its interval cannot show): faint points spread sideways around the
  // cell's x (SeedOffsets), behind the bands and lines.
  const bool difference = !reference.empty();
  const fs::path seeds_data = work / fmt::format("plot_{}_seeds.dat", p);
  bool any_seed = false, pooled_runs = false;
  if (!difference) {
    const std::vector<std::vector<double>> offsets = SeedOffsets(layout);
    std::string seeds;
    for (size_t l = 0; l < lines.size(); ++l) {
      bool any = false;
      for (const Cell* c : layout.line_cells.at(lines[l])) {
        const double x = layout.XPosition(*c);
        if (std::isnan(x)) continue;
        const std::vector<double> values = SeedValues(*c, metric);
        pooled_runs = pooled_runs || c->pooled_values > 1;
        for (size_t k = 0; k < values.size(); ++k) {
          // Seed k of n, in line l's slot of the strip around x.
          const double slot = offsets[l][0], width = offsets[l][1];
          const double offset =
              slot +
              ((static_cast<double>(k) + 0.5) / static_cast<double>(values.size()) - 0.5) * width;
          seeds += fmt::format("{} {}\n", Number(log_x ? x * std::exp(offset) : x + offset),
                               Number(values[k]));
          y_min = std::min(y_min, values[k]);
          y_max = std::max(y_max, values[k]);
          any = true;
        }
      }
      if (!any) seeds += "nan nan\n";
      seeds += "\n\n";
      any_seed = any_seed || any;
    }
    WriteTextFile(seeds_data.string(), seeds);
  }
  // A plot of differences rings its findings (Cell::finding): an open
  // circle for a finding, an open square for one Holm's correction keeps (an
  // audit: the plots did not say which points the tables colour).
  const fs::path findings_data = work / fmt::format("plot_{}_findings.dat", p);
  std::array<bool, 2> any_finding{false, false};
  if (difference) {
    std::array<std::string, 2> blocks;
    for (const std::string& line : lines) {
      for (const Cell* c : layout.line_cells.at(line)) {
        const double x = layout.XPosition(*c);
        const auto f = c->finding.find(metric);
        if (std::isnan(x) || f == c->finding.end() || f->second == 0) continue;
        const auto k = static_cast<size_t>(f->second - 1);
        blocks[k] += fmt::format("{} {}\n", Number(x), Number(c->stats.at(metric).mean));
        any_finding[k] = true;
      }
    }
    WriteTextFile(findings_data.string(), (any_finding[0] ? blocks[0] : "nan nan\n") + "\n\n" +
                                              (any_finding[1] ? blocks[1] : "nan nan\n") + "\n\n");
  }

  std::string gp;
  gp += SvgTerminal(820, "440");
  gp += fmt::format("set output {}\n", GpString(svg.string()));
  // Titles and axes from the metric catalogue: "hijack rate (hijack_rate)",
  // "tracker time per frame, ms (ms_per_frame)".
  const CatalogueMetric* entry = FindMetric(metric);
  const std::string described =
      entry == nullptr ? metric
                       : fmt::format("{}{}{} ({})", entry->label, entry->unit.empty() ? "" : ", ",
                                     entry->unit, metric);
  // A long title goes on two lines: centred over the plot, one line ran past
  // the SVG's left edge and lost its start ("aired difference against ...":
  // an audit).
  const std::string what =
      (difference ? "paired difference against " + reference + ": " : "") + described;
  const std::string against =
      "vs " + layout.x_title + (panel.empty() ? std::string() : ", " + panel);
  gp += fmt::format("set title {} noenhanced\n",
                    what.size() + against.size() + 1 > 70
                        ? GpString(what) + " . \"\\n\" . " + GpString(against)
                        : GpString(what + " " + against));
  gp += fmt::format("set xlabel {} noenhanced\n", GpString(x_label));
  const std::string interval = difference ? "mean of per-seed differences, 95% t CI"
                               : entry != nullptr && entry->range.proportion
                                   ? "mean over seeds, 95% Wilson CI"
                                   : "mean over seeds, 95% t CI";
  // A difference's label names the metric by its short name: the long one
  // and the explanation do not fit beside a 440 px plot.
  gp += fmt::format("set ylabel {} noenhanced\n",
                    GpString(difference ? fmt::format("difference in {}; {}", metric, interval)
                                        : described + "; " + interval));
  size_t longest_label = 0;
  for (const std::string& l : lines) longest_label = std::max(longest_label, l.size());
  // Long line labels go below the plot so they do not squeeze it.
  gp += longest_label > 24 ? "set grid\nset key below noenhanced\n"
                           : "set grid\nset key outside right top noenhanced\n";
  gp += "set style fill transparent solid 0.18 noborder\n";
  if (log_x) gp += "set logscale x\n";
  // A logarithmic y axis when every value drawn is positive and they span
  // more than 20x (a camera-motion error of 2.3 px beside ones of 0.07 px:
  // on a linear axis the small ones are one line at the bottom). Not for
  // differences, which change sign.
  if (y_range) std::tie(y_min, y_max) = *y_range;
  if (difference) y_min = std::min(y_min, 0.0), y_max = std::max(y_max, 0.0);  // the zero line
  const bool log_y = !difference && y_min > 0.0 && y_max / y_min > 20.0;
  if (log_y) gp += "set logscale y\n";
  // The y axis reaches a little past what is drawn, so a line on a bound
  // (every seed at 1) is not drawn on the plot's frame (an audit).
  if (std::isfinite(y_min) && std::isfinite(y_max)) {
    const double span = y_max - y_min;
    // At least 0.05 % of the values' size: the bounds are written to six
    // significant digits, and values that differ past them (a similarity
    // floor of 0.06562598 and 0.06562599 px over seeds) gave a range of one
    // number, which gnuplot refuses, failing the report (an audit).
    const double magnitude = std::max(std::abs(y_min), std::abs(y_max));
    const double pad = span > 0.0 ? std::max(0.04 * span, 5e-4 * magnitude)
                                  : 0.05 * std::max(std::abs(y_max), 1.0);
    gp += log_y ? fmt::format("set yrange [{}:{}]\n", Number(y_min / 1.15), Number(y_max * 1.15))
                : fmt::format("set yrange [{}:{}]\n", Number(y_min - pad), Number(y_max + pad));
  }
  if (!numeric_x) {
    std::string tics;
    for (size_t i = 0; i < x_values.size(); ++i) {
      tics += fmt::format("{}{} {}", i ? ", " : "", GpString(x_values[i]), i);
    }
    // As written: gnuplot's enhanced text drew detections_mixture with a
    // subscript m (an audit).
    gp += fmt::format("set xtics ({}) noenhanced\nset xrange [-0.5:{}]\n", tics,
                      x_values.size() - 0.5);
  } else if (x_min == x_max) {
    gp += fmt::format("set xrange [{}:{}]\n", Number(log_x ? x_min / 2 : x_min - 1),
                      Number(log_x ? x_max * 2 : x_max + 1));
  } else if (log_x) {
    // Just past the values (with room for the per-run points), not gnuplot's
    // decades: 10 to 10000 for 50 to 5000 (an audit).
    gp += fmt::format("set xrange [{}:{}]\n", Number(x_min / 1.4), Number(x_max * 1.4));
  }
  // Tics at the swept values themselves (50, 100, 200, ... rather than 100
  // and 1000 alone), when there are few and x is not a measured metric.
  if (numeric_x && layout.x_metric.empty() && x_values.size() >= 2 && x_values.size() <= 12) {
    std::string tics;
    for (size_t i = 0; i < x_values.size(); ++i) {
      tics += fmt::format("{}{} {}", i ? ", " : "", GpString(x_values[i]),
                          Number(*ParseNumber(x_values[i])));
    }
    gp += fmt::format("set xtics ({}) noenhanced\n", tics);
  }
  std::vector<std::string> plots;
  if (any_seed) {
    // First, so the bands and lines are drawn over them; one key entry.
    for (size_t l = 0; l < lines.size(); ++l) {
      // gnuplot's #AARRGGBB: AA = 0x99 is 60 % transparent.
      plots.push_back(fmt::format(
          "{} index {} using 1:2 with points pt 7 ps 0.4 lc rgb '#99{}' "
          "notitle",
          GpString(seeds_data.string()), l, kPlotColours[l % std::size(kPlotColours)] + 1));
    }
    plots.push_back(pooled_runs ? "NaN with points pt 7 ps 0.5 lc rgb '#99888888' title 'one seed "
                                  "(its pooled runs averaged)'"
                                : "NaN with points pt 7 ps 0.5 lc rgb '#99888888' title 'one run "
                                  "(seed)'");
  }
  for (size_t l = 0; l < lines.size(); ++l) {
    if (!has_data[l]) continue;
    const char* colour = kPlotColours[l % std::size(kPlotColours)];
    plots.push_back(fmt::format("{} index {} using 1:3:4 with filledcurves lc rgb '{}' notitle",
                                GpString(data.string()), l, colour));
    // A marker shape per line, each smaller than the one before: a line on
    // another (systematic's zeros under charged's) still shows around it.
    constexpr int kPointTypes[] = {7, 5, 9, 13, 11, 3};
    const double point_size = std::max(0.45, 1.0 - 0.15 * static_cast<double>(l));
    plots.push_back(
        fmt::format("{} index {} using 1:2 with linespoints lw 2 pt {} ps {} lc rgb '{}' title {}",
                    GpString(data.string()), l, kPointTypes[l % std::size(kPointTypes)],
                    Number(point_size), colour, GpString(lines[l])));
  }
  if (difference && !plots.empty()) {
    plots.push_back("0 with lines lw 1.5 lc rgb '#222222' dt 2 title 'no difference'");
    if (any_finding[0]) {
      plots.push_back(fmt::format(
          "{} index 0 using 1:2 with points pt 6 ps 2.2 lw 1.5 lc rgb '#222222' title 'finding'",
          GpString(findings_data.string())));
    }
    if (any_finding[1]) {
      plots.push_back(fmt::format(
          "{} index 1 using 1:2 with points pt 4 ps 2.2 lw 2 lc rgb '#222222' title 'kept by Holm'",
          GpString(findings_data.string())));
    }
  }
  if (plots.empty()) {
    // Nothing to draw (no finished run, or no run with this metric: an
    // external tracker has no particle filters to score). An empty frame on a
    // linear axis: [0, 1] is not a range a log axis can take.
    gp += "unset logscale x\nunset logscale y\n" +
          fmt::format(
              "set label 1 {} at graph 0.5, 0.5 center noenhanced\n",
              GpString(!unplaced ? std::string("no values of this metric")
                       : placed_without_metric
                           ? fmt::format("no cell with values of both this metric and {}, the x "
                                         "axis, {}",
                                         layout.x_metric,
                                         panel.empty() ? "in these runs" : "in this panel")
                           : fmt::format("no values of {}, the x axis, {}", layout.x_metric,
                                         panel.empty() ? "in these runs" : "in this panel"))) +
          "plot [0:1] [0:1] NaN notitle\n";
  } else {
    gp += "plot " + fmt::format("{}", fmt::join(plots, ", \\\n     ")) + "\n";
  }
  return RunGnuplotToSvg(gnuplot, script, gp, svg);
}

// The index of report.panels among the swept keys; nullopt without panels
// (or a panel key the sweep does not sweep).
std::optional<size_t> PanelKeyIndex(const StoreMeta& meta) {
  const auto it = std::find(meta.swept_keys.begin(), meta.swept_keys.end(), meta.report.panels);
  if (meta.report.panels.empty() || it == meta.swept_keys.end()) return std::nullopt;
  return static_cast<size_t>(it - meta.swept_keys.begin());
}

// Every plot of `cells`: one per y metric, or with report.panels one per
// metric and value of the panel key (ids <metric> and <metric>-<panel
// index>), each panel laid out from its own cells. Files are named
// plot_<file_prefix><i>; `reference` as for PlotSvg.
std::vector<std::pair<std::string, std::string>> Plots(const std::vector<Cell>& cells,
                                                       const Layout& layout, const StoreMeta& meta,
                                                       const fs::path& work,
                                                       const std::string& gnuplot,
                                                       const std::string& file_prefix,
                                                       const std::string& reference) {
  std::vector<std::pair<std::string, std::string>> svgs;
  const std::optional<size_t> panel_index = PanelKeyIndex(meta);
  if (!panel_index) {
    for (size_t p = 0; p < meta.report.y.size(); ++p) {
      svgs.emplace_back(meta.report.y[p],
                        PlotSvg(layout, meta.report.y[p], fmt::format("{}{}", file_prefix, p), work,
                                gnuplot, "", reference));
    }
    return svgs;
  }
  const size_t panel_key = *panel_index;
  std::vector<std::string> panel_values;
  std::vector<std::vector<Cell>> panel_cells;  // LayoutOf keeps pointers into these
  for (const Cell& c : cells) {
    const std::string& v = c.values[panel_key];
    auto at = std::find(panel_values.begin(), panel_values.end(), v);
    if (at == panel_values.end()) {
      panel_values.push_back(v);
      panel_cells.emplace_back();
      at = panel_values.end() - 1;
    }
    panel_cells[static_cast<size_t>(at - panel_values.begin())].push_back(c);
  }
  std::vector<Layout> panel_layouts;
  for (const std::vector<Cell>& pc : panel_cells) panel_layouts.push_back(LayoutOf(pc, meta));
  size_t p = 0;
  for (const std::string& metric : meta.report.y) {
    // One y range for every panel of the metric.
    const std::pair<double, double> shared =
        DrawnRange(panel_layouts, metric, /*seeds=*/reference.empty());
    for (size_t k = 0; k < panel_values.size(); ++k) {
      svgs.emplace_back(
          fmt::format("{}-{}", metric, k),
          PlotSvg(panel_layouts[k], metric, fmt::format("{}{}", file_prefix, p++), work, gnuplot,
                  fmt::format("{} = {}", meta.report.panels, panel_values[k]), reference, shared));
    }
  }
  return svgs;
}

// summary.csv: one row per cell, every catalogue metric.
std::string SummaryCsv(const std::vector<Cell>& cells, const std::vector<std::string>& keys) {
  std::string csv;
  for (const std::string& k : keys) csv += Csv(k) + ",";
  csv += "runs,failures";
  for (const std::string& m : MetricNames()) {
    csv += fmt::format(",{0}_mean,{0}_lo95,{0}_hi95,{0}_n", m);
  }
  csv += "\n";
  for (const Cell& c : cells) {
    for (const std::string& v : c.values) csv += Csv(v) + ",";
    csv += fmt::format("{},{}", c.runs.size(), c.failures);
    for (const std::string& m : MetricNames()) {
      const Interval& s = c.stats.at(m);
      const bool band = s.method != IntervalMethod::kNone;
      csv += fmt::format(",{},{},{},{}", s.n ? Number(s.mean) : "", band ? Number(s.lower) : "",
                         band ? Number(s.upper) : "", s.n);
    }
    csv += "\n";
  }
  return csv;
}

// Stage 2b, paired comparisons. With report.series, each cell whose series
// value is not the reference is compared with the cell that has the same
// values but the reference series value (same x, same panel, same other
// keys): run against run with the same seed (and, in pooled cells, the same
// pooled values), difference = cell − reference per report.y metric. A
// pooled cell's pairs of one seed are averaged: one pair of means per seed.
// The seed pairs of one comparison whose difference (cell − reference) is
// largest and smallest: the first such pair in the cell's run order. Null
// runs when the comparison has no pair.
struct PairExtremes {
  const RunRecord* max_run = nullptr;
  const RunRecord* max_reference = nullptr;
  double max_difference = kNaN;
  const RunRecord* min_run = nullptr;
  const RunRecord* min_reference = nullptr;
  double min_difference = kNaN;
};

struct PairedRow {
  const Cell* cell = nullptr;
  const Cell* reference = nullptr;
  std::map<std::string, PairedComparison> metrics;  // report.y names
  std::map<std::string, PairExtremes> extremes;     // report.y names
  // The signed-rank p-values adjusted by Holm's method with Tarone's rule
  // over the report's tested comparisons (HolmTaroneAdjusted); NaN for a
  // comparison not tested.
  std::map<std::string, double> holm;
};

struct Paired {
  int series_index = -1;
  std::string reference;  // the reference series value
  // No cell has the reference value (a store's report.reference edited, or
  // a store stopped before its runs): nothing is compared, said so.
  bool reference_absent = false;
  // Whether x or the panels follow the series (zipped with it one to one):
  // then no cell has a partner at its x.
  bool zipped_with_x_or_panels = false;
  // Keys that follow the series value (KeysFollowing): they take the
  // reference's value in the partner cell.
  FollowingKeys follow_series;
  std::vector<PairedRow> rows;
  // The comparisons the report tests (Tested: compared cell × report.y
  // metric with pairs, some of which differ, not a timing): Holm's family.
  // At the correction's first step Tarone's rule counts only `first_step`
  // of them, those whose p can fall below 0.05 / tarone_k (TaroneFamilyOf
  // over their SignedRankFloor(nonzero)); first_step == 0: none can be kept.
  int tested = 0;
  // Of them, those whose p can fall below 0.05 at all (SignedRankFloor of
  // their nonzero differences): the only ones chance can make findings.
  int can_reach = 0;
  int first_step = 0;
  int tarone_k = 0;
  // Tested comparisons outside that first-step family whose seed pairs are
  // too few whatever the ties (SignedRankFloor(pairs) >= 0.05 / tarone_k),
  // the most pairs among them, and the pairs that would bring every
  // comparison in (PairsForHolm(tested)).
  int holm_unreachable = 0;
  int unreachable_pairs = 0;
  int pairs_for_holm = 0;
  // Tested comparisons outside it with the pairs but too few of them that
  // differ (tied seeds leave the signed-rank test): fewer than
  // nonzero_for_family (PairsForHolm(tarone_k)).
  int holm_tied_out = 0;
  int nonzero_for_family = 0;
  // Of those outside it (unreachable or tied out), the ones that can be
  // kept at a later step, after enough others: kept where every p is at its
  // floor (the correction keeps more as any p falls, and up to 30 pairs a
  // floor is reached when every seed differs the same way). The others
  // cannot be kept at any step.
  int holm_later = 0;
  // Comparisons (not timings) whose every pair ties (EveryPairTies): not
  // tested, outside the family.
  int every_pair_ties = 0;
  std::vector<std::string> tied_metrics;  // their metrics, in order of first appearance
};

// Whether every seed pair of a comparison has the same value (within
// rounding): a detector's metric across tracker settings that share its
// cached detections, say. No test can find a difference there (the
// signed-rank test has no nonzero difference), so it is not tested and not
// one of Holm's family: an audit found det_recall's 7 comparisons of
// "Δ 0 [0, 0] 0/0/10, p = 1.000" making the correction stricter for the 35
// that could differ.
bool EveryPairTies(const PairedComparison& c) { return c.pairs > 0 && c.test.nonzero == 0; }

// Whether the report tests a comparison (its p-value enters Holm's family):
// it has pairs, some of which differ, and its metric is not a timing.
bool Tested(const PairedComparison& c, const std::string& metric) {
  return c.pairs > 0 && !EveryPairTies(c) && !MachineDependent(metric);
}

Paired PairedRowsOf(const std::vector<Cell>& cells, const StoreMeta& meta) {
  Paired paired;
  const auto& keys = meta.swept_keys;
  const auto it = std::find(keys.begin(), keys.end(), meta.report.series);
  if (meta.report.series.empty() || it == keys.end() || cells.empty()) return paired;
  paired.series_index = static_cast<int>(it - keys.begin());
  const auto si = static_cast<size_t>(paired.series_index);
  // Expansion order puts every key's first value in the first cell.
  paired.reference =
      meta.report.reference.empty() ? cells.front().values[si] : meta.report.reference;
  std::map<std::vector<std::string>, const Cell*> by_values;
  for (const Cell& c : cells) by_values.emplace(c.values, &c);
  paired.reference_absent = std::none_of(
      cells.begin(), cells.end(), [&](const Cell& c) { return c.values[si] == paired.reference; });
  // Keys that follow the series value take the reference's value in the
  // partner cell (an external tracker's cells pair with the reference
  // particle filter's, whose tracker.type and command differ).
  paired.follow_series = KeysFollowing(cells, keys.size(), paired.series_index);
  // A comparison sets two cells at one x, and in one panel, apart: x and the
  // panels never follow the series. Zipped with it one to one, they did, and
  // charged at 100 particles was compared with systematic at 50, filed
  // under 100 (an audit of valid input); such a cell has no partner now.
  for (const std::string& key : {meta.report.x, meta.report.panels}) {
    const auto at = std::find(keys.begin(), keys.end(), key);
    if (key.empty() || at == keys.end() || !paired.follow_series[at - keys.begin()]) continue;
    paired.follow_series[at - keys.begin()].reset();
    paired.zipped_with_x_or_panels = true;
  }
  const FollowingKeys& follow_series = paired.follow_series;
  // The keys a run's partner may differ in: the series and the keys that
  // follow it. A pooled key reads "all" in every cell, so KeysFollowing
  // finds it following the series; the runs of the two cells compared
  // decide instead: it is cleared where their values follow the series,
  // else each run pairs with the reference's run of the same pooled value
  // (until 2026-12-06 every run of a seed paired with the reference's
  // first: an audit). A store that records its expansion clears only a
  // pooled key zipped with the series: a grid key never follows it, though
  // the runs of a partial store (each series value at one pooled value) can
  // look as if it did (a review). Decided per comparison (until 2026-12-06
  // once over the store: a pooled key zipped with x and the series follows
  // the series at each x, not over all of them).
  const std::vector<bool> pooled = PooledKeys(meta);
  const std::vector<bool> zipped_with_series = ZippedWith(meta, si);
  const auto cleared_between = [&](const Cell& c, const Cell& reference) {
    std::vector<const std::vector<std::string>*> run_values;
    for (const Cell* cell : {&c, &reference}) {
      for (const RunRecord* r : cell->runs) {
        if (r->values.size() == keys.size()) run_values.push_back(&r->values);
      }
    }
    std::vector<bool> cleared(keys.size(), false);
    for (size_t j = 0; j < keys.size() && j < follow_series.size(); ++j) {
      cleared[j] =
          follow_series[j].has_value() &&
          (!pooled[j] || (zipped_with_series[j] && ValuesFollowing(run_values, si, j).has_value()));
    }
    return cleared;
  };
  for (const Cell& c : cells) {
    if (c.values[si] == paired.reference) continue;
    std::vector<std::string> ref_values = c.values;
    ref_values[si] = paired.reference;
    for (size_t k = 0; k < keys.size(); ++k) {
      if (!follow_series[k]) continue;
      const auto at = follow_series[k]->find(paired.reference);
      if (at != follow_series[k]->end()) ref_values[k] = at->second;
    }
    const auto ref = by_values.find(ref_values);
    if (ref == by_values.end()) continue;
    // A run's partner key: its values without the series value (and the
    // keys that follow it), and its seed.
    const std::vector<bool> cleared = cleared_between(c, *ref->second);
    const auto pair_key = [&](const RunRecord& r) {
      std::vector<std::string> k = r.values;
      if (si < k.size()) k[si].clear();
      for (size_t j = 0; j < k.size() && j < cleared.size(); ++j) {
        if (cleared[j]) k[j].clear();
      }
      k.push_back(std::to_string(r.seed));
      return k;
    };
    std::map<std::vector<std::string>, const RunRecord*> partner;
    for (const RunRecord* r : ref->second->runs) {
      if (r->ok) partner.emplace(pair_key(*r), r);
    }
    PairedRow row{&c, ref->second, {}, {}, {}};
    for (const std::string& m : meta.report.y) {
      // Per seed, the run pairs whose values are both finite (in a pooled
      // cell, one pair per pooled value; else one): the test and the band
      // take one pair of means per seed, its independent unit, and only
      // from a seed with such a pair at every pooled value (MeanOfSeed).
      struct SeedPairs {
        std::vector<double> a, b;
      };
      std::vector<SeedPairs> seeds;
      std::map<uint64_t, size_t> seed_at;
      struct RunPair {
        size_t seed;
        const RunRecord* run;
        const RunRecord* reference;
        double difference;
      };
      std::vector<RunPair> run_pairs;  // in the cell's run order
      for (const RunRecord* r : c.runs) {
        if (!r->ok) continue;
        const auto p = partner.find(pair_key(*r));
        if (p == partner.end()) continue;
        const auto [at, inserted] = seed_at.emplace(r->seed, seeds.size());
        if (inserted) seeds.emplace_back();
        const double va = r->metrics.at(m), vb = p->second->metrics.at(m);
        // Pairs as ComparePaired counts them: both values finite.
        if (!std::isfinite(va) || !std::isfinite(vb)) continue;
        seeds[at->second].a.push_back(va);
        seeds[at->second].b.push_back(vb);
        run_pairs.push_back({at->second, r, p->second, va - vb});
      }
      std::vector<double> a, b;
      for (const SeedPairs& seed : seeds) {
        a.push_back(MeanOfSeed(seed.a, c.pooled_values));
        b.push_back(MeanOfSeed(seed.b, c.pooled_values));
      }
      // The extremes among the run pairs of the seeds the test counts.
      PairExtremes& extremes = row.extremes[m];
      for (const RunPair& pair : run_pairs) {
        if (!std::isfinite(a[pair.seed])) continue;
        const double d = pair.difference;
        if (extremes.max_run == nullptr || d > extremes.max_difference) {
          extremes.max_run = pair.run;
          extremes.max_reference = pair.reference;
          extremes.max_difference = d;
        }
        if (extremes.min_run == nullptr || d < extremes.min_difference) {
          extremes.min_run = pair.run;
          extremes.min_reference = pair.reference;
          extremes.min_difference = d;
        }
      }
      const CatalogueMetric* entry = FindMetric(m);
      row.metrics[m] = ComparePaired(a, b, entry ? entry->range : MetricRange::Unbounded());
    }
    paired.rows.push_back(std::move(row));
  }
  // Holm over the whole family: a report of 8 cells and 7 metrics makes 56
  // tests, and chance alone makes about 3 of them findings at p < 0.05.
  // Timings and comparisons whose every pair ties are not tested (Tested).
  // Each step of the correction counts only the comparisons left whose p
  // can still reach its level (Tarone's rule over the signed-rank floors of
  // their nonzero differences): the others would only make it stricter.
  std::vector<double> p, floors;
  for (const PairedRow& row : paired.rows) {
    for (const std::string& m : meta.report.y) {
      const PairedComparison& c = row.metrics.at(m);
      const bool tested = Tested(c, m);
      p.push_back(tested ? c.test.p_value : kNaN);
      floors.push_back(tested ? SignedRankFloor(c.test.nonzero) : kNaN);
      paired.tested += tested ? 1 : 0;
      paired.can_reach += floors.back() < 0.05 ? 1 : 0;  // NaN (untested) is not below
      if (EveryPairTies(c) && !MachineDependent(m)) {
        ++paired.every_pair_ties;
        if (std::find(paired.tied_metrics.begin(), paired.tied_metrics.end(), m) ==
            paired.tied_metrics.end()) {
          paired.tied_metrics.push_back(m);
        }
      }
    }
  }
  const TaroneFamily family = TaroneFamilyOf(floors, 0.05);
  paired.first_step = family.size;
  paired.tarone_k = family.k;
  const std::vector<double> adjusted = HolmTaroneAdjusted(p, floors, 0.05);
  const std::vector<double> at_floors = HolmTaroneAdjusted(floors, floors, 0.05);
  size_t next = 0;
  for (PairedRow& row : paired.rows) {
    for (const std::string& m : meta.report.y) row.holm[m] = adjusted[next++];
  }
  if (paired.tested > 0) {
    paired.pairs_for_holm = PairsForHolm(paired.tested, 0.05);
    paired.nonzero_for_family = PairsForHolm(family.k, 0.05);
    next = 0;
    for (const PairedRow& row : paired.rows) {
      for (const std::string& m : meta.report.y) {
        const PairedComparison& c = row.metrics.at(m);
        const size_t i = next++;
        if (!Tested(c, m) || family.member[i]) continue;
        if (at_floors[i] < 0.05) ++paired.holm_later;
        if (SignedRankFloor(c.pairs) < 0.05 / family.k) {
          ++paired.holm_tied_out;
          continue;
        }
        ++paired.holm_unreachable;
        paired.unreachable_pairs = std::max(paired.unreachable_pairs, c.pairs);
      }
    }
  }
  return paired;
}

// Whether a paired comparison is a finding: better or worse than the
// reference in the metric's direction, with both the signed-rank test
// (p < 0.05) and the t interval of the differences (excluding 0) saying so.
// A timing is never one (MachineDependent: an audit found "charged is
// significantly faster at 50 particles" in a rendered sweep whose first
// cell, systematic at 50, rendered the frames while it tracked).
enum class PairedVerdict { kNotSignificant, kBetter, kWorse };

// The side the signed-rank test points to: +1 when W+ is above its centre
// n(n+1)/4 under no difference (the positive differences rank higher), -1
// below, 0 at it. Its p is two-sided, so it says "differs" whichever side.
int TestSide(const SignedRankTest& test) {
  const double centre = test.nonzero * (test.nonzero + 1.0) / 4.0;
  return test.w_plus > centre ? 1 : test.w_plus < centre ? -1 : 0;
}

PairedVerdict VerdictOf(const PairedComparison& c, const std::string& metric) {
  if (c.pairs == 0 || MachineDependent(metric)) return PairedVerdict::kNotSignificant;
  const CatalogueMetric* entry = FindMetric(metric);
  const bool higher_better = entry == nullptr || entry->higher_is_better;
  const bool excludes_zero = c.difference.method != IntervalMethod::kNone &&
                             (c.difference.lower > 0.0 || c.difference.upper < 0.0);
  if (!(c.test.p_value < 0.05 && excludes_zero)) return PairedVerdict::kNotSignificant;
  // Both must say the same way: a few large differences against many small
  // ones of the other sign can put the mean (and the t interval) on one
  // side and the ranks on the other; that is no finding (a review: 34 seeds
  // +0.01, 6 seeds -0.5 were "worse" with a p that said "better").
  const int side = c.difference.mean > 0.0 ? 1 : -1;
  if (TestSide(c.test) != side) return PairedVerdict::kNotSignificant;
  return (side > 0) == higher_better ? PairedVerdict::kBetter : PairedVerdict::kWorse;
}

// A finding (VerdictOf) whose Holm-adjusted p is below 0.05 too: it stays a
// finding when every comparison of the report is tested at once.
bool SurvivesHolm(const PairedRow& row, const std::string& metric) {
  return VerdictOf(row.metrics.at(metric), metric) != PairedVerdict::kNotSignificant &&
         row.holm.at(metric) < 0.05;
}

// The paired rows as cells whose stats are the differences (the series value
// reading "value − reference"), for PlotSvg; with x_metric they sit where
// the compared cell does.
std::vector<Cell> DifferenceCells(const Paired& paired, const StoreMeta& meta) {
  std::vector<Cell> out;
  for (const PairedRow& row : paired.rows) {
    Cell d = *row.cell;
    d.values[static_cast<size_t>(paired.series_index)] += " \u2212 " + paired.reference;
    d.stats.clear();
    for (const auto& [m, c] : row.metrics) {
      d.stats[m] = c.difference;
      d.finding[m] = SurvivesHolm(row, m) ? 2 : VerdictOf(c, m) != PairedVerdict::kNotSignificant;
    }
    if (!meta.report.x_metric.empty()) {
      const Interval& at = row.cell->stats.at(meta.report.x_metric);
      d.x_at = at.n > 0 ? at.mean : kNaN;
    }
    out.push_back(std::move(d));
  }
  return out;
}

// "a, b and c".
std::string JoinWords(const std::vector<std::string>& words) {
  std::string out;
  for (size_t i = 0; i < words.size(); ++i) {
    if (i > 0) out += i + 1 == words.size() ? " and " : ", ";
    out += words[i];
  }
  return out;
}

// Said where the report's metrics include a timing: what is done with it.
std::string TimingsNote(const StoreMeta& meta) {
  std::vector<std::string> timings;
  for (const std::string& m : meta.report.y) {
    if (MachineDependent(m)) timings.push_back(m);
  }
  if (timings.empty()) return {};
  return fmt::format(
      " {} {} plotted and tabled but not tested: not coloured, not a finding, not in the family "
      "of comparisons, not replicated. A time depends on the machine's load and on the order "
      "the runs ran in (the first runs of a rendered sweep render the frames that the others "
      "read from the cache), not only on the settings compared.",
      JoinWords(timings), timings.size() == 1 ? "is" : "are");
}

// Said where some comparisons are left untested because every seed pair
// ties (EveryPairTies).
std::string TiesNote(const Paired& paired) {
  if (paired.every_pair_ties == 0) return {};
  return fmt::format(
      " {} {} ({}) {} the same value in every seed pair (a rate of 0 in both, say, or a "
      "detector's metric across tracker settings that read the same detections): no test can "
      "find a difference there, so {} not tested and not counted among the comparisons, where "
      "{} would only make Holm's correction stricter.",
      paired.every_pair_ties, paired.every_pair_ties == 1 ? "comparison" : "comparisons",
      JoinWords(paired.tied_metrics), paired.every_pair_ties == 1 ? "has" : "have",
      paired.every_pair_ties == 1 ? "it is" : "they are",
      paired.every_pair_ties == 1 ? "it" : "they");
}

// What the seed count allows: empty when every tested comparison can reach
// the first step of Holm's correction with Tarone's rule (Paired::family);
// else how many cannot and why: too few seed pairs whatever the data, and
// then the pairs that would let every comparison in, or the pairs but too
// few of them that differ (Paired::holm_tied_out). None in: no comparison
// can be kept; some: the others only after enough are kept before them.
std::string HolmReachNote(const Paired& paired) {
  const int left_out = paired.tested - paired.first_step;
  if (paired.tested == 0 || left_out == 0) return {};
  const int n = paired.unreachable_pairs;
  const double floor = SignedRankFloor(n);
  if (paired.first_step == 0 && paired.holm_tied_out == 0) {
    // Every comparison has too few pairs: the reason in one sentence (its
    // floor is at least 0.05 / K, and K is at most the tested count).
    const std::string needed = fmt::format(
        " At least {} seed pairs per comparison are needed for "
        "Holm's correction to keep one, more for a difference that does not have the same sign "
        "in every seed.",
        paired.pairs_for_holm);
    if (floor >= 0.05) {
      return fmt::format(
                 "With {} seed pairs the signed-rank test cannot give p below {:.3g}: no "
                 "comparison of this report can be a finding, whatever the data.",
                 n, floor) +
             needed;
    }
    return fmt::format(
               "With {} seed pairs the signed-rank test cannot give p below {:.3g}, and Holm's "
               "correction for {} comparisons needs p < {:.3g} for its first (Tarone's rule: K "
               "= {}): no comparison of this report can stay significant after it, whatever the "
               "data.",
               n, floor, paired.tested, 0.05 / paired.tarone_k, paired.tarone_k) +
           needed;
  }
  std::vector<std::string> why;
  if (paired.holm_unreachable > 0) {
    why.push_back(fmt::format(
        "{} with {} seed pairs or fewer, where the signed-rank test cannot give p below {:.3g}",
        paired.holm_unreachable, n, floor));
  }
  if (paired.holm_tied_out > 0) {
    why.push_back(fmt::format(
        "{} with {} seed pairs but fewer than {} where the two differ (a tied seed leaves the "
        "signed-rank test)",
        paired.holm_tied_out, paired.holm_unreachable == 0 ? "enough" : "more",
        paired.nonzero_for_family));
  }
  const std::string rule = fmt::format(
      "p < {:.3g}, the first step's level (Tarone's rule: K = {}, the smallest k with at most k "
      "comparisons whose p can fall below 0.05 / k; docs/sweeps.md, \"Holm's correction\")",
      0.05 / paired.tarone_k, paired.tarone_k);
  // Pairs enough for every comparison to count at the first step whatever
  // the others (each below 0.05 / tested).
  const std::string every = paired.holm_unreachable == 0
                                ? std::string()
                                : fmt::format(
                                      " {} seed pairs per comparison, each differing, "
                                      "would let every comparison count from the first step.",
                                      paired.pairs_for_holm);
  if (paired.first_step == 0) {
    return fmt::format(
               "No comparison of this report can stay significant after Holm's correction, "
               "whatever the data: {} can reach {}: {}.",
               paired.tested == 1 ? std::string("the one comparison cannot")
                                  : fmt::format("none of the {}", paired.tested),
               rule, fmt::join(why, "; ")) +
           every;
  }
  const int later = paired.holm_later, never = left_out - later;
  const std::string after = "can be kept at a later step, after enough others are kept";
  const std::string not_later = "cannot be kept at any step";
  const std::string which =
      never == 0   ? fmt::format("{} {}.", left_out == 1 ? "It" : "They", after)
      : later == 0 ? fmt::format("{} {}.", left_out == 1 ? "It" : "They", not_later)
                   : fmt::format("{} of them {}; {} {}.", later, after, never, not_later);
  return fmt::format(
             "Of the {} comparisons, {} can reach {}. The other {} cannot, whatever the "
             "data: {}. {}",
             paired.tested, paired.first_step, rule,
             left_out == 1 ? std::string("one") : std::to_string(left_out), fmt::join(why, "; "),
             which) +
         every;
}

// The table columns of a list of cells' swept values: every key whose value
// differs among `rows` (each a cell's values), and `always` (-1: none) even
// when it does not; never `skip` (-1: none).
std::vector<size_t> VaryingKeys(const std::vector<const std::vector<std::string>*>& rows,
                                size_t key_count, int skip, int always) {
  std::vector<size_t> shown;
  for (size_t k = 0; k < key_count; ++k) {
    if (static_cast<int>(k) == skip) continue;
    bool varies = static_cast<int>(k) == always;
    for (const std::vector<std::string>* r : rows) varies = varies || (*r)[k] != (*rows.front())[k];
    if (varies) shown.push_back(k);
  }
  return shown;
}

std::string FormatP(double p) {
  if (p < 0.001) return "p&nbsp;&lt;&nbsp;0.001";
  return fmt::format("p&nbsp;=&nbsp;{:.3f}", p);
}

// The builds of hcpf that made a sweep's finished runs, as the store's rows
// record them from each run folder's manifest.json ("<hcpf_version> at
// <git_revision>"; the manifest itself for rows of a store written before
// the build column), with their run counts, and the finished runs whose
// manifest was missing, unreadable or named no build. A sweep resumed after
// a rebuild, grown with --reuse from another build's sweep or merged from
// shards of different builds keeps each run as its build made it.
struct Builds {
  std::map<std::string, int> runs;  // by build
  int unnamed = 0;
};

Builds BuildsOf(const std::vector<RunRecord>& runs, const fs::path& dir) {
  Builds builds;
  for (const RunRecord& r : runs) {
    if (!r.ok) continue;
    // Rows of a store written before it kept the build: the run's manifest.
    const std::string build = r.build ? *r.build : ReadRunBuild((dir / r.run_dir).string());
    if (build.empty()) {
      ++builds.unnamed;
    } else {
      ++builds.runs[build];
    }
  }
  return builds;
}

// The report's sentence on those builds ("" when no run finished).
std::string BuildsHtml(const Builds& all) {
  const std::map<std::string, int>& builds = all.runs;
  const std::string unnamed =
      all.unnamed == 0
          ? std::string()
          : fmt::format(
                "{} finished run{} name{} no build (a <code>manifest.json</code> missing, "
                "unreadable or without <code>git_revision</code>).",
                all.unnamed, all.unnamed == 1 ? "" : "s", all.unnamed == 1 ? "s" : "");
  if (builds.empty()) return unnamed.empty() ? std::string() : "<p>" + unnamed + "</p>\n";
  const std::string tail = unnamed.empty() ? std::string() : " " + unnamed;
  if (builds.size() == 1) {
    return fmt::format(
        "<p>Every finished run that names its build was made by one: hcpf <code>{}</code>.{}</p>\n",
        EscapeMarkup(builds.begin()->first), tail);
  }
  std::vector<std::pair<std::string, int>> by_count(builds.begin(), builds.end());
  std::stable_sort(by_count.begin(), by_count.end(),
                   [](const auto& a, const auto& b) { return a.second > b.second; });
  std::vector<std::string> parts;
  for (const auto& [build, count] : by_count) {
    parts.push_back(fmt::format("<code>{}</code> ({} run{})", EscapeMarkup(build), count,
                                count == 1 ? "" : "s"));
  }
  return fmt::format(
      "<p><strong>The finished runs were made by {} builds of hcpf</strong>: {}. A sweep resumed "
      "after a rebuild, grown with <code>--reuse</code> from another build's sweep, or merged "
      "from shards of different builds keeps each run as its build made it (its "
      "<code>manifest.json</code> names the build), so a change between the builds may be in "
      "these figures: sweep again into a new folder for one build's (docs/sweeps.md, \"Which "
      "builds made the runs\").{}</p>\n",
      builds.size(), fmt::join(parts, ", "), tail);
}

// The seed pairs to look at behind every coloured cell of the paired table:
// the pair whose difference goes furthest in the direction of the mean
// difference, and the pair that goes least far (a counterexample when its
// difference has the other sign), each with the command that sets its two
// runs side by side (hcpf report RUN --against OTHER_RUN). Timings
// (manifest.json metrics) are left out. Folded, since a big sweep has many
// findings.
std::string SeedsToLookAtHtml(const Paired& paired, const StoreMeta& meta,
                              const std::vector<size_t>& shown, const std::string& dir,
                              const std::string& link_prefix) {
  const auto& keys = meta.swept_keys;
  const auto si = static_cast<size_t>(paired.series_index);
  std::string rows;
  int findings = 0, counterexamples = 0;
  // In a pooled report the extremes are run pairs (one seed at one pooled
  // value), named by their pooled values; the test is over the seeds' means.
  const bool pooled = !meta.report.pool.empty();
  const std::vector<bool> pooled_key = PooledKeys(meta);
  const auto pooled_values = [&](const RunRecord* run) {
    std::string out;
    for (size_t k = 0; k < keys.size() && k < run->values.size(); ++k) {
      if (pooled_key[k])
        out += fmt::format(", {} = {}", EscapeMarkup(keys[k]), EscapeMarkup(run->values[k]));
    }
    return out;
  };
  const auto pair_text = [&](const RunRecord* run, const RunRecord* reference, double d,
                             bool against) {
    const auto folder = [&](const RunRecord* r) {
      return ShellWord((fs::path(dir) / r->run_dir).string());
    };
    // A run whose folder is gone (the page says how many) is named, not
    // linked, and has no command to compare it.
    const auto here = [&](const RunRecord* r) { return HasRunFolder(dir, *r); };
    const std::string name = fmt::format("seed index {}{}", run->seed_index, pooled_values(run));
    const std::string tail =
        fmt::format(": &Delta;&nbsp;{:.3g}{}", d, against ? " <b>(against it)</b>" : "");
    if (!here(run) || !here(reference)) return name + tail + " (a folder of the pair is gone)";
    return fmt::format("<a href=\"{}\">{}</a>{}<br><code>hcpf report {} --against {}</code>",
                       EscapeMarkup(link_prefix + run->run_dir), name, tail,
                       EscapeMarkup(folder(run)), EscapeMarkup(folder(reference)));
  };
  for (const PairedRow& row : paired.rows) {
    for (const std::string& m : meta.report.y) {
      const PairedComparison& c = row.metrics.at(m);
      // (A timing is no finding: its extreme seed is the machine's noise.)
      if (VerdictOf(c, m) == PairedVerdict::kNotSignificant) continue;
      const PairExtremes& e = row.extremes.at(m);
      if (e.max_run == nullptr) continue;
      ++findings;
      const bool up = c.difference.mean > 0.0;
      const RunRecord* most_run = up ? e.max_run : e.min_run;
      const RunRecord* most_ref = up ? e.max_reference : e.min_reference;
      const double most = up ? e.max_difference : e.min_difference;
      const RunRecord* least_run = up ? e.min_run : e.max_run;
      const RunRecord* least_ref = up ? e.min_reference : e.max_reference;
      const double least = up ? e.min_difference : e.max_difference;
      const bool against = up ? least < 0.0 : least > 0.0;
      counterexamples += against ? 1 : 0;
      rows += "<tr>";
      for (size_t k : shown)
        rows += "<td class=\"k\">" + EscapeMarkup(row.cell->values[k]) + "</td>";
      rows += fmt::format(
          "<td class=\"k\">{} &minus; {}</td><td class=\"k\">{}</td><td>{:.3g}</td>"
          "<td class=\"k\">{}</td><td class=\"k\">{}</td></tr>\n",
          EscapeMarkup(row.cell->values[si]), EscapeMarkup(paired.reference), EscapeMarkup(m),
          c.difference.mean, pair_text(most_run, most_ref, most, false),
          pair_text(least_run, least_ref, least, against));
    }
  }
  if (findings == 0) return {};
  std::string h = fmt::format(
      "<details id=\"seeds-to-look-at\"><summary><b>Seeds to look at</b>: for {} coloured "
      "cell{}, the {} whose difference goes furthest in the direction of the mean and the "
      "{} that goes least far ({} of them against it: the other sign{}), with the command that "
      "sets the two runs side by side (docs/sweeps.md, \"Two runs side by "
      "side\").</summary>\n<p>That report plays the runs' overlay videos side by side when "
      "both have one (the first seed of each cell under <code>hcpf sweep --video</code>); for "
      "any other run, <code>hcpf run RUN/scenario.resolved.yaml --out NEW --video</code> makes "
      "the same run with one (the same files), and <code>hcpf report NEW --against "
      "OTHER_NEW</code> then shows both.</p>\n<table><tr>",
      findings == 1 ? std::string("the one") : fmt::format("each of the {}", findings),
      findings == 1 ? "" : "s", pooled ? "run pair (one seed at one pooled value)" : "seed",
      pooled ? "run pair" : "seed", counterexamples,
      pooled ? "; the test is over each seed's mean of its pooled runs, so a run pair against "
               "it need not be a seed against it"
             : "");
  for (size_t k : shown) h += "<th>" + EscapeMarkup(keys[k]) + "</th>";
  h += "<th>compared</th><th>metric</th><th>&Delta;</th><th>furthest</th><th>least far</th>"
       "</tr>\n";
  return h + rows + "</table></details>\n";
}

// The section of the page: what is compared, the table, the plots.
std::string PairedHtml(const Paired& paired, const StoreMeta& meta, const Layout& layout,
                       const std::vector<std::pair<std::string, std::string>>& svgs,
                       const std::string& dir, const std::string& link_prefix) {
  if (paired.rows.empty()) return {};
  const auto& keys = meta.swept_keys;
  const auto si = static_cast<size_t>(paired.series_index);
  // Columns: every key that takes several values among the compared cells
  // (x, panels, other keys), then the comparison.
  std::vector<const std::vector<std::string>*> compared;
  for (const PairedRow& r : paired.rows) compared.push_back(&r.cell->values);
  const std::vector<size_t> shown =
      VaryingKeys(compared, keys.size(), paired.series_index, layout.x_index);
  const std::string reach_note = HolmReachNote(paired);
  std::string h = "<h2 id=\"paired\">Paired differences</h2>\n";
  h += fmt::format(
      "<p>Each <code>{0}</code> value minus <code>{1}</code> (the reference: "
      "<code>report.reference</code>{2}), seed by seed: both cells ran the same seeds, so each "
      "seed's difference cancels what the seed does to both. <b>&Delta;</b>: the mean of the "
      "per-seed differences with its 95&nbsp;% t interval (cut to the range a difference can "
      "take, marked &dagger;); <b>n</b>: the pairs (seeds where both runs finished with a "
      "value{8}); <b>+/&minus;/=</b>: pairs where the value is above, below and equal to the "
      "reference's; <b>p</b>: two-sided Wilcoxon signed-rank test on the nonzero differences "
      "(exact up to {3} of them, normal approximation above; with 5 or fewer nonzero "
      "differences p cannot fall below 0.05). Green: better than the reference in the metric's "
      "direction with p&nbsp;&lt;&nbsp;0.05 and an interval that excludes 0; red: worse, "
      "likewise; the test and the interval can disagree (the test uses ranks, the interval the "
      "values), and a cell is coloured only when both say so. {4}{7}{5}{6}</p>\n",
      EscapeMarkup(meta.report.series), EscapeMarkup(paired.reference),
      meta.report.reference.empty() ? ", else the first series value" : "",
      kExactSignedRankMaxPairs,
      paired.tested == 0 ? std::string("This table tests no comparison, so no cell is coloured.")
      : paired.first_step == 0
          ? std::string("<b>Holm</b>: no comparison of this table can reach the p Holm's "
                        "correction needs (below), so no coloured cell stays a finding when all "
                        "are tested at once.")
          : fmt::format(
                "<b>Holm</b>, in coloured cells: p adjusted by Holm's step-down method over the "
                "{0} comparisons of this table (cells &times; metrics with pairs, not every pair "
                "tied), with Tarone's rule: each step multiplies the p not by the count of "
                "comparisons left but by Tarone's K over them, smaller where some cannot reach p "
                "&lt; 0.05 / K (docs/sweeps.md, &quot;Holm's correction&quot;); chance alone makes "
                "about 1 in "
                "20 of them coloured where nothing differs, and a cell whose Holm p is also below "
                "0.05 (in bold) stays a finding when all {0} are tested at once.",
                paired.tested),
      reach_note.empty() ? std::string() : " <b>" + EscapeMarkup(reach_note) + "</b>",
      EscapeMarkup(TimingsNote(meta)), EscapeMarkup(TiesNote(paired)),
      meta.report.pool.empty()
          ? ""
          : " at every pooled value; a seed's value in each cell is the mean of its pooled runs");
  // Scrolled by itself when wider than the page (an audit: 1290 px at 1280).
  h += "<div class=\"wide\"><table><tr>";
  for (size_t k : shown) h += "<th>" + EscapeMarkup(keys[k]) + "</th>";
  h += "<th>compared</th><th>n</th>";
  for (const std::string& m : meta.report.y) h += "<th>" + EscapeMarkup(m) + "</th>";
  h += "</tr>\n";
  for (const PairedRow& row : paired.rows) {
    h += "<tr>";
    for (size_t k : shown) h += "<td class=\"k\">" + EscapeMarkup(row.cell->values[k]) + "</td>";
    int n = 0;
    for (const auto& [m, c] : row.metrics) n = std::max(n, c.pairs);
    h += fmt::format("<td class=\"k\">{} &minus; {}</td><td>{}</td>",
                     EscapeMarkup(row.cell->values[si]), EscapeMarkup(paired.reference), n);
    for (const std::string& m : meta.report.y) {
      const PairedComparison& c = row.metrics.at(m);
      if (c.pairs == 0) {
        h += "<td>&ndash;</td>";
        continue;
      }
      // Both the rank test and the t interval of the differences must say so.
      const PairedVerdict verdict = VerdictOf(c, m);
      const char* style = verdict == PairedVerdict::kBetter  ? " style=\"background:#dff3df\""
                          : verdict == PairedVerdict::kWorse ? " style=\"background:#f8dede\""
                                                             : "";
      std::string text = fmt::format("&Delta;&nbsp;{:.3g}", c.difference.mean);
      if (c.difference.method != IntervalMethod::kNone) {
        // On a line of its own, not broken (an audit: "[-0.00628," and
        // "0.0449]" on two lines).
        text += fmt::format("<br><span class=\"i\">[{:.3g}, {:.3g}]{}</span>", c.difference.lower,
                            c.difference.upper, c.difference.clipped ? "&dagger;" : "");
      }
      text +=
          fmt::format("<br>{}/{}/{}", c.positive, c.negative, c.pairs - c.positive - c.negative);
      if (c.pairs < n) text += fmt::format(" (n&nbsp;=&nbsp;{})", c.pairs);
      text += MachineDependent(m) ? std::string(", not tested")
              : EveryPairTies(c)  ? std::string(", the same in every pair: not tested")
                                  : ", " + FormatP(c.test.p_value);
      if (verdict != PairedVerdict::kNotSignificant) {
        const double holm = row.holm.at(m);
        const std::string value =
            holm < 0.001 ? std::string("&lt;&nbsp;0.001") : fmt::format("{:.3f}", holm);
        text += holm < 0.05 ? ", <b>Holm&nbsp;" + value + "</b>" : ", Holm&nbsp;" + value;
      }
      h += fmt::format("<td{}>{}</td>", style, text);
    }
    h += "</tr>\n";
  }
  h += "</table></div>\n";
  h += SeedsToLookAtHtml(paired, meta, shown, dir, link_prefix);
  for (const auto& [id, svg] : svgs) {
    h += fmt::format("<div class=\"plot\" id=\"difference-{}\">\n{}\n</div>\n", EscapeMarkup(id),
                     svg);
  }
  return h;
}

// paired.csv: one row per comparison and report.y metric.
// A Holm p in a CSV: empty for a comparison not tested.
std::string HolmCsv(double holm) { return std::isnan(holm) ? std::string() : Number(holm); }

std::string PairedCsv(const Paired& paired, const StoreMeta& meta) {
  std::string csv;
  for (const std::string& k : meta.swept_keys) csv += Csv(k) + ",";
  csv +=
      "reference,metric,pairs,mean_difference,lo95,hi95,clipped,positive,negative,ties,"
      "nonzero,w_plus,p_value,exact,p_holm,max_difference,max_run,max_reference_run,"
      "min_difference,min_run,min_reference_run\n";
  for (const PairedRow& row : paired.rows) {
    for (const std::string& m : meta.report.y) {
      const PairedComparison& c = row.metrics.at(m);
      for (const std::string& v : row.cell->values) csv += Csv(v) + ",";
      const bool band = c.difference.method != IntervalMethod::kNone;
      const double holm = row.holm.at(m);
      csv += fmt::format(
          "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}", Csv(paired.reference), m, c.pairs,
          c.pairs ? Number(c.difference.mean) : "", band ? Number(c.difference.lower) : "",
          band ? Number(c.difference.upper) : "", c.difference.clipped ? 1 : 0, c.positive,
          c.negative, c.pairs - c.positive - c.negative, c.test.nonzero, Number(c.test.w_plus),
          // A comparison not tested (a timing, every pair tied): no p-value (a review).
          Tested(c, m) ? Number(c.test.p_value) : std::string(), c.test.exact ? 1 : 0,
          HolmCsv(holm));
      // The pairs to look at: their difference and both runs' keys.
      const PairExtremes& e = row.extremes.at(m);
      csv += e.max_run == nullptr ? std::string(",,,,,,\n")
                                  : fmt::format(",{},{},{},{},{},{}\n", Number(e.max_difference),
                                                Csv(e.max_run->key), Csv(e.max_reference->key),
                                                Number(e.min_difference), Csv(e.min_run->key),
                                                Csv(e.min_reference->key));
    }
  }
  return csv;
}

// Stage 2c, findings: a few sentences generated from the cells and the
// paired rows, so the report says where a series helps and where it does
// not. One sentence per report.y metric and group of cells (the cells that
// share every swept value but x and series: a panel, a pooled cell, ...):
// which series has the best mean at each x, then, per non-reference series,
// the x values where its paired difference against the reference is a
// finding (VerdictOf) for better, for worse, and where it is not.
struct Finding {
  std::string metric;
  std::string group;  // "key = value, ..." of the keys that vary between groups ("" = one group)
  std::string text;   // plain text, no markup
};

// How the findings and their summary group cells: a cell's group is its
// swept values with x, the series and the keys that follow either (zipped
// with it, e.g. an external tracker's command beside its name) cleared.
class FindingsGrouping {
 public:
  FindingsGrouping(const std::vector<Cell>& cells, const Paired& paired, int x_index,
                   size_t key_count)
      : cleared_(key_count, false) {
    const FollowingKeys follow_x = KeysFollowing(cells, key_count, x_index);
    for (size_t j = 0; j < key_count; ++j) {
      cleared_[j] = static_cast<int>(j) == paired.series_index || static_cast<int>(j) == x_index ||
                    paired.follow_series[j] || follow_x[j];
    }
  }
  std::vector<std::string> Of(const Cell& c) const {
    std::vector<std::string> k = c.values;
    for (size_t j = 0; j < k.size() && j < cleared_.size(); ++j) {
      if (cleared_[j]) k[j].clear();
    }
    return k;
  }

 private:
  std::vector<bool> cleared_;
};

// "k = v, k2 = v2": a group's values of the keys that tell the groups
// apart (VaryingKeys of every group).
std::string GroupWords(const std::vector<std::string>& group, const std::vector<size_t>& varying,
                       const std::vector<std::string>& keys) {
  std::vector<std::string> parts;
  for (size_t k : varying) parts.push_back(keys[k] + " = " + group[k]);
  return fmt::format("{}", fmt::join(parts, ", "));
}

std::vector<Finding> FindingsOf(const std::vector<Cell>& cells, const Paired& paired,
                                const StoreMeta& meta, const Layout& layout) {
  std::vector<Finding> findings;
  if (paired.series_index < 0) return findings;
  const auto& keys = meta.swept_keys;
  const auto si = static_cast<size_t>(paired.series_index);
  const int xi = layout.x_index;
  const FindingsGrouping grouping(cells, paired, xi, keys.size());
  std::vector<std::vector<std::string>> groups;
  std::map<std::vector<std::string>, std::vector<const Cell*>> group_cells;
  for (const Cell& c : cells) {
    const auto k = grouping.Of(c);
    if (!group_cells.count(k)) groups.push_back(k);
    group_cells[k].push_back(&c);
  }
  std::vector<const std::vector<std::string>*> group_rows;
  for (const auto& g : groups) group_rows.push_back(&g);
  const std::vector<size_t> varying = VaryingKeys(group_rows, keys.size(), -1, -1);
  const auto x_of = [&](const Cell& c) {
    return xi >= 0 ? c.values[static_cast<size_t>(xi)] : std::string();
  };
  const std::string x_name = xi >= 0 ? keys[static_cast<size_t>(xi)] : std::string();
  const auto at = [&](const std::vector<std::string>& xs) {
    if (xi < 0) return std::string();
    return " at " + x_name + " = " + JoinWords(xs);
  };
  for (const std::string& m : meta.report.y) {
    const CatalogueMetric* entry = FindMetric(m);
    const bool higher_better = entry == nullptr || entry->higher_is_better;
    for (const auto& g : groups) {
      Finding f;
      f.metric = m;
      f.group = GroupWords(g, varying, keys);
      // Best mean per x, the x values collected per winning series value.
      std::vector<std::string> winners;
      std::map<std::string, std::vector<std::string>> won_at;
      std::vector<std::string> xs;
      for (const Cell* c : group_cells[g]) {
        if (std::find(xs.begin(), xs.end(), x_of(*c)) == xs.end()) xs.push_back(x_of(*c));
      }
      for (const std::string& x : xs) {
        const Cell* best = nullptr;
        bool tie = false;
        for (const Cell* c : group_cells[g]) {
          if (x_of(*c) != x) continue;
          const Interval& s = c->stats.at(m);
          if (s.n == 0 || !std::isfinite(s.mean)) continue;
          if (best == nullptr) {
            best = c;
            continue;
          }
          const double b = best->stats.at(m).mean;
          if (s.mean == b) {
            tie = true;
          } else if ((s.mean > b) == higher_better) {
            best = c;
            tie = false;
          }
        }
        if (best == nullptr) continue;
        const std::string w = tie ? std::string("equal means") : best->values[si];
        if (!won_at.count(w)) winners.push_back(w);
        won_at[w].push_back(x);
      }
      if (winners.empty()) continue;
      std::vector<std::string> best_parts;
      for (const std::string& w : winners) {
        best_parts.push_back(winners.size() == 1 && xi >= 0
                                 ? w + " at every " + x_name
                                 : w + (won_at[w].size() == xs.size() ? "" : at(won_at[w])));
      }
      f.text = fmt::format("best mean ({} is better): {}.", higher_better ? "higher" : "lower",
                           fmt::join(best_parts, "; "));
      if (MachineDependent(m)) {
        // A timing: its means are said, its differences not tested.
        f.text +=
            " Not tested (a time depends on the machine's load and on the order the runs "
            "ran in).";
        findings.push_back(std::move(f));
        continue;
      }
      // Paired verdicts per compared series value.
      std::vector<std::string> compared;
      std::map<std::string, std::array<std::vector<std::string>, 3>> verdicts;
      std::map<std::string, std::vector<std::string>> ties;  // x where every pair ties
      std::map<std::string, std::pair<int, int>> pairs;      // min, max
      std::map<std::string, std::vector<std::string>> holm_kept;
      for (const PairedRow& row : paired.rows) {
        if (grouping.Of(*row.cell) != g) continue;
        const PairedComparison& c = row.metrics.at(m);
        const std::string& s = row.cell->values[si];
        if (SurvivesHolm(row, m)) holm_kept[s].push_back(x_of(*row.cell));
        if (!pairs.count(s)) {
          compared.push_back(s);
          pairs[s] = {c.pairs, c.pairs};
        }
        if (EveryPairTies(c)) {
          ties[s].push_back(x_of(*row.cell));
        } else {
          verdicts[s][static_cast<size_t>(VerdictOf(c, m))].push_back(x_of(*row.cell));
        }
        pairs[s].first = std::min(pairs[s].first, c.pairs);
        pairs[s].second = std::max(pairs[s].second, c.pairs);
      }
      for (const std::string& s : compared) {
        const auto& v = verdicts[s];
        std::vector<std::string> said;
        if (!v[1].empty()) said.push_back("significantly better" + at(v[1]));
        if (!v[2].empty()) said.push_back("significantly worse" + at(v[2]));
        if (!v[0].empty()) {
          said.push_back(
              (said.empty() ? "no significant difference" : "not significantly different") +
              (said.empty() && xi >= 0 && v[0].size() == xs.size()
                   ? std::string(" at any ") + x_name
                   : at(v[0])));
        }
        if (const std::vector<std::string>& t = ties[s]; !t.empty()) {
          said.push_back("the same value in every seed pair" +
                         (said.empty() && xi >= 0 && t.size() == xs.size()
                              ? std::string(" at every ") + x_name
                              : at(t)) +
                         ", not tested");
        }
        const auto [lo, hi] = pairs[s];
        if (hi == 0) {
          // No seed with a finite value in both cells: runs not in this
          // store (a shard, a sweep stopped early), failed, or a metric one
          // side lacks (a fourth bad-input audit: only the last was said).
          f.text += fmt::format(
              " {} \u2212 {}: no seed pairs (no seed has a value of the metric in both: its runs "
              "are not in this store, failed, or lack the metric).",
              s, paired.reference);
          continue;
        }
        f.text += fmt::format(" {} \u2212 {}: {} ({} seed pair{}{}).", s, paired.reference,
                              fmt::join(said, "; "),
                              lo == hi ? std::to_string(lo) : fmt::format("{}\u2013{}", lo, hi),
                              hi == 1 ? "" : "s", xi >= 0 ? " per " + x_name : "");
        if (!v[1].empty() || !v[2].empty()) {
          const std::vector<std::string>& kept = holm_kept[s];
          f.text += kept.empty() ? fmt::format(
                                       " None stays significant after Holm's correction for the "
                                       "report's {} comparisons.",
                                       paired.tested)
                                 : fmt::format(
                                       " After Holm's correction for the report's {} comparisons: "
                                       "still significant{}.",
                                       paired.tested, at(kept));
        }
      }
      findings.push_back(std::move(f));
    }
  }
  return findings;
}

// The findings at a glance: per report.y metric and compared series value,
// in how many of its paired cells the difference against the reference is a
// finding for better, for worse, not one, or has no pairs. A sweep of many
// panels gives one sentence per metric and panel; this is the line a reader
// scans first.
struct Glance {
  std::string metric;
  std::string panel;     // the report.panels value ("" without panels)
  std::string compared;  // the series value compared with the reference
  int better = 0;
  int worse = 0;
  int holm = 0;  // of better + worse, those that survive Holm's correction
  int not_significant = 0;
  int ties = 0;  // every pair the same (EveryPairTies): not tested
  int no_pairs = 0;
  int cells() const { return better + worse + not_significant + ties + no_pairs; }
};

// The table: one row per metric and compared value; the "no pairs" column
// only when some row has a cell without pairs.
struct GlanceTable {
  std::vector<Glance> rows;
  std::string panel_key;  // report.panels when the rows are per panel
  bool no_pairs_column = false;
  bool ties_column = false;
};

// With report.panels, a row per panel too: pooled over the main job's two
// likelihood models, "5 better, 3 worse" hid that every better was under one
// model and every worse under the other (an audit).
GlanceTable GlanceOf(const Paired& paired, const StoreMeta& meta) {
  GlanceTable table;
  std::vector<Glance>& out = table.rows;
  if (paired.series_index < 0) return table;
  const std::optional<size_t> panel_index = PanelKeyIndex(meta);
  table.panel_key = panel_index ? meta.report.panels : std::string();
  const auto si = static_cast<size_t>(paired.series_index);
  for (const std::string& m : meta.report.y) {
    if (MachineDependent(m)) continue;  // not tested
    const size_t first = out.size();
    for (const PairedRow& row : paired.rows) {
      const std::string& s = row.cell->values[si];
      const std::string panel = panel_index ? row.cell->values[*panel_index] : std::string();
      auto it = std::find_if(out.begin() + static_cast<std::ptrdiff_t>(first), out.end(),
                             [&](const Glance& g) { return g.compared == s && g.panel == panel; });
      if (it == out.end()) {
        out.push_back({.metric = m, .panel = panel, .compared = s});
        it = out.end() - 1;
      }
      const PairedComparison& c = row.metrics.at(m);
      if (c.pairs == 0) {
        ++it->no_pairs;
        continue;
      }
      if (EveryPairTies(c)) {
        ++it->ties;
        continue;
      }
      if (SurvivesHolm(row, m)) ++it->holm;
      switch (VerdictOf(c, m)) {
        case PairedVerdict::kBetter:
          ++it->better;
          break;
        case PairedVerdict::kWorse:
          ++it->worse;
          break;
        case PairedVerdict::kNotSignificant:
          ++it->not_significant;
          break;
      }
    }
  }
  for (const Glance& g : out) {
    table.no_pairs_column = table.no_pairs_column || g.no_pairs > 0;
    table.ties_column = table.ties_column || g.ties > 0;
  }
  return table;
}

// The counts of findings and of those kept by Holm are the glance table's,
// summed over its rows.
std::string FindingsIntro(const Paired& paired, const GlanceTable& glance, const StoreMeta& meta) {
  int findings = 0, kept = 0;
  for (const Glance& g : glance.rows) {
    findings += g.better + g.worse;
    kept += g.holm;
  }
  const std::string reach_note = HolmReachNote(paired);
  if (paired.tested == 0) {
    // Timings alone, or every comparison tied (a review: "makes 0
    // comparisons ... about 0.0 findings").
    return fmt::format(
        "Generated from the runs: for every metric, which {} value has the best mean at each x. "
        "This report tests no comparison:{}{}{}",
        meta.report.series, TimingsNote(meta), TiesNote(paired),
        paired.reference_absent
            ? fmt::format(" no run has the reference value {} = {} (report.reference), so no "
                          "cell has a partner.",
                          meta.report.series, paired.reference)
        : paired.rows.empty() && paired.zipped_with_x_or_panels
            ? fmt::format(" no cell has a partner, a cell of {} = {} at its {}{} (each {} value "
                          "is swept at other values of them: zipped with them one to one).",
                          meta.report.series, paired.reference, meta.report.x,
                          meta.report.panels.empty() ? "" : " and " + meta.report.panels,
                          meta.report.series)
            : std::string());
  }
  return fmt::format(
      "Generated from the runs: for every metric, which {0} value has the best mean at each x, "
      "and where each other value differs from {1} (the reference) seed by seed with p < 0.05 "
      "and a 95 % interval that excludes 0 (the green and red cells of the paired differences). "
      "A better mean without that is not a finding. This report makes {2} comparisons; where "
      "nothing differs, chance alone makes {3}. {4}{5}{6}",
      meta.report.series, paired.reference, paired.tested,
      // The test is discrete and a finding needs the interval too, so 0.05
      // a comparison is a bound; a comparison whose seed pairs cannot reach
      // p < 0.05 is never one (a review: "about 0.6 of them" beside "no
      // comparison of this report can be a finding").
      paired.can_reach == 0
          ? std::string("none of them findings (no comparison's seed pairs can reach p < 0.05)")
          : fmt::format("at most about {:.1f} of them findings{}", 0.05 * paired.can_reach,
                        paired.can_reach == paired.tested
                            ? std::string()
                            : fmt::format(" (0.05 for each of the {} whose seed pairs can "
                                          "reach p < 0.05)",
                                          paired.can_reach)),
      findings == 0
          ? std::string("None of them is a finding.")
          : fmt::format("Of them {} {}, and {} of those {} significant after Holm's correction "
                        "for all {} (Holm p < 0.05).",
                        findings, findings == 1 ? "is a finding" : "are findings", kept,
                        kept == 1 ? "stays" : "stay", paired.tested),
      reach_note.empty() ? std::string() : " " + reach_note, TiesNote(paired));
}

// The summary above the findings: per group of cells (as the findings
// group them: every swept value but x, the series and the keys that follow
// either; a panel, a variance, ...) and compared series value, one sentence
// of the findings that survive Holm's correction, the metrics grouped by
// the x values where they do (an audit: "12 bullets of about 60 words each
// ... a researcher wants a 2–3 line conclusion"), and how many findings do
// not survive it. The findings below say the rest.
std::vector<std::string> SummaryOf(const std::vector<Cell>& cells, const Paired& paired,
                                   const StoreMeta& meta, const Layout& layout) {
  std::vector<std::string> out;
  if (paired.series_index < 0 || paired.tested == 0) return out;
  const auto& keys = meta.swept_keys;
  const auto si = static_cast<size_t>(paired.series_index);
  const int xi = layout.x_index;
  const std::string x_name = xi >= 0 ? keys[static_cast<size_t>(xi)] : std::string();
  const FindingsGrouping grouping(cells, paired, xi, keys.size());
  // Per metric, the x values where it is kept.
  using Kept = std::vector<std::pair<std::string, std::vector<std::string>>>;
  struct Group {
    std::vector<std::string> key;
    std::string compared;
    std::vector<std::string> xs;  // of the group's compared cells
    Kept better, worse;
    int not_kept = 0;  // findings Holm's correction does not keep
  };
  std::vector<Group> groups;
  const auto add = [](std::vector<std::string>& list, const std::string& v) {
    if (std::find(list.begin(), list.end(), v) == list.end()) list.push_back(v);
  };
  for (const PairedRow& row : paired.rows) {
    const std::vector<std::string> key = grouping.Of(*row.cell);
    const std::string& s = row.cell->values[si];
    auto g = std::find_if(groups.begin(), groups.end(),
                          [&](const Group& x) { return x.key == key && x.compared == s; });
    if (g == groups.end()) {
      groups.push_back({.key = key, .compared = s});
      g = groups.end() - 1;
    }
    const std::string x = xi >= 0 ? row.cell->values[static_cast<size_t>(xi)] : std::string();
    add(g->xs, x);
    for (const std::string& m : meta.report.y) {
      const PairedVerdict verdict = VerdictOf(row.metrics.at(m), m);
      if (verdict == PairedVerdict::kNotSignificant) continue;
      if (!SurvivesHolm(row, m)) {
        ++g->not_kept;
        continue;
      }
      Kept& kept = verdict == PairedVerdict::kBetter ? g->better : g->worse;
      auto k = std::find_if(kept.begin(), kept.end(), [&](const auto& e) { return e.first == m; });
      if (k == kept.end()) {
        kept.emplace_back(m, std::vector<std::string>{});
        k = kept.end() - 1;
      }
      add(k->second, x);
    }
  }
  // The keys that tell the groups apart ("Under k = v, ...").
  std::vector<const std::vector<std::string>*> group_rows;
  for (const Group& g : groups) group_rows.push_back(&g.key);
  const std::vector<size_t> varying = VaryingKeys(group_rows, keys.size(), -1, -1);
  // x values in the axis's order: numbers by value, others as laid out.
  const auto x_order = [&](const std::string& x) {
    if (layout.numeric_x) return *ParseNumber(x);
    return static_cast<double>(std::find(layout.x_values.begin(), layout.x_values.end(), x) -
                               layout.x_values.begin());
  };
  const auto by_x = [&](const std::string& a, const std::string& b) {
    return x_order(a) < x_order(b);
  };
  // Metrics in report.y's order, whatever order the runs are stored in.
  const auto y_index = [&](const std::string& m) {
    return std::find(meta.report.y.begin(), meta.report.y.end(), m) - meta.report.y.begin();
  };
  for (Group& g : groups) {
    std::sort(g.xs.begin(), g.xs.end(), by_x);
    for (Kept* kept : {&g.better, &g.worse}) {
      for (auto& [m, at] : *kept) std::sort(at.begin(), at.end(), by_x);
      std::sort(kept->begin(), kept->end(),
                [&](const auto& a, const auto& b) { return y_index(a.first) < y_index(b.first); });
    }
  }
  // "every x", "200 to 5000" (three or more in a row of the group's
  // numeric x values), "50 and 2000"; nothing without an x.
  const auto where = [&](const std::vector<std::string>& at, const std::vector<std::string>& all) {
    if (xi < 0) return std::string();
    if (at.size() == all.size() && all.size() > 1) return "every " + x_name;
    const auto first = std::find(all.begin(), all.end(), at.front());
    const bool in_a_row = layout.numeric_x && at.size() >= 3 &&
                          static_cast<size_t>(all.end() - first) >= at.size() &&
                          std::equal(at.begin(), at.end(), first);
    return in_a_row ? at.front() + " to " + at.back() : JoinWords(at);
  };
  // The metrics of one direction, those kept at the same x values together:
  // "hijack_rate at x = 200 to 5000 and in mota and hota at 500 to 5000".
  const auto phrase = [&](const Kept& kept, const std::vector<std::string>& all) {
    std::vector<std::pair<std::string, std::vector<std::string>>> by_where;  // where, metrics
    for (const auto& [m, at] : kept) {
      const std::string w = where(at, all);
      auto it = std::find_if(by_where.begin(), by_where.end(),
                             [&](const auto& e) { return e.first == w; });
      if (it == by_where.end()) {
        by_where.emplace_back(w, std::vector<std::string>{});
        it = by_where.end() - 1;
      }
      it->second.push_back(m);
    }
    std::vector<std::string> parts;
    bool named = false;  // x's name said once
    for (const auto& [w, metrics] : by_where) {
      const bool every = w.rfind("every ", 0) == 0;
      parts.push_back(
          (parts.empty() ? "" : "in ") + JoinWords(metrics) +
          (w.empty() ? std::string() : " at " + (named || every ? w : x_name + " = " + w)));
      named = named || (!w.empty() && !every);
    }
    // "a, and in b" (a comma where the x values of a end in "and").
    std::string joined = parts.front();
    for (size_t i = 1; i < parts.size(); ++i)
      joined += (i + 1 < parts.size() ? ", " : ", and ") + parts[i];
    return joined;
  };
  for (const Group& g : groups) {
    const std::string under = GroupWords(g.key, varying, keys);
    const std::string subject = (under.empty() ? std::string() : "Under " + under + ", ") +
                                g.compared + " \u2212 " + paired.reference;
    const std::string lost =
        g.not_kept == 0 ? std::string()
                        : fmt::format(" {} more {} not survive the correction.", g.not_kept,
                                      g.not_kept == 1 ? "finding does" : "findings do");
    if (g.better.empty() && g.worse.empty()) {
      out.push_back(g.not_kept == 0
                        ? subject + ": no finding."
                        : subject + fmt::format(": {} {}, none of which survives Holm's "
                                                "correction.",
                                                g.not_kept,
                                                g.not_kept == 1 ? "finding" : "findings"));
      continue;
    }
    out.push_back(fmt::format("{}, after Holm's correction: better in {}; worse in {}.{}", subject,
                              g.better.empty() ? std::string("no metric") : phrase(g.better, g.xs),
                              g.worse.empty() ? std::string("no metric") : phrase(g.worse, g.xs),
                              lost));
  }
  return out;
}

std::string GlanceIntro(const Paired& paired, const StoreMeta& meta) {
  return fmt::format(
      "At a glance: for each metric{} and {} value, in how many of its cells (every combination "
      "of the other swept values) the paired difference against {} is a finding for better or "
      "for worse, how many of those findings survive Holm's correction, and in how many cells "
      "it is not a finding{}.",
      meta.report.panels.empty() ? std::string() : ", " + meta.report.panels + " value",
      meta.report.series, paired.reference,
      paired.every_pair_ties == 0 ? std::string()
                                  : " or not tested (every seed pair the same value: \"tied\")");
}

std::string FindingsHtml(const std::vector<Finding>& findings, const GlanceTable& glance,
                         const Paired& paired, const StoreMeta& meta,
                         const std::vector<std::string>& summary) {
  if (findings.empty()) return {};
  std::string h = "<h2 id=\"findings\">Findings</h2>\n";
  if (!summary.empty()) {
    h += "<p id=\"summary\"><b>Summary.</b> " +
         EscapeMarkup(fmt::format("{}", fmt::join(summary, " "))) + "</p>\n";
  }
  h += "<p>" + EscapeMarkup(FindingsIntro(paired, glance, meta)) + "</p>\n";
  const bool any_no_pairs = glance.no_pairs_column;
  const bool any_ties = glance.ties_column;
  h += "<p>" + EscapeMarkup(GlanceIntro(paired, meta)) +
       "</p>\n<table id=\"glance\"><tr><th>metric</th>" +
       (glance.panel_key.empty() ? std::string()
                                 : "<th>" + EscapeMarkup(glance.panel_key) + "</th>") +
       "<th>compared</th><th>better</th>"
       "<th>worse</th><th>of them after Holm</th><th>not significant</th>" +
       std::string(any_ties ? "<th>tied</th>" : "") +
       std::string(any_no_pairs ? "<th>no pairs</th>" : "") + "<th>cells</th></tr>\n";
  for (const Glance& g : glance.rows) {
    const auto coloured = [](int n, const char* colour) {
      return n > 0 ? fmt::format("<td style=\"background:{}\">{}</td>", colour, n)
                   : fmt::format("<td>{}</td>", n);
    };
    h += fmt::format(
        "<tr><td class=\"k\">{}</td>{}<td class=\"k\">{} &minus; {}</td>{}{}<td>{}</td><td>{}</td>"
        "{}{}<td>{}</td></tr>\n",
        EscapeMarkup(g.metric),
        glance.panel_key.empty() ? std::string()
                                 : "<td class=\"k\">" + EscapeMarkup(g.panel) + "</td>",
        EscapeMarkup(g.compared), EscapeMarkup(paired.reference), coloured(g.better, "#dff3df"),
        coloured(g.worse, "#f8dede"), g.holm, g.not_significant,
        any_ties ? fmt::format("<td>{}</td>", g.ties) : "",
        any_no_pairs ? fmt::format("<td>{}</td>", g.no_pairs) : "", g.cells());
  }
  h += "</table>\n<ul>\n";
  for (const Finding& f : findings) {
    h += fmt::format("<li><b>{}</b>{}: {}</li>\n", EscapeMarkup(f.metric),
                     f.group.empty() ? "" : " (" + EscapeMarkup(f.group) + ")",
                     EscapeMarkup(f.text));
  }
  return h + "</ul>\n";
}

std::string FindingsMarkdown(const std::vector<Finding>& findings, const GlanceTable& glance,
                             const Paired& paired, const StoreMeta& meta,
                             const std::vector<std::string>& summary,
                             const std::string& missing_runs) {
  std::string md = "# Findings\n\n" +
                   (missing_runs.empty() ? std::string() : "**" + missing_runs + "**\n\n") +
                   (summary.empty() ? std::string()
                                    : fmt::format("**Summary.** {}\n\n", fmt::join(summary, " "))) +
                   FindingsIntro(paired, glance, meta) + "\n\n" + RootSeedSentence(meta) + "\n\n";
  const bool any_no_pairs = glance.no_pairs_column;
  const bool any_ties = glance.ties_column;
  const bool panels = !glance.panel_key.empty();
  md += GlanceIntro(paired, meta) + "\n\n| metric |" +
        (panels ? " " + glance.panel_key + " |" : std::string()) +
        " compared | better | worse | of them after Holm | not significant |" +
        std::string(any_ties ? " tied |" : "") + std::string(any_no_pairs ? " no pairs |" : "") +
        " cells |\n|---|---|---|---|---|---|" + std::string(panels ? "---|" : "") +
        std::string(any_ties ? "---|" : "") + std::string(any_no_pairs ? "---|" : "") + "---|\n";
  for (const Glance& g : glance.rows) {
    md += fmt::format("| {} |{} {} \u2212 {} | {} | {} | {} | {} |{}{} {} |\n", g.metric,
                      panels ? " " + g.panel + " |" : std::string(), g.compared, paired.reference,
                      g.better, g.worse, g.holm, g.not_significant,
                      any_ties ? fmt::format(" {} |", g.ties) : "",
                      any_no_pairs ? fmt::format(" {} |", g.no_pairs) : "", g.cells());
  }
  md += "\n";
  for (const Finding& f : findings) {
    md += fmt::format("- **{}**{}: {}\n", f.metric, f.group.empty() ? "" : " (" + f.group + ")",
                      f.text);
  }
  return md;
}

// Stage 2d, replication (hcpf report DIR --against OTHER): every paired
// comparison of this report made again on the runs of another store of the
// same swept keys (typically the same sweep on another root seed, hcpf sweep
// --seed), with this report's report: block (the stores hold every headline
// metric of every run), matched by the compared cell's swept values.
// A finding there that is no finding here but goes the same way with one
// of the two criteria (p < 0.05, or an interval that excludes 0) is
// "weaker here": an audit found same-direction differences at p = 6e-5,
// whose interval ended at +0.00004, called "not replicated".
enum class Replication { kReplicated, kWeaker, kNotReplicated, kReversed, kNewHere, kNeither };

const char* ReplicationName(Replication r) {
  switch (r) {
    case Replication::kReplicated:
      return "replicated";
    case Replication::kWeaker:
      return "weaker here";
    case Replication::kNotReplicated:
      return "not replicated";
    case Replication::kReversed:
      return "reversed";
    case Replication::kNewHere:
      return "new here";
    case Replication::kNeither:
      return "neither";
  }
  return "";
}

const char* VerdictName(PairedVerdict v) {
  return v == PairedVerdict::kBetter ? "better" : v == PairedVerdict::kWorse ? "worse" : "none";
}

// The other store, with the cells and paired rows of this report's block.
struct AgainstStore {
  std::string dir;  // as given to --against
  StoreMeta meta;   // its meta, with this report's report: block
  std::vector<RunRecord> runs;
  std::vector<Cell> cells;
  Paired paired;
  // Its swept values read in this store's spelling (RespellAsHere's lines).
  std::vector<std::string> respelled;
};

struct ReplicationRow {
  const PairedRow* there = nullptr;
  const PairedRow* here = nullptr;
  std::string metric;
  PairedVerdict there_verdict = PairedVerdict::kNotSignificant;
  PairedVerdict here_verdict = PairedVerdict::kNotSignificant;
  bool there_kept = false, here_kept = false;  // SurvivesHolm
  Replication outcome = Replication::kNeither;
};

struct ReplicationTable {
  std::vector<ReplicationRow> rows;  // this report's paired order, then report.y
  int only_here = 0;                 // comparisons (row x metric) with no partner there
  int only_there = 0;                // and there without a partner here
};

// Each of `keys` swept keys' values, each once, in order of first
// appearance: the sweep's where `expansion` is given (a store's recorded
// expansion: its rows are held to it), whatever runs there are, else the
// runs'.
std::vector<std::vector<std::string>> SweptValues(const std::vector<RunRecord>& runs, size_t keys,
                                                  const std::optional<StoredExpansion>& expansion) {
  std::vector<std::vector<std::string>> values(keys);
  const auto add = [&values](size_t k, const std::string& v) {
    if (k < values.size() && std::find(values[k].begin(), values[k].end(), v) == values[k].end())
      values[k].push_back(v);
  };
  if (expansion) {
    size_t k = 0;
    for (const auto* axes : {&expansion->grid, &expansion->zip}) {
      for (const StoredExpansion::Axis& a : *axes) {
        for (const std::string& v : a.values) add(k, v);
        ++k;
      }
    }
    return values;
  }
  for (const RunRecord& r : runs) {
    for (size_t k = 0; k < r.values.size(); ++k) add(k, r.values[k]);
  }
  return values;
}

// A number as a sweep file may spell it: a whole number (digits, with an
// optional sign, up to 2^64 − 1) kept exactly, or any finite decimal.
struct SpelledNumber {
  bool whole = false;
  bool negative = false;
  uint64_t magnitude = 0;  // whole numbers (0 is never negative)
  double value = 0.0;
};

std::optional<SpelledNumber> ReadSpelledNumber(std::string text) {
  if (!text.empty() && text.front() == '+') text.erase(0, 1);
  SpelledNumber n;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), n.value);
  if (ec != std::errc() || end != text.data() + text.size() || !std::isfinite(n.value)) {
    return std::nullopt;
  }
  const bool minus = !text.empty() && text.front() == '-';
  const std::string digits = minus ? text.substr(1) : text;
  if (!digits.empty() && digits.find_first_not_of("0123456789") == std::string::npos) {
    const auto [at, error] =
        std::from_chars(digits.data(), digits.data() + digits.size(), n.magnitude);
    n.whole = error == std::errc() && at == digits.data() + digits.size();
    n.negative = minus && n.magnitude != 0;
  }
  return n;
}

bool SameYamlValue(const YAML::Node& a, const YAML::Node& b) {
  if (a.Type() != b.Type()) return false;
  if (a.IsScalar()) {
    const std::string& x = a.Scalar();
    const std::string& y = b.Scalar();
    if (x == y) return true;
    const std::optional<SpelledNumber> u = ReadSpelledNumber(x), v = ReadSpelledNumber(y);
    if (!u || !v) return false;
    // Whole numbers as written compare exactly (two seeds past 2^53 round
    // to one double: a review); a whole number past 2^53 equals no
    // fraction or exponent spelling.
    if (u->whole && v->whole) return u->negative == v->negative && u->magnitude == v->magnitude;
    constexpr uint64_t kExact = uint64_t{1} << 53;
    if ((u->whole && u->magnitude > kExact) || (v->whole && v->magnitude > kExact)) return false;
    return u->value == v->value;
  }
  if (a.IsSequence()) {
    if (a.size() != b.size()) return false;
    for (size_t i = 0; i < a.size(); ++i) {
      if (!SameYamlValue(a[i], b[i])) return false;
    }
    return true;
  }
  if (a.IsMap()) {
    if (a.size() != b.size()) return false;
    for (const auto& entry : a) {
      const YAML::Node other = b[entry.first.Scalar()];
      if (!other || !SameYamlValue(entry.second, other)) return false;
    }
    return true;
  }
  return a.IsNull();
}

// Whether two spellings of a swept value are one value: the same text,
// or the same YAML with numbers compared as numbers (3 and 3.0, 0.1 and
// 0.10, [320, 240] and [320.0, 240]).
bool SameSpelledValue(const std::string& a, const std::string& b) {
  if (a == b) return true;
  try {
    return SameYamlValue(YAML::Load(a), YAML::Load(b));
  } catch (const YAML::Exception&) {
    return false;
  }
}

// Whether `key` (dotted, list items by index) holds a quoted scalar in one
// parsed resolved scenario; nullopt where it is not there (an index past
// size_t included).
std::optional<bool> TakesText(YAML::Node node, const std::string& key) {
  std::stringstream path(key);
  for (std::string part; node && std::getline(path, part, '.');) {
    // reset(), not =: assigning a node writes into the tree it was bound to.
    if (node.IsSequence() && !part.empty() &&
        part.find_first_not_of("0123456789") == std::string::npos) {
      size_t i = 0;
      const bool read =
          std::from_chars(part.data(), part.data() + part.size(), i).ec == std::errc();
      node.reset(read && i < node.size() ? node[i] : YAML::Node());
    } else if (node.IsMap()) {
      node.reset(node[part]);
    } else {
      node.reset(YAML::Node());
    }
  }
  // Found: text when a quoted scalar (a list or a mapping is not).
  if (node && node.IsDefined() && !node.IsNull()) return node.IsScalar() && node.Tag() == "!";
  return std::nullopt;
}

// Whether `key` holds text in a store's resolved base scenario(s)
// (`resolved`: ResolvedBases' texts, else base_resolved): a quoted scalar
// there (the resolved YAML quotes text and paths, docs/scenario.md). Its
// values are compared as written, never as numbers: `name: 1.10` and `1.1`
// are two names (a review). nullopt where the key is not found in any of
// them.
std::optional<bool> TakesText(const std::vector<std::string>& resolved, const std::string& key) {
  for (const std::string& text : resolved) {
    try {
      if (const std::optional<bool> found = TakesText(YAML::Load(text), key)) return found;
    } catch (const YAML::Exception&) {
      continue;  // text that is not YAML: not found here
    }
  }
  return std::nullopt;
}

// TakesText for a key the resolved base scenario leaves out (an optional
// path such as targets.0.model, which the resolved YAML writes only when
// set: its values were compared as numbers, a review): read from the
// scenario.resolved.yaml of this store's runs in `dir` (the key is swept
// key `k`), the first that holds it; for each value, its runs (failed or
// not) until one has a file (a run whose value leaves the key out holds
// none; a file that is not YAML is passed over). nullopt where none does
// (the run folders gone, or every value leaves the key out); `files_read`
// counts the files read.
std::optional<bool> TakesText(const std::vector<std::string>& resolved, const std::string& key,
                              size_t k, const fs::path& dir, const std::vector<RunRecord>& runs,
                              int& files_read) {
  if (const std::optional<bool> text = TakesText(resolved, key)) return *text;
  std::set<std::string> read;  // the values one of whose runs' files was read
  for (const RunRecord& run : runs) {
    if (run.run_dir.empty() || k >= run.values.size() || read.contains(run.values[k])) continue;
    // A missing or unreadable file reads as "", a damaged one is no YAML:
    // the value's next run.
    const std::string text = ReadWholeFile(dir / run.run_dir / "scenario.resolved.yaml");
    if (text.empty()) continue;
    YAML::Node root;
    try {
      root = YAML::Load(text);
    } catch (const YAML::Exception&) {
      continue;
    }
    read.insert(run.values[k]);
    ++files_read;
    if (const std::optional<bool> found = TakesText(root, key)) return *found;
  }
  return std::nullopt;
}

// The other store's runs read in this store's spelling of each swept value
// where it writes the same value otherwise: a number written 3.0 for 3, or
// a grid.base path written relative in one sweep file and absolute in the
// other whose resolved scenarios are the same (an audit of valid input:
// such stores of one sweep matched no cell). Returns a line per value
// respelled, for the log.
// `bases_there`: ResolvedBases of the other store's meta as it was read
// (its expansion is dropped when it lists the keys in another order).
std::vector<std::string> RespellAsHere(const fs::path& dir, const std::vector<RunRecord>& runs,
                                       const StoreMeta& meta,
                                       const std::map<std::string, std::string>& bases_there,
                                       AgainstStore& other) {
  const std::map<std::string, std::string> bases_here = ResolvedBases(meta);
  std::vector<std::string> resolved_here;  // for TakesText
  for (const auto& [value, text] : bases_here) resolved_here.push_back(text);
  if (resolved_here.empty()) resolved_here.push_back(meta.base_resolved);
  const size_t keys = meta.swept_keys.size();
  const std::vector<std::vector<std::string>> values_here = SweptValues(runs, keys, meta.expansion);
  // There: the values its runs hold.
  const std::vector<std::vector<std::string>> values_there =
      SweptValues(other.runs, keys, std::nullopt);
  std::vector<std::string> lines;
  for (size_t k = 0; k < keys; ++k) {
    const std::string& key = meta.swept_keys[k];
    // Text is compared as written; a key no resolved scenario here holds
    // (its run folders gone) is read as numbers, which its lines say.
    int files_read = 0;
    const std::optional<bool> text = key == kSweptBaseKey
                                         ? std::optional<bool>(false)
                                         : TakesText(resolved_here, key, k, dir, runs, files_read);
    if (text.value_or(false)) continue;
    const std::vector<std::string>& here = values_here[k];
    std::map<std::string, std::string> respelled;
    for (const std::string& v : values_there[k]) {
      if (std::find(here.begin(), here.end(), v) != here.end()) continue;
      std::vector<std::string> same;
      for (const std::string& u : here) {
        bool equal = false;
        if (key == kSweptBaseKey) {
          const auto a = bases_here.find(u), b = bases_there.find(v);
          equal = a != bases_here.end() && b != bases_there.end() && a->second == b->second;
        } else {
          equal = SameSpelledValue(u, v);
        }
        if (equal) same.push_back(u);
      }
      if (same.size() != 1) continue;
      respelled.emplace(v, same.front());
      lines.push_back(key == kSweptBaseKey
                          ? fmt::format("{}'s {} = {} read as {} (the same resolved scenario)",
                                        other.dir, key, v, same.front())
                      : text ? fmt::format("{}'s {} = {} read as {} (the same value)", other.dir,
                                           key, v, same.front())
                             : fmt::format("{}'s {} = {} read as {} (the same value as numbers: "
                                           "neither this store's base nor the {} run file{} read "
                                           "here holds {}, so whether it takes text is not known)",
                                           other.dir, key, v, same.front(), files_read,
                                           files_read == 1 ? "" : "s", key));
    }
    if (respelled.empty()) continue;
    for (RunRecord& r : other.runs) {
      if (k >= r.values.size()) continue;
      const auto it = respelled.find(r.values[k]);
      if (it != respelled.end()) r.values[k] = it->second;
    }
  }
  return lines;
}

std::unique_ptr<AgainstStore> OpenAgainst(const std::string& against, const fs::path& dir,
                                          const StoreMeta& meta, const std::vector<RunRecord>& runs,
                                          const Paired& paired) {
  const SourceLocation where{"hcpf report", 0, 0, "--against"};
  const char* expected_kind = "a sweep folder (results.sqlite) over the same swept keys";
  std::error_code ec;
  // DIR itself, as a run's --against refuses it (a fourth bad-input audit:
  // accepted, the replication section then saying it was none).
  if (fs::equivalent(against, dir, ec)) {
    throw InputError(where, std::string(expected_kind) + ", other than DIR",
                     fmt::format("{}, DIR itself", against));
  }
  if (!fs::is_regular_file(fs::path(against) / "results.sqlite", ec)) {
    throw InputError(
        where, expected_kind,
        !fs::exists(against, ec)         ? fmt::format("{}: no such folder", against)
        : !fs::is_directory(against, ec) ? fmt::format("{}, a file", against)
        : fs::is_regular_file(fs::path(against) / "manifest.json", ec)
            ? fmt::format("{}, a run or render folder (manifest.json; a run is compared "
                          "with a run: hcpf report RUN --against OTHER_RUN)",
                          against)
            : fmt::format("{}, a folder without results.sqlite", against));
  }
  auto other = std::make_unique<AgainstStore>();
  other->dir = against;
  const auto store =
      ResultsStore::Open((fs::path(against) / "results.sqlite").string(), StoreAccess::kReadOnly);
  other->meta = store->meta();
  const std::map<std::string, std::string> bases_there = ResolvedBases(other->meta);
  // The same keys listed in another order (grid: in another order in the
  // other sweep file, the same runs): its rows are read in this store's
  // order (an audit of valid input: refused). Which keys are zipped is then
  // left to the runs' values (as for a store that records no expansion).
  std::vector<size_t> order;  // this store's key k is the other's key order[k]
  if (other->meta.swept_keys != meta.swept_keys &&
      std::is_permutation(meta.swept_keys.begin(), meta.swept_keys.end(),
                          other->meta.swept_keys.begin(), other->meta.swept_keys.end())) {
    for (const std::string& key : meta.swept_keys) {
      order.push_back(static_cast<size_t>(
          std::find(other->meta.swept_keys.begin(), other->meta.swept_keys.end(), key) -
          other->meta.swept_keys.begin()));
    }
    other->meta.swept_keys = meta.swept_keys;
    other->meta.expansion.reset();
  }
  if (other->meta.swept_keys != meta.swept_keys) {
    throw InputError(where, fmt::format("{} ({})", expected_kind, fmt::join(meta.swept_keys, ", ")),
                     fmt::format("{} sweeping {}", against,
                                 other->meta.swept_keys.empty()
                                     ? std::string("nothing")
                                     : fmt::format("{}", fmt::join(other->meta.swept_keys, ", "))));
  }
  // This report's block (and its resolved reference) on the other runs.
  other->meta.report = meta.report;
  other->meta.report.reference = paired.reference;
  other->runs = store->Runs();
  if (!order.empty()) {
    for (RunRecord& r : other->runs) {
      std::vector<std::string> values;
      for (size_t k : order) values.push_back(k < r.values.size() ? r.values[k] : std::string());
      r.values = std::move(values);
    }
  }
  other->respelled = RespellAsHere(dir, runs, meta, bases_there, *other);
  for (const std::string& line : other->respelled) spdlog::info("report: --against: {}", line);
  other->cells = CellsOf(other->runs, other->meta);
  other->paired = PairedRowsOf(other->cells, other->meta);
  return other;
}

ReplicationTable ReplicationOf(const Paired& here, const AgainstStore& there,
                               const StoreMeta& meta) {
  ReplicationTable table;
  std::map<std::vector<std::string>, const PairedRow*> there_rows;
  for (const PairedRow& r : there.paired.rows) there_rows.emplace(r.cell->values, &r);
  std::set<std::pair<const PairedRow*, std::string>> matched;  // there's (row, metric)
  const auto has_pairs = [](const PairedRow& r, const std::string& m) {
    return r.metrics.at(m).pairs > 0;
  };
  for (const PairedRow& row : here.rows) {
    const auto it = there_rows.find(row.cell->values);
    for (const std::string& m : meta.report.y) {
      if (!has_pairs(row, m) || MachineDependent(m)) continue;
      if (it == there_rows.end() || !has_pairs(*it->second, m)) {
        table.only_here += EveryPairTies(row.metrics.at(m)) ? 0 : 1;
        continue;
      }
      matched.emplace(it->second, m);
      // Tested in neither store (every pair ties in both): no outcome.
      if (EveryPairTies(row.metrics.at(m)) && EveryPairTies(it->second->metrics.at(m))) continue;
      ReplicationRow r;
      r.there = it->second;
      r.here = &row;
      r.metric = m;
      r.there_verdict = VerdictOf(r.there->metrics.at(m), m);
      r.here_verdict = VerdictOf(row.metrics.at(m), m);
      r.there_kept = SurvivesHolm(*r.there, m);
      r.here_kept = SurvivesHolm(row, m);
      const bool there_finding = r.there_verdict != PairedVerdict::kNotSignificant;
      const bool here_finding = r.here_verdict != PairedVerdict::kNotSignificant;
      // Here, in the direction of there's finding: one criterion of two.
      const PairedComparison& c = row.metrics.at(m);
      const double there_sign = r.there->metrics.at(m).difference.mean > 0.0 ? 1.0 : -1.0;
      const bool same_way = c.difference.mean * there_sign > 0.0;
      const bool interval_same_way =
          c.difference.method != IntervalMethod::kNone &&
          (there_sign > 0.0 ? c.difference.lower > 0.0 : c.difference.upper < 0.0);
      const bool test_same_way =
          c.test.p_value < 0.05 && TestSide(c.test) == (there_sign > 0.0 ? 1 : -1);
      const bool weaker = same_way && (test_same_way || interval_same_way);
      r.outcome = there_finding && here_finding
                      ? (r.there_verdict == r.here_verdict ? Replication::kReplicated
                                                           : Replication::kReversed)
                  : there_finding && weaker ? Replication::kWeaker
                  : there_finding           ? Replication::kNotReplicated
                  : here_finding            ? Replication::kNewHere
                                            : Replication::kNeither;
      table.rows.push_back(r);
    }
  }
  for (const PairedRow& r : there.paired.rows) {
    for (const std::string& m : meta.report.y) {
      table.only_there += Tested(r.metrics.at(m), m) && matched.count({&r, m}) == 0;
    }
  }
  return table;
}

// "root seed 3" / "the base scenario's seed" / "a root seed it does not record".
std::string RootSeedShort(const StoreMeta& meta) {
  if (!meta.root_seed.empty()) return "root seed " + meta.root_seed;
  if (meta.root_seed_from == "base scenario") return "the base scenario's seed";
  return "a root seed it does not record";
}

// "Against `OTHER` (runs of root seed 1; these runs: root seed 2)".
std::string AgainstIntro(const AgainstStore& there, const StoreMeta& meta) {
  return fmt::format("Against `{}` (runs of {}; these runs: {})", there.dir,
                     RootSeedShort(there.meta), RootSeedShort(meta));
}

// Said when both stores draw their seeds from one root seed ("" otherwise).
std::string SameSeedNote(const AgainstStore& there, const StoreMeta& meta) {
  return !meta.root_seed.empty() && meta.root_seed == there.meta.root_seed
             ? "Both stores draw their seeds from the same root seed, so matching runs are the "
               "same runs: this is no replication. "
             : "";
}

// The summary sentence (Markdown: `code`).
std::string ReplicationSentence(const ReplicationTable& table, const AgainstStore& there,
                                const StoreMeta& meta) {
  int there_findings = 0, replicated = 0, replicated_kept = 0, weaker = 0, not_replicated = 0,
      reversed = 0, new_here = 0;
  for (const ReplicationRow& r : table.rows) {
    there_findings += r.there_verdict != PairedVerdict::kNotSignificant;
    replicated += r.outcome == Replication::kReplicated;
    weaker += r.outcome == Replication::kWeaker;
    replicated_kept += r.outcome == Replication::kReplicated && r.there_kept && r.here_kept;
    not_replicated += r.outcome == Replication::kNotReplicated;
    reversed += r.outcome == Replication::kReversed;
    new_here += r.outcome == Replication::kNewHere;
  }
  // A comparison tied in one store only is tested in the other: it counts
  // (a finding there may not be one here), and the sentence says how many.
  int tied_one_side = 0;
  for (const ReplicationRow& r : table.rows) {
    tied_one_side +=
        EveryPairTies(r.there->metrics.at(r.metric)) || EveryPairTies(r.here->metrics.at(r.metric));
  }
  std::string text = fmt::format(
      "{}, {} comparisons are made in both stores{}. {}", AgainstIntro(there, meta),
      table.rows.size(),
      tied_one_side == 0
          ? std::string()
          : fmt::format(" ({} of them with every seed pair tied in one store, tested in the other "
                        "only; a comparison tied in both is left out)",
                        tied_one_side),
      SameSeedNote(there, meta));
  text += there_findings == 0
              ? "None of them is a finding there. "
              : fmt::format(
                    "Of the {} {} there, {} {} here in the same direction ({} of "
                    "them kept by Holm's correction in both stores), {} {} weaker here (the same "
                    "direction with p < 0.05 or an interval that excludes 0, not both), {} {} "
                    "here and {} {} the other way. ",
                    there_findings, there_findings == 1 ? "that is a finding" : "that are findings",
                    replicated, replicated == 1 ? "is a finding" : "are findings", replicated_kept,
                    weaker, weaker == 1 ? "is" : "are", not_replicated,
                    not_replicated == 1 ? "is not a finding" : "are not findings", reversed,
                    reversed == 1 ? "is a finding" : "are findings");
  text += fmt::format("{} {} here and not there.", new_here,
                      new_here == 1 ? "comparison is a finding" : "comparisons are findings");
  if (table.only_here + table.only_there > 0) {
    text += fmt::format(
        " {} comparisons of this report have no partner there and {} there none here (cells "
        "or seeds that one store lacks).",
        table.only_here, table.only_there);
  }
  return text;
}

// Cell by cell: each cell's mean of each report.y metric here against the
// other store's 95 % interval of the same cell (matched by swept values). Not
// a test: with the same n on both sides about 83 % of replicated means fall
// inside the first interval (Cumming & Maillardet 2006), not 95 %.
struct CellReplicationRow {
  const Cell* there = nullptr;
  const Cell* here = nullptr;
  std::string metric;
  bool inside = false;   // here's mean inside there's interval
  bool overlap = false;  // the two intervals overlap
};

struct CellReplicationTable {
  std::vector<CellReplicationRow> rows;  // cells with a mean and an interval in both
  int unmatched = 0;  // cell means here with no interval there (no cell, n < 2, not measured)
};

CellReplicationTable CellReplicationOf(const std::vector<Cell>& cells, const AgainstStore& there,
                                       const StoreMeta& meta) {
  CellReplicationTable table;
  std::map<std::vector<std::string>, const Cell*> there_cells;
  for (const Cell& c : there.cells) there_cells.emplace(c.values, &c);
  const auto usable = [](const Cell& c, const std::string& m) {
    const auto it = c.stats.find(m);
    return it != c.stats.end() && it->second.n > 0 && std::isfinite(it->second.mean) &&
           it->second.method != IntervalMethod::kNone;
  };
  for (const Cell& cell : cells) {
    const auto it = there_cells.find(cell.values);
    for (const std::string& m : meta.report.y) {
      // A timing measures the machine's load as much as the run.
      if (!usable(cell, m) || MachineDependent(m)) continue;
      if (it == there_cells.end() || !usable(*it->second, m)) {
        ++table.unmatched;
        continue;
      }
      const Interval& a = it->second->stats.at(m);
      const Interval& b = cell.stats.at(m);
      CellReplicationRow r;
      r.there = it->second;
      r.here = &cell;
      r.metric = m;
      // A bound computed as 1 − 1e-16 still holds a mean of 1.
      const auto le = [](double x, double y) {
        return x <= y + 1e-9 * std::max({1.0, std::abs(x), std::abs(y)});
      };
      r.inside = le(a.lower, b.mean) && le(b.mean, a.upper);
      r.overlap = le(b.lower, a.upper) && le(a.lower, b.upper);
      table.rows.push_back(r);
    }
  }
  return table;
}

std::string CellReplicationSentence(const CellReplicationTable& table) {
  int inside = 0, overlap = 0;
  for (const CellReplicationRow& r : table.rows) {
    inside += r.inside;
    overlap += r.overlap;
  }
  return fmt::format(
      "Cell by cell: of the {} cell means measured with an interval in both stores (cells "
      "\u00d7 metrics), {} lie inside the other store's 95 % interval of the same cell and {} "
      "of the two intervals overlap{}. (With as many seeds in both, about 83 % of means of a "
      "replication are expected inside the first interval, not 95 %.)",
      table.rows.size(), inside, overlap,
      table.unmatched > 0 ? fmt::format("; {} {} here {} no interval there", table.unmatched,
                                        table.unmatched == 1 ? "cell mean" : "cell means",
                                        table.unmatched == 1 ? "has" : "have")
                          : std::string());
}

// replication_cells.csv: one row per cell and metric in both stores.
std::string CellReplicationCsv(const CellReplicationTable& table, const StoreMeta& meta) {
  std::string csv;
  for (const std::string& k : meta.swept_keys) csv += Csv(k) + ",";
  csv +=
      "metric,n_there,mean_there,lo95_there,hi95_there,n_here,mean_here,lo95_here,hi95_here,"
      "inside,overlap\n";
  for (const CellReplicationRow& r : table.rows) {
    for (const std::string& v : r.here->values) csv += Csv(v) + ",";
    const Interval& a = r.there->stats.at(r.metric);
    const Interval& b = r.here->stats.at(r.metric);
    csv += fmt::format("{},{},{},{},{},{},{},{},{},{},{}\n", r.metric, a.n, Number(a.mean),
                       Number(a.lower), Number(a.upper), b.n, Number(b.mean), Number(b.lower),
                       Number(b.upper), r.inside ? 1 : 0, r.overlap ? 1 : 0);
  }
  return csv;
}

// The cell-by-cell part of the section: the sentence, then the cell means
// outside the other store's interval.
std::string CellReplicationHtml(const CellReplicationTable& table, const StoreMeta& meta) {
  std::string h = "<p>" + EscapeMarkup(CellReplicationSentence(table)) +
                  " Every one is in <code>replication_cells.csv</code>.</p>\n";
  const auto outside = std::count_if(table.rows.begin(), table.rows.end(),
                                     [](const CellReplicationRow& r) { return !r.inside; });
  if (outside == 0) return h;
  const auto& keys = meta.swept_keys;
  std::vector<const std::vector<std::string>*> cells;
  for (const CellReplicationRow& r : table.rows) cells.push_back(&r.here->values);
  const std::vector<size_t> shown = VaryingKeys(cells, keys.size(), -1, -1);
  h += "<p>The cell means outside the other store's interval:</p>\n<table><tr>";
  for (size_t k : shown) h += "<th>" + EscapeMarkup(keys[k]) + "</th>";
  h += "<th>metric</th><th>there</th><th>here</th><th>intervals overlap</th></tr>\n";
  const auto text = [](const Interval& i) {
    return fmt::format("{:.3g} [{:.3g}, {:.3g}] (n&nbsp;=&nbsp;{})", i.mean, i.lower, i.upper, i.n);
  };
  for (const CellReplicationRow& r : table.rows) {
    if (r.inside) continue;
    h += "<tr>";
    for (size_t k : shown) h += "<td class=\"k\">" + EscapeMarkup(r.here->values[k]) + "</td>";
    h += fmt::format(
        "<td class=\"k\">{}</td><td>{}</td><td>{}</td><td class=\"k\"{}>{}</td></tr>\n",
        EscapeMarkup(r.metric), text(r.there->stats.at(r.metric)), text(r.here->stats.at(r.metric)),
        r.overlap ? "" : " style=\"background:#f8dede\"", r.overlap ? "yes" : "no");
  }
  return h + "</table>\n";
}

// replication.csv: one row per comparison made in both stores.
std::string ReplicationCsv(const ReplicationTable& table, const Paired& here,
                           const StoreMeta& meta) {
  std::string csv;
  for (const std::string& k : meta.swept_keys) csv += Csv(k) + ",";
  csv +=
      "reference,metric,pairs_there,mean_difference_there,p_value_there,p_holm_there,"
      "verdict_there,kept_there,pairs_here,mean_difference_here,p_value_here,p_holm_here,"
      "verdict_here,kept_here,outcome\n";
  for (const ReplicationRow& r : table.rows) {
    for (const std::string& v : r.here->cell->values) csv += Csv(v) + ",";
    const PairedComparison& a = r.there->metrics.at(r.metric);
    const PairedComparison& b = r.here->metrics.at(r.metric);
    csv += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n", Csv(here.reference),
                       r.metric, a.pairs, Number(a.difference.mean),
                       Tested(a, r.metric) ? Number(a.test.p_value) : std::string(),
                       HolmCsv(r.there->holm.at(r.metric)), VerdictName(r.there_verdict),
                       r.there_kept ? 1 : 0, b.pairs, Number(b.difference.mean),
                       Tested(b, r.metric) ? Number(b.test.p_value) : std::string(),
                       HolmCsv(r.here->holm.at(r.metric)), VerdictName(r.here_verdict),
                       r.here_kept ? 1 : 0, ReplicationName(r.outcome));
  }
  return csv;
}

// The page's section: the sentence, then a row for every comparison that is
// a finding in either store.
std::string PairedReplicationHtml(const ReplicationTable& table, const AgainstStore& there,
                                  const Paired& here, const StoreMeta& meta) {
  const auto& keys = meta.swept_keys;
  const auto si = static_cast<size_t>(here.series_index);
  std::vector<const std::vector<std::string>*> compared;
  for (const ReplicationRow& r : table.rows) compared.push_back(&r.here->cell->values);
  const std::vector<size_t> shown = VaryingKeys(compared, keys.size(), here.series_index, -1);
  std::string h = "<p>" + CodeSpansToHtml(ReplicationSentence(table, there, meta)) +
                  " Each comparison of this report (paired differences, below) made again on "
                  "the other store's runs, with this report's settings; a finding is as in the "
                  "paired differences "
                  "(p&nbsp;&lt;&nbsp;0.05 and an interval that excludes 0), <b>bold</b> when "
                  "Holm's correction keeps it. Rows: the comparisons that are a finding in either "
                  "store; every one is in <code>replication.csv</code>.</p>\n";
  bool any = false;
  for (const ReplicationRow& r : table.rows) any = any || r.outcome != Replication::kNeither;
  if (!any) return h;
  // At a glance: the outcomes per metric, in report.y's order.
  h += "<p>Per metric, at a glance:</p>\n<table><tr><th>metric</th><th>findings "
       "there</th><th>replicated</th><th>weaker here</th><th>not "
       "replicated</th><th>reversed</th><th>new here</th><th>neither</th></tr>\n";
  for (const std::string& m : meta.report.y) {
    std::map<Replication, int> count;
    int there_findings = 0;
    for (const ReplicationRow& r : table.rows) {
      if (r.metric != m) continue;
      ++count[r.outcome];
      there_findings += r.there_verdict != PairedVerdict::kNotSignificant;
    }
    const auto cell = [&](Replication o, const char* colour) {
      const int n = count[o];
      return n > 0 && colour != nullptr
                 ? fmt::format("<td style=\"background:{}\">{}</td>", colour, n)
                 : fmt::format("<td>{}</td>", n);
    };
    h += fmt::format("<tr><td class=\"k\">{}</td><td>{}</td>{}{}{}{}{}{}</tr>\n", EscapeMarkup(m),
                     there_findings, cell(Replication::kReplicated, "#dff3df"),
                     cell(Replication::kWeaker, "#fff3c4"),
                     cell(Replication::kNotReplicated, "#f8dede"),
                     cell(Replication::kReversed, "#f8dede"), cell(Replication::kNewHere, nullptr),
                     cell(Replication::kNeither, nullptr));
  }
  h += "</table>\n<p>The comparisons that are a finding in either store:</p>\n<table><tr>";
  for (size_t k : shown) h += "<th>" + EscapeMarkup(keys[k]) + "</th>";
  h += fmt::format(
      "<th>compared</th><th>metric</th><th>there: {} ({})</th><th>here ({})</th><th>outcome</th>"
      "</tr>\n",
      EscapeMarkup(there.dir), EscapeMarkup(RootSeedShort(there.meta)),
      EscapeMarkup(RootSeedShort(meta)));
  const auto side = [](const PairedComparison& c, PairedVerdict v, bool kept) {
    std::string text = fmt::format(
        "&Delta;&nbsp;{:.3g}, {}, {}", c.difference.mean,
        EveryPairTies(c) ? std::string("every pair tied: not tested") : FormatP(c.test.p_value),
        VerdictName(v));
    return kept ? "<b>" + text + "</b>" : text;
  };
  for (const ReplicationRow& r : table.rows) {
    if (r.outcome == Replication::kNeither) continue;
    const char* style = r.outcome == Replication::kReplicated ? " style=\"background:#dff3df\""
                        : r.outcome == Replication::kWeaker   ? " style=\"background:#fff3c4\""
                        : r.outcome == Replication::kNewHere  ? ""
                                                              : " style=\"background:#f8dede\"";
    h += "<tr>";
    for (size_t k : shown)
      h += "<td class=\"k\">" + EscapeMarkup(r.here->cell->values[k]) + "</td>";
    h += fmt::format(
        "<td class=\"k\">{} &minus; {}</td><td class=\"k\">{}</td><td>{}</td><td>{}</td><td "
        "class=\"k\"{}>{}</td></tr>\n",
        EscapeMarkup(r.here->cell->values[si]), EscapeMarkup(here.reference),
        EscapeMarkup(r.metric), side(r.there->metrics.at(r.metric), r.there_verdict, r.there_kept),
        side(r.here->metrics.at(r.metric), r.here_verdict, r.here_kept), style,
        ReplicationName(r.outcome));
  }
  return h + "</table>\n";
}

// How many finished runs have no folder (runs/ deleted or moved, a copy of
// results.sqlite alone: a bad-input audit found the report linking to them
// without a word), and how many finished runs there are.
std::pair<int64_t, int64_t> AbsentRunFolders(const std::vector<RunRecord>& runs,
                                             const fs::path& dir) {
  int64_t absent = 0, finished = 0;
  for (const RunRecord& r : runs) {
    if (!r.ok) continue;
    ++finished;
    if (!HasRunFolder(dir, r)) ++absent;
  }
  return {absent, finished};
}

// The sentence on the page and in findings.md ("" when every folder is there).
std::string AbsentFoldersSentence(int64_t absent, int64_t finished, const fs::path& dir) {
  if (absent == 0) return "";
  return fmt::format(
      "{} of the {} finished runs have no folder in `{}` (deleted or moved): their numbers here "
      "are the store's, and nothing links to them. `hcpf sweep` with the sweep file on this "
      "folder computes them again.",
      absent, finished, (dir / "runs").string());
}

// Above the resolved base: what the runs did not take from it (an audit: a
// rendered SKS sweep's base read "source: simulated, detector: oracle",
// seed 7 and its sub-seeds, with nothing to say that no run used them).
std::string BaseScenarioNote(const std::vector<RunRecord>& runs, const StoreMeta& meta,
                             const fs::path& dir, const std::string& link_prefix) {
  // Each swept key's values, each once (an audit: an empty shard's page
  // read "frames = ; tracker.particles = ").
  const std::vector<std::vector<std::string>> values =
      SweptValues(runs, meta.swept_keys.size(), meta.expansion);
  const RunRecord* first = nullptr;  // the first finished run whose folder is there
  for (const RunRecord& r : runs) {
    if (r.ok && HasRunFolder(dir, r)) {
      first = &r;
      break;
    }
  }
  std::vector<std::string> set;
  for (size_t k = 0; k < values.size(); ++k) {
    std::string shown;
    for (size_t i = 0; i < values[k].size() && i < 8; ++i)
      shown += (i > 0 ? ", " : "") + EscapeMarkup(values[k][i]);
    if (values[k].size() > 8) shown += fmt::format(", &hellip; ({} values)", values[k].size());
    set.push_back(fmt::format("<code>{}</code> = {}", EscapeMarkup(meta.swept_keys[k]), shown));
  }
  std::string h = "<p>The scenario the sweep starts from, before its grid and zip. ";
  if (!set.empty()) {
    h += fmt::format("Every run replaces {}: {}. ",
                     set.size() == 1 ? "one key" : fmt::format("{} keys", set.size()),
                     fmt::join(set, "; "));
  }
  h += "Its <code>seed</code> and <code>seeds</code> are the base's own: each run's are drawn "
       "from the sweep's root seed and the run's seed index.";
  if (first != nullptr) {
    h += fmt::format(
        " What a run ran, resolved, is its folder's <code>scenario.resolved.yaml</code> (the "
        "first: <a href=\"{0}{1}/scenario.resolved.yaml\">{1}/scenario.resolved.yaml</a>).",
        EscapeMarkup(link_prefix), EscapeMarkup(first->run_dir));
  }
  return h + "</p>\n";
}

// Stage 4, the page. `link_prefix` leads from the report's folder to `dir`
// ("" when the report is written into the sweep folder).
// The metrics of report.y that no finished run measured (NaN in every ok
// run): their plots are empty frames, which the report and the log say why
// (a second bad-input audit: e.g. det_ap on a sweep of detection-level runs
// gave empty plots without a word). Empty when no run finished at all.
std::vector<std::string> UnmeasuredMetrics(const std::vector<RunRecord>& runs,
                                           const std::vector<std::string>& y) {
  std::vector<std::string> out;
  const bool any_ok =
      std::any_of(runs.begin(), runs.end(), [](const RunRecord& r) { return r.ok; });
  if (!any_ok) return out;
  for (const std::string& metric : y) {
    const bool measured = std::any_of(runs.begin(), runs.end(), [&](const RunRecord& r) {
      const auto it = r.metrics.find(metric);
      return r.ok && it != r.metrics.end() && !std::isnan(it->second);
    });
    if (!measured) out.push_back(metric);
  }
  return out;
}

// "det_ap (metrics.json /detection/precision_recall/average_precision)".
std::string WhereMeasured(const std::string& metric) {
  const CatalogueMetric* entry = FindMetric(metric);
  return entry == nullptr ? metric : fmt::format("{} ({} {})", metric, entry->file, entry->pointer);
}

// Whether the report places cells at a measured metric (report.x_metric)
// that no finished run measured: every plot is then empty, and its note
// "no values of this metric" would blame the metric drawn (an audit).
bool XMetricUnmeasured(const std::vector<RunRecord>& runs, const StoreMeta& meta) {
  return !meta.report.x_metric.empty() && !UnmeasuredMetrics(runs, {meta.report.x_metric}).empty();
}

std::string ReportHtml(const fs::path& dir, const std::string& link_prefix, const StoreMeta& meta,
                       const std::vector<RunRecord>& runs, const std::vector<Cell>& cells,
                       const Layout& layout,
                       const std::vector<std::pair<std::string, std::string>>& svgs,
                       const std::string& scene_html, const std::string& findings_html,
                       const std::string& paired_html, const std::string& replication_html,
                       const std::vector<std::string>& unmeasured, const Builds& builds,
                       const std::string& missing_runs) {
  const std::vector<std::string>& keys = meta.swept_keys;
  const int x_index = layout.x_index;
  int64_t ok_runs = 0, failed_runs = 0;
  for (const RunRecord& r : runs) ++(r.ok ? ok_runs : failed_runs);
  std::error_code ec;
  std::string h;
  h += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n";
  h += fmt::format("<title>HCPF sweep report: {}</title>\n", EscapeMarkup(meta.sweep_file));
  h += "<style>body{font-family:sans-serif;margin:1.5em;color:#222}table{border-collapse:collapse;"
       "font-size:13px}td,th{border:1px solid #ccc;padding:3px 7px;text-align:right}"
       "th{background:#f3f3f3}td.k{text-align:left}span.i{white-space:nowrap}.plot{margin:1em 0}"
       ".wide{overflow-x:auto;max-width:100%}"
       "pre{background:#f7f7f7;"
       "padding:1em;font-size:12px;overflow:auto}.failed{color:#b00}</style>\n</head><body>\n";
  h += fmt::format(
      "<h1>Sweep report</h1>\n<p>Sweep <code>{}</code> (hash <code>{}</code>): {} of {} runs "
      "in the store, {} ok, {} failed. Lines: mean over seeds; bands: 95&nbsp;% confidence "
      "interval of that mean over the n seeds of the cell. Proportions (a fraction of counted "
      "events per run: {}) get the Wilson score interval of the mean for the effective number "
      "of trials of the seeds' spread (Korn &amp; Graubard; the binomial over the n seeds when "
      "every seed is 0 or every seed is 1, so a band even there; width 0 when every seed has "
      "one value between); the other metrics mean &plusmn; "
      "t<sub>0.975,&nbsp;n&minus;1</sub>&middot;s/&radic;n (none when n&nbsp;&lt;&nbsp;2), cut "
      "at the metric's bound where it reaches past it (MOTA &le; 1, [0,&nbsp;1] for IDF1, HOTA, "
      "&hellip;, &ge;&nbsp;0 for times and "
      "distances; marked &dagger; in the tables). docs/sweeps.md states the formulas.</p>\n",
      EscapeMarkup(meta.sweep_file), EscapeMarkup(meta.sweep_hash), runs.size(), meta.run_count,
      ok_runs, failed_runs > 0 ? fmt::format("<span class=\"failed\">{}</span>", failed_runs) : "0",
      [&] {
        std::vector<std::string> names;
        for (const std::string& m : meta.report.y) {
          const CatalogueMetric* entry = FindMetric(m);
          if (entry != nullptr && entry->range.proportion) names.push_back(EscapeMarkup(m));
        }
        return names.empty() ? std::string("none of this report's metrics")
                             : fmt::format("<code>{}</code>", fmt::join(names, "</code>, <code>"));
      }());
  if (!missing_runs.empty()) {
    h += "<p class=\"failed\"><strong>" + CodeSpansToHtml(missing_runs) + "</strong></p>\n";
  }
  h += "<p>" + CodeSpansToHtml(RootSeedSentence(meta)) + "</p>\n";
  h += BuildsHtml(builds);
  if (!meta.report.pool.empty()) {
    h += fmt::format(
        "<p>Pooled (<code>report.pool</code>): each cell holds the runs of every value of "
        "<code>{}</code>; tables show <code>all</code>. A seed's runs share its random "
        "streams, so they are averaged first: n, the bands and the paired tests count seeds, "
        "one mean per seed (docs/sweeps.md, \"Measured x and pooled keys\").</p>\n",
        [&] {
          std::vector<std::string> keys;
          for (const std::string& k : meta.report.pool) keys.push_back(EscapeMarkup(k));
          return fmt::format("{}", fmt::join(keys, "</code>, <code>"));
        }());
  }
  h += findings_html;
  h += replication_html;
  h += "<h2>Plots</h2>\n";
  if (XMetricUnmeasured(runs, meta)) {
    h += fmt::format(
        "<p class=\"note\">No finished run of this sweep measured the x axis's metric, {} "
        "(<code>report.x_metric</code>): the plots place each cell at its mean of it, so every "
        "plot is empty, whatever the metrics drawn (detection metrics are measured by rendered "
        "runs, <code>observation.source: rendered</code>).</p>\n",
        EscapeMarkup(WhereMeasured(meta.report.x_metric)));
  }
  if (!unmeasured.empty()) {
    std::vector<std::string> items;
    for (const std::string& m : unmeasured) items.push_back(EscapeMarkup(WhereMeasured(m)));
    h += fmt::format(
        "<p class=\"note\">No finished run of this sweep measured {}: {} plot{} empty (detection "
        "metrics are measured by rendered runs, <code>observation.source: rendered</code>; "
        "filter metrics by the particle filter, not an external tracker).</p>\n",
        fmt::join(items, ", "), unmeasured.size() == 1 ? "its" : "their",
        unmeasured.size() == 1 ? " is" : "s are");
  }
  for (const auto& [id, svg] : svgs) {
    h += fmt::format("<div class=\"plot\" id=\"plot-{}\">\n{}\n</div>\n", EscapeMarkup(id), svg);
  }
  h += paired_html;
  h += std::string(
           "<h2>Cells</h2>\n<p>Mean [95&nbsp;% interval] over the n seeds (W: Wilson; "
           "&dagger;: the t interval cut at the metric's bound)") +
       (meta.report.pool.empty()
            ? ""
            : "; each seed's value is the mean of its pooled runs, and a seed without a value "
              "at every pooled value is left out of a metric's mean and interval") +
       ".</p>\n<div class=\"wide\"><table><tr>";
  for (const std::string& k : keys) h += "<th>" + EscapeMarkup(k) + "</th>";
  // n: the seeds with a finished run at every pooled value (the finished
  // runs themselves without pooled keys); a pooled report adds the runs.
  const bool pooled_report = !meta.report.pool.empty();
  h += pooled_report ? "<th>n</th><th>runs</th><th>failures</th>" : "<th>n</th><th>failures</th>";
  for (const std::string& m : meta.report.y) h += "<th>" + EscapeMarkup(m) + "</th>";
  h += "</tr>\n";
  for (const Cell& c : cells) {
    h += "<tr>";
    for (const std::string& v : c.values) h += "<td class=\"k\">" + EscapeMarkup(v) + "</td>";
    const auto by_seed = OkRunsBySeed(c.runs);
    h += fmt::format("<td>{}</td>",
                     std::count_if(by_seed.begin(), by_seed.end(), [&](const auto& runs) {
                       return static_cast<int>(runs.size()) >= c.pooled_values;
                     }));
    if (pooled_report) h += fmt::format("<td>{}</td>", c.runs.size() - c.failures);
    h += fmt::format("<td{}>{}</td>", c.failures ? " class=\"failed\"" : "", c.failures);
    for (const std::string& m : meta.report.y) {
      const Interval& s = c.stats.at(m);
      if (s.n == 0) {
        h += "<td>&ndash;</td>";
      } else if (s.method == IntervalMethod::kNone) {
        h += fmt::format("<td>{:.4g}</td>", s.mean);
      } else {
        h += fmt::format("<td>{:.4g} [{:.4g}, {:.4g}]{}</td>", s.mean, s.lower, s.upper,
                         s.method == IntervalMethod::kWilson ? "&nbsp;W"
                         : s.clipped                         ? "&dagger;"
                                                             : "");
      }
    }
    h += "</tr>\n";
  }
  h += "</table></div>\n";

  // Overlay videos of the first seed of each line, when the runs wrote them.
  std::string videos;
  const RunRecord* first_video = nullptr;
  for (const std::string& label : layout.lines) {
    std::string links;
    for (const Cell* c : layout.line_cells.at(label)) {
      for (const RunRecord* r : c->runs) {
        if (r->seed_index != 0 || !r->ok) continue;
        if (!fs::exists(dir / r->run_dir / "overlay.mp4", ec)) continue;
        if (first_video == nullptr) first_video = r;
        const std::string x = x_index >= 0 ? c->values[x_index] : "run";
        links += fmt::format(" <a href=\"{}{}/overlay.mp4\">{}</a>", EscapeMarkup(link_prefix),
                             EscapeMarkup(r->run_dir), EscapeMarkup(x));
      }
    }
    if (!links.empty()) videos += fmt::format("<li>{}:{}</li>\n", EscapeMarkup(label), links);
  }
  if (!videos.empty()) {
    h += "<h2>Overlay videos (first seed)</h2>\n<ul>\n" + videos + "</ul>\n";
    // A bare video has no timeline, metrics or frame buttons: its run's
    // report has them (an audit: the links led to raw mp4s alone).
    h += fmt::format(
        "<p>Each link is a run's <code>overlay.mp4</code>. Its run's own report plays it beside "
        "the timeline of targets, detections and filters, with frame buttons: <code>hcpf report "
        "RUN_FOLDER</code>, e.g. <code>hcpf report {}</code> for the first.</p>\n",
        EscapeMarkup(ShellWord((dir / first_video->run_dir).string())));
  }

  std::string failures;
  for (const RunRecord& r : runs) {
    if (!r.ok)
      failures += fmt::format("<li>run {} (<code>{}</code>): {}</li>\n", r.index, r.key,
                              EscapeMarkup(r.error));
  }
  if (!failures.empty())
    h += "<h2>Failed runs</h2>\n<ul class=\"failed\">\n" + failures + "</ul>\n";
  // The scene, drawn and (rendered sweeps) sampled, beside the base
  // scenario that describes it.
  h += scene_html;
  h += SceneContactSheet(dir);
  const bool several_bases = std::find(keys.begin(), keys.end(), kSweptBaseKey) != keys.end();
  h += fmt::format("<h2>Base scenario{} (resolved)</h2>\n", several_bases ? "s" : "");
  h += BaseScenarioNote(runs, meta, dir, link_prefix);
  h += fmt::format("<pre>{}</pre>\n", EscapeMarkup(meta.base_resolved));
  h += "</body></html>\n";
  return h;
}

}  // namespace

ReportFolder ClassifyReportFolder(const std::string& dir) {
  const std::string expected =
      "a sweep folder (holding results.sqlite, written by hcpf sweep --out) or a run folder "
      "(holding manifest.json with \"format\": \"hcpf-run/1\", written by hcpf run --out)";
  const auto error = [&](const std::string& found) {
    return InputError(SourceLocation{dir, 0, 0, "DIR"}, expected, found);
  };
  std::error_code ec;
  const fs::path path(dir);
  if (!fs::exists(path, ec)) throw error("no such folder");
  if (!fs::is_directory(path, ec)) throw error("a file, not a folder");
  if (fs::exists(path / "results.sqlite", ec)) return ReportFolder::kSweep;
  const fs::path manifest_path = path / "manifest.json";
  if (!fs::is_regular_file(manifest_path, ec)) {
    throw error("a folder with neither results.sqlite nor manifest.json");
  }
  nlohmann::json manifest;
  try {
    manifest = nlohmann::json::parse(
        ReadInputFile(manifest_path.string(), "a run manifest (JSON)", std::uint64_t{64} << 20));
  } catch (const nlohmann::json::exception& e) {
    throw error(fmt::format("a manifest.json that is not JSON ({})", e.what()));
  }
  const std::string format =
      manifest.is_object() && manifest.contains("format") && manifest["format"].is_string()
          ? manifest["format"].get<std::string>()
          : std::string();
  if (format == "hcpf-run/1") return ReportFolder::kRun;
  if (format == "hcpf-render/1") {
    throw error(
        "a render folder (manifest.json \"format\": \"hcpf-render/1\", written by hcpf render: "
        "it has frames, no metrics)");
  }
  throw error(format.empty() ? std::string("a manifest.json without a \"format\" of this tool")
                             : fmt::format("a manifest.json of format \"{}\"", format));
}

// The scene from above (SceneSketch), from the gt.json of the first
// finished run of each base scenario (one sketch, or one per value of a
// swept `base`): every sweep report gets a picture of its scene, rendered or
// not (an audit: the main job's report had none). A run folder without a
// gt.json, or with one that does not read, is said, not drawn.
std::string SceneSketchHtml(const fs::path& dir, const std::vector<Cell>& cells,
                            const StoreMeta& meta, const fs::path& work,
                            const std::string& gnuplot) {
  const auto& keys = meta.swept_keys;
  const auto base = std::find(keys.begin(), keys.end(), kSweptBaseKey);
  std::vector<std::string> seen;
  std::string body;
  for (const Cell& c : cells) {
    const std::string value =
        base == keys.end() ? std::string() : c.values[static_cast<size_t>(base - keys.begin())];
    if (std::find(seen.begin(), seen.end(), value) != seen.end()) continue;
    // The first finished run whose folder is there (a bad-input audit: a
    // deleted first run was "its folder has no gt.json").
    const auto run = std::find_if(c.runs.begin(), c.runs.end(), [&](const RunRecord* r) {
      return r->ok && HasRunFolder(dir, *r);
    });
    if (run == c.runs.end()) continue;
    seen.push_back(value);
    const fs::path gt = dir / (*run)->run_dir / "gt.json";
    // The run and its cell's swept values (a review: a sweep over the
    // camera's position showed one altitude's scene, unnamed).
    std::vector<std::string> swept;
    for (size_t k = 0; k < keys.size() && k < c.values.size(); ++k) {
      swept.push_back(keys[k] + " = " + c.values[k]);
    }
    const std::string who =
        fmt::format("run {} (seed index {}{}{})", (*run)->key, (*run)->seed_index,
                    swept.empty() ? "" : "; ", fmt::join(swept, ", "));
    std::error_code ec;
    if (!fs::is_regular_file(gt, ec)) {
      body += "<p class=\"note\">No sketch of " + EscapeMarkup(who) +
              ": its folder has no "
              "<code>gt.json</code>.</p>\n";
      continue;
    }
    try {
      const SceneSketch sketch = SketchOf(metrics::ReadGroundTruthJson(gt.string()));
      body += "<p>" + EscapeMarkup(who) + ": " + EscapeMarkup(EncounterText(sketch)) + ".</p>\n";
      body += "<div class=\"plot\">\n" +
              SceneSketchSvg(sketch, "The scene from above: run " + (*run)->key, work, gnuplot,
                             std::to_string(seen.size() - 1)) +
              "\n</div>\n";
    } catch (const InputError& e) {
      body += "<p class=\"note\">No sketch of " + EscapeMarkup(who) + ": " +
              EscapeMarkup(e.what()) + "</p>\n";
    }
  }
  if (body.empty()) return {};
  return "<h2 id=\"scene\">The scene from above</h2>\n<p>Drawn from the ground truth "
         "(<code>gt.json</code>) of the first finished run: each target's path on the ground "
         "(metres, x east, y north) with a dot every 10th frame and the frame number (from 1) "
         "every 50th, a ring where less than 0.75 of it is visible in the image, and the ground "
         "the camera sees (dashed) at its first, middle and last frame. It is that run's scene: "
         "other "
         "seeds differ where the scenario draws from its seed, and other cells where a swept key "
         "moves the camera or the targets.</p>\n" +
         body;
}

ReportResult WriteReport(const ReportOptions& options) {
  options.Validate();
  if (ClassifyReportFolder(options.dir) == ReportFolder::kRun) return WriteRunReport(options);
  if (!options.more_against.empty()) {
    throw InputError(SourceLocation{"hcpf report", 0, 0, "--against"},
                     fmt::format("one --against with the sweep folder {} (a sweep is compared "
                                 "with one other sweep; several --against compare runs)",
                                 options.dir),
                     fmt::format("{} more after {}: {}", options.more_against.size(),
                                 options.against, fmt::join(options.more_against, ", ")));
  }
  const fs::path dir(options.dir);
  if (!options.out_dir.empty()) CheckReportOut(options.out_dir);
  const fs::path out = options.out_dir.empty() ? dir : fs::path(options.out_dir);
  auto store = ResultsStore::Open((dir / "results.sqlite").string(), StoreAccess::kReadOnly);
  if (const std::string unchecked = UncheckedLabelsSentence(*store); !unchecked.empty()) {
    spdlog::warn("report: {}", unchecked);
  }
  const StoreMeta& meta = store->meta();
  const std::vector<RunRecord> runs = store->Runs();
  const std::vector<Cell> cells = CellsOf(runs, meta);
  const Layout layout = LayoutOf(cells, meta);
  // Paired differences against the reference series value (their plots
  // below), and --against read and checked before anything is written.
  const Paired paired = PairedRowsOf(cells, meta);
  if (paired.reference_absent) {
    spdlog::warn(
        "report: no run has the reference value {} = {} (report.reference): nothing is "
        "compared",
        meta.report.series, paired.reference);
  }
  const std::unique_ptr<AgainstStore> there =
      options.against.empty() ? nullptr : OpenAgainst(options.against, dir, meta, runs, paired);

  const fs::path work = MakePlotWorkDir(out, options.out_dir.empty());
  std::error_code ec;
  // Links to run folders (overlay videos) from the report's folder.
  std::string link_prefix;
  if (!options.out_dir.empty()) {
    link_prefix = LinkFrom(out, dir) + "/";
  }
  ReportResult result;
  const std::string missing_runs = MissingRunsSentence(meta, runs.size());
  if (!missing_runs.empty()) {
    spdlog::warn("report: {}", missing_runs);
    result.missing_runs = meta.run_count - static_cast<int64_t>(runs.size());
  }
  const auto [absent, finished] = AbsentRunFolders(runs, dir);
  const std::string absent_folders = AbsentFoldersSentence(absent, finished, dir);
  if (!absent_folders.empty()) {
    spdlog::warn("report: {}", absent_folders);
    result.absent_run_folders = absent;
  }
  const std::string missing =
      missing_runs + (missing_runs.empty() || absent_folders.empty() ? "" : " ") + absent_folders;
  const Builds builds = BuildsOf(runs, dir);
  result.builds = static_cast<int>(builds.runs.size());
  if (builds.runs.size() > 1) {
    spdlog::warn("report: the finished runs were made by {} builds of hcpf (the report names them)",
                 builds.runs.size());
  }
  const std::vector<std::string> unmeasured = UnmeasuredMetrics(runs, meta.report.y);
  for (const std::string& metric : unmeasured) {
    spdlog::warn("report: no finished run measured {}: its plot is empty", WhereMeasured(metric));
  }
  if (XMetricUnmeasured(runs, meta)) {
    spdlog::warn(
        "report: no finished run measured the x axis's metric, {} (report.x_metric): every plot "
        "is empty",
        WhereMeasured(meta.report.x_metric));
  }
  std::vector<std::pair<std::string, std::string>> svgs =
      Plots(cells, layout, meta, work, options.gnuplot, "", "");
  result.plots = static_cast<int>(svgs.size());
  // The paired differences' plots (files d<i>, ids
  // difference-<metric>[-<panel index>]).
  const std::vector<Cell> difference_cells = DifferenceCells(paired, meta);
  std::vector<std::pair<std::string, std::string>> difference_svgs;
  if (!difference_cells.empty()) {
    difference_svgs = Plots(difference_cells, LayoutOf(difference_cells, meta), meta, work,
                            options.gnuplot, "d", paired.reference);
  }
  result.difference_plots = static_cast<int>(difference_svgs.size());
  result.comparisons = static_cast<int>(paired.rows.size());
  // Every file is made before any is written, and they replace the earlier
  // report's as one set (PublishReportFiles).
  std::vector<std::pair<std::string, std::string>> files;
  std::vector<std::string> stale;  // files of an earlier report in this folder
  if (!paired.rows.empty()) {
    files.emplace_back("paired.csv", PairedCsv(paired, meta));
  } else {
    stale.push_back("paired.csv");
  }
  // The findings, also as findings.md (read without a browser).
  const std::vector<Finding> findings = FindingsOf(cells, paired, meta, layout);
  const std::vector<std::string> summary = SummaryOf(cells, paired, meta, layout);
  const GlanceTable glance = GlanceOf(paired, meta);
  result.findings = static_cast<int>(findings.size());
  if (!findings.empty()) {
    files.emplace_back("findings.md",
                       FindingsMarkdown(findings, glance, paired, meta, summary, missing));
  } else {
    stale.push_back("findings.md");
  }
  // Replication against another store of the same swept keys.
  std::string replication_html;
  if (there) {
    replication_html = "<h2 id=\"replication\">Replication</h2>\n";
    std::string sentence;
    if (paired.series_index >= 0) {
      const ReplicationTable table = ReplicationOf(paired, *there, meta);
      result.replication_comparisons = static_cast<int>(table.rows.size());
      files.emplace_back("replication.csv", ReplicationCsv(table, paired, meta));
      replication_html += PairedReplicationHtml(table, *there, paired, meta);
      sentence = ReplicationSentence(table, *there, meta);
    } else {
      stale.push_back("replication.csv");
      // A store with a series but no finished run (an empty shard) has no
      // cell to compare (an audit: it said "without report.series").
      sentence = AgainstIntro(*there, meta) +
                 (meta.report.series.empty()
                      ? std::string(": without `report.series` there are no paired comparisons "
                                    "to make again. ")
                      : std::string(": this store holds no finished run, so there are no paired "
                                    "comparisons to make again. ")) +
                 SameSeedNote(*there, meta);
      while (!sentence.empty() && sentence.back() == ' ') sentence.pop_back();
      replication_html += "<p>" + CodeSpansToHtml(sentence) + "</p>\n";
    }
    // Cell by cell, with or without a series.
    const CellReplicationTable cell_table = CellReplicationOf(cells, *there, meta);
    result.replication_cells = static_cast<int>(cell_table.rows.size());
    files.emplace_back("replication_cells.csv", CellReplicationCsv(cell_table, meta));
    replication_html += CellReplicationHtml(cell_table, meta);
    if (!there->respelled.empty()) {
      replication_html += "<p>Values of the other store read in this store's spelling:</p>\n<ul>";
      for (const std::string& line : there->respelled) {
        replication_html += "<li>" + EscapeMarkup(line) + "</li>";
      }
      replication_html += "</ul>\n";
    }
    const std::string cell_sentence = CellReplicationSentence(cell_table);
    spdlog::info("report: {}", sentence);
    spdlog::info("report: {}", cell_sentence);
    for (auto& [name, text] : files) {
      if (name == "findings.md") {
        text += "\n## Replication\n\n" + sentence + "\n\n" + cell_sentence + "\n";
      }
    }
  } else {
    stale.push_back("replication.csv");
    stale.push_back("replication_cells.csv");
  }
  files.emplace_back("summary.csv", SummaryCsv(cells, meta.swept_keys));
  files.emplace_back(
      "report.html",
      ReportHtml(dir, link_prefix, meta, runs, cells, layout, svgs,
                 SceneSketchHtml(dir, cells, meta, work, options.gnuplot),
                 FindingsHtml(findings, glance, paired, meta, summary),
                 PairedHtml(paired, meta, layout, difference_svgs, options.dir, link_prefix),
                 replication_html, unmeasured, builds, missing));
  PublishReportFiles(work, out, files, stale);
  result.csv_path = (out / "summary.csv").string();
  result.html_path = (out / "report.html").string();
  result.cells = static_cast<int>(cells.size());
  fs::remove_all(work, ec);
  return result;
}

}  // namespace hcpf::studies
