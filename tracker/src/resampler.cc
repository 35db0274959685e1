#include "hcpf/tracker/resampler.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "charge_kernel.h"
#include "fast_math.h"
#include "hcpf/core/check.h"
#include "hcpf/core/instruction_set.h"

namespace hcpf::tracker {

std::span<const Field<ResamplerOptions>> ResamplerOptions::Fields() {
  using O = ResamplerOptions;
  static const std::vector<Field<O>> fields = {
      ChoiceField<&O::method>("method", "resampling algorithm"),
      NumberField("ess_threshold", &O::ess_threshold, Closed(0, 1), "",
                  "resample only when ESS < threshold · N (0 = every frame)"),
      ChoiceField<&O::potential>("potential", "charged: the repulsive potential"),
      NumberField("charge", &O::charge, Closed(0, 1e6), "", "charged: charge q"),
      NumberField("beta", &O::beta, Closed(0, 1e6), "", "charged: inverse temperature β"),
      // eps > 0 keeps (Sigma_j + eps^2 I) invertible for a collapsed neighbour
      // and the coulomb potential finite at the neighbour's mean.
      NumberField("softening_px", &O::softening_px, Closed(1e-3, 1e4), "px",
                  "charged: softening length ε"),
      IntegerField("max_tries", &O::max_tries, 0, 10'000, "",
                   "charged: redraws of a rejected candidate"),
      ChoiceField<&O::candidates>("candidates",
                                  "charged: how candidates are drawn (any method but charged)"),
  };
  return fields;
}

void ResamplerOptions::Validate(std::string_view prefix) const {
  CheckFields(*this, Fields(), prefix);
  if (candidates == ResamplingMethod::kCharged) {
    FailOption(prefix, "candidates",
               "one of multinomial | systematic | stratified | residual (not charged: the "
               "candidates a charged resampling draws from)",
               "\"charged\"");
  }
}

namespace {

void CheckInputs(const ParticleSet& set, std::span<int32_t> ancestors) {
  HCPF_CHECK(set.size() >= 1) << "resampling an empty particle set";
  HCPF_CHECK(set.w.size() == set.size());
  HCPF_CHECK(ancestors.size() == set.size())
      << ancestors.size() << " ancestor slots for " << set.size() << " particles";
}

// Index of the last particle with positive weight (0 if none): the merge never
// walks past it, so rounding in the cumulative sum (which may end a few ulp
// below 1) cannot select a trailing zero-weight particle.
size_t LastPositive(std::span<const double> w) {
  for (size_t j = w.size(); j-- > 0;) {
    if (w[j] > 0.0) return j;
  }
  return 0;
}

// Merges sorted points u (ascending, in [0, 1)) with the cumulative weights:
// point u selects the particle j with cum_{j-1} <= u < cum_j. Zero-weight
// particles own an empty interval and are skipped by the >= comparison.
template <typename PointFn>
void MergeSortedPoints(std::span<const double> w, size_t count, PointFn point, int32_t* out) {
  const size_t last = LastPositive(w);
  size_t j = 0;
  double cum = w[0];
  for (size_t i = 0; i < count; ++i) {
    const double u = point(i);
    while (u >= cum && j < last) {
      ++j;
      cum += w[j];
    }
    out[i] = static_cast<int32_t>(j);
  }
}

// Built for AVX-512, AVX2 and the baseline, the CPU's widest run
// (hcpf/core/instruction_set.h; isa_clones_test.cc runs each).
HCPF_DISPATCHED(void, NegLogInPlace, (double* v, size_t n), (v, n), {
  for (size_t i = 0; i < n; ++i) v[i] = -internal::FastLog(v[i]);
})

// `count` sorted uniforms in [0, 1) by normalised exponential spacings, merged
// with weights w into out[0..count). O(count + w.size()).
void SortedUniformMultinomial(std::span<const double> w, size_t count, Rng& rng, int32_t* out) {
  if (count == 0) return;
  std::vector<double> points(count);
  // E_k = -log U_k, U_k in (0, 1]; partial sums S_1..S_count and a final
  // spacing E_{count+1}: S_k / S_{count+1} are the order statistics of count
  // uniforms (Devroye 1986, Theorem V.2.2).
  // Uniforms first (scalar generator), then the logs in one vectorised pass,
  // then the running sum: the same numbers as interleaving, three times faster.
  for (size_t k = 0; k < count; ++k) points[k] = rng.UniformOpenZero();
  NegLogInPlace(points.data(), count);
  double total = 0.0;
  for (size_t k = 0; k < count; ++k) {
    total += points[k];
    points[k] = total;
  }
  total += -internal::FastLog(rng.UniformOpenZero());
  const double inv_total = 1.0 / total;
  MergeSortedPoints(
      w, count, [&](size_t i) { return points[i] * inv_total; }, out);
}

}  // namespace

ResampleResult MultinomialResampler::Resample(const ParticleSet& set, const ResampleContext&,
                                              Rng& rng, std::span<int32_t> ancestors) const {
  CheckInputs(set, ancestors);
  SortedUniformMultinomial(set.w, set.size(), rng, ancestors.data());
  return {};
}

ResampleResult SystematicResampler::Resample(const ParticleSet& set, const ResampleContext&,
                                             Rng& rng, std::span<int32_t> ancestors) const {
  CheckInputs(set, ancestors);
  const size_t n = set.size();
  const auto nd = static_cast<double>(n);
  const double u0 = rng.Uniform() / nd;  // the points are u0 + i / N, i = 0..N-1
  // Branch-free form of the merge (the data-dependent while loop of
  // MergeSortedPoints mispredicts about once per particle). F_j = number of
  // points below cum_j = clamp(ceil((cum_j - u0) N), 0, N) is monotone in j;
  // particle j owns points [F_{j-1}, F_j). Writing marker[F_{j-1}] = j for
  // every j in increasing order leaves at each start position the particle
  // that owns it (zero-count particles write there first and are overwritten
  // by the owner, who comes later), so a running maximum over the marker
  // array yields the ancestors. The last positive-weight particle ends at N
  // exactly, whatever the rounding of the cumulative sum.
  // The marker array is `ancestors` itself; a start at position N belongs to
  // a particle owning no point and is dropped.
  std::fill(ancestors.begin(), ancestors.end(), 0);
  const size_t last = LastPositive(set.w);
  double cum = 0.0;
  size_t f_prev = 0;
  for (size_t j = 0; j < last; ++j) {
    cum += set.w[j];
    if (f_prev < n) ancestors[f_prev] = static_cast<int32_t>(j);
    // ceil(max(x, 0)) by truncation (std::ceil is a libm call without SSE4.1).
    const double x = std::max((cum - u0) * nd, 0.0);
    const auto t = static_cast<int64_t>(x);
    const auto f = static_cast<size_t>(t + (static_cast<double>(t) < x ? 1 : 0));
    f_prev = std::clamp(f, f_prev, n);
  }
  if (f_prev < n) ancestors[f_prev] = static_cast<int32_t>(last);
  int32_t running = 0;
  for (size_t i = 0; i < n; ++i) {
    running = std::max(running, ancestors[i]);
    ancestors[i] = running;
  }
  return {};
}

ResampleResult StratifiedResampler::Resample(const ParticleSet& set, const ResampleContext&,
                                             Rng& rng, std::span<int32_t> ancestors) const {
  CheckInputs(set, ancestors);
  const size_t n = set.size();
  const double inv_n = 1.0 / static_cast<double>(n);
  MergeSortedPoints(
      set.w, n, [&](size_t i) { return (static_cast<double>(i) + rng.Uniform()) * inv_n; },
      ancestors.data());
  return {};
}

ResampleResult ResidualResampler::Resample(const ParticleSet& set, const ResampleContext&, Rng& rng,
                                           std::span<int32_t> ancestors) const {
  CheckInputs(set, ancestors);
  const size_t n = set.size();
  const auto nd = static_cast<double>(n);
  std::vector<double> residual(n);
  size_t filled = 0;
  double residual_total = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double expected = nd * set.w[i];
    auto copies = static_cast<size_t>(std::floor(expected));
    copies = std::min(copies, n - filled);  // rounding can push the sum of floors past N
    for (size_t c = 0; c < copies; ++c) ancestors[filled++] = static_cast<int32_t>(i);
    residual[i] = std::max(0.0, expected - static_cast<double>(copies));
    residual_total += residual[i];
  }
  const size_t remaining = n - filled;
  if (remaining > 0) {
    if (residual_total > 0.0) {
      for (double& r : residual) r /= residual_total;
      SortedUniformMultinomial(residual, remaining, rng, ancestors.data() + filled);
    } else {
      // Only reachable through rounding (floors summing to < N with zero
      // residual): fall back to multinomial on the weights themselves.
      SortedUniformMultinomial(set.w, remaining, rng, ancestors.data() + filled);
    }
  }
  return {};
}

