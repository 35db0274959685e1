#include "hcpf/tracker/particle_set.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace hcpf::tracker {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(NormaliseLogWeights, HandComputedValues) {
  // log-weights log(1), log(3): normalised weights 1/4 and 3/4, log-total log 4.
  ParticleSet set;
  set.Resize(2);
  set.log_w = {0.0, std::log(3.0)};
  const NormaliseResult r = NormaliseLogWeights(set);
  EXPECT_FALSE(r.recovered_degenerate);
  EXPECT_NEAR(r.log_total, std::log(4.0), 1e-15);
  EXPECT_NEAR(set.w[0], 0.25, 1e-15);
  EXPECT_NEAR(set.w[1], 0.75, 1e-15);
  EXPECT_NEAR(set.log_w[0], std::log(0.25), 1e-15);
}

TEST(NormaliseLogWeights, HugeOffsetsDoNotOverflow) {
  // -1000 and -1001: exp underflows in linear space; log-sum-exp keeps the
  // ratio e : 1, so w = e/(1+e), 1/(1+e).
  ParticleSet set;
  set.Resize(2);
  set.log_w = {-1000.0, -1001.0};
  NormaliseLogWeights(set);
  const double e = std::exp(1.0);
  EXPECT_NEAR(set.w[0], e / (1 + e), 1e-14);
  EXPECT_NEAR(set.w[1], 1 / (1 + e), 1e-14);
}

TEST(NormaliseLogWeights, MinusInfinityWeightGetsZero) {
  ParticleSet set;
  set.Resize(3);
  set.log_w = {0.0, -kInf, 0.0};
  NormaliseLogWeights(set);
  EXPECT_EQ(set.w[1], 0.0);
  EXPECT_NEAR(set.w[0], 0.5, 1e-15);
}

TEST(NormaliseLogWeights, AllVanishedResetsToUniformAndFlagsIt) {
  ParticleSet set;
  set.Resize(4);
  set.log_w = {-kInf, std::nan(""), -kInf, std::nan("")};
  const NormaliseResult r = NormaliseLogWeights(set);
  EXPECT_TRUE(r.recovered_degenerate);
  EXPECT_EQ(r.nan_weights, 2);
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(set.w[i], 0.25);
    EXPECT_FALSE(std::isnan(set.log_w[i]));
  }
}

TEST(NormaliseLogWeights, SingleNaNBecomesZeroWeight) {
  ParticleSet set;
  set.Resize(2);
  set.log_w = {std::nan(""), 1.0};
  const NormaliseResult r = NormaliseLogWeights(set);
  EXPECT_FALSE(r.recovered_degenerate);
  EXPECT_EQ(r.nan_weights, 1);
  EXPECT_EQ(set.w[0], 0.0);
  EXPECT_EQ(set.w[1], 1.0);
}

TEST(EffectiveSampleSize, HandValues) {
  // Uniform over 4 -> 4; (0.5, 0.5, 0, 0) -> 2; (1, 0) -> 1.
  EXPECT_DOUBLE_EQ(EffectiveSampleSize(std::vector<double>{0.25, 0.25, 0.25, 0.25}), 4.0);
  EXPECT_DOUBLE_EQ(EffectiveSampleSize(std::vector<double>{0.5, 0.5, 0.0, 0.0}), 2.0);
  EXPECT_DOUBLE_EQ(EffectiveSampleSize(std::vector<double>{1.0, 0.0}), 1.0);
}

TEST(Summarise, WeightedMomentsByHand) {
  // Points (0,0) w 0.25, (4,0) w 0.75: mean x = 3, var x = 0.25*9 + 0.75*1 = 3,
  // y constant 2 -> var 0, cov 0.
  ParticleSet set;
  set.Resize(2);
  set.px = {0.0, 4.0};
  set.py = {2.0, 2.0};
  set.s = {1.0, 2.0};
  set.log_w = {std::log(0.25), std::log(0.75)};
  NormaliseLogWeights(set);
  const FilterSummary s = Summarise(set, TrackId{7});
  EXPECT_EQ(s.id, TrackId{7});
  EXPECT_NEAR(s.mean.x(), 3.0, 1e-14);
  EXPECT_NEAR(s.mean.y(), 2.0, 1e-14);
  EXPECT_NEAR(s.cov(0, 0), 3.0, 1e-13);
  EXPECT_NEAR(s.cov(1, 1), 0.0, 1e-14);
  EXPECT_NEAR(s.cov(0, 1), 0.0, 1e-14);
  EXPECT_NEAR(s.mean_scale, 0.25 * 1 + 0.75 * 2, 1e-14);
  // ESS = 1 / (0.0625 + 0.5625) = 1.6
  EXPECT_NEAR(s.ess, 1.6, 1e-13);
}

TEST(ApplyAncestors, GathersEveryComponentAndResetsWeights) {
  ParticleSet set, scratch;
  set.Resize(3);
  set.px = {1, 2, 3};
  set.py = {4, 5, 6};
  set.vx = {7, 8, 9};
  set.vy = {10, 11, 12};
  set.s = {13, 14, 15};
  const std::vector<int32_t> a = {2, 2, 0};
  ApplyAncestors(set, a, scratch);
  EXPECT_EQ(set.px, (std::vector<double>{3, 3, 1}));
  EXPECT_EQ(set.py, (std::vector<double>{6, 6, 4}));
  EXPECT_EQ(set.vx, (std::vector<double>{9, 9, 7}));
  EXPECT_EQ(set.vy, (std::vector<double>{12, 12, 10}));
  EXPECT_EQ(set.s, (std::vector<double>{15, 15, 13}));
  for (const double w : set.w) EXPECT_DOUBLE_EQ(w, 1.0 / 3.0);
}

}  // namespace
}  // namespace hcpf::tracker
