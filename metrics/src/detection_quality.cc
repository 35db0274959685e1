#include "hcpf/metrics/detection_quality.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

#include "hcpf/core/assignment.h"

namespace hcpf::metrics {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();
// A cost no allowed pair reaches: pairs the rule forbids (IoU costs are in
// [-1, 0], centre costs in [0, 1]).
constexpr double kForbidden = 1e6;

const std::vector<double> kSizeEdges = {0, 8, 16, 32, 64, kInf};
const std::vector<double> kVisibilityEdges = {0, 0.25, 0.5, 0.75, kInf};
const std::vector<double> kTruncationEdges = {0, 0.15, 0.3, 0.5, kInf};

double Ratio(int64_t num, int64_t den) {
  return den > 0 ? static_cast<double>(num) / static_cast<double>(den) : kNaN;
}

size_t BinOf(const std::vector<double>& edges, double v) {
  for (size_t b = 0; b + 1 < edges.size(); ++b) {
    if (v < edges[b + 1]) return b;
  }
  return edges.size() - 2;
}

double SizeOf(const BoxPx& b) { return std::sqrt(b.area()); }

// `last_hi`: the upper end written for the last bin.
std::vector<DetectionBin> Bins(const std::vector<double>& edges, double last_hi) {
  std::vector<DetectionBin> bins(edges.size() - 1);
  for (size_t b = 0; b < bins.size(); ++b) {
    bins[b].lo = edges[b];
    bins[b].hi = b + 1 == bins.size() ? last_hi : edges[b + 1];
  }
  return bins;
}

bool Compatible(const Detection& d, const DetectionTruth& t) {
  return !d.target.has_value() || *d.target == t.target;
}

// Whether the centre of `d` lies within half of `t`'s box (|dx| <= w/2 and
// |dy| <= h/2), and its distance normalised by the half-diagonal.
std::optional<double> CentreCost(const Detection& d, const DetectionTruth& t) {
  const double dx = d.box.centre_x() - t.box.centre_x();
  const double dy = d.box.centre_y() - t.box.centre_y();
  if (std::abs(dx) > 0.5 * t.box.width || std::abs(dy) > 0.5 * t.box.height) return std::nullopt;
  const double half_diagonal = 0.5 * std::hypot(t.box.width, t.box.height);
  return std::hypot(dx, dy) / half_diagonal;
}

enum class Rule { kIou, kCentre };

// Matches one frame under `rule`; for each truth the matched detection or -1.
std::vector<int> Match(const DetectionFrame& f, Rule rule, double iou_threshold,
                       AssignmentSolver& solver) {
  const int rows = static_cast<int>(f.truth.size());
  const int cols = static_cast<int>(f.detections.size());
  std::vector<int> match(f.truth.size(), -1);
  if (rows == 0 || cols == 0) return match;
  std::vector<double> cost(static_cast<size_t>(rows) * cols, kForbidden);
  for (int t = 0; t < rows; ++t) {
    for (int d = 0; d < cols; ++d) {
      const Detection& det = f.detections[d];
      const DetectionTruth& truth = f.truth[t];
      if (!Compatible(det, truth)) continue;
      double& c = cost[static_cast<size_t>(t) * cols + d];
      if (rule == Rule::kIou) {
        const double iou = Iou(det.box, truth.box);
        if (iou >= iou_threshold) c = -iou;
      } else if (const auto centre = CentreCost(det, truth)) {
        c = *centre;
      }
    }
  }
  const std::span<const int> assigned = solver.Solve(cost, rows, cols, AssignmentSense::kMinimise);
  for (int t = 0; t < rows; ++t) {
    const int d = assigned[t];
    if (d >= 0 && cost[static_cast<size_t>(t) * cols + d] < kForbidden) match[t] = d;
  }
  return match;
}

}  // namespace

double DetectionCounts::precision() const { return Ratio(tp, tp + fp); }
double DetectionCounts::recall() const { return Ratio(tp, tp + fn); }
double DetectionCounts::f1() const { return Ratio(2 * tp, 2 * tp + fp + fn); }
double TargetDetections::recall() const { return Ratio(found, found + missed); }
double TargetDetections::recall_centre() const {
  return Ratio(found_centre, found_centre + missed_centre);
}