EssGatedResampler::EssGatedResampler(std::unique_ptr<Resampler> inner, double threshold)
    : inner_(std::move(inner)), threshold_(threshold) {
  HCPF_CHECK(inner_ != nullptr);
  HCPF_CHECK(threshold_ >= 0.0 && threshold_ <= 1.0) << "threshold=" << threshold_;
}

ResampleResult EssGatedResampler::Resample(const ParticleSet& set, const ResampleContext& context,
                                           Rng& rng, std::span<int32_t> ancestors) const {
  CheckInputs(set, ancestors);
  const double ess = EffectiveSampleSize(set.w);
  if (ess >= threshold_ * static_cast<double>(set.size())) {
    std::iota(ancestors.begin(), ancestors.end(), 0);
    return {.resampled = false, .rejections = 0};
  }
  return inner_->Resample(set, context, rng, ancestors);
}

namespace {

using internal::Charge;
using internal::CoulombTerm;
using internal::GaussianTerm;

std::vector<Charge> MakeCharges(std::span<const FilterSummary> others, double eps) {
  std::vector<Charge> charges;
  charges.reserve(others.size());
  const double eps2 = eps * eps;
  for (const FilterSummary& o : others) {
    const double sxx = o.cov(0, 0) + eps2;
    const double sxy = 0.5 * (o.cov(0, 1) + o.cov(1, 0));
    const double syy = o.cov(1, 1) + eps2;
    const double det = sxx * syy - sxy * sxy;
    Charge ch{o.mean.x(), o.mean.y(), 1.0 / eps2, 0.0, 1.0 / eps2};
    // Sigma is positive semi-definite, so det >= eps^4 > 0; the guard only
    // catches a NaN covariance, which then counts as eps^2 I.
    if (det > 0.0 && std::isfinite(det)) {
      ch.a = syy / det;
      ch.b = -sxy / det;
      ch.c = sxx / det;
    }
    charges.push_back(ch);
  }
  return charges;
}

// Gaussian charges whose exponent is below -kCutoffExponent at every particle
// of this filter contribute less than e^-40 ~ 4e-18 to U and are dropped: a
// particle set far from a neighbour then pays nothing for it (a bank of K
// filters spread over the image costs ~O(N) per filter instead of O(N K)).
// Bound: d^T (Sigma + eps^2 I)^-1 d >= |d|^2 / lambda_max(Sigma + eps^2 I),
// with |d| the distance from the charge to the particles' bounding box.
constexpr double kCutoffExponent = 40.0;

void DropNegligibleCharges(const ParticleSet& set, std::span<const FilterSummary> others,
                           double eps2, std::vector<Charge>* charges) {
  double x0 = set.px[0], x1 = set.px[0], y0 = set.py[0], y1 = set.py[0];
  for (size_t i = 1; i < set.size(); ++i) {
    x0 = std::min(x0, set.px[i]);
    x1 = std::max(x1, set.px[i]);
    y0 = std::min(y0, set.py[i]);
    y1 = std::max(y1, set.py[i]);
  }
  std::vector<Charge> kept;
  for (size_t j = 0; j < charges->size(); ++j) {
    const Charge& ch = (*charges)[j];
    const double sxx = others[j].cov(0, 0) + eps2;
    const double syy = others[j].cov(1, 1) + eps2;
    const double sxy = 0.5 * (others[j].cov(0, 1) + others[j].cov(1, 0));
    const double half_diff = 0.5 * (sxx - syy);
    const double lambda_max = 0.5 * (sxx + syy) + std::sqrt(half_diff * half_diff + sxy * sxy);
    const double dx = std::max({x0 - ch.mx, 0.0, ch.mx - x1});
    const double dy = std::max({y0 - ch.my, 0.0, ch.my - y1});
    const double bound = 0.5 * (dx * dx + dy * dy) / lambda_max;
    if (!(bound > kCutoffExponent)) kept.push_back(ch);  // NaN keeps the charge
  }
  *charges = std::move(kept);
}

double PotentialAt(const std::vector<Charge>& charges, ChargePotential potential, double q,
                   double eps2, double x, double y) {
  double u = 0.0;
  if (potential == ChargePotential::kGaussian) {
    for (const Charge& ch : charges) u += GaussianTerm(ch, x, y);
  } else {
    for (const Charge& ch : charges) u += CoulombTerm(ch, x, y, eps2);
  }
  return q * u;
}

// Vectorised pass (charge_kernel.h): acceptance probability exp(-beta U) of
// every candidate, built for AVX-512, AVX2 and the baseline.
HCPF_DISPATCHED(void, AcceptanceProbabilities,
                (const Charge* charges, size_t num_charges, bool gaussian, double q, double beta,
                 double eps2, const double* x, const double* y, double* u, double* accept,
                 size_t n),
                (charges, num_charges, gaussian, q, beta, eps2, x, y, u, accept, n), {
                  internal::AcceptanceKernel(charges, num_charges, gaussian, q, beta, eps2, x, y, u,
                                             accept, n);
                })

}  // namespace

