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
const std::vector<double> kVisibilityEdges = {0, 0.25, 0.5, kMostlyVisible, kInf};
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

// Whether a target is counted (visible at least min_visible); the others are
// "don't care".
bool Counted(const DetectionTruth& t, const DetectionQualityOptions& options) {
  return t.visible_fraction >= options.min_visible;
}

bool Compatible(const Detection& d, const DetectionTruth& t) {
  return !d.target.has_value() || *d.target == t.target;
}

enum class Labels { kRespected, kIgnored };

// Whether the centre of `d` lies within half of `t`'s box (|dx| <= w/2 and
// |dy| <= h/2), and its distance normalised by the half-diagonal; never for a
// box of no size.
std::optional<double> CentreCost(const Detection& d, const DetectionTruth& t) {
  const double dx = d.box.centre_x() - t.box.centre_x();
  const double dy = d.box.centre_y() - t.box.centre_y();
  if (std::abs(dx) > 0.5 * t.box.width || std::abs(dy) > 0.5 * t.box.height) return std::nullopt;
  const double half_diagonal = 0.5 * std::hypot(t.box.width, t.box.height);
  // A box of no size (a 0 x 0 truth box is valid input) has no centre
  // distance to normalise: nothing matches it (0 / 0 stopped the solver).
  if (!(half_diagonal > 0.0)) return std::nullopt;
  return std::hypot(dx, dy) / half_diagonal;
}

enum class Rule { kIou, kCentre };

// Matches one frame under `rule`; for each truth the matched detection or -1.
// Counted targets are matched first, over every detection; "don't care"
// targets then take what is left (COCO's rule, as the precision-recall curve
// below: a detection goes to a don't-care target only when no counted target
// takes it). In one assignment over both, a detection overlapping a counted
// target and, more, a don't-care one went to the don't-care target and the
// counted one was missed (an audit: at occlusions).
std::vector<int> Match(const DetectionFrame& f, Rule rule, const DetectionQualityOptions& options,
                       AssignmentSolver& solver, Labels labels = Labels::kRespected) {
  std::vector<int> match(f.truth.size(), -1);
  std::vector<char> taken(f.detections.size(), 0);
  for (const bool care : {true, false}) {
    std::vector<size_t> truths, detections;
    for (size_t t = 0; t < f.truth.size(); ++t) {
      if (Counted(f.truth[t], options) == care) truths.push_back(t);
    }
    for (size_t d = 0; d < f.detections.size(); ++d) {
      if (!taken[d]) detections.push_back(d);
    }
    const int rows = static_cast<int>(truths.size());
    const int cols = static_cast<int>(detections.size());
    if (rows == 0 || cols == 0) continue;
    std::vector<double> cost(static_cast<size_t>(rows) * cols, kForbidden);
    for (int r = 0; r < rows; ++r) {
      const DetectionTruth& truth = f.truth[truths[static_cast<size_t>(r)]];
      for (int c = 0; c < cols; ++c) {
        const Detection& det = f.detections[detections[static_cast<size_t>(c)]];
        if (labels == Labels::kRespected && !Compatible(det, truth)) continue;
        double& cell = cost[static_cast<size_t>(r) * cols + c];
        if (rule == Rule::kIou) {
          const double iou = Iou(det.box, truth.box);
          if (iou >= options.iou_threshold) cell = -iou;
        } else if (const auto centre = CentreCost(det, truth)) {
          cell = *centre;
        }
      }
    }
    const std::span<const int> assigned =
        solver.Solve(cost, rows, cols, AssignmentSense::kMinimise);
    for (int r = 0; r < rows; ++r) {
      const int c = assigned[static_cast<size_t>(r)];
      if (c < 0 || cost[static_cast<size_t>(r) * cols + c] >= kForbidden) continue;
      const size_t d = detections[static_cast<size_t>(c)];
      match[truths[static_cast<size_t>(r)]] = static_cast<int>(d);
      taken[d] = 1;
    }
  }
  return match;
}

