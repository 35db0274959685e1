// Motion-compensated 3-frame differencing (DiffOptions in detector.h).

#include <algorithm>
#include <cstdint>
#include <limits>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <optional>
#include <utility>
#include <vector>

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
// Registration corners: one per kCornerCell px cell of the half-resolution
// frame (40 px at full resolution: 192 cells at 640 x 480), kept above
// kCornerFloor of the strongest corner response.
constexpr int kCornerCell = 20;
constexpr double kCornerFloor = 1e-3;

class DiffDetector final : public Detector {
 public:
  explicit DiffDetector(const DiffOptions& options)
      : options_((options.Validate(), options)),
        kernel_(MakeStackedBoxKernel(options.smooth_sigma_px, 4)) {}

  DetectorOutput Detect(const DetectorInput& input, Rng&) const override {
    DetectorOutput out;
    const size_t gap = static_cast<size_t>(options_.frame_gap);
    if (input.image.empty() || input.previous.size() < 2 * gap) return out;
    // Per-thread scratch, reused from call to call (Detect stays const and
    // safe from several threads): fresh frame-sized buffers each call cost
    // page faults comparable to the arithmetic.
    thread_local Scratch scratch;
    Scratch& s = scratch;
    const cv::Mat current = Smoothed(input.image, s.current);
    // Corners are found once, on frame t at half resolution, spread over a
    // grid (see Corners), and tracked into both earlier frames.
    cv::pyrDown(current, s.current_half);
    const std::vector<cv::Point2f> corners = Corners(s.current_half, s.eig);
    if (static_cast<int>(corners.size()) < kMinInliers) return out;
    // min over the two earlier frames of |I_t - W_k(I_{t-k})|; 0 where either
    // earlier frame has no pixel after the warp: `warped` starts as a copy of
    // frame t and the warp leaves the pixels it has no source for
    // (BORDER_TRANSPARENT), so their difference is 0.
    s.min_diff.create(current.size(), CV_8U);
    s.min_diff.setTo(cv::Scalar(255));
    for (size_t k = 1; k <= 2; ++k) {
      const ImageView& view = input.previous[k * gap - 1];
      if (view.width != input.image.width || view.height != input.image.height) return out;
      const cv::Mat earlier = Smoothed(view, s.earlier);
      cv::pyrDown(earlier, s.earlier_half);
      const std::optional<cv::Mat> warp = Register(s.earlier_half, s.current_half, corners);
      if (!warp) return out;
      current.copyTo(s.warped);
      cv::warpAffine(earlier, s.warped, *warp, current.size(), cv::INTER_LINEAR,
                     cv::BORDER_TRANSPARENT);
      cv::absdiff(current, s.warped, s.diff);
      cv::min(s.min_diff, s.diff, s.min_diff);
    }
    const cv::Mat& min_diff = s.min_diff;
    cv::Mat moved = min_diff > options_.threshold;
    cv::morphologyEx(moved, moved, cv::MORPH_CLOSE,
                     cv::getStructuringElement(cv::MORPH_RECT, cv::Size(3, 3)));
    // Fragments are grouped: the moving pixels of a uniformly coloured
    // vehicle are its leading and trailing edges and its markings, the
    // interior it shares with its earlier footprints does not change. Pixels
    // within merge_px of each other (the mask dilated by merge_px) are one
    // detection, boxed by its moving pixels (not the dilation).
    cv::Mat grouped = moved;  // no copy: replaced, not written into, below
    if (options_.merge_px > 0) {
      grouped = cv::Mat();
      cv::dilate(moved, grouped,
                 cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * options_.merge_px + 1,
                                                                    2 * options_.merge_px + 1)));
    }
    // One pass over the labels gathers each group's moving pixels: their
    // count, bounding box and summed difference. (OpenCV's
    // connectedComponentsWithStats gathers statistics of every pixel,
    // background included: 2.1 ms of a 640 x 480 frame against 0.3 ms for
    // the labels alone.)
    cv::Mat& labels = s.labels;
    const int n = cv::connectedComponents(grouped, labels, 8, CV_32S);
    s.groups.assign(static_cast<size_t>(std::max(n, 1)), Group{});
    for (int y = 0; y < labels.rows; ++y) {
      const int* label = labels.ptr<int>(y);
      const uint8_t* move = moved.ptr<uint8_t>(y);
      const uint8_t* diff = min_diff.ptr<uint8_t>(y);
      for (int x = 0; x < labels.cols; ++x) {
        if (label[x] == 0 || move[x] == 0) continue;
        Group& g = s.groups[static_cast<size_t>(label[x])];
        g.left = std::min(g.left, x);
        g.top = std::min(g.top, y);
        g.right = std::max(g.right, x);
        g.bottom = std::max(g.bottom, y);
        ++g.area;
        g.sum += diff[x];
      }
    }
    for (int c = 1; c < n; ++c) {
      const Group& g = s.groups[static_cast<size_t>(c)];
      if (g.area < options_.min_area_px) continue;
      // The mean as cv::mean computes it (the sum times 1 / count).
      const double mean = static_cast<double>(g.sum) * (1.0 / static_cast<double>(g.area));
      out.detections.push_back(
          {.box = BoxPx{static_cast<double>(g.left), static_cast<double>(g.top),
                        static_cast<double>(g.right - g.left + 1),
                        static_cast<double>(g.bottom - g.top + 1)},
           .score = std::clamp(mean / kScoreScale, 0.0, 1.0)});
    }
    return out;
  }
  bool uses_models() const override { return false; }
  int history() const override { return 2 * options_.frame_gap; }
  std::string_view name() const override { return "diff"; }

 private:
  // The moving pixels of one group: bounding box (inclusive), count and
  // summed difference.
  struct Group {
    int left = std::numeric_limits<int>::max(), top = std::numeric_limits<int>::max();
    int right = -1, bottom = -1;
    int area = 0;
    int64_t sum = 0;
  };
  // Frame-sized buffers of one thread's calls.
  struct Scratch {
    GreyImage current, earlier;
    cv::Mat current_half, earlier_half, eig, warped, diff, min_diff, labels;
    std::vector<Group> groups;
  };

  // Grey levels smoothed by the stacked integral image blur, into `store`
  // (the returned header shares its pixels: no copy).
  cv::Mat Smoothed(const ImageView& view, GreyImage& store) const {
    StackedIntegralBlur(ToGrey(view), kernel_, store);
    return cv::Mat(store.height, store.width, CV_8U, store.pixels.data());
  }

  // Corners of the half-resolution frame t: the strongest minimum-eigenvalue
  // response in each kCornerCell x kCornerCell cell, kept when it exceeds
  // kCornerFloor of the frame's strongest (none on a uniform frame), the
  // strongest max_corners of them. One per cell spreads them over the
  // ground: a global "best N" (goodFeaturesToTrack) puts nearly all of them
  // on the high-contrast vehicles, which move, and RANSAC then fits their
  // motion or finds too few inliers (the benchmark frames: 36 corners, 9 and
  // 4 inliers, a 35 px wrong shift, then no registration at all).
  std::vector<cv::Point2f> Corners(const cv::Mat& half, cv::Mat& eig) const {
    cv::cornerMinEigenVal(half, eig, 3, 3);
    double strongest = 0.0;
    cv::minMaxLoc(eig, nullptr, &strongest);
    std::vector<std::pair<float, cv::Point2f>> found;
    if (strongest <= 0.0) return {};
    for (int y = 0; y + kCornerCell / 2 <= half.rows; y += kCornerCell) {
      for (int x = 0; x + kCornerCell / 2 <= half.cols; x += kCornerCell) {
        const cv::Rect cell =
            cv::Rect(x, y, kCornerCell, kCornerCell) & cv::Rect(0, 0, half.cols, half.rows);
        double best = 0.0;
        cv::Point at;
        cv::minMaxLoc(eig(cell), nullptr, &best, nullptr, &at);
        if (best <= kCornerFloor * strongest) continue;
        found.push_back({static_cast<float>(best),
                         cv::Point2f(static_cast<float>(x + at.x), static_cast<float>(y + at.y))});
      }
    }
    // Strongest first; ties in grid order (stable): deterministic.
    std::stable_sort(found.begin(), found.end(),
                     [](const auto& a, const auto& b) { return a.first > b.first; });
    if (static_cast<int>(found.size()) > options_.max_corners) {
      found.resize(static_cast<size_t>(options_.max_corners));
    }
    std::vector<cv::Point2f> corners;
    corners.reserve(found.size());
    for (const auto& f : found) corners.push_back(f.second);
    return corners;
  }

  // The similarity taking the earlier frame onto frame t (2 x 3, CV_64F,
  // full resolution): `corners` of frame t's half-resolution image tracked
  // into `earlier_half` by pyramidal Lucas-Kanade (15 x 15 px windows, 30 px
  // at full resolution; 3 pyramid levels), then a RANSAC fit in full-
  // resolution pixels (OpenCV seeds its RANSAC with a fixed state:
  // deterministic).
  std::optional<cv::Mat> Register(const cv::Mat& earlier_half, const cv::Mat& current_half,
                                  const std::vector<cv::Point2f>& corners) const {
    std::vector<cv::Point2f> tracked;
    std::vector<uint8_t> status;
    std::vector<float> error;
    cv::calcOpticalFlowPyrLK(current_half, earlier_half, corners, tracked, status, error,
                             cv::Size(15, 15), 3);
    const auto full = internal::FullResolutionOfHalf;
    std::vector<cv::Point2f> from, to;
    for (size_t i = 0; i < corners.size(); ++i) {
      if (status[i] == 0) continue;
      from.push_back(full(tracked[i]));
      to.push_back(full(corners[i]));
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
