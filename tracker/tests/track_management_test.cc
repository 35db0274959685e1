#include "hcpf/tracker/track_management.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <optional>
#include <set>
#include <vector>

#include "hcpf/tracker/tracker.h"

namespace hcpf::tracker {
namespace {

TrackManagementOptions MofN(int m, int n) {
  TrackManagementOptions o;
  o.confirm_hits = m;
  o.confirm_window = n;
  return o;  // tentative_gate_px 20
}

// One target detected on `hit_frames` (a 10 px box centred at (100, 100),
// static) over frames 0 .. frames - 1, no camera motion: the frames with a
// birth.
std::vector<int> BirthFrames(int m, int n, const std::set<int>& hit_frames, int frames) {
  MofNInitiator initiator(MofN(m, n));
  std::vector<int> births;
  for (int t = 0; t < frames; ++t) {
    Observation obs;
    obs.frame = t;
    std::vector<size_t> free;
    if (hit_frames.contains(t)) {
      obs.detections.push_back({.box = BoxPx::FromCentre(100, 100, 10, 10), .score = 1.0});
      free.push_back(0);
    }
    if (!initiator.Step(obs, free, std::nullopt).empty()) births.push_back(t);
  }
  return births;
}

// The birth frame is the first frame whose last N frames (itself included)
// hold M hits, as in the standard sliding-window M-of-N rule; the expected
// frames are counted by hand from the windows. Cases (a) and (b) failed
// before 2026-12-05 (the audit's F5): a tentative was dropped once its misses
// since creation exceeded N - M within the window, although those misses
// were about to slide out of it.
TEST(MofNInitiator, ConfirmsAtTheFirstWindowOfNFramesWithMHits) {
  // (a) The audit's sequence, M = 3, N = 5: the window [2, 6] holds the hits
  // 3, 5, 6. The old rule dropped the tentative at frame 4 (misses 1, 2, 4)
  // and a new one from frame 5 confirmed at 7.
  EXPECT_EQ(BirthFrames(3, 5, {0, 3, 5, 6, 7}, 9), std::vector<int>{6});
  // (b) M = 4, N = 6, hits 0, 2, 4, 6, 7: [2, 7] holds 2, 4, 6, 7. The old
  // rule dropped it at frame 5 (misses 1, 3, 5) and never confirmed.
  EXPECT_EQ(BirthFrames(4, 6, {0, 2, 4, 6, 7}, 10), std::vector<int>{7});
  // (c) M = 3, N = 5, hits 0, 1, 4: [0, 4] holds all three.
  EXPECT_EQ(BirthFrames(3, 5, {0, 1, 4}, 8), std::vector<int>{4});
  // (d) M = 3, N = 5, hits 0, 1, 5, 6, 7: no window holds 1 and 5 with a
  // third hit ([1, 5]: 1, 5; [2, 6]: 5, 6); [3, 7] holds 5, 6, 7.
  EXPECT_EQ(BirthFrames(3, 5, {0, 1, 5, 6, 7}, 10), std::vector<int>{7});
  // (e) M = 2, N = 3, hits every third frame: no window of 3 holds two.
  EXPECT_TRUE(BirthFrames(2, 3, {0, 3, 6, 9}, 12).empty());
  // (f) M = 2, N = 4, hits every third frame: [0, 3] holds 0 and 3; the
  // detection at 6 starts a new tentative, confirmed with 9 ([6, 9]).
  EXPECT_EQ(BirthFrames(2, 4, {0, 3, 6, 9}, 12), (std::vector<int>{3, 9}));
  // (g) M = 1: every hit is a birth.
  EXPECT_EQ(BirthFrames(1, 5, {2, 4}, 6), (std::vector<int>{2, 4}));
}

// A tentative is kept while a later window could still hold M hits with its
// last hit in it: while its last hit is at most N - M frames old. M = 3,
// N = 5, hits at 0 and 2: at frame 4 the hit at 2 is 2 frames old, so the
// tentative is kept, and hits at 5 and 6 confirm it ([2, 6] holds 2, 5, 6;
// the old rule dropped it at frame 4, misses 1, 3, 4). If frame 5 is missed
// too, the hit at 2 is 3 frames old there and the tentative is dropped:
// rightly, as [2, 6] then holds 2 and 6 only and [3, 7] holds 6 and 7.
TEST(MofNInitiator, KeepsATentativeUntilItsLastHitIsMoreThanNMinusMFramesOld) {
  EXPECT_EQ(BirthFrames(3, 5, {0, 2, 5, 6}, 8), std::vector<int>{6});
  EXPECT_TRUE(BirthFrames(3, 5, {0, 2, 6, 7}, 9).empty());
}

// The velocity of a birth: from the first to the last hit of its window.
// Hits at 0, 3, 5, 6 of a target moving +2 px/frame in x (centre 100 + 2t):
// confirmed at 6 with the window [2, 6]: (112 - 106) / (6 - 3) = 2.
TEST(MofNInitiator, BirthVelocityIsFromTheWindowsFirstHitToItsLast) {
  MofNInitiator initiator(MofN(3, 5));
  std::vector<Birth> births;
  for (const int t : {0, 1, 2, 3, 4, 5, 6}) {
    Observation obs;
    obs.frame = t;
    std::vector<size_t> free;
    if (t == 0 || t == 3 || t == 5 || t == 6) {
      obs.detections.push_back({.box = BoxPx::FromCentre(100 + 2 * t, 50, 10, 10)});
      free.push_back(0);
    }
    births = initiator.Step(obs, free, std::nullopt);
    if (t < 6) {
      EXPECT_TRUE(births.empty()) << t;
    }
  }
  ASSERT_EQ(births.size(), 1U);
  EXPECT_EQ(births[0].box, BoxPx::FromCentre(112, 50, 10, 10));
  EXPECT_EQ(births[0].detection, 0);
  EXPECT_NEAR(births[0].velocity_px.x(), 2.0, 1e-12);
  EXPECT_NEAR(births[0].velocity_px.y(), 0.0, 1e-12);
}

// Three frames of one target under a camera motion `s` (frame 0 has none),
// its centre `centres[t]` in frame t; M = 3, N = 5. Returns the births of
// frame 2 (none before it is checked).
std::vector<Birth> ThreeFramesUnder(const SimilarityMotion& s,
                                    const std::vector<Eigen::Vector2d>& centres) {
  MofNInitiator initiator(MofN(3, 5));
  std::vector<Birth> births;
  for (int t = 0; t < 3; ++t) {
    Observation obs;
    obs.frame = t;
    obs.detections.push_back({.box = BoxPx::FromCentre(centres[t].x(), centres[t].y(), 10, 10)});
    const std::vector<size_t> free = {0};
    births = initiator.Step(obs, free, t == 0 ? std::nullopt : std::optional(s));
    if (t < 2) {
      EXPECT_TRUE(births.empty()) << t;
    }
  }
  return births;
}

// With the camera moving, a tentative's earlier centres are carried through
// each frame's motion, so the birth velocity is the target's own and the gate
// compares positions in one frame (the audit's F3: the raw image displacement
// was the velocity, and the tracker then applied the camera's motion again).
TEST(MofNInitiator, CarriesItsTentativesThroughTheCameraMotion) {
  // The camera pans 5 px/frame in x. A target static in the scene moves 5 px
  // per frame in the image: velocity 0 (was 5). One moving +2 px/frame in the
  // scene moves 7: velocity 2 (was 7).
  const SimilarityMotion pan{.tx_px = 5.0};
  for (const double own : {0.0, 2.0}) {
    const double step = 5.0 + own;
    const std::vector<Birth> b =
        ThreeFramesUnder(pan, {{100, 80}, {100 + step, 80}, {100 + 2 * step, 80}});
    ASSERT_EQ(b.size(), 1U) << own;
    EXPECT_NEAR(b[0].velocity_px.x(), own, 1e-12);
    EXPECT_NEAR(b[0].velocity_px.y(), 0.0, 1e-12);
    EXPECT_EQ(b[0].box, BoxPx::FromCentre(100 + 2 * step, 80, 10, 10));
  }
  // A zoom by 1.1 about the origin: a static target at (100, 50) is seen at
  // (110, 55) and (121, 60.5); its velocity is 0 (was (10.5, 5.25)).
  const std::vector<Birth> zoom = ThreeFramesUnder(SimilarityMotion{.log_scale = std::log(1.1)},
                                                   {{100, 50}, {110, 55}, {121, 60.5}});
  ASSERT_EQ(zoom.size(), 1U);
  EXPECT_NEAR(zoom[0].velocity_px.norm(), 0.0, 1e-9);
  // A pan of 30 px/frame, beyond the 20 px gate: the static target's
  // detections continue one tentative only with the motion taken out.
  EXPECT_EQ(
      ThreeFramesUnder(SimilarityMotion{.tx_px = 30.0}, {{100, 80}, {130, 80}, {160, 80}}).size(),
      1U);
  // A quarter turn about the origin and a shift (200, 0): (x, y) -> (200 - y,
  // x), so a static target is seen at (100, 50), (150, 100), (100, 150),
  // 70 px apart from frame to frame.
  const std::vector<Birth> turn =
      ThreeFramesUnder(SimilarityMotion{.tx_px = 200.0, .rotation_rad = std::numbers::pi / 2},
                       {{100, 50}, {150, 100}, {100, 150}});
  ASSERT_EQ(turn.size(), 1U);
  EXPECT_NEAR(turn[0].velocity_px.norm(), 0.0, 1e-9);
}

}  // namespace
}  // namespace hcpf::tracker
