// FastExp / FastLog against libm.
#include "fast_math.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

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

}  // namespace
}  // namespace hcpf::tracker
