// The hot loops are built for AVX-512, AVX2 and the baseline
// (HCPF_DISPATCHED, hcpf/core/instruction_set.h); which one runs depends on
// the machine. Determinism requires that they compute the same bits. Two
// checks: the kernels built here for each instruction set explicitly (this
// file is compiled with -O3 so the loops are vectorised as in the library)
// against a scalar, unvectorised build on random inputs (any FMA contraction
// or approximate instruction in one shows up as a mismatch); and the
// library's own builds, each run through the public functions that call them
// (the likelihood, the weight normalisation, the multinomial and charged
// resamplers), against the library's baseline build.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

#include "charge_kernel.h"
#include "fast_math.h"
#include "hcpf/core/instruction_set.h"
#include "hcpf/core/rng.h"
#include "hcpf/tracker/likelihood.h"
#include "hcpf/tracker/particle_set.h"
#include "hcpf/tracker/resampler.h"
#include "mixture_kernel.h"

namespace hcpf::tracker {
namespace {

using internal::Charge;
using internal::MixtureComponent;

struct Inputs {
  std::vector<MixtureComponent> comps;
  std::vector<Charge> charges;
  std::vector<double> px, py, log_s, x;
};

Inputs MakeInputs(size_t n, uint64_t seed) {
  Rng rng(seed);
  Inputs in;
  for (int d = 0; d < 10; ++d) {
    MixtureComponent c;
    c.cx = 320.0 + 60.0 * rng.Normal();
    c.cy = 240.0 + 60.0 * rng.Normal();
    c.log_weight = -8.0 + rng.Normal();
    c.weight = std::exp(c.log_weight);
    c.log_size_offset = 0.2 * rng.Normal();
    in.comps.push_back(c);
    // Charges of neighbours 60 px around, softened covariances of 5-20 px.
    const double sxx = 25.0 + 375.0 * rng.Uniform(0.0, 1.0);
    const double syy = 25.0 + 375.0 * rng.Uniform(0.0, 1.0);
    const double sxy = 0.3 * std::sqrt(sxx * syy) * rng.Uniform(-1.0, 1.0);
    const double det = sxx * syy - sxy * sxy;
    in.charges.push_back({320.0 + 60.0 * rng.Normal(), 240.0 + 60.0 * rng.Normal(), syy / det,
                          -sxy / det, sxx / det});
  }
  for (size_t i = 0; i < n; ++i) {
    in.px.push_back(320.0 + 40.0 * rng.Normal());
    in.py.push_back(240.0 + 40.0 * rng.Normal());
    in.log_s.push_back(0.1 * rng.Normal());
    // Arguments for exp/log across their whole range, negative and tiny ones too.
    in.x.push_back(rng.Uniform(-750.0, 750.0));
  }
  return in;
}

#define HCPF_KERNELS(SUFFIX, ATTR)                                                                 \
  ATTR void Mixture##SUFFIX(const Inputs& in, bool size, double* sum) {                            \
    const size_t m = in.px.size();                                                                 \
    if (size) {                                                                                    \
      internal::MixtureKernel<true>(in.comps.data(), in.comps.size(), in.px.data(), in.py.data(),  \
                                    in.log_s.data(), 1.0 / 18.0, 1.0 / 0.08, sum, m);              \
    } else {                                                                                       \
      internal::MixtureKernel<false>(in.comps.data(), in.comps.size(), in.px.data(), in.py.data(), \
                                     in.log_s.data(), 1.0 / 18.0, 0.0, sum, m);                    \
    }                                                                                              \
  }                                                                                                \
  ATTR void Accept##SUFFIX(const Inputs& in, bool gaussian, double* u, double* accept) {           \
    internal::AcceptanceKernel(in.charges.data(), in.charges.size(), gaussian, 40.0, 0.5, 9.0,     \
                               in.px.data(), in.py.data(), u, accept, in.px.size());               \
  }                                                                                                \
  ATTR void Exp##SUFFIX(const std::vector<double>& x, double* out) {                               \
    for (size_t i = 0; i < x.size(); ++i) out[i] = internal::FastExp(x[i]);                        \
  }                                                                                                \
  ATTR void ExpF##SUFFIX(const std::vector<double>& x, double* out) {                              \
    for (size_t i = 0; i < x.size(); ++i) {                                                        \
      out[i] = internal::FastExpF(static_cast<float>(x[i] * 0.125));                               \
    }                                                                                              \
  }                                                                                                \
  ATTR void Log##SUFFIX(const std::vector<double>& x, double* out) {                               \
    for (size_t i = 0; i < x.size(); ++i) out[i] = internal::FastLog(x[i] * x[i] * 1e-300);        \
  }

