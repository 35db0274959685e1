#pragma once
// Interaction factors on the weights: the baseline the thesis compares charged
// resampling against.
//
// Khan, Balch & Dellaert, "MCMC-based particle filtering for tracking a
// variable number of interacting targets", IEEE TPAMI 27(11), 2005 (and the
// 2004 ECCV paper "An MCMC-based particle filter for tracking multiple
// interacting targets"): a pairwise Markov random field whose potential
//   psi(x_i, x_j) = exp(-g(x_i, x_j))
// penalises two targets occupying the same place. Here each target keeps its own
// filter, so the partner's state is its filter's current estimate mu_j and the
// factor multiplies particle weights:
//   log w(p) += -lambda * sum_{j != k} exp(-|p - mu_j|^2 / (2 r^2))
// (g = lambda * Gaussian proximity, the smooth penalty of the paper's Gibbs
// form; lambda dimensionless, r in pixels).

#include <array>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "hcpf/core/enum_names.h"
#include "hcpf/core/fields.h"
#include "hcpf/tracker/particle_set.h"

namespace hcpf::tracker {

enum class InteractionModel {
  kNone,  // "none"
  kMrf,   // "mrf": Khan-Balch-Dellaert pairwise MRF factor
};
}  // namespace hcpf::tracker

template <>
struct hcpf::EnumNames<hcpf::tracker::InteractionModel> {
  static constexpr std::array kNames = {
      std::pair{hcpf::tracker::InteractionModel::kNone, std::string_view("none")},
      std::pair{hcpf::tracker::InteractionModel::kMrf, std::string_view("mrf")}};
};

namespace hcpf::tracker {

struct InteractionOptions {
  InteractionModel model = InteractionModel::kNone;
  // Strength lambda of the penalty (log-weight units at zero distance).
  double lambda = 2.0;
  // Interaction radius r, px.
  double radius_px = 10.0;

  // The scenario keys of these options, with unit, range and doc (core/fields.h);
  // Validate() checks their ranges, then the rules between fields.
  static std::span<const Field<InteractionOptions>> Fields();
  void Validate(std::string_view prefix = "tracker.interaction") const;
};

// Contract: adds a log-factor depending on each particle's position and the
// other filters' summaries (the bank passes the same predicted summaries to
// every filter, so the result does not depend on filter order) to set.log_w.
// Never produces NaN; deterministic; O(N K). Stateless and const.
class Interaction {
 public:
  virtual ~Interaction() = default;
  virtual void Apply(ParticleSet& set, std::span<const FilterSummary> others) const = 0;
  virtual std::string_view name() const = 0;
};

class NoInteraction final : public Interaction {
 public:
  void Apply(ParticleSet&, std::span<const FilterSummary>) const override {}
  std::string_view name() const override { return "none"; }
};

class MrfInteraction final : public Interaction {
 public:
  MrfInteraction(double lambda, double radius_px);
  void Apply(ParticleSet& set, std::span<const FilterSummary> others) const override;
  std::string_view name() const override { return "mrf"; }

 private:
  double lambda_;
  double radius_px_;
};

std::unique_ptr<Interaction> MakeInteraction(const InteractionOptions& options);

}  // namespace hcpf::tracker
