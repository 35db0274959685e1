#include "hcpf/metrics/camera_motion.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <complex>
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
    sum += (Apply(estimate, c) - Eigen::Vector2d(t.x() / t.z(), t.y() / t.z())).norm();
  }
  return sum / 4.0;
}

SimilarityMotion CornerOptimalSimilarity(const Eigen::Matrix3d& true_frame_to_frame, int width,
                                         int height) {
  // Validates the size and the homography (throws as documented).
  CornerDisplacementPx(SimilarityMotion{}, true_frame_to_frame, width, height);
  using Complex = std::complex<double>;
  const double w = width;
  const double h = height;
  const std::array<Complex, 4> p = {Complex(0, 0), Complex(w, 0), Complex(w, h), Complex(0, h)};
  std::array<Complex, 4> q;
  for (size_t i = 0; i < 4; ++i) {
    const Eigen::Vector3d t = true_frame_to_frame * Eigen::Vector3d(p[i].real(), p[i].imag(), 1.0);
    q[i] = Complex(t.x() / t.z(), t.y() / t.z());
  }
  const auto mean_distance = [&](const ComplexSimilarity& s) {
    double sum = 0.0;
    for (size_t i = 0; i < 4; ++i) sum += std::abs(s.a * p[i] + s.b - q[i]);
    return sum / 4.0;
  };
  std::array<double, 4> weight = {1.0, 1.0, 1.0, 1.0};
  ComplexSimilarity best = FitComplexSimilarity(p, q, weight);
  double best_mean = mean_distance(best);
  for (int iteration = 0; iteration < 500 && best_mean > 0.0; ++iteration) {
    // Weiszfeld: weights 1 / residual, floored so an exactly met corner
    // does not divide by zero.
    for (size_t i = 0; i < 4; ++i) {
      weight[i] = 1.0 / std::max(std::abs(best.a * p[i] + best.b - q[i]), 1e-12);
    }
    const ComplexSimilarity next = FitComplexSimilarity(p, q, weight);
    const double next_mean = mean_distance(next);
    if (!(next_mean < best_mean - 1e-13)) {
      if (next_mean < best_mean) best = next, best_mean = next_mean;
      break;
    }
    best = next;
    best_mean = next_mean;
  }
  return best.motion();
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
