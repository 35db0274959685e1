#pragma once
// Likelihoods (the update step) of a target filter. All work in log space:
// an implementation ADDS log p(observation | particle) to set.log_w.

#include <array>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "hcpf/core/enum_names.h"
#include "hcpf/core/fields.h"
#include "hcpf/core/types.h"
#include "hcpf/tracker/particle_set.h"

namespace hcpf::tracker {

enum class LikelihoodModel {
  kDetectionsMixture,  // "detections_mixture": every detection, no association
  kAssociated,         // "associated": only the detection assigned to this filter
  kMap,                // "map": bilinear sample of Observation::likelihood
};
}  // namespace hcpf::tracker

template <>
struct hcpf::EnumNames<hcpf::tracker::LikelihoodModel> {
  static constexpr std::array kNames = {
      std::pair{hcpf::tracker::LikelihoodModel::kDetectionsMixture,
                std::string_view("detections_mixture")},
      std::pair{hcpf::tracker::LikelihoodModel::kAssociated, std::string_view("associated")},
      std::pair{hcpf::tracker::LikelihoodModel::kMap, std::string_view("map")}};
};

namespace hcpf::tracker {

struct LikelihoodOptions {
  LikelihoodModel model = LikelihoodModel::kDetectionsMixture;
  // Standard deviation of a detection's centre about the particle's centre, px.
  double sigma_px = 3.0;
  // detections_mixture: density of the clutter floor, per px^2 (a uniform
  // component added to the mixture; keeps every particle's likelihood > 0).
  // 1e-5 / px^2 is one clutter detection per 100,000 px^2 (a third of 640x480).
  double clutter_density = 1e-5;
  // detections_mixture: weight each detection's component by its score (true)
  // or weight all detections equally (false).
  bool use_scores = true;
  // Standard deviation of log(particle box width / detection box width); 0
  // disables the size term. Needed (> 0) with constant_velocity_scale dynamics
  // or the scale is unobserved.
  double sigma_log_size = 0.0;
  // map: value added to every map sample before the log, so a zero cell does
  // not kill a particle outright (map units).
  double map_floor = 1e-9;

  // The scenario keys of these options, with unit, range and doc (core/fields.h);
  // Validate() checks their ranges, then the rules between fields.
  static std::span<const Field<LikelihoodOptions>> Fields();
  void Validate(std::string_view prefix = "tracker.likelihood") const;
};

// What one filter sees of one frame.
struct LikelihoodInput {
  const Observation* observation = nullptr;
  // The detection the associator gave this filter, or nullptr.
  const Detection* assigned = nullptr;
  // The associator's evidence for this filter (Associator::Evidence): its
  // assigned detection, or without association a detection inside its gate.
  bool detection_evidence = false;
  // The filter's birth box size: a particle's box is (base_w_px*s) x (base_h_px*s).
  double base_w_px = 1.0;
  double base_h_px = 1.0;
};

// Contract: HasEvidence says whether this frame holds evidence for the
// filter under this model; the tracker counts a frame without it as missed
// and, with coast_without_support, coasts (does not call AddLogLikelihood).
// AddLogLikelihood adds log-likelihood terms to set.log_w (never NaN; -inf
// allowed only where the model gives exactly zero density) and returns true,
// or leaves the weights untouched and returns false when it has nothing to
// add (flat likelihood). Deterministic, no randomness, O(N * D) for D
// detections. Stateless and const.
class Likelihood {
 public:
  virtual ~Likelihood() = default;
  virtual bool HasEvidence(const LikelihoodInput& input) const = 0;
  virtual bool AddLogLikelihood(ParticleSet& set, const LikelihoodInput& input) const = 0;
  virtual std::string_view name() const = 0;
};

// log [ c + sum_d a_d N(p; centre_d, sigma^2 I) * LN(size) ] where c is the
// clutter density and a_d the detection's score (or 1). Hijack-prone by
// design: a strong neighbour's detection attracts this filter's particles.
// No detections -> flat (returns false).
class DetectionsMixtureLikelihood final : public Likelihood {
 public:
  explicit DetectionsMixtureLikelihood(const LikelihoodOptions& options);
  // The associator's evidence (every detection enters the mixture, but only
  // the associator says which ones are this filter's).
  bool HasEvidence(const LikelihoodInput& input) const override { return input.detection_evidence; }
  bool AddLogLikelihood(ParticleSet& set, const LikelihoodInput& input) const override;
  std::string_view name() const override { return "detections_mixture"; }

 private:
  LikelihoodOptions options_;
};

// log N(p; centre_assigned, sigma^2 I) (+ size term) for the assigned
// detection only; no assigned detection -> flat (returns false).
class AssociatedLikelihood final : public Likelihood {
 public:
  explicit AssociatedLikelihood(const LikelihoodOptions& options);
  // An assigned detection.
  bool HasEvidence(const LikelihoodInput& input) const override {
    return input.assigned != nullptr;
  }
  bool AddLogLikelihood(ParticleSet& set, const LikelihoodInput& input) const override;
  std::string_view name() const override { return "associated"; }

 private:
  LikelihoodOptions options_;
};

// log(map.Sample(px, py) + map_floor); no map in the observation -> flat.
class MapLikelihood final : public Likelihood {
 public:
  explicit MapLikelihood(const LikelihoodOptions& options);
  // A map in the observation.
  bool HasEvidence(const LikelihoodInput& input) const override {
    return input.observation->likelihood.has_value();
  }
  bool AddLogLikelihood(ParticleSet& set, const LikelihoodInput& input) const override;
  std::string_view name() const override { return "map"; }

 private:
  LikelihoodOptions options_;
};

std::unique_ptr<Likelihood> MakeLikelihood(const LikelihoodOptions& options);

}  // namespace hcpf::tracker
