#pragma once
// Resamplers: turn a weighted particle set into N ancestor indices.
//
// Family: multinomial, systematic, stratified, residual (Douc, Cappé & Moulines,
// "Comparison of resampling schemes for particle filtering", ISPA 2005), an
// ESS-gated wrapper around any of them, and charged resampling (DESIGN.md,
// "Charged resampling"; docs/tracker.md gives the algorithm as implemented).

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "hcpf/core/enum_names.h"
#include "hcpf/core/fields.h"
#include "hcpf/core/rng.h"
#include "hcpf/tracker/particle_set.h"

namespace hcpf::tracker {

// What a resampler may know about the rest of the bank: the pre-resampling
// summaries of every OTHER filter (the bank leaves the resampled filter out).
// All filters of a frame are resampled against the same summaries, so the
// result does not depend on filter order.
struct ResampleContext {
  std::span<const FilterSummary> others;
};

struct ResampleResult {
  // False when the resampler decided not to resample (ESS gate): the ancestors
  // are then the identity and the caller keeps the weights.
  bool resampled = true;
  // Charged resampling: number of rejected draws this call (candidates and
  // replacement draws alike). 0 for every other resampler.
  int64_t rejections = 0;
  // Charged resampling: the potential terms weighed this call, every draw
  // (candidates and replacements) times the other filters' charges within
  // reach (docs/tracker.md). 0 for every other resampler. Its cost grows with
  // the filters within reach of one another, not with the filters alone.
  int64_t potential_terms = 0;
};

// Contract:
// - Precondition: set.w holds normalised weights (NormaliseLogWeights ran):
//   finite, >= 0, summing to 1 within rounding; set.size() >= 1;
//   ancestors.size() == set.size().
// - Fills `ancestors` with N indices in [0, N); each particle i is selected
//   E[count_i] = N w_i times (unbiased), particles with w_i = 0 never.
// - All randomness from `rng`; identical Rng state and inputs give identical
//   output. Stateless and const: one instance may serve every filter and thread.
// - O(N) (charged: O(N K) for K filters).
class Resampler {
 public:
  virtual ~Resampler() = default;
  virtual ResampleResult Resample(const ParticleSet& set, const ResampleContext& context, Rng& rng,
                                  std::span<int32_t> ancestors) const = 0;
  virtual std::string_view name() const = 0;
};

enum class ResamplingMethod {
  kMultinomial,  // "multinomial"
  kSystematic,   // "systematic"
  kStratified,   // "stratified"
  kResidual,     // "residual"
  kCharged,      // "charged"
};
}  // namespace hcpf::tracker

template <>
struct hcpf::EnumNames<hcpf::tracker::ResamplingMethod> {
  static constexpr std::array kNames = {
      std::pair{hcpf::tracker::ResamplingMethod::kMultinomial, std::string_view("multinomial")},
      std::pair{hcpf::tracker::ResamplingMethod::kSystematic, std::string_view("systematic")},
      std::pair{hcpf::tracker::ResamplingMethod::kStratified, std::string_view("stratified")},
      std::pair{hcpf::tracker::ResamplingMethod::kResidual, std::string_view("residual")},
      std::pair{hcpf::tracker::ResamplingMethod::kCharged, std::string_view("charged")}};
};

namespace hcpf::tracker {

enum class ChargePotential {
  kGaussian,  // "gaussian": q exp(-1/2 d^T (Sigma_j + eps^2 I)^-1 d)
  kCoulomb,   // "coulomb":  q / (|d|^2 + eps^2)
};
}  // namespace hcpf::tracker

template <>
struct hcpf::EnumNames<hcpf::tracker::ChargePotential> {
  static constexpr std::array kNames = {
      std::pair{hcpf::tracker::ChargePotential::kGaussian, std::string_view("gaussian")},
      std::pair{hcpf::tracker::ChargePotential::kCoulomb, std::string_view("coulomb")}};
};

namespace hcpf::tracker {

struct ResamplerOptions {
  ResamplingMethod method = ResamplingMethod::kSystematic;
  // ESS gate: resample only when ESS < ess_threshold * N. 0 = always resample
  // (no gate); 1 = resample unless the weights are exactly uniform-equivalent.
  double ess_threshold = 0.0;

