// `hcpf report RUN_DIR`: one run's folder -> RUN_DIR/report.html (headline
// metrics, the per-frame camera-motion error and scene-filter ESS as an
// inline gnuplot SVG, the resolved scenario).

#include <fmt/format.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "gnuplot.h"
#include "hcpf/core/error.h"
#include "hcpf/core/text_file.h"
#include "hcpf/scenarios/output_folder.h"
#include "hcpf/studies/metric_catalogue.h"
#include "hcpf/studies/report.h"
#include "hcpf/studies/results_store.h"
#include "text.h"

namespace hcpf::studies {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// Run files are small (camera_motion.csv: ~100 bytes a frame); this bound
// only keeps a wrong file (a video renamed) from being read whole.
constexpr std::uint64_t kMaxRunFileBytes = std::uint64_t{256} << 20;

// One row of camera_motion.csv (scenarios/src/writers.cc FormatCameraMotionCsv).
struct CameraMotionRow {
  double frame = 0.0;
  double error_px = kNaN;
  double ess = kNaN;       // empty in the file: no scene filter (none, oracle)
  double floor_px = kNaN;  // the best any similarity could do (files before it lack the column)
};

std::optional<double> ParseDouble(const std::string& text) {
  double v = 0.0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
  if (ec != std::errc() || ptr != text.data() + text.size()) return std::nullopt;
  return v;
}

std::vector<std::string> SplitCsvLine(const std::string& line) {
  std::vector<std::string> fields;
  size_t at = 0;
  while (true) {
    const size_t comma = line.find(',', at);
    fields.push_back(line.substr(at, comma == std::string::npos ? std::string::npos : comma - at));
    if (comma == std::string::npos) break;
    at = comma + 1;
  }
  return fields;
}

// Reads the frame, error_px and ess columns, found by the header's names.
// Bad input names the file, line, column and what was found.
std::vector<CameraMotionRow> ReadCameraMotionCsv(const fs::path& path) {
  const std::string file = path.string();
  const std::string text =
      ReadInputFile(file, "a camera_motion.csv written by hcpf run", kMaxRunFileBytes);
  std::vector<std::string> lines;
  for (size_t at = 0; at < text.size();) {
    size_t end = text.find('\n', at);
    if (end == std::string::npos) end = text.size();
    std::string line = text.substr(at, end - at);
    if (!line.empty() && line.back() == '\r') line.pop_back();
    lines.push_back(line);
    at = end + 1;
  }
  if (lines.empty()) return {};
  const std::vector<std::string> header = SplitCsvLine(lines.front());
  const auto column = [&](const std::string& name) -> int {
    for (size_t i = 0; i < header.size(); ++i) {
      if (header[i] == name) return static_cast<int>(i);
    }
    return -1;
  };
  const int frame_col = column("frame");
  const int error_col = column("error_px");
  const int ess_col = column("ess");
  const int floor_col = column("floor_px");
  if (frame_col < 0 || error_col < 0) {
    throw InputError(SourceLocation{file, 1, 1, "header"},
                     "a header naming at least the columns frame and error_px "
                     "(frame,tx_px,ty_px,log_scale,rotation_rad,error_px,ess)",
                     fmt::format("\"{}\"", lines.front()));
  }
  std::vector<CameraMotionRow> rows;
  for (size_t l = 1; l < lines.size(); ++l) {
    if (lines[l].empty()) continue;
    const std::vector<std::string> fields = SplitCsvLine(lines[l]);
    const int line_no = static_cast<int>(l) + 1;
    if (fields.size() != header.size()) {
      throw InputError(SourceLocation{file, line_no, 1, ""},
                       fmt::format("{} comma-separated fields, like the header", header.size()),
                       fmt::format("{} in \"{}\"", fields.size(), lines[l]));
    }
    const auto number = [&](int col, bool may_be_empty) {
      const std::string& f = fields[static_cast<size_t>(col)];
      if (f.empty() && may_be_empty) return kNaN;
      const std::optional<double> v = ParseDouble(f);
      if (!v) {
        // The column of the field: 1 + the lengths of the fields before it and their commas.
        int column_no = 1;
        for (int i = 0; i < col; ++i) column_no += static_cast<int>(fields[i].size()) + 1;
        throw InputError(SourceLocation{file, line_no, column_no, header[static_cast<size_t>(col)]},
                         may_be_empty ? "a number or nothing" : "a number",
                         fmt::format("\"{}\"", f));
      }
      return *v;
    };
    CameraMotionRow row;
    row.frame = number(frame_col, false);
    row.error_px = number(error_col, false);
    if (ess_col >= 0) row.ess = number(ess_col, true);
    if (floor_col >= 0) row.floor_px = number(floor_col, false);
    rows.push_back(row);
  }
  return rows;
}

json ReadRunJson(const fs::path& path) {
  const std::string file = path.string();
  try {
    return json::parse(ReadInputFile(file, "a JSON file written by hcpf run", kMaxRunFileBytes));
  } catch (const json::exception& e) {
    throw InputError(SourceLocation{file, 0, 0, ""}, "JSON written by hcpf run",
                     fmt::format("text that does not parse ({})", e.what()));
  }
}

double JsonDouble(const json& j, const char* key) {
  return j.is_object() && j.contains(key) && j[key].is_number() ? j[key].get<double>() : kNaN;
}

std::string JsonText(const json& j, const char* key) {
  if (!j.is_object() || !j.contains(key)) return "";
  return j[key].is_string() ? j[key].get<std::string>() : j[key].dump();
}

// j[key], or null when j is not an object or lacks the key.
const json& JsonMember(const json& j, const char* key) {
  static const json kNull;
  return j.is_object() && j.contains(key) ? j[key] : kNull;
}

// The per-frame plot: error_px on the left axis with the similarity floor
// when the file has it; ESS on the right when the file has any. Returns the
// inline SVG.
std::string CameraMotionSvg(const std::vector<CameraMotionRow>& rows, const std::string& mode,
                            double mean_px, double floor_mean_px, const fs::path& work,
                            const std::string& gnuplot) {
  const fs::path data = work / "camera_motion.dat";
  const fs::path svg = work / "camera_motion.svg";
  const fs::path script = work / "camera_motion.gp";
  bool has_ess = false;
  bool has_floor = false;
  std::string text = "# frame error_px ess floor_px\n";
  for (const CameraMotionRow& r : rows) {
    has_ess = has_ess || std::isfinite(r.ess);
    has_floor = has_floor || std::isfinite(r.floor_px);
    text += fmt::format("{} {} {} {}\n", Number(r.frame), Number(r.error_px), Number(r.ess),
                        Number(r.floor_px));
  }
  WriteTextFile(data.string(), text);
  std::string gp;
  gp += "set terminal svg size 820,440 dynamic font 'sans,11' background rgb 'white'\n";
  gp += fmt::format("set output {}\n", GpString(svg.string()));
  gp += fmt::format("set title {} noenhanced\n",
                    GpString(fmt::format("camera-motion error per frame, mode {}", mode)));
  gp += "set xlabel 'frame'\n";
  gp += "set ylabel 'camera-motion error, px (mean corner displacement)' noenhanced\n";
  gp += "set grid\nset key below noenhanced\nset yrange [0:*]\n";
  if (has_ess) {
    gp += "set y2label 'scene-filter ESS, particles' noenhanced\n";
    gp += "set y2tics\nset ytics nomirror\nset y2range [0:*]\n";
  }
  std::string plot = fmt::format(
      "plot {} using 1:2 with lines lw 1.5 lc rgb '{}' title {}", GpString(data.string()),
      kPlotColours[0],
      GpString(fmt::format("camera-motion error ({}), mean {} px", mode, Number(mean_px))));
  if (has_floor) {
    plot += fmt::format(
        ", \\\n     {} using 1:4 with lines lw 1.5 dt 2 lc rgb '{}' title {}",
        GpString(data.string()), kPlotColours[2],
        GpString(fmt::format("similarity floor (the best any similarity does), mean {} px",
                             Number(floor_mean_px))));
  }
  if (has_ess) {
    plot += fmt::format(", \\\n     {} using 1:3 axes x1y2 with lines lw 1 lc rgb '{}' title {}",
                        GpString(data.string()), kPlotColours[1],
                        GpString("scene-filter effective sample size (ESS, right axis)"));
  }
  gp += plot + "\n";
  WriteTextFile(script.string(), gp);
  RunGnuplot(gnuplot, script);
  return InlineSvg(ReadWholeFile(svg));
}

// tp, fp, fn of one rule in a metrics.json detection block (0 when absent).
struct Counts {
  int64_t tp = 0, fp = 0, fn = 0;
};

Counts CountsOf(const json& j) {
  const auto get = [&](const char* key) -> int64_t {
    return j.is_object() && j.contains(key) && j[key].is_number_integer() ? j[key].get<int64_t>()
                                                                          : 0;
  };
  return {get("tp"), get("fp"), get("fn")};
}

// A ratio with three decimals, "–" when undefined.
std::string Ratio(int64_t num, int64_t den) {
  return den > 0 ? fmt::format("{:.3f}", static_cast<double>(num) / static_cast<double>(den)) : "–";
}

// One table row: IoU counts, precision and recall, and the centre rule's
// recall. `with_precision`: false detections are counted in this row (the
// totals and the size bins), so precision is defined.
std::string DetectionRow(const std::string& label, const json& row, bool with_precision) {
  const Counts iou = CountsOf(JsonMember(row, "iou"));
  const Counts centre = CountsOf(JsonMember(row, "centre"));
  return fmt::format(
      "<tr><td class=\"k\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
      "<td>{}</td></tr>\n",
      EscapeMarkup(label), iou.tp, iou.fn, with_precision ? std::to_string(iou.fp) : "–",
      with_precision ? Ratio(iou.tp, iou.tp + iou.fp) : "–", Ratio(iou.tp, iou.tp + iou.fn),
      Ratio(centre.tp, centre.tp + centre.fn));
}

// The rows of one binning of a metrics.json detection block ("by_size_px",
// "by_visibility", "by_truncation"), bins that hold no target or detection
// left out.
std::string DetectionBinRows(const json& detection, const char* key, const char* what,
                             const char* unit, bool with_precision) {
  std::string rows;
  const json& bins = JsonMember(detection, key);
  if (!bins.is_array()) return rows;
  for (const json& bin : bins) {
    const Counts c = CountsOf(JsonMember(bin, "iou"));
    if (c.tp + c.fp + c.fn == 0) continue;
    const double lo = JsonDouble(bin, "lo");
    const std::string hi =
        bin.contains("hi") && bin["hi"].is_number() ? Number(bin["hi"].get<double>()) : "∞";
    rows +=
        DetectionRow(fmt::format("{} {}–{}{}", what, Number(lo), hi, unit), bin, with_precision);
  }
  return rows;
}

// The detection-quality section of a rendered run with a detector.
std::string DetectionSection(const json& metrics, const std::string& detector) {
  const json& d = JsonMember(metrics, "detection");
  if (!d.is_object()) return "";
  std::string h = "<h2>Detection quality</h2>\n";
  h += fmt::format(
      "<p>Detector <code>{}</code> against the pixel-exact truth, frame by frame before any "
      "tracking: a detection matches a target when their IoU is at least 0.5 (the centre rule "
      "instead asks the detection's centre to lie within half the target's box). Targets less "
      "visible than <code>metrics.min_visible</code> are not counted. False detections have a "
      "size but no visibility or truncation, so those rows give recall only. Truncation is the "
      "fraction of the target's box outside the image.</p>\n",
      EscapeMarkup(detector));
  h += "<table><tr><th>targets</th><th>found (IoU)</th><th>missed</th><th>false</th>"
       "<th>precision</th><th>recall</th><th>recall (centre)</th></tr>\n";
  h += DetectionRow("all", d, true);
  h += DetectionBinRows(d, "by_size_px", "size", " px", true);
  h += DetectionBinRows(d, "by_visibility", "visible", "", false);
  h += DetectionBinRows(d, "by_truncation", "truncated", "", false);
  h += "</table>\n";
  return h;
}

}  // namespace

