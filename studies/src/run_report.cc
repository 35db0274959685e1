// `hcpf report RUN_DIR`: one run's folder -> RUN_DIR/report.html (headline
// metrics, the per-frame camera-motion error and scene-filter ESS as an
// inline gnuplot SVG, detection quality, a timeline of every target, its
// detections and its filters, the resolved scenario). With --against another
// run folder, the two runs compared: resolved keys, files, metrics side by
// side and, over one ground truth, their filters frame by frame.

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <yaml-cpp/exceptions.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "gnuplot.h"
#include "hcpf/config/yaml_leaves.h"
#include "hcpf/core/error.h"
#include "hcpf/core/text_file.h"
#include "hcpf/metrics/detection_truth.h"
#include "hcpf/metrics/mot_io.h"
#include "hcpf/renderer/renderer.h"
#include "hcpf/scenarios/output_folder.h"
#include "hcpf/scenarios/scenario.h"
#include "hcpf/studies/metric_catalogue.h"
#include "hcpf/studies/report.h"
#include "hcpf/studies/results_store.h"
#include "run_cell.h"
#include "scene_sketch.h"
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

// j[key] as an integer, or nullopt when j is not an object, lacks the key or
// holds something else there.
std::optional<int64_t> JsonInt(const json& j, const char* key) {
  if (!j.is_object() || !j.contains(key) || !j[key].is_number_integer()) return std::nullopt;
  return j[key].get<int64_t>();
}

// j[key], or null when j is not an object or lacks the key.
const json& JsonMember(const json& j, const char* key) {
  static const json kNull;
  return j.is_object() && j.contains(key) ? j[key] : kNull;
}

// What hcpf validate, run and render warned of the scene (manifest.json
// scene_notes: targets driving through each other, an image turning at
// once), kept with the results; "" when nothing (or an older run's manifest).
std::string SceneNotesSentence(const json& manifest) {
  const json& notes = JsonMember(manifest, "scene_notes");
  if (!notes.is_array() || notes.empty()) return "";
  std::string h = "<p><strong>The scene:</strong></p>\n<ul>\n";
  for (const json& note : notes) h += "<li>" + EscapeMarkup(note.get<std::string>()) + "</li>\n";
  return h + "</ul>\n";
}

// Where a rendered run's frames came from (manifest.json frames_rendered,
// gl_renderer, frames_from_cache, frame_cache_renderers): one sentence, or ""
// for a run without rendered frames. Frames of different GL renderers may
// differ in their pixels, so the renderer belongs with the results.
std::string FramesSentence(const json& manifest) {
  const std::optional<int64_t> rendered = JsonInt(manifest, "frames_rendered");
  const std::optional<int64_t> cached = JsonInt(manifest, "frames_from_cache");
  if (!rendered || !cached || *rendered + *cached == 0) return "";
  std::vector<std::string> parts;
  if (*rendered > 0) {
    // In the line the cache notes renderers by.
    const json& gl = JsonMember(manifest, "gl_renderer");
    std::string by;
    if (!JsonText(gl, "renderer").empty()) {
      const renderer::GlInfo info{.platform = JsonText(gl, "platform"),
                                  .vendor = JsonText(gl, "vendor"),
                                  .renderer = JsonText(gl, "renderer"),
                                  .version = JsonText(gl, "version")};
      by = fmt::format(" by <code>{}</code>", EscapeMarkup(renderer::RendererLine(info)));
    }
    parts.push_back(fmt::format("{} rendered{}", *rendered, by));
  }
  if (*cached > 0) {
    const json& renderers = JsonMember(manifest, "frame_cache_renderers");
    std::vector<std::string> names;
    if (renderers.is_array()) {
      for (const json& r : renderers) {
        if (r.is_string())
          names.push_back("<code>" + EscapeMarkup(r.get<std::string>()) + "</code>");
      }
    }
    std::string from = "read from the frame cache";
    if (names.size() == 1) {
      from += ", rendered there by " + names[0];
    } else if (names.size() > 1) {
      // "a, b and c": each name holds semicolons of its own.
      std::string listed;
      for (size_t i = 0; i < names.size(); ++i) {
        listed += (i == 0 ? "" : i + 1 == names.size() ? " and " : ", ") + names[i];
      }
      from += fmt::format(
          ", whose folder holds frames of {} GL renderers, so they may mix: <strong>{}</strong>",
          names.size(), listed);
    }
    parts.push_back(fmt::format("{} {}", *cached, from));
  }
  return fmt::format("<p>Frames: {}.</p>\n", fmt::join(parts, "; "));
}

// "–" where nothing was measured (a run of one frame: metrics.json holds
// null, which the page printed as "nan": an audit).
std::string PixelText(double px) { return std::isfinite(px) ? Number(RoundedPx(px)) : "–"; }

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
  gp += SvgTerminal(820, "440");
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
      GpString(fmt::format("camera-motion error ({}), mean {} px", mode, PixelText(mean_px))));
  if (has_floor) {
    plot += fmt::format(
        ", \\\n     {} using 1:4 with lines lw 1.5 dt 2 lc rgb '{}' title {}",
        GpString(data.string()), kPlotColours[2],
        GpString(fmt::format("similarity floor (the best any similarity does), mean {} px",
                             PixelText(floor_mean_px))));
  }
  if (has_ess) {
    plot += fmt::format(", \\\n     {} using 1:3 axes x1y2 with lines lw 1 lc rgb '{}' title {}",
                        GpString(data.string()), kPlotColours[1],
                        GpString("scene-filter effective sample size (ESS, right axis)"));
  }
  gp += plot + "\n";
  return RunGnuplotToSvg(gnuplot, script, gp, svg);
}

// tp, fp, fn of one rule in a metrics.json detection block (0 when absent).
struct Counts {
  int64_t tp = 0, fp = 0, fn = 0;
};

Counts CountsOf(const json& j) {
  return {JsonInt(j, "tp").value_or(0), JsonInt(j, "fp").value_or(0), JsonInt(j, "fn").value_or(0)};
}

// A ratio with three decimals, "–" when undefined (not finite).
std::string Fixed3(double v) { return std::isfinite(v) ? fmt::format("{:.3f}", v) : "–"; }

