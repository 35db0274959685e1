#pragma once
// Dynamics (the predict step) of a target filter, and the camera-motion
// pre-step of the hierarchical filter.

#include <array>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hcpf/core/enum_names.h"
#include "hcpf/core/fields.h"
#include "hcpf/core/rng.h"
#include "hcpf/core/similarity_motion.h"
#include "hcpf/tracker/particle_set.h"

namespace hcpf::tracker {

enum class DynamicsModel {
  kRandomWalk,             // "random_walk": p += sigma_pos * n; velocity not used or changed
  kConstantVelocity,       // "constant_velocity": p += v + sigma_pos * n; v += sigma_vel * n
  kConstantVelocityScale,  // "constant_velocity_scale": as above and s *= exp(sigma_log_scale * n)
};
}  // namespace hcpf::tracker

template <>
struct hcpf::EnumNames<hcpf::tracker::DynamicsModel> {
  static constexpr std::array kNames = {
      std::pair{hcpf::tracker::DynamicsModel::kRandomWalk, std::string_view("random_walk")},
      std::pair{hcpf::tracker::DynamicsModel::kConstantVelocity,
                std::string_view("constant_velocity")},
      std::pair{hcpf::tracker::DynamicsModel::kConstantVelocityScale,
                std::string_view("constant_velocity_scale")}};
};

namespace hcpf::tracker {

struct DynamicsOptions {
  DynamicsModel model = DynamicsModel::kConstantVelocity;
  // Standard deviation of the position noise added each frame, pixels/frame.
  double sigma_pos_px = 1.5;
  // Standard deviation of the velocity noise each frame, pixels/frame per frame.
  double sigma_vel_px = 0.3;
  // Standard deviation of the log-scale random walk each frame (dimensionless;
  // 0.01 = about 1% size change per frame). Used by constant_velocity_scale only.
  double sigma_log_scale = 0.01;

  // Throws InputError naming "<prefix>.<field>".
  // The scenario keys of these options, with unit, range and doc (core/fields.h);
  // Validate() checks their ranges, then the rules between fields.
  static std::span<const Field<DynamicsOptions>> Fields();
  void Validate(std::string_view prefix = "tracker.dynamics") const;
};

// The predict step of one filter for one frame.
// Contract: moves every particle by one frame of the model, drawing all noise
// from `rng` (the filter's own stream) in particle order; leaves weights
// untouched; deterministic given the Rng state; O(N). Implementations are
// stateless and const, so one instance may be shared by all filters and threads.
class Dynamics {
 public:
  virtual ~Dynamics() = default;
  virtual void Predict(ParticleSet& set, Rng& rng) const = 0;
  virtual std::string_view name() const = 0;
};

class RandomWalkDynamics final : public Dynamics {
 public:
  explicit RandomWalkDynamics(double sigma_pos_px);
  void Predict(ParticleSet& set, Rng& rng) const override;
  std::string_view name() const override { return "random_walk"; }

 private:
  double sigma_pos_px_;
};

class ConstantVelocityDynamics final : public Dynamics {
 public:
  ConstantVelocityDynamics(double sigma_pos_px, double sigma_vel_px);
  void Predict(ParticleSet& set, Rng& rng) const override;
  std::string_view name() const override { return "constant_velocity"; }

 private:
  double sigma_pos_px_;
  double sigma_vel_px_;
};

class ConstantVelocityScaleDynamics final : public Dynamics {
 public:
  ConstantVelocityScaleDynamics(double sigma_pos_px, double sigma_vel_px, double sigma_log_scale);
  void Predict(ParticleSet& set, Rng& rng) const override;
  std::string_view name() const override { return "constant_velocity_scale"; }

 private:
  double sigma_pos_px_;
  double sigma_vel_px_;
  double sigma_log_scale_;
};

// Validates `options` and builds the selected model.
std::unique_ptr<Dynamics> MakeDynamics(const DynamicsOptions& options);

// Hierarchical-filter pre-step: maps every particle through the camera motion:
// position p -> sRp + t, velocity v -> sRv (a displacement, no translation),
// size scale s -> s * exp(log_scale). Deterministic, O(N).
void ApplyCameraMotion(const SimilarityMotion& motion, ParticleSet& set);

}  // namespace hcpf::tracker
