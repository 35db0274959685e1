// Targets that drive through each other (TargetOverlaps, TargetOverlapNote).
// Expected frames and depths are worked by hand from the paths below.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "hcpf/scenarios/scenario.h"
#include "support/test_scenarios.h"

namespace hcpf::scenarios {
namespace {

// A box target `length` x `width` on a straight path from `from` to `to` at
// 5 m/s, starting at `start_frame`.
TargetSpec Moving(int id, Eigen::Vector2d from, Eigen::Vector2d to, double length, double width,
                  int start_frame = 0) {
  TargetSpec t;
  t.id = ObjectId{id};
  t.dimensions_m = {length, width, 1.5};
  t.path.waypoints_m = {from, to};
  t.path.speed_mps = 5.0;
  t.path.start_frame = start_frame;
  return t;
}

// A target standing at `at`, turned to `heading_deg`.
TargetSpec Standing(int id, Eigen::Vector2d at, double heading_deg, double length, double width) {
  TargetSpec t;
  t.id = ObjectId{id};
  t.dimensions_m = {length, width, 1.5};
  t.path.waypoints_m = {at};
  t.path.heading_deg = heading_deg;
  return t;
}

WorldSpec World(int frames, std::vector<TargetSpec> targets) {
  WorldSpec w;
  w.frames = frames;
  w.fps = 10.0;
  w.targets = std::move(targets);
  return w;
}

// Two 4 x 2 m boxes cross at right angles, both at the origin at frame 40
// (5 m/s, 10 fps: 0.5 m a frame, s = 0.5 f - 20 from the origin). On x the
// first reaches 2 m from its centre and the second 1 m, on y the other way
// round, and their centres are |s| apart on each: either must move 3 - |s|
// to clear the other, more than 0.1 m for |s| < 2.9, that is frames 35 to 45;
// deepest 3 m (at frame 40).
TEST(TargetOverlaps, VehiclesCrossingTogetherOverlapWhileTheirRectanglesInterpenetrate) {
  const WorldSpec w =
      World(100, {Moving(1, {-20, 0}, {20, 0}, 4, 2), Moving(2, {0, -20}, {0, 20}, 4, 2)});
  const std::vector<TargetOverlap> overlaps = TargetOverlaps(w);
  ASSERT_EQ(overlaps.size(), 1u);
  EXPECT_EQ(Value(overlaps[0].a), 1);
  EXPECT_EQ(Value(overlaps[0].b), 2);
  EXPECT_EQ(overlaps[0].first_frame, 35);
  EXPECT_EQ(overlaps[0].last_frame, 45);
  EXPECT_EQ(overlaps[0].frames, 11);
  EXPECT_NEAR(overlaps[0].deepest_m, 3.0, 1e-9);
}

// The second vehicle 40 frames later reaches the crossing when the first has
// parked 20 m east of it, out of its way.
TEST(TargetOverlaps, ALaterStartLetsThemPass) {
  const WorldSpec w = World(200, {Moving(1, {-20, 0}, {20, 0}, 4, 2),
                                  Moving(2, {0, -20}, {0, 20}, 4, 2, /*start_frame=*/40)});
  EXPECT_TRUE(TargetOverlaps(w).empty());
}

// Two 4 m vehicles one behind the other on one lane: 3.95 m between their
// centres is 5 cm of bounding-box slack, not reported; 3.5 m is 0.5 m, reported
// on every frame, and so is a third vehicle's overlap with the second.
TEST(TargetOverlaps, AConvoyOverlapsOnlyBeyondTheSlackOfItsBoxes) {
  EXPECT_TRUE(TargetOverlaps(World(20, {Moving(1, {3.95, 0}, {40, 0}, 4, 2),
                                        Moving(2, {0, 0}, {40, 0}, 4, 2)}))
                  .empty());
  const std::vector<TargetOverlap> overlaps = TargetOverlaps(
      World(20, {Moving(1, {3.5, 0}, {40, 0}, 4, 2), Moving(2, {0, 0}, {40, 0}, 4, 2),
                 Moving(3, {-3.0, 0}, {40, 0}, 4, 2)}));
  ASSERT_EQ(overlaps.size(), 2u);
  EXPECT_EQ(Value(overlaps[0].a), 1);
  EXPECT_EQ(Value(overlaps[0].b), 2);
  EXPECT_NEAR(overlaps[0].deepest_m, 0.5, 1e-9);
  EXPECT_EQ(overlaps[0].frames, 20);
  EXPECT_EQ(overlaps[0].first_frame, 0);
  EXPECT_EQ(overlaps[0].last_frame, 19);
  EXPECT_EQ(Value(overlaps[1].a), 2);
  EXPECT_EQ(Value(overlaps[1].b), 3);
  EXPECT_NEAR(overlaps[1].deepest_m, 1.0, 1e-9);
}

// Two 4 x 2 m vehicles side by side, both turned 45 degrees. Their
// axis-aligned bounds (3 / sqrt 2 = 2.12 m half-extents) overlap wherever
// their centres are within 4.24 m on both axes; the rectangles themselves
// only when the offset across their heading, (dx + dy) / sqrt 2 for an
// offset (-dx, dy) with dx = dy, is under 2 m. At 1.5 m a side: 2.12 m
// across, apart. At 1.3 m: 1.84 m across, overlapping by 2 - 2.6 / sqrt 2.
TEST(TargetOverlaps, TurnedFootprintsAreTestedOnTheirOwnAxes) {
  EXPECT_TRUE(
      TargetOverlaps(World(3, {Standing(1, {0, 0}, 45, 4, 2), Standing(2, {-1.5, 1.5}, 45, 4, 2)}))
          .empty());
  const std::vector<TargetOverlap> overlaps =
      TargetOverlaps(World(3, {Standing(1, {0, 0}, 45, 4, 2), Standing(2, {-1.3, 1.3}, 45, 4, 2)}));
  ASSERT_EQ(overlaps.size(), 1u);
  EXPECT_NEAR(overlaps[0].deepest_m, 2.0 - 2.6 / std::sqrt(2.0), 1e-9);
  EXPECT_EQ(overlaps[0].frames, 3);
}

// Two stretches of overlap: the first is named, every frame counted. Target
// 2 stands across the lane that target 1 drives along and back: out (0.5 m a
// frame from x = -10 to 10) and back. They clear each other by moving
// 2 + 1 - |x| along x (3 m along y), more than 0.1 m for |x| < 2.9.
TEST(TargetOverlaps, TheFirstStretchIsNamedAndEveryFrameCounted) {
  TargetSpec there_and_back = Moving(1, {-10, 0}, {10, 0}, 4, 2);
  there_and_back.path.waypoints_m.push_back({-10, 0});
  Scenario scenario;
  scenario.world = World(81, {there_and_back, Standing(2, {0, 0}, 90, 4, 2)});
  const std::vector<TargetOverlap> overlaps = TargetOverlaps(scenario.world);
  ASSERT_EQ(overlaps.size(), 1u);
  // Out: x = 0.5 f - 10, |x| < 2.9 for f in 15..25; back: x = 30 - 0.5 f for
  // f in 55..65.
  EXPECT_EQ(overlaps[0].first_frame, 15);
  EXPECT_EQ(overlaps[0].last_frame, 25);
  EXPECT_EQ(overlaps[0].frames, 22);
  const std::string note = TargetOverlapNote(scenario);
  EXPECT_NE(note.find("targets 1 and 2 drive through each other first at frames 15-25 (22 frames "
                      "in all): "),
            std::string::npos)
      << note;
}

// The note names the pair and the frames; it is one of the scene's notes
// (`hcpf validate`, `run` and `render` print them), and a scene whose
// vehicles do not meet has none.
TEST(TargetOverlapNote, NamesThePairAndItsFramesAmongTheSceneNotes) {
  // kMinimal's vehicles cross the origin 2 frames apart (6 m/s at 30 fps),
  // after frame 99: within its 20 frames they never meet.
  const Scenario apart = LoadScenarioText(testing::kMinimal, "minimal.yaml");
  EXPECT_EQ(TargetOverlapNote(apart), "");
  EXPECT_TRUE(SceneNotes(apart).empty());
  const Scenario meeting = LoadScenarioText(testing::kMinimal, "minimal.yaml", {{"frames", "200"}});
  const std::vector<TargetOverlap> overlaps = TargetOverlaps(meeting.world);
  ASSERT_EQ(overlaps.size(), 1u);
  const std::string note = TargetOverlapNote(meeting);
  EXPECT_NE(note.find(fmt::format("targets 1 and 2 drive through each other"), 0),
            std::string::npos)
      << note;
  EXPECT_NE(
      note.find(fmt::format("at frames {}-{}:", overlaps[0].first_frame, overlaps[0].last_frame)),
      std::string::npos)
      << note;
  EXPECT_NE(note.find("path.start_frame"), std::string::npos) << note;
  EXPECT_EQ(SceneNotes(meeting), std::vector<std::string>{note});
}

}  // namespace
}  // namespace hcpf::scenarios
