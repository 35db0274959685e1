// Colour-histogram back-projection (ColourOptions in detector.h).

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "cv_image.h"
#include "detectors.h"

namespace hcpf::vision::internal {
namespace {

cv::Mat Hsv(const ImageView& view) {
  cv::Mat hsv;
  cv::cvtColor(RgbMat(view), hsv, cv::COLOR_RGB2HSV);  // H in [0, 180), S in [0, 256)
  return hsv;
}

// Where the box of `side` px that cv::blur averages at index 0 (its default
// anchor: pixels -floor(side/2) ... side - 1 - floor(side/2)) is centred:
// 0.5 for an odd side, 0 for an even one. The detection's box and the map
// both use it.
double BoxCentreOffset(int side) { return 0.5 * side - side / 2; }

class ColourDetector final : public Detector {
 public:
  explicit ColourDetector(const ColourOptions& options) : options_(options) { options_.Validate(); }

  DetectorOutput Detect(const DetectorInput& input, Rng&) const override {
    DetectorOutput out;
    const int width = input.image.empty() ? 0 : input.image.width;
    const int height = input.image.empty() ? 0 : input.image.height;
    const cv::Mat hsv = width > 0 ? Hsv(input.image) : cv::Mat();
    const int channels[] = {0, 1};
    const int bins[] = {options_.hue_bins, options_.saturation_bins};
    const float hue_range[] = {0.0f, 180.0f};
    const float saturation_range[] = {0.0f, 256.0f};
    const float* ranges[] = {hue_range, saturation_range};
    for (const TargetModel& model : input.models) {
      cv::Mat mean_in_box;
      cv::Rect region;
      cv::Size box_size;
      if (width > 0 && model.patch.width > 0 && model.patch.height > 0) {
        // The model's histogram, its largest bin scaled to 1.
        const cv::Mat patch = Hsv(ImageView(model.patch));
        cv::Mat hist;
        cv::calcHist(&patch, 1, channels, cv::Mat(), hist, 2, bins, ranges);
        cv::normalize(hist, hist, 1.0, 0.0, cv::NORM_INF);
        const SearchWindow* window = WindowOf(input.windows, model.target);
        region = cv::Rect(0, 0, width, height);
        box_size = cv::Size(model.patch.width, model.patch.height);
        if (window != nullptr && !window->box.empty()) {
          const BoxPx& b = window->box;
          box_size = cv::Size(ClampToInt(std::round(b.width), 1, std::max(1, width)),
                              ClampToInt(std::round(b.height), 1, std::max(1, height)));
          region = AroundBox(b, options_.window_scale, width, height);
        }
        if (region.width > 0 && region.height > 0) {
          // The model's bin value of every pixel of the frame, in [0, 1] (to
          // 1/255: the back-projection of an 8-bit image is 8-bit, so the
          // histogram is scaled to 255 for it; at scale 1 it was rounded to
          // 0 or 1, a pixel counting only where its bin held half the
          // largest: audit). The whole frame even for a window: the contrast
          // is against the frame's mean.
          cv::Mat back;
          cv::calcBackProject(&hsv, 1, channels, hist, back, ranges, 255.0);
          back.convertTo(back, CV_32F, 1.0 / 255.0);
          // Mean back-projection over a model-sized box at each pixel of the
          // region (outside the image counts as 0): at index x it covers
          // pixels x - floor(w/2) ... x - floor(w/2) + w - 1 (OpenCV's
          // anchor), a box centred on x + 0.5 for odd w and on x for even w.
          // A window's boxes read the frame's pixels beyond it: the region
          // grown by the box on each side is blurred, its edges zero only
          // where they are the image's (until 2026-12-07 a window was blurred
          // alone, zero beyond it, against its own mean, so a window of the
          // target's size had contrast 0 and found nothing: a review).
          const cv::Rect grown =
              cv::Rect(region.x - box_size.width, region.y - box_size.height,
                       region.width + 2 * box_size.width, region.height + 2 * box_size.height) &
              cv::Rect(0, 0, width, height);
          cv::Mat blurred;
          cv::blur(back(grown), blurred, box_size, cv::Point(-1, -1),
                   cv::BORDER_CONSTANT | cv::BORDER_ISOLATED);
          mean_in_box = blurred(region - grown.tl()).clone();
          const double frame_mean = cv::mean(back)[0];
          double peak = 0.0;
          cv::Point at;
          cv::minMaxLoc(mean_in_box, nullptr, &peak, nullptr, &at);
          const double contrast = frame_mean < 1.0 ? (peak - frame_mean) / (1.0 - frame_mean) : 0.0;
          if (contrast >= options_.min_contrast) {
            const BoxPx box = BoxPx::FromCentre(region.x + at.x + BoxCentreOffset(box_size.width),
                                                region.y + at.y + BoxCentreOffset(box_size.height),
                                                box_size.width, box_size.height);
            if (const auto inside = ClipToImage(box, width, height)) {
              out.detections.push_back({.box = *inside,
                                        .score = std::clamp(contrast, 0.0, 1.0),
                                        .target = model.target});
            }
          }
        }
      }
      // A value stands for the centre of the box it averages.
      out.maps.push_back(
          {model.target, PoolToMap(mean_in_box, region.x + BoxCentreOffset(box_size.width),
                                   region.y + BoxCentreOffset(box_size.height), width, height,
                                   options_.cell_px)});
    }
    return out;
  }
  bool uses_models() const override { return true; }
  std::string_view name() const override { return "colour"; }

 private:
  ColourOptions options_;
};

}  // namespace

std::unique_ptr<Detector> MakeColourDetector(const ColourOptions& options) {
  return std::make_unique<ColourDetector>(options);
}

}  // namespace hcpf::vision::internal
