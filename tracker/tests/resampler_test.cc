// Contract suite run against every registered resampler (each name of
// ResamplingMethod; a new method is covered by registering its name) and the
// ESS-gated wrapper.
#include "hcpf/tracker/resampler.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>

#include "hcpf/core/error.h"

namespace hcpf::tracker {
namespace {

struct ResamplerCase {
  std::string name;
  std::function<std::unique_ptr<Resampler>()> make;
};

std::unique_ptr<Resampler> Make(ResamplingMethod method, double ess_threshold = 0.0) {
  ResamplerOptions o;
  o.method = method;
  o.ess_threshold = ess_threshold;
  return MakeResampler(o);
}

std::vector<ResamplerCase> Resamplers() {
  std::vector<ResamplerCase> cases;
  // Charged, with no other filter in the context, reduces to its candidates.
  for (const ResamplingMethod method : EnumValues<ResamplingMethod>()) {
    cases.push_back({std::string(ToString(method)), [method] { return Make(method); }});
  }
  // Threshold 1: resamples whenever the weights are not all equal, so the
  // frequency test exercises the inner resampler through the wrapper.
  cases.push_back(
      {"ess_gated_systematic", [] { return Make(ResamplingMethod::kSystematic, 1.0); }});
  cases.push_back(
      {"ess_gated_multinomial", [] { return Make(ResamplingMethod::kMultinomial, 1.0); }});
  return cases;
}

class ResamplerContract : public ::testing::TestWithParam<ResamplerCase> {
 protected:
  static ParticleSet WithWeights(const std::vector<double>& log_w) {
    ParticleSet set;
    set.Resize(log_w.size());
    for (size_t i = 0; i < log_w.size(); ++i) set.px[i] = static_cast<double>(i);
    set.log_w = log_w;
    NormaliseLogWeights(set);
    return set;
  }
  static std::vector<int64_t> Counts(std::span<const int32_t> a, size_t n) {
    std::vector<int64_t> c(n, 0);
    for (const int32_t i : a) ++c[static_cast<size_t>(i)];
    return c;
  }
};

TEST_P(ResamplerContract, ExactlyNIndicesInRange) {
  const auto r = GetParam().make();
  Rng rng(1);
  for (const size_t n : {1UL, 2UL, 7UL, 256UL, 1001UL}) {
    std::vector<double> lw(n);
    for (size_t i = 0; i < n; ++i) lw[i] = -0.01 * static_cast<double>(i * i % 97);
    const ParticleSet set = WithWeights(lw);
    std::vector<int32_t> a(n, -1);
    r->Resample(set, {}, rng, a);
    for (const int32_t i : a) {
      ASSERT_GE(i, 0);
      ASSERT_LT(i, static_cast<int32_t>(n));
    }
  }
}

TEST_P(ResamplerContract, SelectionFrequenciesConvergeToWeights) {
  // R repetitions with N = 8 particles. The count C_i of particle i over all
  // repetitions has mean R N w_i. For multinomial each repetition's count is
  // Binomial(N, w_i), so Var C_i = R N w_i (1 - w_i); systematic, stratified
  // and residual have smaller variance (their counts are floor/ceil of N w_i
  // or a multinomial on the residual only), so the multinomial value bounds
  // them all. Tolerance: 5 standard deviations (two-sided p ~ 6e-7 per
  // particle under the null), fixed seed. Particle 5 has weight 0: never.
  const std::vector<double> w = {0.05, 0.1, 0.15, 0.2, 0.25, 0.0, 0.15, 0.1};
  std::vector<double> lw(w.size());
  for (size_t i = 0; i < w.size(); ++i) lw[i] = std::log(w[i]);
  const ParticleSet set = WithWeights(lw);
  const auto r = GetParam().make();
  Rng rng(2);
  const int reps = 20000;
  const auto n = static_cast<double>(w.size());
  std::vector<int64_t> total(w.size(), 0);
  std::vector<int32_t> a(w.size());
  for (int rep = 0; rep < reps; ++rep) {
    r->Resample(set, {}, rng, a);
    const auto c = Counts(a, w.size());
    for (size_t i = 0; i < w.size(); ++i) total[i] += c[i];
  }
  for (size_t i = 0; i < w.size(); ++i) {
    const double mean = reps * n * w[i];
    const double sd = std::sqrt(reps * n * w[i] * (1.0 - w[i]));
    EXPECT_NEAR(static_cast<double>(total[i]), mean, 5.0 * sd + 1e-9) << "particle " << i;
  }
  EXPECT_EQ(total[5], 0);
}

TEST_P(ResamplerContract, IdenticalRngStateGivesIdenticalOutput) {
  std::vector<double> lw(500);
  for (size_t i = 0; i < lw.size(); ++i) lw[i] = std::sin(0.1 * static_cast<double>(i));
  const ParticleSet set = WithWeights(lw);
  const auto r = GetParam().make();
  Rng a_rng(77), b_rng(77);
  std::vector<int32_t> a(500), b(500);
  r->Resample(set, {}, a_rng, a);
  r->Resample(set, {}, b_rng, b);
  EXPECT_EQ(a, b);
  EXPECT_EQ(a_rng.NextU64(), b_rng.NextU64());  // consumed the same amount
}

TEST_P(ResamplerContract, OneNonZeroWeightSelectsOnlyIt) {
  constexpr double kNegInf = -std::numeric_limits<double>::infinity();
  std::vector<double> lw(64, kNegInf);
  lw[37] = -5.0;
  const ParticleSet set = WithWeights(lw);
  const auto r = GetParam().make();
  Rng rng(3);
  std::vector<int32_t> a(64);
  r->Resample(set, {}, rng, a);
  for (const int32_t i : a) EXPECT_EQ(i, 37);
}

TEST_P(ResamplerContract, AllEqualWeightsKeepEveryIndexValid) {
  // Equal weights: every count has mean 1. Systematic-type schemes give each
  // particle exactly once, and so do the ESS-gated wrappers (ESS = N: no
  // resampling). Multinomial draws N independent indices: the number of
  // distinct ones has mean N(1 − (1 − 1/N)^N) = 63.4 for N = 100 and
  // standard deviation 3.1 (the occupancy problem's variance, N(1 − 1/N)^N +
  // N(N − 1)(1 − 2/N)^N − N²(1 − 1/N)^2N), so [48, 79] is ±5 sd.
  const ParticleSet set = WithWeights(std::vector<double>(100, 0.0));
  const auto r = GetParam().make();
  Rng rng(4);
  std::vector<int32_t> a(100, -1);
  r->Resample(set, {}, rng, a);
  for (const int32_t i : a) {
    ASSERT_GE(i, 0);
    ASSERT_LT(i, 100);
  }
  const auto c = Counts(a, 100);
  const std::string name = GetParam().name;
  if (name == "multinomial") {
    const auto distinct = std::count_if(c.begin(), c.end(), [](int64_t v) { return v > 0; });
    EXPECT_GE(distinct, 48);
    EXPECT_LE(distinct, 79);
  } else {
    for (const int64_t v : c) EXPECT_EQ(v, 1) << name;
  }
}

TEST_P(ResamplerContract, MinusInfinityWeightIsNeverSelected) {
  constexpr double kNegInf = -std::numeric_limits<double>::infinity();
  std::vector<double> lw(50, 0.0);
  lw[0] = kNegInf;
  lw[17] = kNegInf;
  lw[49] = kNegInf;
  const ParticleSet set = WithWeights(lw);
  const auto r = GetParam().make();
  Rng rng(5);
  std::vector<int32_t> a(50);
  for (int rep = 0; rep < 200; ++rep) {
    r->Resample(set, {}, rng, a);
    for (const int32_t i : a) {
      ASSERT_NE(i, 0);
      ASSERT_NE(i, 17);
      ASSERT_NE(i, 49);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllResamplers, ResamplerContract, ::testing::ValuesIn(Resamplers()),
                         [](const auto& info) { return info.param.name; });

TEST(SystematicResampler, HandComputedAncestors) {
  // Weights (0.5, 0.25, 0.25), N = 3: points u0 + i/3. With any u0 in
  // [0, 1/3): 0 lands in [0, .5) -> 0; 1/3 + u0 in [1/3, 2/3): -> 0 if < .5
  // else 1; 2/3 + u0 in [2/3, 1) -> 1 if < .75 else 2. Checked over many u0
  // (many seeds): each output must be one of those two cases.
  ParticleSet set;
  set.Resize(3);
  set.log_w = {std::log(0.5), std::log(0.25), std::log(0.25)};
  NormaliseLogWeights(set);
  SystematicResampler r;
  for (uint64_t seed = 0; seed < 200; ++seed) {
    Rng rng(seed);
    const double u0 = Rng(seed).Uniform() / 3.0;
    std::vector<int32_t> a(3);
    r.Resample(set, {}, rng, a);
    EXPECT_EQ(a[0], 0);
    EXPECT_EQ(a[1], u0 + 1.0 / 3.0 < 0.5 ? 0 : 1);
    EXPECT_EQ(a[2], u0 + 2.0 / 3.0 < 0.75 ? 1 : 2);
  }
}

TEST(ResidualResampler, DeterministicCopiesComeFirst) {
  // Weights (0.5, 0.3, 0.2), N = 3: N w = (1.5, 0.9, 0.6) -> one sure copy of
  // particle 0 in slot 0; the other two slots are multinomial draws on the
  // residuals (0.5, 0.9, 0.6) / 2. Over 3000 repetitions the residual slots
  // select particle 1 with probability 0.45: 6000 draws, sd sqrt(6000 * 0.45
  // * 0.55) = 38.5, tolerance 5 sd.
  ParticleSet set;
  set.Resize(3);
  set.log_w = {std::log(0.5), std::log(0.3), std::log(0.2)};
  NormaliseLogWeights(set);
  ResidualResampler r;
  Rng rng(21);
  std::vector<int32_t> a(3);
  int64_t ones = 0;
  for (int rep = 0; rep < 3000; ++rep) {
    r.Resample(set, {}, rng, a);
    ASSERT_EQ(a[0], 0);
    ones += (a[1] == 1) + (a[2] == 1);
  }
  EXPECT_NEAR(static_cast<double>(ones), 6000 * 0.45, 5 * 38.5);
}

TEST(StratifiedResampler, EachPointStaysInItsStratum) {
  // Weights (0.5, 0.5), N = 2: point 0 in [0, 0.5) -> particle 0, point 1 in
  // [0.5, 1) -> particle 1, whatever the uniforms: the output is always (0, 1).
  ParticleSet set;
  set.Resize(2);
  NormaliseLogWeights(set);
  StratifiedResampler r;
  Rng rng(22);
  std::vector<int32_t> a(2);
  for (int rep = 0; rep < 1000; ++rep) {
    r.Resample(set, {}, rng, a);
    ASSERT_EQ(a, (std::vector<int32_t>{0, 1}));
  }
}

TEST(EssGatedResampler, SkipsWhenEssHighAndDrawsNothing) {
  // Weights (0.3, 0.7): ESS = 1 / (0.09 + 0.49) = 1.724 = 0.862 N.
  ParticleSet set;
  set.Resize(2);
  set.log_w = {std::log(0.3), std::log(0.7)};
  NormaliseLogWeights(set);
  EssGatedResampler gated(std::make_unique<MultinomialResampler>(), 0.8);
  Rng rng(1), untouched(1);
  std::vector<int32_t> a(2);
  const ResampleResult r = gated.Resample(set, {}, rng, a);
  EXPECT_FALSE(r.resampled);
  EXPECT_EQ(a, (std::vector<int32_t>{0, 1}));
  EXPECT_EQ(rng.NextU64(), untouched.NextU64());
  EssGatedResampler strict(std::make_unique<MultinomialResampler>(), 0.9);
  EXPECT_TRUE(strict.Resample(set, {}, rng, a).resampled);
}

TEST(ResamplerOptions, DefaultsValidateAndErrorsNameTheField) {
  EXPECT_NO_THROW(ResamplerOptions{}.Validate());
  auto expect_key = [](ResamplerOptions o, const std::string& key) {
    try {
      o.Validate();
      FAIL() << "expected InputError for " << key;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    }
  };
  ResamplerOptions o;
  o.beta = -1.0;
  expect_key(o, "tracker.resampling.beta");
  o = {};
  o.softening_px = 0.0;
  expect_key(o, "tracker.resampling.softening_px");
  o = {};
  o.max_tries = -2;
  expect_key(o, "tracker.resampling.max_tries");
  o = {};
  o.ess_threshold = 1.5;
  expect_key(o, "tracker.resampling.ess_threshold");
  o = {};
  o.candidates = ResamplingMethod::kCharged;
  expect_key(o, "tracker.resampling.candidates");
}

TEST(ResamplingMethod, NamesRoundTrip) {
  for (const auto name : NamesOf<ResamplingMethod>()) {
    const auto m = ParseName<ResamplingMethod>(name);
    ASSERT_TRUE(m.has_value()) << name;
    ResamplerOptions o;
    o.method = *m;
    EXPECT_EQ(MakeResampler(o)->name(), name);
  }
  for (const auto name : NamesOf<ChargePotential>()) {
    const auto p = ParseName<ChargePotential>(name);
    ASSERT_TRUE(p.has_value());
    EXPECT_EQ(ToString(*p), name);
  }
  EXPECT_FALSE(ParseName<ResamplingMethod>("Systematic").has_value());
}

}  // namespace
}  // namespace hcpf::tracker
