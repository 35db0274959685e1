#include "hcpf/studies/statistics.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

#include "hcpf/core/check.h"
#include "text.h"

namespace hcpf::studies {

std::vector<double> Finite(std::span<const double> values) {
  std::vector<double> out;
  out.reserve(values.size());
  for (double v : values) {
    if (std::isfinite(v)) out.push_back(v);
  }
  return out;
}

// The mean as v_0 plus the mean of x − v_0: values all equal give v_0
// exactly, so their sum of squared deviations is exactly 0 (summed directly,
// 0.9 ten times has mean 0.8999999999999999 and a variance of 1e-32, which
// made a proportion's band zero wide where n* = n was meant: an audit).
double Mean(std::span<const double> v) {
  if (v.empty()) return std::numeric_limits<double>::quiet_NaN();
  const double v0 = v[0];
  double sum = 0.0;
  for (double x : v) sum += x - v0;
  return v0 + sum / static_cast<double>(v.size());
}

namespace {

// Cuts [lower, upper] to `range`; says whether it had to.
void Clip(Interval& r, double lower, double upper) {
  if (r.lower < lower) {
    r.lower = lower;
    r.clipped = true;
  }
  if (r.upper > upper) {
    r.upper = upper;
    r.clipped = true;
  }
}

}  // namespace

double StudentT975(int dof) {
  HCPF_CHECK(dof >= 1) << "dof=" << dof;
  // Two-sided 95 % critical values of Student's t (standard tables).
  static const double kTable[30] = {12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306,
                                    2.262,  2.228, 2.201, 2.179, 2.160, 2.145, 2.131, 2.120,
                                    2.110,  2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064,
                                    2.060,  2.056, 2.052, 2.048, 2.045, 2.042};
  if (dof <= 30) return kTable[dof - 1];
  // Cornish–Fisher expansion around z = Φ⁻¹(0.975) (Abramowitz & Stegun 26.7.5).
  const double z = kZ975;
  const double v = dof;
  const double z3 = z * z * z, z5 = z3 * z * z, z7 = z5 * z * z;
  return z + (z3 + z) / (4 * v) + (5 * z5 + 16 * z3 + 3 * z) / (96 * v * v) +
         (3 * z7 + 19 * z5 + 17 * z3 - 15 * z) / (384 * v * v * v);
}

Interval StudentInterval95(std::span<const double> values, const MetricRange& range) {
  const std::vector<double> v = Finite(values);
  Interval r;
  r.n = static_cast<int>(v.size());
  if (r.n == 0) return r;
  r.mean = Mean(v);
  r.lower = r.upper = r.mean;
  if (r.n < 2) return r;
  double ss = 0.0;
  for (double x : v) ss += (x - r.mean) * (x - r.mean);
  const double s = std::sqrt(ss / (r.n - 1));
  const double half = StudentT975(r.n - 1) * s / std::sqrt(static_cast<double>(r.n));
  r.lower = r.mean - half;
  r.upper = r.mean + half;
  r.method = IntervalMethod::kStudentT;
  Clip(r, range.lower, range.upper);
  return r;
}

Interval WilsonInterval95(double p_hat, double n) {
  HCPF_CHECK(n > 0.0 && p_hat >= 0.0 && p_hat <= 1.0) << "p_hat=" << p_hat << " n=" << n;
  const double z2 = kZ975 * kZ975;
  const double nn = n;
  const double denominator = 1.0 + z2 / nn;
  const double centre = (p_hat + z2 / (2.0 * nn)) / denominator;
  const double half =
      kZ975 / denominator * std::sqrt(p_hat * (1.0 - p_hat) / nn + z2 / (4.0 * nn * nn));
  Interval r;
  r.n = static_cast<int>(std::lround(n));
  r.trials = n;
  r.mean = p_hat;
  // The bounds are inside [0, 1] in exact arithmetic; rounding can put them
  // an ulp outside at p̂ = 0 or 1, which is not a clip.
  r.lower = std::clamp(centre - half, 0.0, 1.0);
  r.upper = std::clamp(centre + half, 0.0, 1.0);
  r.method = IntervalMethod::kWilson;
  return r;
}

Interval MeanInterval95(std::span<const double> values, const MetricRange& range) {
  if (!range.proportion) return StudentInterval95(values, range);
  const std::vector<double> v = Finite(values);
  if (v.empty()) return Interval{};
  // A value outside [0, 1] is not a fraction (a store written by a metric of
  // another definition): its mean gets the t interval cut to [0, 1] instead.
  for (double x : v) {
    if (x < 0.0 || x > 1.0) return StudentInterval95(v, range);
  }
  const int n = static_cast<int>(v.size());
  const double p = std::clamp(Mean(v), 0.0, 1.0);
  double trials = n;
  if (n >= 2) {
    double ss = 0.0;
    for (double x : v) ss += (x - p) * (x - p);
    const double s2 = ss / (n - 1);
    // Seeds equal but for rounding (0.1 + 0.2 against 0.3) have s² ~ 1e-33:
    // no spread, as for zeros of the signed-rank test, not n* ~ 1e32 and a
    // band of width 0 (a review).
    double largest = 0.0;
    for (double x : v) largest = std::max(largest, std::abs(x));
    if (std::sqrt(s2) > kRoundingRelative * largest) {
      const double df_factor = kZ975 / StudentT975(n - 1);
      trials = n * p * (1.0 - p) / s2 * df_factor * df_factor;
    } else if (p > 0.0 && p < 1.0) {
      // No spread inside (0, 1): the seeds do not vary, and n* grows
      // without bound as s² falls to 0, so the band is the t interval's, of
      // width 0 (until 2026-12-07 it was the binomial's over the seeds, the
      // widest band, which one seed off by 0.01 shrank to nearly nothing: a
      // review). At 0 or 1 the sample can show no spread whatever the
      // uncertainty, and the binomial band over the seeds stays.
      return StudentInterval95(v, range);
    }
  }
  Interval r = WilsonInterval95(p, trials);
  r.n = n;
  return r;
}

namespace {

// The normal approximation's two-sided p for W+ of n nonzero differences
// whose tied groups give Σ(t³ − t) = tie_term (statistics.h).
double NormalSignedRankP(double w_plus, int n, double tie_term) {
  const double nn = n;
  const double mean = nn * (nn + 1.0) / 4.0;
  const double variance = nn * (nn + 1.0) * (2.0 * nn + 1.0) / 24.0 - tie_term / 48.0;
  const double z = (std::abs(w_plus - mean) - 0.5) / std::sqrt(variance);
  return z <= 0.0 ? 1.0 : std::erfc(z / std::sqrt(2.0));
}

}  // namespace

SignedRankTest WilcoxonSignedRank(std::span<const double> differences,
                                  std::span<const double> scales) {
  HCPF_CHECK(scales.empty() || scales.size() == differences.size())
      << scales.size() << " scales for " << differences.size() << " differences";
  SignedRankTest t;
  std::vector<double> d;
  std::vector<double> scale;  // the size rounding is relative to, per difference
  for (size_t i = 0; i < differences.size(); ++i) {
    const double x = differences[i];
    if (!std::isfinite(x) || x == 0.0) continue;
    d.push_back(x);
    scale.push_back(std::max(std::abs(x), scales.empty() ? 0.0 : std::abs(scales[i])));
  }
  const int n = static_cast<int>(d.size());
  t.nonzero = n;
  if (n == 0) return t;
  // Ranks of |d|, ties averaged; kept doubled so that they are integers.
  // Tied: within kRoundingRelative of the largest scale in the group (equal
  // fractions reached by different roundings, 1 − 299/300 and 291/300 −
  // 290/300, differ in the 16th digit: an audit). The scale is that of the
  // values a difference came from, as for zeros: a difference of two values
  // of 1000 carries their rounding, ~1e-13, however small it is (a review:
  // relative to |d| alone, equal differences of large values were not tied).
  std::vector<int> order(n);
  for (int i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return std::abs(d[a]) < std::abs(d[b]) || (std::abs(d[a]) == std::abs(d[b]) && a < b);
  });
  std::vector<int> rank2(n);  // 2 × rank
  double tie_term = 0.0;      // Σ (t³ − t) over groups of tied |d|
  for (int i = 0; i < n;) {
    int j = i;
    const double smallest = std::abs(d[order[i]]);
    double group_scale = scale[order[i]];
    while (j + 1 < n && std::abs(d[order[j + 1]]) - smallest <=
                            kRoundingRelative * std::max(group_scale, scale[order[j + 1]])) {
      ++j;
      group_scale = std::max(group_scale, scale[order[j]]);
    }
    // Positions i..j (0-based) share the ranks i+1..j+1: average (i+j+2)/2.
    for (int k = i; k <= j; ++k) rank2[order[k]] = i + j + 2;
    const double size = j - i + 1;
    tie_term += size * size * size - size;
    i = j + 1;
  }
  int64_t w2 = 0;  // 2 × W+ (up to n(n+1): past int from 46,341 pairs)
  int64_t total2 = 0;
  for (int i = 0; i < n; ++i) {
    total2 += rank2[i];
    if (d[i] > 0) w2 += rank2[i];
  }
  t.w_plus = w2 / 2.0;
  if (n <= kExactSignedRankMaxPairs) {
    // count[s]: sign assignments whose positive doubled ranks sum to s. At
    // most 2^30 of them: exact in a double.
    std::vector<double> count(static_cast<size_t>(total2) + 1, 0.0);
    count[0] = 1.0;
    int reach = 0;
    for (int r : rank2) {
      for (int s = reach; s >= 0; --s) count[static_cast<size_t>(s + r)] += count[s];
      reach += r;
    }
    double at_most = 0.0, at_least = 0.0;
    for (int64_t s = 0; s <= total2; ++s) {
      if (s <= w2) at_most += count[s];
      if (s >= w2) at_least += count[s];
    }
    const double all = std::ldexp(1.0, n);
    t.p_value = std::min(1.0, 2.0 * std::min(at_most, at_least) / all);
    t.exact = true;
    return t;
  }
  t.p_value = NormalSignedRankP(t.w_plus, n, tie_term);
  return t;
}

