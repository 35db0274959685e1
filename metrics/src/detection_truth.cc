#include "hcpf/metrics/detection_truth.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <set>

#include "hcpf/core/error.h"
#include "hcpf/core/ground_truth_json.h"
#include "hcpf/core/text_file.h"

namespace hcpf::metrics {

namespace {

// gt.json of a long run at a high resolution: 10 000 frames of a few targets
// take about 15 MB.
constexpr uint64_t kMaxGroundTruthBytes = uint64_t{1} << 30;

}  // namespace

std::vector<DetectionTruth> DetectionTruthOf(const FrameGroundTruth& frame) {
  const BoxPx image{0.0, 0.0, static_cast<double>(frame.camera.intrinsics.width_px),
                    static_cast<double>(frame.camera.intrinsics.height_px)};
  std::vector<DetectionTruth> truth;
  for (const GroundTruthObject& o : frame.objects) {
    if (!o.in_frame) continue;
    truth.push_back({o.id, Intersect(o.amodal_box, image), o.visible_fraction, o.truncation});
  }
  return truth;
}

GroundTruthFile ReadGroundTruthJson(const std::string& path) {
  const std::string what = "a gt.json written by hcpf render or hcpf run";
  const std::string text = ReadInputFile(path, what, kMaxGroundTruthBytes);
  nlohmann::json root;
  try {
    root = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    // nlohmann counts the byte it stopped at from 1.
    const TextPosition at = PositionOf(text, e.byte == 0 ? 0 : e.byte - 1);
    throw InputError(SourceLocation{path, at.line, at.column, ""}, what,
                     fmt::format("text that does not parse as JSON ({})", e.what()));
  }
  const auto member = [&](const char* key) -> const nlohmann::json* {
    return root.is_object() && root.contains(key) ? &root[key] : nullptr;
  };
  const nlohmann::json* format = member("format");
  if (format == nullptr || !format->is_string() || format->get<std::string>() != "hcpf-gt/1") {
    throw InputError(SourceLocation{path, 0, 0, "format"}, what + " (format \"hcpf-gt/1\")",
                     format == nullptr ? "no \"format\" key" : format->dump());
  }
  GroundTruthFile file;
  const nlohmann::json* source = member("source");
  if (source == nullptr || !source->is_string() ||
      (*source != "rendered" && *source != "analytic")) {
    throw InputError(SourceLocation{path, 0, 0, "source"}, "\"rendered\" or \"analytic\"",
                     source == nullptr ? "no \"source\" key" : source->dump());
  }
  file.source = source->get<std::string>();
  const nlohmann::json* frames = member("frames");
  if (frames == nullptr || !frames->is_array()) {
    throw InputError(SourceLocation{path, 0, 0, "frames"}, "a list of frames",
                     frames == nullptr ? "no \"frames\" key" : frames->type_name());
  }
  for (size_t f = 0; f < frames->size(); ++f) {
    const std::string key = fmt::format("frames[{}]", f);
    try {
      file.frames.push_back(GroundTruthFromJson((*frames)[f]));
    } catch (const InputError& e) {
      // The field that does not read, by its path (a bad-input audit: only
      // frames[i] and the JSON library's text).
      const std::string& field = e.where().key;
      throw InputError(SourceLocation{path, 0, 0, field.empty() ? key : key + "." + field},
                       e.expected(), e.found());
    }
    const FrameGroundTruth& frame = file.frames.back();
    if (frame.frame != static_cast<int>(f)) {
      throw InputError(SourceLocation{path, 0, 0, key + ".frame"}, fmt::format("{}", f),
                       fmt::format("{}", frame.frame));
    }
    // What the scores read: a box of finite numbers and a size of at least
    // 0, fractions in [0, 1] (hcpf writes nothing else; a file made by hand
    // may).
    std::set<int32_t> ids;
    for (size_t i = 0; i < frame.objects.size(); ++i) {
      const GroundTruthObject& o = frame.objects[i];
      const std::string object = fmt::format("{}.objects[{}]", key, i);
      if (!ids.insert(Value(o.id)).second) {
        throw InputError(SourceLocation{path, 0, 0, object + ".id"},
                         "an id no other object of the frame has",
                         fmt::format("{}, an earlier object's too", Value(o.id)));
      }
      const BoxPx& b = o.amodal_box;
      if (!b.finite() || b.width < 0.0 || b.height < 0.0 || std::fabs(b.left) > kMaxCoordinatePx ||
          std::fabs(b.top) > kMaxCoordinatePx || b.width > kMaxCoordinatePx ||
          b.height > kMaxCoordinatePx) {
        throw InputError(SourceLocation{path, 0, 0, object + ".amodal_box"},
                         fmt::format("[left, top, width, height] in pixels, width and height at "
                                     "least 0, each within {:g} px",
                                     kMaxCoordinatePx),
                         fmt::format("[{}, {}, {}, {}]", b.left, b.top, b.width, b.height));
      }
      for (const auto& [value, name] : {std::pair{o.visible_fraction, "visible_fraction"},
                                        std::pair{o.truncation, "truncation"}}) {
        if (!(value >= 0.0 && value <= 1.0)) {
          throw InputError(SourceLocation{path, 0, 0, object + "." + name}, "a fraction in [0, 1]",
                           fmt::format("{}", value));
        }
      }
    }
  }
  return file;
}

std::vector<DetectionFileRow> DetectionRowsOf(const MotFile& file) {
  const std::string within = fmt::format("within {:g} px", kMaxCoordinatePx);
  std::vector<DetectionFileRow> rows;
  rows.reserve(file.rows.size());
  for (const MotRow& row : file.rows) {
    const auto bad = [&](int column, const char* key, const std::string& expected, double found) {
      throw InputError(SourceLocation{file.path, row.line, column, key}, expected,
                       fmt::format("{}", found));
    };
    if (!(std::fabs(row.box.left) <= kMaxCoordinatePx)) {
      bad(3, "column 3 (left)", "a number " + within, row.box.left);
    }
    if (!(std::fabs(row.box.top) <= kMaxCoordinatePx)) {
      bad(4, "column 4 (top)", "a number " + within, row.box.top);
    }
    if (!(row.box.width > 0.0 && row.box.width <= kMaxCoordinatePx)) {
      bad(5, "column 5 (width)", "a width above 0 px, " + within, row.box.width);
    }
    if (!(row.box.height > 0.0 && row.box.height <= kMaxCoordinatePx)) {
      bad(6, "column 6 (height)", "a height above 0 px, " + within, row.box.height);
    }
    if (!std::isfinite(row.conf)) bad(7, "column 7 (score)", "a finite score", row.conf);
    // MOT's 1-based pixels: left 1 is the image's first column.
    rows.push_back({.frame = row.frame - 1,
                    .detection = {.box = {row.box.left - 1.0, row.box.top - 1.0, row.box.width,
                                          row.box.height},
                                  .score = row.conf},
                    .id = row.id,
                    .line = row.line,
                    .id_whole = row.id_whole});
  }
  return rows;
}

void ReadDetectionLabels(const MotFile& file, const std::set<int64_t>& targets,
                         const std::string& labels_option, std::vector<DetectionFileRow>* rows) {
  for (DetectionFileRow& row : *rows) {
    if (row.id == -1 && row.id_whole) continue;
    // A fractional label names no target (a bad-input audit: 1.5 was read
    // as "no label", where 7 is refused); MotFile keeps only its truncation.
    if (!row.id_whole || !targets.contains(row.id)) {
      throw InputError(SourceLocation{file.path, row.line, 2, "column 2 (id)"},
                       fmt::format("the id of one of the targets ({}), or -1 for a detection of "
                                   "none: {} reads column 2 as the target",
                                   fmt::join(targets, ", "), labels_option),
                       row.id_whole ? std::to_string(row.id)
                                    : fmt::format("a fraction (read as {} by truncation)", row.id));
    }
    row.detection.target = ObjectId{static_cast<int32_t>(row.id)};
  }
}

}  // namespace hcpf::metrics
