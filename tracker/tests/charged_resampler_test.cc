// Charged resampling (DESIGN.md "Charged resampling").
#include <gtest/gtest.h>

#include <cmath>

#include "hcpf/tracker/resampler.h"

namespace hcpf::tracker {
namespace {

ResamplerOptions Charged(double beta, int max_tries = 20,
                         ChargePotential potential = ChargePotential::kGaussian) {
  ResamplerOptions o;
  o.method = ResamplingMethod::kCharged;
  o.beta = beta;
  o.max_tries = max_tries;
  o.potential = potential;
  o.charge = 1.0;
  o.softening_px = 5.0;
  return o;
}

FilterSummary Neighbour(double x, double y, double var = 4.0) {
  FilterSummary s;
  s.id = TrackId{99};
  s.mean = {x, y};
  s.cov << var, 0.0, 0.0, var;
  return s;
}

// N particles on a regular grid over [0, 100) x [0, 10), equal weights.
ParticleSet Strip(int n) {
  ParticleSet set;
  set.Resize(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    set.px[i] = 100.0 * (i % 100) / 100.0 + 0.5;
    set.py[i] = 10.0 * ((i / 100) % 10) / 10.0 + 0.5;
  }
  NormaliseLogWeights(set);
  return set;
}

TEST(ChargedResampler, WithoutOtherFiltersEqualsSystematic) {
  // No charges -> every acceptance probability is 1 and no uniform is drawn:
  // the output is the systematic candidates themselves, draw for draw.
  ParticleSet set = Strip(1000);
  for (size_t i = 0; i < set.size(); ++i) set.log_w[i] = -0.001 * static_cast<double>(i % 37);
  NormaliseLogWeights(set);
  ChargedResampler charged(Charged(5.0));
  SystematicResampler systematic;
  for (uint64_t seed = 0; seed < 20; ++seed) {
    Rng a(seed), b(seed);
    std::vector<int32_t> x(1000), y(1000);
    const ResampleResult r = charged.Resample(set, {}, a, x);
    systematic.Resample(set, {}, b, y);
    EXPECT_EQ(x, y);
    EXPECT_EQ(r.rejections, 0);
    EXPECT_EQ(a.NextU64(), b.NextU64());
  }
}

TEST(ChargedResampler, BetaZeroEqualsSystematicEvenWithNeighbours) {
  ParticleSet set = Strip(500);
  const std::vector<FilterSummary> others = {Neighbour(50, 5)};
  ChargedResampler charged(Charged(0.0));
  SystematicResampler systematic;
  Rng a(3), b(3);
  std::vector<int32_t> x(500), y(500);
  EXPECT_EQ(charged.Resample(set, {others}, a, x).rejections, 0);
  systematic.Resample(set, {}, b, y);
  EXPECT_EQ(x, y);
}

double FractionNear(const ParticleSet& set, std::span<const int32_t> a, double cx, double cy,
                    double radius) {
  int64_t near = 0;
  for (const int32_t i : a) {
    const double dx = set.px[i] - cx;
    const double dy = set.py[i] - cy;
    near += dx * dx + dy * dy < radius * radius ? 1 : 0;
  }
  return static_cast<double>(near) / static_cast<double>(a.size());
}

TEST(ChargedResampler, NeighbourRegionEmptiesAsBetaGrows) {
  // Uniform strip [0,100)x[0,10), neighbour at (80, 5) with Sigma = 4 I,
  // eps = 5: U = exp(-d^2 / (2 * 29)). Region: within 8 px of (80, 5); its
  // share of the strip at beta = 0 is ~0.16 (16 of 100 columns, clipped disc).
  // Each fraction is a mean over N = 10000 slots: binomial standard error
  // <= sqrt(0.25 / 10000) = 0.005; adjacent betas must differ by more than
  // 4 such errors (0.02) -- the expected gaps are several times that.
  const ParticleSet set = Strip(10000);
  const std::vector<FilterSummary> others = {Neighbour(80.0, 5.0)};
  double previous = 1.0;
  for (const double beta : {0.0, 1.0, 3.0, 10.0}) {
    ChargedResampler charged(Charged(beta));
    Rng rng(7);
    std::vector<int32_t> a(set.size());
    charged.Resample(set, {others}, rng, a);
    const double f = FractionNear(set, a, 80.0, 5.0, 8.0);
    EXPECT_LT(f, previous - 0.02) << "beta=" << beta;
    previous = f;
  }
  EXPECT_LT(previous, 0.02);
}

TEST(ChargedResampler, CoulombPotentialAlsoRepels) {
  // Coulomb with q = 1, eps = 5: U at the neighbour = 1/25; beta = 200 makes
  // exp(-8) ~ 3e-4 acceptance there.
  const ParticleSet set = Strip(10000);
  const std::vector<FilterSummary> others = {Neighbour(30.0, 5.0)};
  Rng r0(8), r1(8);
  std::vector<int32_t> a(set.size()), b(set.size());
  ChargedResampler(Charged(0.0, 20, ChargePotential::kCoulomb)).Resample(set, {others}, r0, a);
  ChargedResampler(Charged(200.0, 20, ChargePotential::kCoulomb)).Resample(set, {others}, r1, b);
  EXPECT_GT(FractionNear(set, a, 30.0, 5.0, 4.0), 0.04);
  EXPECT_LT(FractionNear(set, b, 30.0, 5.0, 4.0), 0.01);
}

TEST(ChargedResampler, PotentialHandValues) {
  // Gaussian: Sigma = 4 I, eps = 5 -> M = I / 29; at distance 3: exp(-9/58).
  // Coulomb: 1 / (9 + 25).
  const std::vector<FilterSummary> others = {Neighbour(0.0, 0.0)};
  EXPECT_NEAR(ChargedResampler(Charged(1.0)).Potential(3.0, 0.0, others), std::exp(-9.0 / 58.0),
              1e-14);
  EXPECT_NEAR(
      ChargedResampler(Charged(1.0, 20, ChargePotential::kCoulomb)).Potential(0.0, 3.0, others),
      1.0 / 34.0, 1e-15);
}

// Two clusters: particles [0, N/2) at the neighbour's mean (U = q = 1,
// acceptance exp(-beta) = exp(-60) ~ 1e-26: always rejected in practice) and
// [N/2, N) 1000 px away (U = exp(-1e6/58) = 0 exactly: always accepted).
ParticleSet NearFar(int n) {
  ParticleSet set;
  set.Resize(static_cast<size_t>(n));
  for (int i = 0; i < n; ++i) {
    set.px[i] = i < n / 2 ? 0.0 : 1000.0;
    set.py[i] = 0.0;
  }
  NormaliseLogWeights(set);
  return set;
}

TEST(ChargedResampler, RejectionsEqualNearCandidatesWhenNoRetries) {
  // max_tries = 0: every candidate is kept and each near one counts exactly
  // one rejection, so the count must equal the number of near ancestors.
  const ParticleSet set = NearFar(2000);
  const std::vector<FilterSummary> others = {Neighbour(0.0, 0.0)};
  ChargedResampler charged(Charged(60.0, 0));
  Rng rng(9);
  std::vector<int32_t> a(2000);
  const ResampleResult r = charged.Resample(set, {others}, rng, a);
  int64_t near = 0;
  for (const int32_t i : a) near += i < 1000 ? 1 : 0;
  EXPECT_EQ(r.rejections, near);
  EXPECT_EQ(near, 1000);               // systematic on equal weights: each particle once
  EXPECT_EQ(r.potential_terms, 2000);  // every candidate against the one charge
}

// The potential terms are every draw times the charges within reach: with
// no redraws, N candidates against the two neighbours near the particles;
// the one 10^4 px away is out of reach (its exponent is below -40 at every
// particle) and weighs nothing.
TEST(ChargedResampler, PotentialTermsAreDrawsTimesChargesWithinReach) {
  const ParticleSet set = Strip(1000);
  const std::vector<FilterSummary> others = {Neighbour(20.0, 5.0), Neighbour(80.0, 5.0),
                                             Neighbour(1e4, 1e4)};
  ChargedResampler charged(Charged(1.0, 0));
  Rng rng(3);
  std::vector<int32_t> a(1000);
  EXPECT_EQ(charged.Resample(set, {others}, rng, a).potential_terms, 1000 * 2);
  const std::vector<FilterSummary> far = {Neighbour(1e4, 1e4)};
  EXPECT_EQ(charged.Resample(set, {far}, rng, a).potential_terms, 0);
}

TEST(ChargedResampler, AllRejectedCountsEveryDrawAndKeepsLowestPotential) {
  // Particles [0, 150) sit on the neighbour (U = 1), [150, 300) 1 px away
  // (U = exp(-1/58) = 0.983). With beta = 60 both acceptances are below
  // e^-58: every draw is rejected, so each slot counts 1 + max_tries = 8
  // rejections (N * 8 in total) and keeps its lowest-U draw. A slot keeps an
  // on-neighbour particle only if all 8 draws were on it: the 150 slots with
  // such a candidate then need 7 replacement draws from that half
  // (probability 2^-7 each), so on average 150 / 128 = 1.2 slots; more than
  // 10 has Poisson probability ~1e-8.
  ParticleSet set;
  set.Resize(300);
  for (size_t i = 0; i < 300; ++i) set.px[i] = i < 150 ? 0.0 : 1.0;
  NormaliseLogWeights(set);
  const std::vector<FilterSummary> others = {Neighbour(0.0, 0.0)};
  ChargedResampler charged(Charged(60.0, 7));
  Rng rng(10);
  std::vector<int32_t> a(300);
  const ResampleResult r = charged.Resample(set, {others}, rng, a);
  EXPECT_EQ(r.rejections, 300 * (1 + 7));
  EXPECT_EQ(r.potential_terms, 300 * (1 + 7));  // every draw, one charge
  int on_neighbour = 0;
  for (size_t slot = 0; slot < 300; ++slot) {
    // Systematic candidates on equal weights are the identity: slots >= 150
    // start from a 1-px particle, which no later draw can beat.
    if (slot >= 150) {
      EXPECT_GE(a[slot], 150) << slot;
    }
    on_neighbour += a[slot] < 150 ? 1 : 0;
  }
  EXPECT_LE(on_neighbour, 10);
}

TEST(ChargedResampler, RejectionCountMatchesGeometricExpectation) {
  // Near/far halves, max_tries T = 20. Systematic candidates: exactly 1000
  // near. Each near candidate is rejected, then replacements are near with
  // probability 1/2 each until a far one is drawn (accepted) or T run out:
  // rejections per near slot = 1 + G, G ~ Geometric(1/2) failures truncated
  // at T, E[1 + G] = sum_{t=0}^{T} 2^-t = 2 - 2^-20, Var G <= (1-p)/p^2 = 2.
  // Total: mean 1000 (2 - 2^-20) ~ 2000, sd <= sqrt(1000 * 2) = 44.7;
  // tolerance 5 sd = 224. Near ancestors survive only if all 21 draws were
  // near: expected 1000 * 2^-20 ~ 0.001, so none.
  const ParticleSet set = NearFar(2000);
  const std::vector<FilterSummary> others = {Neighbour(0.0, 0.0)};
  ChargedResampler charged(Charged(60.0, 20));
  Rng rng(11);
  std::vector<int32_t> a(2000);
  const ResampleResult r = charged.Resample(set, {others}, rng, a);
  EXPECT_NEAR(static_cast<double>(r.rejections), 1000.0 * (2.0 - std::pow(2.0, -20)), 224.0);
  for (const int32_t i : a) EXPECT_GE(i, 1000);
}

}  // namespace
}  // namespace hcpf::tracker