// num / den as Fixed3 writes it, "–" when den is 0.
std::string Ratio(int64_t num, int64_t den) {
  return den > 0 ? Fixed3(static_cast<double>(num) / static_cast<double>(den)) : "–";
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

// The precision-recall curve of metrics.json's detection.precision_recall
// block (IoU rule, interpolated at 101 recalls) with its best-F1 point, or ""
// when the block has no curve (no counted target).
std::string PrecisionRecallSvg(const json& pr, const fs::path& work, const std::string& gnuplot) {
  const json& curve = JsonMember(pr, "curve");
  const json& recall = JsonMember(curve, "recall");
  const json& precision = JsonMember(curve, "precision");
  if (!recall.is_array() || !precision.is_array() || recall.empty() ||
      recall.size() != precision.size()) {
    return "";
  }
  const fs::path data = work / "precision_recall.dat";
  const fs::path best = work / "precision_recall_best.dat";
  const fs::path svg = work / "precision_recall.svg";
  const fs::path script = work / "precision_recall.gp";
  std::string text = "# recall precision\n";
  for (size_t i = 0; i < recall.size(); ++i) {
    const double r = recall[i].is_number() ? recall[i].get<double>() : kNaN;
    const double p = precision[i].is_number() ? precision[i].get<double>() : kNaN;
    text += fmt::format("{} {}\n", Number(r), Number(p));
  }
  WriteTextFile(data.string(), text);
  const json& f1 = JsonMember(pr, "best_f1");
  const double best_recall = JsonDouble(f1, "recall");
  const double best_precision = JsonDouble(f1, "precision");
  const bool has_best = std::isfinite(best_recall) && std::isfinite(best_precision);
  std::string gp;
  gp += SvgTerminal(820, "440");
  gp += fmt::format("set output {}\n", GpString(svg.string()));
  gp += fmt::format("set title {} noenhanced\n",
                    GpString(fmt::format("precision against recall (IoU >= 0.5), every score "
                                         "threshold: average precision {}",
                                         Fixed3(JsonDouble(pr, "average_precision")))));
  gp += "set xlabel 'recall'\nset ylabel 'precision (best at this recall or more)'\n";
  gp += "set grid\nset key below noenhanced\nset xrange [0:1]\nset yrange [0:1.02]\n";
  std::string plot =
      fmt::format("plot {} using 1:2 with lines lw 1.5 lc rgb '{}' title {}",
                  GpString(data.string()), kPlotColours[0],
                  GpString("interpolated precision at the 101 recalls 0, 0.01, ..., 1 (COCO)"));
  if (has_best) {
    WriteTextFile(best.string(),
                  fmt::format("{} {}\n", Number(best_recall), Number(best_precision)));
    plot +=
        fmt::format(", \\\n     {} using 1:2 with points pt 7 ps 1.3 lc rgb '{}' title {}",
                    GpString(best.string()), kPlotColours[1],
                    GpString(fmt::format("best F1 {} at score >= {}", Fixed3(JsonDouble(f1, "f1")),
                                         Number(JsonDouble(f1, "min_score")))));
  }
  gp += plot + "\n";
  return RunGnuplotToSvg(gnuplot, script, gp, svg);
}

// The detection-quality section of a rendered run with a detector, with the
// precision-recall plot when there is one.
std::string DetectionSection(const json& metrics, const std::string& detector,
                             const std::string& precision_recall_svg) {
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
  const json& mostly = JsonMember(d, "mostly_visible");
  if (mostly.is_object()) {
    // The subset has a precision: detections on the less visible targets
    // are neither true nor false there.
    h += DetectionRow(fmt::format("visible ≥ {} (the others not counted)",
                                  Number(JsonDouble(mostly, "min_visible"))),
                      mostly, true);
  }
  h += DetectionBinRows(d, "by_size_px", "size", " px", true);
  h += DetectionBinRows(d, "by_visibility", "visible", "", false);
  h += DetectionBinRows(d, "by_truncation", "truncated", "", false);
  const json& targets = JsonMember(d, "by_target");
  if (targets.is_array()) {
    for (const json& t : targets) {
      const auto count = [&t](const char* key) { return JsonInt(t, key).value_or(0); };
      const int64_t found = count("found"), missed = count("missed");
      if (found + missed == 0) continue;  // never counted
      const int64_t found_centre = count("found_centre"), missed_centre = count("missed_centre");
      h += fmt::format(
          "<tr><td class=\"k\">target {}</td><td>{}</td><td>{}</td><td>–</td><td>–</td>"
          "<td>{}</td><td>{}</td></tr>\n",
          EscapeMarkup(JsonText(t, "target")), found, missed, Ratio(found, found + missed),
          Ratio(found_centre, found_centre + missed_centre));
    }
  }
  h += "</table>\n";
  const json& labels = JsonMember(d, "labels");
  if (labels.is_object()) {
    const int64_t matched = JsonInt(labels, "matched").value_or(0);
    h += fmt::format(
        "<p>Labels: the detector says which target each detection is of, and above a "
        "detection may match only its own target. Matched again with the labels ignored, "
        "{} of its {} detections on a target name that target: label accuracy <b>{}</b>.</p>\n",
        JsonInt(labels, "right").value_or(0), matched, Fixed3(JsonDouble(labels, "accuracy")));
  }
  const json& pr = JsonMember(d, "precision_recall");
  const json& f1 = JsonMember(pr, "best_f1");
  if (std::isfinite(JsonDouble(pr, "average_precision"))) {
    h += fmt::format(
        "<p>Every score threshold (the detections ranked by score over all frames, each "
        "matched greedily to the unmatched target it overlaps most, IoU ≥ 0.5): average "
        "precision <b>{}</b> (COCO's 101-point AP50). {} Only the detections the detector "
        "reported are ranked: its own thresholds end the curve at its recall.</p>\n",
        Fixed3(JsonDouble(pr, "average_precision")),
        std::isfinite(JsonDouble(f1, "f1"))
            ? fmt::format("The best F1, {}, is at score ≥ {} (precision {}, recall {}).",
                          Fixed3(JsonDouble(f1, "f1")), Number(JsonDouble(f1, "min_score")),
                          Fixed3(JsonDouble(f1, "precision")), Fixed3(JsonDouble(f1, "recall")))
            : std::string("No detection matches a target."));
    const double mostly_ap =
        JsonDouble(JsonMember(mostly, "precision_recall"), "average_precision");
    if (std::isfinite(mostly_ap)) {
      h += fmt::format(
          "<p>The same for the targets visible at least {} alone (a detection on a less visible "
          "target neither true nor false): average precision <b>{}</b>.</p>\n",
          Number(JsonDouble(mostly, "min_visible")), Fixed3(mostly_ap));
    }
  }
  if (!precision_recall_svg.empty()) {
    h += fmt::format("<div class=\"plot\" id=\"plot-precision_recall\">\n{}\n</div>\n",
                     precision_recall_svg);
  }
  return h;
}

// The timeline: rows of coloured segments over the frames (counted from 1, as
// gt/gt.txt and filters.csv count them).
struct TimelineRow {
  std::string label;
  // Per frame (index = frame - 1): the segment's colour, 0xRRGGBB, or -1.
  std::vector<int> colour;
  // Frames (from 1) marked with each kMarks symbol.
  std::array<std::vector<int>, 3> marks;
};

// The timeline's point symbols, one data file and legend entry each.
struct TimelineMark {
  const char* file;
  const char* style;  // gnuplot point style
  const char* title;
};
constexpr std::array<TimelineMark, 3> kMarks = {{
    // A detection row: the frame its target's model was cut.
    {"timeline_marks.dat", "pt 13 ps 1.3", "model cut"},
    // A filter row: the frame at whose end it was found again from its own
    // target's detections (tracker.management.reacquire).
    {"timeline_reacquired.dat", "pt 6 ps 1.6 lw 2", "re-acquired"},
    // A filter row: the first frame it no longer exists in, before the run's
    // end (deleted at the end of the frame before; an audit: a row that just
    // ended said nothing).
    {"timeline_deleted.dat", "pt 2 ps 1.3 lw 2", "deleted"},
}};
constexpr size_t kModelCut = 0;
constexpr size_t kReacquired = 1;
constexpr size_t kDeleted = 2;

// Colours of the timeline, and the legend's names for them.
struct TimelineColour {
  int rgb;
  const char* name;
};
// A target row is shaded by the share of the whole vehicle that is seen:
// its visible fraction (of its pixels inside the image) times the share of
// its box inside the image, 1 − truncation (gt.json). An audit found a
// truck 98 % outside the image drawn "visible ≥ 0.75" above 40 frames of
// "detector missed it": the visible fraction alone counts only the part in
// the image (docs/metrics.md).
constexpr TimelineColour kVisibleMost{0x404040, "target seen ≥ 0.75 (unhidden, in the image)"};
constexpr TimelineColour kVisibleHalf{0x9a9a9a, "seen 0.25–0.75"};
constexpr TimelineColour kVisibleLittle{0xd4d4d4, "seen under 0.25 (hidden or outside)"};
constexpr TimelineColour kFound{0x2ca02c, "detector found it (IoU ≥ 0.5)"};
constexpr TimelineColour kMissed{0xf4a0a0, "detector missed it"};
// A model-based detector's misses before the target's model was cut: it
// could not look for the target yet.
constexpr TimelineColour kNoModel{0xf3dcb8, "missed, before its model was cut"};
// Filter states (metrics/filter_metrics.h, docs/metrics.md), the overlay
// video's state labels' colours too (scenarios/src/overlay.cc StateColour).
// LOST was near-black, beside the dark grey of a target's row (an audit).
constexpr TimelineColour kStateColours[] = {{0x1f77b4, "CORRECT"},  {0xff7f0e, "SWAPPED"},
                                            {0xd62728, "HIJACKED"}, {0x8c564b, "STRAYED"},
                                            {0x9467bd, "LOST"},     {0x9ecae1, "COASTING"}};

int StateColour(const std::string& state) {
  for (const TimelineColour& c : kStateColours) {
    if (state == c.name) return c.rgb;
  }
  return 0xe377c2;  // a state this report does not know: visible, not hidden
}

std::string RgbText(int rgb) { return fmt::format("#{:06x}", rgb); }

// metrics.json filters.per_frame_states: visit(filter, frame from 0, state)
// for every row with a filter and a frame.
template <typename Visit>
void ForEachFilterState(const json& metrics, Visit visit) {
  const json& states = JsonMember(JsonMember(metrics, "filters"), "per_frame_states");
  if (!states.is_array()) return;
  for (const json& r : states) {
    const std::optional<int64_t> filter = JsonInt(r, "filter");
    const std::optional<int64_t> frame = JsonInt(r, "frame");
    if (filter && frame) visit(*filter, *frame, JsonText(r, "state"));
  }
}

// The frame runs of a metrics.json detection.by_target entry's `key`
// ("found_frames" or "missed_frames"): visit(first, last) for each
// well-formed [first, last] pair, frames from 0.
template <typename Visit>
void ForEachFrameRun(const json& entry, const char* key, Visit visit) {
  const json& runs = JsonMember(entry, key);
  if (!runs.is_array()) return;
  for (const json& run : runs) {
    if (run.is_array() && run.size() == 2 && run[0].is_number_integer() &&
        run[1].is_number_integer()) {
      visit(run[0].get<int64_t>(), run[1].get<int64_t>());
    }
  }
}

// metrics.json filters.mapping: (filter, target) pairs in the file's order.
std::vector<std::pair<int64_t, int64_t>> FilterMapping(const json& metrics) {
  std::vector<std::pair<int64_t, int64_t>> out;
  const json& mapping = JsonMember(JsonMember(metrics, "filters"), "mapping");
  if (!mapping.is_array()) return out;
  for (const json& m : mapping) {
    const std::optional<int64_t> filter = JsonInt(m, "filter");
    const std::optional<int64_t> target = JsonInt(m, "target");
    if (filter && target) out.emplace_back(*filter, *target);
  }
  return out;
}

// One line of the centre-error plot: a target and a filter the identity
// mapping gives it, and per frame (from 1) the distance between the centres
// of the filter's box (tracks.txt) and the target's (gt/gt.txt), in px.
struct CentreErrorLine {
  std::string label;
  std::vector<std::pair<int, double>> points;  // frame, px
};

// The lines of one run: every (filter, target) pair of metrics.json's
// filters.mapping, over the frames where both have a box. `prefix` names
// the run ("A ", "B " when two are compared).
std::vector<CentreErrorLine> CentreErrorLines(const metrics::MotFile& gt,
                                              const metrics::MotFile& tracks, const json& metrics,
                                              const std::string& prefix) {
  const auto centre = [](const BoxPx& b) {
    return std::pair{b.left + 0.5 * b.width, b.top + 0.5 * b.height};
  };
  // By (id, frame): one id's rows are a range, in frame order.
  std::map<std::pair<int64_t, int>, std::pair<double, double>> truth, estimate;
  for (const metrics::MotRow& r : gt.rows) truth[{r.id, r.frame}] = centre(r.box);
  for (const metrics::MotRow& r : tracks.rows) estimate[{r.id, r.frame}] = centre(r.box);
  std::vector<CentreErrorLine> lines;
  std::set<std::pair<int64_t, int64_t>> seen;
  for (const auto& [filter, target] : FilterMapping(metrics)) {
    if (!seen.insert({filter, target}).second) continue;
    CentreErrorLine line{fmt::format("{}target {}: filter {}", prefix, target, filter), {}};
    for (auto e = estimate.lower_bound({filter, std::numeric_limits<int>::min()});
         e != estimate.end() && e->first.first == filter; ++e) {
      const int frame = e->first.second;
      const auto it = truth.find({target, frame});
      if (it == truth.end()) continue;
      line.points.emplace_back(frame, std::hypot(e->second.first - it->second.first,
                                                 e->second.second - it->second.second));
    }
    if (!line.points.empty()) lines.push_back(std::move(line));
  }
  return lines;
}

// A mean error in a key: three significant digits ("1.66", "16.4"), whole
// px from 100 ("112", "1234"), 0 under 0.005 px (rounding, not an error).
std::string ShortPx(double px) {
  if (std::abs(px) < 0.005) return "0";
  if (std::abs(px) >= 100.0) return fmt::format("{:.0f}", px);
  return fmt::format("{:.3g}", px);
}

// The plot: one line per (target, filter), broken where frames are missing,
// its mean in the legend. The standard picture of a particle filter's run,
// and where two runs' accuracy differs (an audit found two runs differing
// in IDF1 0.952 against 0.910 with identical timelines).
std::string CentreErrorSvg(const std::vector<CentreErrorLine>& lines, const fs::path& work,
                           const std::string& gnuplot) {
  const fs::path data = work / "centre_error.dat";
  const fs::path svg = work / "centre_error.svg";
  const fs::path script = work / "centre_error.gp";
  std::string text;
  std::vector<std::string> plots;
  for (size_t l = 0; l < lines.size(); ++l) {
    text += fmt::format("# {}\n", lines[l].label);
    double sum = 0.0;
    int previous = -1;
    for (const auto& [frame, px] : lines[l].points) {
      if (previous >= 0 && frame != previous + 1) text += "\n";  // a gap breaks the line
      text += fmt::format("{} {}\n", frame, Number(px));
      sum += px;
      previous = frame;
    }
    text += "\n\n";
    // Past ten lines the colours come round again, dashed: one dash pattern
    // per round.
    plots.push_back(fmt::format(
        "{} index {} using 1:2 with lines lw 1.5 lc rgb '{}' dt {} title {}",
        GpString(data.string()), l, kPlotColours[l % std::size(kPlotColours)],
        l / std::size(kPlotColours) % 5 + 1,
        GpString(fmt::format("{}, mean {} px", lines[l].label,
                             ShortPx(sum / static_cast<double>(lines[l].points.size()))))));
  }
  WriteTextFile(data.string(), text);
  // The plot's box 300 px tall, below it a key of any number of lines
  // (FitCanvasToBox), drawn first on a canvas tall enough for the key in one
  // column (on one too short gnuplot draws the key over the plot).
  const int trial_height = 440 + 20 * static_cast<int>(lines.size());
  std::string gp = SvgTerminal(820, std::to_string(trial_height));
  gp += fmt::format("set output {}\n", GpString(svg.string()));
  gp += "set title 'centre error of each target''s filter, frame by frame' noenhanced\n";
  gp += "set xlabel 'frame (from 1, as in gt/gt.txt and tracks.txt)' noenhanced\n";
  gp += "set ylabel 'filter box centre to target box centre, px' noenhanced\n";
  gp += "set grid\nset key below noenhanced height 1\nset yrange [0:*]\n";
  gp += "plot " + fmt::format("{}", fmt::join(plots, ", \\\n     ")) + "\n";
  gp += FitCanvasToBox(820, trial_height, 300, svg, work / "centre_error-box.txt");
  return RunGnuplotToSvg(gnuplot, script, gp, svg);
}

// Each filter's target by that mapping (the first pair of a filter counts).
std::map<int64_t, int64_t> TargetOfFilter(const json& metrics) {
  std::map<int64_t, int64_t> target_of;
  for (const auto& [filter, target] : FilterMapping(metrics)) target_of.try_emplace(filter, target);
  return target_of;
}

// A manifest.json list of {"<id_key>": id, "frame": frame} entries
// (target_model_sources, tracker.reacquired): visit(id, frame from 0) for
// each entry that has both.
template <typename Visit>
void ForEachIdFrame(const json& list, const char* id_key, Visit visit) {
  if (!list.is_array()) return;
  for (const json& entry : list) {
    const std::optional<int64_t> id = JsonInt(entry, id_key);
    const std::optional<int64_t> frame = JsonInt(entry, "frame");
    if (id && frame) visit(*id, *frame);
  }
}

// The timeline's rows before they are ordered: per target (gt/gt.txt) its
// visibility; in a rendered run with a detector, the frames where the
// detector found or missed it (metrics.json detection.by_target) and the frame
// its model was cut (manifest.json target_model_sources); per filter its
// state each frame (filters.per_frame_states), ringed where it was
// re-acquired (manifest.json tracker.reacquired), and the filters the
// identity mapping gives each target (metrics.json filters.mapping). Frames
// outside 1..frames are ignored (never drawn off the axis).
struct TimelineParts {
  std::map<int64_t, TimelineRow> truth;     // by target id
  std::map<int64_t, TimelineRow> detected;  // by target id
  std::map<int64_t, TimelineRow> filters;   // by filter id
  std::map<int64_t, std::vector<int64_t>> filters_of_target;
  std::set<int64_t> mapped;  // filters the mapping gives a target
};

// A run folder's gt.json, read once for the timeline's truncations and the
// scene from above: nullopt when the file is absent, or cannot be read
// (`note` then says why): the timeline shades by visible fraction alone,
// there is no sketch, and the report stands (a review: a gt.json cut short
// or over the reader's limit stopped a report that never needed it before).
// The project's reader (metrics/detection_truth.h) checks each truncation
// is a fraction.
std::optional<metrics::GroundTruthFile> ReadRunGroundTruth(const fs::path& gt_json,
                                                           std::string* note) {
  std::error_code ec;
  if (!fs::is_regular_file(gt_json, ec)) return std::nullopt;
  try {
    return metrics::ReadGroundTruthJson(gt_json.string());
  } catch (const InputError& e) {
    *note = fmt::format(" {} was not read ({}): targets are shaded by visible fraction alone.",
                        gt_json.string(), e.what());
    return std::nullopt;
  }
}

// gt.json's truncation of each target, by (frame from 1, target id): the
// share of its box outside the image. Empty without a gt.json.
std::map<std::pair<int64_t, int64_t>, double> TruncationOf(
    const std::optional<metrics::GroundTruthFile>& gt) {
  std::map<std::pair<int64_t, int64_t>, double> out;
  if (!gt) return out;
  for (const FrameGroundTruth& frame : gt->frames) {
    for (const GroundTruthObject& o : frame.objects) {
      out[{frame.frame + 1, Value(o.id)}] = o.truncation;
    }
  }
  return out;
}

TimelineParts ReadTimeline(const metrics::MotFile& gt, const json& metrics, const json& manifest,
                           int frames,
                           const std::map<std::pair<int64_t, int64_t>, double>& truncation) {
  const auto row_of = [frames](std::string label) {
    return TimelineRow{std::move(label), std::vector<int>(static_cast<size_t>(frames), -1), {}};
  };
  const auto in_range = [frames](int64_t frame) { return frame >= 1 && frame <= frames; };
  std::map<int64_t, TimelineRow> truth;
  for (const metrics::MotRow& r : gt.rows) {
    auto [it, inserted] = truth.try_emplace(r.id, row_of(fmt::format("target {}", r.id)));
    if (!in_range(r.frame)) continue;
    const auto cut = truncation.find({r.frame, r.id});
    const double v = r.col9 * (cut == truncation.end() ? 1.0 : 1.0 - cut->second);
    it->second.colour[static_cast<size_t>(r.frame - 1)] =
        v >= 0.75 ? kVisibleMost.rgb : (v >= 0.25 ? kVisibleHalf.rgb : kVisibleLittle.rgb);
  }
  // Detection rows, by target.
  std::map<int64_t, TimelineRow> detected;
  const json& by_target = JsonMember(JsonMember(metrics, "detection"), "by_target");
  if (by_target.is_array()) {
    for (const json& t : by_target) {
      const std::optional<int64_t> id = JsonInt(t, "target");
      if (!id) continue;
      TimelineRow& row = detected.try_emplace(*id, row_of("detections")).first->second;
      for (const auto& [key, rgb] :
           {std::pair{"found_frames", kFound.rgb}, std::pair{"missed_frames", kMissed.rgb}}) {
        // metrics.json counts frames from 0.
        ForEachFrameRun(t, key, [&, rgb = rgb](int64_t first, int64_t last) {
          for (int64_t f = first + 1; f <= last + 1; ++f) {
            if (in_range(f)) row.colour[static_cast<size_t>(f - 1)] = rgb;
          }
        });
      }
      truth.try_emplace(*id, row_of(fmt::format("target {}", *id)));
    }
    ForEachIdFrame(
        JsonMember(manifest, "target_model_sources"), "target", [&](int64_t id, int64_t frame) {
          if (!in_range(frame + 1)) return;
          TimelineRow& row = detected.try_emplace(id, row_of("detections")).first->second;
          row.marks[kModelCut].push_back(static_cast<int>(frame + 1));
          // Misses before the cut (frame from 0: the frames from 1
          // before frame + 1) were no look at the target.
          for (int64_t f = 1; f <= frame && f <= frames; ++f) {
            int& colour = row.colour[static_cast<size_t>(f - 1)];
            if (colour == kMissed.rgb) colour = kNoModel.rgb;
          }
        });
  }
  // Filter rows, by filter id, and the target each is mapped to.
  std::map<int64_t, TimelineRow> filter_rows;
  ForEachFilterState(metrics, [&](int64_t filter, int64_t frame, const std::string& state) {
    TimelineRow& row =
        filter_rows.try_emplace(filter, row_of(fmt::format("filter {}", filter))).first->second;
    if (in_range(frame + 1)) row.colour[static_cast<size_t>(frame)] = StateColour(state);
  });
  for (auto& [filter, row] : filter_rows) {
    for (size_t f = 0; f + 1 < row.colour.size(); ++f) {
      if (row.colour[f] >= 0 && row.colour[f + 1] < 0) {
        row.marks[kDeleted].push_back(static_cast<int>(f + 2));
      }
    }
  }
  ForEachIdFrame(JsonMember(JsonMember(manifest, "tracker"), "reacquired"), "filter",
                 [&](int64_t filter, int64_t frame) {
                   const auto row = filter_rows.find(filter);
                   if (row == filter_rows.end() || !in_range(frame + 1)) return;
                   row->second.marks[kReacquired].push_back(static_cast<int>(frame + 1));
                 });
  std::map<int64_t, std::vector<int64_t>> filters_of_target;
  std::set<int64_t> mapped;
  for (const auto& [filter, target] : FilterMapping(metrics)) {
    if (!filter_rows.contains(filter) || !truth.contains(target)) continue;
    if (mapped.insert(filter).second) filters_of_target[target].push_back(filter);
  }
  return {std::move(truth), std::move(detected), std::move(filter_rows),
          std::move(filters_of_target), std::move(mapped)};
}

// One run's timeline, top to bottom: each target (increasing id), its
// detections, the filters mapped to it; then the filters mapped to none.
std::vector<TimelineRow> TimelineRows(const TimelineParts& parts) {
  std::vector<TimelineRow> rows;
  for (const auto& [id, row] : parts.truth) {
    rows.push_back(row);
    if (const auto it = parts.detected.find(id); it != parts.detected.end()) {
      rows.push_back(it->second);
    }
    if (const auto it = parts.filters_of_target.find(id); it != parts.filters_of_target.end()) {
      for (const int64_t f : it->second) rows.push_back(parts.filters.at(f));
    }
  }
  for (const auto& [id, row] : parts.filters) {
    if (!parts.mapped.contains(id)) {
      rows.push_back(row);
      rows.back().label = fmt::format("filter {} (no target)", id);
    }
  }
  return rows;
}

// Two runs of one ground truth on one timeline: each target (from run A's
// truth), then A's detections and filters of it, then B's, labelled "A ..."
// and "B ..."; one row "detections (A and B)" when the two detectors' rows
// are the same. Filters mapped to no target come last, A's first.
std::vector<TimelineRow> ComparedTimelineRows(const TimelineParts& a, const TimelineParts& b) {
  const auto labelled = [](TimelineRow row, const std::string& label) {
    row.label = label;
    return row;
  };
  std::vector<TimelineRow> rows;
  for (const auto& [id, row] : a.truth) {
    rows.push_back(row);
    const auto da = a.detected.find(id);
    const auto db = b.detected.find(id);
    const bool same = da != a.detected.end() && db != b.detected.end() &&
                      da->second.colour == db->second.colour &&
                      da->second.marks == db->second.marks;
    for (const auto& [run, parts, detected] : {std::tuple{"A", &a, da}, std::tuple{"B", &b, db}}) {
      if (detected != parts->detected.end() && !(same && parts == &b)) {
        rows.push_back(labelled(detected->second, same ? std::string("detections (A and B)")
                                                       : fmt::format("{} detections", run)));
      }
      if (const auto it = parts->filters_of_target.find(id); it != parts->filters_of_target.end()) {
        for (const int64_t f : it->second) {
          rows.push_back(labelled(parts->filters.at(f), fmt::format("{} filter {}", run, f)));
        }
      }
    }
  }
  for (const auto& [run, parts] : {std::pair{"A", &a}, std::pair{"B", &b}}) {
    for (const auto& [id, row] : parts->filters) {
      if (!parts->mapped.contains(id)) {
        rows.push_back(labelled(row, fmt::format("{} filter {} (no target)", run, id)));
      }
    }
  }
  return rows;
}

// The timeline plot: its inline SVG, and where gnuplot put the plot's box
// in the SVG's own units (its viewBox: x from the left, y from the top), so
// that the report's script can map a click to a frame and draw a cursor.
struct TimelinePlot {
  std::string svg;
  bool has_box = false;
  double left = 0, right = 0, top = 0, bottom = 0;
};

// The timeline's inline SVG: each row's runs of one colour as thick
// segments, top to bottom in row order, with a legend of the colours used.
TimelinePlot TimelineSvg(const std::vector<TimelineRow>& rows, int frames, const std::string& title,
                         const fs::path& work, const std::string& gnuplot) {
  const fs::path data = work / "timeline.dat";
  const fs::path svg = work / "timeline.svg";
  const fs::path script = work / "timeline.gp";
  std::string text = "# first_frame-0.5 row length colour (rows from 0 at the top, y = -row)\n";
  std::array<std::string, kMarks.size()> mark_text;
  mark_text.fill("# frame row\n");
  std::array<bool, kMarks.size()> has_marks{};
  std::set<int> used;
  for (size_t r = 0; r < rows.size(); ++r) {
    const std::vector<int>& c = rows[r].colour;
    for (size_t i = 0; i < c.size();) {
      size_t j = i;
      while (j + 1 < c.size() && c[j + 1] == c[i]) ++j;
      if (c[i] >= 0) {
        text += fmt::format("{} {} {} {}\n", static_cast<double>(i) + 0.5, -static_cast<int>(r),
                            j - i + 1, c[i]);
        used.insert(c[i]);
      }
      i = j + 1;
    }
    for (size_t k = 0; k < kMarks.size(); ++k) {
      for (const int f : rows[r].marks[k]) {
        mark_text[k] += fmt::format("{} {}\n", f, -static_cast<int>(r));
        has_marks[k] = true;
      }
    }
  }
  WriteTextFile(data.string(), text);
  for (size_t k = 0; k < kMarks.size(); ++k) {
    WriteTextFile((work / kMarks[k].file).string(), mark_text[k]);
  }
  const int n = static_cast<int>(rows.size());
  constexpr int kWidth = 820;
  // Rows 24 px apart, whatever the key's entries (FitCanvasToBox), drawn
  // first on a canvas tall enough for a key of up to 15 entries in one
  // column (on one too short gnuplot draws the key over the plot).
  const int trial_height = 170 + 24 * n + 300;
  const fs::path box = work / "timeline-box.txt";
  std::string gp = SvgTerminal(kWidth, std::to_string(trial_height));
  gp += fmt::format("set output {}\n", GpString(svg.string()));
  gp += fmt::format("set title {} noenhanced\n", GpString(title));
  gp += "set xlabel 'frame (from 1, as in gt/gt.txt and filters.csv)' noenhanced\n";
  gp += fmt::format("set xrange [0.5:{}]\n", frames + 0.5);
  gp += fmt::format("set yrange [{}:0.8]\n", -n + 0.2);
  std::string tics;
  for (int r = 0; r < n; ++r) {
    tics += fmt::format("{}{} {}", r ? ", " : "", GpString(rows[static_cast<size_t>(r)].label), -r);
  }
  gp += fmt::format("set ytics ({}) noenhanced\n", tics);
  // gnuplot sizes the key's columns by the longest entry's bytes, not its
  // width ("≥" is 3 bytes), so without `width -12` one column of 9 to 14
  // entries; `height 1` keeps it off the axis label.
  gp += "set grid xtics\nset key below noenhanced maxcols 3 width -12 height 1\n";
  std::string plot =
      fmt::format("plot {} using 1:2:3:(0):4 with vectors nohead lw 9 lc rgb variable notitle",
                  GpString(data.string()));
  const auto legend = [&](const TimelineColour& c) {
    if (used.contains(c.rgb)) {
      plot += fmt::format(", \\\n     NaN with lines lw 9 lc rgb '{}' title {}", RgbText(c.rgb),
                          GpString(c.name));
    }
  };
  for (const TimelineColour& c :
       {kVisibleMost, kVisibleHalf, kVisibleLittle, kFound, kMissed, kNoModel}) {
    legend(c);
  }
  for (const TimelineColour& c : kStateColours) legend(c);
  for (size_t k = 0; k < kMarks.size(); ++k) {
    if (has_marks[k]) {
      plot +=
          fmt::format(", \\\n     {} using 1:2 with points {} lc rgb 'black' title '{}'",
                      GpString((work / kMarks[k].file).string()), kMarks[k].style, kMarks[k].title);
    }
  }
  gp += plot + "\n";
  gp += FitCanvasToBox(kWidth, trial_height, 24 * n, svg, box);
  TimelinePlot out{.svg = RunGnuplotToSvg(gnuplot, script, gp, svg)};
  if (const std::optional<PlotBox> b = ReadPlotBox(box, kWidth)) {
    out.has_box = true;
    out.left = b->left;
    out.right = b->right;
    out.top = b->top;
    out.bottom = b->bottom;
  }
  return out;
}

// One run folder as the report reads it.
struct RunFolder {
  fs::path dir;
  json manifest;
  json metrics;
  std::map<std::string, double> headline;  // catalogue metrics (ReadRunMetrics)
  int frames = 0;                          // manifest.json's frames; 0 when it has none
  // scenario.resolved.yaml, parsed once to check it is YAML; nullopt when
  // the folder has none.
  std::optional<std::string> resolved;
  // overlay.mp4 (hcpf run --video): whether the folder has one, and whether
  // a browser plays it: H.264, by an hcpf whose manifest.json says so
  // (its "video" entry, with the rate and frame count the report seeks by).
  bool has_video = false;
  bool video_plays = false;
  std::string video_codec;  // the manifest's; "" when it has no video entry
  double video_fps = 0.0;
  int video_frames = 0;
  int video_width = 640;  // the manifest's, for the player's largest width
};

// ", tracker: particle filter, 500 particles, charged resampling, likelihood
// detections_mixture, camera motion none" from the resolved scenario, so the
// header says what the run is (an audit: the keys set with --set showed only
// in the YAML at the page's foot); "" without a resolved scenario.
std::string TrackerText(const RunFolder& run) {
  if (!run.resolved) return {};
  try {
    const YAML::Node tracker = YAML::Load(*run.resolved)["tracker"];
    if (!tracker.IsMap()) return {};
    const auto text = [](const YAML::Node& n) {
      return n.IsDefined() && n.IsScalar() ? n.Scalar() : std::string("?");
    };
    if (tracker["type"].IsDefined() && text(tracker["type"]) == "external") {
      std::vector<std::string> words;
      for (const auto& w : tracker["command"]) words.push_back(ShellWord(text(w)));
      return fmt::format(", tracker: external ({})", fmt::join(words, " "));
    }
    return fmt::format(
        ", tracker: particle filter, {} particles, {} resampling, likelihood {}, camera motion {}",
        text(tracker["particles"]), text(tracker["resampling"]["method"]),
        text(tracker["likelihood"]["model"]), text(tracker["camera_motion"]));
  } catch (const YAML::Exception&) {
    return {};
  }
}

// The manifest's fields of the type hcpf run writes them, where present (a
// bad-input audit: "frames": "twenty" and "seed": -1 were shown in the
// header, "timings": "x" dropped a row without a word). Absent fields are
// left to the readers (manifests of older builds lack some).
void CheckRunManifest(const json& manifest, const fs::path& path) {
  if (!manifest.is_object()) {
    throw InputError(SourceLocation{path.string(), 0, 0, ""}, "the manifest.json of hcpf run",
                     manifest.dump().substr(0, 40));
  }
  const auto bad = [&](const char* key, const std::string& expected) {
    throw InputError(SourceLocation{path.string(), 0, 0, key}, expected,
                     manifest[key].dump().substr(0, 60));
  };
  constexpr int64_t kNoBound = std::numeric_limits<int64_t>::max();
  const auto whole = [&](const char* key, int64_t lo,
                         int64_t hi = std::numeric_limits<int64_t>::max()) {
    if (manifest.contains(key) &&
        (!manifest[key].is_number_integer() || manifest[key].get<int64_t>() < lo ||
         manifest[key].get<int64_t>() > hi)) {
      bad(key, hi == kNoBound ? fmt::format("a whole number, {} or more", lo)
                              : fmt::format("a whole number, {} to {}", lo, hi));
    }
  };
  // A scenario's frames, at most (a bad-input audit: 10^8 kept the report
  // busy past a minute, sizing every per-frame table by it).
  whole("frames", 1, scenarios::kMaxFrames);
  whole("frames_rendered", 0);
  whole("frames_from_cache", 0);
  whole("detections", 0);
  whole("gt_boxes", 0);
  if (manifest.contains("seed") && !manifest["seed"].is_number_unsigned()) {
    bad("seed", "a seed (a whole number, 0 or more)");
  }
  for (const char* key : {"config_hash", "detector", "hcpf_version", "git_revision", "scenario",
                          "observation_source", "ground_truth", "format"}) {
    if (manifest.contains(key) && !manifest[key].is_string()) bad(key, "text");
  }
  for (const char* key : {"timings", "files", "libraries", "seeds", "tracker", "video"}) {
    if (manifest.contains(key) && !manifest[key].is_object()) bad(key, "an object");
  }
  if (manifest.contains("scene_notes") &&
      (!manifest["scene_notes"].is_array() ||
       !std::all_of(manifest["scene_notes"].begin(), manifest["scene_notes"].end(),
                    [](const json& note) { return note.is_string(); }))) {
    bad("scene_notes", "a list of texts");
  }
}

// The run folder's manifest.json and metrics.json; throws InputError when
// either is missing, not JSON, or not a run's.
RunFolder ReadRunFolder(const fs::path& dir) {
  RunFolder run;
  run.dir = dir;
  run.manifest = ReadRunJson(dir / "manifest.json");
  CheckRunManifest(run.manifest, dir / "manifest.json");
  run.metrics = ReadRunJson(dir / "metrics.json");
  // Every run's metrics.json has its MOT block, whatever the tracker: without
  // it ("{}", a file of another tool) the report would be NaN throughout.
  if (!JsonMember(run.metrics, "mot").is_object()) {
    throw InputError(SourceLocation{(dir / "metrics.json").string(), 0, 0, "mot"},
                     "the metrics.json of hcpf run (with its mot block)",
                     run.metrics.is_object() ? "no mot block" : run.metrics.dump().substr(0, 40));
  }
  try {
    run.headline = ReadRunMetrics(dir.string());
  } catch (const RunError& e) {
    // ReadRunMetrics reports missing files as RunError; here they are the
    // user's input.
    throw InputError(SourceLocation{dir.string(), 0, 0, ""},
                     "a run folder with metrics.json and manifest.json", e.what());
  }
  const std::optional<int64_t> frames = JsonInt(run.manifest, "frames");
  if (frames && *frames > 0 && *frames <= std::numeric_limits<int>::max()) {
    run.frames = static_cast<int>(*frames);
  }
  std::error_code ec;
  run.has_video = fs::is_regular_file(dir / "overlay.mp4", ec);
  const json& video = JsonMember(run.manifest, "video");
  if (run.has_video && video.is_object()) {
    run.video_codec = JsonText(video, "codec");
    const double fps = JsonDouble(video, "fps");
    const std::optional<int64_t> frames = JsonInt(video, "frames");
    const json& plays = JsonMember(video, "plays_in_browsers");
    if (plays.is_boolean() && plays.get<bool>() && std::isfinite(fps) && fps > 0.0 && frames &&
        *frames > 0 && *frames <= std::numeric_limits<int>::max()) {
      run.video_plays = true;
      run.video_fps = fps;
      run.video_frames = static_cast<int>(*frames);
      const std::optional<int64_t> width = JsonInt(video, "width");
      if (width && *width > 0 && *width <= std::numeric_limits<int>::max()) {
        run.video_width = static_cast<int>(*width);
      }
    }
  }
  const fs::path resolved = dir / "scenario.resolved.yaml";
  int scenario_frames = 0;  // its frames, when it has them
  if (fs::is_regular_file(resolved, ec)) {
    run.resolved = ReadInputFile(resolved.string(), "a resolved scenario", kMaxRunFileBytes);
    YAML::Node scenario;
    try {
      scenario = YAML::Load(*run.resolved);
    } catch (const YAML::Exception& e) {
      throw InputError(SourceLocation{resolved.string(), e.mark.line + 1, e.mark.column + 1, ""},
                       "the resolved scenario hcpf run writes (YAML)",
                       fmt::format("text that does not parse ({})", e.msg));
    }
    // The scenario's frames (a whole number, as hcpf run writes it: a
    // bad-input audit found "abc" blamed on the manifest, and none at all
    // accepted), and the manifest's are the same: an edited count drew the
    // timeline and per-frame tables to it.
    const YAML::Node frames = scenario.IsMap() ? scenario["frames"] : YAML::Node();
    const std::string text = frames.IsScalar() ? frames.Scalar() : std::string();
    int count = 0;
    const auto [end, failure] = std::from_chars(text.data(), text.data() + text.size(), count);
    if (text.empty() || failure != std::errc() || end != text.data() + text.size() || count < 1 ||
        count > scenarios::kMaxFrames) {
      throw InputError(
          SourceLocation{resolved.string(), frames.IsDefined() ? frames.Mark().line + 1 : 0,
                         frames.IsDefined() ? frames.Mark().column + 1 : 0, "frames"},
          fmt::format("the run's frames, 1 to {}", scenarios::kMaxFrames),
          frames.IsDefined() ? fmt::format("\"{}\"", text) : std::string("no frames"));
    }
    if (run.frames > 0 && text != std::to_string(run.frames)) {
      throw InputError(SourceLocation{(dir / "manifest.json").string(), 0, 0, "frames"},
                       fmt::format("{}, the frames of its scenario.resolved.yaml", text),
                       std::to_string(run.frames));
    }
    scenario_frames = count;
  }
  // seqinfo.ini's seqLength, which hcpf run writes with the same count: a
  // manifest and a resolved scenario edited together were read past it (the
  // timeline and per-frame tables drawn to their count).
  const fs::path seqinfo = dir / "seqinfo.ini";
  const int frames_said = run.frames > 0 ? run.frames : scenario_frames;
  if (frames_said > 0 && fs::is_regular_file(seqinfo, ec)) {
    const std::string text =
        ReadInputFile(seqinfo.string(), "the seqinfo.ini of hcpf run", kMaxRunFileBytes);
    const std::string why =
        "hcpf run writes the three with one count; the report reads the run's per-frame files to "
        "it";
    metrics::SeqInfo info;
    try {
      info = metrics::ParseSeqInfo(text, seqinfo.string());
    } catch (const InputError& e) {
      throw InputError(
          e.where(), e.expected(), e.found(),
          e.hint().empty() ? "the report checks seqLength against the run's frames" : e.hint());
    }
    if (info.seq_length != frames_said) {
      throw InputError(
          SourceLocation{seqinfo.string(), info.seq_length_line, 0, "Sequence.seqLength"},
          fmt::format("{}, the frames of its {}", frames_said,
                      run.frames > 0 && scenario_frames > 0
                          ? "manifest.json and scenario.resolved.yaml"
                      : run.frames > 0 ? "manifest.json"
                                       : "scenario.resolved.yaml"),
          std::to_string(info.seq_length), why);
    }
  }
  return run;
}

// The run folder --against names, read; throws InputError at --against when
// it is no run folder or is DIR itself.
RunFolder ReadAgainstRun(const std::string& against, const fs::path& dir) {
  const SourceLocation where{"hcpf report", 0, 0, "--against"};
  const std::string expected =
      "another run folder (hcpf run --out) to compare this run with (or, as the only "
      "--against, a sweep folder), when DIR is a run";
  ReportFolder kind{};
  try {
    kind = ClassifyReportFolder(against);
  } catch (const InputError& e) {
    throw InputError(where, expected, fmt::format("{}: {}", against, e.found()));
  }
  if (kind != ReportFolder::kRun) {
    throw InputError(where, expected,
                     fmt::format("{}, a sweep folder after the first --against (a sweep is set "
                                 "beside run A as the only --against)",
                                 against));
  }
  std::error_code ec;
  if (fs::equivalent(against, dir, ec)) {
    throw InputError(where, expected, fmt::format("{}, DIR itself", against));
  }
  return ReadRunFolder(against);
}

// Run A's cell in the sweep folder --against names (FindRunCell), found by
// A's resolved scenario and seed; InputError at --against when A has none.
RunCell FindRunCellOf(const RunFolder& run, const std::string& sweep_dir) {
  const SourceLocation where{"hcpf report", 0, 0, "--against"};
  const std::string expected =
      "a run with scenario.resolved.yaml and its seed, to find its cell in the sweep";
  if (!run.resolved) {
    throw InputError(where, expected,
                     fmt::format("{}: no scenario.resolved.yaml", run.dir.string()));
  }
  uint64_t seed = 0;
  try {
    seed = YAML::Load(*run.resolved)["seed"].as<uint64_t>();
  } catch (const YAML::Exception&) {
    throw InputError(
        where, expected,
        fmt::format("{}: scenario.resolved.yaml without a whole-number seed", run.dir.string()));
  }
  return FindRunCell(sweep_dir, run.dir.string(), *run.resolved, seed);
}

// Whether two files hold the same bytes; nullopt when either is not a
// regular file.
std::optional<bool> SameBytes(const fs::path& a, const fs::path& b) {
  std::error_code ec;
  if (!fs::is_regular_file(a, ec) || !fs::is_regular_file(b, ec)) return std::nullopt;
  std::error_code ea, eb;
  const std::uintmax_t size_a = fs::file_size(a, ea);
  const std::uintmax_t size_b = fs::file_size(b, eb);
  if (ea || eb || size_a != size_b) return false;
  std::ifstream fa(a, std::ios::binary);
  std::ifstream fb(b, std::ios::binary);
  std::array<char, 1 << 16> ba{};
  std::array<char, 1 << 16> bb{};
  while (fa && fb) {
    fa.read(ba.data(), ba.size());
    fb.read(bb.data(), bb.size());
    if (fa.gcount() != fb.gcount() ||
        !std::equal(ba.begin(), ba.begin() + fa.gcount(), bb.begin())) {
      return false;
    }
  }
  return fa.eof() && fb.eof();
}

// The files of a run folder that one resolved scenario makes byte-identical
// (docs/outputs.md, "Determinism"), in the order the comparison lists them.
constexpr std::array<const char*, 9> kDeterministicFiles = {
    "scenario.resolved.yaml", "gt/gt.txt",    "gt.json",
    "detections.txt",         "tracks.txt",   "filters.csv",
    "camera_motion.csv",      "metrics.json", "seqinfo.ini"};

// Per target, per frame (index = frame from 0): the state of the filters the
// identity mapping gives it (metrics.json filters.mapping and
// per_frame_states): CORRECT when one of them is; else the scored state of
// the first of them by filter id (SWAPPED, HIJACKED, STRAYED or LOST); else
// COASTING when one of them exists that frame; "" when none does.
std::map<int64_t, std::vector<std::string>> TargetStates(const json& metrics, int frames) {
  const std::map<int64_t, int64_t> target_of = TargetOfFilter(metrics);
  std::map<int64_t, std::vector<std::string>> by_filter;
  ForEachFilterState(metrics, [&](int64_t filter, int64_t frame, const std::string& state) {
    if (frame < 0 || frame >= frames || !target_of.contains(filter)) return;
    by_filter.try_emplace(filter, std::vector<std::string>(static_cast<size_t>(frames)))
        .first->second[static_cast<size_t>(frame)] = state;
  });
  const auto rank = [](const std::string& state) {
    return state == "CORRECT" ? 0 : state.empty() ? 3 : state == "COASTING" ? 2 : 1;
  };
  std::map<int64_t, std::vector<std::string>> out;
  for (const auto& [filter, row] : by_filter) {  // increasing filter id
    std::vector<std::string>& target =
        out.try_emplace(target_of.at(filter), std::vector<std::string>(static_cast<size_t>(frames)))
            .first->second;
    for (size_t f = 0; f < row.size(); ++f) {
      // The first filter keeps a scored state; CORRECT beats it.
      if (rank(row[f]) < rank(target[f])) target[f] = row[f];
    }
  }
  return out;
}

// One target's frames in the comparison of two runs.
struct TargetComparison {
  int64_t target = 0;
  int scored_a = 0, correct_a = 0;  // scored: a state other than COASTING
  int scored_b = 0, correct_b = 0;
  int only_a = 0, only_b = 0;    // frames CORRECT in one run alone
  int first_differ = -1;         // first frame (from 0) CORRECT in one run alone; -1: none
  std::string state_a, state_b;  // the states at that frame
};

std::vector<TargetComparison> CompareTargets(const std::set<int64_t>& targets,
                                             const json& metrics_a, const json& metrics_b,
                                             int frames) {
  const auto states_a = TargetStates(metrics_a, frames);
  const auto states_b = TargetStates(metrics_b, frames);
  const std::vector<std::string> none(static_cast<size_t>(frames));
  const auto of = [&none](const auto& states, int64_t target) -> const std::vector<std::string>& {
    const auto it = states.find(target);
    return it == states.end() ? none : it->second;
  };
  std::vector<TargetComparison> out;
  for (const int64_t target : targets) {
    TargetComparison c;
    c.target = target;
    const std::vector<std::string>& a = of(states_a, target);
    const std::vector<std::string>& b = of(states_b, target);
    for (size_t f = 0; f < static_cast<size_t>(frames); ++f) {
      const bool scored_a = !a[f].empty() && a[f] != "COASTING";
      const bool scored_b = !b[f].empty() && b[f] != "COASTING";
      const bool correct_a = a[f] == "CORRECT";
      const bool correct_b = b[f] == "CORRECT";
      c.scored_a += scored_a;
      c.scored_b += scored_b;
      c.correct_a += correct_a;
      c.correct_b += correct_b;
      c.only_a += correct_a && !correct_b;
      c.only_b += correct_b && !correct_a;
      if (correct_a != correct_b && c.first_differ < 0) {
        c.first_differ = static_cast<int>(f);
        c.state_a = a[f];
        c.state_b = b[f];
      }
    }
    out.push_back(std::move(c));
  }
  return out;
}

// A frame (counted from 1) in the report's text: where the report shows a
// video that plays, a link that moves every overlay video to that frame
// ("#frame=K", handled by the report's script); else the number.
using FrameLink = std::function<std::string(int)>;

FrameLink MakeFrameLink(bool videos) {
  if (!videos) return [](int frame) { return fmt::format("{}", frame); };
  return [](int frame) { return fmt::format("<a href=\"#frame={0}\">{0}</a>", frame); };
}

// Per target of a run's metrics.json detection.by_target, frame by frame
// (index = frame from 0): whether it is counted (found or missed) and whether
// the detector found it.
struct TargetDetections {
  std::vector<char> counted;
  std::vector<char> found;
};

std::map<int64_t, TargetDetections> DetectionFrames(const json& metrics, int frames) {
  std::map<int64_t, TargetDetections> out;
  const json& by_target = JsonMember(JsonMember(metrics, "detection"), "by_target");
  if (!by_target.is_array()) return out;
  for (const json& t : by_target) {
    const std::optional<int64_t> id = JsonInt(t, "target");
    if (!id) continue;
    TargetDetections& d = out[*id];
    d.counted.assign(static_cast<size_t>(frames), 0);
    d.found.assign(static_cast<size_t>(frames), 0);
    for (const bool found : {true, false}) {
      ForEachFrameRun(t, found ? "found_frames" : "missed_frames",
                      [&](int64_t first, int64_t last) {
                        for (int64_t f = std::max<int64_t>(0, first);
                             f <= std::min<int64_t>(frames - 1, last); ++f) {
                          d.counted[static_cast<size_t>(f)] = 1;
                          if (found) d.found[static_cast<size_t>(f)] = 1;
                        }
                      });
    }
  }
  return out;
}

// Two runs' detectors target by target over one ground truth: the frames
// each found each target in, and those one found it in alone. "" when
// neither run has a detector's per-target counts.
std::string DetectionComparisonHtml(const RunFolder& a, const RunFolder& b,
                                    const std::set<int64_t>& targets, const FrameLink& link) {
  const auto da = DetectionFrames(a.metrics, a.frames);
  const auto db = DetectionFrames(b.metrics, b.frames);
  if (da.empty() && db.empty()) return {};
  if (da.empty() || db.empty()) {
    return fmt::format(
        "<p>Only run {} has a detector's per-target counts (<code>metrics.json</code> "
        "<code>detection.by_target</code>: a rendered run with a detector), so the detectors are "
        "not compared target by target.</p>\n",
        da.empty() ? "B" : "A");
  }
  const TargetDetections none{std::vector<char>(static_cast<size_t>(a.frames), 0),
                              std::vector<char>(static_cast<size_t>(a.frames), 0)};
  const auto of = [&none](const auto& m, int64_t id) -> const TargetDetections& {
    const auto it = m.find(id);
    return it == m.end() ? none : it->second;
  };
  std::string rows;
  int alone_a = 0, alone_b = 0;
  for (const int64_t id : targets) {
    const TargetDetections& x = of(da, id);
    const TargetDetections& y = of(db, id);
    int counted_a = 0, found_a = 0, counted_b = 0, found_b = 0, only_a = 0, only_b = 0;
    int first = -1;
    for (size_t f = 0; f < x.counted.size() && f < y.counted.size(); ++f) {
      counted_a += x.counted[f];
      found_a += x.found[f];
      counted_b += y.counted[f];
      found_b += y.found[f];
      const bool both = x.counted[f] && y.counted[f];
      only_a += both && x.found[f] && !y.found[f];
      only_b += both && y.found[f] && !x.found[f];
      if (both && x.found[f] != y.found[f] && first < 0) first = static_cast<int>(f);
    }
    alone_a += only_a;
    alone_b += only_b;
    const std::string first_text =
        first < 0 ? std::string("–")
                  : fmt::format("{} (A {}, B {})", link(first + 1),
                                x.found[static_cast<size_t>(first)] ? "found" : "missed",
                                y.found[static_cast<size_t>(first)] ? "found" : "missed");
    rows += fmt::format(
        "<tr><td class=\"k\">target {}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
        "<td>{}</td><td>{}</td><td class=\"k\">{}</td></tr>\n",
        id, counted_a, found_a, counted_b, found_b, only_a, only_b, first_text);
  }
  return fmt::format(
             "<p>Detector by detector (A: <code>{}</code>, B: <code>{}</code>), target by target: "
             "the frames each target is counted in (visible enough, docs/vision.md) and found in "
             "(IoU ≥ 0.5, as the detection-quality table counts); of the frames counted in both, "
             "found by A's detector alone <b>{}</b>, by B's alone <b>{}</b>.</p>\n"
             "<table><tr><th>target</th><th>counted, A</th><th>found, A</th><th>counted, "
             "B</th><th>found, B</th><th>found by A alone</th><th>found by B alone</th><th>first "
             "frame found by one alone</th></tr>\n",
             EscapeMarkup(JsonText(a.manifest, "detector")),
             EscapeMarkup(JsonText(b.manifest, "detector")), alone_a, alone_b) +
         rows + "</table>\n";
}

// "CORRECT", "no filter" for "".
std::string StateText(const std::string& state) { return state.empty() ? "no filter" : state; }

// A filter's run of consecutive frames in one scored state other than
// CORRECT (SWAPPED, HIJACKED, STRAYED or LOST), frames counted from 1.
struct Episode {
  std::string state;
  int first = 0, last = 0;
};

// Per filter (metrics.json filters.per_frame_states), its episodes in frame
// order; COASTING, CORRECT and frames without the filter end an episode.
std::map<int64_t, std::vector<Episode>> FilterEpisodes(const json& metrics, int frames) {
  std::map<int64_t, std::map<int, std::string>> states;
  ForEachFilterState(metrics, [&](int64_t filter, int64_t frame, const std::string& state) {
    if (frame >= 0 && frame < frames) states[filter][static_cast<int>(frame) + 1] = state;
  });
  std::map<int64_t, std::vector<Episode>> out;
  for (const auto& [filter, by_frame] : states) {
    std::vector<Episode>& episodes = out[filter];
    for (const auto& [frame, state] : by_frame) {
      if (state.empty() || state == "CORRECT" || state == "COASTING") continue;
      if (!episodes.empty() && episodes.back().state == state &&
          episodes.back().last == frame - 1) {
        episodes.back().last = frame;
      } else {
        episodes.push_back({state, frame, frame});
      }
    }
  }
  return out;
}

// The "Frames to look at" rows of one run, (what, frames): each filter's
// episodes, the frames the target models were cut and those where a filter
// was re-acquired, each frame through `link`.
std::vector<std::pair<std::string, std::string>> FramesToLookAt(const RunFolder& r,
                                                                const FrameLink& link) {
  constexpr size_t kEpisodesShown = 8;
  std::vector<std::pair<std::string, std::string>> rows;
  const auto row = [&rows](std::string what, std::string frames) {
    rows.emplace_back(std::move(what), std::move(frames));
  };
  const std::map<int64_t, int64_t> target_of = TargetOfFilter(r.metrics);
  for (const auto& [filter, episodes] : FilterEpisodes(r.metrics, r.frames)) {
    if (episodes.empty()) continue;
    std::string text;
    for (size_t i = 0; i < episodes.size() && i < kEpisodesShown; ++i) {
      const Episode& e = episodes[i];
      text += fmt::format("{}{} {}{}", i ? ", " : "", e.state, link(e.first),
                          e.last > e.first ? fmt::format("–{}", e.last) : std::string());
    }
    if (episodes.size() > kEpisodesShown) {
      text +=
          fmt::format(" and {} more (the timeline shows them)", episodes.size() - kEpisodesShown);
    }
    const auto target = target_of.find(filter);
    row(target == target_of.end() ? fmt::format("filter {} (no target)", filter)
                                  : fmt::format("filter {} (target {})", filter, target->second),
        text);
  }
  const auto frame_list = [&](const json& list, const char* who, const char* label) {
    std::string text;
    ForEachIdFrame(list, who, [&](int64_t id, int64_t frame) {
      if (frame < 0 || frame >= r.frames) return;
      text += fmt::format("{}{} {}: {}", text.empty() ? "" : ", ", who, id,
                          link(static_cast<int>(frame) + 1));
    });
    if (!text.empty()) row(label, text);
  };
  frame_list(JsonMember(r.manifest, "target_model_sources"), "target", "target models cut");
  frame_list(JsonMember(JsonMember(r.manifest, "tracker"), "reacquired"), "filter",
             "filters re-acquired");
  return rows;
}

// The report's script for its overlay videos: buttons and "#frame=K" links
// move every video to frame K (counted from 1; shown at the middle of its
// display interval), each video's caption follows its frame, and a report
// opened at "report.html#frame=K" starts there.
constexpr std::string_view kVideoScript = R"(<script>
const hcpfVideos = () => [...document.querySelectorAll('video.overlay')];
// The video with the most frames leads: its frame is the report's frame
// (another, shorter one stays on its last frame past its end).
const hcpfLeader = () =>
  hcpfVideos().reduce((a, b) => (+b.dataset.frames > +a.dataset.frames ? b : a));
let hcpfCurrent = 1;
function hcpfFrameOf(v) {
  return Math.min(Math.floor(v.currentTime * +v.dataset.fps + 1e-6) + 1, +v.dataset.frames);
}
function hcpfShow(frame) {
  hcpfCurrent = Math.min(Math.max(Math.round(frame) || 1, 1), +hcpfLeader().dataset.frames);
  for (const v of hcpfVideos()) {
    const k = Math.min(hcpfCurrent, +v.dataset.frames);
    v.pause();
    v.currentTime = (k - 0.5) / +v.dataset.fps;
  }
  document.getElementById('overlay-frame').value = hcpfCurrent;
  hcpfCursor(hcpfCurrent);
}
function hcpfStep(d) { hcpfShow(hcpfCurrent + d); }
function hcpfPlay() {
  const t = hcpfLeader().currentTime;
  for (const v of hcpfVideos()) {
    // A shorter video past its end stays on its last frame (play() on an
    // ended video would start it again from the beginning).
    const end = (+v.dataset.frames - 0.5) / +v.dataset.fps;
    v.currentTime = Math.min(t, end);
    if (t < end) v.play();
  }
}
function hcpfPause() { for (const v of hcpfVideos()) v.pause(); }
// The timeline's cursor at `frame`, in the SVG's own units (the plot's box
// from the div's data attributes; the axis runs from 0.5 to frames + 0.5).
function hcpfCursor(frame) {
  const t = document.querySelector('#plot-timeline[data-left]');
  const svg = t && t.querySelector('svg');
  if (!svg) return;
  let line = svg.querySelector('#hcpf-cursor');
  if (!line) {
    line = document.createElementNS('http://www.w3.org/2000/svg', 'line');
    line.id = 'hcpf-cursor';
    line.setAttribute('stroke', '#d00');
    line.setAttribute('stroke-width', '1.5');
    line.setAttribute('y1', t.dataset.top);
    line.setAttribute('y2', t.dataset.bottom);
    svg.appendChild(line);
  }
  // Past the timeline's last frame (a longer video of the other run), none.
  line.style.display = frame > +t.dataset.frames ? 'none' : '';
  const x = +t.dataset.left + (frame - 0.5) / +t.dataset.frames * (t.dataset.right - t.dataset.left);
  line.setAttribute('x1', x);
  line.setAttribute('x2', x);
}
document.addEventListener('click', e => {
  const svg = e.target.closest('#plot-timeline[data-left] svg');
  if (svg) {
    const t = svg.parentElement;
    const p = svg.createSVGPoint();
    p.x = e.clientX;
    p.y = e.clientY;
    const q = p.matrixTransform(svg.getScreenCTM().inverse());
    const left = +t.dataset.left, right = +t.dataset.right;
    if (q.x >= left && q.x <= right && q.y >= +t.dataset.top && q.y <= +t.dataset.bottom) {
      const n = +t.dataset.frames;
      hcpfShow(Math.min(Math.round(0.5 + (q.x - left) / (right - left) * n), n));
    }
    return;
  }
  const a = e.target.closest('a[href^="#frame="]');
  if (!a) return;
  e.preventDefault();
  history.replaceState(null, '', a.getAttribute('href'));
  hcpfShow(+a.getAttribute('href').slice(7));
  document.getElementById('overlay').scrollIntoView();
});
window.addEventListener('load', () => {
  for (const v of hcpfVideos()) {
    const caption = document.getElementById(v.id + '-frame');
    const update = () => {
      caption.textContent = hcpfFrameOf(v);
      if (v === hcpfLeader() && !v.seeking) {
        hcpfCurrent = hcpfFrameOf(v);
        document.getElementById('overlay-frame').value = hcpfCurrent;
        hcpfCursor(hcpfCurrent);
      }
    };
    v.addEventListener('timeupdate', update);
    v.addEventListener('seeked', update);
  }
  hcpfCursor(hcpfCurrent);
  const m = /^#frame=(\d+)$/.exec(location.hash);
  if (m) { hcpfShow(+m[1]); document.getElementById('overlay').scrollIntoView(); }
});
// A frame typed into the address bar, or back and forward between frames.
window.addEventListener('hashchange', () => {
  const m = /^#frame=(\d+)$/.exec(location.hash);
  if (m) hcpfShow(+m[1]);
});
</script>
)";

