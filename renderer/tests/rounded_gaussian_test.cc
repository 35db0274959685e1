// The sensor noise's integer sampler (src/rounded_gaussian.h).

#include "rounded_gaussian.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <numeric>
#include <vector>

namespace hcpf::renderer::internal {
namespace {

constexpr long double kUnits = 4294967296.0L;  // 2^32

// P(round(sigma z) = k), z ~ N(0, 1), in long double from erf (the code
// under test uses erfc tails in double): P(a <= sigma z < b) with a, b the
// half levels; +-kmax take their whole tail.
long double Probability(double sigma, int k, int kmax) {
  const long double s = sigma * std::sqrt(2.0L);
  const auto cdf = [&](long double t) { return 0.5L * (1.0L + std::erf(t / s)); };
  const long double lo = k == -kmax ? 0.0L : cdf(k - 0.5L);
  const long double hi = k == kmax ? 1.0L : cdf(k + 0.5L);
  return hi - lo;
}

TEST(RoundedGaussian, KmaxIsEightSigmaUpTo255) {
  EXPECT_EQ(RoundedGaussianKmax(0.05), 1);
  EXPECT_EQ(RoundedGaussianKmax(0.1), 1);
  EXPECT_EQ(RoundedGaussianKmax(0.7), 6);  // ceil(5.6)
  EXPECT_EQ(RoundedGaussianKmax(3.0), 24);
  EXPECT_EQ(RoundedGaussianKmax(31.875), 255);
  EXPECT_EQ(RoundedGaussianKmax(100.0), 255);
}

TEST(RoundedGaussian, WeightsAreTheClosedFormProbabilitiesInUnitsOfTwoToMinus32) {
  for (const double sigma : {0.1, 0.5, 0.7, 1.0, 3.0, 5.0, 12.5, 40.0, 100.0}) {
    const int kmax = RoundedGaussianKmax(sigma);
    const std::vector<uint64_t> w = RoundedGaussianWeights(sigma, kmax);
    ASSERT_EQ(w.size(), 2 * static_cast<size_t>(kmax) + 1);
    EXPECT_EQ(std::accumulate(w.begin(), w.end(), uint64_t{0}), uint64_t{1} << 32) << sigma;
    for (int k = -kmax; k <= kmax; ++k) {
      const long double exact = Probability(sigma, k, kmax) * kUnits;
      const auto got = static_cast<long double>(w[static_cast<size_t>(k + kmax)]);
      // Rounded to the nearest unit: within 1/2, plus the double erfc's error
      // (relative ~1e-15 of P, under 0.01 units). k = 0 takes the other
      // values' rounding too: under 1/2 unit each.
      const long double tolerance = k == 0 ? 0.51L + 0.5L * 2 * kmax : 0.51L;
      EXPECT_NEAR(static_cast<double>(got), static_cast<double>(exact),
                  static_cast<double>(tolerance))
          << "sigma " << sigma << " k " << k;
    }
    // Symmetric: K and -K alike.
    for (int k = 1; k <= kmax; ++k) {
      EXPECT_EQ(w[static_cast<size_t>(kmax + k)], w[static_cast<size_t>(kmax - k)]);
    }
  }
}

TEST(RoundedGaussian, TheTableRealisesTheWeightsExactly) {
  for (const double sigma : {0.1, 0.7, 3.0, 5.0, 40.0, 100.0}) {
    const RoundedGaussianTable table(sigma);
    const int kmax = table.kmax();
    const std::vector<uint64_t> w = RoundedGaussianWeights(sigma, kmax);
    for (int k = -kmax; k <= kmax; ++k) {
      EXPECT_EQ(table.Count(k), w[static_cast<size_t>(k + kmax)])
          << "sigma " << sigma << " k " << k;
    }
    EXPECT_EQ(table.Count(kmax + 1), 0u);
    EXPECT_EQ(table.Count(-kmax - 1), 0u);
  }
}

TEST(RoundedGaussian, SampleMatchesTheCountsOfASmallTable) {
  // sigma 0.1: 3 values in 4 bins of 2^30 inputs each. Within a bin (top 2
  // bits) Sample gives the bin's value while the other 30 bits are below its
  // threshold and its alias from there on: at most one change. Each bin's
  // change is found by bisection between its first and last input, and both
  // pieces are counted exactly, which must give Count.
  const RoundedGaussianTable table(0.1);
  ASSERT_EQ(table.kmax(), 1);
  constexpr uint64_t kBin = uint64_t{1} << 30;
  std::vector<uint64_t> counted(3, 0);
  for (uint64_t bin = 0; bin < 4; ++bin) {
    const auto sample = [&](uint64_t r) {
      return table.Sample(static_cast<uint32_t>(bin * kBin + r));
    };
    const int32_t first = sample(0);
    const int32_t last = sample(kBin - 1);
    uint64_t change = kBin;  // first input of the second piece
    if (last != first) {
      uint64_t lo = 0, hi = kBin - 1;  // sample(lo) == first, sample(hi) != first
      while (hi - lo > 1) {
        const uint64_t mid = (lo + hi) / 2;
        (sample(mid) == first ? lo : hi) = mid;
      }
      change = hi;
    }
    counted[static_cast<size_t>(first + 1)] += change;
    if (change < kBin) {
      const int32_t second = sample(change);
      ASSERT_GE(second, -1);
      ASSERT_LE(second, 1);
      counted[static_cast<size_t>(second + 1)] += kBin - change;
      // One change only: the last input of the bin gives the second value.
      EXPECT_EQ(last, second);
    }
  }
  for (int k = -1; k <= 1; ++k) {
    EXPECT_EQ(counted[static_cast<size_t>(k + 1)], table.Count(k)) << k;
  }
  // P(K = +-1) = P(|z| > 5) / 2 each: 2.87e-7, about 1232 units.
  EXPECT_NEAR(static_cast<double>(table.Count(1)), 1232.0, 2.0);
}

TEST(RoundedGaussian, VectorLookupsEqualSample) {
  // SampleWords' vector path (AVX-512 register permutes, tables of up to 64
  // bins) against Sample on each half of each word, for sigmas on both sides
  // of the 64-bin limit (kmax 31, sigma 3.875), over words that hit every
  // bin and both sides of every threshold: random words, and the edges of
  // every bin of the largest table.
  std::vector<uint64_t> words(4096 + 128);
  uint64_t x = 0x9E3779B97F4A7C15ULL;
  for (size_t i = 0; i < 4096; ++i) {
    x ^= x << 13;
    x ^= x >> 7;
    x ^= x << 17;
    words[i] = x;
  }
  for (uint64_t b = 0; b < 64; ++b) {
    const uint64_t first = b << 26;  // 64 bins: shift 26
    const uint64_t last = first | ((uint64_t{1} << 26) - 1);
    words[4096 + 2 * b] = first | (last << 32);
    words[4096 + 2 * b + 1] = (first + 1) | ((last - 1) << 32);
  }
  // An odd count: the last words go through the scalar tail.
  const size_t count = words.size() - 3;
  bool vector_ran = false;
  for (const double sigma : {0.05, 0.7, 1.0, 2.0, 3.0, 3.875, 3.9, 10.0}) {
    const RoundedGaussianTable table(sigma);
    vector_ran = vector_ran || table.HasVectorPath();
    std::vector<int16_t> fast(2 * count), reference(2 * count);
    table.SampleWords(words.data(), count, fast.data());
    table.SampleWords(words.data(), count, reference.data(), /*scalar=*/true);
    for (size_t i = 0; i < count; ++i) {
      ASSERT_EQ(reference[2 * i], table.Sample(static_cast<uint32_t>(words[i]))) << i;
      ASSERT_EQ(reference[2 * i + 1], table.Sample(static_cast<uint32_t>(words[i] >> 32))) << i;
    }
    EXPECT_EQ(fast, reference) << "sigma " << sigma;
    // Tables beyond 64 bins have no vector path.
    if (RoundedGaussianKmax(sigma) > 31) {
      EXPECT_FALSE(table.HasVectorPath()) << sigma;
    }
  }
  if (!vector_ran) GTEST_SKIP() << "no AVX-512 on this machine: only the scalar path ran";
}

}  // namespace
}  // namespace hcpf::renderer::internal