PairedComparison ComparePaired(std::span<const double> a, std::span<const double> b,
                               const MetricRange& range) {
  HCPF_CHECK(a.size() == b.size()) << a.size() << " vs " << b.size();
  PairedComparison c;
  std::vector<double> d;
  std::vector<double> scales;
  for (size_t i = 0; i < a.size(); ++i) {
    if (!std::isfinite(a[i]) || !std::isfinite(b[i])) continue;
    // A difference within kRoundingRelative of the values is a tie
    // (0.1 + 0.2 against 0.3 differs by 5.6e-17): zero, as the test drops.
    const double scale = std::max(std::abs(a[i]), std::abs(b[i]));
    const double difference =
        std::abs(a[i] - b[i]) <= kRoundingRelative * scale ? 0.0 : a[i] - b[i];
    d.push_back(difference);
    scales.push_back(scale);
    if (difference > 0.0) ++c.positive;
    if (difference < 0.0) ++c.negative;
  }
  c.pairs = static_cast<int>(d.size());
  // A difference of two values in [L, U] lies in [L − U, U − L].
  const double width = range.upper - range.lower;
  MetricRange difference_range;
  if (std::isfinite(width)) {
    difference_range.lower = -width;
    difference_range.upper = width;
  }
  c.difference = StudentInterval95(d, difference_range);
  c.test = WilcoxonSignedRank(d, scales);
  return c;
}

