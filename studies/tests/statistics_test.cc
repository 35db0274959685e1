// The report's statistics against hand-worked values and published tables.
// Every expected value below is derived in its comment (or quoted from the
// table named there), never taken from the code under test.

#include "hcpf/studies/statistics.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <tuple>
#include <vector>

#include "hcpf/studies/metric_catalogue.h"
#include "hcpf/studies/regress.h"

namespace hcpf::studies {
namespace {

TEST(StudentT975, MatchesPrintedTables) {
  // Printed two-sided 95 % t tables: 12.706 (1), 2.228 (10), 2.042 (30),
  // 2.021 (40), 2.000 (60), 1.980 (120). Above 30 the expansion must agree to 1e-3.
  EXPECT_DOUBLE_EQ(StudentT975(1), 12.706);
  EXPECT_DOUBLE_EQ(StudentT975(10), 2.228);
  EXPECT_NEAR(StudentT975(40), 2.021, 1e-3);
  EXPECT_NEAR(StudentT975(60), 2.000, 1e-3);
  EXPECT_NEAR(StudentT975(120), 1.980, 1e-3);
}

TEST(StudentInterval95, MeanAndBoundsByHand) {
  // {1, 2, 3}: mean 2, s = 1, half-width = t(2) · 1 / √3 = 4.303 / 1.7320508 = 2.484338.
  const std::vector<double> a = {1.0, 2.0, 3.0};
  const Interval r = StudentInterval95(a);
  EXPECT_EQ(r.n, 3);
  EXPECT_EQ(r.method, IntervalMethod::kStudentT);
  EXPECT_DOUBLE_EQ(r.mean, 2.0);
  EXPECT_NEAR(r.lower, 2.0 - 2.484338, 1e-6);
  EXPECT_NEAR(r.upper, 2.0 + 2.484338, 1e-6);
  EXPECT_FALSE(r.clipped);
  // NaN is left out: {4, 6}: mean 5, s = √2, half-width = 12.706 · √2 / √2.
  const std::vector<double> b = {std::nan(""), 4.0, 6.0};
  const Interval rb = StudentInterval95(b);
  EXPECT_EQ(rb.n, 2);
  EXPECT_NEAR(rb.upper - rb.mean, 12.706, 1e-9);
  // One value: no interval; none: NaN.
  const std::vector<double> c = {0.5};
  EXPECT_EQ(StudentInterval95(c).method, IntervalMethod::kNone);
  EXPECT_EQ(StudentInterval95(c).lower, 0.5);
  EXPECT_TRUE(std::isnan(StudentInterval95(std::vector<double>{}).mean));
}

TEST(StudentInterval95, IsCutToTheRangeAndSaysSo) {
  // {0, 0, 1} in [0, 1]: mean 1/3, s = √(1/3) = 0.57735, half-width =
  // 4.303 · 0.57735 / √3 = 1.434333: [−1.101, 1.768] → [0, 1], clipped.
  const std::vector<double> v = {0.0, 0.0, 1.0};
  const Interval r = StudentInterval95(v, MetricRange::UnitInterval());
  EXPECT_NEAR(r.mean, 1.0 / 3.0, 1e-12);
  EXPECT_EQ(r.lower, 0.0);
  EXPECT_EQ(r.upper, 1.0);
  EXPECT_TRUE(r.clipped);
  // MOTA-like, at most 1: {0.9, 1.0}: mean 0.95, s = 0.0707107, half-width
  // = 12.706 · 0.0707107 / √2 = 0.6353: lower 0.3147 kept, upper cut to 1.
  const std::vector<double> m = {0.9, 1.0};
  const Interval rm = StudentInterval95(m, MetricRange::AtMost(1.0));
  EXPECT_NEAR(rm.lower, 0.95 - 0.6353, 1e-9);
  EXPECT_EQ(rm.upper, 1.0);
  EXPECT_TRUE(rm.clipped);
}

// Wilson: centre (p̂ + z²/2n) / (1 + z²/n), half-width z/(1 + z²/n) ·
// √(p̂(1−p̂)/n + z²/4n²), z² = 3.841459.
TEST(WilsonInterval95, HandWorkedValues) {
  // 0 of 10: centre = 0.1920729 / 1.3841459 = 0.1387667, half-width =
  // 1.4160 · √(0.0096036) = 0.1387667: [0, 0.2775334].
  const Interval zero = WilsonInterval95(0.0, 10);
  EXPECT_EQ(zero.method, IntervalMethod::kWilson);
  EXPECT_NEAR(zero.lower, 0.0, 1e-12);
  EXPECT_NEAR(zero.upper, 0.277533, 1e-6);
  // 5 of 10: centre 0.5, half-width 1.4160 · √(0.025 + 0.0096036) = 0.263407.
  const Interval half = WilsonInterval95(0.5, 10);
  EXPECT_NEAR(half.lower, 0.236593, 1e-6);
  EXPECT_NEAR(half.upper, 0.763407, 1e-6);
  // 10 of 10 mirrors 0 of 10.
  const Interval all = WilsonInterval95(1.0, 10);
  EXPECT_NEAR(all.lower, 1.0 - 0.277533, 1e-6);
  EXPECT_NEAR(all.upper, 1.0, 1e-12);
}

TEST(WilsonInterval95, MatchesNewcombe1998) {
  // Newcombe, "Two-sided confidence intervals for the single proportion",
  // Stat. Med. 17 (1998), Table II, method 3 (score, no continuity
  // correction), printed to 4 decimals.
  struct Case {
    int k, n;
    double lower, upper;
  };
  for (const Case& c : {Case{81, 263, 0.2553, 0.3662}, Case{15, 148, 0.0624, 0.1605},
                        Case{0, 20, 0.0, 0.1611}, Case{1, 29, 0.0061, 0.1718}}) {
    const Interval r = WilsonInterval95(static_cast<double>(c.k) / c.n, c.n);
    EXPECT_NEAR(r.lower, c.lower, 5e-5) << c.k << "/" << c.n;
    EXPECT_NEAR(r.upper, c.upper, 5e-5) << c.k << "/" << c.n;
  }
}

// Proportions: Wilson with the effective number of trials
// n* = n · p̂(1 − p̂) / s² · (z / t(0.975, n−1))², or n when s² = 0.
TEST(MeanInterval95, ProportionsGetWilsonWithTheEffectiveNumberOfTrials) {
  // Ten runs that each hijacked nothing: s² = 0, n* = 10: [0, 0.2775],
  // where a t interval would have width 0.
  const std::vector<double> zeros(10, 0.0);
  const Interval w = MeanInterval95(zeros, MetricRange::Proportion());
  EXPECT_EQ(w.method, IntervalMethod::kWilson);
  EXPECT_EQ(w.n, 10);
  EXPECT_EQ(w.trials, 10.0);
  EXPECT_NEAR(w.upper, 0.277533, 1e-6);
  EXPECT_EQ(StudentInterval95(zeros).upper, 0.0);
  // Five of ten runs hijacked (0/1 each; the NaN is left out): s² = 2.5/9,
  // n·p̂(1−p̂)/s² = 2.5 / (2.5/9) = 9, (z/t(9))² = (1.959964/2.262)² =
  // 0.7507770, n* = 6.756993; centre 0.5, z²/n* = 0.5685160, half-width
  // 1.959964 / 1.5685160 · √(0.25/6.756993 + 3.841459/(4 · 6.756993²)) =
  // 1.2495658 · √(0.0369987 + 0.0210344) = 0.3010211.
  const std::vector<double> five = {1, 0, 1, 0, 1, 0, 1, 0, 1, std::nan(""), 0};
  const Interval f = MeanInterval95(five, MetricRange::Proportion());
  EXPECT_EQ(f.n, 10);
  EXPECT_NEAR(f.trials, 6.756993, 1e-6);
  EXPECT_NEAR(f.lower, 0.5 - 0.3010211, 1e-6);
  EXPECT_NEAR(f.upper, 0.5 + 0.3010211, 1e-6);
  // Two seeds, {0.2, 0.4}: p̂ = 0.3, s² = 0.02, n·p̂(1−p̂)/s² = 21, (z/t(1))²
  // = (1.959964/12.706)² = 0.0237940, n* = 0.4996867: z²/n* = 7.687735,
  // centre (0.3 + 3.843869) / 8.687737 = 0.4769790, half-width 1.959964 /
  // 8.687737 · √(0.21/0.4996867 + 3.841459/(4 · 0.4996867²)) = 0.4659931.
  const std::vector<double> fr = {0.2, 0.4};
  const Interval rf = MeanInterval95(fr, MetricRange::Proportion());
  EXPECT_NEAR(rf.mean, 0.3, 1e-12);
  EXPECT_NEAR(rf.trials, 0.4996867, 1e-6);
  EXPECT_NEAR(rf.lower, 0.4769790 - 0.4659931, 1e-6);
  EXPECT_NEAR(rf.upper, 0.4769790 + 0.4659931, 1e-6);
  // Fractions with a small spread (a DA accuracy): {0.96, 0.98, 0.97, 0.99,
  // 0.95}: p̂ = 0.97, s² = 0.00025, n* = 5 · 0.0291 / 0.00025 · (1.959964 /
  // 2.776)² = 290.12: [0.943413, 0.984303] — about the t interval's width
  // (0.950371 … 0.989629: 0.0393 against 0.0409), not the width of a
  // binomial over 5 seeds, and skewed away from the bound at 1.
  const std::vector<double> da = {0.96, 0.98, 0.97, 0.99, 0.95};
  const Interval rd = MeanInterval95(da, MetricRange::Proportion());
  EXPECT_NEAR(rd.trials, 290.12, 0.01);
  EXPECT_NEAR(rd.lower, 0.943413, 1e-6);
  EXPECT_NEAR(rd.upper, 0.984303, 1e-6);
  // Not a proportion: the t interval.
  EXPECT_EQ(MeanInterval95(fr, MetricRange::UnitInterval()).method, IntervalMethod::kStudentT);
}

// Seeds all of one value have s² = 0 exactly, so n* = n whatever the value's
// digits: 0.9 ten times sums to 8.999999999999998, and its mean's squared
// deviations were 1e-32, n* 5e31 and the band [0.9, 0.9] (an audit). By
// hand, Wilson at p̂ = 0.9, n = 10: centre (0.9 + 3.841459/20) / 1.3841459
// = 0.7889869, half-width 1.959964 / 1.3841459 · √(0.009 + 3.841459/400) =
// 0.1931369: [0.5958500, 0.9821238]; at 0.3: [0.1077913, 0.6032219].
// Every seed 0 (or 1): a proportion at its bound shows no spread whatever
// its uncertainty, so the band is the binomial's over the 10 seeds, Wilson
// by hand: upper = (z²/n) / (1 + z²/n) = 0.384146 / 1.384146 = 0.2775328.
// Inside (0, 1) the seeds of one value do not vary: the band has width 0,
// as the t interval's, and a seed off by 0.001 widens it a little (n* is
// finite). It was the binomial band there too ([0.5958500, 0.9821238] for
// ten 0.9s), widest with no spread and nearly shut with a little (a review).
TEST(MeanInterval95, SeedsOfOneValueGetTheBinomialBandAtTheBoundsAndWidthZeroInside) {
  for (const auto& [value, lower, upper] :
       {std::tuple{0.0, 0.0, 0.2775328}, std::tuple{1.0, 0.7224672, 1.0}}) {
    const std::vector<double> same(10, value);
    const Interval r = MeanInterval95(same, MetricRange::Proportion());
    EXPECT_EQ(r.mean, value);
    EXPECT_EQ(r.trials, 10.0) << value;
    EXPECT_NEAR(r.lower, lower, 1e-6) << value;
    EXPECT_NEAR(r.upper, upper, 1e-6) << value;
  }
  for (const double value : {0.9, 0.3}) {
    std::vector<double> same(10, value);
    const Interval r = MeanInterval95(same, MetricRange::Proportion());
    EXPECT_EQ(r.mean, value);
    EXPECT_EQ(r.lower, value);
    EXPECT_EQ(r.upper, value);
    same[0] += 0.001;
    const Interval off = MeanInterval95(same, MetricRange::Proportion());
    EXPECT_LT(off.lower, off.mean);
    EXPECT_GT(off.upper, off.mean);
    EXPECT_LT(off.upper - off.lower, 0.002);
  }
}

// Seeds equal but for rounding (one fraction reached by two formulas:
// 0.1 + 0.2 is 0.30000000000000004) count as seeds of one value, as
// ComparePaired calls them equal (a review): below, the band of ten seeds
// of 0.3, width 0 (above). Summed directly, ten 0.9s have mean 0.8999999999999999; the regression
// gate's rows took their means that way (a review: its own copy).
TEST(Mean, ValuesAllEqualGiveThatValueExactly) {
  const std::vector<double> nines(10, 0.9);
  EXPECT_EQ(Mean(nines), 0.9);
  EXPECT_TRUE(std::isnan(Mean(std::vector<double>{})));
  EXPECT_EQ(Mean(std::vector<double>{1.0, 2.0, 6.0}), 3.0);
  RegressTolerance t;
  t.metric = "da_accuracy";
  const RegressRow row = CompareSeeds(nines, nines, t);
  EXPECT_EQ(row.baseline, 0.9);
  EXPECT_EQ(row.current, 0.9);
}

TEST(MeanInterval95, SeedsEqualButForRoundingAreSeedsOfOneValue) {
  std::vector<double> values(10, 0.3);
  for (int i = 0; i < 10; i += 2) values[i] = 0.1 + 0.2;
  ASSERT_NE(values[0], values[1]);
  const Interval r = MeanInterval95(values, MetricRange::Proportion());
  EXPECT_NEAR(r.lower, 0.3, 1e-15);  // no spread: width 0, not n* ~ 1e32's rounding
  EXPECT_NEAR(r.upper, 0.3, 1e-15);
  // A true spread, however small against the values, is kept.
  values[1] = 0.3 + 1e-6;
  EXPECT_GT(MeanInterval95(values, MetricRange::Proportion()).trials, 1e6);
}

// The exact signed-rank distribution with ranks 1..n: P(W+ = w) is the
// number of subsets of {1..n} summing to w over 2^n; for w <= n that is the
// number of partitions of w into distinct parts, 1 1 1 2 2 3 4 5 6 8 for w = 0..9.
TEST(WilcoxonSignedRank, ExactSmallSamplesByHand) {
  // All five positive: W+ = 15, P(W+ >= 15) = 1/32, p = 2/32.
  const std::vector<double> five = {0.5, 1.0, 1.5, 2.0, 2.5};
  SignedRankTest t = WilcoxonSignedRank(five);
  EXPECT_TRUE(t.exact);
  EXPECT_EQ(t.nonzero, 5);
  EXPECT_EQ(t.w_plus, 15.0);
  EXPECT_DOUBLE_EQ(t.p_value, 0.0625);
  // Zeros are dropped: the same five and three zeros.
  const std::vector<double> zeros = {0.0, 0.5, 1.0, 0.0, 1.5, 2.0, 2.5, 0.0};
  t = WilcoxonSignedRank(zeros);
  EXPECT_EQ(t.nonzero, 5);
  EXPECT_DOUBLE_EQ(t.p_value, 0.0625);
  // n = 10, only rank 8 positive: W+ = 8, P(W+ <= 8) = (1+1+1+2+2+3+4+5+6)/1024
  // = 25/1024, p = 50/1024.
  const std::vector<double> ten = {-1, -2, -3, -4, -5, -6, -7, 8, -9, -10};
  t = WilcoxonSignedRank(ten);
  EXPECT_EQ(t.w_plus, 8.0);
  EXPECT_DOUBLE_EQ(t.p_value, 50.0 / 1024.0);
  // Ties: {−1, 2, 2} has ranks 1, 2.5, 2.5 and W+ = 5; the eight sign
  // assignments give W+ = 0, 1, 2.5, 2.5, 3.5, 3.5, 5, 6: P(W+ >= 5) = 2/8, p = 0.5.
  const std::vector<double> tied = {-1.0, 2.0, 2.0};
  t = WilcoxonSignedRank(tied);
  EXPECT_EQ(t.w_plus, 5.0);
  EXPECT_DOUBLE_EQ(t.p_value, 0.5);
  // No nonzero difference: nothing to test.
  const std::vector<double> none = {0.0, 0.0};
  t = WilcoxonSignedRank(none);
  EXPECT_EQ(t.nonzero, 0);
  EXPECT_EQ(t.p_value, 1.0);
}

// Published critical values of the two-sided 5 % signed-rank test (e.g.
// Siegel & Castellan, Nonparametric Statistics, table H; the smaller rank
// sum T rejects at T <= the value): the exact p at T is <= 0.05, at T + 1 above.
TEST(WilcoxonSignedRank, ExactPValuesAgreeWithCriticalValueTables) {
  struct Row {
    int n, critical;
  };
  for (const Row& row :
       {Row{6, 0}, Row{8, 3}, Row{10, 8}, Row{15, 25}, Row{20, 52}, Row{25, 89}, Row{30, 137}}) {
    for (int w : {row.critical, row.critical + 1}) {
      // Differences ±1..±n with positive ranks summing to w: the largest
      // ranks below w taken greedily (any subset with that sum will do).
      std::vector<double> d;
      int left = w;
      for (int r = row.n; r >= 1; --r) {
        const bool positive = r <= left;
        if (positive) left -= r;
        d.push_back(positive ? r : -r);
      }
      ASSERT_EQ(left, 0);
      const SignedRankTest t = WilcoxonSignedRank(d);
      EXPECT_TRUE(t.exact);
      EXPECT_EQ(t.w_plus, w);
      if (w == row.critical) {
        EXPECT_LE(t.p_value, 0.05) << "n=" << row.n << " T=" << w;
      } else {
        EXPECT_GT(t.p_value, 0.05) << "n=" << row.n << " T=" << w;
      }
    }
  }
}

TEST(WilcoxonSignedRank, NormalApproximationWithTiesByHand) {
  // 40 differences of equal size (one tie group of 40, every rank 20.5), 30
  // positive: W+ = 30 · 20.5 = 615, E = 40·41/4 = 410, Var = 40·41·81/24 −
  // (40³ − 40)/48 = 5535 − 1332.5 = 4202.5, z = (205 − 0.5)/64.8267 = 3.154565,
  // p = erfc(z/√2) = 0.0016074 (normal table: 2·(1 − Φ(3.15)) = 0.00163).
  std::vector<double> d(40, 0.25);
  for (int i = 0; i < 10; ++i) d[i] = -0.25;
  const SignedRankTest t = WilcoxonSignedRank(d);
  EXPECT_FALSE(t.exact);
  EXPECT_EQ(t.w_plus, 615.0);
  EXPECT_NEAR(t.p_value, 0.0016074, 1e-6);
  // 31 distinct differences ±1..±31 (no ties), W+ = 31·32/4 = 248 exactly
  // the mean: |W+ − E| − ½ < 0, p = 1.
  std::vector<double> balanced;
  int left = 248;
  for (int r = 31; r >= 1; --r) {
    const bool positive = r <= left;
    if (positive) left -= r;
    balanced.push_back(positive ? r : -r);
  }
  const SignedRankTest b = WilcoxonSignedRank(balanced);
  EXPECT_FALSE(b.exact);
  EXPECT_EQ(b.w_plus, 248.0);
  EXPECT_EQ(b.p_value, 1.0);
}

// W+ of many pairs: 2 W+ passes 2^31 from 46,341 pairs (it was an int, and
// wrapped to a negative W+ and p = 0: an audit). d_i = ±(i + 1), positive
// for even i, 70,000 pairs: ranks i + 1, W+ = 1 + 3 + ... + 69,999 =
// 35,000² = 1,225,000,000 against the mean n(n+1)/4 = 1,225,017,500; z =
// (17,500 − 0.5) / √(n(n+1)(2n+1)/24) = 0.0032731, p = erfc(z/√2) = 0.99739.
TEST(WilcoxonSignedRank, ManyPairsDoNotOverflowTheRankSum) {
  std::vector<double> d(70000);
  for (size_t i = 0; i < d.size(); ++i)
    d[i] = (i % 2 == 0 ? 1.0 : -1.0) * static_cast<double>(i + 1);
  const SignedRankTest t = WilcoxonSignedRank(d);
  EXPECT_EQ(t.nonzero, 70000);
  EXPECT_EQ(t.w_plus, 1225000000.0);
  EXPECT_NEAR(t.p_value, 0.99739, 1e-5);
  // All of one sign: W+ = n(n+1)/2 = 2,450,035,000.
  for (double& x : d) x = std::abs(x);
  EXPECT_EQ(WilcoxonSignedRank(d).w_plus, 2450035000.0);
}

// One fraction reached by two roundings is one value: 152/300 − 151/300 =
// 0.0033333333333334103 and 77/300 − 76/300 = 0.0033333333333332993 are both
// 1/300. With d = {152/300 − 151/300, −(77/300 − 76/300), 2/300} the first
// two tie at rank 1.5 and W+ = 1.5 + 3 = 4.5 (it was 5 by their last digits:
// an audit). And a difference of one value reached two ways, 0.1 + 0.2
// against 0.3 (5.6e-17 apart), is a tie in ComparePaired, not a pair.
TEST(WilcoxonSignedRank, FractionsEqualButForRoundingAreTied) {
  const double a = 152.0 / 300.0 - 151.0 / 300.0;
  const double b = 77.0 / 300.0 - 76.0 / 300.0;
  ASSERT_NE(a, b);
  const std::vector<double> d = {a, -b, 2.0 / 300.0};
  EXPECT_EQ(WilcoxonSignedRank(d).w_plus, 4.5);
  const std::vector<double> x = {0.1 + 0.2, 0.5}, y = {0.3, 0.4};
  const PairedComparison c = ComparePaired(x, y, MetricRange::Unbounded());
  EXPECT_EQ(c.pairs, 2);
  EXPECT_EQ(c.positive, 1);
  EXPECT_EQ(c.negative, 0);
  EXPECT_EQ(c.test.nonzero, 1);
  EXPECT_NEAR(c.difference.mean, 0.05, 1e-12);
}

// Equal differences of large values (milliseconds, pixels) differ by the
// values' rounding, ~1e-13 at 1000, which is more than 1e-9 of a difference
// of 1e-5: 1000.00001 − 1000 and 3000.00001 − 3000 are 9.99999997e-06 and
// 1.00000002e-05 in doubles. Relative to |d| they were ranked 1 and 2; to
// the values they came from (as zeros are), they are tied at 1.5 (a review).
TEST(ComparePaired, EqualDifferencesOfLargeValuesAreTied) {
  const std::vector<double> a = {1000.0 + 1e-5, 3000.0 + 1e-5, 3.0};
  const std::vector<double> b = {1000.0, 3000.0, 1.0};
  ASSERT_NE(a[0] - b[0], a[1] - b[1]);
  const PairedComparison c = ComparePaired(a, b, MetricRange::Unbounded());
  EXPECT_EQ(c.test.nonzero, 3);
  EXPECT_EQ(c.test.w_plus, 6.0);  // all positive: 1.5 + 1.5 + 3
  // With one sign flipped, W+ shows the tied ranks: −1.5 +1.5 +3 → 4.5.
  const std::vector<double> flipped = {1000.0, 3000.0 + 1e-5, 3.0};
  const std::vector<double> flipped_b = {1000.0 + 1e-5, 3000.0, 1.0};
  EXPECT_EQ(ComparePaired(flipped, flipped_b, MetricRange::Unbounded()).test.w_plus, 4.5);
  // Without the scales the two are ranked apart: W+ = 2 + 3 = 5.
  const std::vector<double> d = {flipped[0] - flipped_b[0], flipped[1] - flipped_b[1], 2.0};
  EXPECT_EQ(WilcoxonSignedRank(d).w_plus, 5.0);
}

TEST(ComparePaired, DifferenceIntervalCountsAndTestByHand) {
  // d = a − b = {0.2, 0, 0.5}: mean 0.233333, s = √(0.0633333) = 0.251661,
  // half-width 4.303 · 0.251661 / √3 = 0.625211; signs + 0 +; the test sees
  // the two nonzero differences, both positive: W+ = 3, p = 2 · 1/4.
  const std::vector<double> a = {0.9, 0.8, 1.0, std::nan("")};
  const std::vector<double> b = {0.7, 0.8, 0.5, 0.4};
  const PairedComparison c = ComparePaired(a, b, MetricRange::UnitInterval());
  EXPECT_EQ(c.pairs, 3);
  EXPECT_EQ(c.positive, 2);
  EXPECT_EQ(c.negative, 0);
  EXPECT_NEAR(c.difference.mean, 0.233333, 1e-6);
  EXPECT_NEAR(c.difference.lower, 0.233333 - 0.625211, 1e-6);
  EXPECT_NEAR(c.difference.upper, 0.233333 + 0.625211, 1e-6);
  EXPECT_FALSE(c.difference.clipped);
  EXPECT_EQ(c.test.nonzero, 2);
  EXPECT_DOUBLE_EQ(c.test.p_value, 0.5);
  // A difference of values in [0, 1] lies in [−1, 1]: {1, 0}: mean 0.5,
  // half-width 12.706 · 0.707107 / √2 = 6.353 → cut to [−1, 1].
  const std::vector<double> one = {1.0, 0.0}, nil = {0.0, 0.0};
  const PairedComparison cut = ComparePaired(one, nil, MetricRange::Proportion());
  EXPECT_EQ(cut.difference.lower, -1.0);
  EXPECT_EQ(cut.difference.upper, 1.0);
  EXPECT_TRUE(cut.difference.clipped);
}

// Holm by hand. p = {0.04, 0.005, NaN, 0.03, 0.01, 0.5}: five tests, sorted
// 0.005, 0.01, 0.03, 0.04, 0.5 times 5, 4, 3, 2, 1: 0.025, 0.04, 0.09, 0.08,
// 0.5; the running maximum makes the fourth 0.09. Bonferroni (5p) would keep
// only 0.005 below 0.05; Holm keeps 0.01 too.
TEST(HolmAdjusted, StepDownByHandKeepsOrderAndSkipsNaN) {
  const std::vector<double> p = {0.04, 0.005, std::nan(""), 0.03, 0.01, 0.5};
  const std::vector<double> h = HolmAdjusted(p);
  ASSERT_EQ(h.size(), 6U);
  EXPECT_NEAR(h[0], 0.09, 1e-12);  // 2 · 0.04 = 0.08, raised to the 0.09 before it
  EXPECT_NEAR(h[1], 0.025, 1e-12);
  EXPECT_TRUE(std::isnan(h[2]));
  EXPECT_NEAR(h[3], 0.09, 1e-12);
  EXPECT_NEAR(h[4], 0.04, 1e-12);
  EXPECT_NEAR(h[5], 0.5, 1e-12);
  // Capped at 1; one test is its own adjustment; no test, nothing.
  const std::vector<double> big = {0.3, 0.6, 0.9};
  const std::vector<double> big_h = HolmAdjusted(big);
  EXPECT_NEAR(big_h[0], 0.9, 1e-12);  // 3 · 0.3
  EXPECT_EQ(big_h[1], 1.0);           // 2 · 0.6, capped
  EXPECT_EQ(big_h[2], 1.0);           // raised to the 1 before it
  const std::vector<double> one = {0.03};
  EXPECT_EQ(HolmAdjusted(one), one);
  EXPECT_TRUE(HolmAdjusted(std::vector<double>{}).empty());
}

// The floor of the signed-rank p by hand: n differences of one sign give
// W+ at its maximum, reached by one of the 2^n sign assignments, so the
// exact two-sided p is 2 / 2^n. The test itself, run on n positive
// differences, must return exactly that floor (and above 30 the normal
// approximation's). Holm over m comparisons needs p < 0.05 / m first.
TEST(SignedRankFloor, ByHandAndReachedByOneSignedDifferences) {
  EXPECT_EQ(SignedRankFloor(0), 1.0);
  EXPECT_EQ(SignedRankFloor(1), 1.0);           // 2 / 2
  EXPECT_EQ(SignedRankFloor(5), 0.0625);        // 2 / 32: five pairs never reach 0.05
  EXPECT_EQ(SignedRankFloor(6), 0.03125);       // 2 / 64
  EXPECT_EQ(SignedRankFloor(10), 0.001953125);  // 2 / 1024
  for (int n : {1, 4, 10, 17, 30, 31, 40}) {
    std::vector<double> d;
    for (int i = 1; i <= n; ++i) d.push_back(0.5 * i);
    EXPECT_DOUBLE_EQ(WilcoxonSignedRank(d).p_value, SignedRankFloor(n)) << n;
  }
  // Above 30, z = (31·32/4 − ½) / √(31·32·63/24) = 247.5 / √2604 = 4.8503:
  // p = 1.2337e-6, larger than the exact 2^-29 at 30 pairs.
  EXPECT_NEAR(SignedRankFloor(31), 1.2337e-6, 1e-9);
  EXPECT_GT(SignedRankFloor(31), SignedRankFloor(30));
  // The pairs Holm needs: one comparison, p < 0.05 → 6 (5 give 0.0625);
  // 25 → p < 0.002: 10 (0.00195); 26 → p < 0.001923: 11; 52 → p < 0.000962:
  // 12 (11 give 0.000977); 112 → p < 0.000446: 13.
  EXPECT_EQ(PairsForHolm(1, 0.05), 6);
  EXPECT_EQ(PairsForHolm(25, 0.05), 10);
  EXPECT_EQ(PairsForHolm(26, 0.05), 11);
  EXPECT_EQ(PairsForHolm(52, 0.05), 12);
  EXPECT_EQ(PairsForHolm(112, 0.05), 13);
}

// Tarone's family by hand, alpha = 0.05. Floors {2/32, 2/1024, NaN, 2/1024,
// 2/128, 2/1024}: five tests, sorted 0.00195 (three), 0.0156, 0.0625. Below
// 0.05 / k: k = 1 (0.05), 2 (0.025), 3 (0.0167): four, more than k; k = 4
// (0.0125): three, so K = 4 and the family is the three of 10 differing
// seeds. Holm over all five would need p < 0.01 first; Tarone's
// Bonferroni, 0.05 / K = 0.0125.
TEST(TaroneFamily, TheSmallestKWithAtMostKFloorsBelowAlphaOverK) {
  const std::vector<double> floors = {0.0625,     2.0 / 1024, std::nan(""),
                                      2.0 / 1024, 2.0 / 128,  2.0 / 1024};
  const TaroneFamily f = TaroneFamilyOf(floors, 0.05);
  EXPECT_EQ(f.k, 4);
  EXPECT_EQ(f.size, 3);
  EXPECT_EQ(f.member, (std::vector<bool>{false, true, false, true, false, true}));
  // Twenty comparisons of 10 differing seeds and ten of 5: below 0.05 / k
  // twenty for every k up to 25 (0.002 > 0.00195), so K = 20 and the ten
  // leave: Holm's first step needs p < 0.0025, which 2 / 1024 reaches; over
  // all thirty it would need 0.00167, which it does not.
  std::vector<double> mixed(20, 2.0 / 1024);
  mixed.resize(30, 0.0625);
  const TaroneFamily twenty = TaroneFamilyOf(mixed, 0.05);
  EXPECT_EQ(twenty.k, 20);
  EXPECT_EQ(twenty.size, 20);
  EXPECT_LT(mixed[0], 0.05 / twenty.k);
  EXPECT_GT(mixed[0], 0.05 / 30);
  // Thirty of 10 seeds: thirty below 0.05 / k up to k = 25, none from 26
  // (0.001923): K = 26 and no comparison can be kept, as with Holm over 30.
  const std::vector<double> thirty(30, 2.0 / 1024);
  const TaroneFamily none = TaroneFamilyOf(thirty, 0.05);
  EXPECT_EQ(none.k, 26);
  EXPECT_EQ(none.size, 0);
  // Every floor low enough: all of them, K = their count.
  const std::vector<double> low(7, 2.0 / 1024);
  EXPECT_EQ(TaroneFamilyOf(low, 0.05).size, 7);
  EXPECT_EQ(TaroneFamilyOf(low, 0.05).k, 7);
  // No test: no family.
  const std::vector<double> nan_only = {std::nan("")};
  EXPECT_EQ(TaroneFamilyOf(nan_only, 0.05).k, 0);
  EXPECT_EQ(TaroneFamilyOf(nan_only, 0.05).member, std::vector<bool>{false});
  EXPECT_EQ(TaroneFamilyOf(std::vector<double>{}, 0.05).size, 0);
}

// Holm with Tarone's rule by hand, alpha = 0.05: at each step the smallest
// p left times Tarone's K over the floors left, kept monotone.
TEST(HolmTaroneAdjusted, StepDownByHandWithTaronesKPerStep) {
  const double nan = std::nan("");
  // p {0.001, 0.02, NaN, 0.5} with floors {0.001, 0.02, NaN, 0.02}. Step 1:
  // below 0.05 / 1 and 0.05 / 2 three, below 0.05 / 3 one: K = 3, 0.003.
  // Step 2 (floors 0.02, 0.02): below 0.025 two: K = 2, 0.04. Step 3: K =
  // 1, 0.5. As Holm: a family fixed at the first step (the one floor below
  // 0.0167) would have lost 0.02, which the step-down keeps.
  const std::vector<double> p = {0.001, 0.02, nan, 0.5}, f = {0.001, 0.02, nan, 0.02};
  const std::vector<double> h = HolmTaroneAdjusted(p, f, 0.05);
  ASSERT_EQ(h.size(), 4U);
  EXPECT_NEAR(h[0], 0.003, 1e-12);
  EXPECT_NEAR(h[1], 0.04, 1e-12);
  EXPECT_TRUE(std::isnan(h[2]));
  EXPECT_NEAR(h[3], 0.5, 1e-12);
  // p 2/1024, 0.03, 0.04 with floors 2/1024, 2/128, 2/64. Step 1: below
  // 0.05 three, below 0.025 two: K = 2, 4/1024 (Holm: 3 × 2/1024). Step 2
  // (2/128, 2/64): below 0.05 two, below 0.025 one: K = 2, 0.06. Step 3: K
  // = 1, 0.04 raised to 0.06.
  const std::vector<double> p3 = {2.0 / 1024, 0.03, 0.04}, f3 = {2.0 / 1024, 2.0 / 128, 2.0 / 64};
  const std::vector<double> h3 = HolmTaroneAdjusted(p3, f3, 0.05);
  EXPECT_NEAR(h3[0], 4.0 / 1024, 1e-12);
  EXPECT_NEAR(h3[1], 0.06, 1e-12);
  EXPECT_NEAR(h3[2], 0.06, 1e-12);
  EXPECT_NEAR(HolmAdjusted(p3)[0], 6.0 / 1024, 1e-12);
  // Twenty of 10 seeds all one sign (p = floor = 2/1024) beside ten of 5
  // (floor 2/32, p 0.0625): K = 20 at step 1, 20 × 2/1024 = 0.0390625, and
  // 19, 18, ... after: all twenty kept. The ten: K = 1, p 0.0625. Holm
  // over thirty keeps none (30 × 2/1024 = 0.0586).
  std::vector<double> pm(20, 2.0 / 1024), fm(20, 2.0 / 1024);
  pm.resize(30, 0.0625);
  fm.resize(30, 0.0625);
  const std::vector<double> hm = HolmTaroneAdjusted(pm, fm, 0.05);
  for (int i = 0; i < 20; ++i) EXPECT_NEAR(hm[static_cast<size_t>(i)], 0.0390625, 1e-12) << i;
  for (int i = 20; i < 30; ++i) EXPECT_NEAR(hm[static_cast<size_t>(i)], 0.0625, 1e-12) << i;
  EXPECT_GT(HolmAdjusted(pm)[0], 0.05);
  // Every floor low: Tarone's K is the count left, and it is Holm.
  const std::vector<double> plain = {0.04, 0.005, nan, 0.03, 0.01, 0.5};
  const std::vector<double> tiny = {1e-9, 1e-9, nan, 1e-9, 1e-9, 1e-9};
  const std::vector<double> tarone = HolmTaroneAdjusted(plain, tiny, 0.05);
  const std::vector<double> holm = HolmAdjusted(plain);
  for (size_t i = 0; i < plain.size(); ++i) {
    EXPECT_EQ(std::isnan(tarone[i]), std::isnan(holm[i])) << i;
    if (!std::isnan(holm[i])) {
      EXPECT_EQ(tarone[i], holm[i]) << i;
    }
  }
  EXPECT_TRUE(HolmTaroneAdjusted(std::vector<double>{}, std::vector<double>{}, 0.05).empty());
}

// The step-down against its definition written out plainly: per step,
// Tarone's K by counting from k = 1 over the floors of the tests left
// (linear scans), on 300 tests with floors 2 / 2^n for n in 1..24 (many
// equal) and p at or above them, some equal, in a fixed pseudo-random order.
TEST(HolmTaroneAdjusted, MatchesTheDefinitionStepByStep) {
  std::mt19937 gen(7);
  std::uniform_int_distribution<int> pairs(1, 24);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const int m = 300;
  std::vector<double> p(m), f(m);
  for (int i = 0; i < m; ++i) {
    f[static_cast<size_t>(i)] = std::ldexp(2.0, -pairs(gen));
    const double u = unit(gen);
    p[static_cast<size_t>(i)] =
        u < 0.2 ? f[static_cast<size_t>(i)] : std::max(f[static_cast<size_t>(i)], u * u * u);
  }
  p[5] = std::nan("");  // not a test
  std::vector<size_t> order;
  for (size_t i = 0; i < p.size(); ++i) {
    if (!std::isnan(p[i])) order.push_back(i);
  }
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return p[a] < p[b]; });
  std::vector<double> want(p.size(), std::nan(""));
  double running = 0.0;
  for (size_t step = 0; step < order.size(); ++step) {
    int k = 1;
    for (;; ++k) {
      int below = 0;
      for (size_t j = step; j < order.size(); ++j) below += f[order[j]] < 0.05 / k ? 1 : 0;
      if (below <= k) break;
    }
    running = std::max(running, k * p[order[step]]);
    want[order[step]] = std::min(1.0, running);
  }
  const std::vector<double> got = HolmTaroneAdjusted(p, f, 0.05);
  ASSERT_EQ(got.size(), want.size());
  int kept = 0;
  for (size_t i = 0; i < p.size(); ++i) {
    if (std::isnan(want[i])) {
      EXPECT_TRUE(std::isnan(got[i])) << i;
      continue;
    }
    EXPECT_EQ(got[i], want[i]) << i;
    kept += want[i] < 0.05 ? 1 : 0;
  }
  // Not a degenerate case: some kept, some not.
  EXPECT_GT(kept, 0);
  EXPECT_LT(kept, m - 1);
}

