#include "hcpf/tracker/dynamics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "hcpf/core/error.h"

namespace hcpf::tracker {
namespace {

ParticleSet Cloud(size_t n, double px, double py, double vx, double vy) {
  ParticleSet set;
  set.Resize(n);
  std::fill(set.px.begin(), set.px.end(), px);
  std::fill(set.py.begin(), set.py.end(), py);
  std::fill(set.vx.begin(), set.vx.end(), vx);
  std::fill(set.vy.begin(), set.vy.end(), vy);
  return set;
}

TEST(ConstantVelocityDynamics, NoNoiseMovesByVelocity) {
  ParticleSet set = Cloud(300, 10.0, 20.0, 2.0, -1.5);  // 300 crosses a 256-particle chunk
  Rng rng(1);
  ConstantVelocityDynamics(0.0, 0.0).Predict(set, rng);
  for (size_t i = 0; i < set.size(); ++i) {
    EXPECT_EQ(set.px[i], 12.0);
    EXPECT_EQ(set.py[i], 18.5);
    EXPECT_EQ(set.vx[i], 2.0);
    EXPECT_EQ(set.vy[i], -1.5);
  }
}

TEST(RandomWalkDynamics, NoNoiseLeavesParticlesAndVelocityIsUnused) {
  ParticleSet set = Cloud(10, 10.0, 20.0, 5.0, 5.0);
  Rng rng(1);
  RandomWalkDynamics(0.0).Predict(set, rng);
  EXPECT_EQ(set.px[3], 10.0);
  EXPECT_EQ(set.py[3], 20.0);
}

// Sample variance of v about `mean`.
double Variance(const std::vector<double>& v, double mean) {
  double s = 0.0;
  for (const double x : v) s += (x - mean) * (x - mean);
  return s / static_cast<double>(v.size());
}

TEST(ConstantVelocityDynamics, NoiseVariancesMatchSigmas) {
  // After one step from a point with v = 0: px ~ N(0, sp^2), vx ~ N(0, sv^2).
  // The sample variance of n normals has relative standard error sqrt(2/n)
  // = 3.2e-3 for n = 2e5; tolerance 5 standard errors = 1.6% relative.
  const size_t n = 200'000;
  ParticleSet set = Cloud(n, 0.0, 0.0, 0.0, 0.0);
  Rng rng(2);
  ConstantVelocityDynamics(1.5, 0.3).Predict(set, rng);
  EXPECT_NEAR(Variance(set.px, 0.0), 2.25, 2.25 * 0.016);
  EXPECT_NEAR(Variance(set.py, 0.0), 2.25, 2.25 * 0.016);
  EXPECT_NEAR(Variance(set.vx, 0.0), 0.09, 0.09 * 0.016);
  EXPECT_NEAR(Variance(set.vy, 0.0), 0.09, 0.09 * 0.016);
}

TEST(ConstantVelocityScaleDynamics, LogScaleVarianceMatches) {
  // log s ~ N(0, 0.1^2) after one step from s = 1; same 1.6% bound as above.
  const size_t n = 200'000;
  ParticleSet set = Cloud(n, 0.0, 0.0, 0.0, 0.0);
  Rng rng(3);
  ConstantVelocityScaleDynamics(0.0, 0.0, 0.1).Predict(set, rng);
  std::vector<double> log_s(n);
  for (size_t i = 0; i < n; ++i) log_s[i] = std::log(set.s[i]);
  EXPECT_NEAR(Variance(log_s, 0.0), 0.01, 0.01 * 0.016);
  EXPECT_EQ(set.px[0], 0.0);
}

TEST(Dynamics, SameRngStateSameResult) {
  for (const auto model : {DynamicsModel::kRandomWalk, DynamicsModel::kConstantVelocity,
                           DynamicsModel::kConstantVelocityScale}) {
    DynamicsOptions o;
    o.model = model;
    const auto dyn = MakeDynamics(o);
    ParticleSet a = Cloud(700, 1.0, 2.0, 0.5, 0.5), b = a;
    Rng ra(9), rb(9);
    dyn->Predict(a, ra);
    dyn->Predict(b, rb);
    EXPECT_EQ(a, b) << ToString(model);
    EXPECT_EQ(dyn->name(), ToString(model));
  }
}

TEST(ApplyCameraMotion, QuarterTurnPlusTranslation) {
  // a = cos(pi/2) = 0, b = 1: (x, y) -> (-y + tx, x + ty) = (-4 + 1, 3 + 2).
  ParticleSet set = Cloud(1, 3.0, 4.0, 1.0, 0.0);
  ApplyCameraMotion({.tx_px = 1.0, .ty_px = 2.0, .rotation_rad = std::numbers::pi / 2}, set);
  EXPECT_NEAR(set.px[0], -3.0, 1e-12);
  EXPECT_NEAR(set.py[0], 5.0, 1e-12);
  EXPECT_NEAR(set.vx[0], 0.0, 1e-12);  // velocity rotates, no translation
  EXPECT_NEAR(set.vy[0], 1.0, 1e-12);
  EXPECT_NEAR(set.s[0], 1.0, 1e-12);
}

TEST(ApplyCameraMotion, ZoomDoublesPositionVelocityAndSize) {
  ParticleSet set = Cloud(1, 3.0, 4.0, 1.0, -1.0);
  ApplyCameraMotion({.log_scale = std::log(2.0)}, set);
  EXPECT_NEAR(set.px[0], 6.0, 1e-12);
  EXPECT_NEAR(set.py[0], 8.0, 1e-12);
  EXPECT_NEAR(set.vx[0], 2.0, 1e-12);
  EXPECT_NEAR(set.vy[0], -2.0, 1e-12);
  EXPECT_NEAR(set.s[0], 2.0, 1e-12);
}

TEST(DynamicsOptions, DefaultsValidateAndNegativeSigmaIsNamed) {
  EXPECT_NO_THROW(DynamicsOptions{}.Validate());
  DynamicsOptions o;
  o.sigma_vel_px = -1.0;
  try {
    o.Validate();
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("tracker.dynamics.sigma_vel_px"), std::string::npos)
        << e.what();
  }
}

TEST(DynamicsModel, NamesRoundTrip) {
  for (const auto name : NamesOf<DynamicsModel>()) {
    const auto m = ParseName<DynamicsModel>(name);
    ASSERT_TRUE(m.has_value()) << name;
    EXPECT_EQ(ToString(*m), name);
  }
  EXPECT_FALSE(ParseName<DynamicsModel>("constant_acceleration").has_value());
}

}  // namespace
}  // namespace hcpf::tracker

