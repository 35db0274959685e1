// Detection quality on hand-made frames; every expected value is derived in
// the comments.

#include "hcpf/metrics/detection_quality.h"

#include <gtest/gtest.h>

#include <cmath>

namespace hcpf::metrics {
namespace {

Detection Det(double x, double y, double w, double h) { return {.box = BoxPx{x, y, w, h}}; }

// Frame 1: A (id 1) at (0,0,10,10), visible 1.0; B (id 2) at (100,100,20,20),
// visible 0.5; C (id 3) at (200,0,10,10), visible 0.05 (below min_visible
// 0.1: "don't care").
//   d0 (1,0,10,10) on A: overlap 9x10 = 90, union 110, IoU 0.818; centre
//      offset (1, 0) within (5, 5): a match under both rules.
//   d1 (105,100,20,20) on B: overlap 15x20 = 300, union 500, IoU 0.6; centre
//      offset (5, 0) within (10, 10): both rules.
//   d2 on C: ignored (neither true nor false).
//   d3 (300,300,10,10): false under both rules.
// Frame 2: A again; d0 (4,0,10,10): overlap 60, union 140, IoU 0.43 < 0.5:
//   under IoU a miss (fn) and a false detection (fp); its centre offset
//   (4, 0) lies within (5, 5): a match under the centre rule.
// IoU: tp 2, fp 2, fn 1 -> precision 0.5, recall 2/3, F1 4/7.
// Centre: tp 3, fp 1, fn 0 -> precision 0.75, recall 1, F1 6/7.
// IoU matches: centre errors 1 and 5 px (mean 3); IoU (90/110 + 0.6) / 2.
std::vector<DetectionFrame> HandFrames() {
  DetectionFrame f1;
  f1.truth = {{ObjectId{1}, BoxPx{0, 0, 10, 10}, 1.0},
              {ObjectId{2}, BoxPx{100, 100, 20, 20}, 0.5},
              {ObjectId{3}, BoxPx{200, 0, 10, 10}, 0.05}};
  f1.detections = {Det(1, 0, 10, 10), Det(105, 100, 20, 20), Det(200, 0, 10, 10),
                   Det(300, 300, 10, 10)};
  DetectionFrame f2;
  f2.truth = {{ObjectId{1}, BoxPx{0, 0, 10, 10}, 1.0}};
  f2.detections = {Det(4, 0, 10, 10)};
  return {f1, f2};
}

TEST(DetectionQuality, HandCountedFrames) {
  const DetectionQuality q = ScoreDetections(HandFrames());
  EXPECT_EQ(q.iou.tp, 2);
  EXPECT_EQ(q.iou.fp, 2);
  EXPECT_EQ(q.iou.fn, 1);
  EXPECT_DOUBLE_EQ(q.iou.precision(), 0.5);
  EXPECT_DOUBLE_EQ(q.iou.recall(), 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(q.iou.f1(), 4.0 / 7.0);
  EXPECT_EQ(q.centre.tp, 3);
  EXPECT_EQ(q.centre.fp, 1);
  EXPECT_EQ(q.centre.fn, 0);
  EXPECT_DOUBLE_EQ(q.centre.f1(), 6.0 / 7.0);
  EXPECT_DOUBLE_EQ(q.mean_centre_error_px, 3.0);
  EXPECT_NEAR(q.mean_iou, (90.0 / 110.0 + 0.6) / 2.0, 1e-12);
  // Counted targets: A (10 px) twice and B (20 px); C is "don't care". The
  // sizes 10, 10, 20 have median 10.
  EXPECT_DOUBLE_EQ(q.median_size_px, 10.0);
}

// Bins: A is 10 px (sqrt of its area) -> [8, 16); B 20 px -> [16, 32); the
// false detections (d3 and frame 2's d0 under IoU) are 10 px -> [8, 16).
// Visibility: A 1.0 -> [0.75, 1]; B 0.5 -> [0.5, 0.75); no fp there.
TEST(DetectionQuality, BinnedBySizeAndVisibility) {
  const DetectionQuality q = ScoreDetections(HandFrames());
  ASSERT_EQ(q.by_size.size(), 5u);
  EXPECT_EQ(q.by_size[1].lo, 8.0);
  EXPECT_EQ(q.by_size[1].iou.tp, 1);
  EXPECT_EQ(q.by_size[1].iou.fn, 1);
  EXPECT_EQ(q.by_size[1].iou.fp, 2);
  EXPECT_EQ(q.by_size[2].iou.tp, 1);
  EXPECT_EQ(q.by_size[2].iou.fp, 0);
  EXPECT_EQ(q.by_size[0].iou.tp + q.by_size[0].iou.fn + q.by_size[0].iou.fp, 0);
  EXPECT_TRUE(std::isinf(q.by_size[4].hi));
  ASSERT_EQ(q.by_visibility.size(), 4u);
  EXPECT_EQ(q.by_visibility[3].hi, 1.0);
  EXPECT_EQ(q.by_visibility[3].iou.tp, 1);
  EXPECT_EQ(q.by_visibility[3].iou.fn, 1);
  EXPECT_EQ(q.by_visibility[2].iou.tp, 1);
  for (const DetectionBin& b : q.by_visibility) EXPECT_EQ(b.iou.fp, 0);
}

// Truncation bins [0, 0.15), [0.15, 0.3), [0.3, 0.5), [0.5, 1]: the hand
// frames' targets are all untruncated, so their counts (IoU: tp 2, fn 1) are
// all in the first bin. Here A is truncated 0.6 (-> [0.5, 1]) and found, B
// 0.2 (-> [0.15, 0.3)) and missed, C 0.3 (-> [0.3, 0.5), the lower edge
// belongs to the bin) and found; the false detection counts in none.
TEST(DetectionQuality, BinnedByTruncation) {
  const DetectionQuality hand = ScoreDetections(HandFrames());
  ASSERT_EQ(hand.by_truncation.size(), 4u);
  EXPECT_EQ(hand.by_truncation[0].iou.tp, 2);
  EXPECT_EQ(hand.by_truncation[0].iou.fn, 1);
  EXPECT_EQ(hand.by_truncation[0].iou.fp, 0);
  EXPECT_EQ(hand.by_truncation[3].hi, 1.0);

  DetectionFrame f;
  f.truth = {{ObjectId{1}, BoxPx{0, 0, 10, 10}, 1.0, 0.6},
             {ObjectId{2}, BoxPx{100, 100, 20, 20}, 1.0, 0.2},
             {ObjectId{3}, BoxPx{200, 0, 10, 10}, 1.0, 0.3}};
  f.detections = {Det(0, 0, 10, 10), Det(200, 0, 10, 10), Det(400, 400, 10, 10)};
  const DetectionQuality q = ScoreDetections(std::vector<DetectionFrame>{f});
  EXPECT_EQ(q.by_truncation[0].iou.tp + q.by_truncation[0].iou.fn, 0);
  EXPECT_EQ(q.by_truncation[1].iou.tp, 0);
  EXPECT_EQ(q.by_truncation[1].iou.fn, 1);
  EXPECT_EQ(q.by_truncation[2].iou.tp, 1);
  EXPECT_EQ(q.by_truncation[3].iou.tp, 1);
  for (const DetectionBin& b : q.by_truncation) EXPECT_EQ(b.iou.fp, 0);
  EXPECT_EQ(q.iou.fp, 1);
}

// A target-specific detection matches only its own target: labelled 2 on A
// (target 1), it is a miss and a false detection, though it covers A exactly.
TEST(DetectionQuality, TargetSpecificDetectionsMatchOnlyTheirTarget) {
  DetectionFrame f;
  f.truth = {{ObjectId{1}, BoxPx{0, 0, 10, 10}, 1.0}};
  Detection d = Det(0, 0, 10, 10);
  d.target = ObjectId{2};
  f.detections = {d};
  DetectionQuality q = ScoreDetections(std::vector<DetectionFrame>{f});
  EXPECT_EQ(q.iou.tp, 0);
  EXPECT_EQ(q.iou.fp, 1);
  EXPECT_EQ(q.iou.fn, 1);
  f.detections[0].target = ObjectId{1};
  q = ScoreDetections(std::vector<DetectionFrame>{f});
  EXPECT_EQ(q.iou.tp, 1);
  EXPECT_DOUBLE_EQ(q.mean_iou, 1.0);
}

// Label accuracy: the IoU matching with the labels ignored. Frame 1: A (id 1)
// and B (id 2) side by side, far apart; d0 exactly on A labelled 2 (a false
// detection and a miss in `iou`, matched and wrong here), d1 on B labelled 2
// (right), d2 on C (id 3, visible 0.05: "don't care") labelled 1 (not
// counted), d3 on nothing labelled 1 (not matched), d4 unlabelled on A's
// twin D (id 4) (not a labelled detection). So 2 matched, 1 right.
TEST(DetectionQuality, LabelAccuracyCountsTheLabelsOfBoxesOnTargets) {
  DetectionFrame f;
  f.truth = {{ObjectId{1}, BoxPx{0, 0, 10, 10}, 1.0},
             {ObjectId{2}, BoxPx{100, 0, 10, 10}, 1.0},
             {ObjectId{3}, BoxPx{200, 0, 10, 10}, 0.05},
             {ObjectId{4}, BoxPx{0, 100, 10, 10}, 1.0}};
  const auto labelled = [](double x, double y, int target) {
    Detection d = Det(x, y, 10, 10);
    d.target = ObjectId{target};
    return d;
  };
  f.detections = {labelled(0, 0, 2), labelled(100, 0, 2), labelled(200, 0, 1),
                  labelled(300, 300, 1), Det(0, 100, 10, 10)};
  const DetectionQuality q = ScoreDetections(std::vector<DetectionFrame>{f});
  ASSERT_TRUE(q.labels.has_value());
  EXPECT_EQ(q.labels->matched, 2);
  EXPECT_EQ(q.labels->right, 1);
  EXPECT_DOUBLE_EQ(q.labels->accuracy(), 0.5);
  // The counts themselves keep the labels: d0 false and A missed; d2 false
  // too, its label forbids it C, so it is not on a "don't care" target.
  EXPECT_EQ(q.iou.tp, 2);  // B and D
  EXPECT_EQ(q.iou.fn, 1);  // A
  EXPECT_EQ(q.iou.fp, 3);  // d0, d2 and d3
  // Labelled detections that match nothing: measured, undefined accuracy.
  DetectionFrame g;
  g.truth = {{ObjectId{1}, BoxPx{0, 0, 10, 10}, 1.0}};
  g.detections = {labelled(300, 300, 1)};
  const DetectionQuality none = ScoreDetections(std::vector<DetectionFrame>{g});
  ASSERT_TRUE(none.labels.has_value());
  EXPECT_EQ(none.labels->matched, 0);
  EXPECT_TRUE(std::isnan(none.labels->accuracy()));
  // No labelled detection anywhere: nothing measured.
  EXPECT_FALSE(ScoreDetections(HandFrames()).labels.has_value());
}

// One detection between two targets goes to the better match, and counts once.
TEST(DetectionQuality, OneToOneAssignment) {
  DetectionFrame f;
  f.truth = {{ObjectId{1}, BoxPx{0, 0, 10, 10}, 1.0}, {ObjectId{2}, BoxPx{3, 0, 10, 10}, 1.0}};
  f.detections = {Det(2, 0, 10, 10)};  // IoU 80/120 with 1, 90/110 with 2
  const DetectionQuality q = ScoreDetections(std::vector<DetectionFrame>{f});
  EXPECT_EQ(q.iou.tp, 1);
  EXPECT_EQ(q.iou.fn, 1);
  EXPECT_EQ(q.iou.fp, 0);
  EXPECT_NEAR(q.mean_iou, 90.0 / 110.0, 1e-12);
}

// A counted target is matched before a "don't care" one (COCO's rule, and
// the precision-recall curve's): A (visible 1.0) at (100,100,40,40), B
// (visible 0.05, don't care) at (104,100,40,40), one detection on B exactly.
// IoU with A: overlap 36 x 40 = 1440, union 1760, 0.818; with B 1.0. The
// detection is A's: tp 1, fn 0, fp 0 (it was B's, ignored, and A missed).
// The centre rule likewise: the detection's centre (124, 120) lies 4 px
// from A's, within (20, 20).
TEST(DetectionQuality, ACountedTargetIsMatchedBeforeADontCareOne) {
  DetectionFrame f;
  f.truth = {{ObjectId{1}, BoxPx{100, 100, 40, 40}, 1.0},
             {ObjectId{2}, BoxPx{104, 100, 40, 40}, 0.05}};
  f.detections = {Det(104, 100, 40, 40)};
  const DetectionQuality q = ScoreDetections(std::vector<DetectionFrame>{f});
  EXPECT_EQ(q.iou.tp, 1);
  EXPECT_EQ(q.iou.fn, 0);
  EXPECT_EQ(q.iou.fp, 0);
  EXPECT_NEAR(q.mean_iou, 1440.0 / 1760.0, 1e-12);
  EXPECT_EQ(q.centre.tp, 1);
  EXPECT_EQ(q.centre.fn, 0);
  EXPECT_EQ(q.centre.fp, 0);
  // With B moved clear of A, to (150,100,40,40), and a second detection on
  // it: the first is A's, the second B's, ignored (neither true nor false).
  f.truth[1].box = BoxPx{150, 100, 40, 40};
  f.detections.push_back(Det(150, 100, 40, 40));
  const DetectionQuality q2 = ScoreDetections(std::vector<DetectionFrame>{f});
  EXPECT_EQ(q2.iou.tp, 1);
  EXPECT_EQ(q2.iou.fn, 0);
  EXPECT_EQ(q2.iou.fp, 0);
}

// Per target, from the hand frames (comment above HandFrames) and a third
// frame where A is missed under both rules (no detection) and B found:
//   A: frame 0 found under both rules; frame 1 missed under IoU (0.43),
//      found under the centre rule; frame 2 missed under both. IoU 1 found,
//      2 missed (frames [0] and [1, 2]); centre 2 found, 1 missed.
//   B: frame 0 found (IoU 0.6), frame 1 absent, frame 2 found: IoU 2 found
//      (frames 0 and 2: two runs, not one), centre 2 found.
//   C: only "don't care" (visible 0.05): listed, with no counts.
// The sum over targets is the total: IoU tp 1 + 2 = 3 and fn 2.
TEST(DetectionQuality, PerTargetCountsAndFrames) {
  std::vector<DetectionFrame> frames = HandFrames();
  DetectionFrame f3;
  f3.truth = {{ObjectId{2}, BoxPx{100, 100, 20, 20}, 0.5}, {ObjectId{1}, BoxPx{0, 0, 10, 10}, 1.0}};
  f3.detections = {Det(100, 100, 20, 20)};
  frames.push_back(f3);
  const DetectionQuality q = ScoreDetections(frames);
  ASSERT_EQ(q.by_target.size(), 3u);
  const TargetDetections& a = q.by_target[0];
  const TargetDetections& b = q.by_target[1];
  const TargetDetections& c = q.by_target[2];
  EXPECT_EQ(a.target, ObjectId{1});
  EXPECT_EQ(b.target, ObjectId{2});
  EXPECT_EQ(c.target, ObjectId{3});
  EXPECT_EQ(a.found, 1);
  EXPECT_EQ(a.missed, 2);
  EXPECT_EQ(a.found_frames, std::vector<int>({0}));
  EXPECT_EQ(a.missed_frames, std::vector<int>({1, 2}));
  EXPECT_EQ(a.found_centre, 2);
  EXPECT_EQ(a.missed_centre, 1);
  EXPECT_DOUBLE_EQ(a.recall(), 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(a.recall_centre(), 2.0 / 3.0);
  EXPECT_EQ(b.found, 2);
  EXPECT_EQ(b.missed, 0);
  EXPECT_EQ(b.found_frames, std::vector<int>({0, 2}));
  EXPECT_TRUE(b.missed_frames.empty());
  EXPECT_EQ(b.found_centre, 2);
  EXPECT_EQ(c.found + c.missed + c.found_centre + c.missed_centre, 0);
  EXPECT_TRUE(std::isnan(c.recall()));
  EXPECT_EQ(a.found + b.found, q.iou.tp);
  EXPECT_EQ(a.missed + b.missed, q.iou.fn);
}

TEST(DetectionQuality, NoFramesGiveUndefinedRatios) {
  const DetectionQuality q = ScoreDetections({});
  EXPECT_TRUE(std::isnan(q.iou.precision()));
  EXPECT_TRUE(std::isnan(q.iou.recall()));
  EXPECT_TRUE(std::isnan(q.mean_iou));
  EXPECT_TRUE(std::isnan(q.median_size_px));
  EXPECT_TRUE(q.by_target.empty());
}

Detection Scored(double x, double y, double score) {
  Detection d = Det(x, y, 10, 10);
  d.score = score;
  return d;
}

// Ranking runs over every frame together. Target A (0,0,10,10) in three
// frames (3 positives); frame 0 has only a false detection (score 0.8),
// frames 1 and 2 an exact one (0.9 and 0.7). By score: 0.9 tp, 0.8 fp, 0.7
// tp -> (precision, recall) (1, 1/3), (1/2, 1/3), (2/3, 2/3). Monotone from
// the right: 1 up to recall 1/3 (the 34 levels 0..0.33, threshold 0.9), 2/3
// up to 2/3 (0.34..0.66: 33 levels, threshold 0.7), 0 beyond (34 levels).
// AP = (34 + 33 * 2/3) / 101 = 56/101. F1 = 2tp / (tp + fp + 3): 1/2, 2/5,
// 2/3 -> the best at threshold 0.7.
TEST(PrecisionRecall, RankedOverAllFrames) {
  const DetectionTruth a{ObjectId{1}, BoxPx{0, 0, 10, 10}, 1.0};
  std::vector<DetectionFrame> frames(3);
  for (DetectionFrame& f : frames) f.truth = {a};
  frames[0].detections = {Scored(300, 300, 0.8)};
  frames[1].detections = {Scored(0, 0, 0.9)};
  frames[2].detections = {Scored(0, 0, 0.7)};
  const PrecisionRecall pr = ScoreDetections(frames).precision_recall;
  ASSERT_EQ(pr.curve.size(), 101u);
  EXPECT_NEAR(pr.average_precision, 56.0 / 101.0, 1e-12);
  EXPECT_DOUBLE_EQ(pr.curve[0].precision, 1.0);
  EXPECT_DOUBLE_EQ(pr.curve[33].precision, 1.0);
  EXPECT_DOUBLE_EQ(pr.curve[33].min_score, 0.9);
  EXPECT_DOUBLE_EQ(pr.curve[34].precision, 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(pr.curve[66].precision, 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(pr.curve[66].min_score, 0.7);
  EXPECT_DOUBLE_EQ(pr.curve[67].precision, 0.0);
  EXPECT_TRUE(std::isnan(pr.curve[67].min_score));
  EXPECT_DOUBLE_EQ(pr.curve[100].recall, 1.0);
  EXPECT_NEAR(pr.best_f1, 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(pr.best_f1_precision, 2.0 / 3.0, 1e-12);
  EXPECT_NEAR(pr.best_f1_recall, 2.0 / 3.0, 1e-12);
  EXPECT_DOUBLE_EQ(pr.best_f1_min_score, 0.7);
}

// Equal scores are one threshold: a true and a false detection both at 0.5
// give one point (1/2, 1), AP 1/2. Taken one at a time in list order, the
// true one first, they would give (1, 1) and AP 1.
TEST(PrecisionRecall, EqualScoresAreOneThreshold) {
  DetectionFrame f;
  f.truth = {{ObjectId{1}, BoxPx{0, 0, 10, 10}, 1.0}};
  f.detections = {Scored(0, 0, 0.5), Scored(300, 300, 0.5)};
  const PrecisionRecall pr = ScoreDetections(std::vector<DetectionFrame>{f}).precision_recall;
  EXPECT_DOUBLE_EQ(pr.average_precision, 0.5);
  for (const PrecisionAtRecall& p : pr.curve) {
    EXPECT_DOUBLE_EQ(p.precision, 0.5);
    EXPECT_DOUBLE_EQ(p.min_score, 0.5);
  }
}

// Greedy by score, one match per target, "don't care" targets and target
// labels. A (id 1, 0,0,10,10) counted; C (id 3, 200,0,10,10) visible 0.05.
//   0.99 labelled target 2, exactly on A: matches nothing -> fp;
//   0.95 on C: ignored (neither true nor false);
//   0.9 on A shifted by 1 px (IoU 0.818) -> tp: the greedy match, although
//   0.6 exactly on A (IoU 1) would overlap more -> A is taken: fp.
// Points: (0, 0), (0, 0) after the ignored one, (1/2, 1), (1/3, 1); one
// positive. Every level reads the 0.9 point: AP 1/2, best F1 2/(1+1+1).
// The optimal matching of the counts gives A to the IoU-1 detection instead
// (tp 1, fp 2: the curve's last point, 1/3, is the same here).
TEST(PrecisionRecall, GreedyOneMatchPerTargetDontCareAndLabels) {
  DetectionFrame f;
  f.truth = {{ObjectId{1}, BoxPx{0, 0, 10, 10}, 1.0}, {ObjectId{3}, BoxPx{200, 0, 10, 10}, 0.05}};
  Detection labelled = Scored(0, 0, 0.99);
  labelled.target = ObjectId{2};
  f.detections = {Scored(0, 0, 0.6), Scored(1, 0, 0.9), Scored(200, 0, 0.95), labelled};
  const DetectionQuality q = ScoreDetections(std::vector<DetectionFrame>{f});
  const PrecisionRecall& pr = q.precision_recall;
  EXPECT_DOUBLE_EQ(pr.average_precision, 0.5);
  EXPECT_DOUBLE_EQ(pr.curve[0].min_score, 0.9);
  EXPECT_DOUBLE_EQ(pr.curve[100].min_score, 0.9);
  EXPECT_DOUBLE_EQ(pr.curve[100].precision, 0.5);
  EXPECT_NEAR(pr.best_f1, 2.0 / 3.0, 1e-12);
  EXPECT_DOUBLE_EQ(pr.best_f1_min_score, 0.9);
  EXPECT_EQ(q.iou.tp, 1);
  EXPECT_EQ(q.iou.fp, 2);
  EXPECT_NEAR(q.mean_iou, 1.0, 1e-12);
}

// The hand frames: every score 1, one threshold: tp 2, fp 2 (the ignored
// detection on C is neither), 3 positives -> (1/2, 2/3): 1/2 at the 67
// levels 0..0.66, AP 67 * 0.5 / 101; its F1 is the counts' 4/7.
TEST(PrecisionRecall, HandFramesAtOneThreshold) {
  const DetectionQuality q = ScoreDetections(HandFrames());
  EXPECT_NEAR(q.precision_recall.average_precision, 67 * 0.5 / 101, 1e-12);
  EXPECT_DOUBLE_EQ(q.precision_recall.curve[66].precision, 0.5);
  EXPECT_DOUBLE_EQ(q.precision_recall.curve[67].precision, 0.0);
  EXPECT_NEAR(q.precision_recall.best_f1, 4.0 / 7.0, 1e-12);
  EXPECT_NEAR(q.precision_recall.best_f1, q.iou.f1(), 1e-12);
}

// A half-visible target B overlapping a mostly visible A takes the one
// detection in the matching over both (IoU 9000/11000 = 0.818 against A's
// 7000/13000 = 0.538), so the visibility bin [0.75, 1] misses A. The subset
// counts A alone and B does not care, so A matches (0.538 >= 0.5): found,
// nothing false, as the subset's own curve has it. (Its counts were the
// bin's: tp 0, fn 1, beside an AP of 1.)
TEST(PrecisionRecall, MostlyVisibleSubsetIsMatchedWithItsOwnDontCare) {
  DetectionFrame f;
  f.truth = {{ObjectId{1}, BoxPx{100, 100, 100, 100}, 0.9},
             {ObjectId{2}, BoxPx{140, 100, 100, 100}, 0.5}};
  f.detections = {{.box = BoxPx{130, 100, 100, 100}, .score = 0.9}};
  const DetectionQuality q = ScoreDetections(std::vector<DetectionFrame>{f});
  EXPECT_EQ(q.by_visibility[3].iou.tp, 0);
  EXPECT_EQ(q.by_visibility[3].iou.fn, 1);
  EXPECT_EQ(q.iou_mostly_visible.tp, 1);
  EXPECT_EQ(q.iou_mostly_visible.fn, 0);
  EXPECT_EQ(q.iou_mostly_visible.fp, 0);
  EXPECT_DOUBLE_EQ(q.precision_recall_mostly_visible.average_precision, 1.0);
}

// A 0 x 0 truth box (valid in gt.json) with a detection centred on it: the
// centre rule's cost was 0 / 0 and the solver stopped the program
// (HCPF_CHECK, a review). A box of no size is matched by no rule, so it is
// missed; the other target is found by both.
TEST(ScoreDetections, ATruthBoxOfNoSizeIsMissedNotACrash) {
  DetectionFrame f;
  f.truth = {{ObjectId{1}, BoxPx{100, 100, 0, 0}, 1.0}, {ObjectId{2}, BoxPx{95, 95, 10, 10}, 1.0}};
  f.detections = {{.box = BoxPx{95, 95, 10, 10}, .score = 0.9},
                  {.box = BoxPx{96, 95, 10, 10}, .score = 0.8}};
  const DetectionQuality q = ScoreDetections(std::vector<DetectionFrame>{f});
  EXPECT_EQ(q.centre.tp, 1);
  EXPECT_EQ(q.centre.fn, 1);
  EXPECT_EQ(q.iou.tp, 1);
  EXPECT_EQ(q.iou.fn, 1);
}

// The mostly visible subset of the hand frames: A (visible 1.0) is counted,
// B (0.5) joins C as "don't care". Frame 1: d0 true on A, d1 on B and d2 on C
// ignored, d3 false; frame 2: A missed, d0 false. tp 1, fp 2, fn 1: precision
// 1/3 (the visibility bin [0.75, 1] has no precision: fp 0 there), recall
// 1/2, the bin's recall. One threshold (every score 0): AP = 51 levels
// (recall 0 .. 0.5) at 1/3, over 101.
TEST(PrecisionRecall, MostlyVisibleSubsetHasItsOwnPrecision) {
  const DetectionQuality q = ScoreDetections(HandFrames());
  EXPECT_EQ(q.iou_mostly_visible.tp, 1);
  EXPECT_EQ(q.iou_mostly_visible.fp, 2);
  EXPECT_EQ(q.iou_mostly_visible.fn, 1);
  EXPECT_NEAR(q.precision_recall_mostly_visible.average_precision, 51.0 / 3.0 / 101.0, 1e-12);
  EXPECT_NEAR(q.precision_recall_mostly_visible.best_f1, 2.0 / 5.0, 1e-12);  // 2/(1+2+2)
  // With min_visible already at 0.75 the subset is the whole.
  const DetectionQuality same = ScoreDetections(HandFrames(), {.min_visible = 0.8});
  EXPECT_EQ(same.iou_mostly_visible.tp, same.iou.tp);
  EXPECT_EQ(same.iou_mostly_visible.fp, same.iou.fp);
  EXPECT_EQ(same.precision_recall_mostly_visible.average_precision,
            same.precision_recall.average_precision);
}

// No detection: AP 0 and no operating point. No counted target: AP undefined.
TEST(PrecisionRecall, NoDetectionsOrNoTargets) {
  DetectionFrame f;
  f.truth = {{ObjectId{1}, BoxPx{0, 0, 10, 10}, 1.0}};
  PrecisionRecall pr = ScoreDetections(std::vector<DetectionFrame>{f}).precision_recall;
  EXPECT_EQ(pr.average_precision, 0.0);
  ASSERT_EQ(pr.curve.size(), 101u);
  EXPECT_TRUE(std::isnan(pr.curve[0].min_score));
  EXPECT_TRUE(std::isnan(pr.best_f1));
  f.truth[0].visible_fraction = 0.05;
  f.detections = {Scored(0, 0, 0.9)};
  pr = ScoreDetections(std::vector<DetectionFrame>{f}).precision_recall;
  EXPECT_TRUE(std::isnan(pr.average_precision));
  EXPECT_TRUE(pr.curve.empty());
  EXPECT_TRUE(std::isnan(pr.best_f1_min_score));
}

}  // namespace
}  // namespace hcpf::metrics
