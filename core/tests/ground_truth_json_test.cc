#include "hcpf/core/ground_truth_json.h"

#include <gtest/gtest.h>

#include <string>

#include "hcpf/core/error.h"

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

// A field missing or not of the type written is an InputError naming its
// path in the frame (a bad-input audit: the JSON library's text; a frame 3.5
// or an id 1.7 truncated without a word).
TEST(GroundTruthJson, AFieldThatDoesNotReadIsNamed) {
  FrameGroundTruth gt;
  gt.frame = 3;
  GroundTruthObject o;
  o.id = ObjectId{1};
  gt.objects = {o};
  const nlohmann::json good = GroundTruthToJson(gt);
  const auto error = [](const nlohmann::json& j) -> std::string {
    try {
      GroundTruthFromJson(j);
    } catch (const InputError& e) {
      return e.what();
    }
    return "read";
  };
  EXPECT_EQ(error(good), "read");
  nlohmann::json j = good;
  j.erase("camera");
  EXPECT_NE(error(j).find("camera: expected the frame's camera, found nothing"), std::string::npos)
      << error(j);
  j = good;
  j["frame"] = 3.5;
  EXPECT_NE(error(j).find("frame: expected a whole number in [0, 2147483647], found 3.5"),
            std::string::npos)
      << error(j);
  j = good;
  j["objects"][0]["id"] = 1.7;
  EXPECT_NE(error(j).find("objects[0].id: expected a whole number"), std::string::npos) << error(j);
  j = good;
  j["objects"][0].erase("visible_box");
  EXPECT_NE(error(j).find("objects[0].visible_box: expected the object's visible_box, found "
                          "nothing"),
            std::string::npos)
      << error(j);
  j = good;
  j["camera"]["K"][1] = {1, "x", 3};
  EXPECT_NE(error(j).find("camera.K[1][1]: expected a number, found \"x\""), std::string::npos)
      << error(j);
  j = good;
  j["objects"][0]["in_frame"] = 1;
  EXPECT_NE(error(j).find("objects[0].in_frame: expected true or false, found 1"),
            std::string::npos)
      << error(j);
}

}  // namespace
}  // namespace hcpf
