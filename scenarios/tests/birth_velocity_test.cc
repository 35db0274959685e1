// tracker.management.birth_velocity: ground_truth against the camera's motion
// (camera_motion_pass.h, GroundTruthBirthVelocity).

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "../src/camera_motion_pass.h"
#include "hcpf/core/ground_truth.h"
#include "hcpf/scenarios/scenario.h"

namespace hcpf::scenarios {
namespace {

const std::string kClimb =
    std::string(HCPF_SOURCE_DIR) + "/scenarios/library/thesis/ch11-single-climb.yaml";

Eigen::Vector2d Centre(const FrameGroundTruth& gt, ObjectId id) {
  for (const GroundTruthObject& o : gt.objects) {
    if (o.id == id) return {o.amodal_box.centre_x(), o.amodal_box.centre_y()};
  }
  ADD_FAILURE() << "no such target";
  return Eigen::Vector2d::Zero();
}

// Born with the camera's motion applied (the climbing camera of ch11: the
// image shrinks by about 0.7 % a frame), the filter's next prediction carries
// its centre by the frame-to-frame motion and adds its velocity turned by
// that motion's linear part (sR v): it lands on the truth's next centre. The
// velocity was the displacement in the next frame's pixels, so it moved by
// sR times it (a review: a one-off error of the scale and rotation).
TEST(GroundTruthBirthVelocity, TurnedByTheCamerasMotionItReachesTheNextCentre) {
  const Scenario climb = LoadScenarioFile(kClimb);
  ASSERT_NE(climb.tracker.camera_motion, tracker::CameraMotionMode::kNone);
  const int frame = 60;
  const FrameGroundTruth now = ComputeGroundTruth(climb.world, frame);
  const FrameGroundTruth next = ComputeGroundTruth(climb.world, frame + 1);
  ASSERT_FALSE(now.objects.empty());
  const ObjectId id = now.objects.front().id;
  const Eigen::Matrix3d h = next.image_from_ground * now.image_from_ground.inverse();
  const SimilarityMotion m =
      internal::BestSimilarity(h, climb.world.camera.width_px, climb.world.camera.height_px);
  ASSERT_GT(std::abs(m.log_scale), 1e-3);  // the camera's motion is not the identity
  const Eigen::Vector2d before = Centre(now, id);
  const Eigen::Vector3d carried = h * Eigen::Vector3d(before.x(), before.y(), 1.0);
  const Eigen::Vector2d v = internal::GroundTruthBirthVelocity(climb, frame, id);
  const Eigen::Vector2d turned = std::exp(m.log_scale) * (Eigen::Rotation2Dd(m.rotation_rad) * v);
  const Eigen::Vector2d predicted = carried.head<2>() / carried.z() + turned;
  EXPECT_LT((predicted - Centre(next, id)).norm(), 1e-9) << v.transpose();

  // Without the camera's motion applied the velocity is the image
  // displacement itself.
  const Scenario plain = LoadScenarioFile(kClimb, {ParseOverride("tracker.camera_motion=none")});
  const Eigen::Vector2d raw = internal::GroundTruthBirthVelocity(plain, frame, id);
  EXPECT_LT((raw - (Centre(next, id) - before)).norm(), 1e-12);
}

}  // namespace
}  // namespace hcpf::scenarios
