#pragma once
// Frame-to-frame camera motion, shared by the tracker (which applies it to
// particles), the scene-motion estimators that produce it, and the metrics
// that score it.

#include <Eigen/Core>
#include <cmath>

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

// One point correspondence between consecutive frames: p in frame t-1, q in
// frame t (pixels). vision/ produces them from images (corner tracks), the
// run pipeline simulates them at detection level, the scene filter and the
// RANSAC baseline read them.
struct PointTrack {
  Eigen::Vector2d p = Eigen::Vector2d::Zero();
  Eigen::Vector2d q = Eigen::Vector2d::Zero();
};

}  // namespace hcpf
