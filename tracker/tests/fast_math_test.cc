// FastExp / FastLog against libm, and the ziggurat normal generator.
#include "fast_math.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "hcpf/core/rng.h"
#include "hcpf/tracker/normal.h"

namespace hcpf::tracker {
namespace {

using internal::FastExp;
using internal::FastLog;

TEST(FastExp, MatchesStdExpToFewUlpsOverTheUsedRange) {
  // The header derives a truncation error ~1.7e-16; with rounding in the
  // reduction and Horner steps a handful of ulps (1e-15 relative) is the
  // bound we accept.
  double worst = 0.0;
  for (double x = -700.0; x <= 700.0; x += 0.01173) {
    const double ref = std::exp(x);
    worst = std::max(worst, std::abs(FastExp(x) - ref) / ref);
  }
  EXPECT_LT(worst, 1e-15);
  EXPECT_EQ(FastExp(0.0), 1.0);
}

TEST(FastExp, UnderflowsToZeroAndNeverNaN) {
  EXPECT_EQ(FastExp(-709.0), 0.0);
  EXPECT_EQ(FastExp(-1e300), 0.0);
  EXPECT_EQ(FastExp(-std::numeric_limits<double>::infinity()), 0.0);
  EXPECT_TRUE(std::isfinite(FastExp(1e6)));  // clamped at exp(709)
}

TEST(FastLog, MatchesStdLogToFewUlps) {
  double worst_abs = 0.0;
  for (double x = 1e-300; x < 1e300; x *= 1.0137) {
    worst_abs = std::max(worst_abs,
                         std::abs(FastLog(x) - std::log(x)) / std::max(1.0, std::abs(std::log(x))));
  }
  EXPECT_LT(worst_abs, 1e-15);
  for (double x = 0.5; x < 2.0; x += 1e-4) {
    ASSERT_NEAR(FastLog(x), std::log(x), 4e-16) << x;  // few ulps near log = 0
  }
  EXPECT_EQ(FastLog(1.0), 0.0);
}

TEST(FastLog, NonPositiveGivesMinusInfinity) {
  EXPECT_EQ(FastLog(0.0), -std::numeric_limits<double>::infinity());
  EXPECT_EQ(FastLog(-3.0), -std::numeric_limits<double>::infinity());
}

TEST(FastExpF, WithinTwoAndAHalfFloatUlpsOfStdExp) {
  // The header's bound: interpolation error 8e-8 plus float rounding in the
  // reduction and Horner steps; 1.5e-7 is 2.5 ulp of float (2^-23 = 1.19e-7
  // per ulp at the top of a binade, 6e-8 at the bottom).
  double worst = 0.0;
  for (double x = -87.0; x <= 88.0; x += 0.000731) {
    const auto xf = static_cast<float>(x);
    const double ref = std::exp(static_cast<double>(xf));
    worst = std::max(worst, std::abs(static_cast<double>(internal::FastExpF(xf)) - ref) / ref);
  }
  EXPECT_LT(worst, 1.5e-7);
  EXPECT_EQ(internal::FastExpF(0.0f), 1.0f);
  EXPECT_EQ(internal::FastExpF(-87.5f), 0.0f);
  EXPECT_EQ(internal::FastExpF(-1e30f), 0.0f);
  EXPECT_TRUE(std::isfinite(internal::FastExpF(1e30f)));
}

TEST(ZigguratNormal, MomentsMatchStandardNormal) {
  // n = 1e6 draws. Standard errors: mean 1/sqrt(n) = 1e-3; variance
  // sqrt(2/n) = 1.41e-3; third moment sqrt(15/n) = 3.9e-3; fourth moment
  // sqrt(96/n) = 9.8e-3. Tolerances are 5 standard errors.
  Rng rng(11);
  const int n = 1'000'000;
  std::vector<double> v(n);
  FillStandardNormal(rng, v);
  double m1 = 0, m2 = 0, m3 = 0, m4 = 0;
  for (const double x : v) {
    m1 += x;
    m2 += x * x;
    m3 += x * x * x;
    m4 += x * x * x * x;
  }
  m1 /= n;
  m2 /= n;
  m3 /= n;
  m4 /= n;
  EXPECT_NEAR(m1, 0.0, 5e-3);
  EXPECT_NEAR(m2, 1.0, 7.1e-3);
  EXPECT_NEAR(m3, 0.0, 2e-2);
  EXPECT_NEAR(m4, 3.0, 4.9e-2);
}

TEST(ZigguratNormal, CdfMatchesAtQuantilesIncludingTheTail) {
  // Fraction below t against Phi(t), tolerance 5 binomial standard errors
  // sqrt(p(1-p)/n). t = -3.8 and 3.8 lie beyond r = 3.654 (the tail sampler).
  Rng rng(12);
  const int n = 2'000'000;
  std::vector<double> v(n);
  FillStandardNormal(rng, v);
  for (const double t : {-3.8, -2.0, -1.0, -0.3, 0.0, 0.5, 1.5, 2.5, 3.8}) {
    const double p = 0.5 * std::erfc(-t / std::sqrt(2.0));
    int64_t below = 0;
    for (const double x : v) below += x < t ? 1 : 0;
    const double tol = 5.0 * std::sqrt(p * (1 - p) / n);
    EXPECT_NEAR(static_cast<double>(below) / n, p, tol) << "t=" << t;
  }
}

TEST(ZigguratNormal, SameStateSameNumbers) {
  // FillStandardNormal works in batches and rewinds the stream at slow-path
  // draws; it must give exactly the one-at-a-time numbers and leave the stream
  // where the one-at-a-time code leaves it, for lengths around the batch size
  // and for long runs that hit the slow path and the tail many times.
  for (const size_t n : {size_t{0}, size_t{1}, size_t{2}, size_t{31}, size_t{32}, size_t{33},
                         size_t{1000}, size_t{200'000}}) {
    Rng a(5 + n), b(5 + n);
    std::vector<double> x(n), y(n);
    FillStandardNormal(a, x);
    for (double& v : y) v = ZigguratNormal(b);
    EXPECT_EQ(x, y) << "n=" << n;
    EXPECT_EQ(a.NextU64(), b.NextU64()) << "stream state after n=" << n;
  }
}

}  // namespace
}  // namespace hcpf::tracker
