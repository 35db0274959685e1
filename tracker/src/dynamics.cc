#include "hcpf/tracker/dynamics.h"

#include <algorithm>
#include <array>
#include <cmath>

#include "fast_math.h"
#include "hcpf/core/check.h"
#include "hcpf/core/normal.h"

namespace hcpf::tracker {
namespace {

// Noise is drawn in chunks of kNoiseChunk particles into a stack buffer, one
// contiguous block per state component, so the update loops vectorise without
// heap traffic. The draw order (component-major within each chunk) is part of
// the determinism contract: changing kNoiseChunk changes the numbers.
constexpr size_t kNoiseChunk = 256;

}  // namespace

std::span<const Field<DynamicsOptions>> DynamicsOptions::Fields() {
  using O = DynamicsOptions;
  static const std::vector<Field<O>> fields = {
      ChoiceField<&O::model>("model", "motion model of a particle"),
      NumberField("sigma_pos_px", &O::sigma_pos_px, Closed(0, 1000), "px/frame",
                  "std. dev. of the position noise"),
      NumberField("sigma_vel_px", &O::sigma_vel_px, Closed(0, 1000), "px/frame²",
                  "std. dev. of the velocity noise"),
      NumberField("sigma_log_scale", &O::sigma_log_scale, Closed(0, 1), "/frame",
                  "std. dev. of the log-scale noise (constant_velocity_scale)"),
  };
  return fields;
}

void DynamicsOptions::Validate(std::string_view prefix) const {
  CheckFields(*this, Fields(), prefix);
}

RandomWalkDynamics::RandomWalkDynamics(double sigma_pos_px) : sigma_pos_px_(sigma_pos_px) {}

void RandomWalkDynamics::Predict(ParticleSet& set, Rng& rng) const {
  std::array<double, 2 * kNoiseChunk> noise;
  const size_t n = set.size();
  const double sp = sigma_pos_px_;
  for (size_t begin = 0; begin < n; begin += kNoiseChunk) {
    const size_t m = std::min(kNoiseChunk, n - begin);
    FillStandardNormal(rng, std::span<double>(noise.data(), 2 * m));
    double* px = set.px.data() + begin;
    double* py = set.py.data() + begin;
    const double* nx = noise.data();
    const double* ny = noise.data() + m;
    for (size_t i = 0; i < m; ++i) {
      px[i] += sp * nx[i];
      py[i] += sp * ny[i];
    }
  }
}

ConstantVelocityDynamics::ConstantVelocityDynamics(double sigma_pos_px, double sigma_vel_px)
    : sigma_pos_px_(sigma_pos_px), sigma_vel_px_(sigma_vel_px) {}

namespace {

// Shared by both constant-velocity models: p += v + sp n_p; v += sv n_v.
void ConstantVelocityChunk(double* px, double* py, double* vx, double* vy, const double* noise,
                           size_t m, double sp, double sv) {
  const double* npx = noise;
  const double* npy = noise + m;
  const double* nvx = noise + 2 * m;
  const double* nvy = noise + 3 * m;
  for (size_t i = 0; i < m; ++i) {
    px[i] += vx[i] + sp * npx[i];
    py[i] += vy[i] + sp * npy[i];
    vx[i] += sv * nvx[i];
    vy[i] += sv * nvy[i];
  }
}

}  // namespace

void ConstantVelocityDynamics::Predict(ParticleSet& set, Rng& rng) const {
  std::array<double, 4 * kNoiseChunk> noise;
  const size_t n = set.size();
  for (size_t begin = 0; begin < n; begin += kNoiseChunk) {
    const size_t m = std::min(kNoiseChunk, n - begin);
    FillStandardNormal(rng, std::span<double>(noise.data(), 4 * m));
    ConstantVelocityChunk(set.px.data() + begin, set.py.data() + begin, set.vx.data() + begin,
                          set.vy.data() + begin, noise.data(), m, sigma_pos_px_, sigma_vel_px_);
  }
}

ConstantVelocityScaleDynamics::ConstantVelocityScaleDynamics(double sigma_pos_px,
                                                             double sigma_vel_px,
                                                             double sigma_log_scale)
    : sigma_pos_px_(sigma_pos_px), sigma_vel_px_(sigma_vel_px), sigma_log_scale_(sigma_log_scale) {}

void ConstantVelocityScaleDynamics::Predict(ParticleSet& set, Rng& rng) const {
  std::array<double, 5 * kNoiseChunk> noise;
  const size_t n = set.size();
  for (size_t begin = 0; begin < n; begin += kNoiseChunk) {
    const size_t m = std::min(kNoiseChunk, n - begin);
    FillStandardNormal(rng, std::span<double>(noise.data(), 5 * m));
    ConstantVelocityChunk(set.px.data() + begin, set.py.data() + begin, set.vx.data() + begin,
                          set.vy.data() + begin, noise.data(), m, sigma_pos_px_, sigma_vel_px_);
    double* s = set.s.data() + begin;
    const double* ns = noise.data() + 4 * m;
    for (size_t i = 0; i < m; ++i) s[i] *= internal::FastExp(sigma_log_scale_ * ns[i]);
  }
}

std::unique_ptr<Dynamics> MakeDynamics(const DynamicsOptions& options) {
  options.Validate();
  switch (options.model) {
    case DynamicsModel::kRandomWalk:
      return std::make_unique<RandomWalkDynamics>(options.sigma_pos_px);
    case DynamicsModel::kConstantVelocity:
      return std::make_unique<ConstantVelocityDynamics>(options.sigma_pos_px, options.sigma_vel_px);
    case DynamicsModel::kConstantVelocityScale:
      return std::make_unique<ConstantVelocityScaleDynamics>(
          options.sigma_pos_px, options.sigma_vel_px, options.sigma_log_scale);
  }
  HCPF_CHECK(false) << "unknown dynamics model";
  return nullptr;
}

void ApplyCameraMotion(const SimilarityMotion& motion, ParticleSet& set) {
  const double scale = std::exp(motion.log_scale);
  const double a = scale * std::cos(motion.rotation_rad);
  const double b = scale * std::sin(motion.rotation_rad);
  const size_t n = set.size();
  for (size_t i = 0; i < n; ++i) {
    const double x = set.px[i];
    const double y = set.py[i];
    set.px[i] = a * x - b * y + motion.tx_px;
    set.py[i] = b * x + a * y + motion.ty_px;
    const double u = set.vx[i];
    const double v = set.vy[i];
    set.vx[i] = a * u - b * v;
    set.vy[i] = b * u + a * v;
    set.s[i] *= scale;
  }
}

}  // namespace hcpf::tracker
