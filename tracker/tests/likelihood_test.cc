#include "hcpf/tracker/likelihood.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace hcpf::tracker {
namespace {

// The mixture's exp is single precision: FastExpF's own relative error is
// < 1.5e-7 (fast_math_test.cc) and rounding the exponent e to float adds
// 2^-24 |e| more. L is a sum of positive terms plus the exact clutter floor,
// so L's relative error, hence log L's absolute error, is below the largest
// term's: 2e-7 + 2^-24 max|e| (2e-7 leaves room for the double rounding
// around it). The hand cases below have |e| <= 2. Against a wrong component
// (weight, normaliser, distance) the errors are > 1e-3.
constexpr double kMixtureTol = 2e-7 + 0x1p-24 * 2.0;

ParticleSet At(std::vector<std::pair<double, double>> points) {
  ParticleSet set;
  set.Resize(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    set.px[i] = points[i].first;
    set.py[i] = points[i].second;
  }
  std::fill(set.log_w.begin(), set.log_w.end(), 0.0);
  return set;
}

Detection Det(double cx, double cy, double score = 1.0, double w = 10.0) {
  return {.box = BoxPx::FromCentre(cx, cy, w, w), .score = score};
}

TEST(AssociatedLikelihood, HandComputedGaussian) {
  // sigma 2, detection centre (10, 10), particle (13, 14): d^2 = 25,
  // log N = -log(2 pi 4) - 25 / 8 = -3.224171 - 3.125 = -6.349171.
  LikelihoodOptions o;
  o.sigma_px = 2.0;
  AssociatedLikelihood lik(o);
  ParticleSet set = At({{13.0, 14.0}});
  Observation obs;
  obs.detections = {Det(10.0, 10.0)};
  EXPECT_TRUE(lik.AddLogLikelihood(set, {.observation = &obs, .assigned = &obs.detections[0]}));
  EXPECT_NEAR(set.log_w[0], -6.349171427529, 1e-9);
}

TEST(AssociatedLikelihood, NoAssignedDetectionIsFlat) {
  AssociatedLikelihood lik(LikelihoodOptions{});
  ParticleSet set = At({{1.0, 2.0}});
  Observation obs;
  obs.detections = {Det(1.0, 2.0)};
  EXPECT_FALSE(lik.AddLogLikelihood(set, {.observation = &obs, .assigned = nullptr}));
  EXPECT_EQ(set.log_w[0], 0.0);
}

TEST(DetectionsMixtureLikelihood, HandComputedMixtureWithClutter) {
  // sigma 1, clutter 0.01, detections (0,0) score 1 and (3,0) score 0.5,
  // particle (1,0): d^2 = 1 and 4;
  // L = 0.01 + e^-0.5 / (2 pi) + 0.5 e^-2 / (2 pi)
  //   = 0.01 + 0.0965324 + 0.0107696 = 0.1173020, log L = -2.1430035.
  LikelihoodOptions o;
  o.sigma_px = 1.0;
  o.clutter_density = 0.01;
  DetectionsMixtureLikelihood lik(o);
  ParticleSet set = At({{1.0, 0.0}});
  Observation obs;
  obs.detections = {Det(0.0, 0.0, 1.0), Det(3.0, 0.0, 0.5)};
  EXPECT_TRUE(lik.AddLogLikelihood(set, {.observation = &obs}));
  EXPECT_NEAR(set.log_w[0], -2.1430035389744, kMixtureTol);
}

TEST(DetectionsMixtureLikelihood, ScoresIgnoredWhenAsked) {
  // use_scores = false: both components weigh 1: L = 0.01 + (e^-0.5 + e^-2)/(2 pi).
  LikelihoodOptions o;
  o.sigma_px = 1.0;
  o.clutter_density = 0.01;
  o.use_scores = false;
  DetectionsMixtureLikelihood lik(o);
  ParticleSet set = At({{1.0, 0.0}});
  Observation obs;
  obs.detections = {Det(0.0, 0.0, 1.0), Det(3.0, 0.0, 0.5)};
  lik.AddLogLikelihood(set, {.observation = &obs});
  const double expected =
      std::log(0.01 + (std::exp(-0.5) + std::exp(-2.0)) / (2.0 * std::numbers::pi));
  EXPECT_NEAR(set.log_w[0], expected, kMixtureTol);
}

TEST(DetectionsMixtureLikelihood, FarParticleWithoutClutterStaysFinite) {
  // Particle at (10000, 0), no clutter: linear-space terms underflow; the exact
  // log-sum-exp fallback gives the nearer component (3, 0), score 0.5:
  // log(0.5 / (2 pi)) - 9997^2 / 2, the other term e^{-(10000^2-9997^2)/2} ~ 0.
  LikelihoodOptions o;
  o.sigma_px = 1.0;
  o.clutter_density = 0.0;
  DetectionsMixtureLikelihood lik(o);
  ParticleSet set = At({{10000.0, 0.0}, {1.0, 0.0}});
  Observation obs;
  obs.detections = {Det(0.0, 0.0, 1.0), Det(3.0, 0.0, 0.5)};
  lik.AddLogLikelihood(set, {.observation = &obs});
  const double expected = std::log(0.5 / (2.0 * std::numbers::pi)) - 9997.0 * 9997.0 / 2.0;
  EXPECT_NEAR(set.log_w[0], expected, 1e-6);
  EXPECT_TRUE(std::isfinite(set.log_w[1]));
}

TEST(DetectionsMixtureLikelihood, NonFiniteDetectionsAreIgnored) {
  // A NaN or infinite box must not turn weights into NaN: the mixture of the
  // remaining detection equals the single-detection value, and a frame of only
  // broken detections is flat.
  LikelihoodOptions o;
  o.sigma_px = 1.0;
  o.clutter_density = 0.01;
  DetectionsMixtureLikelihood lik(o);
  ParticleSet with_bad = At({{1.0, 0.0}});
  ParticleSet clean = At({{1.0, 0.0}});
  Observation bad;
  bad.detections = {Det(std::nan(""), 0.0), Det(0.0, 0.0), Det(INFINITY, 3.0)};
  Observation good;
  good.detections = {Det(0.0, 0.0)};
  lik.AddLogLikelihood(with_bad, {.observation = &bad});
  lik.AddLogLikelihood(clean, {.observation = &good});
  EXPECT_EQ(with_bad.log_w[0], clean.log_w[0]);
  Observation only_bad;
  only_bad.detections = {Det(std::nan(""), 1.0)};
  ParticleSet set = At({{1.0, 0.0}});
  EXPECT_FALSE(lik.AddLogLikelihood(set, {.observation = &only_bad}));
  EXPECT_EQ(set.log_w[0], 0.0);
}

TEST(DetectionsMixtureLikelihood, NoDetectionsIsFlat) {
  DetectionsMixtureLikelihood lik(LikelihoodOptions{});
  ParticleSet set = At({{1.0, 0.0}});
  Observation obs;
  EXPECT_FALSE(lik.AddLogLikelihood(set, {.observation = &obs}));
  EXPECT_EQ(set.log_w[0], 0.0);
}

TEST(DetectionsMixtureLikelihood, SizeTermHandValue) {
  // Particle on the detection centre, s = 2, base width 10, detection width 10:
  // log-size error log(20/10) = log 2; sigma_log_size 0.5, sigma 1, no clutter:
  // log L = -log(2 pi) - log(sqrt(2 pi) 0.5) - (log 2)^2 / (2 0.25).
  LikelihoodOptions o;
  o.sigma_px = 1.0;
  o.clutter_density = 0.0;
  o.sigma_log_size = 0.5;
  DetectionsMixtureLikelihood lik(o);
  ParticleSet set = At({{5.0, 5.0}});
  set.s[0] = 2.0;
  Observation obs;
  obs.detections = {Det(5.0, 5.0, 1.0, 10.0)};
  lik.AddLogLikelihood(set, {.observation = &obs, .base_w_px = 10.0, .base_h_px = 10.0});
  const double l2 = std::log(2.0);
  const double expected = -std::log(2 * std::numbers::pi) -
                          std::log(std::sqrt(2 * std::numbers::pi) * 0.5) - l2 * l2 / 0.5;
  EXPECT_NEAR(set.log_w[0], expected, kMixtureTol);
}

TEST(DetectionsMixtureLikelihood, ManyParticlesMatchScalarFormula) {
  // 1000 particles (several 256 chunks) against the formula evaluated here
  // with std::exp/std::log: the vectorised path must agree to kMixtureTol.
  LikelihoodOptions o;
  o.sigma_px = 3.0;
  o.clutter_density = 1e-5;
  DetectionsMixtureLikelihood lik(o);
  Observation obs;
  for (int d = 0; d < 7; ++d) obs.detections.push_back(Det(10.0 * d, 5.0 * d, 0.2 + 0.1 * d));
  std::vector<std::pair<double, double>> pts;
  for (int i = 0; i < 1000; ++i) pts.emplace_back(0.07 * i, 0.035 * i + 3.0);
  ParticleSet set = At(pts);
  lik.AddLogLikelihood(set, {.observation = &obs});
  for (size_t i = 0; i < pts.size(); ++i) {
    double l = 1e-5;
    double max_abs_e = 0.0;
    for (const Detection& d : obs.detections) {
      const double dx = pts[i].first - d.box.centre_x();
      const double dy = pts[i].second - d.box.centre_y();
      const double e = -(dx * dx + dy * dy) / 18.0;
      l += d.score / (2 * std::numbers::pi * 9.0) * std::exp(e);
      if (e > -87.0) max_abs_e = std::max(max_abs_e, -e);
    }
    // The bound of kMixtureTol with this particle's largest |e| (terms below
    // -87 are flushed, and are negligible against the clutter floor here).
    ASSERT_NEAR(set.log_w[i], std::log(l), 2e-7 + 0x1p-24 * max_abs_e) << i;
  }
}

// Without clutter, terms past the vectorised exp's flush limit (exponent
// -87, 13.2σ) are not negligible against a sum that is itself near it: a
// particle at exponent -86.5 from one detection and -87.5 from ten others
// lost the ten (1.54 nats, a review). Such particles are recomputed exactly;
// along a line from 0 to 25σ every particle matches the formula to the fast
// path's bound.
TEST(DetectionsMixtureLikelihood, TermsPastTheFlushLimitCountWithoutClutter) {
  LikelihoodOptions o;
  o.sigma_px = 3.0;  // exponent -d² / 18
  o.clutter_density = 0.0;
  DetectionsMixtureLikelihood lik(o);
  Observation obs;
  obs.detections.push_back(Det(std::sqrt(86.5 * 18.0), 0.0));
  for (int k = 0; k < 10; ++k) {
    const double angle = 0.5 + 0.2 * k;
    const double r = std::sqrt(87.5 * 18.0);
    obs.detections.push_back(Det(r * std::cos(angle), r * std::sin(angle)));
  }
  const double w = 1.0 / (2.0 * std::numbers::pi * 9.0);
  ParticleSet one = At({{0.0, 0.0}});
  lik.AddLogLikelihood(one, {.observation = &obs});
  const double exact = std::log(w) + std::log(std::exp(-86.5) + 10.0 * std::exp(-87.5));
  EXPECT_NEAR(one.log_w[0], exact, 1e-9);

  std::vector<std::pair<double, double>> pts;
  for (int i = 0; i <= 500; ++i) pts.emplace_back(-0.15 * i, -0.05 * i);  // 0 … 25σ
  ParticleSet set = At(pts);
  lik.AddLogLikelihood(set, {.observation = &obs});
  for (size_t i = 0; i < pts.size(); ++i) {
    double max_term = -INFINITY;
    std::vector<double> terms;
    for (const Detection& d : obs.detections) {
      const double dx = pts[i].first - d.box.centre_x();
      const double dy = pts[i].second - d.box.centre_y();
      terms.push_back(std::log(w) - (dx * dx + dy * dy) / 18.0);
      max_term = std::max(max_term, terms.back());
    }
    double total = 0.0;
    for (const double t : terms) total += std::exp(t - max_term);
    // The fast path's bound at this particle's largest exponent (as in
    // ManyParticlesMatchScalarFormula); exact particles are well inside it.
    const double e = std::log(w) - max_term;
    ASSERT_NEAR(set.log_w[i], max_term + std::log(total), 2e-7 + 0x1p-24 * std::abs(e) + 1e-9) << i;
  }
}

TEST(MapLikelihood, BilinearSampleAndFloor) {
  // 2x2 cells of 10 px, values [[0, 1], [2, 3]]: (10, 10) is midway between
  // the four cell centres -> 1.5; (5, 5) is cell (0,0)'s centre -> 0 -> floor.
  LikelihoodOptions o;
  o.model = LikelihoodModel::kMap;
  o.map_floor = 1e-9;
  MapLikelihood lik(o);
  Observation obs;
  obs.likelihood = LikelihoodMap{.width = 2, .height = 2, .cell_px = 10.0, .values = {0, 1, 2, 3}};
  ParticleSet set = At({{10.0, 10.0}, {5.0, 5.0}});
  EXPECT_TRUE(lik.AddLogLikelihood(set, {.observation = &obs}));
  EXPECT_NEAR(set.log_w[0], std::log(1.5 + 1e-9), 1e-12);
  EXPECT_NEAR(set.log_w[1], std::log(1e-9), 1e-12);
}

TEST(MapLikelihood, MissingMapIsFlat) {
  LikelihoodOptions o;
  o.model = LikelihoodModel::kMap;
  MapLikelihood lik(o);
  Observation obs;
  ParticleSet set = At({{1.0, 1.0}});
  EXPECT_FALSE(lik.AddLogLikelihood(set, {.observation = &obs}));
  EXPECT_EQ(set.log_w[0], 0.0);
}

// Each model's verdict on a frame's evidence, which the tracker uses as the
// filter's support: the assigned detection, the associator's evidence (every
// detection enters the mixture, but not every one is this filter's), a map.
TEST(LikelihoodModel, EachModelSaysWhenAFrameHoldsEvidence) {
  Observation obs;
  obs.detections = {Det(1.0, 2.0)};
  const LikelihoodInput nothing{.observation = &obs};
  const LikelihoodInput assigned{
      .observation = &obs, .assigned = &obs.detections[0], .detection_evidence = true};
  const LikelihoodInput gated{.observation = &obs, .detection_evidence = true};
  LikelihoodOptions o;
  const AssociatedLikelihood associated(o);
  EXPECT_FALSE(associated.HasEvidence(nothing));
  EXPECT_FALSE(associated.HasEvidence(gated));
  EXPECT_TRUE(associated.HasEvidence(assigned));
  const DetectionsMixtureLikelihood mixture(o);
  EXPECT_FALSE(mixture.HasEvidence(nothing));  // detections, but none of them this filter's
  EXPECT_TRUE(mixture.HasEvidence(gated));
  EXPECT_TRUE(mixture.HasEvidence(assigned));
  o.model = LikelihoodModel::kMap;
  const MapLikelihood map(o);
  EXPECT_FALSE(map.HasEvidence(assigned));
  obs.likelihood = LikelihoodMap{.width = 1, .height = 1, .cell_px = 1.0, .values = {0}};
  EXPECT_TRUE(map.HasEvidence(nothing));
}

TEST(LikelihoodModel, NamesRoundTripAndFactoryMatches) {
  for (const auto name : NamesOf<LikelihoodModel>()) {
    const auto m = ParseName<LikelihoodModel>(name);
    ASSERT_TRUE(m.has_value()) << name;
    LikelihoodOptions o;
    o.model = *m;
    EXPECT_EQ(MakeLikelihood(o)->name(), name);
  }
}

}  // namespace
}  // namespace hcpf::tracker
