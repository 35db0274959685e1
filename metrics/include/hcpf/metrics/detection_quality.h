#pragma once
// Detection quality against pixel-exact truth: how well a detector's boxes
// find the targets, frame by frame, before any tracking. Precision, recall
// and F1 under two matching rules (IoU >= 0.5, and the detection's centre
// within half the target's box), the localisation error of the matches, and
// the same counts binned by the target's apparent size, visible fraction and
// truncation by the image border.

#include <optional>
#include <span>
#include <vector>

#include "hcpf/core/types.h"

namespace hcpf::metrics {

// One target in one frame, as the ground truth sees it.
struct DetectionTruth {
  ObjectId target{};
  BoxPx box;                      // the target's box clipped to the image, px
  double visible_fraction = 1.0;  // of the unoccluded target inside the image
  // The fraction of the target's amodal box outside the image (KITTI's
  // truncation): a target entering across the border is fully "visible" by
  // visible_fraction while most of it is not yet in the image.
  double truncation = 0.0;
};

struct DetectionFrame {
  std::vector<DetectionTruth> truth;
  std::vector<Detection> detections;
};

struct DetectionQualityOptions {
  double iou_threshold = 0.5;
  // Targets less visible than this are "don't care": not missed when no
  // detection finds them, and a detection on one is neither true nor false.
  double min_visible = 0.1;
};

struct DetectionCounts {
  int64_t tp = 0, fp = 0, fn = 0;
  // NaN when undefined (no detection / no target).
  double precision() const;
  double recall() const;
  double f1() const;
};

// How well a target-specific detector's labels (Detection::target) name the
// target under each box, apart from where its boxes are: the IoU matching done
// again with every label ignored, and of the labelled detections it matches
// to a counted target, how many name that target. A box on the right place
// with the wrong label is a false detection and a miss in `iou`; here it is
// matched and wrong.
struct LabelCounts {
  int64_t matched = 0;      // labelled detections matched to a counted target, labels ignored
  int64_t right = 0;        // of them, those whose label is that target
  double accuracy() const;  // right / matched; NaN when none matched
};

// One target's record over the frames it is counted in (visible at least
// min_visible): its counts under both rules, and the frames (indices into
// ScoreDetections' frames, increasing) where the IoU rule found it and where
// it did not. Frames where the target is absent or "don't care" are in
// neither list.
struct TargetDetections {
  ObjectId target{};
  int64_t found = 0, missed = 0;                // IoU rule: tp and fn
  int64_t found_centre = 0, missed_centre = 0;  // centre rule
  std::vector<int> found_frames;
  std::vector<int> missed_frames;
  double recall() const;         // IoU rule; NaN when never counted
  double recall_centre() const;  // centre rule
};

// Counts of the targets (and, by size, of the detections) in [lo, hi).
struct DetectionBin {
  double lo = 0.0, hi = 0.0;
  DetectionCounts iou;
  DetectionCounts centre;
};

// One point of the interpolated precision-recall curve (IoU rule): the best
// precision any score threshold reaches at recall >= `recall`, and the
// threshold that reaches it (report the detections scoring at least
// `min_score`). Past the curve's largest recall: precision 0, min_score NaN.
struct PrecisionAtRecall {
  double recall = 0.0;
  double precision = 0.0;
  double min_score = 0.0;
};

// Average precision at IoU >= iou_threshold over the whole sequence, COCO's
// way: detections ranked by score (every frame together; equal scores form
// one threshold), each matched greedily to the unmatched compatible target it
// overlaps most (a counted one first; one on a "don't care" target is
// ignored), precision made monotone from the right and read at the 101
// recalls 0, 0.01, ..., 1. Only the detections the detector reported are
// ranked: a detector that drops low-score detections has a curve that ends
// at its recall.
struct PrecisionRecall {
  double average_precision = 0.0;        // mean of the 101 precisions; NaN without targets
  std::vector<PrecisionAtRecall> curve;  // 101 points; empty without targets
  // The score threshold of the best F1 on the (uninterpolated) curve, and its
  // precision and recall; all NaN when no detection matches.
  double best_f1 = 0.0, best_f1_precision = 0.0, best_f1_recall = 0.0, best_f1_min_score = 0.0;
};

struct DetectionQuality {
  DetectionCounts iou;     // matched when IoU >= iou_threshold
  DetectionCounts centre;  // matched when the centre lies within half the box of the target
  double mean_centre_error_px = 0.0;  // IoU matches: detection centre to target centre
  double mean_iou = 0.0;              // IoU matches
  // Median size (sqrt of the box area, px) of the counted targets: the
  // apparent target size the counts are about (NaN without targets).
  double median_size_px = 0.0;
  // Size: sqrt(box area) in px, bins [0, 8), [8, 16), [16, 32), [32, 64),
  // [64, inf); a false detection counts in its own box's bin. Visibility:
  // [0, 0.25), [0.25, 0.5), [0.5, 0.75), [0.75, 1]; false detections have no
  // visibility, so these bins give recall only (fp = 0). Truncation: [0,
  // 0.15), [0.15, 0.3), [0.3, 0.5), [0.5, 1] (KITTI's limits for its easy,
  // moderate and hard targets), recall only as well.
  std::vector<DetectionBin> by_size;
  std::vector<DetectionBin> by_visibility;
  std::vector<DetectionBin> by_truncation;
  // Per target, in increasing target id: every target that appears in any
  // frame, with or without counted frames (a target only ever "don't care"
  // has zero counts and empty frame lists).
  std::vector<TargetDetections> by_target;
  PrecisionRecall precision_recall;  // IoU rule, every score threshold
  // The mostly visible targets alone, the way COCO scores a subset: targets
  // visible at least kMostlyVisible are counted and the less visible ones are
  // "don't care" too, so a detection on one of them is neither true nor
  // false. The visibility bin [0.75, 1] gives this subset's recall only (a
  // false detection has no visibility); here it has a precision as well.
  // IoU rule; the same as `iou` and `precision_recall` when min_visible is
  // already at least kMostlyVisible. Each frame is matched again for it: in
  // the matching over every counted target, a less visible target may take
  // the detection of a mostly visible one it overlaps, which the subset
  // counts as found (so its tp and fn can differ from the last bin's).
  DetectionCounts iou_mostly_visible;
  PrecisionRecall precision_recall_mostly_visible;
  // Absent when no detection carries a label (the oracle, a model-free
  // detector, an unlabelled file).
  std::optional<LabelCounts> labels;
};

// The visible fraction from which a target counts as mostly visible: the
// lower edge of the last visibility bin.
inline constexpr double kMostlyVisible = 0.75;

// Matching, per frame and rule: a one-to-one assignment (core/assignment.h)
// maximising the total IoU (IoU rule) or minimising the total normalised
// centre distance (centre rule) over the pairs the rule allows. A detection
// that carries Detection::target (a target-specific detector) may only match
// that target. The precision-recall curve matches greedily by score instead
// (PrecisionRecall), so its last point can differ from `iou` where the two
// matchings disagree (overlapping targets).
DetectionQuality ScoreDetections(std::span<const DetectionFrame> frames,
                                 const DetectionQualityOptions& options = {});

}  // namespace hcpf::metrics