// Greedy matching by score over the whole sequence (PrecisionRecall).
PrecisionRecall ComputePrecisionRecall(std::span<const DetectionFrame> frames,
                                       const DetectionQualityOptions& options) {
  PrecisionRecall pr;
  pr.best_f1 = pr.best_f1_precision = pr.best_f1_recall = pr.best_f1_min_score = kNaN;
  struct Ranked {
    double score;
    size_t frame, detection;
  };
  std::vector<Ranked> ranked;
  std::vector<std::vector<char>> taken(frames.size());
  int64_t positives = 0;
  for (size_t i = 0; i < frames.size(); ++i) {
    for (const DetectionTruth& t : frames[i].truth) {
      if (Counted(t, options)) ++positives;
    }
    taken[i].assign(frames[i].truth.size(), 0);
    for (size_t d = 0; d < frames[i].detections.size(); ++d) {
      ranked.push_back({frames[i].detections[d].score, i, d});
    }
  }
  if (positives == 0) {
    pr.average_precision = kNaN;
    return pr;
  }
  // Highest score first; equal scores keep frame and detection order.
  std::stable_sort(ranked.begin(), ranked.end(),
                   [](const Ranked& a, const Ranked& b) { return a.score > b.score; });
  // The target `r` matches: the unmatched compatible one it overlaps most at
  // IoU >= threshold, among the counted targets (`care`) or the others.
  const auto best = [&](const Ranked& r, bool care) {
    const DetectionFrame& f = frames[r.frame];
    const Detection& det = f.detections[r.detection];
    int found = -1;
    double found_iou = 0.0;
    for (size_t t = 0; t < f.truth.size(); ++t) {
      const DetectionTruth& truth = f.truth[t];
      if (taken[r.frame][t] || Counted(truth, options) != care || !Compatible(det, truth)) {
        continue;
      }
      const double iou = Iou(det.box, truth.box);
      if (iou >= options.iou_threshold && (found < 0 || iou > found_iou)) {
        found = static_cast<int>(t);
        found_iou = iou;
      }
    }
    return found;
  };
  struct Point {
    double score, precision;
    int64_t tp, fp;
  };
  std::vector<Point> points;  // after each distinct score
  int64_t tp = 0, fp = 0;
  for (size_t i = 0; i < ranked.size();) {
    size_t j = i;
    for (; j < ranked.size() && ranked[j].score == ranked[i].score; ++j) {
      if (const int t = best(ranked[j], true); t >= 0) {
        taken[ranked[j].frame][static_cast<size_t>(t)] = 1;
        ++tp;
      } else if (const int u = best(ranked[j], false); u >= 0) {
        taken[ranked[j].frame][static_cast<size_t>(u)] = 1;  // on a "don't care" target
      } else {
        ++fp;
      }
    }
    if (tp + fp > 0) points.push_back({ranked[i].score, Ratio(tp, tp + fp), tp, fp});
    i = j;
  }
  // The envelope from the right: at each point, the best precision at this
  // recall or more, and the point that has it (the larger recall on a tie).
  std::vector<size_t> envelope(points.size());
  for (size_t k = points.size(); k-- > 0;) {
    envelope[k] = k + 1 < points.size() && points[envelope[k + 1]].precision >= points[k].precision
                      ? envelope[k + 1]
                      : k;
  }
  double sum = 0.0;
  size_t first = 0;  // the first point whose recall reaches the current level
  for (int level = 0; level <= 100; ++level) {
    // recall >= level / 100, in integers: tp * 100 >= level * positives.
    while (first < points.size() && points[first].tp * 100 < level * positives) ++first;
    PrecisionAtRecall& p = pr.curve.emplace_back();
    p.recall = level / 100.0;
    if (first < points.size()) {
      p.precision = points[envelope[first]].precision;
      p.min_score = points[envelope[first]].score;
    } else {
      p.precision = 0.0;
      p.min_score = kNaN;
    }
    sum += p.precision;
  }
  pr.average_precision = sum / 101.0;
  for (const Point& p : points) {
    if (p.tp == 0) continue;
    const double f1 = Ratio(2 * p.tp, p.tp + p.fp + positives);
    if (std::isnan(pr.best_f1) || f1 > pr.best_f1) {
      pr.best_f1 = f1;
      pr.best_f1_precision = p.precision;
      pr.best_f1_recall = Ratio(p.tp, positives);
      pr.best_f1_min_score = p.score;
    }
  }
  return pr;
}

}  // namespace

