#include "hcpf/core/ground_truth_json.h"

#include <gtest/gtest.h>

namespace hcpf {
namespace {

// The frame cache stores what GroundTruthToJson writes and reads it back with
// GroundTruthFromJson: the round trip must give back every field exactly
// (JSON numbers keep full double precision).
TEST(GroundTruthJson, RoundTripIsExact) {
  WorldSpec w;
  w.frames = 1;
  w.camera.width_px = 640;
  w.camera.height_px = 480;
  w.camera.hfov_deg = 37.3;
  w.camera.path = {{0, {3.1, -20.7, 120.3}, {0.3, 0.1, 0}}};
  for (int id : {1, 2}) {
    TargetSpec t;
    t.id = ObjectId{id};
    t.dimensions_m = {4.4, 2.1, 1.7};
    t.path.waypoints_m = {{id * 5.3, -1.0 / 3.0}};
    w.targets.push_back(t);
  }
  FrameGroundTruth gt = ComputeGroundTruth(w, 0);
  ASSERT_EQ(gt.objects.size(), 2u);
  gt.objects[1].pixels_visible = 1234;
  gt.objects[1].pixels_total = 2345;
  const FrameGroundTruth back = GroundTruthFromJson(GroundTruthToJson(gt));
  EXPECT_EQ(back.frame, gt.frame);
  EXPECT_EQ(back.camera.intrinsics, gt.camera.intrinsics);
  EXPECT_EQ(back.camera.pose.position_m, gt.camera.pose.position_m);
  EXPECT_EQ(back.camera.pose.world_from_camera, gt.camera.pose.world_from_camera);
  EXPECT_EQ(back.image_from_ground, gt.image_from_ground);
  ASSERT_EQ(back.objects.size(), gt.objects.size());
  for (size_t i = 0; i < gt.objects.size(); ++i) {
    const GroundTruthObject& a = gt.objects[i];
    const GroundTruthObject& b = back.objects[i];
    EXPECT_EQ(b.id, a.id);
    EXPECT_EQ(b.in_frame, a.in_frame);
    EXPECT_EQ(b.amodal_box, a.amodal_box);
    EXPECT_EQ(b.visible_box, a.visible_box);
    EXPECT_EQ(b.visible_fraction, a.visible_fraction);
    EXPECT_EQ(b.truncation, a.truncation);
    EXPECT_EQ(b.pixels_visible, a.pixels_visible);
    EXPECT_EQ(b.pixels_total, a.pixels_total);
    EXPECT_EQ(b.position_m, a.position_m);
    EXPECT_EQ(b.heading_deg, a.heading_deg);
    EXPECT_EQ(b.dimensions_m, a.dimensions_m);
  }
}

TEST(GroundTruthJson, MissingFieldThrows) {
  nlohmann::json j = GroundTruthToJson(FrameGroundTruth{});
  j.erase("camera");
  EXPECT_THROW(GroundTruthFromJson(j), nlohmann::json::exception);
}

}  // namespace
}  // namespace hcpf
