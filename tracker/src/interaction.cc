#include "hcpf/tracker/interaction.h"

#include "fast_math.h"
#include "hcpf/core/check.h"

namespace hcpf::tracker {

std::span<const Field<InteractionOptions>> InteractionOptions::Fields() {
  using O = InteractionOptions;
  static const std::vector<Field<O>> fields = {
      ChoiceField<&O::model>("model", "none, or mrf (Khan–Balch–Dellaert pairwise factor)"),
      NumberField("lambda", &O::lambda, Closed(0, 1e6), "", "mrf: strength λ"),
      NumberField("radius_px", &O::radius_px, Closed(1e-3, 1e4), "px", "mrf: radius"),
  };
  return fields;
}

void InteractionOptions::Validate(std::string_view prefix) const {
  CheckFields(*this, Fields(), prefix);
}

MrfInteraction::MrfInteraction(double lambda, double radius_px)
    : lambda_(lambda), radius_px_(radius_px) {
  HCPF_CHECK(lambda_ >= 0.0 && radius_px_ > 0.0);
}

void MrfInteraction::Apply(ParticleSet& set, std::span<const FilterSummary> others) const {
  const double inv_2r2 = 1.0 / (2.0 * radius_px_ * radius_px_);
  const size_t n = set.size();
  for (const FilterSummary& o : others) {
    const double mx = o.mean.x();
    const double my = o.mean.y();
    for (size_t i = 0; i < n; ++i) {
      const double dx = set.px[i] - mx;
      const double dy = set.py[i] - my;
      set.log_w[i] -= lambda_ * internal::FastExp(-(dx * dx + dy * dy) * inv_2r2);
    }
  }
}

std::unique_ptr<Interaction> MakeInteraction(const InteractionOptions& options) {
  options.Validate();
  switch (options.model) {
    case InteractionModel::kNone:
      return std::make_unique<NoInteraction>();
    case InteractionModel::kMrf:
      return std::make_unique<MrfInteraction>(options.lambda, options.radius_px);
  }
  HCPF_CHECK(false) << "unknown interaction model";
  return nullptr;
}

}  // namespace hcpf::tracker
