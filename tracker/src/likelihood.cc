#include "hcpf/tracker/likelihood.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>

#include "fast_math.h"
#include "hcpf/core/check.h"
#include "hcpf/core/instruction_set.h"
#include "mixture_kernel.h"

namespace hcpf::tracker {

std::span<const Field<LikelihoodOptions>> LikelihoodOptions::Fields() {
  using O = LikelihoodOptions;
  static const std::vector<Field<O>> fields = {
      ChoiceField<&O::model>("model",
                             "detections_mixture: every detection, no association; associated: "
                             "the assigned detection only; map: the likelihood map"),
      NumberField("sigma_px", &O::sigma_px, Closed(1e-3, 1000), "px",
                  "std. dev. of a detection's centre about the particle"),
      NumberField("clutter_density", &O::clutter_density, Closed(0, 1), "1/px²",
                  "uniform floor of the mixture"),
      FlagField("use_scores", &O::use_scores, "weight mixture components by detection score"),
      NumberField("sigma_log_size", &O::sigma_log_size, Closed(0, 10), "",
                  "std. dev. of the log box size; 0 = no size term"),
      NumberField("map_floor", &O::map_floor, Closed(0, 1e6), "", "added to map samples"),
  };
  return fields;
}

void LikelihoodOptions::Validate(std::string_view prefix) const {
  CheckFields(*this, Fields(), prefix);
}

namespace {

using Component = internal::MixtureComponent;

constexpr size_t kWeightChunk = 256;
// Below this a mixture sum may be subnormal (FastLog is exact only for normal
// numbers): such particles are recomputed with the exact log-sum-exp. 1e-300
// leaves eight decades of margin above DBL_MIN ~ 2.2e-308.
constexpr double kTinySum = 1e-300;
// FastExpF flushes exponents below kMixtureUnderflow (-87) to zero, so the
// fast sum may leave out up to W e^-87 (W: the components' weights summed).
// A particle whose sum + clutter is below W e^(-87 + 37) may thus be off by
// more than 2^-53 relative and is recomputed exactly: with no clutter, a
// particle 13σ from one detection and 13.2σ from ten others lost the ten
// (1.5 nats: a review).
constexpr double kFlushMarginLog = 37.0;

// Per-component quadratic exponent of particle i.
inline double Exponent(const Component& c, double x, double y, double log_s, double inv_2s2,
                       double inv_2ss2) {
  const double dx = x - c.cx;
  const double dy = y - c.cy;
  const double dl = log_s + c.log_size_offset;
  return -(dx * dx + dy * dy) * inv_2s2 - dl * dl * inv_2ss2;
}

// Builds the mixture components for the detections (skipping zero weights).
std::vector<Component> MakeComponents(std::span<const Detection> detections,
                                      const LikelihoodOptions& o, double base_w_px) {
  std::vector<Component> comps;
  comps.reserve(detections.size());
  const double log_norm_pos = -std::log(2.0 * std::numbers::pi * o.sigma_px * o.sigma_px);
  const double log_norm_size = o.sigma_log_size > 0.0
                                   ? -std::log(std::sqrt(2.0 * std::numbers::pi) * o.sigma_log_size)
                                   : 0.0;
  for (const Detection& d : detections) {
    const double a = o.use_scores ? d.score : 1.0;
    if (!(a > 0.0) || !std::isfinite(a)) continue;
    // A detection with a non-finite box carries no usable position (a broken
    // detector output): it is ignored rather than poisoning every weight.
    if (!std::isfinite(d.box.centre_x()) || !std::isfinite(d.box.centre_y())) continue;
    Component c;
    c.cx = d.box.centre_x();
    c.cy = d.box.centre_y();
    c.log_weight = std::log(a) + log_norm_pos + log_norm_size;
    c.weight = std::exp(c.log_weight);
    c.log_size_offset = 0.0;
    if (o.sigma_log_size > 0.0 && d.box.width > 0.0) {
      c.log_size_offset = std::log(base_w_px / d.box.width);
    }
    comps.push_back(c);
  }
  return comps;
}

// Exact log-sum-exp of the clutter floor and every component for one particle
// (used where the fast linear-space sum underflows).
double ExactLogMixture(std::span<const Component> comps, double log_clutter, double x, double y,
                       double log_s, double inv_2s2, double inv_2ss2) {
  double max_term = log_clutter;
  for (const Component& c : comps) {
    max_term = std::max(max_term, c.log_weight + Exponent(c, x, y, log_s, inv_2s2, inv_2ss2));
  }
  if (max_term == -std::numeric_limits<double>::infinity()) return max_term;
  double total = std::exp(log_clutter - max_term);
  for (const Component& c : comps) {
    total += std::exp(c.log_weight + Exponent(c, x, y, log_s, inv_2s2, inv_2ss2) - max_term);
  }
  return max_term + std::log(total);
}

// Built for AVX-512, AVX2 and the baseline, the CPU's widest run
// (hcpf/core/instruction_set.h; isa_clones_test.cc runs each).
HCPF_DISPATCHED(void, MixtureChunk,
                (const Component* comps, size_t num_comps, const double* px, const double* py,
                 const double* log_s, double inv_2s2, double inv_2ss2, double* sum, size_t m),
                (comps, num_comps, px, py, log_s, inv_2s2, inv_2ss2, sum, m), {
                  if (inv_2ss2 > 0.0) {
                    internal::MixtureKernel<true>(comps, num_comps, px, py, log_s, inv_2s2,
                                                  inv_2ss2, sum, m);
                  } else {
                    internal::MixtureKernel<false>(comps, num_comps, px, py, log_s, inv_2s2,
                                                   inv_2ss2, sum, m);
                  }
                })

HCPF_DISPATCHED(void, AddLogOfSum, (const double* sum, double clutter, double* log_w, size_t m),
                (sum, clutter, log_w, m), {
                  for (size_t i = 0; i < m; ++i) log_w[i] += internal::FastLog(sum[i] + clutter);
                })

}  // namespace

DetectionsMixtureLikelihood::DetectionsMixtureLikelihood(const LikelihoodOptions& options)
    : options_(options) {
  options_.Validate();
}

bool DetectionsMixtureLikelihood::AddLogLikelihood(ParticleSet& set,
                                                   const LikelihoodInput& input) const {
  HCPF_CHECK(input.observation != nullptr);
  const std::vector<Component> comps =
      MakeComponents(input.observation->detections, options_, input.base_w_px);
  // Without detections the mixture is the constant clutter floor: no
  // information about this filter, so the weights are left alone (flat).
  if (comps.empty()) return false;
  const double inv_2s2 = 1.0 / (2.0 * options_.sigma_px * options_.sigma_px);
  const bool use_size = options_.sigma_log_size > 0.0;
  const double inv_2ss2 =
      use_size ? 1.0 / (2.0 * options_.sigma_log_size * options_.sigma_log_size) : 0.0;
  const double clutter = options_.clutter_density;
  const double log_clutter =
      clutter > 0.0 ? std::log(clutter) : -std::numeric_limits<double>::infinity();
  // A component whose largest possible term in a chunk is below 2^-60 times
  // the clutter floor changes no particle's L = sum + clutter by more than
  // 2^-60 relative (below double resolution, 2^-53) and is skipped; with no
  // clutter only exact zeros are skipped (FastExpF flushes exponents < -87).
  // Far detections of other targets then cost nothing.
  const double negligible_log = clutter > 0.0 ? log_clutter - 60.0 * std::numbers::ln2
                                              : -std::numeric_limits<double>::infinity();
  // Where the fast sum is exact to double resolution (kFlushMarginLog).
  double total_weight = 0.0;
  for (const Component& c : comps) total_weight += c.weight;
  const double exact_below =
      std::max(kTinySum, total_weight * std::exp(internal::kMixtureUnderflow + kFlushMarginLog));
  std::vector<Component> active;
  active.reserve(comps.size());
  std::array<double, kWeightChunk> sum;
  std::array<double, kWeightChunk> log_s;
  const size_t n = set.size();
  for (size_t begin = 0; begin < n; begin += kWeightChunk) {
    const size_t m = std::min(kWeightChunk, n - begin);
    const double* px = set.px.data() + begin;
    const double* py = set.py.data() + begin;
    const double* s = set.s.data() + begin;
    if (use_size) {
      for (size_t i = 0; i < m; ++i) log_s[i] = internal::FastLog(s[i]);
    } else {
      std::fill_n(log_s.data(), m, 0.0);
    }
    // Components that cannot matter anywhere in this chunk are skipped (see
    // kNegligibleLog below); the decision depends only on the data, so the
    // result stays deterministic.
    double x0 = px[0], x1 = px[0], y0 = py[0], y1 = py[0];
    for (size_t i = 1; i < m; ++i) {
      x0 = std::min(x0, px[i]);
      x1 = std::max(x1, px[i]);
      y0 = std::min(y0, py[i]);
      y1 = std::max(y1, py[i]);
    }
    active.clear();
    for (const Component& c : comps) {
      const double dx = std::max({x0 - c.cx, 0.0, c.cx - x1});
      const double dy = std::max({y0 - c.cy, 0.0, c.cy - y1});
      const double max_exponent = -(dx * dx + dy * dy) * inv_2s2;  // the size term is <= 0
      if (max_exponent >= internal::kMixtureUnderflow &&
          c.log_weight + max_exponent >= negligible_log) {
        active.push_back(c);
      }
    }
    MixtureChunk(active.data(), active.size(), px, py, log_s.data(), inv_2s2, inv_2ss2, sum.data(),
                 m);
    double* log_w = set.log_w.data() + begin;
    bool any_tiny = false;
    for (size_t i = 0; i < m; ++i) any_tiny |= (sum[i] + clutter) < exact_below;
    if (!any_tiny) {
      AddLogOfSum(sum.data(), clutter, log_w, m);
      continue;
    }
    for (size_t i = 0; i < m; ++i) {
      if (sum[i] + clutter < exact_below) {
        const double ls = use_size ? std::log(s[i]) : 0.0;
        log_w[i] += ExactLogMixture(comps, log_clutter, px[i], py[i], ls, inv_2s2, inv_2ss2);
      } else {
        log_w[i] += internal::FastLog(sum[i] + clutter);
      }
    }
  }
  return true;
}

AssociatedLikelihood::AssociatedLikelihood(const LikelihoodOptions& options) : options_(options) {
  options_.Validate();
}

bool AssociatedLikelihood::AddLogLikelihood(ParticleSet& set, const LikelihoodInput& input) const {
  if (input.assigned == nullptr) return false;
  const Detection& d = *input.assigned;
  if (!std::isfinite(d.box.centre_x()) || !std::isfinite(d.box.centre_y())) return false;
  const double cx = d.box.centre_x();
  const double cy = d.box.centre_y();
  const double inv_2s2 = 1.0 / (2.0 * options_.sigma_px * options_.sigma_px);
  const double log_norm = -std::log(2.0 * std::numbers::pi * options_.sigma_px * options_.sigma_px);
  const size_t n = set.size();
  for (size_t i = 0; i < n; ++i) {
    const double dx = set.px[i] - cx;
    const double dy = set.py[i] - cy;
    set.log_w[i] += log_norm - (dx * dx + dy * dy) * inv_2s2;
  }
  if (options_.sigma_log_size > 0.0 && d.box.width > 0.0) {
    const double inv_2ss2 = 1.0 / (2.0 * options_.sigma_log_size * options_.sigma_log_size);
    const double offset = std::log(input.base_w_px / d.box.width);
    const double log_norm_size =
        -std::log(std::sqrt(2.0 * std::numbers::pi) * options_.sigma_log_size);
    for (size_t i = 0; i < n; ++i) {
      const double dl = std::log(set.s[i]) + offset;
      set.log_w[i] += log_norm_size - dl * dl * inv_2ss2;
    }
  }
  return true;
}

MapLikelihood::MapLikelihood(const LikelihoodOptions& options) : options_(options) {
  options_.Validate();
}

bool MapLikelihood::AddLogLikelihood(ParticleSet& set, const LikelihoodInput& input) const {
  HCPF_CHECK(input.observation != nullptr);
  if (!input.observation->likelihood.has_value()) return false;
  const LikelihoodMap& map = *input.observation->likelihood;
  if (map.width <= 0 || map.height <= 0) return false;
  const size_t n = set.size();
  for (size_t i = 0; i < n; ++i) {
    // Negative or NaN map values are invalid input to a density; treat as 0.
    double v = map.Sample(set.px[i], set.py[i]);
    v = v > 0.0 ? v : 0.0;
    set.log_w[i] += std::log(v + options_.map_floor);
  }
  return true;
}

std::unique_ptr<Likelihood> MakeLikelihood(const LikelihoodOptions& options) {
  options.Validate();
  switch (options.model) {
    case LikelihoodModel::kDetectionsMixture:
      return std::make_unique<DetectionsMixtureLikelihood>(options);
    case LikelihoodModel::kAssociated:
      return std::make_unique<AssociatedLikelihood>(options);
    case LikelihoodModel::kMap:
      return std::make_unique<MapLikelihood>(options);
  }
  HCPF_CHECK(false) << "unknown likelihood model";
  return nullptr;
}

}  // namespace hcpf::tracker
