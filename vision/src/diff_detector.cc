// Motion-compensated 3-frame differencing (DiffOptions in detector.h).

#include <algorithm>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <optional>

#include "cv_image.h"
#include "detectors.h"
#include "hcpf/vision/stacked_integral_blur.h"

namespace hcpf::vision::internal {
namespace {

// Registration needs at least this many RANSAC inliers; fewer (a uniform or
// featureless frame) is no registration, so no detection.
constexpr int kMinInliers = 8;
// Score: the component's mean of min(|I_t - W1|, |I_t - W2|) over this many
// grey levels, clipped to 1 (a difference of half the 8-bit range scores 1).
constexpr double kScoreScale = 128.0;

class DiffDetector final : public Detector {
 public:
  explicit DiffDetector(const DiffOptions& options)
      : options_((options.Validate(), options)),
        kernel_(MakeStackedBoxKernel(options.smooth_sigma_px, 4)) {}

  DetectorOutput Detect(const DetectorInput& input, Rng&) const override {
    DetectorOutput out;
    const size_t gap = static_cast<size_t>(options_.frame_gap);
    if (input.image.empty() || input.previous.size() < 2 * gap) return out;
    const cv::Mat current = Smoothed(input.image);
    // min over the two earlier frames of |I_t - W_k(I_{t-k})|; 0 where either
    // earlier frame has no pixel after the warp.
    cv::Mat min_diff(current.size(), CV_8U, cv::Scalar(255));
    for (size_t k = 1; k <= 2; ++k) {
      const ImageView& view = input.previous[k * gap - 1];
      if (view.width != input.image.width || view.height != input.image.height) return out;
      const cv::Mat earlier = Smoothed(view);
      const std::optional<cv::Mat> warp = Register(earlier, current);
      if (!warp) return out;
      cv::Mat warped, valid, diff;
      cv::warpAffine(earlier, warped, *warp, current.size(), cv::INTER_LINEAR, cv::BORDER_CONSTANT,
                     cv::Scalar(0));
      cv::warpAffine(cv::Mat(earlier.size(), CV_8U, cv::Scalar(255)), valid, *warp, current.size(),
                     cv::INTER_NEAREST, cv::BORDER_CONSTANT, cv::Scalar(0));
      cv::absdiff(current, warped, diff);
      diff.setTo(cv::Scalar(0), valid == 0);
      cv::min(min_diff, diff, min_diff);
    }
    cv::Mat moved = min_diff > options_.threshold;
    cv::morphologyEx(moved, moved, cv::MORPH_CLOSE,
                     cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
    cv::Mat labels, stats, centroids;
    const int n = cv::connectedComponentsWithStats(moved, labels, stats, centroids, 8, CV_32S);
    for (int c = 1; c < n; ++c) {
      const int area = stats.at<int>(c, cv::CC_STAT_AREA);
      if (area < options_.min_area_px) continue;
      const cv::Rect box(stats.at<int>(c, cv::CC_STAT_LEFT), stats.at<int>(c, cv::CC_STAT_TOP),
                         stats.at<int>(c, cv::CC_STAT_WIDTH), stats.at<int>(c, cv::CC_STAT_HEIGHT));
      const double mean = cv::mean(min_diff(box), labels(box) == c)[0];
      out.detections.push_back(
          {.box = BoxPx{static_cast<double>(box.x), static_cast<double>(box.y),
                        static_cast<double>(box.width), static_cast<double>(box.height)},
           .score = std::clamp(mean / kScoreScale, 0.0, 1.0)});
    }
    return out;
  }
  bool uses_models() const override { return false; }
  int history() const override { return 2 * options_.frame_gap; }
  std::string_view name() const override { return "diff"; }

 private:
  // Grey levels smoothed by the stacked integral image blur.
  cv::Mat Smoothed(const ImageView& view) const {
    GreyImage grey = ToGrey(view);
    GreyImage blurred;
    StackedIntegralBlur(grey, kernel_, blurred);
    return cv::Mat(blurred.height, blurred.width, CV_8U, blurred.pixels.data()).clone();
  }

  // The similarity taking `earlier` onto `current` (2 x 3, CV_64F): corners
  // of `current` tracked into `earlier` by pyramidal Lucas-Kanade, then a
  // RANSAC fit (OpenCV seeds its RANSAC with a fixed state: deterministic).
  std::optional<cv::Mat> Register(const cv::Mat& earlier, const cv::Mat& current) const {
    std::vector<cv::Point2f> corners;
    cv::goodFeaturesToTrack(current, corners, options_.max_corners, 0.01, 8.0);
    if (static_cast<int>(corners.size()) < kMinInliers) return std::nullopt;
    std::vector<cv::Point2f> tracked;
    std::vector<uint8_t> status;
    std::vector<float> error;
    cv::calcOpticalFlowPyrLK(current, earlier, corners, tracked, status, error);
    std::vector<cv::Point2f> from, to;
    for (size_t i = 0; i < corners.size(); ++i) {
      if (status[i] == 0) continue;
      from.push_back(tracked[i]);
      to.push_back(corners[i]);
    }
    if (static_cast<int>(from.size()) < kMinInliers) return std::nullopt;
    std::vector<uint8_t> inliers;
    cv::Mat warp = cv::estimateAffinePartial2D(from, to, inliers, cv::RANSAC, options_.ransac_px);
    if (warp.empty() || std::count(inliers.begin(), inliers.end(), 1) < kMinInliers) {
      return std::nullopt;
    }
    return warp;
  }

  DiffOptions options_;
  StackedBoxKernel kernel_;
};

}  // namespace

std::unique_ptr<Detector> MakeDiffDetector(const DiffOptions& options) {
  return std::make_unique<DiffDetector>(options);
}

}  // namespace hcpf::vision::internal