// The overlay video section: the runs' overlay.mp4 that browsers play, side
// by side, moved together by the buttons and the report's frame links; a link
// and the reason for one that does not play. "" when neither run has a
// video. `link_a` is the link to A's video.
std::string VideoSection(const RunFolder& a, const RunFolder* b, const fs::path& out,
                         const std::string& link_a) {
  if (!a.has_video && !(b && b->has_video)) return {};
  std::string h = "<h2 id=\"overlay\">Overlay video</h2>\n";
  std::vector<std::pair<const RunFolder*, std::string>> runs = {{&a, b ? "A" : ""}};
  if (b) runs.emplace_back(b, "B");
  std::string figures, notes;
  int frames = 0, players = 0;
  for (const auto& [r, name] : runs) {
    const std::string who = name.empty() ? std::string("This run") : "Run " + name;
    // One resolved scenario gives the same files (docs/outputs.md,
    // "Determinism"): run again with --video, the run gains its video.
    const std::string again =
        fmt::format("<code>hcpf run {} --out {} --video</code> makes the same run with one",
                    EscapeMarkup(ShellWord((r->dir / "scenario.resolved.yaml").string())),
                    EscapeMarkup(ShellWord(r->dir.string() + "-video")));
    if (!r->has_video) {
      notes += fmt::format("<p>{} has no <code>overlay.mp4</code>: {}.</p>\n", who, again);
      continue;
    }
    const std::string href = r == &a ? link_a : LinkFrom(out, r->dir / "overlay.mp4");
    if (!r->video_plays) {
      notes += fmt::format(
          "<p>{}'s video: <a href=\"{}\">overlay.mp4</a>, {}, which VLC and mpv play and most "
          "browsers do not{}.</p>\n",
          who, EscapeMarkup(href),
          r->video_codec.empty() ? std::string("MPEG-4 Part 2") : EscapeMarkup(r->video_codec),
          r->video_codec.empty()
              ? fmt::format(" (made by an hcpf that wrote no H.264: its manifest.json has no "
                            "video entry; {} that plays here)",
                            again)
          : r->video_codec == "H.264"
              ? std::string(" (its frames are larger, or come faster, than any H.264 level "
                            "codes: 8176 x 4352, or 1920 x 1080 at 2048 fps, say)")
              : std::string(" (the FFmpeg that wrote it had no H.264 encoder)"));
      continue;
    }
    const std::string id = name.empty() ? "video" : "video-" + std::string(1, name[0] + 32);
    ++players;
    // No native controls: they cover the bottom 40 px of the picture (an
    // audit: a filter's state label under the control bar); the buttons
    // under the videos play, pause and step them, and the timeline seeks.
    figures += fmt::format(
        "<figure style=\"flex:1 1 0;max-width:{0}px;margin:0\"><video id=\"{1}\" "
        "class=\"overlay\" data-fps=\"{2}\" data-frames=\"{3}\" src=\"{4}\" muted "
        "preload=\"auto\" style=\"width:100%\"></video><figcaption>{5}<a href=\"{4}\">overlay.mp4"
        "</a>, frame <span id=\"{1}-frame\">1</span> of {3}</figcaption></figure>\n",
        r->video_width, id, r->video_fps, r->video_frames, EscapeMarkup(href),
        name.empty() ? std::string() : fmt::format("<b>{}</b>: ", name));
    frames = std::max(frames, r->video_frames);
  }
  if (players > 0) {
    h += fmt::format(
        "<p>Each frame with the ground truth (white), the detections the tracker was given "
        "(yellow), each filter's box, particles and state (docs/sweeps.md, \"Overlay videos\"). "
        "The buttons, and every frame number that is a link in this report, move {} to that "
        "frame (counted from 1, as the timeline); <code>report.html#frame=K</code> opens the "
        "report at frame K.</p>\n",
        players == 2 ? "both videos" : "the video");
    h += "<div style=\"display:flex;gap:1em;flex-wrap:wrap\">\n" + figures + "</div>\n";
    h += fmt::format(
        "<p><button type=\"button\" onclick=\"hcpfStep(-1)\">◀ frame</button> <button "
        "type=\"button\" onclick=\"hcpfStep(1)\">frame ▶</button> frame <input "
        "id=\"overlay-frame\" "
        "type=\"number\" min=\"1\" max=\"{}\" value=\"1\" style=\"width:5em\" "
        "onchange=\"hcpfShow(+this.value)\"> <button type=\"button\" onclick=\"hcpfPlay()\">play"
        "</button> <button type=\"button\" onclick=\"hcpfPause()\">pause</button></p>\n",
        frames);
  }
  h += notes;
  if (players > 0) h += kVideoScript;
  return h;
}