HCPF_KERNELS(Scalar, __attribute__((noinline, optimize("no-tree-vectorize"))))
HCPF_KERNELS(Baseline, __attribute__((noinline)))
HCPF_KERNELS(Avx2, __attribute__((noinline, target("avx2"))))
HCPF_KERNELS(Avx512, __attribute__((noinline, target("avx512f"))))
#undef HCPF_KERNELS

using Kernels = void (*)(const Inputs&, bool, double*);
using Acceptance = void (*)(const Inputs&, bool, double*, double*);
using Map = void (*)(const std::vector<double>&, double*);

struct Isa {
  const char* name;
  bool supported;
  Kernels mixture;
  Acceptance accept;
  Map exp;
  Map expf;
  Map log;
};

std::vector<Isa> Isas() {
  __builtin_cpu_init();
  return {
      {"baseline", true, MixtureBaseline, AcceptBaseline, ExpBaseline, ExpFBaseline, LogBaseline},
      {"avx2", __builtin_cpu_supports("avx2") != 0, MixtureAvx2, AcceptAvx2, ExpAvx2, ExpFAvx2,
       LogAvx2},
      {"avx512f", __builtin_cpu_supports("avx512f") != 0, MixtureAvx512, AcceptAvx512, ExpAvx512,
       ExpFAvx512, LogAvx512}};
}

bool SameBits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

TEST(IsaClones, EveryInstructionSetComputesTheScalarBits) {
  // 1003 particles: not a multiple of any vector width, so the remainder
  // loops run too.
  const Inputs in = MakeInputs(1003, 77);
  const size_t n = in.px.size();
  std::vector<double> ref_mix(n), ref_mix_size(n), ref_exp(n), ref_expf(n), ref_log(n);
  std::vector<double> ref_u_gauss(n), ref_gauss(n), ref_u_coulomb(n), ref_coulomb(n);
  MixtureScalar(in, false, ref_mix.data());
  MixtureScalar(in, true, ref_mix_size.data());
  AcceptScalar(in, true, ref_u_gauss.data(), ref_gauss.data());
  AcceptScalar(in, false, ref_u_coulomb.data(), ref_coulomb.data());
  ExpScalar(in.x, ref_exp.data());
  ExpFScalar(in.x, ref_expf.data());
  LogScalar(in.x, ref_log.data());
  // The inputs reach the kernels' whole range: some candidates are repelled
  // hard (acceptance near 0), some barely (near 1).
  EXPECT_LT(*std::min_element(ref_gauss.begin(), ref_gauss.end()), 0.01);
  EXPECT_GT(*std::max_element(ref_gauss.begin(), ref_gauss.end()), 0.99);
  for (const Isa& isa : Isas()) {
    if (!isa.supported) {
      std::printf("[ SKIPPED  ] %s: this CPU does not have it\n", isa.name);
      continue;
    }
    std::vector<double> mix(n), mix_size(n), e(n), ef(n), l(n);
    std::vector<double> u_gauss(n), gauss(n), u_coulomb(n), coulomb(n);
    isa.mixture(in, false, mix.data());
    isa.mixture(in, true, mix_size.data());
    isa.accept(in, true, u_gauss.data(), gauss.data());
    isa.accept(in, false, u_coulomb.data(), coulomb.data());
    isa.exp(in.x, e.data());
    isa.expf(in.x, ef.data());
    isa.log(in.x, l.data());
    EXPECT_TRUE(SameBits(mix, ref_mix)) << isa.name << ": mixture (position only)";
    EXPECT_TRUE(SameBits(mix_size, ref_mix_size)) << isa.name << ": mixture with size";
    EXPECT_TRUE(SameBits(u_gauss, ref_u_gauss)) << isa.name << ": gaussian potential";
    EXPECT_TRUE(SameBits(gauss, ref_gauss)) << isa.name << ": gaussian acceptance";
    EXPECT_TRUE(SameBits(u_coulomb, ref_u_coulomb)) << isa.name << ": coulomb potential";
    EXPECT_TRUE(SameBits(coulomb, ref_coulomb)) << isa.name << ": coulomb acceptance";
    EXPECT_TRUE(SameBits(e, ref_exp)) << isa.name << ": FastExp";
    EXPECT_TRUE(SameBits(ef, ref_expf)) << isa.name << ": FastExpF";
    EXPECT_TRUE(SameBits(l, ref_log)) << isa.name << ": FastLog";
  }
}

