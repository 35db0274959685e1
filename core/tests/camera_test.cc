#include "hcpf/core/camera.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "hcpf/core/rng.h"

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

// A camera 100 m up looking at a ground point `tilt_deg` from below it, the
// camera displaced towards compass heading `heading_deg` (0 = north, 90 =
// east), so the view leans the other way.
CameraPose Tilted(double tilt_deg, double heading_deg) {
  const double t = tilt_deg * std::numbers::pi / 180.0, h = heading_deg * std::numbers::pi / 180.0;
  const double r = 100.0 * std::tan(t);
  return CameraPose::LookAt({r * std::sin(h), r * std::cos(h), 100.0}, {0, 0, 0});
}

double DegreesBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::acos(std::clamp(a.normalized().dot(b.normalized()), -1.0, 1.0)) * 180.0 /
         std::numbers::pi;
}

TEST(CameraPose, ImageUpIsLevelAwayFromVerticalAndNorthNearIt) {
  for (double heading = 0.0; heading < 360.0; heading += 15.0) {
    // More than 8.1 degrees from vertical: a level horizon (right axis
    // horizontal), as before 2026-12-07.
    for (const double tilt : {8.2, 21.0, 45.0, 89.0}) {
      EXPECT_EQ(Tilted(tilt, heading).world_from_camera.col(0).z(), 0.0) << heading;
    }
    // Within 2 degrees: north is up, as at the nadir.
    for (const double tilt : {0.0, 1.0, 1.99}) {
      const CameraPose p = Tilted(tilt, heading);
      const Eigen::Vector3d f = p.world_from_camera.col(2);
      EXPECT_LT(
          (p.world_from_camera.col(0) - f.cross(Eigen::Vector3d::UnitY()).normalized()).norm(),
          1e-12)
          << heading << " " << tilt;
    }
  }
}

TEST(CameraPose, ImageTurnsContinuouslyAsTheViewNearsVertical) {
  // Paths from 12 to 0.5 degrees off vertical in steps of 0.01 degrees, from
  // every side at least 20 degrees of heading from the one direction no rule
  // can make smooth (the camera north of its target, the view leaning south,
  // ~6 degrees off vertical). Until 2026-12-07 "up" switched from +z to +y
  // at 8 degrees, and the image turned at once by about the heading's angle
  // from south (0.74 degrees on climb, 20 to 180 degrees on these paths).
  double worst = 0.0;
  for (double heading = 20.0; heading <= 340.0; heading += 5.0) {
    Eigen::Vector3d previous = Tilted(12.0, heading).world_from_camera.col(0);
    for (double tilt = 12.0 - 0.01; tilt > 0.5; tilt -= 0.01) {
      const Eigen::Vector3d right = Tilted(tilt, heading).world_from_camera.col(0);
      worst = std::max(worst, DegreesBetween(previous, right));
      previous = right;
    }
  }
  // The turn spreads over the band from 8 to 2 degrees and gathers towards
  // the singular direction (a path passing it closer turns faster: 0.33
  // degrees a step at 90 degrees of heading from it, 1.9 at 20, 7.5 at 5; a
  // rule from the view alone cannot avoid it). 2.5 degrees bounds the paths
  // tried; the old switch made 20 at least.
  EXPECT_LT(worst, 2.5);
  // At the singular view itself (the two right axes' blend 1e-12 long: a
  // review found this view), a rotation all the same.
  const Eigen::Vector3d singular(0.0, -0.10286415480173679, -0.99469541350954482);
  const Eigen::Matrix3d r = CameraPose::LookAt({0, 0, 0}, 100.0 * singular).world_from_camera;
  EXPECT_LT((r.transpose() * r - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
}

// Outside the band the rule is the level one, and inside 2 degrees the north
// one, as computed before 2026-12-07, to the bit (so no scene outside the
// band changed).
TEST(CameraPose, OutsideTheBandThePoseIsTheOldRulesToTheBit) {
  const auto old_rule = [](const Eigen::Vector3d& position, const Eigen::Vector3d& target) {
    const Eigen::Vector3d forward = (target - position).normalized();
    const Eigen::Vector3d hint =
        std::abs(forward.z()) > 0.990 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitZ();
    return forward.cross(hint).normalized();
  };
  Rng rng(17);
  int outside = 0;
  for (int k = 0; k < 20000; ++k) {
    const Eigen::Vector3d position(rng.Uniform(-200, 200), rng.Uniform(-200, 200),
                                   rng.Uniform(1, 400));
    const Eigen::Vector3d target(rng.Uniform(-50, 50), rng.Uniform(-50, 50), rng.Uniform(-5, 5));
    const double c = std::abs((target - position).normalized().z());
    if (c > 0.990 && c < 0.99939082701909576) continue;  // the band
    ++outside;
    ASSERT_EQ(CameraPose::LookAt(position, target).world_from_camera.col(0),
              old_rule(position, target))
        << k;
  }
  EXPECT_GT(outside, 15000);
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
