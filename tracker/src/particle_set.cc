#include "hcpf/tracker/particle_set.h"

#include <cmath>
#include <limits>

#include "fast_math.h"
#include "hcpf/core/check.h"
#include "hcpf/core/instruction_set.h"

namespace hcpf::tracker {
namespace {

// Built for AVX-512, AVX2 and the baseline, the CPU's widest run
// (hcpf/core/instruction_set.h; isa_clones_test.cc runs each).
HCPF_DISPATCHED(void, ExpShifted, (const double* log_w, double shift, double* out, size_t n),
                (log_w, shift, out, n), {
                  for (size_t i = 0; i < n; ++i) out[i] = internal::FastExp(log_w[i] - shift);
                })

}  // namespace

void ParticleSet::Resize(size_t n) {
  px.assign(n, 0.0);
  py.assign(n, 0.0);
  vx.assign(n, 0.0);
  vy.assign(n, 0.0);
  s.assign(n, 1.0);
  log_w.resize(n);
  w.resize(n);
  SetUniformWeights();
}

void ParticleSet::SetUniformWeights() {
  const size_t n = size();
  if (n == 0) return;
  log_w.assign(n, -std::log(static_cast<double>(n)));
  w.assign(n, 1.0 / static_cast<double>(n));
}

NormaliseResult NormaliseLogWeights(ParticleSet& set) {
  NormaliseResult result;
  const size_t n = set.size();
  HCPF_CHECK(set.log_w.size() == n);
  set.w.resize(n);
  if (n == 0) return result;
  constexpr double kNegInf = -std::numeric_limits<double>::infinity();
  double max_log = kNegInf;
  bool has_pos_inf = false;
  for (double& lw : set.log_w) {
    if (std::isnan(lw)) {
      lw = kNegInf;
      ++result.nan_weights;
    }
    if (lw > max_log) max_log = lw;
  }
  has_pos_inf = max_log == std::numeric_limits<double>::infinity();
  if (max_log == kNegInf || has_pos_inf) {
    // Recovery (docs/tracker.md, "Degenerate frames"): no particle carries
    // usable weight, so the frame's evidence is discarded and the cloud keeps
    // its positions with uniform weights. +inf cannot come from a density but
    // is treated the same way rather than silently favouring those particles.
    set.SetUniformWeights();
    result.log_total = kNegInf;
    result.recovered_degenerate = true;
    return result;
  }
  // exp(log_w - max) in a vectorisable map (FastExp: ~1e-15 relative error),
  // then a four-way partial sum (fixed order, so deterministic) to break the
  // loop-carried add latency.
  ExpShifted(set.log_w.data(), max_log, set.w.data(), n);
  double partial[4] = {0.0, 0.0, 0.0, 0.0};
  size_t i = 0;
  for (; i + 4 <= n; i += 4) {
    partial[0] += set.w[i];
    partial[1] += set.w[i + 1];
    partial[2] += set.w[i + 2];
    partial[3] += set.w[i + 3];
  }
  for (; i < n; ++i) partial[0] += set.w[i];
  // total >= 1 because the maximum contributes exp(0) = 1.
  const double total = (partial[0] + partial[1]) + (partial[2] + partial[3]);
  const double inv_total = 1.0 / total;
  const double log_total = std::log(total);
  const double shift = max_log + log_total;
  for (size_t k = 0; k < n; ++k) {
    set.w[k] *= inv_total;
    set.log_w[k] -= shift;
  }
  result.log_total = max_log + log_total;
  return result;
}

double EffectiveSampleSize(std::span<const double> w) {
  double sum_sq = 0.0;
  for (const double v : w) sum_sq += v * v;
  return sum_sq > 0.0 ? 1.0 / sum_sq : 0.0;
}

FilterSummary Summarise(const ParticleSet& set, TrackId id) {
  FilterSummary summary;
  summary.id = id;
  const size_t n = set.size();
  if (n == 0) return summary;
  double mx = 0.0, my = 0.0, ms = 0.0, sum_sq = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double w = set.w[i];
    mx += w * set.px[i];
    my += w * set.py[i];
    ms += w * set.s[i];
    sum_sq += w * w;
  }
  double cxx = 0.0, cxy = 0.0, cyy = 0.0;
  for (size_t i = 0; i < n; ++i) {
    const double w = set.w[i];
    const double dx = set.px[i] - mx;
    const double dy = set.py[i] - my;
    cxx += w * dx * dx;
    cxy += w * dx * dy;
    cyy += w * dy * dy;
  }
  summary.mean = {mx, my};
  summary.cov << cxx, cxy, cxy, cyy;
  summary.mean_scale = ms;
  summary.ess = sum_sq > 0.0 ? 1.0 / sum_sq : 0.0;
  return summary;
}

void ApplyAncestors(ParticleSet& set, std::span<const int32_t> ancestors, ParticleSet& scratch) {
  const size_t n = set.size();
  HCPF_CHECK(ancestors.size() == n) << ancestors.size() << " ancestors for " << n << " particles";
  scratch.px.resize(n);
  scratch.py.resize(n);
  scratch.vx.resize(n);
  scratch.vy.resize(n);
  scratch.s.resize(n);
  for (size_t i = 0; i < n; ++i) {
    const auto a = static_cast<size_t>(ancestors[i]);
    scratch.px[i] = set.px[a];
    scratch.py[i] = set.py[a];
    scratch.vx[i] = set.vx[a];
    scratch.vy[i] = set.vy[a];
    scratch.s[i] = set.s[a];
  }
  set.px.swap(scratch.px);
  set.py.swap(scratch.py);
  set.vx.swap(scratch.vx);
  set.vy.swap(scratch.vy);
  set.s.swap(scratch.s);
  set.SetUniformWeights();
}

}  // namespace hcpf::tracker
