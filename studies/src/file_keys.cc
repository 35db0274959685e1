#include "hcpf/studies/file_keys.h"

#include <fmt/format.h>

namespace hcpf::studies {

std::span<const FileKey> SweepFileKeys() {
  static const FileKey keys[] = {
      {"base", "path", "**required** (unless `grid.base`)",
       "the base scenario; looked for relative to the sweep file, then the current folder, then "
       "the project folder"},
      {"grid", "mapping: dotted key → non-empty list", "none", "cartesian product over the keys"},
      {"grid.base", "non-empty list of paths", "none",
       "several base scenarios, swept like a key (instead of `base`; grid only): each is found "
       "like `base`, every grid combination's runs start from its file, and `base` names a "
       "column of the store, a `report.series` or `report.panels`"},
      {"zip", "mapping: dotted key → list", "none",
       "parallel lists, all of one length; position *i* of every list goes together"},
      {"seeds", "integer 1 … 100000", "absent",
       "runs per cell; run seed *i* is `Rng(seed).Fork(\"sweep/seed/i\").identity()` (see "
       "`core/include/hcpf/core/rng.h`), set as the scenario's `seed` (so `seeds.*` derive from "
       "it unless the base scenario pins them). Absent: every run keeps the base scenario's seed "
       "(one run per cell)"},
      {"seed", "integer 0 … 2⁶⁴−1", "1", "root of the derived run seeds"},
      {"report.x", "a swept key", "the first swept key", "x axis of every plot"},
      {"report.y", "list of metric names (one may be written alone: `y: hota`)",
       "`da_accuracy, hijack_rate, idf1, hota, mota, ms_per_frame`", "one plot each"},
      {"report.series", "a swept key other than `x`", "none", "one line per value"},
      {"report.pool", "list of swept keys other than `x` and `series` (one may be written alone)",
       "none",
       "keys whose values are pooled into each cell (e.g. sun azimuths when recall is plotted "
       "against sun elevation): fewer lines, more runs per point, averaged per seed before the "
       "bands and tests (they count seeds)"},
      {"report.x_metric", "a metric name", "none",
       "place each cell on the x axis at this metric's mean over its runs (e.g. `det_size_px`, "
       "the measured target size) instead of its value of `x`; `x` still orders each line"},
      {"report.panels", "a swept key other than `x`, `series` and the pooled keys", "none",
       "one plot per value of this key for every `y` metric (e.g. `base`: one figure per base "
       "scenario), each with its own lines"},
      {"report.reference", "a value of `series`", "the first value of `series`",
       "the series value the others are compared with seed by seed: the report's paired "
       "differences (other − reference at every x, with interval and signed-rank test)"},
  };
  return keys;
}

std::span<const FileKey> SuiteFileKeys() {
  static const FileKey keys[] = {
      {"scenes[i].scenario", "path", "**required**",
       "scenario file (relative to the suite, the current folder, the project folder)"},
      {"scenes[i].name", "text", "the file's stem",
       "unique name; the key in the baseline and the run folder under --work, so no '/', '\\\\', "
       "\".\", \"..\" or control characters"},
      {"scenes[i].set", "mapping: dotted key → value", "none", "applied like `--set`"},
      {"scenes[i].seed", "integer 0 … 2⁶⁴−1", "the scenario's own",
       "the scenario seed (with `seeds`: the root of the derived seeds)"},
      {"scenes[i].seeds", "integer 2 … 1000", "absent",
       "run the scene with this many seeds, seed *i* = "
       "`Rng(seed).Fork(\"sweep/seed/i\").identity()` "
       "as in sweeps, and judge each metric by the paired difference against the baseline's "
       "per-seed values (see below). Absent: one run, exact comparison"},
      {"metrics.<m>.tolerance", "number 0 … 1e12", "**required**",
       "absolute tolerance of metric *m* (a name of the metric catalogue); for a scene with "
       "`seeds`, of the mean paired difference"},
      {"metrics.<m>.direction", "`higher_is_better` \\| `lower_is_better`",
       "the catalogue's direction", "optional; stating the other direction is an error"},
  };
  return keys;
}

std::span<const std::string_view> FileKeySections() {
  static const std::string_view sections[] = {"sweep", "suite"};
  return sections;
}

std::string FileKeysMarkdown(std::string_view section) {
  std::span<const FileKey> keys;
  if (section == "sweep") {
    keys = SweepFileKeys();
  } else if (section == "suite") {
    keys = SuiteFileKeys();
  } else {
    return "";
  }
  std::string out = "| key | type | default | meaning |\n|---|---|---|---|\n";
  for (const FileKey& k : keys) {
    out += fmt::format("| `{}` | {} | {} | {} |\n", k.key, k.type, k.default_text, k.meaning);
  }
  return out;
}

}  // namespace hcpf::studies