DetectionQuality ScoreDetections(std::span<const DetectionFrame> frames,
                                 const DetectionQualityOptions& options) {
  DetectionQuality q;
  q.by_size = Bins(kSizeEdges, kInf);
  q.by_visibility = Bins(kVisibilityEdges, 1.0);
  q.by_truncation = Bins(kTruncationEdges, 1.0);
  AssignmentSolver solver;
  double centre_error_sum = 0.0, iou_sum = 0.0;
  std::vector<double> sizes;
  std::map<int32_t, TargetDetections> by_target;
  for (size_t i = 0; i < frames.size(); ++i) {
    const DetectionFrame& f = frames[i];
    for (const DetectionTruth& truth : f.truth) {
      by_target[Value(truth.target)].target = truth.target;
      if (truth.visible_fraction >= options.min_visible) sizes.push_back(SizeOf(truth.box));
    }
    for (const Rule rule : {Rule::kIou, Rule::kCentre}) {
      const std::vector<int> match = Match(f, rule, options.iou_threshold, solver);
      const auto counts = [rule](DetectionBin& b) -> DetectionCounts& {
        return rule == Rule::kIou ? b.iou : b.centre;
      };
      DetectionCounts& total = rule == Rule::kIou ? q.iou : q.centre;
      std::vector<char> used(f.detections.size(), 0);     // matched to a counted target
      std::vector<char> ignored(f.detections.size(), 0);  // matched to a "don't care" one
      for (size_t t = 0; t < f.truth.size(); ++t) {
        const DetectionTruth& truth = f.truth[t];
        const bool care = truth.visible_fraction >= options.min_visible;
        const int d = match[t];
        if (!care) {
          if (d >= 0) ignored[static_cast<size_t>(d)] = 1;
          continue;
        }
        DetectionCounts& by_size = counts(q.by_size[BinOf(kSizeEdges, SizeOf(truth.box))]);
        DetectionCounts& by_vis =
            counts(q.by_visibility[BinOf(kVisibilityEdges, truth.visible_fraction)]);
        DetectionCounts& by_trunc =
            counts(q.by_truncation[BinOf(kTruncationEdges, truth.truncation)]);
        TargetDetections& mine = by_target[Value(truth.target)];
        const int frame = static_cast<int>(i);
        if (rule == Rule::kIou) {
          ++(d >= 0 ? mine.found : mine.missed);
          (d >= 0 ? mine.found_frames : mine.missed_frames).push_back(frame);
        } else {
          ++(d >= 0 ? mine.found_centre : mine.missed_centre);
        }
        if (d >= 0) {
          used[static_cast<size_t>(d)] = 1;
          ++total.tp, ++by_size.tp, ++by_vis.tp, ++by_trunc.tp;
          if (rule == Rule::kIou) {
            const Detection& det = f.detections[static_cast<size_t>(d)];
            centre_error_sum += std::hypot(det.box.centre_x() - truth.box.centre_x(),
                                           det.box.centre_y() - truth.box.centre_y());
            iou_sum += Iou(det.box, truth.box);
          }
        } else {
          ++total.fn, ++by_size.fn, ++by_vis.fn, ++by_trunc.fn;
        }
      }
      for (size_t d = 0; d < f.detections.size(); ++d) {
        if (used[d] || ignored[d]) continue;
        ++total.fp;
        ++counts(q.by_size[BinOf(kSizeEdges, SizeOf(f.detections[d].box))]).fp;
      }
    }
  }
  for (auto& [id, t] : by_target) q.by_target.push_back(std::move(t));
  q.mean_centre_error_px = q.iou.tp > 0 ? centre_error_sum / q.iou.tp : kNaN;
  q.mean_iou = q.iou.tp > 0 ? iou_sum / q.iou.tp : kNaN;
  q.median_size_px = kNaN;
  if (!sizes.empty()) {
    // The lower median for an even count: one of the sizes, not a mean of two.
    const auto mid = sizes.begin() + static_cast<std::ptrdiff_t>((sizes.size() - 1) / 2);
    std::nth_element(sizes.begin(), mid, sizes.end());
    q.median_size_px = *mid;
  }
  return q;
}

}  // namespace hcpf::metrics