// The frames to look at of one run, or of two compared: a paragraph and a
// table (FramesToLookAt), "" when there is none; frames through `link`.
std::string FramesToLookAtHtml(const RunFolder& a, const RunFolder* b, const FrameLink& link) {
  std::string h;
  // Compared, a row B has as A has it (the same models cut, a filter of the
  // same id with the same episodes) is one row.
  std::string rows;
  const auto a_rows = FramesToLookAt(a, link);
  const auto b_rows = b ? FramesToLookAt(*b, link) : decltype(a_rows){};
  const auto row_html = [](const std::string& who, const std::pair<std::string, std::string>& r) {
    return fmt::format("<tr><td class=\"k\">{}{}</td><td class=\"k\">{}</td></tr>\n", who, r.first,
                       r.second);
  };
  for (const auto& r : a_rows) {
    const bool shared = std::find(b_rows.begin(), b_rows.end(), r) != b_rows.end();
    rows += row_html(!b ? "" : shared ? "A and B: " : "A ", r);
  }
  for (const auto& r : b_rows) {
    if (std::find(a_rows.begin(), a_rows.end(), r) == a_rows.end()) rows += row_html("B ", r);
  }
  if (!rows.empty()) {
    h += "<p>Frames to look at: each filter's frames in a scored state other than CORRECT "
         "(first–last frame of each episode; docs/metrics.md), the frames the target models "
         "were cut and those where a filter was re-acquired.</p>\n<table><tr><th>what</th>"
         "<th>frames</th></tr>\n" +
         rows + "</table>\n";
  }
  return h;
}

