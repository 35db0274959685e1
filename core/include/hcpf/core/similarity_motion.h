#pragma once
// Frame-to-frame camera motion, shared by the tracker (which applies it to
// particles), the scene-motion estimators that produce it, and the metrics
// that score it.

#include <Eigen/Core>
#include <cmath>
#include <complex>
#include <span>

namespace hcpf {

// Frame-to-frame camera motion as a 2-D similarity of image coordinates:
//   p' = exp(log_scale) * R(rotation_rad) * p + (tx_px, ty_px)
// (rotation about the image origin, counter-clockwise in x-right/y-down pixel
// coordinates means clockwise on screen; any other centre c is expressed by
// choosing t = c - sR c + t_c).
struct SimilarityMotion {
  double tx_px = 0.0;
  double ty_px = 0.0;
  double log_scale = 0.0;
  double rotation_rad = 0.0;
  friend bool operator==(const SimilarityMotion&, const SimilarityMotion&) = default;
};

// Maps a point by a similarity: exp(log_scale) R(rotation) p + t.
inline Eigen::Vector2d Apply(const SimilarityMotion& motion, const Eigen::Vector2d& p) {
  const double scale = std::exp(motion.log_scale);
  const double a = scale * std::cos(motion.rotation_rad);
  const double b = scale * std::sin(motion.rotation_rad);
  return {a * p.x() - b * p.y() + motion.tx_px, b * p.x() + a * p.y() + motion.ty_px};
}

// A similarity in complex form, p' = a p + b with a = exp(log_scale)
// e^{i rotation} and b = tx + i ty (points as x + i y).
struct ComplexSimilarity {
  std::complex<double> a = 1.0;
  std::complex<double> b = 0.0;
  SimilarityMotion motion() const {
    return {.tx_px = b.real(),
            .ty_px = b.imag(),
            .log_scale = std::log(std::abs(a)),
            .rotation_rad = std::arg(a)};
  }
};

// The weighted least-squares similarity q_i ~ a p_i + b (closed form: with
// weighted means p_m, q_m, a = sum w (q - q_m) conj(p - p_m) / sum w |p - p_m|^2
// and b = q_m - a p_m). Empty `weights`: all 1. p and q (and weights) have
// the same size; at least two distinct p with non-zero weight, else a is not
// finite.
inline ComplexSimilarity FitComplexSimilarity(std::span<const std::complex<double>> p,
                                              std::span<const std::complex<double>> q,
                                              std::span<const double> weights = {}) {
  const auto w = [&](size_t i) { return weights.empty() ? 1.0 : weights[i]; };
  double total = 0.0;
  std::complex<double> pm = 0.0, qm = 0.0;
  for (size_t i = 0; i < p.size(); ++i) {
    total += w(i);
    pm += w(i) * p[i];
    qm += w(i) * q[i];
  }
  pm /= total;
  qm /= total;
  std::complex<double> num = 0.0;
  double den = 0.0;
  for (size_t i = 0; i < p.size(); ++i) {
    num += w(i) * (q[i] - qm) * std::conj(p[i] - pm);
    den += w(i) * std::norm(p[i] - pm);
  }
  ComplexSimilarity fit;
  fit.a = num / den;
  fit.b = qm - fit.a * pm;
  return fit;
}

// One point correspondence between consecutive frames: p in frame t-1, q in
// frame t (pixels). vision/ produces them from images (corner tracks), the
// run pipeline simulates them at detection level, the scene filter and the
// RANSAC baseline read them.
struct PointTrack {
  Eigen::Vector2d p = Eigen::Vector2d::Zero();
  Eigen::Vector2d q = Eigen::Vector2d::Zero();
};

}  // namespace hcpf
