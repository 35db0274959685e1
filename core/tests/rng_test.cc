#include "hcpf/core/rng.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <vector>

namespace hcpf {
namespace {

TEST(Rng, SameSeedGivesSameSequence) {
  Rng a(42), b(42);
  for (int i = 0; i < 100; ++i) ASSERT_EQ(a.NextU64(), b.NextU64());
}

TEST(Rng, DifferentSeedsDiffer) {
  Rng a(1), b(2);
  int equal = 0;
  for (int i = 0; i < 100; ++i) equal += a.NextU64() == b.NextU64();
  EXPECT_EQ(equal, 0);
}

TEST(Rng, ForkDependsOnNameNotOnParentDraws) {
  Rng parent(7);
  Rng before = parent.Fork("tracker/filter/1");
  for (int i = 0; i < 1000; ++i) parent.NextU64();
  Rng after = parent.Fork("tracker/filter/1");
  for (int i = 0; i < 50; ++i) ASSERT_EQ(before.NextU64(), after.NextU64());
  EXPECT_NE(parent.Fork("a").identity(), parent.Fork("b").identity());
  EXPECT_EQ(parent.Fork("frame", 3).identity(), parent.Fork("frame/3").identity());
  // A fork of a fork is not the same stream as a fork with the joined name
  // from the root: paths are hierarchical.
  EXPECT_NE(Rng(7).Fork("a").Fork("b").identity(), Rng(7).Fork("b").Fork("a").identity());
}

// The step is xoshiro256** as published: from state (1, 2, 3, 4) its first
// outputs are the reference sequence of Blackman and Vigna's C code (also
// the test vector of Rust's rand_xoshiro). And stepping a copy of an Rng's
// state() gives the numbers its NextU64 does (the renderer's noise lanes
// seed themselves so).
TEST(Rng, StepIsXoshiro256StarStarAndStateContinuesTheStream) {
  uint64_t s0 = 1, s1 = 2, s2 = 3, s3 = 4;
  const uint64_t expected[] = {11520u,
                               0u,
                               1509978240u,
                               1215971899390074240u,
                               1216172134540287360u,
                               607988272756665600u,
                               16172922978634559625u,
                               8476171486693032832u,
                               10595114339597558777u,
                               2904607092377533576u};
  for (const uint64_t e : expected) EXPECT_EQ(Xoshiro256StarStar(s0, s1, s2, s3), e);
  Rng rng = Rng(9).Fork("noise/lane", 3);
  for (int i = 0; i < 5; ++i) rng.NextU64();
  std::array<uint64_t, 4> s = rng.state();
  for (int i = 0; i < 100; ++i)
    ASSERT_EQ(Xoshiro256StarStar(s[0], s[1], s[2], s[3]), rng.NextU64());
}

// Moments of 200,000 draws. The standard error of a uniform mean is
// sqrt(1/12/n) = 6.5e-4 and of a normal mean 1/sqrt(n) = 2.2e-3; the bounds
// below are 5 standard errors, so a correct generator fails with p < 1e-6.
TEST(Rng, UniformAndNormalMoments) {
  Rng rng(123);
  const int n = 200000;
  double su = 0, sn = 0, sn2 = 0;
  double umin = 1, umax = 0;
  for (int i = 0; i < n; ++i) {
    const double u = rng.Uniform();
    su += u;
    umin = std::min(umin, u);
    umax = std::max(umax, u);
    const double z = rng.Normal();
    sn += z;
    sn2 += z * z;
  }
  EXPECT_NEAR(su / n, 0.5, 5 * std::sqrt(1.0 / 12.0 / n));
  EXPECT_GE(umin, 0.0);
  EXPECT_LT(umax, 1.0);
  EXPECT_NEAR(sn / n, 0.0, 5.0 / std::sqrt(n));
  // Var of the sample variance of N(0,1) is 2/n: 5 sigma = 5*sqrt(2/n) = 0.016.
  EXPECT_NEAR(sn2 / n, 1.0, 5 * std::sqrt(2.0 / n));
}

TEST(Rng, UniformIntCoversRangeEvenly) {
  Rng rng(5);
  std::vector<int> counts(7, 0);
  const int n = 70000;
  for (int i = 0; i < n; ++i) {
    const uint64_t k = rng.UniformInt(7);
    ASSERT_LT(k, 7u);
    ++counts[k];
  }
  // Each count is Binomial(n, 1/7): sd = sqrt(n p (1-p)) = 92.6; 5 sd = 463.
  for (int c : counts) EXPECT_NEAR(c, n / 7, 463);
}

TEST(Rng, PoissonMeanAndVariance) {
  for (double lambda : {0.0, 0.5, 3.0, 40.0}) {
    Rng rng(9);
    const int n = 50000;
    double s = 0, s2 = 0;
    for (int i = 0; i < n; ++i) {
      const double k = static_cast<double>(rng.Poisson(lambda));
      ASSERT_GE(k, 0.0);
      s += k;
      s2 += k * k;
    }
    const double mean = s / n;
    // Mean of n Poisson draws has sd sqrt(lambda/n); 5 sd (+1e-12 for lambda 0).
    EXPECT_NEAR(mean, lambda, 5 * std::sqrt(lambda / n) + 1e-12) << lambda;
    EXPECT_NEAR(s2 / n - mean * mean, lambda, 0.05 * lambda + 1e-12) << lambda;
  }
}

}  // namespace
}  // namespace hcpf
