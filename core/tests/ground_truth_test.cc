#include "hcpf/core/ground_truth.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace hcpf {
namespace {

// A nadir camera at `altitude` with horizontal field of view 20 deg on a
// 640-pixel-wide image: f = 320 / tan(10 deg) = 1814.8 px.
WorldSpec NadirWorld(double altitude, Eigen::Vector3d dims) {
  WorldSpec w;
  w.frames = 1;
  w.camera.width_px = 640;
  w.camera.height_px = 480;
  w.camera.hfov_deg = 20.0;
  w.camera.path = {{0, {0, 0, altitude}, {0, 0, 0}}};
  TargetSpec t;
  t.id = ObjectId{1};
  t.dimensions_m = dims;
  t.path.waypoints_m = {{0, 0}};
  w.targets.push_back(t);
  return w;
}

TEST(ComputeGroundTruth, NadirTargetSpansFocalTimesLengthOverAltitude) {
  const double h = 100.0;
  const double length = 4.0;
  // A flat (1 cm) target so its top face is at the altitude of the ground.
  const WorldSpec w = NadirWorld(h, {length, 2.0, 0.01});
  const FrameGroundTruth gt = ComputeGroundTruth(w, 0);
  ASSERT_EQ(gt.objects.size(), 1u);
  const double f = 320.0 / std::tan(10.0 * std::numbers::pi / 180.0);
  EXPECT_NEAR(gt.objects[0].amodal_box.width, f * length / h, 0.5);
  EXPECT_NEAR(gt.objects[0].amodal_box.height, f * 2.0 / h, 0.5);
  EXPECT_NEAR(gt.objects[0].amodal_box.centre_x(), 320.0, 1e-6);
  EXPECT_NEAR(gt.objects[0].visible_fraction, 1.0, 1e-12);
  EXPECT_TRUE(gt.objects[0].in_frame);
  EXPECT_EQ(gt.objects[0].truncation, 0.0);
}

// Hand-made frames: target 1's centre moves from (100, 50) to (104, 53).
// Without camera motion in the homographies (both identity) its velocity is
// (4, 3) either way. When the current frame's ground homography is shifted by
// (10, 0) px (the camera panned), the previous centre is carried to
// (110, 50) and the target's own motion is (-6, 3); scaled by 2 (the camera
// halved its altitude), carried to (200, 100): (-96, -47). A target absent
// from one of the frames has none.
TEST(ImageVelocity, DisplacementOfTheCentreLessTheCameraMotion) {
  FrameGroundTruth previous, current;
  GroundTruthObject o;
  o.id = ObjectId{1};
  o.amodal_box = BoxPx{90, 40, 20, 20};
  previous.objects = {o};
  o.amodal_box = BoxPx{94, 43, 20, 20};
  current.objects = {o};
  const auto near = [](const std::optional<Eigen::Vector2d>& v, double x, double y) {
    return v && std::abs(v->x() - x) < 1e-9 && std::abs(v->y() - y) < 1e-9;
  };
  EXPECT_TRUE(near(ImageVelocity(previous, current, ObjectId{1}, false), 4, 3));
  EXPECT_TRUE(near(ImageVelocity(previous, current, ObjectId{1}, true), 4, 3));
  current.image_from_ground << 1, 0, 10, 0, 1, 0, 0, 0, 1;
  EXPECT_TRUE(near(ImageVelocity(previous, current, ObjectId{1}, false), 4, 3));
  EXPECT_TRUE(near(ImageVelocity(previous, current, ObjectId{1}, true), -6, 3));
  current.image_from_ground = Eigen::Vector3d(2, 2, 1).asDiagonal();
  EXPECT_TRUE(near(ImageVelocity(previous, current, ObjectId{1}, true), -96, -47));
  EXPECT_FALSE(ImageVelocity(previous, current, ObjectId{2}, false));
  previous.objects.clear();
  EXPECT_FALSE(ImageVelocity(previous, current, ObjectId{1}, false));
}

// A target driving east at 6 m/s under a still nadir camera at 100 m, 30 fps:
// 0.2 m a frame, about f · 0.2 / 100 px = 3.63 px/frame along x (f = 1814.8
// px), none along y; the camera does not move, so the same without its
// motion. Exactly: the target is 1 cm tall and wholly on one side of the
// nadir, so its box's outer edge is its top face's (99.99 m away) and its
// inner edge its base's (100 m): the centre moves f · 0.2 · (1/99.99 + 1/100) / 2.
TEST(ImageVelocity, ADrivingTargetUnderAStillNadirCamera) {
  WorldSpec w = NadirWorld(100.0, {4.0, 2.0, 0.01});
  w.frames = 2;
  w.fps = 30;
  w.targets[0].path.waypoints_m = {{-10, 0}, {10, 0}};
  w.targets[0].path.speed_mps = 6.0;
  const FrameGroundTruth a = ComputeGroundTruth(w, 0);
  const FrameGroundTruth b = ComputeGroundTruth(w, 1);
  const double f = 320.0 / std::tan(10.0 * std::numbers::pi / 180.0);
  for (const bool without : {false, true}) {
    const std::optional<Eigen::Vector2d> v = ImageVelocity(a, b, ObjectId{1}, without);
    ASSERT_TRUE(v);
    EXPECT_NEAR(std::abs(v->x()), f * 0.2 * (1.0 / 99.99 + 1.0 / 100.0) / 2.0, 1e-9);
    EXPECT_NEAR(v->y(), 0.0, 1e-6);
  }
}

TEST(ComputeGroundTruth, BuildingCoveringHalfTheVehicle) {
  WorldSpec w = NadirWorld(100.0, {4.0, 2.0, 0.01});
  OccluderSpec building;
  building.kind = OccluderKind::kBuilding;
  building.at_m = {5.0, 0.0};  // covers x in [0, 10]: the east half of the target
  building.size_m = {10.0, 10.0, 5.0};
  w.occluders.push_back(building);
  const FrameGroundTruth gt = ComputeGroundTruth(w, 0);
  const GroundTruthObject& o = gt.objects[0];
  // Rays to points with x < 0 pass west of the building (x * 95/100 < 0 at its
  // roof), rays to x > 0 hit the roof: half the lattice is visible.
  EXPECT_NEAR(o.visible_fraction, 0.5, 0.05);
  // The visible box lies inside the amodal box and covers its west half.
  EXPECT_GE(o.visible_box.left, o.amodal_box.left - 1e-9);
  EXPECT_LE(o.visible_box.right(), o.amodal_box.right() + 1e-9);
  EXPECT_NEAR(o.visible_box.width, 0.5 * o.amodal_box.width, 0.05 * o.amodal_box.width);
}

TEST(ComputeGroundTruth, TruncationAndOutOfFrame) {
  WorldSpec w = NadirWorld(100.0, {4.0, 2.0, 0.01});
  // Half-width of the view at 100 m: 100 * tan(10 deg) = 17.63 m. A target
  // centred on the right edge is cut in half.
  w.targets[0].path.waypoints_m = {{100.0 * std::tan(10.0 * std::numbers::pi / 180.0), 0.0}};
  FrameGroundTruth gt = ComputeGroundTruth(w, 0);
  EXPECT_TRUE(gt.objects[0].in_frame);
  EXPECT_NEAR(gt.objects[0].truncation, 0.5, 0.01);
  EXPECT_NEAR(gt.objects[0].visible_fraction, 1.0, 1e-12);
  w.targets[0].path.waypoints_m = {{60.0, 0.0}};
  gt = ComputeGroundTruth(w, 0);
  EXPECT_FALSE(gt.objects[0].in_frame);
  // Wholly outside the image: all of it is outside, as the renderer writes
  // (it was 0 here, the renderer's 1; a review).
  EXPECT_EQ(gt.objects[0].truncation, 1.0);
}

TEST(ComputeGroundTruth, AbsentTargetsAreNotListed) {
  WorldSpec w = NadirWorld(100.0, {4.0, 2.0, 1.5});
  w.frames = 10;
  w.targets[0].path.start_frame = 5;
  EXPECT_TRUE(ComputeGroundTruth(w, 4).objects.empty());
  EXPECT_EQ(ComputeGroundTruth(w, 5).objects.size(), 1u);
}

// Visibility skips, for each target, the boxes whose image cannot meet its
// rays (a scale audit: every ray against every box made 160 targets x 500
// frames take 65 s). Skipping must change nothing: a low oblique camera over
// 70 tall targets packed close (most hide others in part), three buildings
// and targets beside and behind the camera (their boxes reach behind it, so
// they have no image box and are tested on every ray), against the
// definition cast by hand: every lattice ray against every other box.
TEST(ComputeGroundTruth, ManyTargetsAsEveryRayAgainstEveryBoxGives) {
  WorldSpec w;
  w.frames = 1;
  w.camera.width_px = 320;
  w.camera.height_px = 240;
  w.camera.hfov_deg = 70.0;
  w.camera.path = {{0, {0, -30, 5}, {0, 20, 0}}};
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> x(-25.0, 25.0), y(-33.0, 35.0), heading(0.0, 180.0);
  for (int i = 0; i < 70; ++i) {
    TargetSpec t;
    t.id = ObjectId{i + 1};
    t.dimensions_m = {4.5, 2.0, 3.0};
    t.path.waypoints_m = {{x(rng), y(rng)}};
    t.path.heading_deg = heading(rng);
    w.targets.push_back(t);
  }
  for (const double at : {-8.0, 4.0, 15.0}) {
    OccluderSpec building;
    building.at_m = {at, at};
    building.size_m = {6.0, 6.0, 4.0};
    w.occluders.push_back(building);
  }
  const FrameGroundTruth gt = ComputeGroundTruth(w, 0);
  ASSERT_EQ(gt.objects.size(), w.targets.size());

  std::vector<OrientedBox> boxes;  // targets, in order, then occluders
  for (const TargetSpec& t : w.targets) {
    boxes.push_back(EvaluateTarget(t, w.terrain, 0, w.fps).Box(t.dimensions_m));
  }
  for (const OccluderSpec& o : w.occluders) {
    for (const OrientedBox& b : o.Boxes(w.terrain)) boxes.push_back(b);
  }
  const int n = AnalyticVisibilityOptions{}.grid;
  const Eigen::Vector3d origin = gt.camera.pose.position_m;
  const BoxPx image{0.0, 0.0, 320.0, 240.0};
  int partly_hidden = 0, behind = 0, in_frame = 0;
  for (size_t i = 0; i < w.targets.size(); ++i) {
    SCOPED_TRACE(::testing::Message() << "target " << i + 1);
    bool in_front = false;
    const BoxPx amodal = ProjectBox(gt.camera, boxes[i], &in_front);
    behind += in_front ? 0 : 1;
    const BoxPx clipped = Intersect(amodal, image);
    ASSERT_EQ(gt.objects[i].in_frame, in_front && !clipped.empty());
    if (!gt.objects[i].in_frame) continue;
    ++in_frame;
    int hits = 0, visible = 0;
    BoxPx visible_box;
    const double cw = clipped.width / n, ch = clipped.height / n;
    for (int gy = 0; gy < n; ++gy) {
      for (int gx = 0; gx < n; ++gx) {
        const Eigen::Vector3d dir =
            gt.camera.RayDirection(clipped.left + (gx + 0.5) * cw, clipped.top + (gy + 0.5) * ch);
        const auto t_hit = boxes[i].Intersect(origin, dir);
        if (!t_hit) continue;
        ++hits;
        bool blocked = false;
        for (size_t j = 0; j < boxes.size(); ++j) {
          const auto t = j == i ? std::nullopt : boxes[j].Intersect(origin, dir);
          blocked = blocked || (t && *t < *t_hit);
        }
        if (blocked) continue;
        ++visible;
        visible_box =
            Union(visible_box, BoxPx{clipped.left + gx * cw, clipped.top + gy * ch, cw, ch});
      }
    }
    const double fraction = hits > 0 ? static_cast<double>(visible) / hits : 0.0;
    EXPECT_EQ(gt.objects[i].visible_fraction, fraction);
    EXPECT_EQ(gt.objects[i].visible_box, visible_box);
    partly_hidden += fraction > 0.0 && fraction < 1.0 ? 1 : 0;
  }
  // The scene is what the comment says.
  EXPECT_GE(in_frame, 40);
  EXPECT_GE(partly_hidden, 20);
  EXPECT_GE(behind, 1);
}

}  // namespace
}  // namespace hcpf