ChargedResampler::ChargedResampler(const ResamplerOptions& options) : options_(options) {
  options_.Validate();
  ResamplerOptions base = options_;
  base.method = options_.candidates;
  base.ess_threshold = 0.0;
  candidates_ = MakeResampler(base);
}

double ChargedResampler::Potential(double x_px, double y_px,
                                   std::span<const FilterSummary> others) const {
  const std::vector<Charge> charges = MakeCharges(others, options_.softening_px);
  const double eps2 = options_.softening_px * options_.softening_px;
  return PotentialAt(charges, options_.potential, options_.charge, eps2, x_px, y_px);
}

namespace {

// Per-thread work buffers of the charged resampler. Allocating ~10 arrays of
// N doubles per call made glibc return the memory to the OS on free and fault
// it back in on the next call (page faults were a tenth of the step); the
// buffers carry no information from one call to the next.
struct ChargedScratch {
  std::vector<double> x, y, pot, accept, cum, best_u;
  std::vector<int32_t> slot, draw, best;
};

ChargedScratch& Scratch() {
  thread_local ChargedScratch scratch;
  return scratch;
}

// One multinomial draw from the cumulative weights cum (cum.back() = total):
// the first j with cum_j > u * total, by a branch-free binary search (the
// comparison becomes a conditional move), never past the last positive weight.
inline int32_t DrawFromCumulative(const std::vector<double>& cum, size_t last, Rng& rng) {
  const double u = rng.Uniform() * cum.back();
  size_t lo = 0;
  size_t len = cum.size();
  while (len > 1) {
    const size_t half = len / 2;
    lo = cum[lo + half - 1] <= u ? lo + half : lo;
    len -= half;
  }
  return static_cast<int32_t>(std::min(lo, last));
}

}  // namespace

