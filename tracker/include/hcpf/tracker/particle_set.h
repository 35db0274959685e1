#pragma once
// Particle storage for one target filter and the small numerics every filter
// component shares: log-weight normalisation, effective sample size, weighted
// position moments.
//
// State per particle: x = (px, py, vx, vy, s)
//   px, py  box centre in image pixels (pixel (0,0) covers [0,1)x[0,1))
//   vx, vy  velocity in pixels per frame
//   s       size scale, dimensionless: the box is (base_w * s) x (base_h * s),
//           where base_w, base_h are the filter's birth box size (kept by the
//           filter, not per particle). Decision: one scale keeps the state
//           5-dimensional as DESIGN.md specifies and preserves the aspect ratio,
//           which a rigid vehicle seen from above does not change.
// Stored structure-of-arrays so predict/update loops vectorise.

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "hcpf/core/types.h"

namespace hcpf::tracker {

struct ParticleSet {
  std::vector<double> px, py, vx, vy, s;
  // Unnormalised or normalised natural-log weights (-inf allowed, never NaN
  // after NormaliseLogWeights).
  std::vector<double> log_w;
  // Linear weights summing to 1; valid only after NormaliseLogWeights (the
  // resamplers read these).
  std::vector<double> w;

  size_t size() const { return px.size(); }
  // Resizes every array to n (new entries zero state, unit scale, weight 1/n).
  void Resize(size_t n);
  // Sets every weight to 1/N (log_w = -log N, w = 1/N).
  void SetUniformWeights();
  friend bool operator==(const ParticleSet&, const ParticleSet&) = default;
};

// Result of normalising a set's log-weights.
struct NormaliseResult {
  // log of the total weight before normalisation (log-sum-exp); -inf when the
  // set was degenerate.
  double log_total = 0.0;
  // True when every weight was -inf or NaN: the weights were reset to uniform
  // (the documented recovery) and the frame should be counted as degenerate.
  bool recovered_degenerate = false;
  // Number of individual NaN log-weights that were replaced by -inf.
  int64_t nan_weights = 0;
};

// Normalises log_w in place with the log-sum-exp trick (subtract the maximum
// before exponentiating) and fills w. NaN log-weights become -inf. If no
// weight is finite (all -inf/NaN, or +inf present), resets to uniform weights.
// Postcondition: every w[i] is finite, >= 0 and they sum to 1 (to rounding);
// log_w[i] = log(w[i]). O(N).
NormaliseResult NormaliseLogWeights(ParticleSet& set);

// Kish's effective sample size 1 / sum(w_i^2) of the normalised weights, in [1, N].
double EffectiveSampleSize(std::span<const double> w);

// Weighted summary of a filter's position distribution, as other filters and
// the associator see it.
struct FilterSummary {
  TrackId id{};
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();  // px
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();   // px^2
  double mean_scale = 1.0;
  double ess = 0.0;
};

// Weighted mean and covariance of (px, py) and mean scale using the normalised
// weights w. The covariance is the biased (weights-sum-to-one) estimator.
FilterSummary Summarise(const ParticleSet& set, TrackId id = TrackId{0});

// Replaces the set by its particles at `ancestors` (any multiset of indices in
// [0, N)), weights uniform. `scratch` is a work buffer reused across calls.
void ApplyAncestors(ParticleSet& set, std::span<const int32_t> ancestors, ParticleSet& scratch);

}  // namespace hcpf::tracker