// Why two runs cannot be compared frame by frame ("" when they can): their
// frame counts or ground truths (gt/gt.txt) differ, or one lacks either.
// `label`: the second run's letter in the text (B, C, ...).
std::string TruthDifference(const RunFolder& a, const RunFolder& b, const std::string& label) {
  if (a.frames == 0 || b.frames == 0) {
    return fmt::format("The manifest.json of run {} has no frame count",
                       a.frames == 0 ? (b.frames == 0 ? "A nor " + label : "A") : label);
  }
  if (a.frames != b.frames) {
    return fmt::format("Run A has {} frames and run {} {}", a.frames, label, b.frames);
  }
  const std::optional<bool> same = SameBytes(a.dir / "gt" / "gt.txt", b.dir / "gt" / "gt.txt");
  if (!same) return "One of the runs has no <code>gt/gt.txt</code>";
  if (!*same) return "Their ground truths differ (<code>gt/gt.txt</code>)";
  return "";
}

// A run in the comparison's text: its folder, scenario, seed, config hash
// and build.
std::string WhoIs(const RunFolder& r) {
  return fmt::format(
      "<code>{}</code> (scenario <code>{}</code>, seed {}, config hash "
      "<code>{}</code>, hcpf {} at <code>{}</code>)",
      EscapeMarkup(r.dir.string()), EscapeMarkup(JsonText(r.manifest, "scenario")),
      EscapeMarkup(JsonText(r.manifest, "seed")), EscapeMarkup(JsonText(r.manifest, "config_hash")),
      EscapeMarkup(JsonText(r.manifest, "hcpf_version")),
      EscapeMarkup(JsonText(r.manifest, "git_revision")));
}