ResampleResult ChargedResampler::Resample(const ParticleSet& set, const ResampleContext& context,
                                          Rng& rng, std::span<int32_t> ancestors) const {
  CheckInputs(set, ancestors);
  ResampleResult result = candidates_->Resample(set, {}, rng, ancestors);
  if (context.others.empty() || options_.charge == 0.0 || options_.beta == 0.0) {
    return result;  // every acceptance probability is exactly 1
  }
  const size_t n = set.size();
  const double eps2 = options_.softening_px * options_.softening_px;
  const double q = options_.charge;
  const double beta = options_.beta;
  const bool gaussian = options_.potential == ChargePotential::kGaussian;
  std::vector<Charge> charges = MakeCharges(context.others, options_.softening_px);
  if (gaussian) DropNegligibleCharges(set, context.others, eps2, &charges);
  if (charges.empty()) {
    // Every neighbour is out of range: exp(-beta U) = 1 to double precision;
    // the uniforms are still drawn so the stream does not depend on geometry.
    for (size_t i = 0; i < n; ++i) (void)rng.Uniform();
    return result;
  }

  ChargedScratch& s = Scratch();
  s.x.resize(n);
  s.y.resize(n);
  s.pot.resize(n);
  s.accept.resize(n);
  s.slot.resize(n);
  s.draw.resize(n);
  s.best.resize(n);
  s.best_u.resize(n);
  // Round 0: the candidates. Potentials in one vectorised pass, then one
  // uniform per slot in slot order; rejected slots are compacted into
  // `slot` without branches.
  for (size_t i = 0; i < n; ++i) {
    s.x[i] = set.px[static_cast<size_t>(ancestors[i])];
    s.y[i] = set.py[static_cast<size_t>(ancestors[i])];
  }
  AcceptanceProbabilities(charges.data(), charges.size(), gaussian, q, beta, eps2, s.x.data(),
                          s.y.data(), s.pot.data(), s.accept.data(), n);
  size_t pending = 0;
  for (size_t i = 0; i < n; ++i) {
    const bool rejected = !(rng.Uniform() < s.accept[i]);
    s.slot[pending] = static_cast<int32_t>(i);
    s.best[pending] = ancestors[i];
    s.best_u[pending] = s.pot[i];
    pending += rejected ? 1 : 0;
  }
  int64_t rejections = static_cast<int64_t>(pending);
  int64_t draws = static_cast<int64_t>(n);
  if (pending > 0 && options_.max_tries > 0) {
    // Replacement draws are made in rounds: in round t every still-rejected
    // slot (in slot order) draws its t-th replacement, multinomially from
    // this filter's weights; the potentials of a round are one vectorised
    // pass, then one uniform per slot decides. Each slot still sees i.i.d.
    // replacements tested one at a time, exactly as DESIGN.md specifies.
    s.cum.resize(n);
    double total = 0.0;
    for (size_t i = 0; i < n; ++i) {
      total += set.w[i];
      s.cum[i] = total;
    }
    const size_t last = LastPositive(set.w);
    for (int t = 0; t < options_.max_tries && pending > 0; ++t) {
      draws += static_cast<int64_t>(pending);
      for (size_t k = 0; k < pending; ++k) {
        const int32_t j = DrawFromCumulative(s.cum, last, rng);
        s.draw[k] = j;
        s.x[k] = set.px[static_cast<size_t>(j)];
        s.y[k] = set.py[static_cast<size_t>(j)];
      }
      AcceptanceProbabilities(charges.data(), charges.size(), gaussian, q, beta, eps2, s.x.data(),
                              s.y.data(), s.pot.data(), s.accept.data(), pending);
      size_t still = 0;
      for (size_t k = 0; k < pending; ++k) {
        if (rng.Uniform() < s.accept[k]) {
          ancestors[static_cast<size_t>(s.slot[k])] = s.draw[k];
          continue;
        }
        // Rejected again: keep the lowest-U draw seen so far (the earlier on ties).
        const bool better = s.pot[k] < s.best_u[k];
        s.slot[still] = s.slot[k];
        s.best[still] = better ? s.draw[k] : s.best[k];
        s.best_u[still] = better ? s.pot[k] : s.best_u[k];
        ++still;
      }
      rejections += static_cast<int64_t>(still);
      pending = still;
    }
  }
  for (size_t k = 0; k < pending; ++k) ancestors[static_cast<size_t>(s.slot[k])] = s.best[k];
  result.rejections = rejections;
  result.potential_terms = draws * static_cast<int64_t>(charges.size());
  return result;
}

std::unique_ptr<Resampler> MakeResampler(const ResamplerOptions& options) {
  options.Validate();
  std::unique_ptr<Resampler> resampler;
  switch (options.method) {
    case ResamplingMethod::kMultinomial:
      resampler = std::make_unique<MultinomialResampler>();
      break;
    case ResamplingMethod::kSystematic:
      resampler = std::make_unique<SystematicResampler>();
      break;
    case ResamplingMethod::kStratified:
      resampler = std::make_unique<StratifiedResampler>();
      break;
    case ResamplingMethod::kResidual:
      resampler = std::make_unique<ResidualResampler>();
      break;
    case ResamplingMethod::kCharged:
      resampler = std::make_unique<ChargedResampler>(options);
      break;
  }
  HCPF_CHECK(resampler != nullptr) << "unknown resampling method";
  if (options.ess_threshold > 0.0) {
    return std::make_unique<EssGatedResampler>(std::move(resampler), options.ess_threshold);
  }
  return resampler;
}

}  // namespace hcpf::tracker