double SignedRankFloor(int n) {
  if (n <= 0) return 1.0;
  if (n <= kExactSignedRankMaxPairs) return std::min(1.0, std::ldexp(2.0, -n));
  const double nn = n;
  return NormalSignedRankP(nn * (nn + 1.0) / 2.0, n, 0.0);  // every rank positive, no ties
}

int PairsForHolm(int m, double alpha) {
  const double threshold = alpha / m;
  int n = 1;
  // The first n that gets below: the floor halves per pair up to 30 and
  // jumps up at 31 (the normal approximation is less extreme than the exact
  // tail), so it is not monotone there; a family of a million comparisons
  // needs 26 pairs.
  while (SignedRankFloor(n) >= threshold && n < 1000) ++n;
  return n;
}

namespace {

// The indices of the tests (p not NaN), by ascending p; ties in given order.
std::vector<size_t> AscendingTests(std::span<const double> p_values) {
  std::vector<size_t> order;
  for (size_t i = 0; i < p_values.size(); ++i) {
    if (!std::isnan(p_values[i])) order.push_back(i);
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return p_values[a] < p_values[b]; });
  return order;
}

// Tarone's K: the smallest k >= 1 with below(k), the count of floors below
// alpha / k, at most k. below(k) falls as k grows and below(n) <= n for n
// floors, so "below(k) <= k" holds from K on and K is in [1, max(n, 1)]: a
// binary search (a counting loop from 1 made the report's correction over
// 10 000 comparisons take half a second, docs/performance.md).
template <typename Below>
int TaroneK(int n, Below below) {
  int lo = 1, hi = std::max(n, 1);
  while (lo < hi) {
    const int mid = lo + (hi - lo) / 2;
    if (below(mid) <= mid) {
      hi = mid;
    } else {
      lo = mid + 1;
    }
  }
  return lo;
}