namespace hcpf::tracker {
namespace {

// Contract suite over every dynamics model: weights untouched, deterministic
// given the Rng state, zero noise moves by the model's deterministic part only.
class DynamicsContract : public ::testing::TestWithParam<DynamicsModel> {};

TEST_P(DynamicsContract, LeavesWeightsAndIsDeterministic) {
  DynamicsOptions o;
  o.model = GetParam();
  const auto dyn = MakeDynamics(o);
  ParticleSet a = Cloud(513, 1.0, 2.0, 0.5, -0.5);
  a.log_w[7] = -3.0;
  const std::vector<double> log_w = a.log_w;
  ParticleSet b = a;
  Rng ra(4), rb(4);
  dyn->Predict(a, ra);
  dyn->Predict(b, rb);
  EXPECT_EQ(a, b);
  EXPECT_EQ(a.log_w, log_w);
  EXPECT_EQ(ra.NextU64(), rb.NextU64());
}

TEST_P(DynamicsContract, ZeroNoiseIsDeterministicMotion) {
  DynamicsOptions o;
  o.model = GetParam();
  o.sigma_pos_px = 0.0;
  o.sigma_vel_px = 0.0;
  o.sigma_log_scale = 0.0;
  ParticleSet set = Cloud(3, 10.0, 20.0, 2.0, 1.0);
  Rng rng(5);
  MakeDynamics(o)->Predict(set, rng);
  const bool moves = GetParam() != DynamicsModel::kRandomWalk;
  EXPECT_EQ(set.px[2], moves ? 12.0 : 10.0);
  EXPECT_EQ(set.py[2], moves ? 21.0 : 20.0);
  EXPECT_EQ(set.s[2], 1.0);
}

INSTANTIATE_TEST_SUITE_P(AllDynamics, DynamicsContract,
                         ::testing::ValuesIn(EnumValues<DynamicsModel>()),
                         [](const auto& info) { return std::string(ToString(info.param)); });

}  // namespace
}  // namespace hcpf::tracker
