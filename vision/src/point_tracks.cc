// Background point tracks and the RANSAC baseline (point_tracks.h).

#include "hcpf/vision/point_tracks.h"

#include <fmt/format.h>

#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>
#include <vector>

#include "cv_image.h"
#include "hcpf/core/error.h"

namespace hcpf::vision {
namespace {

// Shi-Tomasi block size (goodFeaturesToTrack's default): the structure
// tensor summed over 3 x 3 pixels of the corner image.
constexpr int kCornerBlock = 3;
// Lucas-Kanade stops after 30 iterations or when an update moves the point
// by less than 0.01 px of the image it runs on (OpenCV's defaults; a finer
// eps changed the climb error by less than its frame-to-frame spread,
// docs/vision.md).
constexpr int kFlowIterations = 30;
constexpr double kFlowEpsPx = 0.01;
// Lucas-Kanade gives up on a point whose window's smaller gradient
// eigenvalue (normalised by the window's pixel count) is below this: OpenCV's
// default, a flat window.
constexpr double kFlowMinEigen = 1e-4;

// The grey levels resized to `scale` of their size (INTER_AREA: at 0.5 the
// mean of each 2 x 2 block, no shift), or the grey levels themselves at 1.
// `sx`, `sy` receive the exact per-axis ratios (the sizes are rounded).
// `store` keeps the resized pixels (the returned header shares them).
cv::Mat Resized(const cv::Mat& grey, double scale, double& sx, double& sy, cv::Mat& store) {
  if (scale == 1.0) {
    sx = sy = 1.0;
    return grey;
  }
  const int w = std::max(1, static_cast<int>(std::lround(grey.cols * scale)));
  const int h = std::max(1, static_cast<int>(std::lround(grey.rows * scale)));
  cv::resize(grey, store, cv::Size(w, h), 0.0, 0.0, cv::INTER_AREA);
  const cv::Mat out = store;
  sx = static_cast<double>(w) / grey.cols;
  sy = static_cast<double>(h) / grey.rows;
  return out;
}

// Where corners may be found: 255 except on the pixels (of the image at
// scale sx, sy) that overlap an excluded box grown by `dilation_px`. Pixel i
// of the scaled image covers [i / sx, (i + 1) / sx) of the full-resolution
// frame, so it overlaps [l, r) when floor(l sx) <= i < ceil(r sx).
void CornerMask(cv::Size size, double sx, double sy, std::span<const BoxPx> exclude,
                double dilation_px, cv::Mat& mask) {
  mask.create(size, CV_8U);
  mask.setTo(cv::Scalar(255));
  for (const BoxPx& box : exclude) {
    const double l = box.left - dilation_px;
    const double t = box.top - dilation_px;
    const double r = box.left + box.width + dilation_px;
    const double b = box.top + box.height + dilation_px;
    if (!std::isfinite(l) || !std::isfinite(t) || !std::isfinite(r) || !std::isfinite(b)) continue;
    if (r <= l || b <= t) continue;
    const double x0 = std::clamp(std::floor(l * sx), 0.0, static_cast<double>(size.width));
    const double x1 = std::clamp(std::ceil(r * sx), 0.0, static_cast<double>(size.width));
    const double y0 = std::clamp(std::floor(t * sy), 0.0, static_cast<double>(size.height));
    const double y1 = std::clamp(std::ceil(b * sy), 0.0, static_cast<double>(size.height));
    if (x1 <= x0 || y1 <= y0) continue;
    mask(cv::Rect(static_cast<int>(x0), static_cast<int>(y0), static_cast<int>(x1 - x0),
                  static_cast<int>(y1 - y0)))
        .setTo(cv::Scalar(0));
  }
}

// Frame-sized buffers of one thread's calls, reused from call to call (the
// function stays stateless in what it returns): fresh buffers each call cost
// page faults several times the arithmetic at full resolution (the
// benchmark: 13.6 ms a frame with them, see docs/vision.md).
struct Scratch {
  cv::Mat grey_previous, grey_current, corner_image, flow_previous, flow_current, mask;
  std::vector<cv::Mat> pyramid_previous, pyramid_current;
};

}  // namespace

std::span<const Field<PointTrackerOptions>> PointTrackerOptions::Fields() {
  using O = PointTrackerOptions;
  static const std::vector<Field<O>> fields = {
      IntegerField("max_corners", &O::max_corners, 1, 500, "",
                   "most background corners tracked per frame"),
      NumberField("quality_level", &O::quality_level, AboveUpTo(0, 1), "",
                  "a corner's response must reach this fraction of the frame's strongest"),
      NumberField("min_distance_px", &O::min_distance_px, Closed(0, 200), "px",
                  "closest two corners may be (full resolution)"),
      NumberField("corner_scale", &O::corner_scale, Closed(0.25, 1), "",
                  "resolution corners are found at, fraction of the frame's"),
      NumberField("flow_scale", &O::flow_scale, Closed(0.25, 1), "",
                  "resolution Lucas-Kanade tracks at, fraction of the frame's"),
      IntegerField("window_px", &O::window_px, 5, 101, "px",
                   "Lucas-Kanade window side, pixels of the image it runs on"),
      IntegerField("pyramid_levels", &O::pyramid_levels, 0, 8, "",
                   "Lucas-Kanade pyramid levels above the image it runs on"),
      NumberField("forward_backward_px", &O::forward_backward_px, Closed(0, 100), "px",
                  "largest forward-backward tracking error kept (0: no check)"),
  };
  return fields;
}

void PointTrackerOptions::Validate(std::string_view prefix) const {
  CheckFields(*this, Fields(), prefix);
}

std::span<const Field<RansacOptions>> RansacOptions::Fields() {
  using O = RansacOptions;
  static const std::vector<Field<O>> fields = {
      NumberField("threshold_px", &O::threshold_px, AboveUpTo(0, 100), "px",
                  "RANSAC inlier distance"),
      IntegerField("max_iterations", &O::max_iterations, 1, 100000, "", "most RANSAC iterations"),
      NumberField("confidence", &O::confidence, {0, 1, true, true}, "",
                  "RANSAC stops once an outlier-free sample was drawn with this probability"),
      IntegerField("refine_iterations", &O::refine_iterations, 0, 1000, "",
                   "Levenberg-Marquardt iterations on the inliers (0: none)"),
  };
  return fields;
}

void RansacOptions::Validate(std::string_view prefix) const {
  CheckFields(*this, Fields(), prefix);
}

std::span<const Field<PerspectiveOptions>> PerspectiveOptions::Fields() {
  using O = PerspectiveOptions;
  static const std::vector<Field<O>> fields = {
      FlagField("enabled", &O::enabled,
                "camera_motion scene_filter: fit the perspective terms of the frame-to-frame "
                "homography to the tracks, let the scene filter estimate the rest, and apply "
                "the similarity closest to that homography at the image corners"),
      NumberField("inlier_px", &O::inlier_px, AboveUpTo(0, 100), "px",
                  "tracks within this of the RANSAC similarity enter the perspective fit"),
  };
  return fields;
}

void PerspectiveOptions::Validate(std::string_view prefix) const {
  CheckFields(*this, Fields(), prefix);
}

std::optional<Eigen::Vector2d> FitPerspective(std::span<const PointTrack> tracks,
                                              const SimilarityMotion& guide, double inlier_px,
                                              const Eigen::Vector2d& centre) {
  using Vec6 = Eigen::Matrix<double, 6, 1>;
  Eigen::Matrix<double, 6, 6> normal = Eigen::Matrix<double, 6, 6>::Zero();
  Vec6 rhs = Vec6::Zero();
  int used = 0;
  for (const PointTrack& t : tracks) {
    if (!t.p.allFinite() || !t.q.allFinite()) continue;
    const Eigen::Vector2d e = Apply(guide, t.p) - t.q;
    if (!(std::hypot(e.x(), e.y()) <= inlier_px)) continue;
    const Eigen::Vector2d x = t.p - centre;
    const Eigen::Vector2d q = t.q - centre;
    // Unknowns (a, b, tx, ty, g, h): q = a x + t - q (g x + h y), complex a = a + i b.
    Vec6 row_x, row_y;
    row_x << x.x(), -x.y(), 1.0, 0.0, -q.x() * x.x(), -q.x() * x.y();
    row_y << x.y(), x.x(), 0.0, 1.0, -q.y() * x.x(), -q.y() * x.y();
    normal += row_x * row_x.transpose() + row_y * row_y.transpose();
    rhs += row_x * q.x() + row_y * q.y();
    ++used;
  }
  if (used < 8) return std::nullopt;
  const Eigen::LLT<Eigen::Matrix<double, 6, 6>> llt(normal);
  if (llt.info() != Eigen::Success) return std::nullopt;
  const Vec6 v = llt.solve(rhs);
  if (!v.allFinite()) return std::nullopt;
  // A fit from tracks bunched in a corner of the frame can extrapolate to a
  // perspective no camera makes between two frames: the denominator
  // 1 + g x + h y at an image corner at 0 or below (the corner behind the
  // camera; the run stopped on it, blaming the true homography: a review)
  // or far from 1. Such a fit is no fit.
  for (const double sx : {-1.0, 1.0}) {
    for (const double sy : {-1.0, 1.0}) {
      const double d = 1.0 + v(4) * sx * centre.x() + v(5) * sy * centre.y();
      if (!(d >= kMinPerspectiveDenominator && d <= 1.0 / kMinPerspectiveDenominator)) {
        return std::nullopt;
      }
    }
  }
  return Eigen::Vector2d(v(4), v(5));
}

Eigen::Matrix3d PerspectiveHomography(const SimilarityMotion& numerator, const Eigen::Vector2d& gh,
                                      const Eigen::Vector2d& centre) {
  const double k = std::exp(numerator.log_scale);
  const double a = k * std::cos(numerator.rotation_rad);
  const double b = k * std::sin(numerator.rotation_rad);
  // S about the centre: S_c(x) = S(x + c) - c = A x + (S(c) - c).
  const Eigen::Vector2d t_c = Apply(numerator, centre) - centre;
  Eigen::Matrix3d centred;
  centred << a, -b, t_c.x(), b, a, t_c.y(), gh.x(), gh.y(), 1.0;
  Eigen::Matrix3d to_centred = Eigen::Matrix3d::Identity();
  to_centred(0, 2) = -centre.x();
  to_centred(1, 2) = -centre.y();
  Eigen::Matrix3d from_centred = Eigen::Matrix3d::Identity();
  from_centred(0, 2) = centre.x();
  from_centred(1, 2) = centre.y();
  return from_centred * centred * to_centred;
}

std::vector<PointTrack> RemovePerspective(std::span<const PointTrack> tracks,
                                          const Eigen::Vector2d& gh,
                                          const Eigen::Vector2d& centre) {
  std::vector<PointTrack> out(tracks.begin(), tracks.end());
  for (PointTrack& t : out) {
    const Eigen::Vector2d x = t.p - centre;
    t.q = centre + (t.q - centre) * (1.0 + gh.dot(x));
  }
  return out;
}

std::vector<PointTrack> TrackBackgroundPoints(const ImageView& previous, const ImageView& current,
                                              std::span<const BoxPx> exclude,
                                              double mask_dilation_px,
                                              const PointTrackerOptions& options) {
  options.Validate();
  if (!std::isfinite(mask_dilation_px) || mask_dilation_px < 0.0) {
    throw InputError(fmt::format(
        "background point tracks: mask dilation must be a finite number >= 0 px, found {}",
        mask_dilation_px));
  }
  if (previous.width != current.width || previous.height != current.height) {
    throw InputError(fmt::format(
        "background point tracks: frames t-1 and t must be of one size, found {} x {} and {} x {}",
        previous.width, previous.height, current.width, current.height));
  }
  std::vector<PointTrack> tracks;
  if (previous.empty()) return tracks;
  const int width = previous.width;
  const int height = previous.height;
  thread_local Scratch scratch;
  Scratch& s = scratch;
  cv::cvtColor(internal::RgbMat(previous), s.grey_previous, cv::COLOR_RGB2GRAY);
  cv::cvtColor(internal::RgbMat(current), s.grey_current, cv::COLOR_RGB2GRAY);
  const cv::Mat& grey_previous = s.grey_previous;
  const cv::Mat& grey_current = s.grey_current;

  // Corners of frame t-1 at corner_scale, as full-resolution positions in
  // the project's convention: pixel centre (x, y) of the scaled image covers
  // [x / s, (x + 1) / s), centre (x + 0.5) / s.
  double csx = 1.0, csy = 1.0;
  const cv::Mat corner_image =
      Resized(grey_previous, options.corner_scale, csx, csy, s.corner_image);
  CornerMask(corner_image.size(), csx, csy, exclude, mask_dilation_px, s.mask);
  cv::Mat& mask = s.mask;
  // No track within half a Lucas-Kanade window of the frame's edge, at
  // either end: there the window reaches past the image, OpenCV fills it by
  // reflecting the border, and the track is biased (the synthetic test's
  // frames: every track error above 0.2 px started or ended within 13 px of
  // the edge).
  const double edge_px = 0.5 * options.window_px / options.flow_scale;
  const int ex = std::min(mask.cols, static_cast<int>(std::ceil(edge_px * csx)));
  const int ey = std::min(mask.rows, static_cast<int>(std::ceil(edge_px * csy)));
  mask.colRange(0, ex).setTo(cv::Scalar(0));
  mask.colRange(mask.cols - ex, mask.cols).setTo(cv::Scalar(0));
  mask.rowRange(0, ey).setTo(cv::Scalar(0));
  mask.rowRange(mask.rows - ey, mask.rows).setTo(cv::Scalar(0));
  std::vector<cv::Point2f> corners;
  if (corner_image.cols >= kCornerBlock && corner_image.rows >= kCornerBlock) {
    cv::goodFeaturesToTrack(corner_image, corners, options.max_corners, options.quality_level,
                            options.min_distance_px * 0.5 * (csx + csy), mask, kCornerBlock,
                            /*useHarrisDetector=*/false);
  }
  if (corners.empty()) return tracks;

  double fsx = 1.0, fsy = 1.0;
  const cv::Mat flow_previous =
      Resized(grey_previous, options.flow_scale, fsx, fsy, s.flow_previous);
  const cv::Mat flow_current = Resized(grey_current, options.flow_scale, fsx, fsy, s.flow_current);
  const cv::Size window(options.window_px, options.window_px);
  // Lucas-Kanade reads a window around each point: an image smaller than the
  // window has nothing to track with.
  if (flow_previous.cols <= options.window_px || flow_previous.rows <= options.window_px) {
    return tracks;
  }
  std::vector<Eigen::Vector2d> starts;  // full resolution, the project's convention
  std::vector<cv::Point2f> from;        // the same in the flow image's pixel coordinates
  starts.reserve(corners.size());
  from.reserve(corners.size());
  for (const cv::Point2f& c : corners) {
    const Eigen::Vector2d p((c.x + 0.5) / csx, (c.y + 0.5) / csy);
    starts.push_back(p);
    from.emplace_back(static_cast<float>(p.x() * fsx - 0.5), static_cast<float>(p.y() * fsy - 0.5));
  }
  // Pyramids built once per frame and shared by the forward and backward
  // passes (calcOpticalFlowPyrLK would otherwise build each twice).
  std::vector<cv::Mat>& pyramid_previous = s.pyramid_previous;
  std::vector<cv::Mat>& pyramid_current = s.pyramid_current;
  const int levels_previous =
      cv::buildOpticalFlowPyramid(flow_previous, pyramid_previous, window, options.pyramid_levels);
  // Lucas-Kanade reads the gradients of the image it tracks from only:
  // frame t's pyramid needs them for the backward pass alone.
  const bool backward = options.forward_backward_px > 0.0;
  const int levels_current = cv::buildOpticalFlowPyramid(flow_current, pyramid_current, window,
                                                         options.pyramid_levels, backward);
  const int levels = std::min(levels_previous, levels_current);
  const cv::TermCriteria criteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, kFlowIterations,
                                  kFlowEpsPx);
  std::vector<cv::Point2f> to;
  std::vector<uint8_t> status;
  std::vector<float> error;
  cv::calcOpticalFlowPyrLK(pyramid_previous, pyramid_current, from, to, status, error, window,
                           levels, criteria, 0, kFlowMinEigen);

