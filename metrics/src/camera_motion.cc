#include "hcpf/metrics/camera_motion.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "hcpf/core/error.h"

namespace hcpf::metrics {
namespace {

// Linear interpolation between closest ranks of sorted values at q in [0, 1].
double Quantile(const std::vector<double>& sorted, double q) {
  const double position = q * static_cast<double>(sorted.size() - 1);
  const auto lo = static_cast<size_t>(std::floor(position));
  const size_t hi = std::min(lo + 1, sorted.size() - 1);
  const double fraction = position - static_cast<double>(lo);
  return sorted[lo] + fraction * (sorted[hi] - sorted[lo]);
}

}  // namespace

double CornerDisplacementPx(const SimilarityMotion& estimate,
                            const Eigen::Matrix3d& true_frame_to_frame, int width, int height) {
  if (width < 1 || height < 1) {
    throw InputError(fmt::format(
        "camera-motion error: image size must be at least 1 x 1, got {} x {}", width, height));
  }
  const double scale = std::exp(estimate.log_scale);
  const double a = scale * std::cos(estimate.rotation_rad);
  const double b = scale * std::sin(estimate.rotation_rad);
  const double w = width;
  const double h = height;
  double sum = 0.0;
  for (const Eigen::Vector2d& c : {Eigen::Vector2d(0, 0), Eigen::Vector2d(w, 0),
                                   Eigen::Vector2d(w, h), Eigen::Vector2d(0, h)}) {
    const Eigen::Vector3d t = true_frame_to_frame * Eigen::Vector3d(c.x(), c.y(), 1.0);
    if (!(t.z() > 0.0) || !t.allFinite()) {
      throw InputError(fmt::format(
          "camera-motion error: the true homography maps corner ({}, {}) to homogeneous z = {}, "
          "expected a positive number",
          c.x(), c.y(), t.z()));
    }
    const Eigen::Vector2d s(a * c.x() - b * c.y() + estimate.tx_px,
                            b * c.x() + a * c.y() + estimate.ty_px);
    sum += (s - Eigen::Vector2d(t.x() / t.z(), t.y() / t.z())).norm();
  }
  return sum / 4.0;
}

CameraMotionErrorSummary SummariseCameraMotionError(std::span<const double> per_frame_px) {
  CameraMotionErrorSummary summary;
  if (per_frame_px.empty()) return summary;
  std::vector<double> sorted(per_frame_px.begin(), per_frame_px.end());
  for (const double v : sorted) {
    if (!std::isfinite(v) || v < 0.0) {
      throw InputError(
          fmt::format("camera-motion error: per-frame errors must be finite and >= 0, got {}", v));
    }
  }
  std::sort(sorted.begin(), sorted.end());
  double sum = 0.0;
  for (const double v : sorted) sum += v;
  summary.frames = static_cast<int>(sorted.size());
  summary.mean_px = sum / static_cast<double>(sorted.size());
  summary.median_px = Quantile(sorted, 0.5);
  summary.p95_px = Quantile(sorted, 0.95);
  summary.max_px = sorted.back();
  return summary;
}

}  // namespace hcpf::metrics
