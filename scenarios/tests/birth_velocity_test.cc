// tracker.management.birth_velocity: ground_truth against the camera's motion
// (camera_motion_pass.h, GroundTruthBirthVelocity).

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "../src/camera_motion_pass.h"
#include "hcpf/core/ground_truth.h"
#include "hcpf/scenarios/scenario.h"
#include "hcpf/tracker/dynamics.h"
#include "hcpf/tracker/particle_set.h"

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
// image shrinks by about 0.7 % a frame), the filter's first prediction
// without noise (tracker::ApplyCameraMotion with the similarity
// camera_motion: oracle applies, then the constant-velocity step) lands on
// the truth's next centre. The velocity was the displacement less the
// homography's transfer, in the next frame's pixels: the particle moved by sR
// times it from S(x), 0.056 px off here (a review found the first version,
// taken back through sR but still from the homography, no closer).
TEST(GroundTruthBirthVelocity, TheFirstPredictionLandsOnTheNextCentre) {
  const Scenario climb = LoadScenarioFile(kClimb);
  ASSERT_NE(climb.tracker.camera_motion, tracker::CameraMotionMode::kNone);
  for (const int frame : {1, 60, 120}) {
    const FrameGroundTruth now = ComputeGroundTruth(climb.world, frame);
    const FrameGroundTruth next = ComputeGroundTruth(climb.world, frame + 1);
    ASSERT_FALSE(now.objects.empty());
    const ObjectId id = now.objects.front().id;
    const SimilarityMotion m =
        internal::BestSimilarity(next.image_from_ground * now.image_from_ground.inverse(),
                                 climb.world.camera.width_px, climb.world.camera.height_px);
    ASSERT_GT(std::abs(m.log_scale), 1e-3);  // the camera's motion is not the identity
    const Eigen::Vector2d v = internal::GroundTruthBirthVelocity(climb, frame, id);
    tracker::ParticleSet set;
    set.Resize(1);
    const Eigen::Vector2d before = Centre(now, id);
    set.px[0] = before.x();
    set.py[0] = before.y();
    set.vx[0] = v.x();
    set.vy[0] = v.y();
    set.s[0] = 1.0;
    tracker::ApplyCameraMotion(m, set);
    const Eigen::Vector2d predicted(set.px[0] + set.vx[0], set.py[0] + set.vy[0]);
    EXPECT_LT((predicted - Centre(next, id)).norm(), 1e-9) << "frame " << frame;
  }

  // Without the camera's motion applied the velocity is the image
  // displacement itself.
  const Scenario plain = LoadScenarioFile(kClimb, {ParseOverride("tracker.camera_motion=none")});
  const FrameGroundTruth now = ComputeGroundTruth(plain.world, 60);
  const ObjectId id = now.objects.front().id;
  const Eigen::Vector2d raw = internal::GroundTruthBirthVelocity(plain, 60, id);
  EXPECT_LT((raw - (Centre(ComputeGroundTruth(plain.world, 61), id) - Centre(now, id))).norm(),
            1e-12);
}

}  // namespace
}  // namespace hcpf::scenarios