  // Charged resampling (method = charged).
  ChargePotential potential = ChargePotential::kGaussian;
  // Charge q of every filter: gaussian -> dimensionless, coulomb -> px^2.
  double charge = 1.0;
  // Inverse temperature beta of the acceptance exp(-beta U), dimensionless.
  double beta = 1.0;
  // Softening eps, px: added as eps^2 I to each covariance (gaussian) or eps^2
  // to the squared distance (coulomb).
  double softening_px = 6.0;
  // Replacement draws after a rejected candidate; 0 keeps every candidate.
  int max_tries = 20;
  // How the candidates are drawn (DESIGN.md: systematic). Must not be charged.
  ResamplingMethod candidates = ResamplingMethod::kSystematic;

  // The scenario keys of these options, with unit, range and doc (core/fields.h);
  // Validate() checks their ranges, then the rules between fields.
  static std::span<const Field<ResamplerOptions>> Fields();
  void Validate(std::string_view prefix = "tracker.resampling") const;
};

class MultinomialResampler final : public Resampler {
 public:
  // O(N): N sorted uniforms from normalised cumulative exponential spacings
  // (Devroye 1986, ch. V.3), merged with the cumulative weights. The ancestor
  // list comes out sorted.
  ResampleResult Resample(const ParticleSet& set, const ResampleContext& context, Rng& rng,
                          std::span<int32_t> ancestors) const override;
  std::string_view name() const override { return "multinomial"; }
};

class SystematicResampler final : public Resampler {
 public:
  // One uniform U; points (i + U) / N.
  ResampleResult Resample(const ParticleSet& set, const ResampleContext& context, Rng& rng,
                          std::span<int32_t> ancestors) const override;
  std::string_view name() const override { return "systematic"; }
};

class StratifiedResampler final : public Resampler {
 public:
  // One uniform per stratum; points (i + U_i) / N.
  ResampleResult Resample(const ParticleSet& set, const ResampleContext& context, Rng& rng,
                          std::span<int32_t> ancestors) const override;
  std::string_view name() const override { return "stratified"; }
};

class ResidualResampler final : public Resampler {
 public:
  // floor(N w_i) copies of each particle, the remaining R draws multinomial
  // (as MultinomialResampler) on the residual weights N w_i - floor(N w_i).
  ResampleResult Resample(const ParticleSet& set, const ResampleContext& context, Rng& rng,
                          std::span<int32_t> ancestors) const override;
  std::string_view name() const override { return "residual"; }
};

// Resamples with `inner` only when ESS < threshold * N; otherwise returns the
// identity ancestors with resampled = false and draws nothing from rng.
class EssGatedResampler final : public Resampler {
 public:
  EssGatedResampler(std::unique_ptr<Resampler> inner, double threshold);
  ResampleResult Resample(const ParticleSet& set, const ResampleContext& context, Rng& rng,
                          std::span<int32_t> ancestors) const override;
  std::string_view name() const override { return "ess_gated"; }

 private:
  std::unique_ptr<Resampler> inner_;
  double threshold_;
};

// Charged resampling, exactly as DESIGN.md specifies:
//   1. draw N candidates with the candidate resampler (systematic by default);
//   2. U(p) = sum over the other filters j of the potential of j at p;
//      accept candidate p with probability exp(-beta U(p)) (one uniform);
//   3. a rejected candidate is replaced by a fresh multinomial draw from this
//      filter's weights, up to max_tries replacements; if all are rejected the
//      draw with the lowest U is kept.
// Implementation: candidate potentials in one vectorised pass; replacements
// drawn in rounds (round t: every still-rejected slot, in slot order, draws
// its t-th replacement by a branch-free binary search of the cumulative
// weights), each round's potentials again one vectorised pass. Each slot sees
// i.i.d. replacements tested one at a time, as specified.
// With no other filter (or q = 0 or beta = 0) every acceptance probability is
// 1: no uniform is drawn and the output equals the candidate resampler's.
// Gaussian charges that are negligible for every particle (exponent < -40)
// are skipped. Cost O(N K) per filter for K others, plus O(R log N) for R
// replacement draws.
class ChargedResampler final : public Resampler {
 public:
  explicit ChargedResampler(const ResamplerOptions& options);
  ResampleResult Resample(const ParticleSet& set, const ResampleContext& context, Rng& rng,
                          std::span<int32_t> ancestors) const override;
  std::string_view name() const override { return "charged"; }

  // The potential U(p) at (x, y) from `others` (exposed for tests and overlays).
  double Potential(double x_px, double y_px, std::span<const FilterSummary> others) const;

 private:
  ResamplerOptions options_;
  std::unique_ptr<Resampler> candidates_;
};

// Builds the selected resampler, wrapped in EssGatedResampler when
// ess_threshold > 0. Validates the options.
std::unique_ptr<Resampler> MakeResampler(const ResamplerOptions& options);

}  // namespace hcpf::tracker
