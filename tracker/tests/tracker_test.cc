#include "hcpf/tracker/tracker.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <tuple>

#include "hcpf/core/error.h"

namespace hcpf::tracker {
namespace {

void ExpectKeyInError(const TrackerOptions& o, const std::string& key) {
  try {
    o.Validate();
    FAIL() << "expected InputError naming " << key;
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
  }
}

TEST(TrackerOptions, DefaultsValidate) { EXPECT_NO_THROW(TrackerOptions{}.Validate()); }

TEST(TrackerOptions, ErrorsNameTheField) {
  TrackerOptions o;
  o.particles = 0;
  ExpectKeyInError(o, "tracker.particles");
  o = {};
  o.likelihood.sigma_px = -1;
  ExpectKeyInError(o, "tracker.likelihood.sigma_px");
  o = {};
  o.management.confirm_hits = 6;  // > confirm_window 5
  ExpectKeyInError(o, "tracker.management.confirm_hits");
  o = {};
  o.likelihood.model = LikelihoodModel::kAssociated;
  o.association.method = AssociationMethod::kNone;
  ExpectKeyInError(o, "tracker.association.method");
  o = {};
  o.dynamics.model = DynamicsModel::kConstantVelocityScale;
  ExpectKeyInError(o, "tracker.likelihood.sigma_log_size");
  o.likelihood.sigma_log_size = 0.2;
  EXPECT_NO_THROW(o.Validate());
  o = {};
  o.interaction.radius_px = 0;
  ExpectKeyInError(o, "tracker.interaction.radius_px");
  o = {};
  o.association.min_iou = 2;
  ExpectKeyInError(o, "tracker.association.min_iou");
  o = {};
  o.threads = 0;
  ExpectKeyInError(o, "tracker.threads");
  o = {};
  o.init = InitMode::kDetections;
  o.management.reacquire = ReacquireMode::kOwnDetections;
  ExpectKeyInError(o, "tracker.management.reacquire");
}

TEST(InitMode, NamesRoundTrip) {
  for (const auto name : NamesOf<InitMode>()) EXPECT_EQ(ToString(*ParseName<InitMode>(name)), name);
  EXPECT_FALSE(ParseName<InitMode>("gt").has_value());
}

Observation Frame(int frame, std::vector<std::pair<BoxPx, double>> dets) {
  Observation obs;
  obs.frame = frame;
  for (const auto& [box, score] : dets) obs.detections.push_back({.box = box, .score = score});
  return obs;
}

TEST(MultiTargetTracker, FollowsAMovingTarget) {
  // One target moving (+2, +1) px/frame, exact detections. After 40 frames
  // the estimate must lie within 2 px of the truth: the posterior sd with
  // sigma 3 and ~10 frames of memory is ~1 px, so 2 px is a loose bound.
  TrackerOptions o;
  o.particles = 400;
  o.management.birth_sigma_log_scale = 0.0;  // s = 1 exactly, so the width stays 16
  auto tracker = MakeTracker(o, Rng(1));
  tracker->BirthTrack(TrackId{5}, BoxPx::FromCentre(100, 100, 16, 16));
  FrameReport last;
  for (int t = 0; t < 40; ++t) {
    last = tracker->Step(Frame(t, {{BoxPx::FromCentre(100 + 2 * t, 100 + t, 16, 16), 1.0}}));
  }
  ASSERT_EQ(last.filters.size(), 1U);
  const FilterReport& f = last.filters[0];
  EXPECT_EQ(f.id, TrackId{5});
  EXPECT_NEAR(f.box.centre_x(), 178.0, 2.0);
  EXPECT_NEAR(f.box.centre_y(), 139.0, 2.0);
  EXPECT_NEAR(f.box.width, 16.0, 1e-6);  // constant_velocity: scale unchanged
  EXPECT_GT(f.ess, 1.0);
  EXPECT_LE(f.ess, 400.0);
  EXPECT_FALSE(f.coasting);
  EXPECT_TRUE(f.resampled);
  const auto estimates = ToTrackEstimates(last, o.particles);
  ASSERT_EQ(estimates.size(), 1U);
  EXPECT_EQ(estimates[0].box, f.box);
}

// Runs three targets 15 px apart (close enough for charged rejections) for
// 15 frames and returns every report.
std::vector<FrameReport> RunThree(TrackerOptions o, bool reverse_births) {
  auto tracker = MakeTracker(o, Rng(42));
  std::vector<int> ids = {1, 2, 3};
  if (reverse_births) std::reverse(ids.begin(), ids.end());
  for (const int id : ids)
    tracker->BirthTrack(TrackId{id}, BoxPx::FromCentre(100.0 + 15.0 * id, 80, 16, 16));
  std::vector<FrameReport> out;
  for (int t = 0; t < 15; ++t) {
    std::vector<std::pair<BoxPx, double>> dets;
    for (int id = 1; id <= 3; ++id)
      dets.push_back({BoxPx::FromCentre(100.0 + 15.0 * id + t, 80 + 0.5 * t, 16, 16), 0.3 * id});
    out.push_back(tracker->Step(Frame(t, dets)));
  }
  return out;
}

void ExpectSameReports(const std::vector<FrameReport>& a, const std::vector<FrameReport>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (size_t t = 0; t < a.size(); ++t) {
    ASSERT_EQ(a[t].filters.size(), b[t].filters.size());
    for (size_t k = 0; k < a[t].filters.size(); ++k) {
      const FilterReport& x = a[t].filters[k];
      const FilterReport& y = b[t].filters[k];
      EXPECT_EQ(x.id, y.id);
      EXPECT_EQ(x.box, y.box);
      EXPECT_EQ(x.ess, y.ess);
      EXPECT_EQ(x.rejections, y.rejections);
      EXPECT_EQ(x.particles, y.particles);
    }
  }
}

TEST(MultiTargetTracker, ResultsDoNotDependOnThreadsOrBirthOrder) {
  TrackerOptions o;
  o.particles = 300;
  o.resampling.method = ResamplingMethod::kCharged;
  o.association.method = AssociationMethod::kNone;
  o.keep_particles = 20;
  const auto base = RunThree(o, false);
  ExpectSameReports(base, RunThree(o, true));
  o.threads = 2;
  ExpectSameReports(base, RunThree(o, false));
  o.threads = 3;
  ExpectSameReports(base, RunThree(o, true));
  // And the charged resampler did reject something (the test is not vacuous).
  int64_t rejections = 0;
  for (const auto& r : base) {
    for (const auto& f : r.filters) rejections += f.rejections;
  }
  EXPECT_GT(rejections, 0);
  EXPECT_EQ(base.back().filters[0].particles.size(), 20U);  // 300 / stride 15
}

TEST(MultiTargetTracker, CoastsWithoutEvidenceAndDeletesAfterKFrames) {
  // GNN association: with no detections the filter is unsupported, predicts
  // only (coasting) and is deleted when 4 consecutive frames lack support.
  TrackerOptions o;
  o.particles = 100;
  o.management.max_missed_frames = 4;
  auto tracker = MakeTracker(o, Rng(3));
  tracker->BirthTrack(TrackId{1}, BoxPx::FromCentre(50, 50, 10, 10));
  FrameReport r = tracker->Step(Frame(0, {{BoxPx::FromCentre(50, 50, 10, 10), 1.0}}));
  EXPECT_FALSE(r.filters[0].coasting);
  EXPECT_EQ(r.filters[0].assigned_detection, 0);
  for (int t = 1; t <= 3; ++t) {
    r = tracker->Step(Frame(t, {}));
    ASSERT_EQ(r.filters.size(), 1U);
    EXPECT_TRUE(r.filters[0].coasting);
    EXPECT_FALSE(r.filters[0].resampled);
    EXPECT_EQ(r.filters[0].missed_frames, t);
    EXPECT_TRUE(r.deleted.empty());
  }
  r = tracker->Step(Frame(4, {}));
  EXPECT_EQ(r.deleted, std::vector<TrackId>{TrackId{1}});
  EXPECT_EQ(tracker->num_filters(), 0U);
}

// Target-specific detections (a vision/ detector with target models): each
// filter sees only the detections labelled with its own target (TrackId value
// == ObjectId value) and that target's map.
TEST(MultiTargetTracker, TargetSpecificDetectionsGoToTheirOwnFilter) {
  TrackerOptions o;
  o.particles = 100;
  const auto make = [&o] {
    auto t = MakeTracker(o, Rng(3));
    t->BirthTrack(TrackId{1}, BoxPx::FromCentre(100, 100, 10, 10));
    t->BirthTrack(TrackId{2}, BoxPx::FromCentre(140, 100, 10, 10));
    return t;
  };
  // Labels swapped against position: target 1's detection lies at filter 2
  // and target 2's at filter 1, 40 px from the filter of their own target
  // (outside its gate, sqrt(9.21 (4 + 9)) ~ 11 px), so neither filter is
  // given a detection and both coast.
  Observation swapped = Frame(
      0, {{BoxPx::FromCentre(140, 100, 10, 10), 1.0}, {BoxPx::FromCentre(100, 100, 10, 10), 1.0}});
  swapped.detections[0].target = ObjectId{1};
  swapped.detections[1].target = ObjectId{2};
  FrameReport r = make()->Step(swapped);
  ASSERT_EQ(r.filters.size(), 2U);
  EXPECT_EQ(r.filters[0].assigned_detection, -1);
  EXPECT_EQ(r.filters[1].assigned_detection, -1);
  EXPECT_TRUE(r.filters[0].coasting);
  EXPECT_TRUE(r.filters[1].coasting);
  // Without labels the same boxes go to the nearer filter.
  for (Detection& d : swapped.detections) d.target.reset();
  r = make()->Step(swapped);
  EXPECT_EQ(r.filters[0].assigned_detection, 1);
  EXPECT_EQ(r.filters[1].assigned_detection, 0);
  // Labelled as their positions say: each filter gets its own (index in the
  // whole frame), and a target with no detection this frame coasts.
  Observation own = Frame(0, {{BoxPx::FromCentre(141, 100, 10, 10), 1.0}});
  own.detections[0].target = ObjectId{2};
  r = make()->Step(own);
  EXPECT_EQ(r.filters[0].assigned_detection, -1);
  EXPECT_TRUE(r.filters[0].coasting);
  EXPECT_EQ(r.filters[1].assigned_detection, 0);
  EXPECT_FALSE(r.filters[1].coasting);
}

// The map likelihood reads the filter's own target map: filter 1 has a map
// (supported), filter 2 has none in this frame (coasts).
TEST(MultiTargetTracker, TargetMapsGoToTheirOwnFilter) {
  TrackerOptions o;
  o.particles = 100;
  o.likelihood.model = LikelihoodModel::kMap;
  auto tracker = MakeTracker(o, Rng(3));
  tracker->BirthTrack(TrackId{1}, BoxPx::FromCentre(100, 100, 10, 10));
  tracker->BirthTrack(TrackId{2}, BoxPx::FromCentre(140, 100, 10, 10));
  Observation obs;
  LikelihoodMap map{.width = 60, .height = 60, .cell_px = 4.0};
  map.values.assign(60 * 60, 1.0f);
  obs.target_maps.push_back({ObjectId{1}, map});
  const FrameReport r = tracker->Step(obs);
  ASSERT_EQ(r.filters.size(), 2U);
  EXPECT_FALSE(r.filters[0].coasting);
  EXPECT_TRUE(r.filters[1].coasting);
}

// management.reacquire. A frame of detections each labelled with a target.
Observation Labelled(int frame, std::vector<std::tuple<BoxPx, double, int32_t>> dets) {
  Observation obs;
  obs.frame = frame;
  for (const auto& [box, score, target] : dets) {
    obs.detections.push_back({.box = box, .score = score, .target = ObjectId{target}});
  }
  return obs;
}

TrackerOptions Reacquiring(ReacquireMode mode) {
  TrackerOptions o;
  o.particles = 200;
  o.management.reacquire = mode;
  return o;
}

// Target 1's detections are 100 px from its filter (outside its gate), as
// after a filter has lost its target; target 7 was never born. With none the
// filter never finds them; with own_detections the third of them (confirm_hits
// 3 of 5, each within 20 px of the last) re-seeds it there, and target 7
// gets no filter.
TEST(MultiTargetTracker, ReacquireFindsALostFilterAtItsOwnTargetsDetections) {
  for (const ReacquireMode mode : {ReacquireMode::kNone, ReacquireMode::kOwnDetections}) {
    auto tracker = MakeTracker(Reacquiring(mode), Rng(5));
    tracker->BirthTrack(TrackId{1}, BoxPx::FromCentre(100, 100, 10, 10));
    std::vector<int> reacquired_at;
    FrameReport r;
    for (int t = 0; t < 8; ++t) {
      r = tracker->Step(Labelled(t, {{BoxPx::FromCentre(200 + t, 100, 12, 12), 0.9, 1},
                                     {BoxPx::FromCentre(300, 300, 10, 10), 0.9, 7}}));
      if (!r.reacquired.empty()) {
        EXPECT_EQ(r.reacquired, std::vector<TrackId>{TrackId{1}});
        reacquired_at.push_back(t);
      }
    }
    ASSERT_EQ(tracker->num_filters(), 1U) << ToString(mode);
    if (mode == ReacquireMode::kNone) {
      EXPECT_TRUE(reacquired_at.empty());
      EXPECT_TRUE(r.filters[0].coasting);
      // Coasting at rest (no detection in its gate), its mean only diffuses,
      // well under 1 px in 8 frames: 5 px is generous and still 95 px short
      // of the detections it must not jump to.
      EXPECT_NEAR(r.filters[0].box.centre_x(), 100.0, 5.0);
    } else {
      EXPECT_EQ(reacquired_at, std::vector<int>{2});
      // Re-seeded at frame 2's box (202, 12 px wide) moving +1 px/frame (its
      // first to last hit), then followed: 207 at frame 7. 3 px: the birth
      // spread is 2 px and five frames of exact detections narrow it. Width
      // 12 px with a birth spread of 0.05 in log scale (0.6 px): 1.5 px is
      // 2.5 of that for one particle, more for the mean.
      EXPECT_FALSE(r.filters[0].coasting);
      EXPECT_NEAR(r.filters[0].box.centre_x(), 207.0, 3.0);
      EXPECT_NEAR(r.filters[0].box.width, 12.0, 1.5);
    }
  }
}

// A deleted filter is born again with its id from its target's detections,
// on a stream of its own; the result does not depend on the thread count.
TEST(MultiTargetTracker, ReacquireBearsADeletedFilterAgainWithItsId) {
  std::vector<BoxPx> last;
  for (const int threads : {1, 3}) {
    TrackerOptions o = Reacquiring(ReacquireMode::kOwnDetections);
    o.management.max_missed_frames = 2;
    o.threads = threads;
    auto tracker = MakeTracker(o, Rng(6));
    tracker->BirthTrack(TrackId{1}, BoxPx::FromCentre(100, 100, 10, 10));
    tracker->BirthTrack(TrackId{2}, BoxPx::FromCentre(40, 40, 10, 10));
    FrameReport r = tracker->Step(Labelled(0, {{BoxPx::FromCentre(40, 40, 10, 10), 0.9, 2}}));
    r = tracker->Step(Labelled(1, {{BoxPx::FromCentre(40, 40, 10, 10), 0.9, 2}}));
    EXPECT_EQ(r.deleted, std::vector<TrackId>{TrackId{1}});
    for (int t = 2; t <= 6; ++t) {
      r = tracker->Step(Labelled(t, {{BoxPx::FromCentre(150, 100, 10, 10), 0.9, 1},
                                     {BoxPx::FromCentre(40, 40, 10, 10), 0.9, 2}}));
      EXPECT_EQ(r.reacquired.size(), t == 4 ? 1U : 0U) << t;
    }
    EXPECT_EQ(tracker->track_ids(), (std::vector<TrackId>{TrackId{1}, TrackId{2}}));
    ASSERT_EQ(r.filters.size(), 2U);
    EXPECT_EQ(r.filters[0].id, TrackId{1});
    EXPECT_EQ(r.filters[0].assigned_detection, 0);
    // Born again at frame 4 at the 150 px detection (birth spread 2 px), then
    // two frames of exact detections there: within 3 px, as above.
    EXPECT_NEAR(r.filters[0].box.centre_x(), 150.0, 3.0);
    if (!last.empty()) {
      EXPECT_EQ(last[0], r.filters[0].box);
    }
    last = {r.filters[0].box};
  }
}

// A filter with support keeps it: a stronger detection of its own target
// elsewhere (a false one, no filter claims it) never moves it; and detections
// that jump more than tentative_gate_px from frame to frame never confirm.
TEST(MultiTargetTracker, ReacquireLeavesASupportedFilterAloneAndNeedsAConsistentTrack) {
  auto tracker = MakeTracker(Reacquiring(ReacquireMode::kOwnDetections), Rng(7));
  tracker->BirthTrack(TrackId{1}, BoxPx::FromCentre(100, 100, 10, 10));
  FrameReport r;
  for (int t = 0; t < 10; ++t) {
    r = tracker->Step(Labelled(t, {{BoxPx::FromCentre(100, 100, 10, 10), 0.5, 1},
                                   {BoxPx::FromCentre(250, 250, 10, 10), 1.0, 1}}));
    EXPECT_TRUE(r.reacquired.empty()) << t;
  }
  // Ten frames of exact detections at 100 hold it to about a pixel (the
  // birth spread, 2 px, narrowed); the stronger one is 150 px away.
  EXPECT_NEAR(r.filters[0].box.centre_x(), 100.0, 2.0);
  // Lost (its own detections gone from its gate); each one now lies 30 px
  // beyond the last, so no two continue one tentative.
  for (int t = 10; t < 20; ++t) {
    r = tracker->Step(Labelled(t, {{BoxPx::FromCentre(30 * t, 300, 10, 10), 1.0, 1}}));
    EXPECT_TRUE(r.reacquired.empty()) << t;
  }
  EXPECT_TRUE(r.filters[0].coasting);
}

// A lost filter's own-labelled detections that sit on another filter (their
// centre inside its predicted box) are that filter's target, not evidence of
// the lost one: a model that fires on a similar vehicle never drags its filter
// onto it. The same detections 60 px away from the other filter re-seed it.
TEST(MultiTargetTracker, ReacquireIgnoresDetectionsAnotherFilterIsOn) {
  for (const double x : {140.0, 200.0}) {
    auto tracker = MakeTracker(Reacquiring(ReacquireMode::kOwnDetections), Rng(8));
    tracker->BirthTrack(TrackId{1}, BoxPx::FromCentre(60, 100, 10, 10));
    tracker->BirthTrack(TrackId{2}, BoxPx::FromCentre(140, 100, 30, 14));
    int reacquired = 0;
    for (int t = 0; t < 8; ++t) {
      const FrameReport r =
          tracker->Step(Labelled(t, {{BoxPx::FromCentre(140, 100, 30, 14), 0.9, 2},
                                     {BoxPx::FromCentre(x + 6, 102, 10, 10), 0.9, 1}}));
      reacquired += static_cast<int>(r.reacquired.size());
      ASSERT_EQ(r.filters.size(), 2U);
      EXPECT_FALSE(r.filters[1].coasting) << t;
    }
    EXPECT_EQ(reacquired, x == 140.0 ? 0 : 1) << x;
  }
}

TEST(MultiTargetTracker, ReacquiresAfterOcclusion) {
  // Target moving +1 px/frame; detections missing on frames 10..17 (coasting
  // on the constant-velocity prediction), back from 18. At frame 30 the
  // estimate must be within 3 px of the truth (130, 60): 13 frames of exact
  // detections after the gap leave the cloud's mean within about a pixel
  // (born 2 px wide, 500 particles); 3 px fails a filter that lost it.
  TrackerOptions o;
  o.particles = 500;
  auto tracker = MakeTracker(o, Rng(4));
  tracker->BirthTrack(TrackId{1}, BoxPx::FromCentre(100, 60, 16, 16), Eigen::Vector2d(1.0, 0.0));
  FrameReport r;
  int coasting_frames = 0;
  for (int t = 0; t <= 30; ++t) {
    const bool occluded = t >= 10 && t <= 17;
    r = tracker->Step(occluded ? Frame(t, {})
                               : Frame(t, {{BoxPx::FromCentre(100 + t, 60, 16, 16), 1.0}}));
    coasting_frames += r.filters[0].coasting ? 1 : 0;
  }
  EXPECT_EQ(coasting_frames, 8);
  EXPECT_NEAR(r.filters[0].box.centre_x(), 130.0, 3.0);
  EXPECT_NEAR(r.filters[0].box.centre_y(), 60.0, 3.0);
}

TEST(MultiTargetTracker, MOfNConfirmationFromDetections) {
  // confirm 3 of 5: a detection seen on frames 0, 1, 2 (moving +2 px/frame)
  // is born at the end of frame 2 with velocity (2, 0); a one-frame clutter
  // detection at frame 1 is never born.
  TrackerOptions o;
  o.init = InitMode::kDetections;
  o.particles = 100;
  auto tracker = MakeTracker(o, Rng(5));
  EXPECT_TRUE(tracker->Step(Frame(0, {{BoxPx::FromCentre(50, 50, 10, 10), 1.0}})).born.empty());
  EXPECT_TRUE(tracker
                  ->Step(Frame(1, {{BoxPx::FromCentre(52, 50, 10, 10), 1.0},
                                   {BoxPx::FromCentre(300, 300, 10, 10), 1.0}}))
                  .born.empty());
  const FrameReport r = tracker->Step(Frame(2, {{BoxPx::FromCentre(54, 50, 10, 10), 1.0}}));
  ASSERT_EQ(r.born.size(), 1U);
  EXPECT_EQ(r.born[0], TrackId{1});
  const ParticleSet* p = tracker->particles(TrackId{1});
  ASSERT_NE(p, nullptr);
  double mean_vx = 0.0;
  for (const double v : p->vx) mean_vx += v / static_cast<double>(p->size());
  // 100 particles with birth velocity sd 0.5: standard error 0.05; 5 sd = 0.25.
  EXPECT_NEAR(mean_vx, 2.0, 0.25);
  // Frames 3 to 7: the clutter tentative (1 hit, at frame 1) is dropped at
  // frame 4, its hit 3 > N - M = 2 frames old, and is never born; the track
  // keeps being supported.
  for (int t = 3; t < 8; ++t) {
    const FrameReport q =
        tracker->Step(Frame(t, {{BoxPx::FromCentre(50 + 2 * t, 50, 10, 10), 1.0}}));
    EXPECT_TRUE(q.born.empty()) << t;
  }
  EXPECT_EQ(tracker->num_filters(), 1U);
}

// A detection box with a non-finite side is no birth (a review: with
// confirm_hits 1 a NaN left was born as a NaN filter, a NaN width aborted on
// an empty box); a finite one in the same frame is.
TEST(MultiTargetTracker, NonFiniteDetectionsAreNeverBorn) {
  TrackerOptions o;
  o.init = InitMode::kDetections;
  o.particles = 50;
  o.management.confirm_hits = 1;
  o.management.confirm_window = 1;
  auto tracker = MakeTracker(o, Rng(5));
  const double nan = std::nan("");
  BoxPx left_nan = BoxPx::FromCentre(50, 50, 10, 10), width_nan = left_nan;
  left_nan.left = nan;
  width_nan.width = nan;
  const FrameReport r = tracker->Step(
      Frame(0, {{left_nan, 1.0}, {width_nan, 1.0}, {BoxPx::FromCentre(200, 80, 10, 10), 1.0}}));
  ASSERT_EQ(r.born.size(), 1U);
  ASSERT_EQ(r.filters.size(), 1U);
  // The estimate is the mean of 50 particles drawn around the detection (as
  // in FollowsAMovingTarget, 3 px).
  EXPECT_NEAR(r.filters[0].box.centre_x(), 200.0, 3.0);
  EXPECT_NEAR(r.filters[0].box.centre_y(), 80.0, 3.0);
}

// A track confirmed from detections describes its confirmation frame, so the
// frame reports it (tracks.txt has its box there), at the detection it was
// confirmed from, with uniform weights; before 2026-12-05 it appeared only from
// the next frame on (the audit's F6: one missed box per birth).
TEST(MultiTargetTracker, ATrackBornFromDetectionsIsReportedInItsConfirmationFrame) {
  TrackerOptions o;
  o.init = InitMode::kDetections;
  o.particles = 100;
  auto tracker = MakeTracker(o, Rng(5));
  FrameReport r;
  for (int t = 0; t < 3; ++t) {
    r = tracker->Step(Frame(t, {{BoxPx::FromCentre(50 + 2 * t, 50, 10, 10), 1.0}}));
    EXPECT_EQ(r.born.empty(), t < 2) << t;
  }
  ASSERT_EQ(r.filters.size(), 1U);
  const FilterReport& f = r.filters[0];
  EXPECT_EQ(f.id, TrackId{1});
  // 100 particles drawn 2 px about (54, 50): the mean's sd is 0.2 px, 1 px
  // is 5 of it. Width 10 with a log-scale spread of 0.05: the mean scale's
  // sd is 0.005, 0.5 px is 10 of it (0.05 px).
  EXPECT_NEAR(f.box.centre_x(), 54.0, 1.0);
  EXPECT_NEAR(f.box.centre_y(), 50.0, 1.0);
  EXPECT_NEAR(f.box.width, 10.0, 0.5);
  EXPECT_NEAR(f.ess, 100.0, 1e-9);  // uniform weights: 1 / (100 / 100^2)
  EXPECT_EQ(f.assigned_detection, 0);
  EXPECT_EQ(f.missed_frames, 0);
  EXPECT_FALSE(f.coasting);
  const auto rows = ToTrackEstimates(r, o.particles);
  ASSERT_EQ(rows.size(), 1U);
  EXPECT_EQ(rows[0].id, TrackId{1});
  EXPECT_NEAR(rows[0].confidence, 1.0, 1e-9);
}

// Noise-free dynamics and births: every particle of a filter moves as one.
TrackerOptions Exact(TrackerOptions o) {
  o.particles = 50;
  o.dynamics.sigma_pos_px = 0.0;
  o.dynamics.sigma_vel_px = 0.0;
  o.management.birth_sigma_px = 0.0;
  o.management.birth_sigma_vel_px = 0.0;
  o.management.birth_sigma_log_scale = 0.0;
  return o;
}

double MeanVx(const ParticleSet& p) {
  double sum = 0.0;
  for (const double v : p.vx) sum += v;
  return sum / static_cast<double>(p.size());
}

// The camera pans 5 px/frame (frames 1 on). A target static in the scene
// (own = 0), or moving +2 px/frame in it, is seen at 100 + (5 + own) t. Born
// from detections at the end of frame 2 (3 of 5), the filter's velocity is
// the target's own, and at frame 3 the camera's pan and that velocity put it
// at 100 + 3 (5 + own), the target's place. Before 2026-12-05 the velocity was
// 5 + own (the image displacement) and the camera's 5 px were counted twice:
// 5 px ahead at frame 3 (the audit's F3).
TEST(MultiTargetTracker, NewbornsFromDetectionsMoveWithTheCameraOnce) {
  const SimilarityMotion pan{.tx_px = 5.0};
  for (const double own : {0.0, 2.0}) {
    TrackerOptions o = Exact({});
    o.init = InitMode::kDetections;
    auto tracker = MakeTracker(o, Rng(9));
    const double step = 5.0 + own;
    FrameReport r;
    for (int t = 0; t < 4; ++t) {
      r = tracker->Step(Frame(t, {{BoxPx::FromCentre(100 + step * t, 80, 10, 10), 1.0}}),
                        t == 0 ? std::nullopt : std::optional(pan));
      EXPECT_EQ(r.born.size(), t == 2 ? 1U : 0U) << t;
      if (t == 2) {
        EXPECT_NEAR(MeanVx(*tracker->particles(TrackId{1})), own, 1e-12) << own;
      }
    }
    ASSERT_EQ(r.filters.size(), 1U);
    EXPECT_NEAR(r.filters[0].mean.x(), 100 + 3 * step, 1e-9) << own;
    EXPECT_NEAR(r.filters[0].mean.y(), 80.0, 1e-9) << own;
  }
}

// The same for a filter re-seeded by reacquire: filter 1 coasts at (100,
// 100) moved by the pan, 200 px from its target's labelled detections at
// 300 + (5 + own) t; they confirm at frame 2 and re-seed it with the target's
// own velocity, so at frame 3 it is at 300 + 3 (5 + own).
TEST(MultiTargetTracker, AReacquiredFilterMovesWithTheCameraOnce) {
  const SimilarityMotion pan{.tx_px = 5.0};
  for (const double own : {0.0, 2.0}) {
    TrackerOptions o = Exact({});
    o.management.reacquire = ReacquireMode::kOwnDetections;
    auto tracker = MakeTracker(o, Rng(10));
    tracker->BirthTrack(TrackId{1}, BoxPx::FromCentre(100, 100, 10, 10));
    const double step = 5.0 + own;
    FrameReport r;
    for (int t = 0; t < 4; ++t) {
      r = tracker->Step(Labelled(t, {{BoxPx::FromCentre(300 + step * t, 100, 10, 10), 0.9, 1}}),
                        t == 0 ? std::nullopt : std::optional(pan));
      EXPECT_EQ(r.reacquired.size(), t == 2 ? 1U : 0U) << t;
      if (t == 2) {
        EXPECT_NEAR(MeanVx(*tracker->particles(TrackId{1})), own, 1e-12) << own;
      }
    }
    ASSERT_EQ(r.filters.size(), 1U);
    EXPECT_FALSE(r.filters[0].coasting);
    EXPECT_NEAR(r.filters[0].mean.x(), 300 + 3 * step, 1e-9) << own;
  }
}

// A frame without detections between a re-acquisition's hits still carries
// its tentative through the camera's motion (and counts as a miss). The lost
// filter's target stands still in the scene under a pan of 5 px/frame: its
// detections at 300 (frame 0), none (frame 1), 310 and 315 (frames 2, 3).
// Three hits in four frames confirm at frame 3, the first hit carried
// through three pans to 315: velocity 0. Before, frame 1 was skipped, its
// pan never applied to the tentative, and the filter was born moving.
TEST(MultiTargetTracker, AFrameWithoutDetectionsStillCarriesAReacquisitionsTentative) {
  const SimilarityMotion pan{.tx_px = 5.0};
  TrackerOptions o = Exact({});
  o.management.reacquire = ReacquireMode::kOwnDetections;
  auto tracker = MakeTracker(o, Rng(10));
  tracker->BirthTrack(TrackId{1}, BoxPx::FromCentre(100, 100, 10, 10));
  const double xs[] = {300, 0, 310, 315};
  FrameReport r;
  for (int t = 0; t < 4; ++t) {
    std::vector<std::tuple<BoxPx, double, int32_t>> dets;
    if (t != 1) dets.push_back({BoxPx::FromCentre(xs[t], 100, 10, 10), 0.9, 1});
    r = tracker->Step(Labelled(t, dets), t == 0 ? std::nullopt : std::optional(pan));
  }
  ASSERT_EQ(r.reacquired, std::vector<TrackId>{TrackId{1}});
  EXPECT_NEAR(MeanVx(*tracker->particles(TrackId{1})), 0.0, 1e-12);
}

// A filter re-seeded by reacquire reports its new estimate in that frame,
// not the lost one; one deleted in the same frame and born again has one row,
// the new one. Filter 1 lost at (100, 100), its target's detections at
// 200 + t, confirmed at frame 2 (the filter's third unsupported frame).
TEST(MultiTargetTracker, AReacquiredFilterReportsItsNewEstimateInItsFrame) {
  for (const int max_missed : {30, 3}) {
    TrackerOptions o = Reacquiring(ReacquireMode::kOwnDetections);
    o.management.max_missed_frames = max_missed;
    auto tracker = MakeTracker(o, Rng(11));
    tracker->BirthTrack(TrackId{1}, BoxPx::FromCentre(100, 100, 10, 10));
    FrameReport r;
    for (int t = 0; t < 3; ++t) {
      r = tracker->Step(Labelled(t, {{BoxPx::FromCentre(200 + t, 100, 12, 12), 0.9, 1}}));
    }
    EXPECT_EQ(r.reacquired, std::vector<TrackId>{TrackId{1}});
    EXPECT_EQ(r.deleted.size(), max_missed == 3 ? 1U : 0U);
    ASSERT_EQ(r.filters.size(), 1U) << max_missed;
    const FilterReport& f = r.filters[0];
    EXPECT_EQ(f.id, TrackId{1});
    // 200 particles drawn 2 px about (202, 100): the mean's sd is 0.14 px;
    // 1 px is 7 of it, and 100 px short of the lost estimate.
    EXPECT_NEAR(f.box.centre_x(), 202.0, 1.0) << max_missed;
    EXPECT_NEAR(f.box.centre_y(), 100.0, 1.0) << max_missed;
    EXPECT_NEAR(f.box.width, 12.0, 0.6) << max_missed;
    EXPECT_EQ(f.assigned_detection, 0);
    EXPECT_EQ(f.missed_frames, 0);
    EXPECT_FALSE(f.coasting);
  }
}

TEST(MultiTargetTracker, CameraMotionIsAppliedBeforeDynamicsButNotToNewborns) {
  // Noise-free random walk and birth spread 0: all particles sit on the box
  // centre. Frame 0: born this frame, no predict, so the motion is ignored.
  // Frame 1: camera moved by (+5, -2) -> the estimate is (55, 48); scale
  // log 2 at frame 2 -> (110, 96) and the box doubles to 20 x 12.
  TrackerOptions o;
  o.particles = 20;
  o.dynamics.model = DynamicsModel::kRandomWalk;
  o.dynamics.sigma_pos_px = 0.0;
  o.management.birth_sigma_px = 0.0;
  o.management.birth_sigma_log_scale = 0.0;
  o.management.max_missed_frames = 0;
  auto tracker = MakeTracker(o, Rng(8));
  tracker->BirthTrack(TrackId{1}, BoxPx::FromCentre(50, 50, 10, 6));
  const SimilarityMotion shift{.tx_px = 5.0, .ty_px = -2.0};
  FrameReport r = tracker->Step(Frame(0, {}), shift);
  EXPECT_NEAR(r.filters[0].mean.x(), 50.0, 1e-12);
  r = tracker->Step(Frame(1, {}), shift);
  EXPECT_NEAR(r.filters[0].mean.x(), 55.0, 1e-12);
  EXPECT_NEAR(r.filters[0].mean.y(), 48.0, 1e-12);
  r = tracker->Step(Frame(2, {}), SimilarityMotion{.log_scale = std::log(2.0)});
  EXPECT_NEAR(r.filters[0].mean.x(), 110.0, 1e-9);
  EXPECT_NEAR(r.filters[0].mean.y(), 96.0, 1e-9);
  EXPECT_NEAR(r.filters[0].box.width, 20.0, 1e-9);
  EXPECT_NEAR(r.filters[0].box.height, 12.0, 1e-9);
}

TEST(MultiTargetTracker, VanishedWeightsAreRecoveredAndCounted) {
  // map likelihood with an all-zero map and no floor: every log-weight is
  // -inf. The frame is recovered (uniform weights), flagged and counted; no
  // NaN reaches the estimate.
  TrackerOptions o;
  o.particles = 50;
  o.likelihood.model = LikelihoodModel::kMap;
  o.likelihood.map_floor = 0.0;
  auto tracker = MakeTracker(o, Rng(6));
  tracker->BirthTrack(TrackId{1}, BoxPx::FromCentre(20, 20, 8, 8));
  Observation obs;
  obs.likelihood = LikelihoodMap{
      .width = 4, .height = 4, .cell_px = 10.0, .values = std::vector<float>(16, 0.0F)};
  const FrameReport r = tracker->Step(obs);
  EXPECT_EQ(r.degenerate_filters, 1);
  EXPECT_TRUE(r.filters[0].recovered_degenerate);
  EXPECT_TRUE(std::isfinite(r.filters[0].box.left));
  EXPECT_NEAR(r.filters[0].ess, 50.0, 1e-9);
}

}  // namespace
}  // namespace hcpf::tracker