TEST(MetricCatalogue, ProportionsAreTheFractionsOfCountedEvents) {
  for (const char* name :
       {"da_accuracy", "hijack_rate", "hijacked_fraction", "det_precision", "det_recall",
        "det_recall_visible", "det_recall_centre", "det_precision_centre"}) {
    ASSERT_NE(FindMetric(name), nullptr) << name;
    EXPECT_TRUE(FindMetric(name)->range.proportion) << name;
  }
  for (const char* name : {"idf1", "hota", "motp", "deta", "assa", "det_f1", "det_ap"}) {
    EXPECT_FALSE(FindMetric(name)->range.proportion) << name;
    EXPECT_EQ(FindMetric(name)->range.lower, 0.0) << name;
    EXPECT_EQ(FindMetric(name)->range.upper, 1.0) << name;
  }
  EXPECT_EQ(FindMetric("mota")->range.upper, 1.0);
  EXPECT_FALSE(FindMetric("mota")->range.bounded_below());
  EXPECT_EQ(FindMetric("ms_per_frame")->range.lower, 0.0);
  EXPECT_FALSE(FindMetric("ms_per_frame")->range.bounded_above());
}

// The metrics that describe a run rather than score it are catalogue
// entries (a renamed one would leave Descriptive silently false), and no
// score is one.
TEST(MetricCatalogue, DescriptiveMetricsAreTheSizeTheFloorAndTheReacquisitions) {
  std::vector<std::string> descriptive;
  for (const CatalogueMetric& m : MetricCatalogue()) {
    if (Descriptive(m.name)) descriptive.emplace_back(m.name);
  }
  EXPECT_EQ(descriptive,
            (std::vector<std::string>{"camera_motion_floor_px", "det_size_px", "reacquisitions"}));
  EXPECT_FALSE(Descriptive("da_accuracy"));
}

}  // namespace
}  // namespace hcpf::studies
