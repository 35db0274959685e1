#pragma once
// The statistics of a sweep report: confidence intervals of a cell's mean
// over seeds that stay inside the metric's range, and paired comparisons of
// two cells that ran the same seeds. docs/sweeps.md ("Statistics") states
// every formula; the tests check them against hand-worked and table values.
//
//   Interval t = MeanInterval95(values);                       // Student t
//   Interval w = MeanInterval95(values, MetricRange::Proportion());  // Wilson
//   PairedComparison d = ComparePaired(charged, systematic, range);  // per seed
//
// All functions are pure and deterministic (no randomness, no state); the
// values they are given may hold NaN (a run without that metric), which is
// left out; O(n) except the signed-rank test (O(n log n), and O(n^3) for the
// exact distribution of up to kExactSignedRankMaxPairs pairs).

#include <limits>
#include <span>
#include <vector>

namespace hcpf::studies {

// The values a metric can take and how its across-seed mean is bounded.
struct MetricRange {
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
  // A per-run fraction of counted events (successes / trials) in [0, 1]:
  // its across-seed mean gets a Wilson score interval (see WilsonInterval95).
  bool proportion = false;

  static constexpr MetricRange Unbounded() { return {}; }
  static constexpr MetricRange NonNegative() { return {.lower = 0.0}; }
  static constexpr MetricRange UnitInterval() { return {.lower = 0.0, .upper = 1.0}; }
  static constexpr MetricRange AtMost(double bound) { return {.upper = bound}; }
  static constexpr MetricRange Proportion() {
    return {.lower = 0.0, .upper = 1.0, .proportion = true};
  }
  constexpr bool bounded_below() const { return lower > -std::numeric_limits<double>::infinity(); }
  constexpr bool bounded_above() const { return upper < std::numeric_limits<double>::infinity(); }
};

enum class IntervalMethod {
  kNone,      // fewer values than the method needs (t: n < 2; Wilson: n < 1)
  kStudentT,  // mean ± t(0.975, n−1) · s / √n
  kWilson,    // Wilson score interval of the mean as a proportion over n seeds
};

// A mean with its 95 % confidence interval [lower, upper]. With kNone the
// interval is the mean itself (or NaN when n == 0).
struct Interval {
  int n = 0;  // finite values used
  // kWilson: the number of trials n* the interval is computed for (see
  // MeanInterval95); 0 otherwise.
  double trials = 0.0;
  double mean = std::numeric_limits<double>::quiet_NaN();
  double lower = std::numeric_limits<double>::quiet_NaN();
  double upper = std::numeric_limits<double>::quiet_NaN();
  IntervalMethod method = IntervalMethod::kNone;
  // The t interval reached past the metric's range and was cut at its bound.
  bool clipped = false;
};

// The finite values of `values`, in order.
std::vector<double> Finite(std::span<const double> values);

// The mean of `values` (all finite; NaN when there are none), summed as
// v₀ + mean(x − v₀) so that values all equal give that value exactly.
double Mean(std::span<const double> values);

// The 0.975 quantile of Student's t with `dof` >= 1 degrees of freedom
// (table for dof <= 30, Cornish–Fisher expansion above; error < 1e-3).
double StudentT975(int dof);

// z = Φ⁻¹(0.975), the two-sided 95 % normal quantile.
inline constexpr double kZ975 = 1.959963984540054;

// Mean of the finite values with the 95 % t interval, cut to `range`
// (clipped = true when it was). kNone when fewer than two values.
Interval StudentInterval95(std::span<const double> values,
                           const MetricRange& range = MetricRange::Unbounded());

// Wilson score interval (Wilson 1927) at 95 % for a proportion p̂ over n
// trials: (p̂ + z²/2n ± z·√(p̂(1−p̂)/n + z²/4n²)) / (1 + z²/n). Always inside
// [0, 1]. n need not be an integer (an effective number of trials).
// Preconditions: 0 <= p_hat <= 1, n > 0. The result's n is round(n).
Interval WilsonInterval95(double p_hat, double n);

// The cell statistic of a metric with `range`. A proportion's mean p̂ over
// its n seeds gets WilsonInterval95(p̂, n*) with the effective number of
// trials of Korn & Graubard (1998), with the Wilson interval as in Dean &
// Pagano (2015) for clustered binary data: the seeds are the clusters (a
// run's events are not independent), so
//   n* = n · p̂(1 − p̂) / s² · (z / t(0.975, n−1))²   when s² > 0,
//   n* = n                                           when s² = 0 (or n = 1),
// s² the sample variance of the seeds' values; s <= kRoundingRelative ·
// max|x| counts as 0 (seeds equal but for rounding). n·p̂(1−p̂)/s² is the n whose
// binomial variance p̂(1−p̂)/n equals the observed s²/n; the (z/t)² factor
// accounts for s² being estimated from n − 1 degrees of freedom, so in the
// interior the band is about as wide as the t interval. For values in
// [0, 1], s² <= n/(n−1) · p̂(1−p̂) (X² <= X), with equality when every run is
// 0 or 1: n* >= (n − 1)(z/t)². With no spread (every seed 0, every seed 1)
// the binomial model over the n seeds is assumed, so p̂ = 0 over 10 seeds
// gives [0, 0.2775] where a t interval has width 0.
// Other metrics, and a proportion with a value outside [0, 1], get
// StudentInterval95 cut to their range.
Interval MeanInterval95(std::span<const double> values, const MetricRange& range);

// Wilcoxon signed-rank test of paired differences (two-sided, H0: the
// differences are symmetric about 0). Zero differences are dropped
// (Wilcoxon's rule), the others ranked by |d| with tied values given their
// average rank; W+ is the sum of the ranks of positive differences. Values of
// |d| within kRoundingRelative · s of the smallest of their group are tied,
// s the largest scale in the group (metrics are ratios of counts: one
// fraction reached by two roundings differs in the 16th digit). A
// difference's scale is the larger of |d| and `scales[i]` when given
// (ComparePaired gives max(|a|, |b|), the size its rounding comes from);
// `scales` is empty or as long as `differences`.
// For up to kExactSignedRankMaxPairs nonzero differences p is exact: the
// permutation distribution of W+ over the 2^n sign assignments of these
// ranks (so exact with ties too), p = min(1, 2·min(P(W+ <= w), P(W+ >= w))).
// Above, the normal approximation with tie correction and continuity
// correction: z = (|W+ − n(n+1)/4| − ½) / √(n(n+1)(2n+1)/24 − Σ(t³−t)/48),
// p = erfc(z/√2) (z < 0 → p = 1). No nonzero difference: p = 1.
inline constexpr int kExactSignedRankMaxPairs = 30;
// What rounding may leave between two values that are one: 1e-9 of their
// size. Ties and zeros of the signed-rank test, and the regression gate's
// slack at its tolerance (regress.cc), allow it.
inline constexpr double kRoundingRelative = 1e-9;
struct SignedRankTest {
  int nonzero = 0;      // differences left after dropping zeros
  double w_plus = 0.0;  // sum of the ranks of the positive differences
  double p_value = 1.0;
  bool exact = false;
};
SignedRankTest WilcoxonSignedRank(std::span<const double> differences,
                                  std::span<const double> scales = {});

// The smallest p WilcoxonSignedRank can return for n nonzero differences,
// whatever they are: every difference of one sign. Exact (n <= 30):
// 2 · 2^−n, the one sign assignment with W+ at its maximum; above, the
// normal approximation at W+ = n(n+1)/2 without ties. n <= 0: 1. With 10
// seed pairs it is 0.00195: Holm's correction over more than 25 comparisons
// (first step p < 0.05 / m) can keep none of them, whatever the data.
double SignedRankFloor(int n);
// The fewest nonzero differences whose SignedRankFloor is below alpha / m:
// with that many, each differing, a comparison counts from the first step
// of Holm's correction over m comparisons at level alpha, whatever the
// others (HolmTaroneAdjusted). Precondition: m >= 1, 0 < alpha < 1.
int PairsForHolm(int m, double alpha);

// A paired comparison of two cells on the seeds they share: d_i = a_i − b_i
// for every pair where both values are finite, 0 where |a_i − b_i| is within
// kRoundingRelative of max(|a_i|, |b_i|) (one value reached by two
// roundings).
struct PairedComparison {
  int pairs = 0;                   // n: pairs with both values finite
  int positive = 0, negative = 0;  // pairs with a > b, a < b (the rest tie)
  Interval difference;             // mean of d with its t interval, cut to the
                                   // range of a difference, [lower−upper, upper−lower]
  SignedRankTest test;
};
// `a` and `b` are aligned: a[i] and b[i] are one seed's values.
// Precondition: a.size() == b.size().
PairedComparison ComparePaired(std::span<const double> a, std::span<const double> b,
                               const MetricRange& range);

// Holm's step-down adjustment (Holm 1979) of a family of m p-values for
// testing them all at once: with p_(1) <= ... <= p_(m) sorted ascending,
//   p̃_(i) = min(1, max_{j <= i} (m − j + 1) · p_(j)),
// returned in the order given. Rejecting the hypotheses whose p̃ < α keeps
// the chance of any false rejection in the family at most α, whatever the
// dependence between the tests (correlated metrics of the same runs), and
// rejects at least what Bonferroni (m · p) does. NaN entries are not tests:
// they stay NaN and do not count in m. Ties keep their given order (their
// adjusted values are equal anyway).
std::vector<double> HolmAdjusted(std::span<const double> p_values);

// Tarone's rule (Tarone 1990, "A modified Bonferroni method for discrete
// data") for tests whose p-value cannot fall below a floor (SignedRankFloor
// of their nonzero differences): with floors[i] per test (NaN: not a test),
// K is the smallest k >= 1 with at most k floors below alpha / k, and the
// family is the tests whose floor is below alpha / K: at most K of them, the
// only ones that can reach p < alpha / K. Bonferroni at alpha / K over them
// keeps the chance of any false rejection among all the tests at most alpha
// (K counts every test that could be rejected at that level).
// Precondition: 0 < alpha < 1.
struct TaroneFamily {
  int k = 0;                 // Tarone's K; 0 when there is no test
  std::vector<bool> member;  // per test given, in order
  int size = 0;              // members
};
TaroneFamily TaroneFamilyOf(std::span<const double> floors, double alpha);

// Holm's step-down adjustment with Tarone's rule (Hommel and Krummenauer
// 1998): as HolmAdjusted, but the multiplier at each step is not the count
// of tests left but Tarone's K over them (TaroneFamilyOf their floors at
// `alpha`), never more than that count: a test whose p cannot fall low
// enough to be rejected among the tests left does not make the step
// stricter for the others. With p_(1) <= ... <= p_(m) sorted ascending and
// K_j Tarone's K over the tests from the j-th on,
//   p̃_(i) = min(1, max_{j <= i} K_j · p_(j)),
// and p̃ < alpha exactly where the step-down rejects at level alpha: a
// closed test whose local tests are Tarone's Bonferroni, so the chance of
// any false rejection stays at most alpha, whatever the dependence. It
// rejects at least what HolmAdjusted does. The K_j are taken at `alpha`:
// compare p̃ with alpha, not another level. NaN p-values are not tests.
// Precondition: a floor (not NaN) for every test, 0 < alpha < 1. A floor
// must not exceed what its test can give: SignedRankFloor is exact up to 30
// pairs; above, it is the untied normal approximation's, which a tied test
// can undercut (31 pairs all tied: 2.8e-8), at levels (below 1.3e-6) that
// only a family of more than 40 000 comparisons reaches. The floors follow
// from which seeds tie; the rule's guarantee takes them as given, so a
// difference's sign must not depend on which seeds tie elsewhere.
std::vector<double> HolmTaroneAdjusted(std::span<const double> p_values,
                                       std::span<const double> floors, double alpha);

}  // namespace hcpf::studies