  // The forward-backward check (Kalal et al. 2010): each found point tracked
  // back into frame t-1 from scratch (no initial guess, which would bias the
  // return towards the start).
  std::vector<uint8_t> back_status;
  std::vector<cv::Point2f> back;
  if (backward) {
    std::vector<cv::Point2f> found;
    for (size_t i = 0; i < to.size(); ++i) {
      if (status[i] != 0) found.push_back(to[i]);
    }
    if (!found.empty()) {
      std::vector<cv::Point2f> returned;
      cv::calcOpticalFlowPyrLK(pyramid_current, pyramid_previous, found, returned, back_status,
                               error, window, levels, criteria, 0, kFlowMinEigen);
      back = std::move(returned);
    }
  }

  tracks.reserve(from.size());
  size_t k = 0;  // index into `back`
  for (size_t i = 0; i < from.size(); ++i) {
    if (status[i] == 0) continue;
    const size_t j = k++;
    // Scaled pixel coordinates x of the flow image are full-resolution
    // (x + 0.5) / s in the project's convention.
    const Eigen::Vector2d q((to[i].x + 0.5) / fsx, (to[i].y + 0.5) / fsy);
    // Kept off the edge band for the same reason as the corners: a window
    // reaching past frame t's edge biases the track.
    if (!q.allFinite() || q.x() < edge_px || q.y() < edge_px || q.x() > width - edge_px ||
        q.y() > height - edge_px) {
      continue;
    }
    if (backward) {
      if (back_status[j] == 0) continue;
      const double ex = (back[j].x - from[i].x) / fsx;
      const double ey = (back[j].y - from[i].y) / fsy;
      if (!(std::hypot(ex, ey) <= options.forward_backward_px)) continue;
    }
    tracks.push_back({.p = starts[i], .q = q});
  }
  return tracks;
}