namespace hcpf::tracker {
namespace {

// ---------------------------------------------------------------------------
// The composite assembled entirely from fake components: each fake does one
// visible, hand-checkable thing, so the test shows the order in which Step
// calls the roles and what it does with their answers.

struct Calls {
  int resamples = 0;
  std::vector<std::vector<size_t>> free_detections;  // what the initiator saw, per frame
};

class ShiftDynamics final : public Dynamics {  // every particle 3 px to the right
 public:
  void Predict(ParticleSet& set, Rng&) const override {
    for (double& x : set.px) x += 3.0;
  }
  std::string_view name() const override { return "shift"; }
};

class EvidenceLikelihood final : public Likelihood {  // weights untouched, evidence iff assigned
 public:
  bool HasEvidence(const LikelihoodInput& input) const override {
    return input.assigned != nullptr;
  }
  bool AddLogLikelihood(ParticleSet&, const LikelihoodInput&) const override { return false; }
  std::string_view name() const override { return "evidence"; }
};

class NoopInteraction final : public Interaction {
 public:
  void Apply(ParticleSet&, std::span<const FilterSummary>) const override {}
  std::string_view name() const override { return "noop"; }
};

class CountingResampler final : public Resampler {  // never resamples, counts calls
 public:
  explicit CountingResampler(Calls* calls) : calls_(calls) {}
  ResampleResult Resample(const ParticleSet&, const ResampleContext&, Rng&,
                          std::span<int32_t>) const override {
    ++calls_->resamples;
    return {.resampled = false};
  }
  std::string_view name() const override { return "counting"; }

