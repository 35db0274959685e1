// The thesis's claim in miniature: with the detections_mixture likelihood (no
// association), a weak target's filter next to a strong target is hijacked by
// it under systematic resampling; charged resampling keeps it on its own target.
#include <gtest/gtest.h>

#include <cmath>

#include "hcpf/tracker/tracker.h"

namespace hcpf::tracker {
namespace {

// Strong target A (score 1.0) and weak target B (score 0.25) move right at
// 1 px/frame, B 12 px below A (4 sigma of the likelihood), for 50 frames; then
// B turns away (down 2 px/frame) for 30 frames. Exact detections every frame.
// Returns true when B's filter ends nearer to A than to B (hijacked).
struct Outcome {
  bool b_hijacked = false;
  bool a_lost = false;
};

Outcome RunPair(ResamplingMethod method, uint64_t seed, double offset_px = 12.0,
                InteractionModel interaction = InteractionModel::kNone) {
  TrackerOptions o;
  o.particles = 300;
  o.association.method = AssociationMethod::kNone;
  o.likelihood.model = LikelihoodModel::kDetectionsMixture;
  o.likelihood.sigma_px = 3.0;
  o.resampling.method = method;
  o.interaction.model = interaction;
  o.interaction.lambda = 5.0;
  o.resampling.beta = 4.0;
  o.resampling.softening_px = 4.0;
  o.management.max_missed_frames = 0;
  auto tracker = MakeTracker(o, Rng(seed));
  auto a_at = [](int t) { return Eigen::Vector2d(100.0 + t, 100.0); };
  auto b_at = [offset_px](int t) {
    return Eigen::Vector2d(100.0 + t, 100.0 + offset_px + (t > 50 ? 2.0 * (t - 50) : 0.0));
  };
  tracker->BirthTrack(TrackId{1}, BoxPx::FromCentre(a_at(0).x(), a_at(0).y(), 16, 16),
                      Eigen::Vector2d(1.0, 0.0));
  tracker->BirthTrack(TrackId{2}, BoxPx::FromCentre(b_at(0).x(), b_at(0).y(), 16, 16),
                      Eigen::Vector2d(1.0, 0.0));
  FrameReport r;
  const int frames = 80;
  for (int t = 0; t < frames; ++t) {
    Observation obs;
    obs.frame = t;
    obs.detections.push_back(
        {.box = BoxPx::FromCentre(a_at(t).x(), a_at(t).y(), 16, 16), .score = 1.0});
    obs.detections.push_back(
        {.box = BoxPx::FromCentre(b_at(t).x(), b_at(t).y(), 16, 16), .score = 0.25});
    r = tracker->Step(obs);
  }
  const Eigen::Vector2d a_end = a_at(frames - 1);
  const Eigen::Vector2d b_end = b_at(frames - 1);
  Outcome out;
  for (const FilterReport& f : r.filters) {
    const double to_a = (f.mean - a_end).norm();
    const double to_b = (f.mean - b_end).norm();
    if (f.id == TrackId{2}) out.b_hijacked = to_a < to_b;
    if (f.id == TrackId{1}) out.a_lost = to_a > 10.0;
  }
  return out;
}

TEST(Hijack, ChargedResamplingHijackedLessThanSystematic) {
  int systematic = 0;
  int charged = 0;
  int a_lost = 0;
  const int seeds = 12;
  for (uint64_t seed = 1; seed <= seeds; ++seed) {
    systematic += RunPair(ResamplingMethod::kSystematic, seed).b_hijacked ? 1 : 0;
    const Outcome c = RunPair(ResamplingMethod::kCharged, seed);
    charged += c.b_hijacked ? 1 : 0;
    a_lost += c.a_lost ? 1 : 0;
  }
  RecordProperty("systematic_hijacks", systematic);
  RecordProperty("charged_hijacks", charged);
  std::printf("hijacked runs out of %d: systematic %d, charged %d (A lost under charged: %d)\n",
              seeds, systematic, charged, a_lost);
  // Deterministic for these seeds (measured: systematic 12/12, charged 0/12).
  // The outcome of one run is seed-dependent, so the bounds leave a quarter
  // of the runs as margin on each side rather than demanding 12 and 0.
  EXPECT_GE(systematic, 9);
  EXPECT_LE(charged, 3);
  EXPECT_EQ(a_lost, 0);
}

TEST(Hijack, MrfInteractionBaselineAlsoPreventsItHere) {
  // The Khan-Balch-Dellaert factor on the weights (lambda 5, r 10 px) in the
  // same scenario and seeds. Measured: 0 of 12 hijacked (lambda 2: 10 of 12,
  // so the penalty must outweigh the 4:1 score ratio, log 4 = 1.4, at the
  // strong target's centre). Same margin reasoning as above.
  int mrf = 0;
  for (uint64_t seed = 1; seed <= 12; ++seed) {
    mrf += RunPair(ResamplingMethod::kSystematic, seed, 12.0, InteractionModel::kMrf).b_hijacked
               ? 1
               : 0;
  }
  std::printf("hijacked runs out of 12: systematic + mrf(lambda 5) %d\n", mrf);
  EXPECT_LE(mrf, 3);
}

TEST(Hijack, FarApartTargetsAreTrackedAlikeByBoth) {
  // B 200 px below A: the repulsion is exp(-200^2 / (2 (Sigma + eps^2))) ~ 0,
  // no filter is hijacked or loses its target under either resampler.
  for (uint64_t seed = 1; seed <= 6; ++seed) {
    for (const auto m : {ResamplingMethod::kSystematic, ResamplingMethod::kCharged}) {
      const Outcome o = RunPair(m, seed, 200.0);
      EXPECT_FALSE(o.b_hijacked) << ToString(m) << " seed " << seed;
      EXPECT_FALSE(o.a_lost) << ToString(m) << " seed " << seed;
    }
  }
}

}  // namespace
}  // namespace hcpf::tracker
