#pragma once
// CLEAR MOT, Identity (IDF1) and HOTA on boxes, computed exactly as TrackEval
// computes them (the rules, including TrackEval's quirks, are written out in
// docs/metrics.md and ../shared/conformance/mot/README.md), plus pooling over
// several sequences and a per-frame event log.
//
// Entry points:
//   MotSummary s = ComputeAll(sequence);            // everything, IoU computed once
//   ClearMetrics c = ComputeClear(sequence);         // or one family at a time
//   MotSummary combined = Pool({s1, s2, ...});       // TrackEval's COMBINED row
// Cost: O(boxes + overlapping pairs) per frame plus a Hungarian step on each
// connected group of overlapping boxes (see SparseMatcher).

#include <array>
#include <cstdint>
#include <ostream>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "hcpf/metrics/sequence.h"

namespace hcpf::metrics {

// IoU threshold of CLEAR and Identity (a pair matches iff IoU >= 0.5).
inline constexpr double kMotIouThreshold = 0.5;
inline constexpr int kNumHotaAlphas = 19;
// 0.05, 0.10, ..., 0.95 exactly as numpy.arange(0.05, 0.99, 0.05) produces them.
const std::array<double, kNumHotaAlphas>& HotaAlphas();

struct ClearMetrics {
  int64_t tp = 0, fp = 0, fn = 0, idsw = 0, frag = 0;
  int64_t mt = 0, pt = 0, ml = 0;
  double motp_sum = 0.0;  // sum of IoU over matches
  // Ratios (fractions, not percent), recomputed from the counts by Finalize.
  double mota = 0.0, motp = 0.0, motp_distance = 0.0, moda = 0.0, smota = 0.0;
  double recall = 0.0, precision = 0.0;
  // num_gt_dets = TP + FN. `empty_gt` applies TrackEval's convention for a
  // sequence without ground truth (every ratio 0 instead of MOTA = -FP).
  void Finalize(bool empty_gt = false, bool empty_hyp = false);
};

struct IdentityMetrics {
  int64_t idtp = 0, idfp = 0, idfn = 0;
  double idf1 = 0.0, idp = 0.0, idr = 0.0;
  void Finalize();
};

struct HotaMetrics {
  template <typename T>
  using PerAlpha = std::array<T, kNumHotaAlphas>;
  PerAlpha<int64_t> tp{}, fn{}, fp{};
  PerAlpha<double> hota{}, deta{}, assa{}, loca{}, detre{}, detpr{}, assre{}, asspr{};
  // Means over the 19 alphas of the arrays above (HOTA != sqrt(DetA * AssA)).
  double hota_mean = 0.0, deta_mean = 0.0, assa_mean = 0.0, loca_mean = 0.0;
  double detre_mean = 0.0, detpr_mean = 0.0, assre_mean = 0.0, asspr_mean = 0.0;
  double hota0 = 0.0, loca0 = 0.0, hotaloca0 = 0.0;  // at alpha = 0.05
  // Recomputes det*, hota and every mean from tp/fn/fp, assa/assre/asspr, loca.
  void Finalize();
};

struct MotSummary {
  std::string name;
  int64_t num_frames = 0;
  int64_t num_objects = 0;      // gt boxes evaluated
  int64_t num_predictions = 0;  // tracker boxes evaluated
  int64_t num_gt_ids = 0;
  int64_t num_tracker_ids = 0;
  ClearMetrics clear;
  IdentityMetrics identity;
  HotaMetrics hota;
};

// One event of the CLEAR matching, py-motmetrics' vocabulary:
//   MATCH    gt matched to the same hypothesis as the last time it was matched (or first time)
//   SWITCH   gt matched to a different hypothesis than the last time (an IDSW)
//   ASCEND   extra event with a SWITCH whose hypothesis had never been matched before
//   TRANSFER extra event: the hypothesis was last matched to a different gt
//   MIGRATE  extra event with a TRANSFER whose gt had never been matched before
//   FP       unmatched hypothesis; MISS unmatched gt
// gt/hyp are the original ids (-1 where not applicable), iou the pair's IoU (0 for FP/MISS).
enum class MotEventType { kMatch, kSwitch, kTransfer, kAscend, kMigrate, kFp, kMiss };
const char* MotEventName(MotEventType type);
struct MotEvent {
  int frame = 0;  // 1-based: frames[t] is frame t + 1
  MotEventType type = MotEventType::kMatch;
  int64_t gt = -1;
  int64_t hyp = -1;
  double iou = 0.0;
  friend bool operator==(const MotEvent&, const MotEvent&) = default;
};

ClearMetrics ComputeClear(const Sequence& seq, std::vector<MotEvent>* events = nullptr);
IdentityMetrics ComputeIdentity(const Sequence& seq);
HotaMetrics ComputeHota(const Sequence& seq);
// All three, plus the counts; IoUs computed once. `events` as in ComputeClear.
MotSummary ComputeAll(const Sequence& seq, std::vector<MotEvent>* events = nullptr);

// The Identity (IDF1) matching itself: the (gt id, hyp id) pairs of the global
// one-to-one assignment maximising the number of frames with IoU >= iou_threshold.
// Pairs are sorted by gt id. Used to map tracks/filters to targets.
std::vector<std::pair<int64_t, int64_t>> IdentityMatching(const Sequence& seq,
                                                          double iou_threshold = kMotIouThreshold);

// TrackEval's combination of sequences: counts summed, ratios recomputed from
// the sums (MOTP TP-weighted), HOTA AssA/AssRe/AssPr/LocA per alpha weighted
// by each sequence's HOTA TP.
MotSummary Pool(std::span<const MotSummary> sequences, std::string name = "COMBINED");

// Every value of a summary under the names TrackEval / the conformance kit use:
// scalars "MOTA", "MOTP", "MOTP_distance", "IDF1", ..., "HOTA(0)", "HOTALocA(0)"
// (counts as exact doubles) and the 19-element arrays "HOTA_alpha", "DetA_alpha",
// ..., "HOTA_TP_alpha", "HOTA_FN_alpha", "HOTA_FP_alpha". Order is fixed.
struct NamedMetrics {
  std::vector<std::pair<std::string, double>> scalars;
  std::vector<std::pair<std::string, std::vector<double>>> arrays;
  // nullptr when absent.
  const double* Scalar(const std::string& name) const;
  const std::vector<double>* Array(const std::string& name) const;
};
NamedMetrics ToNamedMetrics(const MotSummary& summary);
// True for the names that hold integer counts (compared exactly).
bool IsCountMetric(const std::string& name);

// One JSON object per line: {"frame":F,"type":"MATCH","gt":G,"hyp":H,"iou":X}.
void WriteEventsJsonLines(std::ostream& out, std::span<const MotEvent> events);

}  // namespace hcpf::metrics