// The label of the k-th run beside A: B for the first (--against), then C, D, ...
std::string RunLabel(size_t k) { return std::string(1, static_cast<char>('B' + k)); }

// The most runs one report sets beside A: B to Z.
constexpr size_t kMostComparedRuns = 25;

// The section of the runs set beside A after B (several --against): who
// each is, the resolved keys it differs from A in and, over A's ground
// truth (`a_targets`: gt/gt.txt's targets), the target-frames whose filters
// are CORRECT in both, in A alone and in it alone ("" without them).
std::string MoreRunsSection(const RunFolder& a, const std::vector<RunFolder>& more,
                            const std::set<int64_t>& a_targets) {
  if (more.empty()) return {};
  std::string h = fmt::format(
      "<h2>More runs beside A</h2>\n<p>{} more run{} (<code>--against</code> after the first), "
      "set beside A in the headline metrics below (each with A − that run). Over one ground "
      "truth, the target-frames whose filters the identity mapping gives the target are CORRECT "
      "are counted as for B (in both, in A alone, in that run alone); only B is compared with A "
      "file by file, target by target and on the timeline.</p>\n<table><tr><th>run</th>"
      "<th>who</th><th>resolved keys differing from A</th><th>target-frames CORRECT: in "
      "both, in A alone, in it alone</th></tr>\n",
      more.size(), more.size() == 1 ? "" : "s");
  for (size_t k = 0; k < more.size(); ++k) {
    const RunFolder& x = more[k];
    std::string keys;
    if (!a.resolved || !x.resolved) {
      keys = fmt::format("not compared (run {} has no <code>scenario.resolved.yaml</code>)",
                         a.resolved ? RunLabel(k + 1) : std::string("A"));
    } else {
      const std::vector<config::LeafDifference> differ =
          config::DifferingLeaves(*a.resolved, *x.resolved);
      std::string rows;
      for (const config::LeafDifference& d : differ) {
        rows += fmt::format("{}<code>{}</code>: {} → {}", rows.empty() ? "" : "<br>",
                            EscapeMarkup(d.key), EscapeMarkup(d.first.value_or("(absent)")),
                            EscapeMarkup(d.second.value_or("(absent)")));
      }
      // A few keys shown, more folded (another detector's whole block).
      constexpr size_t kShownKeys = 6;
      keys =
          differ.empty() ? std::string("none: the same resolved scenario")
          : differ.size() <= kShownKeys
              ? rows
              : fmt::format("<details><summary>{} keys</summary>{}</details>", differ.size(), rows);
    }
    // Counted as ComparisonSection counts B's: over one ground truth, both
    // runs with filter states.
    std::string correct;
    const std::string truth = TruthDifference(a, x, RunLabel(k + 1));
    if (a_targets.empty()) {
      correct = "not counted (run A has no <code>gt/gt.txt</code>)";
    } else if (!truth.empty()) {
      correct = "not counted: " + truth;
    } else if (!JsonMember(a.metrics, "filters").is_object() ||
               !JsonMember(x.metrics, "filters").is_object()) {
      correct = "not counted (no filter states in <code>metrics.json</code>)";
    } else {
      int both = 0, only_a = 0, only_x = 0;
      for (const TargetComparison& c : CompareTargets(a_targets, a.metrics, x.metrics, a.frames)) {
        both += c.correct_a - c.only_a;
        only_a += c.only_a;
        only_x += c.only_b;
      }
      correct = fmt::format("{}, <b>{}</b>, <b>{}</b>", both, only_a, only_x);
    }
    h += fmt::format(
        "<tr><td><b>{}</b></td><td class=\"k\">{}</td><td class=\"k\">{}</td><td "
        "class=\"k\">{}</td></tr>\n",
        RunLabel(k + 1), WhoIs(x), keys, correct);
  }
  return h + "</table>\n";
}

