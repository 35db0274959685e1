#include "hcpf/core/camera.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "hcpf/core/check.h"

namespace hcpf {

CameraIntrinsics CameraIntrinsics::FromHorizontalFov(int width_px, int height_px, double hfov_deg) {
  HCPF_CHECK(width_px > 0 && height_px > 0 && hfov_deg > 0.0 && hfov_deg < 180.0);
  CameraIntrinsics k;
  k.width_px = width_px;
  k.height_px = height_px;
  k.fx_px = 0.5 * width_px / std::tan(0.5 * hfov_deg * std::numbers::pi / 180.0);
  k.fy_px = k.fx_px;
  k.cx_px = 0.5 * width_px;
  k.cy_px = 0.5 * height_px;
  return k;
}

Eigen::Matrix3d CameraIntrinsics::K() const {
  Eigen::Matrix3d k;
  k << fx_px, 0.0, cx_px, 0.0, fy_px, cy_px, 0.0, 0.0, 1.0;
  return k;
}

CameraPose CameraPose::LookAt(const Eigen::Vector3d& position, const Eigen::Vector3d& target) {
  const Eigen::Vector3d forward_raw = target - position;
  HCPF_CHECK(forward_raw.norm() > 1e-9) << "camera position equals look-at point";
  const Eigen::Vector3d forward = forward_raw.normalized();
  // The image's "up" is world +z (a level horizon) more than 8 degrees from
  // vertical and north (+y) within 2 degrees of it, where +z says nothing;
  // between, the right axis moves smoothly from the one to the other, so the
  // image turns continuously as a path crosses the band (until 2026-12-07 it
  // switched at 8 degrees and turned at once: by 0.74 degrees on climb, by up
  // to 180 degrees elsewhere). No rule from the view direction alone can be
  // smooth everywhere (a tangent field on the sphere has a zero): two views
  // are left in the band, where the two right axes are opposite and weigh
  // the same, both in the y-z plane: 5.9 degrees south of straight down (the
  // camera north of what it looks at) and 5.9 degrees north of straight up.
  constexpr double kOuter = 0.990;                // cos(8.1 deg)
  constexpr double kInner = 0.99939082701909576;  // cos(2 deg)
  const double t = std::clamp((std::abs(forward.z()) - kOuter) / (kInner - kOuter), 0.0, 1.0);
  const double w = t * t * (3.0 - 2.0 * t);
  const Eigen::Vector3d north_right = forward.cross(Eigen::Vector3d::UnitY()).normalized();
  Eigen::Vector3d right = north_right;
  if (w <= 0.0) {
    // Outside the band: the level rule alone, as before to the bit.
    right = forward.cross(Eigen::Vector3d::UnitZ()).normalized();
  } else if (w < 1.0) {
    // Each right axis at unit length: the level one is short near vertical,
    // and blended as it is would take over late and fast.
    right = (1.0 - w) * forward.cross(Eigen::Vector3d::UnitZ()).normalized() + w * north_right;
    if (right.norm() < 1e-12) right = north_right;
    right.normalize();
  }
  const Eigen::Vector3d down = forward.cross(right);
  CameraPose pose;
  pose.position_m = position;
  pose.world_from_camera.col(0) = right;
  pose.world_from_camera.col(1) = down;
  pose.world_from_camera.col(2) = forward;
  return pose;
}

Eigen::Vector3d CameraState::ToCamera(const Eigen::Vector3d& world_m) const {
  return pose.camera_from_world() * (world_m - pose.position_m);
}

std::optional<Eigen::Vector2d> CameraState::Project(const Eigen::Vector3d& world_m,
                                                    double min_depth_m) const {
  const Eigen::Vector3d c = ToCamera(world_m);
  if (c.z() <= min_depth_m) return std::nullopt;
  return Eigen::Vector2d(intrinsics.fx_px * c.x() / c.z() + intrinsics.cx_px,
                         intrinsics.fy_px * c.y() / c.z() + intrinsics.cy_px);
}

Eigen::Vector3d CameraState::RayDirection(double u_px, double v_px) const {
  const Eigen::Vector3d c((u_px - intrinsics.cx_px) / intrinsics.fx_px,
                          (v_px - intrinsics.cy_px) / intrinsics.fy_px, 1.0);
  return pose.world_from_camera * c;
}

Eigen::Matrix3d CameraState::ImageFromGround(double ground_z_m) const {
  const Eigen::Matrix3d r = pose.camera_from_world();
  const Eigen::Vector3d t = -r * pose.position_m;
  Eigen::Matrix3d m;
  m.col(0) = r.col(0);
  m.col(1) = r.col(1);
  m.col(2) = r.col(2) * ground_z_m + t;
  return intrinsics.K() * m;
}

}  // namespace hcpf
