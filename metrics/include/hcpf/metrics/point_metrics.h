#pragma once
// Point-set metrics on box centres: OSPA (Schuhmacher, Vo & Vo, 2008) and GOSPA
// with alpha = 2 (Rahmathullah, García-Fernández & Svensson, 2017), with cut-off
// c and order p, per frame and averaged over frames; GOSPA optionally adds a
// track-switching term (see docs/metrics.md for the exact definition).

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "hcpf/core/fields.h"
#include "hcpf/metrics/sequence.h"

namespace hcpf::metrics {

struct PointMetricsOptions {
  double cutoff_px = 20.0;  // c > 0: distances are saturated at c
  double order = 2.0;       // p >= 1
  // GOSPA switching penalty gamma >= 0 (0 = off): each full id switch of a truth
  // between consecutive frames adds gamma^p, each half switch (assigned <-> not
  // assigned while the truth is present in both frames) gamma^p / 2.
  double switching_penalty = 0.0;
  // The `metrics.ospa_*` / `metrics.gospa_*` keys of these options.
  static std::span<const Field<PointMetricsOptions>> Fields();
  // Throws hcpf::InputError naming the field when a constraint is broken.
  void Validate() const;
};

struct IdPoint {
  int64_t id = 0;
  double x = 0.0;
  double y = 0.0;
};

struct PointFrame {
  std::vector<IdPoint> truth;
  std::vector<IdPoint> estimate;
};

// Box centres of a Sequence (gt -> truth, hyp -> estimate).
std::vector<PointFrame> PointFramesFromSequence(const Sequence& seq);

// OSPA distance between two point sets: 0 when both are empty, c when exactly one is.
double Ospa(std::span<const IdPoint> truth, std::span<const IdPoint> estimate, double cutoff,
            double order);

struct GospaTerms {
  double distance = 0.0;      // (localisation + missed + false + switching)^(1/p)
  double localisation = 0.0;  // sum of d^p over assigned pairs (d < c)
  double missed = 0.0;        // c^p / 2 per missed truth
  double false_alarm = 0.0;   // c^p / 2 per false estimate
  double switching = 0.0;     // gamma^p * switches
  int64_t num_assigned = 0, num_missed = 0, num_false = 0;
  double switches = 0.0;  // full switches + 0.5 * half switches
};

// GOSPA (alpha = 2) of one frame without the switching term.
GospaTerms Gospa(std::span<const IdPoint> truth, std::span<const IdPoint> estimate, double cutoff,
                 double order);

struct PointMetrics {
  std::vector<double> ospa;       // per frame
  std::vector<GospaTerms> gospa;  // per frame
  double mean_ospa = 0.0;         // arithmetic means over frames (0 for no frames)
  double mean_gospa = 0.0;
  double total_switches = 0.0;
};

PointMetrics ComputePointMetrics(std::span<const PointFrame> frames,
                                 const PointMetricsOptions& options);

}  // namespace hcpf::metrics