ReportResult WriteRunReport(const ReportOptions& options) {
  options.Validate();
  if (ClassifyReportFolder(options.dir) != ReportFolder::kRun) {
    throw InputError(SourceLocation{options.dir, 0, 0, "DIR"},
                     "a run folder (manifest.json with \"format\": \"hcpf-run/1\")",
                     "a sweep folder (use hcpf report on it as a sweep)");
  }
  const fs::path dir(options.dir);
  if (!options.out_dir.empty()) scenarios::CheckFolderArgument(options.out_dir, "--out");
  const fs::path out = options.out_dir.empty() ? dir : fs::path(options.out_dir);

  const json manifest = ReadRunJson(dir / "manifest.json");
  const json metrics = ReadRunJson(dir / "metrics.json");
  std::map<std::string, double> headline;
  try {
    headline = ReadRunMetrics(dir.string());
  } catch (const RunError& e) {
    // ReadRunMetrics reports missing files as RunError; here they are the
    // user's input.
    throw InputError(SourceLocation{dir.string(), 0, 0, ""},
                     "a run folder with metrics.json and manifest.json", e.what());
  }
  const json& camera = JsonMember(metrics, "camera_motion");
  const std::string mode =
      camera.is_object() && camera.contains("mode") && camera["mode"].is_string()
          ? camera["mode"].get<std::string>()
          : std::string("unknown (metrics.json has no camera_motion.mode)");
  std::vector<CameraMotionRow> rows;
  std::error_code ec;
  const fs::path csv = dir / "camera_motion.csv";
  if (fs::exists(csv, ec)) rows = ReadCameraMotionCsv(csv);

  ReportResult result;
  std::string svg;
  if (!rows.empty()) {
    const fs::path work = MakePlotWorkDir(out, options.out_dir.empty());
    try {
      svg = CameraMotionSvg(rows, mode, JsonDouble(camera, "mean_px"),
                            JsonDouble(JsonMember(camera, "floor"), "mean_px"), work,
                            options.gnuplot);
    } catch (...) {
      fs::remove_all(work, ec);
      throw;
    }
    fs::remove_all(work, ec);
    ++result.plots;
  }

  const std::string name = JsonText(manifest, "scenario");
  std::string h;
  h += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n";
  h += fmt::format("<title>HCPF run report: {}</title>\n", EscapeMarkup(name));
  h += "<style>body{font-family:sans-serif;margin:1.5em;color:#222}table{border-collapse:collapse;"
       "font-size:13px}td,th{border:1px solid #ccc;padding:3px 7px;text-align:right}"
       "th{background:#f3f3f3}td.k{text-align:left}.plot{margin:1em 0}pre{background:#f7f7f7;"
       "padding:1em;font-size:12px;overflow:auto}</style>\n</head><body>\n";
  h += fmt::format(
      "<h1>Run report: {}</h1>\n<p>Run folder <code>{}</code>: seed {}, {} frames, observations "
      "{} ({}), config hash <code>{}</code>.</p>\n",
      EscapeMarkup(name), EscapeMarkup(dir.string()), EscapeMarkup(JsonText(manifest, "seed")),
      EscapeMarkup(JsonText(manifest, "frames")),
      EscapeMarkup(JsonText(manifest, "observation_source")),
      EscapeMarkup(JsonText(manifest, "detector")),
      EscapeMarkup(JsonText(manifest, "config_hash")));

  h += "<h2>Headline metrics</h2>\n<table><tr><th>metric</th><th>name</th><th>value</th></tr>\n";
  for (const CatalogueMetric& m : MetricCatalogue()) {
    const auto it = headline.find(std::string(m.name));
    if (it == headline.end() || !std::isfinite(it->second)) continue;  // not measured in this run
    h += fmt::format(
        "<tr><td class=\"k\">{}</td><td class=\"k\"><code>{}</code></td>"
        "<td>{:.4g}{}{}</td></tr>\n",
        EscapeMarkup(std::string(m.label)), EscapeMarkup(std::string(m.name)), it->second,
        m.unit.empty() ? "" : " ", EscapeMarkup(std::string(m.unit)));
  }
  h += "</table>\n";

  h += "<h2>Camera motion</h2>\n";
  if (camera.is_object()) {
    h += fmt::format(
        "<p>Mode <code>{}</code> (<code>tracker.camera_motion</code>). Error: the mean "
        "displacement of the four image corners between the applied and the true "
        "frame-to-frame motion, over {} frames; the floor is the same for the similarity "
        "closest to the true motion at the corners, the best any similarity estimate "
        "could do on these frames.</p>\n<table><tr><th></th><th>mean, px</th><th>median, "
        "px</th><th>p95, px</th><th>max, px</th></tr>\n",
        EscapeMarkup(mode), EscapeMarkup(JsonText(camera, "frames")));
    // One row per summary: the error, and the floor when metrics.json has it.
    const auto row = [&h](const char* label, const json& summary) {
      h += fmt::format(
          "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>\n", label,
          Number(JsonDouble(summary, "mean_px")), Number(JsonDouble(summary, "median_px")),
          Number(JsonDouble(summary, "p95_px")), Number(JsonDouble(summary, "max_px")));
    };
    row("error", camera);
    if (camera.contains("floor")) row("floor", camera["floor"]);
    h += "</table>\n";
  } else {
    h += "<p>metrics.json has no <code>camera_motion</code> block.</p>\n";
  }
  if (!svg.empty()) {
    h += fmt::format("<div class=\"plot\" id=\"plot-camera_motion\">\n{}\n</div>\n", svg);
  } else {
    h += "<p>No per-frame camera motion to plot (camera_motion.csv is absent or has no "
         "rows).</p>\n";
  }
  h += DetectionSection(metrics, JsonText(manifest, "detector"));
  const fs::path resolved = dir / "scenario.resolved.yaml";
  if (fs::is_regular_file(resolved, ec)) {
    h += "<h2>Scenario (resolved)</h2>\n<pre>" + EscapeMarkup(ReadWholeFile(resolved)) + "</pre>\n";
  }
  h += "</body></html>\n";
  result.html_path = (out / "report.html").string();
  WriteTextFile(result.html_path, h);
  return result;
}

}  // namespace hcpf::studies
