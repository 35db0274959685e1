// Normalised cross-correlation template matching (NccOptions in detector.h).

#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "cv_image.h"
#include "detectors.h"

namespace hcpf::vision::internal {
namespace {

// The search region and the template size for one model: the whole frame at
// the model's own size, or a window around the target's predicted box at the
// predicted size.
struct Search {
  cv::Rect region;
  cv::Size templ;
};

Search SearchFor(const TargetModel& model, const SearchWindow* window, double window_scale,
                 int width, int height) {
  if (window == nullptr || window->box.empty()) {
    return {cv::Rect(0, 0, width, height), cv::Size(model.patch.width, model.patch.height)};
  }
  const BoxPx& b = window->box;
  const cv::Size templ(ClampToInt(std::round(b.width), 2, std::max(2, width)),
                       ClampToInt(std::round(b.height), 2, std::max(2, height)));
  return {AroundBox(b, window_scale, width, height), templ};
}

class NccDetector final : public Detector {
 public:
  explicit NccDetector(const NccOptions& options) : options_(options) { options_.Validate(); }

  DetectorOutput Detect(const DetectorInput& input, Rng&) const override {
    DetectorOutput out;
    const int width = input.image.empty() ? 0 : input.image.width;
    const int height = input.image.empty() ? 0 : input.image.height;
    const cv::Mat grey = width > 0 ? GreyMat(input.image) : cv::Mat();
    for (const TargetModel& model : input.models) {
      cv::Mat response;
      Search search{};
      if (width > 0 && model.patch.width > 0 && model.patch.height > 0) {
        search = SearchFor(model, WindowOf(input.windows, model.target), options_.window_scale,
                           width, height);
        if (search.templ.width <= search.region.width &&
            search.templ.height <= search.region.height) {
          cv::Mat templ = GreyMat(ImageView(model.patch));
          if (templ.size() != search.templ) {
            cv::resize(templ, templ, search.templ, 0, 0, cv::INTER_AREA);
          }
          cv::matchTemplate(grey(search.region), templ, response, cv::TM_CCOEFF_NORMED);
        }
      }
      // A response pixel is the template's top-left corner; the map holds it
      // at the template's centre (in the middle of a pixel for an odd side).
      const double x0 = search.region.x + search.templ.width / 2.0;
      const double y0 = search.region.y + search.templ.height / 2.0;
      out.maps.push_back(
          {model.target, PoolToMap(response, x0, y0, width, height, options_.cell_px)});
      if (response.empty()) continue;
      double peak = 0.0;
      cv::Point at;
      cv::minMaxLoc(response, nullptr, &peak, nullptr, &at);
      if (!(peak >= options_.min_correlation)) continue;
      out.detections.push_back({.box = BoxPx{static_cast<double>(search.region.x + at.x),
                                             static_cast<double>(search.region.y + at.y),
                                             static_cast<double>(search.templ.width),
                                             static_cast<double>(search.templ.height)},
                                .score = std::clamp(peak, 0.0, 1.0),
                                .target = model.target});
    }
    return out;
  }
  bool uses_models() const override { return true; }
  std::string_view name() const override { return "ncc"; }

 private:
  NccOptions options_;
};

}  // namespace

std::unique_ptr<Detector> MakeNccDetector(const NccOptions& options) {
  return std::make_unique<NccDetector>(options);
}

}  // namespace hcpf::vision::internal
