#include "hcpf/core/camera.h"

#include <gtest/gtest.h>

namespace hcpf {
namespace {

CameraState Nadir(double altitude_m, double hfov_deg) {
  CameraState c;
  c.intrinsics = CameraIntrinsics::FromHorizontalFov(640, 480, hfov_deg);
  c.pose = CameraPose::LookAt({0, 0, altitude_m}, {0, 0, 0});
  return c;
}

TEST(CameraIntrinsics, FocalLengthFromFieldOfView) {
  // hfov 90 deg: f = (W/2) / tan(45 deg) = 320.
  const auto k = CameraIntrinsics::FromHorizontalFov(640, 480, 90.0);
  EXPECT_NEAR(k.fx_px, 320.0, 1e-9);
  EXPECT_NEAR(k.fy_px, 320.0, 1e-9);
  EXPECT_DOUBLE_EQ(k.cx_px, 320.0);
  EXPECT_DOUBLE_EQ(k.cy_px, 240.0);
}

TEST(CameraState, NadirProjectionHandComputed) {
  const CameraState c = Nadir(100.0, 90.0);
  // 10 m east at 100 m depth: u = 320 * 10/100 + 320 = 352, v = 240.
  auto p = c.Project({10, 0, 0});
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->x(), 352.0, 1e-9);
  EXPECT_NEAR(p->y(), 240.0, 1e-9);
  // 10 m north appears above the centre (image up = north): v = 240 - 32.
  p = c.Project({0, 10, 0});
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->x(), 320.0, 1e-9);
  EXPECT_NEAR(p->y(), 208.0, 1e-9);
  // Behind the camera: no projection.
  EXPECT_FALSE(c.Project({0, 0, 200}));
}

TEST(CameraState, ObliqueViewKeepsWorldUpAsImageUp) {
  CameraState c;
  c.intrinsics = CameraIntrinsics::FromHorizontalFov(640, 480, 90.0);
  c.pose = CameraPose::LookAt({0, -100, 0}, {0, 0, 0});  // horizontal, looking north
  // A point 10 m above the look-at point, 100 m ahead: v = 240 - 320*10/100.
  const auto p = c.Project({0, 0, 10});
  ASSERT_TRUE(p);
  EXPECT_NEAR(p->y(), 208.0, 1e-9);
  // East is to the right.
  EXPECT_GT(c.Project({10, 0, 0})->x(), 320.0);
}

TEST(CameraState, GroundHomographyMatchesProjection) {
  CameraState c;
  c.intrinsics = CameraIntrinsics::FromHorizontalFov(640, 480, 50.0);
  c.intrinsics.cx_px += 1.7;  // shake moves the optical centre
  c.pose = CameraPose::LookAt({13, -40, 120}, {5, 3, 0});
  const Eigen::Matrix3d h = c.ImageFromGround(0.0);
  for (const Eigen::Vector2d& g :
       {Eigen::Vector2d(0, 0), Eigen::Vector2d(12, -7), Eigen::Vector2d(-30, 25)}) {
    const Eigen::Vector3d q = h * Eigen::Vector3d(g.x(), g.y(), 1.0);
    const auto p = c.Project({g.x(), g.y(), 0.0});
    ASSERT_TRUE(p);
    EXPECT_NEAR(q.x() / q.z(), p->x(), 1e-9);
    EXPECT_NEAR(q.y() / q.z(), p->y(), 1e-9);
  }
}

TEST(CameraState, RayThroughProjectionHitsThePoint) {
  const CameraState c = Nadir(80.0, 60.0);
  const Eigen::Vector3d point(7, -3, 0);
  const auto p = c.Project(point);
  const Eigen::Vector3d dir = c.RayDirection(p->x(), p->y());
  const Eigen::Vector3d to_point = point - c.pose.position_m;
  EXPECT_NEAR(dir.normalized().dot(to_point.normalized()), 1.0, 1e-12);
}

}  // namespace
}  // namespace hcpf
