// The ziggurat normal generator (core/normal.h): moments, CDF including the
// tail, and batched draws equal to one-at-a-time draws.
#include "hcpf/core/normal.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>

#include "hcpf/core/rng.h"

namespace hcpf {
namespace {

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
}  // namespace hcpf