 private:
  Calls* calls_;
};

class IndexAssociator final : public Associator {  // track i <- detection i, if present
 public:
  std::vector<int> Associate(std::span<const TrackPrediction> tracks,
                             std::span<const Detection> detections) const override {
    std::vector<int> out(tracks.size(), -1);
    for (size_t i = 0; i < tracks.size() && i < detections.size(); ++i)
      out[i] = static_cast<int>(i);
    return out;
  }
  std::string_view name() const override { return "index"; }
};

class FirstFrameInitiator final : public Initiator {  // births every free detection of frame 0
 public:
  explicit FirstFrameInitiator(Calls* calls) : calls_(calls) {}
  std::vector<Birth> Step(const Observation& observation, std::span<const size_t> free_detections,
                          const std::optional<SimilarityMotion>&) override {
    calls_->free_detections.emplace_back(free_detections.begin(), free_detections.end());
    std::vector<Birth> births;
    if (observation.frame != 0) return births;
    for (size_t d : free_detections) {
      births.push_back({observation.detections[d].box, {2.0, 0.0}, static_cast<int>(d)});
    }
    return births;
  }
  std::string_view name() const override { return "first_frame"; }

 private:
  Calls* calls_;
};

class OneMissDeleter final : public Deleter {  // ends a filter at its first unsupported frame
 public:
  bool Delete(int missed_frames) const override { return missed_frames >= 1; }
  std::string_view name() const override { return "one_miss"; }
};

Observation FrameWith(int frame, std::vector<BoxPx> boxes) {
  Observation o;
  o.frame = frame;
  for (const BoxPx& b : boxes) o.detections.push_back({.box = b});
  return o;
}

TEST(MultiTargetTracker, AssembledFromFakeComponents) {
  Calls calls;
  TrackerOptions options;
  options.particles = 8;
  // A newborn filter's particles sit exactly on the birth box.
  options.management.birth_sigma_px = 0.0;
  options.management.birth_sigma_vel_px = 0.0;
  options.management.birth_sigma_log_scale = 0.0;
  TrackerComponents parts{.dynamics = std::make_unique<ShiftDynamics>(),
                          .likelihood = std::make_unique<EvidenceLikelihood>(),
                          .interaction = std::make_unique<NoopInteraction>(),
                          .resampler = std::make_unique<CountingResampler>(&calls),
                          .associator = std::make_unique<IndexAssociator>(),
                          .initiator = std::make_unique<FirstFrameInitiator>(&calls),
                          .deleter = std::make_unique<OneMissDeleter>()};
  MultiTargetTracker tracker(options, std::move(parts), Rng(1));

  // Frame 0: no filter yet, so the one detection is free: the initiator
  // births track 1 at its box (centre 105, 105) after the filters have run,
  // and the frame reports it there, from detection 0, with uniform weights.
  FrameReport r = tracker.Step(FrameWith(0, {{100, 100, 10, 10}}));
  ASSERT_EQ(r.filters.size(), 1u);
  EXPECT_EQ(r.filters[0].id, TrackId{1});
  EXPECT_EQ(r.filters[0].box, (BoxPx{100, 100, 10, 10}));
  EXPECT_DOUBLE_EQ(r.filters[0].ess, 8.0);
  EXPECT_EQ(r.filters[0].assigned_detection, 0);
  EXPECT_FALSE(r.filters[0].coasting);
  EXPECT_EQ(r.filters[0].missed_frames, 0);
  ASSERT_EQ(r.born.size(), 1u);
  EXPECT_EQ(r.born[0], TrackId{1});
  EXPECT_EQ(tracker.num_filters(), 1u);

  // Frame 1: predict moves every particle 3 px right (105 -> 108); the
  // associator gives it detection 0, so the likelihood reports evidence, the
  // filter is not coasting and the resampler is asked (once). The assigned
  // detection is not free.
  r = tracker.Step(FrameWith(1, {{102, 100, 10, 10}}));
  ASSERT_EQ(r.filters.size(), 1u);
  EXPECT_DOUBLE_EQ(r.filters[0].mean.x(), 108.0);
  EXPECT_DOUBLE_EQ(r.filters[0].mean.y(), 105.0);
  EXPECT_EQ(r.filters[0].assigned_detection, 0);
  EXPECT_FALSE(r.filters[0].coasting);
  EXPECT_FALSE(r.filters[0].resampled);
  EXPECT_EQ(calls.resamples, 1);
  EXPECT_TRUE(r.deleted.empty());

  // Frame 2: no detection, so no support: the filter coasts (no resampling)
  // and the deleter ends it at its first miss.
  r = tracker.Step(FrameWith(2, {}));
  ASSERT_EQ(r.filters.size(), 1u);
  EXPECT_TRUE(r.filters[0].coasting);
  EXPECT_EQ(r.filters[0].missed_frames, 1);
  EXPECT_EQ(calls.resamples, 1);
  ASSERT_EQ(r.deleted.size(), 1u);
  EXPECT_EQ(r.deleted[0], TrackId{1});
  EXPECT_EQ(tracker.num_filters(), 0u);

  const std::vector<std::vector<size_t>> expected_free = {{0}, {}, {}};
  EXPECT_EQ(calls.free_detections, expected_free);
}

// Evidence on odd frames only, whatever the association.
class OddFramesLikelihood final : public Likelihood {
 public:
  bool HasEvidence(const LikelihoodInput& input) const override {
    return input.observation->frame % 2 == 1;
  }
  bool AddLogLikelihood(ParticleSet&, const LikelihoodInput&) const override { return false; }
  std::string_view name() const override { return "odd_frames"; }
};

class NeverDeleter final : public Deleter {
 public:
  bool Delete(int) const override { return false; }
  std::string_view name() const override { return "never"; }
};

// Support is what the likelihood says, not what the composite would infer
// from the association: the filter is given a detection every frame, yet it
// coasts and counts a miss on the frames its likelihood has no evidence.
TEST(MultiTargetTracker, SupportIsTheLikelihoodsVerdict) {
  Calls calls;
  TrackerOptions options;
  options.particles = 8;
  TrackerComponents parts{.dynamics = std::make_unique<ShiftDynamics>(),
                          .likelihood = std::make_unique<OddFramesLikelihood>(),
                          .interaction = std::make_unique<NoopInteraction>(),
                          .resampler = std::make_unique<CountingResampler>(&calls),
                          .associator = std::make_unique<IndexAssociator>(),
                          .initiator = std::make_unique<FirstFrameInitiator>(&calls),
                          .deleter = std::make_unique<NeverDeleter>()};
  MultiTargetTracker tracker(options, std::move(parts), Rng(1));
  tracker.Step(FrameWith(0, {{100, 100, 10, 10}}));
  ASSERT_EQ(tracker.num_filters(), 1u);
  const std::vector<bool> coasting_expected = {false, true, false, true};
  const std::vector<int> missed_expected = {0, 1, 0, 1};
  for (int frame = 1; frame <= 4; ++frame) {
    const FrameReport r = tracker.Step(FrameWith(frame, {{100, 100, 10, 10}}));
    ASSERT_EQ(r.filters.size(), 1u);
    EXPECT_EQ(r.filters[0].assigned_detection, 0) << frame;
    EXPECT_EQ(r.filters[0].coasting, coasting_expected[frame - 1]) << frame;
    EXPECT_EQ(r.filters[0].missed_frames, missed_expected[frame - 1]) << frame;
  }
  EXPECT_EQ(calls.resamples, 2);  // frames 1 and 3
}

// The evidence a `none` associator reports: a detection inside the gate.
TEST(NoAssociator, EvidenceIsADetectionInsideTheGate) {
  const NoAssociator none(AssociationOptions{});
  TrackPrediction near{.id = TrackId{1}, .mean = {100, 100}};
  near.cov = Eigen::Matrix2d::Identity() * 4.0;
  TrackPrediction far = near;
  far.id = TrackId{2};
  far.mean = {400, 400};
  const std::vector<TrackPrediction> tracks = {near, far};
  const std::vector<Detection> detections = {{.box = BoxPx::FromCentre(101, 100, 10, 10)}};
  const std::vector<int> assignment = none.Associate(tracks, detections);
  EXPECT_EQ(assignment, (std::vector<int>{-1, -1}));
  EXPECT_EQ(none.Evidence(tracks, detections, assignment), (std::vector<uint8_t>{1, 0}));
  // Other associators: the assigned detection.
  const GnnAssociator gnn(AssociationOptions{});
  const std::vector<int> paired = gnn.Associate(tracks, detections);
  EXPECT_EQ(gnn.Evidence(tracks, detections, paired), (std::vector<uint8_t>{1, 0}));
}

}  // namespace
}  // namespace hcpf::tracker
