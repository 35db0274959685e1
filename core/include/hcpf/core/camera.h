#pragma once
// Pinhole camera model shared by the world model, the renderer and the writers.
//
// Conventions (documented in docs/conventions.md):
// - World frame: x east, y north, z up, metres. The ground is the terrain
//   height field (z = Terrain::HeightAt(x, y)).
// - Camera frame (OpenCV): x right, y down, z forward (viewing direction).
// - Pixels: (u, v) with pixel (0,0) covering [0,1)x[0,1); the optical centre of
//   a W x H image is (W/2, H/2) before shake.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>

namespace hcpf {

struct CameraIntrinsics {
  int width_px = 0;
  int height_px = 0;
  double fx_px = 0.0;
  double fy_px = 0.0;
  double cx_px = 0.0;
  double cy_px = 0.0;

  // Square pixels, horizontal field of view `hfov_deg`, optical centre at the
  // image centre.
  static CameraIntrinsics FromHorizontalFov(int width_px, int height_px, double hfov_deg);
  Eigen::Matrix3d K() const;
  friend bool operator==(const CameraIntrinsics&, const CameraIntrinsics&) = default;
};

// Camera pose: where the camera is and how it is turned.
struct CameraPose {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  // Rotation taking camera-frame vectors to world-frame vectors; columns are
  // the camera's right, down and forward axes expressed in the world.
  Eigen::Matrix3d world_from_camera = Eigen::Matrix3d::Identity();

  // Camera looking from `position` at `target`. Image "up" is world +z more
  // than 8.1 degrees from vertical, world +y (north) within 2 degrees of it,
  // and between them a smooth blend of the two (docs/scenario.md).
  static CameraPose LookAt(const Eigen::Vector3d& position, const Eigen::Vector3d& target);
  Eigen::Matrix3d camera_from_world() const { return world_from_camera.transpose(); }
};

struct CameraState {
  CameraIntrinsics intrinsics;
  CameraPose pose;

  // Camera-frame coordinates of a world point.
  Eigen::Vector3d ToCamera(const Eigen::Vector3d& world_m) const;
  // Pixel of a world point, or nullopt when it is not in front of the camera
  // (depth <= `min_depth_m`).
  std::optional<Eigen::Vector2d> Project(const Eigen::Vector3d& world_m,
                                         double min_depth_m = 1e-3) const;
  // World-frame direction of the ray through pixel (u, v) (not normalised).
  Eigen::Vector3d RayDirection(double u_px, double v_px) const;
  // Homography taking ground-plane points (x, y, 1) at height `ground_z_m` to
  // homogeneous pixels: H = K [r1 r2 (r3*z + t)] with [R|t] = camera_from_world.
  Eigen::Matrix3d ImageFromGround(double ground_z_m = 0.0) const;
};

}  // namespace hcpf
