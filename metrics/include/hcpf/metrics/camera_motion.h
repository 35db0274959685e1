#pragma once
// Camera-motion error of the hierarchical filter's scene level (DESIGN.md,
// "Metrics": the scene filter's camera-motion error against the ground-truth
// frame-to-frame homography, as the mean displacement of the image corners).
// docs/metrics.md gives the definitions.

#include <Eigen/Core>
#include <span>

#include "hcpf/core/similarity_motion.h"

namespace hcpf::metrics {

// Mean over the four image corners c = (0, 0), (width, 0), (width, height),
// (0, height) of |S(c) - H(c)|, px, where S is `estimate` (similarity_motion.h:
// exp(log_scale) R(rotation) c + t) and H(c) = (H (c, 1))_xy / (H (c, 1))_z is
// the true frame-to-frame homography (frame t-1 pixels to frame t pixels).
// Throws hcpf::InputError when width or height < 1 or when H maps a corner to
// a non-positive or non-finite homogeneous z.
double CornerDisplacementPx(const SimilarityMotion& estimate,
                            const Eigen::Matrix3d& true_frame_to_frame, int width, int height);

// The similarity with the lowest CornerDisplacementPx against
// `true_frame_to_frame`: the floor of the camera-motion error for any
// estimator whose motion model is a similarity (the rest is the homography's
// perspective part). Minimising a sum of Euclidean norms of residuals that are
// affine in (a, b) of c' = a c + b (complex form, a = exp(log_scale)
// e^{i rotation}) is convex, so iteratively reweighted least squares
// (Weiszfeld's iteration) from the corners' least-squares fit reaches the
// global minimum; it stops when an iteration lowers the mean by less than
// 1e-13 px, or after 500 iterations. Same errors as CornerDisplacementPx.
SimilarityMotion CornerOptimalSimilarity(const Eigen::Matrix3d& true_frame_to_frame, int width,
                                         int height);

// Summary of per-frame camera-motion errors (px).
struct CameraMotionErrorSummary {
  // Values summarised; 0: nothing was measured, every statistic below is 0
  // here and null in metrics.json (RunMetricsToJson).
  int frames = 0;
  double mean_px = 0.0;
  double median_px = 0.0;
  // The 95th percentile, linear interpolation between closest ranks: with the
  // values sorted v_0 <= ... <= v_{n-1}, position 0.95 (n - 1) (numpy's default).
  double p95_px = 0.0;
  double max_px = 0.0;
  friend bool operator==(const CameraMotionErrorSummary&,
                         const CameraMotionErrorSummary&) = default;
};

// Summarises per-frame errors (any order). Throws hcpf::InputError on a
// negative or non-finite value. The median is the same interpolation at 0.5.
CameraMotionErrorSummary SummariseCameraMotionError(std::span<const double> per_frame_px);

}  // namespace hcpf::metrics