// What the library computes with the active instruction set on 1003
// particles: the detections-mixture likelihood without and with the size
// term, the normalised weights, and the ancestors of the multinomial
// resampler (its sorted uniforms go through NegLogInPlace) and of the
// charged one under both potentials (with their rejection counts).
struct LibraryOutputs {
  std::vector<double> log_w, log_w_size, w;
  std::vector<int32_t> multinomial, gaussian, coulomb;
  int64_t gaussian_rejections = 0, coulomb_rejections = 0;
};

LibraryOutputs RunLibrary(const Inputs& in) {
  const size_t n = in.px.size();
  ParticleSet set;
  set.Resize(n);
  for (size_t i = 0; i < n; ++i) {
    set.px[i] = in.px[i];
    set.py[i] = in.py[i];
    set.s[i] = std::exp(in.log_s[i]);
  }
  Observation obs;
  for (const MixtureComponent& c : in.comps) {
    obs.detections.push_back({.box = BoxPx::FromCentre(c.cx, c.cy, 12.0, 12.0),
                              .score = 0.2 + 0.8 * c.weight / (c.weight + 1e-4)});
  }
  LikelihoodOptions options;
  options.sigma_px = 2.0;
  options.clutter_density = 1e-8;
  LibraryOutputs out;
  ParticleSet sized = set;
  DetectionsMixtureLikelihood(options).AddLogLikelihood(set, {.observation = &obs});
  out.log_w = set.log_w;
  options.sigma_log_size = 0.2;
  DetectionsMixtureLikelihood(options).AddLogLikelihood(sized,
                                                        {.observation = &obs, .base_w_px = 12.0});
  out.log_w_size = sized.log_w;
  NormaliseLogWeights(set);
  out.w = set.w;
  const auto ancestors = [&](const ResamplerOptions& o, std::span<const FilterSummary> others,
                             int64_t* rejections) {
    std::vector<int32_t> a(n);
    Rng rng(5);
    const ResampleResult r = MakeResampler(o)->Resample(set, {others}, rng, a);
    if (rejections != nullptr) *rejections = r.rejections;
    return a;
  };
  ResamplerOptions multinomial;
  multinomial.method = ResamplingMethod::kMultinomial;
  out.multinomial = ancestors(multinomial, {}, nullptr);
  std::vector<FilterSummary> others;
  for (const Charge& ch : in.charges) {
    FilterSummary f;
    f.mean = {ch.mx, ch.my};
    f.cov << 9.0, 0.0, 0.0, 9.0;
    others.push_back(f);
  }
  ResamplerOptions charged;
  charged.method = ResamplingMethod::kCharged;
  charged.beta = 2.0;
  charged.softening_px = 6.0;
  out.gaussian = ancestors(charged, others, &out.gaussian_rejections);
  charged.potential = ChargePotential::kCoulomb;
  charged.charge = 40.0;
  out.coulomb = ancestors(charged, others, &out.coulomb_rejections);
  return out;
}

TEST(IsaClones, TheLibrarysBuildsComputeTheSameBits) {
  const Inputs in = MakeInputs(1003, 91);
  LibraryOutputs expected;
  {
    const hcpf::testing::ScopedInstructionSet baseline(InstructionSet::kBaseline);
    expected = RunLibrary(in);
  }
  // The inputs exercise every path: the weights are far from uniform and
  // the charges reject some candidates under both potentials.
  EXPECT_GT(*std::max_element(expected.w.begin(), expected.w.end()),
            1e3 * *std::min_element(expected.w.begin(), expected.w.end()));
  EXPECT_GT(expected.gaussian_rejections, 0);
  EXPECT_GT(expected.coulomb_rejections, 0);
  hcpf::testing::ForEachInstructionSetOfThisCpu([&](InstructionSet set) {
    const LibraryOutputs out = RunLibrary(in);
    EXPECT_TRUE(SameBits(out.log_w, expected.log_w)) << NameOf(set) << ": mixture likelihood";
    EXPECT_TRUE(SameBits(out.log_w_size, expected.log_w_size))
        << NameOf(set) << ": mixture likelihood with size";
    EXPECT_TRUE(SameBits(out.w, expected.w)) << NameOf(set) << ": normalised weights";
    EXPECT_EQ(out.multinomial, expected.multinomial) << NameOf(set) << ": multinomial";
    EXPECT_EQ(out.gaussian, expected.gaussian) << NameOf(set) << ": charged, gaussian";
    EXPECT_EQ(out.coulomb, expected.coulomb) << NameOf(set) << ": charged, coulomb";
    EXPECT_EQ(out.gaussian_rejections, expected.gaussian_rejections) << NameOf(set);
    EXPECT_EQ(out.coulomb_rejections, expected.coulomb_rejections) << NameOf(set);
  });
}

}  // namespace
}  // namespace hcpf::tracker