std::optional<SimilarityMotion> EstimateSimilarityRansac(std::span<const PointTrack> tracks,
                                                         const RansacOptions& options) {
  options.Validate();
  std::vector<cv::Point2d> from, to;
  from.reserve(tracks.size());
  to.reserve(tracks.size());
  for (const PointTrack& t : tracks) {
    if (!t.p.allFinite() || !t.q.allFinite()) continue;
    from.emplace_back(t.p.x(), t.p.y());
    to.emplace_back(t.q.x(), t.q.y());
  }
  if (from.size() < 3) return std::nullopt;
  std::vector<uint8_t> inliers;
  // [a -b tx; b a ty] with a = s cos(theta), b = s sin(theta).
  const cv::Mat m =
      cv::estimateAffinePartial2D(from, to, inliers, cv::RANSAC, options.threshold_px,
                                  static_cast<size_t>(options.max_iterations), options.confidence,
                                  static_cast<size_t>(options.refine_iterations));
  if (m.empty()) return std::nullopt;
  const double a = m.at<double>(0, 0);
  const double b = m.at<double>(1, 0);
  const double scale = std::hypot(a, b);
  const SimilarityMotion s{.tx_px = m.at<double>(0, 2),
                           .ty_px = m.at<double>(1, 2),
                           .log_scale = std::log(scale),
                           .rotation_rad = std::atan2(b, a)};
  if (!(scale > 0.0) || !std::isfinite(s.tx_px) || !std::isfinite(s.ty_px) ||
      !std::isfinite(s.log_scale)) {
    return std::nullopt;
  }
  return s;
}

}  // namespace hcpf::vision
