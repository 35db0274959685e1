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
  // Weighted least squares of q = a p + b (closed form, complex regression).
  const auto fit = [&](const std::array<double, 4>& weight, Complex& a, Complex& b) {
    double total = 0.0;
    Complex pm = 0.0, qm = 0.0;
    for (size_t i = 0; i < 4; ++i) {
      total += weight[i];
      pm += weight[i] * p[i];
      qm += weight[i] * q[i];
    }
    pm /= total;
    qm /= total;
    Complex num = 0.0;
    double den = 0.0;
    for (size_t i = 0; i < 4; ++i) {
      num += weight[i] * (q[i] - qm) * std::conj(p[i] - pm);
      den += weight[i] * std::norm(p[i] - pm);
    }
    a = num / den;
    b = qm - a * pm;
  };
  const auto mean_distance = [&](Complex a, Complex b) {
    double sum = 0.0;
    for (size_t i = 0; i < 4; ++i) sum += std::abs(a * p[i] + b - q[i]);
    return sum / 4.0;
  };
  std::array<double, 4> weight = {1.0, 1.0, 1.0, 1.0};
  Complex a, b;
  fit(weight, a, b);
  double best = mean_distance(a, b);
  for (int iteration = 0; iteration < 500 && best > 0.0; ++iteration) {
    // Weiszfeld: weights 1 / residual, floored so an exactly met corner
    // does not divide by zero.
    for (size_t i = 0; i < 4; ++i) weight[i] = 1.0 / std::max(std::abs(a * p[i] + b - q[i]), 1e-12);
    Complex a2, b2;
    fit(weight, a2, b2);
    const double next = mean_distance(a2, b2);
    if (!(next < best - 1e-13)) {
      if (next < best) a = a2, b = b2, best = next;
      break;
    }
    a = a2;
    b = b2;
    best = next;
  }
  return {.tx_px = b.real(),
          .ty_px = b.imag(),
          .log_scale = std::log(std::abs(a)),
          .rotation_rad = std::arg(a)};
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
