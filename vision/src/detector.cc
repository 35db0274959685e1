#include "hcpf/vision/detector.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "cv_image.h"
#include "detectors.h"
#include "hcpf/vision/detectors.h"

namespace hcpf::vision {

std::span<const Field<NccOptions>> NccOptions::Fields() {
  using O = NccOptions;
  static const std::vector<Field<O>> fields = {
      NumberField("min_correlation", &O::min_correlation, AboveUpTo(0, 1), "",
                  "peak normalised cross-correlation needed for a detection"),
      NumberField("window_scale", &O::window_scale, Closed(1, 20), "",
                  "windowed search: window side = scale × predicted box side"),
      NumberField("cell_px", &O::cell_px, Closed(1, 64), "px", "map cell size"),
  };
  return fields;
}

void NccOptions::Validate(std::string_view prefix) const { CheckFields(*this, Fields(), prefix); }

std::span<const Field<ColourOptions>> ColourOptions::Fields() {
  using O = ColourOptions;
  static const std::vector<Field<O>> fields = {
      IntegerField("hue_bins", &O::hue_bins, 2, 180, "", "hue bins of the model histogram"),
      IntegerField("saturation_bins", &O::saturation_bins, 2, 256, "",
                   "saturation bins of the model histogram"),
      NumberField("min_contrast", &O::min_contrast, AboveUpTo(0, 1), "",
                  "(peak − frame mean) / (1 − frame mean) needed for a detection"),
      NumberField("window_scale", &O::window_scale, Closed(1, 20), "",
                  "windowed search: window side = scale × predicted box side"),
      NumberField("cell_px", &O::cell_px, Closed(1, 64), "px", "map cell size"),
  };
  return fields;
}

void ColourOptions::Validate(std::string_view prefix) const {
  CheckFields(*this, Fields(), prefix);
}

std::span<const Field<DiffOptions>> DiffOptions::Fields() {
  using O = DiffOptions;
  static const std::vector<Field<O>> fields = {
      IntegerField("frame_gap", &O::frame_gap, 1, 100, "frames",
                   "frames t − g and t − 2g are compared with frame t"),
      NumberField("threshold", &O::threshold, AboveUpTo(0, 255), "grey levels",
                  "a pixel moved when it differs from both registered earlier frames by more"),
      IntegerField("min_area_px", &O::min_area_px, 1, 100000, "px",
                   "fewest moving pixels in a detection (after grouping by merge_px)"),
      NumberField("smooth_sigma_px", &O::smooth_sigma_px, Closed(0.5, 10), "px",
                  "Gaussian (stacked integral image) smoothing before differencing"),
      IntegerField("max_corners", &O::max_corners, 10, 10000, "",
                   "corners tracked to register the earlier frames"),
      NumberField("ransac_px", &O::ransac_px, AboveUpTo(0, 50), "px",
                  "RANSAC inlier distance of the registration"),
      IntegerField("merge_px", &O::merge_px, 0, 100, "px",
                   "moving pixels within this distance (per axis) are one detection"),
  };
  return fields;
}

void DiffOptions::Validate(std::string_view prefix) const { CheckFields(*this, Fields(), prefix); }

std::vector<std::string_view> DetectorNames() {
  std::vector<std::string_view> names;
  DetectorOptions{}.ForEach([&](const char* name, const auto&) { names.push_back(name); });
  return names;
}

std::unique_ptr<Detector> MakeDetector(std::string_view name, const DetectorOptions& options) {
  if (name == "ncc") return internal::MakeNccDetector(options.ncc);
  if (name == "colour") return internal::MakeColourDetector(options.colour);
  if (name == "prca") return MakePrcaDetector(options.prca);
  if (name == "sks") return MakeSksDetector(options.sks);
  if (name == "diff") return internal::MakeDiffDetector(options.diff);
  if (name.find('+') == std::string_view::npos) return nullptr;
  // A fusion: each '+'-separated part a registered name (so not empty),
  // none twice.
  std::vector<std::unique_ptr<Detector>> parts;
  for (size_t start = 0; start <= name.size();) {
    const size_t end = std::min(name.find('+', start), name.size());
    const std::string_view part = name.substr(start, end - start);
    const bool twice =
        std::any_of(parts.begin(), parts.end(), [&](const auto& p) { return p->name() == part; });
    std::unique_ptr<Detector> made = twice ? nullptr : MakeDetector(part, options);
    if (made == nullptr) return nullptr;
    parts.push_back(std::move(made));
    start = end + 1;
  }
  return internal::MakeFusedDetector(std::move(parts));
}

namespace internal {

cv::Mat GreyMat(const ImageView& view) {
  cv::Mat grey;
  cv::cvtColor(RgbMat(view), grey, cv::COLOR_RGB2GRAY);
  return grey;
}

LikelihoodMap PoolToMap(const cv::Mat& response, double x0, double y0, int width, int height,
                        double cell_px) {
  LikelihoodMap map;
  map.cell_px = cell_px;
  map.width = static_cast<int>(std::ceil(width / cell_px));
  map.height = static_cast<int>(std::ceil(height / cell_px));
  map.values.assign(static_cast<size_t>(map.width) * map.height, 0.0f);
  for (int y = 0; y < response.rows; ++y) {
    const float* row = response.ptr<float>(y);
    const int cy = std::clamp(static_cast<int>(std::floor((y0 + y) / cell_px)), 0, map.height - 1);
    for (int x = 0; x < response.cols; ++x) {
      const int cx = std::clamp(static_cast<int>(std::floor((x0 + x) / cell_px)), 0, map.width - 1);
      float& cell = map.values[static_cast<size_t>(cy) * map.width + cx];
      if (std::isfinite(row[x])) cell = std::max(cell, row[x]);
    }
  }
  return map;
}

std::optional<BoxPx> ClipToImage(const BoxPx& box, int width, int height) {
  const BoxPx clipped =
      Intersect(box, BoxPx{0.0, 0.0, static_cast<double>(width), static_cast<double>(height)});
  if (clipped.width < 1.0 || clipped.height < 1.0) return std::nullopt;
  return clipped;
}

const SearchWindow* WindowOf(std::span<const SearchWindow> windows, ObjectId target) {
  for (const SearchWindow& w : windows) {
    if (w.target != target) continue;
    // A box with a side of no number is no window (a diverged filter's).
    return w.box.finite() ? &w : nullptr;
  }
  return nullptr;
}

int ClampToInt(double v, int lo, int hi) {
  // Clamped as a double first: a cast of a value beyond int is undefined.
  if (!(v > lo)) return lo;
  if (!(v < hi)) return hi;
  return static_cast<int>(v);
}

cv::Rect AroundBox(const BoxPx& box, double scale, int width, int height) {
  // A box too large for a double (its centre or its scaled side overflows)
  // covers the frame (computed as it was, its edges would be NaN: empty).
  const BoxPx around =
      BoxPx::FromCentre(box.centre_x(), box.centre_y(), scale * box.width, scale * box.height);
  if (!std::isfinite(box.centre_x()) || !std::isfinite(box.centre_y())) {
    return {0, 0, width, height};
  }
  const bool wide = !std::isfinite(around.width), tall = !std::isfinite(around.height);
  const int x0 = wide ? 0 : ClampToInt(std::floor(around.left), 0, width);
  const int y0 = tall ? 0 : ClampToInt(std::floor(around.top), 0, height);
  const int x1 = wide ? width : ClampToInt(std::ceil(around.right()), 0, width);
  const int y1 = tall ? height : ClampToInt(std::ceil(around.bottom()), 0, height);
  return {x0, y0, std::max(0, x1 - x0), std::max(0, y1 - y0)};
}

}  // namespace internal
}  // namespace hcpf::vision
