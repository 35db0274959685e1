#pragma once
// Plain value types that cross module boundaries: boxes, ids, detections,
// observations, ground truth and track estimates. Copyable, comparable, no
// behaviour beyond small geometric helpers. Units are in the names.

#include <Eigen/Core>
#include <cmath>
#include <compare>
#include <cstdint>
#include <optional>
#include <vector>

namespace hcpf {

// Distinct id types so a scene object id and a track id cannot be mixed.
enum class ObjectId : int32_t {};
enum class TrackId : int32_t {};
constexpr int32_t Value(ObjectId id) { return static_cast<int32_t>(id); }
constexpr int32_t Value(TrackId id) { return static_cast<int32_t>(id); }

// An axis-aligned image box: top-left corner and size, in pixels. Pixel (0,0)
// covers [0,1)x[0,1); MOT files store the same numbers 1-based (left + 1).
struct BoxPx {
  double left = 0.0;
  double top = 0.0;
  double width = 0.0;
  double height = 0.0;

  double right() const { return left + width; }
  double bottom() const { return top + height; }
  double centre_x() const { return left + 0.5 * width; }
  double centre_y() const { return top + 0.5 * height; }
  double area() const { return width > 0.0 && height > 0.0 ? width * height : 0.0; }
  bool empty() const { return !(width > 0.0 && height > 0.0); }
  // Every side a number (a diverged filter's or a broken file's box is not).
  bool finite() const {
    return std::isfinite(left) && std::isfinite(top) && std::isfinite(width) &&
           std::isfinite(height);
  }

  static BoxPx FromCentre(double cx, double cy, double w, double h) {
    return {cx - 0.5 * w, cy - 0.5 * h, w, h};
  }
  static BoxPx FromCorners(double x0, double y0, double x1, double y1) {
    return {x0, y0, x1 - x0, y1 - y0};
  }
  friend bool operator==(const BoxPx&, const BoxPx&) = default;
};

// Intersection of two boxes (empty box with zero size when they do not overlap).
BoxPx Intersect(const BoxPx& a, const BoxPx& b);
// Smallest box containing both (an empty box is ignored).
BoxPx Union(const BoxPx& a, const BoxPx& b);
// Intersection over union, 0 when either box is empty or the union is ~0.
double Iou(const BoxPx& a, const BoxPx& b);

// One detection in one frame, as a detector (or the simulated one) reports it.
struct Detection {
  BoxPx box;
  double score = 1.0;
  // For simulated detections only: the object the detection came from, or
  // nullopt for clutter. Never read by the tracker; metrics and tests use it.
  std::optional<ObjectId> source;
  // For target-specific detectors (vision/): the target whose model produced
  // the detection.
  std::optional<ObjectId> target;
  friend bool operator==(const Detection&, const Detection&) = default;
};

// A dense likelihood (or detector accumulator) over the image at a reduced
// resolution: value(cx, cy) covers the image points [cx*cell_px,
// (cx+1)*cell_px) in continuous coordinates (pixel i spans [i, i + 1); a
// detector pools a value by the point it stands for, e.g. a pixel's centre).
struct LikelihoodMap {
  int width = 0;   // cells
  int height = 0;  // cells
  double cell_px = 1.0;
  std::vector<float> values;  // row-major, width*height, >= 0

  float At(int cx, int cy) const { return values[static_cast<size_t>(cy) * width + cx]; }
  // Bilinear sample at image position (x_px, y_px); cell centres at (i+0.5)*cell_px;
  // clamped at the border.
  double Sample(double x_px, double y_px) const;
  friend bool operator==(const LikelihoodMap&, const LikelihoodMap&) = default;
};

// Everything a tracker may see of one frame.
// One target's likelihood map, from a target-specific detector (its
// accumulator for that target's model).
struct TargetMap {
  ObjectId target{};
  LikelihoodMap map;
  friend bool operator==(const TargetMap&, const TargetMap&) = default;
};

// A frame's evidence. With a target-specific detector (vision/) detections
// carry Detection::target and `target_maps` holds a map per target: the
// tracker then gives each filter only its own target's part (TrackId value
// == ObjectId value, as filters born from ground truth are numbered).
struct Observation {
  int frame = 0;  // 0-based frame index
  std::vector<Detection> detections;
  std::optional<LikelihoodMap> likelihood;
  std::vector<TargetMap> target_maps;
  // Whether any detection or map is target-specific.
  bool target_specific() const;
  friend bool operator==(const Observation&, const Observation&) = default;
};

// A tracker's output for one track in one frame.
struct TrackEstimate {
  TrackId id{};
  BoxPx box;
  double confidence = 1.0;
  friend bool operator==(const TrackEstimate&, const TrackEstimate&) = default;
};

}  // namespace hcpf
