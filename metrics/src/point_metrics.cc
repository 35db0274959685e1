#include "hcpf/metrics/point_metrics.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>

#include "hcpf/core/check.h"
#include "hcpf/core/error.h"
#include "hcpf/metrics/assignment.h"

namespace hcpf::metrics {
namespace {

// The largest power of ten a p-th power may reach (c^p, γ^p): a frame's
// sums of up to 10^8 such terms stay below a double's 1.8e308.
constexpr int kMaxPowerExponent = 300;

double Distance(const IdPoint& a, const IdPoint& b) { return std::hypot(a.x - b.x, a.y - b.y); }

// Optimal assignment of truths to estimates minimising sum min(d, c)^p.
// Returns, per truth, the estimate index or -1.
std::vector<int> AssignCut(std::span<const IdPoint> truth, std::span<const IdPoint> estimate,
                           double cutoff, double order, AssignmentSolver* solver) {
  const int m = static_cast<int>(truth.size());
  const int n = static_cast<int>(estimate.size());
  std::vector<double> cost(static_cast<size_t>(m) * n);
  for (int i = 0; i < m; ++i) {
    for (int j = 0; j < n; ++j) {
      cost[static_cast<size_t>(i) * n + j] =
          std::pow(std::min(Distance(truth[i], estimate[j]), cutoff), order);
    }
  }
  const auto result = solver->Solve(cost, m, n, AssignmentSense::kMinimise);
  return {result.begin(), result.end()};
}

}  // namespace

std::span<const Field<PointMetricsOptions>> PointMetricsOptions::Fields() {
  using O = PointMetricsOptions;
  static const std::vector<Field<O>> fields = {
      NumberField("ospa_cutoff_px", &O::cutoff_px, Closed(1e-3, 1e6), "px", "OSPA/GOSPA cut-off c"),
      NumberField("ospa_order", &O::order, Closed(1, 100), "", "OSPA/GOSPA order p"),
      NumberField("gospa_switching_penalty", &O::switching_penalty, Closed(0, 1e6), "",
                  "GOSPA switching penalty γ; 0 = no switching term"),
  };
  return fields;
}

void PointMetricsOptions::Validate() const {
  CheckFields(*this, Fields(), "metrics");
  // OSPA and GOSPA sum p-th powers of distances up to c (and GOSPA's
  // switching penalty γ^p): past 1e300 a double overflows to infinity and a
  // frame's value becomes NaN (an audit of valid input: c = 10^6 with p = 60
  // wrote "nan" throughout, exit 0).
  const double largest = std::max(cutoff_px, switching_penalty);
  if (largest > 1.0 && order * std::log10(largest) > kMaxPowerExponent) {
    FailOption("metrics", "ospa_order",
               fmt::format("an order p with {}^p at most 1e{} (p at most {:.4g} with that {}): "
                           "OSPA and GOSPA sum p-th powers, which a double cannot hold past that",
                           largest == cutoff_px ? "ospa_cutoff_px" : "gospa_switching_penalty",
                           kMaxPowerExponent, kMaxPowerExponent / std::log10(largest),
                           largest == cutoff_px ? fmt::format("cut-off, {:g} px", cutoff_px)
                                                : fmt::format("penalty, {:g}", switching_penalty)),
               order);
  }
}

std::vector<PointFrame> PointFramesFromSequence(const Sequence& seq) {
  HCPF_CHECK(!seq.sparse()) << "point metrics need every frame (a dense Sequence)";
  std::vector<PointFrame> frames(seq.frames.size());
  for (size_t t = 0; t < seq.frames.size(); ++t) {
    for (const LabelledBox& b : seq.frames[t].gt)
      frames[t].truth.push_back({b.id, b.box.centre_x(), b.box.centre_y()});
    for (const LabelledBox& b : seq.frames[t].hyp)
      frames[t].estimate.push_back({b.id, b.box.centre_x(), b.box.centre_y()});
  }
  return frames;
}

double Ospa(std::span<const IdPoint> truth, std::span<const IdPoint> estimate, double cutoff,
            double order) {
  const size_t m = truth.size();
  const size_t n = estimate.size();
  if (m == 0 && n == 0) return 0.0;
  if (m == 0 || n == 0) return cutoff;
  AssignmentSolver solver;
  const std::vector<int> a = AssignCut(truth, estimate, cutoff, order, &solver);
  double sum = 0.0;
  for (size_t i = 0; i < m; ++i) {
    if (a[i] >= 0) sum += std::pow(std::min(Distance(truth[i], estimate[a[i]]), cutoff), order);
  }
  sum += std::pow(cutoff, order) * static_cast<double>(std::max(m, n) - std::min(m, n));
  return std::pow(sum / static_cast<double>(std::max(m, n)), 1.0 / order);
}

namespace {
GospaTerms GospaWithAssignment(std::span<const IdPoint> truth, std::span<const IdPoint> estimate,
                               double cutoff, double order, std::vector<int>* assignment) {
  GospaTerms g;
  AssignmentSolver solver;
  std::vector<int> a = truth.empty() || estimate.empty()
                           ? std::vector<int>(truth.size(), -1)
                           : AssignCut(truth, estimate, cutoff, order, &solver);
  const double half_cp = 0.5 * std::pow(cutoff, order);
  // With alpha = 2 a pair at distance >= c costs c^p either way; count it as a
  // missed truth plus a false estimate (the usual GOSPA decomposition).
  for (size_t i = 0; i < truth.size(); ++i) {
    if (a[i] >= 0 && Distance(truth[i], estimate[a[i]]) < cutoff) {
      g.localisation += std::pow(Distance(truth[i], estimate[a[i]]), order);
      ++g.num_assigned;
    } else {
      a[i] = -1;
    }
  }
  g.num_missed = static_cast<int64_t>(truth.size()) - g.num_assigned;
  g.num_false = static_cast<int64_t>(estimate.size()) - g.num_assigned;
  g.missed = half_cp * g.num_missed;
  g.false_alarm = half_cp * g.num_false;
  g.distance = std::pow(g.localisation + g.missed + g.false_alarm, 1.0 / order);
  if (assignment) *assignment = std::move(a);
  return g;
}
}  // namespace

GospaTerms Gospa(std::span<const IdPoint> truth, std::span<const IdPoint> estimate, double cutoff,
                 double order) {
  return GospaWithAssignment(truth, estimate, cutoff, order, nullptr);
}

PointMetrics ComputePointMetrics(std::span<const PointFrame> frames,
                                 const PointMetricsOptions& options) {
  options.Validate();
  PointMetrics out;
  // truth id -> estimate id it was assigned to in the previous frame (-1: present, unassigned).
  std::unordered_map<int64_t, int64_t> previous, current;
  constexpr int64_t kUnassigned = std::numeric_limits<int64_t>::min();
  std::vector<int> assignment;
  for (const PointFrame& f : frames) {
    out.ospa.push_back(Ospa(f.truth, f.estimate, options.cutoff_px, options.order));
    GospaTerms g =
        GospaWithAssignment(f.truth, f.estimate, options.cutoff_px, options.order, &assignment);
    current.clear();
    for (size_t i = 0; i < f.truth.size(); ++i) {
      current[f.truth[i].id] = assignment[i] >= 0 ? f.estimate[assignment[i]].id : kUnassigned;
    }
    if (options.switching_penalty > 0.0) {
      for (const auto& [truth_id, now] : current) {
        const auto it = previous.find(truth_id);
        if (it == previous.end()) continue;  // not present in the previous frame
        const int64_t before = it->second;
        if (before == now) continue;
        g.switches += (before == kUnassigned || now == kUnassigned) ? 0.5 : 1.0;
      }
      g.switching = std::pow(options.switching_penalty, options.order) * g.switches;
      g.distance =
          std::pow(g.localisation + g.missed + g.false_alarm + g.switching, 1.0 / options.order);
      out.total_switches += g.switches;
    }
    std::swap(previous, current);
    out.gospa.push_back(g);
  }
  if (!frames.empty()) {
    for (double v : out.ospa) out.mean_ospa += v;
    for (const GospaTerms& g : out.gospa) out.mean_gospa += g.distance;
    out.mean_ospa /= static_cast<double>(frames.size());
    out.mean_gospa /= static_cast<double>(frames.size());
  }
  return out;
}

}  // namespace hcpf::metrics