// The comparison's own section (hcpf report RUN --against OTHER): who A and B
// are, the resolved keys they differ in, which files are the same, and, over
// one ground truth, target by target where their filters are CORRECT.
std::string ComparisonSection(const RunFolder& a, const RunFolder& b,
                              const std::string& truth_difference,
                              const std::set<int64_t>& truth_targets, const FrameLink& link,
                              ReportResult* result) {
  std::string h = "<h2>Compared with another run</h2>\n";
  h += fmt::format(
      "<p><b>A</b> is this run, {}; <b>B</b> is {} (<code>--against</code>). "
      "Differences are A − B.</p>\n",
      WhoIs(a), WhoIs(b));

  // The resolved scenarios, key by key (both parsed when they were read).
  if (a.resolved && b.resolved) {
    const std::vector<config::LeafDifference> differ =
        config::DifferingLeaves(*a.resolved, *b.resolved);
    result->differing_keys = static_cast<int>(differ.size());
    if (differ.empty()) {
      h += "<p>Their resolved scenarios (<code>scenario.resolved.yaml</code>) are the same, key "
           "by key.</p>\n";
    } else {
      h += fmt::format(
          "<p>Their resolved scenarios differ in {} key{}:</p>\n"
          "<table><tr><th>key</th><th>A</th><th>B</th></tr>\n",
          differ.size(), differ.size() == 1 ? "" : "s");
      // A block one run has and the other lacks (another detector's options)
      // is one row, its keys folded under it.
      constexpr size_t kFoldAt = 4;
      const auto parent = [](const std::string& key) {
        const size_t dot = key.rfind('.');
        return dot == std::string::npos ? std::string() : key.substr(0, dot);
      };
      const auto one_sided = [](const config::LeafDifference& d) {
        return d.first.has_value() != d.second.has_value();
      };
      for (size_t i = 0; i < differ.size();) {
        const config::LeafDifference& d = differ[i];
        size_t j = i + 1;
        if (one_sided(d) && !parent(d.key).empty()) {
          while (j < differ.size() && one_sided(differ[j]) &&
                 differ[j].first.has_value() == d.first.has_value() &&
                 parent(differ[j].key) == parent(d.key)) {
            ++j;
          }
        }
        if (j - i >= kFoldAt) {
          std::string keys;
          for (size_t k = i; k < j; ++k) {
            keys +=
                fmt::format("{}<code>{}</code>: {}", k == i ? "" : "<br>",
                            EscapeMarkup(differ[k].key.substr(parent(d.key).size() + 1)),
                            EscapeMarkup(differ[k].first ? *differ[k].first : *differ[k].second));
          }
          const std::string folded =
              fmt::format("<details><summary>{} keys</summary>{}</details>", j - i, keys);
          h += fmt::format(
              "<tr><td class=\"k\"><code>{}.*</code></td><td class=\"k\">{}</td>"
              "<td class=\"k\">{}</td></tr>\n",
              EscapeMarkup(parent(d.key)), d.first ? folded : "(absent)",
              d.first ? "(absent)" : folded);
        } else {
          for (size_t k = i; k < j; ++k) {
            h += fmt::format(
                "<tr><td class=\"k\"><code>{}</code></td><td class=\"k\">{}</td>"
                "<td class=\"k\">{}</td></tr>\n",
                EscapeMarkup(differ[k].key), EscapeMarkup(differ[k].first.value_or("(absent)")),
                EscapeMarkup(differ[k].second.value_or("(absent)")));
          }
        }
        i = j;
      }
      h += "</table>\n";
    }
  } else {
    h += fmt::format(
        "<p>Run {} has no <code>scenario.resolved.yaml</code>: the keys are not compared.</p>\n",
        a.resolved   ? "B"
        : b.resolved ? "A"
                     : "A nor B");
  }

  // The files one resolved scenario makes byte-identical.
  std::error_code ec;
  std::vector<std::string> same, differ, one_side;
  for (const char* file : kDeterministicFiles) {
    const std::string name = fmt::format("<code>{}</code>", file);
    if (const std::optional<bool> s = SameBytes(a.dir / file, b.dir / file)) {
      (*s ? same : differ).push_back(name);
      continue;
    }
    const bool in_a = fs::is_regular_file(a.dir / file, ec);
    if (in_a != fs::is_regular_file(b.dir / file, ec)) {
      one_side.push_back(fmt::format("{} ({} only)", name, in_a ? "A" : "B"));
    }
  }
  const auto listed = [](const std::vector<std::string>& v) {
    return v.empty() ? std::string("none") : fmt::format("{}", fmt::join(v, ", "));
  };
  h += fmt::format(
      "<p>Files with the same bytes in both: {}. Files that differ: {}.{}</p>\n", listed(same),
      listed(differ),
      one_side.empty() ? "" : fmt::format(" In one folder only: {}.", listed(one_side)));
  const std::string hash_a = JsonText(a.manifest, "config_hash");
  if (!hash_a.empty() && hash_a == JsonText(b.manifest, "config_hash")) {
    // One resolved scenario: hcpf run promises the same bytes.
    std::vector<std::string> broken = differ;
    std::erase(broken, std::string("<code>scenario.resolved.yaml</code>"));
    h += broken.empty()
             ? std::string(
                   "<p>Both are runs of one resolved scenario, and their files agree, "
                   "as hcpf run's determinism promises (docs/outputs.md).</p>\n")
             : fmt::format(
                   "<p><strong>Both are runs of one resolved scenario, yet {} differ{}</strong>: "
                   "one resolved scenario gives byte-identical files (docs/outputs.md, "
                   "\"Determinism\"), so the two runs were made by different builds of hcpf "
                   "(compare the versions above) or that promise broke.</p>\n",
                   listed(broken), broken.size() == 1 ? "s" : "");
  }

  if (!truth_difference.empty()) {
    h += fmt::format(
        "<p>{}, so the runs are not known to track the same targets over the same frames: only "
        "their headline metrics are set side by side, not their filters frame by frame.</p>\n",
        truth_difference);
    return h;
  }
  h += DetectionComparisonHtml(a, b, truth_targets, link);
  // Filter states exist only where a particle filter ran (an external
  // tracker's metrics.json has no filters block): none is not "no filter".
  const bool filters_a = JsonMember(a.metrics, "filters").is_object();
  const bool filters_b = JsonMember(b.metrics, "filters").is_object();
  if (!filters_a || !filters_b) {
    h += fmt::format(
        "<p>{} no filter states (<code>metrics.json</code> without a <code>filters</code> "
        "block: an external tracker's run, docs/external-trackers.md), so the runs' tracks are "
        "compared through the MOT metrics below, not filter by filter.</p>\n",
        filters_a   ? "Run B has"
        : filters_b ? "Run A has"
                    : "Neither run has");
    return h;
  }
  const std::vector<TargetComparison> targets =
      CompareTargets(truth_targets, a.metrics, b.metrics, a.frames);
  if (targets.empty()) return h;
  int correct_both = 0, only_a = 0, only_b = 0;
  for (const TargetComparison& c : targets) {
    correct_both += c.correct_a - c.only_a;
    only_a += c.only_a;
    only_b += c.only_b;
  }
  h += fmt::format(
      "<p>Over the same ground truth, target by target, the frames where the filters the "
      "identity mapping gives it are CORRECT (covering it; docs/metrics.md): in both runs "
      "{}, in A alone <b>{}</b>, in B alone <b>{}</b>. A scored frame is one whose filter is "
      "not COASTING; the first frame counts from 1, as the timeline and "
      "<code>gt/gt.txt</code> do.</p>\n"
      "<table><tr><th>target</th><th>scored, A</th><th>CORRECT, A</th><th>scored, "
      "B</th><th>CORRECT, B</th><th>CORRECT in A alone</th><th>CORRECT in B "
      "alone</th><th>first frame CORRECT in one alone</th></tr>\n",
      correct_both, only_a, only_b);
  for (const TargetComparison& c : targets) {
    const std::string first = c.first_differ < 0
                                  ? std::string("–")
                                  : fmt::format("{} (A {}, B {})", link(c.first_differ + 1),
                                                StateText(c.state_a), StateText(c.state_b));
    h += fmt::format(
        "<tr><td class=\"k\">target {}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
        "<td>{}</td><td>{}</td><td class=\"k\">{}</td></tr>\n",
        c.target, c.scored_a, c.correct_a, c.scored_b, c.correct_b, c.only_a, c.only_b, first);
  }
  h += "</table>\n";
  result->compared_targets = static_cast<int>(targets.size());
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
  // Every input is read and checked before anything is written.
  std::optional<RunFolder> other;
  // A sweep folder as the only --against: run A beside its cell's seeds.
  std::error_code sweep_ec;
  const bool against_sweep = !options.against.empty() &&
                             fs::exists(fs::path(options.against) / "results.sqlite", sweep_ec);
  if (against_sweep && !options.more_against.empty()) {
    throw InputError(SourceLocation{"hcpf report", 0, 0, "--against"},
                     "one sweep folder alone (run A beside its cell), or run folders",
                     fmt::format("the sweep folder {}, then {}", options.against,
                                 fmt::join(options.more_against, ", ")));
  }
  if (!options.against.empty() && !against_sweep) {
    other = ReadAgainstRun(options.against, dir);
  }
  // Runs C, D, ...: each another run folder, named once.
  std::vector<RunFolder> more;
  if (!options.more_against.empty()) {
    const SourceLocation where{"hcpf report", 0, 0, "--against"};
    if (!other) {
      throw InputError(
          where, "the run B to compare A with before more runs",
          fmt::format("only more runs ({}) and no first", fmt::join(options.more_against, ", ")));
    }
    if (options.more_against.size() + 1 > kMostComparedRuns) {
      throw InputError(
          where, fmt::format("at most {} runs beside A (B to Z)", kMostComparedRuns),
          fmt::format("{} runs (--against given {} times)", options.more_against.size() + 1,
                      options.more_against.size() + 1));
    }
    std::vector<std::string> named = {options.against};
    for (const std::string& path : options.more_against) {
      RunFolder x = ReadAgainstRun(path, dir);
      std::error_code same;
      for (const std::string& earlier : named) {
        if (fs::equivalent(path, earlier, same)) {
          throw InputError(where, "each run folder once",
                           fmt::format("{} again (as {})", path, earlier));
        }
      }
      named.push_back(path);
      more.push_back(std::move(x));
    }
  }
  if (!options.out_dir.empty()) CheckReportOut(options.out_dir);
  const fs::path out = options.out_dir.empty() ? dir : fs::path(options.out_dir);

  const RunFolder run = ReadRunFolder(dir);
  std::optional<RunCell> cell;
  if (against_sweep) cell = FindRunCellOf(run, options.against);
  const json& manifest = run.manifest;
  const json& metrics = run.metrics;
  const std::map<std::string, double>& headline = run.headline;
  const json& camera = JsonMember(metrics, "camera_motion");
  const std::string mode =
      camera.is_object() && camera.contains("mode") && camera["mode"].is_string()
          ? camera["mode"].get<std::string>()
          : std::string("unknown (metrics.json has no camera_motion.mode)");
  std::vector<CameraMotionRow> rows;
  std::error_code ec;
  const fs::path csv = dir / "camera_motion.csv";
  if (fs::exists(csv, ec)) rows = ReadCameraMotionCsv(csv);

  // The timeline needs the ground truth's rows and the run's frame count;
  // compared with another run of the same ground truth, it shows both runs'
  // rows, and the targets' filters are compared frame by frame.
  std::vector<TimelineRow> timeline;
  const fs::path gt_txt = dir / "gt" / "gt.txt";
  const std::string truth_difference = other ? TruthDifference(run, *other, "B") : std::string();
  const bool same_truth = other && truth_difference.empty();
  std::set<int64_t> truth_targets;            // gt/gt.txt's, when the runs share it
  std::set<int64_t> a_targets;                // gt/gt.txt's targets of run A
  std::vector<CentreErrorLine> centre_lines;  // A's then B's when compared over one truth
  std::string centre_note;                    // why a run's tracks.txt was left out of that plot
  std::string truncation_note;                // why gt.json's truncation was not used
  const std::optional<metrics::GroundTruthFile> gt_json =
      ReadRunGroundTruth(dir / "gt.json", &truncation_note);
  if (run.frames > 0 && fs::is_regular_file(gt_txt, ec)) {
    const metrics::MotFile gt =
        metrics::ReadMotFile(gt_txt.string(), metrics::MotFileKind::kGroundTruth, run.frames);
    const auto truncation = TruncationOf(gt_json);
    const TimelineParts parts = ReadTimeline(gt, metrics, manifest, run.frames, truncation);
    for (const auto& [id, row] : parts.truth) a_targets.insert(id);
    if (same_truth) {
      truth_targets = a_targets;
      timeline = ComparedTimelineRows(
          parts, ReadTimeline(gt, other->metrics, other->manifest, run.frames, truncation));
    } else {
      timeline = TimelineRows(parts);
    }
    const auto add_centre_lines = [&](const RunFolder& r, const std::string& prefix) {
      const fs::path tracks = r.dir / "tracks.txt";
      // A tracks.txt missing or that the plot cannot read (edited by hand,
      // cut short, a row past the run's frames) leaves the plot, said in the
      // page and the log; the rest of the report stands. (A bad-input audit
      // found the section gone without a word when it was the only run's.)
      if (!fs::is_regular_file(tracks, ec)) {
        centre_note += fmt::format(" {} is left out of this plot: it is missing.", tracks.string());
        return;
      }
      try {
        const std::vector<CentreErrorLine> lines = CentreErrorLines(
            gt, metrics::ReadMotFile(tracks.string(), metrics::MotFileKind::kTracks, r.frames),
            r.metrics, prefix);
        centre_lines.insert(centre_lines.end(), lines.begin(), lines.end());
      } catch (const InputError& e) {
        centre_note += fmt::format(" {} is left out of this plot: {}.", tracks.string(), e.what());
      }
    };
    add_centre_lines(run, same_truth ? "A " : "");
    if (same_truth) add_centre_lines(*other, "B ");
  }
  ReportResult result;
  std::string svg;
  TimelinePlot timeline_plot;
  std::string precision_recall_svg;
  const json& precision_recall = JsonMember(JsonMember(metrics, "detection"), "precision_recall");
  const bool has_curve = !JsonMember(JsonMember(precision_recall, "curve"), "recall").empty();
  // A static camera, or motion applied exactly, leaves errors of 1e-14 px:
  // rounding, drawn as a plot of noise on a 0 to 7e-14 axis (an audit).
  const bool rounding_only =
      !rows.empty() && std::all_of(rows.begin(), rows.end(), [](const CameraMotionRow& r) {
        return std::abs(r.error_px) < kRoundingPx &&
               (!std::isfinite(r.floor_px) || std::abs(r.floor_px) < kRoundingPx);
      });
  std::string centre_svg;
  // The scene from above (scene_sketch.h), from run A's gt.json: a run
  // without a video had no picture of its scene.
  const std::optional<SceneSketch> sketch =
      gt_json ? std::optional<SceneSketch>(SketchOf(*gt_json)) : std::nullopt;
  std::string sketch_svg;
  if ((!rows.empty() && !rounding_only) || !timeline.empty() || has_curve ||
      !centre_lines.empty() || sketch) {
    const fs::path work = MakePlotWorkDir(out, options.out_dir.empty());
    try {
      if (!rows.empty() && !rounding_only) {
        svg = CameraMotionSvg(rows, mode, JsonDouble(camera, "mean_px"),
                              JsonDouble(JsonMember(camera, "floor"), "mean_px"), work,
                              options.gnuplot);
        ++result.plots;
      }
      if (!timeline.empty()) {
        // Compared, the rows are both runs'.
        const auto has = [&](const json& m) {
          return std::pair{JsonMember(JsonMember(m, "detection"), "by_target").is_array(),
                           JsonMember(m, "filters").is_object()};
        };
        auto [detected, filtered] = has(metrics);
        if (same_truth) {
          const auto [detected_b, filtered_b] = has(other->metrics);
          detected = detected || detected_b;
          filtered = filtered || filtered_b;
        }
        const std::string title =
            fmt::format("targets{}{}{}, frame by frame",
                        detected ? (filtered ? ", detections" : " and detections") : "",
                        filtered ? " and filters" : "", same_truth ? " of runs A and B" : "");
        timeline_plot = TimelineSvg(timeline, run.frames, title, work, options.gnuplot);
        ++result.plots;
      }
      if (!centre_lines.empty()) {
        centre_svg = CentreErrorSvg(centre_lines, work, options.gnuplot);
        ++result.plots;
      }
      if (sketch) {
        sketch_svg =
            SceneSketchSvg(*sketch, other ? "The scene from above (run A)" : "The scene from above",
                           work, options.gnuplot, "run");
        ++result.plots;
      }
      if (has_curve) {
        precision_recall_svg = PrecisionRecallSvg(precision_recall, work, options.gnuplot);
        if (!precision_recall_svg.empty()) ++result.plots;
      }
    } catch (...) {
      fs::remove_all(work, ec);
      throw;
    }
    fs::remove_all(work, ec);
  }

  const std::string name = JsonText(manifest, "scenario");
  std::string h;
  h += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n";
  h += fmt::format("<title>HCPF run report: {}</title>\n", EscapeMarkup(name));
  h += "<style>body{font-family:sans-serif;margin:1.5em;color:#222}table{border-collapse:collapse;"
       "font-size:13px}td,th{border:1px solid #ccc;padding:3px 7px;text-align:right}"
       "th{background:#f3f3f3}td.k{text-align:left}.plot{margin:1em 0}#plot-timeline[data-left] "
       "svg{cursor:crosshair}pre{background:#f7f7f7;"
       "padding:1em;font-size:12px;overflow:auto}</style>\n</head><body>\n";
  h += fmt::format(
      "<h1>Run report: {}</h1>\n<p>Run folder <code>{}</code>: seed {}, {} frames, observations "
      "{} ({}){}, config hash <code>{}</code>.</p>\n",
      EscapeMarkup(name), EscapeMarkup(dir.string()), EscapeMarkup(JsonText(manifest, "seed")),
      EscapeMarkup(JsonText(manifest, "frames")),
      EscapeMarkup(JsonText(manifest, "observation_source")),
      EscapeMarkup(JsonText(manifest, "detector")), EscapeMarkup(TrackerText(run)),
      EscapeMarkup(JsonText(manifest, "config_hash")));
  h += FramesSentence(manifest);
  h += SceneNotesSentence(manifest);

  // Frame numbers link to the overlay videos where one plays in a browser.
  const bool videos_play = run.video_plays || (other && other->video_plays);
  const FrameLink link = MakeFrameLink(videos_play);
  if (other) {
    h += ComparisonSection(run, *other, truth_difference, truth_targets, link, &result);
  }
  h += MoreRunsSection(run, more, a_targets);
  result.more_runs = static_cast<int>(more.size());
  if (cell) {
    h += RunCellSection(*cell, headline, ReadRunBuild(dir.string()));
    result.beside_cell = true;
    for (size_t i = 0; i < cell->runs.size(); ++i) {
      result.cell_runs += cell->runs[i].ok && cell->itself != i ? 1 : 0;
    }
    result.cell_differing_keys = static_cast<int>(cell->differences.size());
  }

  // The runs beside A: B, then C, D, ...
  std::vector<const RunFolder*> beside;
  if (other) beside.push_back(&*other);
  for (const RunFolder& x : more) beside.push_back(&x);
  if (beside.empty()) {
    h += "<h2>Headline metrics</h2>\n<table><tr><th>metric</th><th>name</th>"
         "<th>value</th></tr>\n";
  } else {
    h += "<h2>Headline metrics</h2>\n<table><tr><th>metric</th><th>name</th><th>A</th>";
    for (size_t k = 0; k < beside.size(); ++k) {
      h += fmt::format("<th>{0}</th><th>A − {0}</th>", RunLabel(k));
    }
    h += "</tr>\n";
  }
  const auto value = [](const std::map<std::string, double>& values, std::string_view name) {
    const auto it = values.find(std::string(name));
    return it == values.end() ? kNaN : it->second;
  };
  // One precision per kind of value (MetricValueText).
  const auto text = MetricValueText;
  for (const CatalogueMetric& m : MetricCatalogue()) {
    // A distance in px below kRoundingPx is rounding (a static camera's
    // camera-motion error of 7e-14 px): 0.
    const auto rounded = [&m](double v) { return m.unit == "px" ? RoundedPx(v) : v; };
    const double a = rounded(value(headline, m.name));
    std::vector<double> others;
    for (const RunFolder* x : beside) others.push_back(rounded(value(x->headline, m.name)));
    // Measured in no run.
    if (!std::isfinite(a) &&
        std::none_of(others.begin(), others.end(), [](double v) { return std::isfinite(v); })) {
      continue;
    }
    const std::string unit = m.unit.empty() ? "" : " " + EscapeMarkup(std::string(m.unit));
    // A hijack rate of 1 beside a hijacked fraction of 0 read as a
    // contradiction (an audit): a lost filter counts as a hijack.
    const std::string note =
        m.name == "hijack_rate"
            ? "<br><small>encounters after which a filter of either target is HIJACKED, STRAYED "
              "or LOST (a target left with no filter counts as LOST while in view; "
              "docs/metrics.md)</small>"
            : "";
    h += fmt::format(
        "<tr><td class=\"k\">{}{}</td><td class=\"k\"><code>{}</code></td><td>{}{}</td>",
        EscapeMarkup(std::string(m.label)), note, EscapeMarkup(std::string(m.name)),
        text(m, a, false), std::isfinite(a) ? unit : "");
    for (const double b : others) {
      // A − B green where A is better in the metric's direction, red where
      // worse; not coloured: a time (MachineDependent), and what describes
      // the scene or the run rather than scores it (Descriptive, a review).
      const double d = a - b;
      const char* style =
          !std::isfinite(d) || d == 0.0 || MachineDependent(m.name) || Descriptive(m.name) ? ""
          : (d > 0.0) == m.higher_is_better ? " style=\"background:#dff3df\""
                                            : " style=\"background:#f8dede\"";
      h += fmt::format("<td>{}{}</td><td{}>{}{}</td>", text(m, b, false),
                       std::isfinite(b) ? unit : "", style, text(m, d, true),
                       std::isfinite(d) && d != 0.0 ? unit : "");
    }
    h += "</tr>\n";
  }
  h += "</table>\n";

  if (!timeline_plot.svg.empty()) {
    h += "<h2>Targets, detections and filters over time</h2>\n";
    h += "<p>One row per target, grey where it is in view, darker the more of it is seen: its "
         "visible fraction (of its pixels inside the image, gt.txt's visibility) times the share "
         "of its box inside the image (1 − gt.json's truncation). In a rendered run with a "
         "detector, the row under it shows the frames where the detector found it (IoU ≥ 0.5, as "
         "the detection-quality table below counts) and where it missed it, of the frames it is "
         "counted in (the detection metrics count a target by its visible fraction alone, so a "
         "target half outside the image is counted), with ◆ at the frame its model was cut and "
         "the misses before it, when the detector could not look for it yet, in pale orange. "
         "Then each filter "
         "that the identity mapping gives that target, coloured by its state in each frame "
         "(docs/metrics.md), with ○ where it was re-acquired from its own target's detections "
         "(tracker.management.reacquire); a filter the mapping gives no target comes last. A "
         "target with no filter row was never tracked." +
         EscapeMarkup(truncation_note) + "</p>\n";
    if (same_truth) {
      h += "<p>Both runs on one timeline: under each target, run A's detections and filters "
           "(\"A ...\"), then run B's (\"B ...\"); one row \"detections (A and B)\" where the "
           "two detectors found and missed it in the same frames.</p>\n";
    } else if (other) {
      h += "<p>Run A's alone: the runs are not compared frame by frame (above).</p>\n";
    }
    // Where the videos play, a click on the timeline shows that frame, and a
    // cursor marks the videos' frame (the report's script).
    const std::string box =
        videos_play && timeline_plot.has_box
            ? fmt::format(
                  " data-frames=\"{}\" data-left=\"{:.2f}\" data-right=\"{:.2f}\" "
                  "data-top=\"{:.2f}\" data-bottom=\"{:.2f}\"",
                  run.frames, timeline_plot.left, timeline_plot.right, timeline_plot.top,
                  timeline_plot.bottom)
            : std::string();
    if (!box.empty()) {
      h += fmt::format(
          "<p>A click on the timeline shows that frame in the overlay video{} below; the red "
          "line marks the frame {} show{}.</p>\n",
          other && other->video_plays && run.video_plays ? "s" : "",
          other && other->video_plays && run.video_plays ? "they" : "it",
          other && other->video_plays && run.video_plays ? "" : "s");
    }
    h += fmt::format("<div class=\"plot\" id=\"plot-timeline\"{}>\n{}\n</div>\n", box,
                     timeline_plot.svg);
  }
  // The overlay videos (hcpf run --video), linked from the report's folder.
  h += VideoSection(run, other ? &*other : nullptr, out,
                    options.out_dir.empty() ? "overlay.mp4" : LinkFrom(out, dir / "overlay.mp4"));
  h += FramesToLookAtHtml(run, other ? &*other : nullptr, link);
  if (!centre_note.empty()) spdlog::warn("report: centre error per frame:{}", centre_note);
  if (!centre_svg.empty() || !centre_note.empty()) {
    h += "<h2>Centre error per frame</h2>\n<p>For each target, the distance in px between the "
         "centre of the box of each filter the identity mapping gives it (tracks.txt) and the "
         "centre of its own box (gt/gt.txt), in the frames where both have one; a gap is a frame "
         "where either has none. It is what DA accuracy and the MOT metrics judge, frame by "
         "frame, and where two runs of one ground truth differ." +
         EscapeMarkup(centre_note) + (centre_svg.empty() ? " Nothing is left to plot." : "") +
         "</p>\n";
  }
  if (!centre_svg.empty()) {
    h += fmt::format("<div class=\"plot\" id=\"plot-centre_error\">\n{}\n</div>\n", centre_svg);
  }
  if (!sketch_svg.empty()) {
    h += "<h2 id=\"scene\">The scene from above</h2>\n<p>From <code>gt.json</code>" +
         std::string(other ? " (run A's)" : "") +
         ": each target's path on the ground (metres, x east, y north) with a dot every 10th frame "
         "and the frame number (from 1) every 50th, a ring where less than 0.75 of it is visible "
         "in the image, and the ground the camera sees (dashed) at its first, middle and last "
         "frame; " +
         EscapeMarkup(EncounterText(*sketch)) + ".</p>\n";
    h += fmt::format("<div class=\"plot\" id=\"plot-scene\">\n{}\n</div>\n", sketch_svg);
  }
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
          PixelText(JsonDouble(summary, "mean_px")), PixelText(JsonDouble(summary, "median_px")),
          PixelText(JsonDouble(summary, "p95_px")), PixelText(JsonDouble(summary, "max_px")));
    };
    const json& camera_b = other ? JsonMember(other->metrics, "camera_motion") : camera;
    row(other ? "error, A" : "error", camera);
    if (other && camera_b.is_object()) row("error, B", camera_b);
    if (camera.contains("floor")) row(other ? "floor, A" : "floor", camera["floor"]);
    if (other && camera_b.is_object() && camera_b.contains("floor")) {
      row("floor, B", camera_b["floor"]);
    }
    h += "</table>\n";
  } else {
    h += "<p>metrics.json has no <code>camera_motion</code> block.</p>\n";
  }
  if (!svg.empty()) {
    h += fmt::format("<div class=\"plot\" id=\"plot-camera_motion\">\n{}\n</div>\n", svg);
  } else if (rounding_only) {
    h +=
        "<p>Every frame's error (and floor) is below 10<sup>&minus;9</sup>&nbsp;px, floating-point "
        "rounding, shown as 0: the camera did not move, or its motion was applied exactly. "
        "Nothing to plot.</p>\n";
  } else {
    h += "<p>No per-frame camera motion to plot (camera_motion.csv is absent or has no "
         "rows).</p>\n";
  }
  h += DetectionSection(metrics, JsonText(manifest, "detector"), precision_recall_svg);
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