// Counts of a fixed multiset of floors, sorted, some of them removed: how
// many are left, and how many of those are below x, in O(log n) (a Fenwick
// tree over their ranks).
class FloorsLeft {
 public:
  explicit FloorsLeft(std::vector<double> sorted)
      : sorted_(std::move(sorted)),
        tree_(sorted_.size() + 1, 0),
        left_(static_cast<int>(sorted_.size())) {
    for (size_t i = 0; i < sorted_.size(); ++i) Add(i, 1);
  }
  int size() const { return left_; }
  // Those left below x.
  int Below(double x) const {
    size_t end =
        static_cast<size_t>(std::lower_bound(sorted_.begin(), sorted_.end(), x) - sorted_.begin());
    int count = 0;
    for (; end > 0; end &= end - 1) count += tree_[end];
    return count;
  }
  // Removes the floor at `rank` (its index in the sorted floors).
  void Remove(size_t rank) {
    Add(rank, -1);
    --left_;
  }

 private:
  void Add(size_t rank, int delta) {
    for (size_t i = rank + 1; i < tree_.size(); i += i & (~i + 1)) tree_[i] += delta;
  }
  std::vector<double> sorted_;
  std::vector<int> tree_;
  int left_;
};

}  // namespace

std::vector<double> HolmAdjusted(std::span<const double> p_values) {
  std::vector<double> adjusted(p_values.size(), std::numeric_limits<double>::quiet_NaN());
  const std::vector<size_t> order = AscendingTests(p_values);
  const size_t m = order.size();
  double running = 0.0;  // the max over j <= i keeps the adjusted values monotone
  for (size_t j = 0; j < m; ++j) {
    running = std::max(running, static_cast<double>(m - j) * p_values[order[j]]);
    adjusted[order[j]] = std::min(1.0, running);
  }
  return adjusted;
}

TaroneFamily TaroneFamilyOf(std::span<const double> floors, double alpha) {
  HCPF_CHECK(alpha > 0.0 && alpha < 1.0);
  TaroneFamily family;
  family.member.assign(floors.size(), false);
  std::vector<double> sorted;
  for (const double f : floors) {
    if (!std::isnan(f)) sorted.push_back(f);
  }
  if (sorted.empty()) return family;
  std::sort(sorted.begin(), sorted.end());
  const int k = TaroneK(static_cast<int>(sorted.size()), [&](int j) {
    return std::lower_bound(sorted.begin(), sorted.end(), alpha / j) - sorted.begin();
  });
  family.k = k;
  for (size_t i = 0; i < floors.size(); ++i) {
    family.member[i] = !std::isnan(floors[i]) && floors[i] < alpha / k;
    family.size += family.member[i] ? 1 : 0;
  }
  return family;
}

std::vector<double> HolmTaroneAdjusted(std::span<const double> p_values,
                                       std::span<const double> floors, double alpha) {
  HCPF_CHECK(p_values.size() == floors.size());
  HCPF_CHECK(alpha > 0.0 && alpha < 1.0);
  std::vector<double> adjusted(p_values.size(), std::numeric_limits<double>::quiet_NaN());
  const std::vector<size_t> order = AscendingTests(p_values);
  // Each test's rank among the floors (ties in test order), and the floors
  // of the tests left.
  std::vector<size_t> by_floor = order;
  for (const size_t i : order) HCPF_CHECK(!std::isnan(floors[i]));
  std::stable_sort(by_floor.begin(), by_floor.end(),
                   [&](size_t a, size_t b) { return floors[a] < floors[b]; });
  std::vector<size_t> rank(floors.size());
  std::vector<double> sorted;
  for (size_t r = 0; r < by_floor.size(); ++r) {
    rank[by_floor[r]] = r;
    sorted.push_back(floors[by_floor[r]]);
  }
  FloorsLeft left(std::move(sorted));
  double running = 0.0;  // the max over j <= i keeps the adjusted values monotone
  for (const size_t i : order) {
    const int k = TaroneK(left.size(), [&](int j) { return left.Below(alpha / j); });
    running = std::max(running, static_cast<double>(k) * p_values[i]);
    adjusted[i] = std::min(1.0, running);
    left.Remove(rank[i]);
  }
  return adjusted;
}

}  // namespace hcpf::studies
