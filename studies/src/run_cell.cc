// `hcpf report RUN --against SWEEP`: the run set beside its cell's seeds.

#include "run_cell.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>
#include <set>
#include <utility>

#include "hcpf/core/error.h"
#include "hcpf/core/text_file.h"
#include "hcpf/scenarios/scenario.h"
#include "hcpf/studies/statistics.h"
#include "text.h"

namespace hcpf::studies {

namespace fs = std::filesystem;

namespace {

const SourceLocation kAgainst{"hcpf report", 0, 0, "--against"};

// A cell's values as "k = v, k2 = v2".
std::string ValuesText(const std::vector<std::string>& keys,
                       const std::vector<std::string>& values) {
  std::string out;
  for (size_t k = 0; k < keys.size() && k < values.size(); ++k) {
    out += fmt::format("{}{} = {}", out.empty() ? "" : ", ", keys[k], values[k]);
  }
  return out;
}

// "k = v, k2 = v2" in code spans.
std::string CellName(const RunCell& cell) {
  std::string out;
  for (size_t k = 0; k < cell.keys.size() && k < cell.values.size(); ++k) {
    out += fmt::format("{}<code>{} = {}</code>", out.empty() ? "" : ", ",
                       EscapeMarkup(cell.keys[k]), EscapeMarkup(cell.values[k]));
  }
  return out;
}

// The leaf differences as lines "key: A's → the other's".
std::string DifferenceLines(const std::vector<config::LeafDifference>& differ) {
  std::string rows;
  for (const config::LeafDifference& d : differ) {
    rows += fmt::format("<br><code>{}</code>: {} → {}", EscapeMarkup(d.key),
                        EscapeMarkup(d.first.value_or("(absent)")),
                        EscapeMarkup(d.second.value_or("(absent)")));
  }
  return rows;
}

// The whole-number `seed` of a resolved scenario, nullopt without one.
std::optional<uint64_t> SeedOf(const config::YamlLeaves& leaves) {
  const auto it = leaves.find("seed");
  if (it == leaves.end()) return std::nullopt;
  try {
    return YAML::Node(it->second).as<uint64_t>();
  } catch (const YAML::Exception&) {
    return std::nullopt;
  }
}

// A resolved scenario read once: its file and its leaves.
struct Resolved {
  fs::path file;
  config::YamlLeaves leaves;
};

// A run folder's scenario.resolved.yaml when it is there, not empty, YAML
// and with a whole-number `seed` (a damaged file is no file here: the
// cell's next run is read).
std::optional<Resolved> ReadableResolved(const fs::path& sweep, const RunRecord& r) {
  std::error_code ec;
  if (r.run_dir.empty()) return std::nullopt;
  Resolved out{sweep / r.run_dir / "scenario.resolved.yaml", {}};
  if (!fs::is_regular_file(out.file, ec)) return std::nullopt;
  const std::string text = ReadWholeFile(out.file);
  if (text.empty()) return std::nullopt;
  try {
    out.leaves = config::FlattenYaml(text);
  } catch (const YAML::Exception&) {
    return std::nullopt;
  }
  if (!SeedOf(out.leaves)) return std::nullopt;
  return out;
}

// The dotted keys of the `seeds:` map.
constexpr std::string_view kSeedsPrefix = "seeds.";

// The `seeds.X` leaves of a resolved scenario, by key, as written.
std::map<std::string, std::string> SeedLeaves(const config::YamlLeaves& leaves) {
  std::map<std::string, std::string> out;
  for (auto it = leaves.lower_bound(std::string(kSeedsPrefix));
       it != leaves.end() && it->first.starts_with(kSeedsPrefix); ++it) {
    if (it->first.find_first_of(".[", kSeedsPrefix.size()) == std::string::npos) {
      out.insert(*it);
    }
  }
  return out;
}

// The leaves of a resolved scenario that are draws of its seed: `seed`,
// and each `seeds.X` equal to what `seed` derives for X (not pinned by the
// scenario, not swept). Empty without a whole-number seed.
std::set<std::string> DrawnLeaves(const config::YamlLeaves& leaves) {
  std::set<std::string> out;
  const std::optional<uint64_t> seed = SeedOf(leaves);
  if (!seed) return out;
  out.insert("seed");
  for (const auto& [key, value] : SeedLeaves(leaves)) {
    const std::string name = key.substr(kSeedsPrefix.size());
    if (value == std::to_string(scenarios::DeriveSeed(*seed, name.c_str()))) out.insert(key);
  }
  return out;
}

}  // namespace

RunCell FindRunCell(const std::string& sweep_dir, const std::string& run_dir,
                    const std::string& run_resolved, uint64_t run_seed) {
  const fs::path dir(sweep_dir);
  const fs::path store_file = dir / "results.sqlite";
  std::error_code ec;
  if (!fs::is_regular_file(store_file, ec)) {
    throw InputError(kAgainst, "a sweep folder (results.sqlite, a file)",
                     fmt::format("{}, not a file", store_file.string()));
  }
  std::unique_ptr<ResultsStore> store;
  try {
    store = ResultsStore::Open(store_file.string(), StoreAccess::kReadOnly);
  } catch (const InputError& e) {
    throw InputError(kAgainst, "a sweep folder whose results.sqlite is a results store",
                     fmt::format("{}: {}", store_file.string(), e.found()));
  }
  RunCell best;
  best.sweep_dir = sweep_dir;
  const std::vector<RunRecord> runs = store->Runs();
  best.missing_runs = MissingRunsSentence(store->meta(), runs.size());
  // A swept `seed` replicates (a sweep of explicit seeds): its column makes
  // no cell.
  const std::vector<std::string>& swept = store->meta().swept_keys;
  const auto seed_column = std::find(swept.begin(), swept.end(), "seed") - swept.begin();
  const auto cell_values = [&](const std::vector<std::string>& values) {
    std::vector<std::string> out = values;
    if (seed_column < static_cast<std::ptrdiff_t>(out.size())) out.erase(out.begin() + seed_column);
    return out;
  };
  best.keys = cell_values(swept);
  // The cells in the order of their first run (the expansion's); the row
  // of the run's own folder when it is one of the store's.
  std::vector<std::vector<std::string>> order;
  std::map<std::vector<std::string>, std::vector<size_t>> rows_of;
  std::optional<size_t> own_row;
  for (size_t i = 0; i < runs.size(); ++i) {
    const std::vector<std::string> values = cell_values(runs[i].values);
    auto [it, inserted] = rows_of.try_emplace(values);
    if (inserted) order.push_back(values);
    it->second.push_back(i);
    if (!own_row && !runs[i].run_dir.empty() &&
        fs::equivalent(dir / runs[i].run_dir, run_dir, ec)) {
      own_row = i;
    }
  }
  // Each cell compared through the first two of its runs whose folders
  // hold a readable file (one damaged file does not decide it).
  struct Compared {
    const std::vector<std::string>* values;
    std::vector<config::LeafDifference> differ;
    std::set<std::string> drawn;
    fs::path file;
    // The drawn leaves A's scenario differs from `file` in: between two
    // cells as near, the one that needs fewer of its draws to hold A's
    // scenario is A's (a base pinning seeds.world beside one drawing it).
    size_t by_draws = 0;
  };
  // A's leaves, flattened once for every comparison (its text is YAML with a
  // seed: FindRunCellOf has read it).
  const config::YamlLeaves run_leaves = config::FlattenYaml(run_resolved);
  const std::set<std::string> run_drawn = DrawnLeaves(run_leaves);
  std::vector<Compared> compared;
  for (const std::vector<std::string>& values : order) {
    std::vector<Resolved> texts;
    for (const size_t i : rows_of[values]) {
      if (std::optional<Resolved> text = ReadableResolved(dir, runs[i])) {
        texts.push_back(std::move(*text));
        if (texts.size() == 2) break;
      }
    }
    if (texts.empty()) {
      best.uncompared.push_back(ValuesText(best.keys, values));
      continue;
    }
    // What the cell's seeds are drawn over: `seed`, and the seeds.X two of
    // its runs differ in; with one run, the seeds.X it and A both derive
    // from their `seed`. A seed pinned or swept counts like any other key.
    Compared c{&values, {}, {"seed"}, {}};
    if (texts.size() == 2) {
      const std::map<std::string, std::string> one = SeedLeaves(texts[0].leaves);
      const std::map<std::string, std::string> two = SeedLeaves(texts[1].leaves);
      for (const auto& [key, value] : one) {
        const auto it = two.find(key);
        if (it != two.end() && it->second != value) c.drawn.insert(key);
      }
    } else {
      for (const std::string& key : DrawnLeaves(texts[0].leaves)) {
        if (run_drawn.contains(key)) c.drawn.insert(key);
      }
    }
    for (const auto& [file, leaves] : texts) {
      std::vector<config::LeafDifference> differ = config::DifferingLeaves(run_leaves, leaves);
      const size_t all = differ.size();
      std::erase_if(differ,
                    [&](const config::LeafDifference& d) { return c.drawn.contains(d.key); });
      const size_t by_draws = all - differ.size();
      if (c.file.empty() ||
          std::pair(differ.size(), by_draws) < std::pair(c.differ.size(), c.by_draws)) {
        c.differ = std::move(differ);
        c.file = file;
        c.by_draws = by_draws;
      }
    }
    compared.push_back(std::move(c));
  }
  if (compared.empty()) {
    throw InputError(
        kAgainst,
        "a sweep folder whose run folders hold scenario.resolved.yaml (the run's cell is the one "
        "whose resolved scenario is the run's, seeds aside)",
        fmt::format("{}: {}", sweep_dir,
                    runs.empty() ? "no runs in its results.sqlite"
                                 : fmt::format("none of its {} runs' folders holds one (runs/ "
                                               "removed, or the store copied alone)",
                                               runs.size())));
  }
  best.cells = compared.size();
  // The run's own cell when it is one of the store's runs; else the first
  // of the fewest differences.
  const auto nearness = [](const Compared& c) { return std::pair(c.differ.size(), c.by_draws); };
  auto chosen = std::min_element(
      compared.begin(), compared.end(),
      [&](const Compared& a, const Compared& b) { return nearness(a) < nearness(b); });
  if (own_row) {
    // A's own cell, whatever its other files hold: A is one of its runs.
    const auto it = std::find_if(compared.begin(), compared.end(),
                                 [&, own = cell_values(runs[*own_row].values)](const Compared& c) {
                                   return *c.values == own;
                                 });
    if (it != compared.end()) {
      chosen = it;
      chosen->differ.clear();
      chosen->by_draws = 0;
      chosen->file = fs::path(run_dir) / "scenario.resolved.yaml";
    }
  }
  for (const Compared& c : compared) {
    if (&c != &*chosen && nearness(c) == nearness(*chosen)) {
      best.as_near.push_back(ValuesText(best.keys, *c.values));
    }
  }
  best.values = *chosen->values;
  best.differences = chosen->differ;
  best.compared_file = chosen->file.string();
  for (const size_t j : rows_of[best.values]) {
    if (j == own_row) best.itself = best.runs.size();
    best.runs.push_back(runs[j]);
  }
  const std::set<std::string>& drawn = chosen->drawn;
  best.drawn.assign(drawn.begin(), drawn.end());
  for (size_t i = 0; i < best.runs.size(); ++i) {
    const RunRecord& r = best.runs[i];
    if (i == best.itself) continue;
    if (best.same_seed || r.seed != run_seed) continue;
    best.same_seed = i;
    if (const std::optional<Resolved> text = ReadableResolved(dir, r)) {
      best.same_seed_differences = config::DifferingLeaves(run_leaves, text->leaves);
    }
  }
  return best;
}

std::string MetricValueText(const CatalogueMetric& m, double v, bool sign) {
  if (!std::isfinite(v)) return "–";
  if (sign && v == 0.0) return "0";
  const bool score = m.unit.empty() && m.range.upper == 1.0;
  const bool whole = !score && v == std::round(v) && std::abs(v) < 1e15;
  // A difference a score's 3 decimals would print as +0.000: 2 digits.
  if (score && sign && std::abs(v) < 0.0005) return fmt::format("{:+.2g}", v);
  return fmt::format(fmt::runtime(score   ? (sign ? "{:+.3f}" : "{:.3f}")
                                  : whole ? (sign ? "{:+.0f}" : "{:.0f}")
                                          : (sign ? "{:+.4g}" : "{:.4g}")),
                     v);
}

std::string RunCellSection(const RunCell& cell, const std::map<std::string, double>& headline,
                           const std::string& build) {
  const auto value_of = [&headline](const std::string& name) {
    const auto it = headline.find(name);
    return it == headline.end() ? kNaN : it->second;
  };
  // The cell's finished runs, A's own folder aside (A reported from inside
  // the sweep is not one more of its seeds).
  std::vector<const RunRecord*> ok;
  for (size_t i = 0; i < cell.runs.size(); ++i) {
    if (cell.runs[i].ok && cell.itself != i) ok.push_back(&cell.runs[i]);
  }
  const std::string drawn =
      cell.drawn.empty()
          ? std::string("nothing")
          : fmt::format("<code>{}</code>",
                        EscapeMarkup(fmt::format("{}", fmt::join(cell.drawn, ", "))));
  std::string h = "<h2>Beside a sweep's cell</h2>\n";
  h += fmt::format(
      "<p>Run A is set beside {} of the sweep <code>{}</code> "
      "(<code>--against</code>): {} run{} of it, {} finished. Its seeds are drawn over {}.",
      cell.keys.empty() ? std::string("the one cell") : "the cell " + CellName(cell),
      EscapeMarkup(cell.sweep_dir), cell.runs.size(), cell.runs.size() == 1 ? "" : "s",
      ok.size() + (cell.itself && cell.runs[*cell.itself].ok), drawn);
  if (!cell.missing_runs.empty()) h += " " + CodeSpansToHtml(cell.missing_runs);
  const std::string uncompared =
      cell.uncompared.empty()
          ? std::string()
          : fmt::format(
                " {} cell{} could not be compared (no run folder with a readable "
                "<code>scenario.resolved.yaml</code>): {}.",
                cell.uncompared.size(), cell.uncompared.size() == 1 ? "" : "s",
                EscapeMarkup(fmt::format("{}", fmt::join(cell.uncompared, "; "))));
  const std::string as_near =
      cell.as_near.empty()
          ? std::string()
          : fmt::format(" {} other cell{} {} as near, left out: {}.", cell.as_near.size(),
                        cell.as_near.size() == 1 ? "" : "s",
                        cell.as_near.size() == 1 ? "is" : "are",
                        EscapeMarkup(fmt::format("{}", fmt::join(cell.as_near, "; "))));
  if (cell.differences.empty()) {
    const bool replay =
        cell.same_seed && cell.same_seed_differences && cell.same_seed_differences->empty();
    h += fmt::format(
        " Its resolved scenario is A's but for those (<code>{}</code> compared with A's): {}.{}{}"
        "</p>\n",
        EscapeMarkup(cell.compared_file),
        cell.itself ? "A is one of this cell's runs"
        : replay    ? "A replays one of this cell's runs (below)"
                    : "A is one more draw of this cell",
        as_near, uncompared);
  } else {
    h += fmt::format(
        "</p>\n<p style=\"background:#fff3cd;padding:4px\"><b>No cell of the sweep has A's "
        "resolved scenario</b> but for the drawn keys ({} cell{} compared).{} This, the nearest, "
        "differs from A in {} key{} (A's → the cell's, from <code>{}</code>):{}<br>{}Its seeds "
        "are not A's population: read A's place among them with that in mind.</p>\n",
        cell.cells, cell.cells == 1 ? "" : "s", uncompared, cell.differences.size(),
        cell.differences.size() == 1 ? "" : "s", EscapeMarkup(cell.compared_file),
        DifferenceLines(cell.differences), as_near.empty() ? "" : as_near.substr(1) + " ");
  }

  if (cell.itself) {
    h += fmt::format(
        "<p>A is the cell's run <code>{}</code> itself: it is left out of the seeds below.</p>\n",
        EscapeMarkup(cell.runs[*cell.itself].run_dir));
  }
  // The cell's run of A's seed: the same resolved scenario gives the same
  // outputs (docs/outputs.md, "Determinism"), so the same metrics but for
  // the times. Of another scenario, its values are not expected to be A's.
  if (cell.same_seed) {
    const RunRecord& r = cell.runs[*cell.same_seed];
    const std::string who = fmt::format("The cell's run <code>{}</code> has A's seed {}",
                                        EscapeMarkup(r.run_dir), r.seed);
    const auto& differ = cell.same_seed_differences;
    if (!r.ok) {
      h += fmt::format("<p>{}; it failed ({}).</p>\n", who, EscapeMarkup(r.error));
    } else if (differ && !differ->empty()) {
      h += fmt::format(
          "<p>{}, but its resolved scenario differs from A's in {} key{}, so its values are not "
          "expected to be A's (A's → that run's):{}</p>\n",
          who, differ->size(), differ->size() == 1 ? "" : "s", DifferenceLines(*differ));
    } else {
      std::vector<std::string> unequal;  // metrics that run gives otherwise
      int compared = 0;
      for (const CatalogueMetric& m : MetricCatalogue()) {
        if (MachineDependent(m.name)) continue;
        const std::string name(m.name);
        const double a = value_of(name);
        const auto it = r.metrics.find(name);
        const double b = it == r.metrics.end() ? kNaN : it->second;
        if (!std::isfinite(a) && !std::isfinite(b)) continue;
        ++compared;
        if (a == b) continue;
        // Shortest round-trip digits where the table's would print one text.
        const bool alike = MetricValueText(m, a, false) == MetricValueText(m, b, false);
        unequal.push_back(fmt::format("<code>{}</code> (A {}, that run {})", EscapeMarkup(name),
                                      alike ? fmt::format("{}", a) : MetricValueText(m, a, false),
                                      alike ? fmt::format("{}", b) : MetricValueText(m, b, false)));
      }
      const std::string scenario =
          differ ? " and A's whole resolved scenario, so it should give A's metrics "
                   "(docs/outputs.md, \"Determinism\")"
                 : " (its folder holds no readable resolved scenario: whether it is A's is not "
                   "known)";
      const std::string builds =
          r.build && !r.build->empty()
              ? fmt::format(" It was made by hcpf {}, A by {}.", EscapeMarkup(*r.build),
                            EscapeMarkup(build.empty() ? "an hcpf that names no build" : build))
              : std::string();
      if (unequal.empty()) {
        h += fmt::format(
            "<p>{}{}. It gives A's values in all {} metrics measured (the times aside, which "
            "depend on the machine).{} It is one of the cell's seeds below.</p>\n",
            who, scenario, compared, builds);
      } else {
        // Marked only where the scenarios are known to be one.
        h += fmt::format(
            "<p{}>{}{}. <b>It gives other values in {} of {} metrics</b> (the times aside): "
            "{}.{} It is one of the cell's seeds below.</p>\n",
            differ ? " style=\"background:#f8dede;padding:4px\"" : "", who, scenario,
            unequal.size(), compared, fmt::join(unequal, ", "), builds);
      }
    }
  } else if (!cell.itself) {
    h += "<p>A's seed is none of the cell's: A is a draw beside them, not one of them.</p>\n";
  }

  h += "<table><tr><th>metric</th><th>name</th><th>A</th><th>seeds</th><th>mean</th>"
       "<th>95 % interval of the mean</th><th>lowest</th><th>highest</th>"
       "<th>A among the seeds</th></tr>\n";
  for (const CatalogueMetric& m : MetricCatalogue()) {
    const std::string name(m.name);
    // A distance in px below kRoundingPx is rounding, as in the headline table.
    const auto rounded = [&m](double v) { return m.unit == "px" ? RoundedPx(v) : v; };
    const double a = rounded(value_of(name));
    std::vector<double> values;
    for (const RunRecord* r : ok) {
      const auto it = r->metrics.find(name);
      if (it != r->metrics.end() && std::isfinite(it->second)) {
        values.push_back(rounded(it->second));
      }
    }
    if (!std::isfinite(a) && values.empty()) continue;  // measured nowhere
    const Interval interval = MeanInterval95(values, m.range);
    const auto [low, high] = values.empty()
                                 ? std::pair{kNaN, kNaN}
                                 : std::pair{*std::min_element(values.begin(), values.end()),
                                             *std::max_element(values.begin(), values.end())};
    std::string place = "–";
    std::string style;
    if (std::isfinite(a) && !values.empty()) {
      const auto below =
          std::count_if(values.begin(), values.end(), [a](double v) { return v < a; });
      const auto equal = std::count(values.begin(), values.end(), a);
      const auto above = static_cast<long>(values.size()) - below - equal;
      if (below == static_cast<long>(values.size()) || above == static_cast<long>(values.size())) {
        place = below > 0 ? "higher than every seed" : "lower than every seed";
        // Outside the cell's range: marked, not called better or worse (one
        // seed is no range).
        if (!MachineDependent(m.name) && values.size() >= 2) {
          style = " style=\"background:#fff3cd\"";
        }
      } else {
        std::vector<std::string> parts;
        if (below > 0) parts.push_back(fmt::format("higher than {}", below));
        if (equal > 0) parts.push_back(fmt::format("equal to {}", equal));
        if (above > 0) parts.push_back(fmt::format("lower than {}", above));
        place = fmt::format("{} of {}", fmt::join(parts, ", "), values.size());
      }
    }
    const std::string unit = m.unit.empty() ? "" : " " + EscapeMarkup(std::string(m.unit));
    const auto with_unit = [&](double v) {
      return MetricValueText(m, v, false) + (std::isfinite(v) ? unit : "");
    };
    const std::string band =
        interval.method == IntervalMethod::kNone
            ? "–"
            : fmt::format("{} to {}", MetricValueText(m, interval.lower, false),
                          with_unit(interval.upper));
    h += fmt::format(
        "<tr><td class=\"k\">{}</td><td class=\"k\"><code>{}</code></td><td>{}</td><td>{}</td>"
        "<td>{}</td><td>{}</td><td>{}</td><td>{}</td><td class=\"k\"{}>{}</td></tr>\n",
        EscapeMarkup(std::string(m.label)), EscapeMarkup(name), with_unit(a), values.size(),
        with_unit(interval.mean), band, with_unit(low), with_unit(high), style, place);
  }
  h += "</table>\n<p>The interval is the sweep report's (docs/sweeps.md): Student's t over the "
       "seeds, or for a proportion Wilson's with the seeds as clusters. A value outside every "
       "seed's is marked, not called better or worse: one run is one draw.</p>\n";
  return h;
}

}  // namespace hcpf::studies
