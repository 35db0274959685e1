#include "hcpf/scenarios/observation_simulator.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

namespace hcpf::scenarios {
namespace {

FrameGroundTruth TwoTargets() {
  FrameGroundTruth gt;
  gt.frame = 3;
  gt.camera.intrinsics = CameraIntrinsics::FromHorizontalFov(320, 240, 40.0);
  GroundTruthObject a;
  a.id = ObjectId{1};
  a.in_frame = true;
  a.amodal_box = {100, 100, 20, 10};
  a.visible_fraction = 1.0;
  GroundTruthObject b = a;
  b.id = ObjectId{2};
  b.amodal_box = {200, 50, 30, 12};
  b.visible_fraction = 0.5;
  gt.objects = {a, b};
  return gt;
}

TEST(SimulateObservation, NoiselessPerfectDetectorReturnsTheBoxes) {
  SimulatedObservationOptions o;
  o.sigma_px = 0.0;
  o.size_sigma = 0.0;
  o.p_detect = 1.0;
  o.visibility_exponent = 0.0;  // p independent of visibility
  o.clutter_per_frame = 0.0;
  o.strength = {{2, 0.4}};
  const Observation obs = SimulateObservation(TwoTargets(), o, 1);
  ASSERT_EQ(obs.detections.size(), 2u);
  EXPECT_EQ(obs.frame, 3);
  EXPECT_EQ(obs.detections[0].box, (BoxPx{100, 100, 20, 10}));
  EXPECT_EQ(obs.detections[1].box, (BoxPx{200, 50, 30, 12}));
  EXPECT_DOUBLE_EQ(obs.detections[0].score, 1.0);
  EXPECT_DOUBLE_EQ(obs.detections[1].score, 0.4 * 0.5);  // strength * visibility
  EXPECT_EQ(obs.detections[1].source, ObjectId{2});
}

// Clutter scores lie in [0, max strength of the in-frame targets]: with both
// targets of strength 0, every clutter box scores 0 (it scored up to 1
// before, above the targets' own 0); with none in the frame, up to 1.
TEST(SimulateObservation, ClutterScoresStayWithinTheStrongestTargetsStrength) {
  SimulatedObservationOptions o;
  o.p_detect = 1.0;
  o.clutter_per_frame = 20.0;
  o.strength = {{1, 0.0}, {2, 0.0}};
  FrameGroundTruth gt = TwoTargets();
  const Observation obs = SimulateObservation(gt, o, 3);
  int clutter = 0;
  for (const Detection& d : obs.detections) {
    if (d.source) continue;
    ++clutter;
    EXPECT_EQ(d.score, 0.0);
  }
  EXPECT_GT(clutter, 5);  // Poisson(20): P(<= 5) < 1e-4
  for (GroundTruthObject& object : gt.objects) object.in_frame = false;
  double highest = 0.0;
  for (const Detection& d : SimulateObservation(gt, o, 3).detections) {
    highest = std::max(highest, d.score);
  }
  EXPECT_GT(highest, 0.5);  // 20 uniform draws on [0, 1] all below 0.5: 1e-6
}

TEST(SimulateObservation, DeterministicAndSeeded) {
  SimulatedObservationOptions o;
  o.likelihood_map = true;
  EXPECT_EQ(SimulateObservation(TwoTargets(), o, 5), SimulateObservation(TwoTargets(), o, 5));
  EXPECT_NE(SimulateObservation(TwoTargets(), o, 5), SimulateObservation(TwoTargets(), o, 6));
}

// Rates over 4000 frames. Detection of a target with visibility 0.5 and
// exponent 1: p = 0.9 * 0.5 = 0.45; sd of the rate = sqrt(p(1-p)/n) = 0.0079,
// 5 sd = 0.04. Clutter mean 2 per frame: sd of the mean sqrt(2/n) = 0.022, 5 sd = 0.11.
TEST(SimulateObservation, DetectionProbabilityFallsWithVisibilityAndClutterIsPoisson) {
  SimulatedObservationOptions o;
  o.p_detect = 0.9;
  o.clutter_per_frame = 2.0;
  const int n = 4000;
  int hits_a = 0, hits_b = 0, clutter = 0;
  for (int f = 0; f < n; ++f) {
    FrameGroundTruth gt = TwoTargets();
    gt.frame = f;
    for (const Detection& d : SimulateObservation(gt, o, 17).detections) {
      if (!d.source)
        ++clutter;
      else if (*d.source == ObjectId{1})
        ++hits_a;
      else
        ++hits_b;
    }
  }
  EXPECT_NEAR(static_cast<double>(hits_a) / n, 0.9, 5 * std::sqrt(0.9 * 0.1 / n));
  EXPECT_NEAR(static_cast<double>(hits_b) / n, 0.45, 0.04);
  EXPECT_NEAR(static_cast<double>(clutter) / n, 2.0, 0.11);
}

TEST(SimulateObservation, BelowMinVisibleNeverDetected) {
  SimulatedObservationOptions o;
  o.p_detect = 1.0;
  o.min_visible = 0.6;
  o.clutter_per_frame = 0.0;
  for (int f = 0; f < 50; ++f) {
    FrameGroundTruth gt = TwoTargets();
    gt.frame = f;
    // Target 1 (visible 1.0, p_detect 1) always; target 2 (0.5) never.
    const std::vector<Detection> detections = SimulateObservation(gt, o, 2).detections;
    ASSERT_EQ(detections.size(), 1u) << "frame " << f;
    EXPECT_EQ(detections[0].source, ObjectId{1});
  }
}

TEST(SimulateObservation, LikelihoodMapPeaksAtTheStrongTarget) {
  SimulatedObservationOptions o;
  o.likelihood_map = true;
  o.map_noise = 0.0;
  o.map_cell_px = 2.0;
  o.clutter_per_frame = 0.0;
  o.strength = {{2, 0.2}};
  const Observation obs = SimulateObservation(TwoTargets(), o, 3);
  ASSERT_TRUE(obs.likelihood);
  const LikelihoodMap& m = *obs.likelihood;
  EXPECT_EQ(m.width, 160);
  EXPECT_EQ(m.height, 120);
  // At target 1's centre (110, 105) the blob of amplitude 1 dominates.
  EXPECT_NEAR(m.Sample(110.0, 105.0), 1.0, 0.05);
  // Target 2 (centre 215, 56): amplitude 0.2 * visibility 0.5 = 0.1.
  EXPECT_NEAR(m.Sample(215.0, 56.0), 0.1, 0.01);
  EXPECT_NEAR(m.Sample(10.0, 230.0), 0.0, 1e-6);
}

}  // namespace
}  // namespace hcpf::scenarios