double DetectionCounts::precision() const { return Ratio(tp, tp + fp); }
double DetectionCounts::recall() const { return Ratio(tp, tp + fn); }
double DetectionCounts::f1() const { return Ratio(2 * tp, 2 * tp + fp + fn); }
double LabelCounts::accuracy() const { return Ratio(right, matched); }
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
  // The mostly visible subset, matched again under its own "don't care"
  // (below): the matching over every counted target gives a less visible
  // target a detection that the subset gives a mostly visible one.
  DetectionQualityOptions mostly = options;
  mostly.min_visible = kMostlyVisible;
  const bool subset = options.min_visible < kMostlyVisible;
  for (size_t i = 0; i < frames.size(); ++i) {
    const DetectionFrame& f = frames[i];
    if (subset) {
      const std::vector<int> match = Match(f, Rule::kIou, mostly, solver);
      std::vector<char> matched(f.detections.size(), 0);  // to any target, counted or not
      for (size_t t = 0; t < f.truth.size(); ++t) {
        if (match[t] >= 0) matched[static_cast<size_t>(match[t])] = 1;
        if (Counted(f.truth[t], mostly))
          ++(match[t] >= 0 ? q.iou_mostly_visible.tp : q.iou_mostly_visible.fn);
      }
      q.iou_mostly_visible.fp += std::count(matched.begin(), matched.end(), 0);
    }
    for (const DetectionTruth& truth : f.truth) {
      by_target[Value(truth.target)].target = truth.target;
      if (Counted(truth, options)) sizes.push_back(SizeOf(truth.box));
    }
    if (std::any_of(f.detections.begin(), f.detections.end(),
                    [](const Detection& d) { return d.target.has_value(); })) {
      LabelCounts& labels = q.labels ? *q.labels : q.labels.emplace();
      const std::vector<int> match = Match(f, Rule::kIou, options, solver, Labels::kIgnored);
      for (size_t t = 0; t < f.truth.size(); ++t) {
        if (match[t] < 0 || !Counted(f.truth[t], options)) continue;
        const Detection& det = f.detections[static_cast<size_t>(match[t])];
        if (!det.target) continue;
        ++labels.matched;
        if (*det.target == f.truth[t].target) ++labels.right;
      }
    }
    for (const Rule rule : {Rule::kIou, Rule::kCentre}) {
      const std::vector<int> match = Match(f, rule, options, solver);
      const auto counts = [rule](DetectionBin& b) -> DetectionCounts& {
        return rule == Rule::kIou ? b.iou : b.centre;
      };
      DetectionCounts& total = rule == Rule::kIou ? q.iou : q.centre;
      std::vector<char> used(f.detections.size(), 0);     // matched to a counted target
      std::vector<char> ignored(f.detections.size(), 0);  // matched to a "don't care" one
      for (size_t t = 0; t < f.truth.size(); ++t) {
        const DetectionTruth& truth = f.truth[t];
        const bool care = Counted(truth, options);
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
  q.precision_recall = ComputePrecisionRecall(frames, options);
  if (options.min_visible >= kMostlyVisible) {
    q.iou_mostly_visible = q.iou;
    q.precision_recall_mostly_visible = q.precision_recall;
    return q;
  }
  // The subset's curve, drawn again with its "don't care" (its counts are
  // above).
  q.precision_recall_mostly_visible = ComputePrecisionRecall(frames, mostly);
  return q;
}

}  // namespace hcpf::metrics
