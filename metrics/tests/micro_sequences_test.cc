// Hand-made micro-sequences in metrics/tests/data/ (MOT15 layout, boxes 10x10
// unless stated), one per event type and edge case. Every expected value is
// worked out by hand in the comment above its test, from the rules in
// docs/metrics.md, never produced by the code under test.

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <string>

#include "hcpf/metrics/mot_io.h"
#include "hcpf/metrics/mot_metrics.h"

namespace hcpf::metrics {
namespace {

constexpr double kTol = 1e-12;  // hand values are exact fractions; only rounding differs

std::string DataPath(const std::string& name) {
  return std::string(HCPF_SOURCE_DIR) + "/metrics/tests/data/" + name;
}

MotSummary Score(const std::string& stem, int seq_length, std::vector<MotEvent>* events = nullptr) {
  const MotFile gt = ReadMotFile(DataPath(stem + "_gt.txt"), MotFileKind::kGroundTruth, seq_length);
  const MotFile hyp = ReadMotFile(DataPath(stem + "_hyp.txt"), MotFileKind::kTracks, seq_length);
  return ComputeAll(BuildSequence(gt, hyp, seq_length, Benchmark::kMot15, {}, stem), events);
}

// switch: gt 1 on the same box in frames 1-3; hyp 10 covers it in 1-2, hyp 11 in 3.
// CLEAR: TP 3, FP 0, FN 0; frame 3 gt 1 was last matched to 10 -> IDSW 1 (SWITCH),
//   and 11 was never matched before -> ASCEND. MOTA = (3-0-1)/3 = 2/3, MOTP = 1.
//   Matched 3/3 frames -> MT 1; one matched run -> Frag 0.
// Identity: n(1,10) = 2, n(1,11) = 1 -> IDTP 2, IDFN 1, IDFP 1, IDF1 = 4/6.
// HOTA: one pair per frame with S = 1, sim_iou = 1/(1+1-1) = 1; P(1,10) = 2, P(1,11) = 1;
//   every alpha: TP 3 -> DetA 1; C(1,10) = 2, C(1,11) = 1, Ng = 3, N10 = 2, N11 = 1:
//   AssA = (2 * 2/(3+2-2) + 1 * 1/(3+1-1)) / 3 = (4/3 + 1/3)/3 = 5/9; HOTA = sqrt(5/9); LocA 1.
void ExpectSwitchValues(const MotSummary& s) {
  EXPECT_EQ(s.clear.tp, 3);
  EXPECT_EQ(s.clear.fp, 0);
  EXPECT_EQ(s.clear.fn, 0);
  EXPECT_EQ(s.clear.idsw, 1);
  EXPECT_EQ(s.clear.frag, 0);
  EXPECT_EQ(s.clear.mt, 1);
  EXPECT_NEAR(s.clear.mota, 2.0 / 3.0, kTol);
  EXPECT_NEAR(s.clear.motp, 1.0, kTol);
  EXPECT_EQ(s.identity.idtp, 2);
  EXPECT_EQ(s.identity.idfn, 1);
  EXPECT_EQ(s.identity.idfp, 1);
  EXPECT_NEAR(s.identity.idf1, 2.0 / 3.0, kTol);
  EXPECT_NEAR(s.hota.deta_mean, 1.0, kTol);
  EXPECT_NEAR(s.hota.assa_mean, 5.0 / 9.0, kTol);
  EXPECT_NEAR(s.hota.hota_mean, std::sqrt(5.0 / 9.0), kTol);
  EXPECT_NEAR(s.hota.loca_mean, 1.0, kTol);
}

TEST(MicroSequences, SwitchAndAscend) {
  std::vector<MotEvent> events;
  const MotSummary s = Score("switch", 3, &events);
  ExpectSwitchValues(s);
  const std::vector<MotEvent> expected = {
      {1, MotEventType::kMatch, 1, 10, 1.0},
      {2, MotEventType::kMatch, 1, 10, 1.0},
      {3, MotEventType::kSwitch, 1, 11, 1.0},
      {3, MotEventType::kAscend, 1, 11, 1.0},
  };
  EXPECT_EQ(events, expected);
}

// unsorted: the switch sequence with rows shuffled (and a blank line): same values.
TEST(MicroSequences, UnsortedRowsGiveTheSameResult) { ExpectSwitchValues(Score("unsorted", 3)); }

// transfer: frame 1 gt 1 with hyp 10; frame 2 gt 1 gone, new gt 2 elsewhere with hyp 10.
// Events: f1 MATCH(1,10); f2 MATCH(2,10) (gt 2 never matched: no switch), TRANSFER (hyp 10
//   was last on gt 1), MIGRATE (gt 2 never matched before). TP 2, IDSW 0, MOTA 1.
// Identity: n(1,10) = n(2,10) = 1 -> IDTP 1, IDF1 = 2*1/(2+2) = 0.5.
// HOTA: Ng1 = Ng2 = 1, N10 = 2, C = 1 each: AssA = (1*1/(1+2-1) + 1*1/2)/2 = 0.5,
//   DetA 1, HOTA = sqrt(0.5).
TEST(MicroSequences, TransferAndMigrate) {
  std::vector<MotEvent> events;
  const MotSummary s = Score("transfer", 2, &events);
  const std::vector<MotEvent> expected = {
      {1, MotEventType::kMatch, 1, 10, 1.0},
      {2, MotEventType::kMatch, 2, 10, 1.0},
      {2, MotEventType::kTransfer, 2, 10, 1.0},
      {2, MotEventType::kMigrate, 2, 10, 1.0},
  };
  EXPECT_EQ(events, expected);
  EXPECT_EQ(s.clear.tp, 2);
  EXPECT_EQ(s.clear.idsw, 0);
  EXPECT_NEAR(s.clear.mota, 1.0, kTol);
  EXPECT_EQ(s.identity.idtp, 1);
  EXPECT_NEAR(s.identity.idf1, 0.5, kTol);
  EXPECT_NEAR(s.hota.assa_mean, 0.5, kTol);
  EXPECT_NEAR(s.hota.hota_mean, std::sqrt(0.5), kTol);
}

// fp_miss: gt 1 at (1,1), hyp 10 at (201,201): IoU 0. MISS + FP; TP 0, FN 1, FP 1,
// MOTA = (0-1-0)/1 = -1, MOTP 0 and MOTP_distance 0 (no match), IDF1 0, HOTA 0,
// LocA 1 (TrackEval's max(1e-10, 0)/max(1e-10, 0)), ML 1.
TEST(MicroSequences, FalsePositiveAndMiss) {
  std::vector<MotEvent> events;
  const MotSummary s = Score("fp_miss", 1, &events);
  const std::vector<MotEvent> expected = {
      {1, MotEventType::kMiss, 1, -1, 0.0},
      {1, MotEventType::kFp, -1, 10, 0.0},
  };
  EXPECT_EQ(events, expected);
  EXPECT_EQ(s.clear.tp, 0);
  EXPECT_EQ(s.clear.fn, 1);
  EXPECT_EQ(s.clear.fp, 1);
  EXPECT_EQ(s.clear.ml, 1);
  EXPECT_NEAR(s.clear.mota, -1.0, kTol);
  EXPECT_EQ(s.clear.motp, 0.0);
  EXPECT_EQ(s.clear.motp_distance, 0.0);
  EXPECT_EQ(s.identity.idf1, 0.0);
  EXPECT_EQ(s.hota.hota_mean, 0.0);
  EXPECT_NEAR(s.hota.loca_mean, 1.0, kTol);
}

// empty_gt: no gt, hyp 10 in frames 1-2. FP 2; TrackEval's convention: MOTA 0 (not -2),
// every ratio 0; IDFP 2, IDF1 0; HOTA_FP 2 at every alpha, HOTA 0, LocA 1.
TEST(MicroSequences, EmptyGroundTruth) {
  const MotSummary s = Score("empty_gt", 2);
  EXPECT_EQ(s.num_objects, 0);
  EXPECT_EQ(s.num_predictions, 2);
  EXPECT_EQ(s.clear.fp, 2);
  EXPECT_EQ(s.clear.mota, 0.0);
  EXPECT_EQ(s.clear.precision, 0.0);
  EXPECT_EQ(s.identity.idfp, 2);
  EXPECT_EQ(s.identity.idf1, 0.0);
  for (int a = 0; a < kNumHotaAlphas; ++a) EXPECT_EQ(s.hota.fp[a], 2);
  EXPECT_EQ(s.hota.hota_mean, 0.0);
  EXPECT_NEAR(s.hota.loca_mean, 1.0, kTol);
}

// empty_hyp: gt 1 in frames 1-2, no hyp. FN 2, ML 1 (ratio 0 < 0.2), MOTA 0, recall 0,
// IDFN 2, HOTA_FN 2 at every alpha, HOTA 0, LocA 1.
TEST(MicroSequences, EmptyHypothesis) {
  const MotSummary s = Score("empty_hyp", 2);
  EXPECT_EQ(s.clear.fn, 2);
  EXPECT_EQ(s.clear.ml, 1);
  EXPECT_EQ(s.clear.mt, 0);
  EXPECT_EQ(s.clear.mota, 0.0);
  EXPECT_EQ(s.clear.recall, 0.0);
  EXPECT_EQ(s.identity.idfn, 2);
  for (int a = 0; a < kNumHotaAlphas; ++a) EXPECT_EQ(s.hota.fn[a], 2);
  EXPECT_EQ(s.hota.hota_mean, 0.0);
  EXPECT_NEAR(s.hota.loca_mean, 1.0, kTol);
}

// huge_ids: gt ids 0, 2^53+1, 2^53 (distinct only if read as integers, not doubles);
// hyp ids 0, 4e9, 4e9+1 (beyond int32). Three disjoint perfect pairs in frames 1-2:
// TP 6, IDSW 0, MOTA 1, 3 gt ids, 3 tracker ids, IDF1 1, HOTA 1.
TEST(MicroSequences, IdZeroAndHugeIds) {
  std::vector<MotEvent> events;
  const MotSummary s = Score("huge_ids", 2, &events);
  EXPECT_EQ(s.num_gt_ids, 3);
  EXPECT_EQ(s.num_tracker_ids, 3);
  EXPECT_EQ(s.clear.tp, 6);
  EXPECT_EQ(s.clear.idsw, 0);
  EXPECT_NEAR(s.clear.mota, 1.0, kTol);
  EXPECT_NEAR(s.identity.idf1, 1.0, kTol);
  EXPECT_NEAR(s.hota.hota_mean, 1.0, kTol);
  ASSERT_EQ(events.size(), 6u);
  EXPECT_EQ(events[1].gt, int64_t{9007199254740993});
  EXPECT_EQ(events[1].hyp, int64_t{4000000000});
}

// iou_half: gt 1 (1,1,10,10) vs hyp 10 (1,1,10,5): inter 50, union 100 -> IoU exactly 0.5,
// a match. gt 2 (101,1,10,10) vs hyp 20 (101,1,10,4.9): IoU 0.49, no match.
// CLEAR: TP 1, FN 1, FP 1, MOTA 0, MOTP 0.5. Identity: IDTP 1, IDF1 = 2/(2+2) = 0.5.
// HOTA (one frame, both pairs assigned): alphas 0.05..0.45 (9 of them): TP 2, DetA 1,
// AssA 1 (C = Ng = Nh = 1); alpha 0.5: TP 1 (0.5 >= 0.5 - eps), DetA 1/3, AssA 1,
// HOTA sqrt(1/3); alphas 0.55..0.95: TP 0, HOTA 0. HOTA = (9 + sqrt(1/3)) / 19.
TEST(MicroSequences, IouExactlyHalfMatches) {
  const MotSummary s = Score("iou_half", 1);
  EXPECT_EQ(s.clear.tp, 1);
  EXPECT_EQ(s.clear.fn, 1);
  EXPECT_EQ(s.clear.fp, 1);
  EXPECT_NEAR(s.clear.mota, 0.0, kTol);
  EXPECT_NEAR(s.clear.motp, 0.5, kTol);
  EXPECT_EQ(s.identity.idtp, 1);
  EXPECT_NEAR(s.identity.idf1, 0.5, kTol);
  for (int a = 0; a < 9; ++a) EXPECT_EQ(s.hota.tp[a], 2) << a;
  EXPECT_EQ(s.hota.tp[9], 1);
  for (int a = 10; a < kNumHotaAlphas; ++a) EXPECT_EQ(s.hota.tp[a], 0) << a;
  EXPECT_NEAR(s.hota.deta[9], 1.0 / 3.0, kTol);
  EXPECT_NEAR(s.hota.hota_mean, (9.0 + std::sqrt(1.0 / 3.0)) / 19.0, kTol);
}

// frag: gt 1 in frames 1-5; hyp 10 on it in 1, 2, 4, 5 and far away in 3 (FP + MISS,
// so frame 3 is evaluated and breaks the run). Matched runs {1,2}, {4,5}: Frag 1.
// Tracked ratio 4/5 = 0.8 is not > 0.8: PT 1, MT 0. TP 4, FN 1, FP 1, IDSW 0,
// MOTA = (4-1-0)/5 = 0.6. Identity n = 4: IDF1 = 8/10.
// HOTA: P = 4, Ng = Nh = 5, every alpha TP 4, FN 1, FP 1: DetA = 4/6,
// AssA = 4 * (4/(5+5-4)) / 4 = 4/6, HOTA = 4/6.
TEST(MicroSequences, FragmentationAndStrictMostlyTracked) {
  const MotSummary s = Score("frag", 5);
  EXPECT_EQ(s.clear.frag, 1);
  EXPECT_EQ(s.clear.mt, 0);
  EXPECT_EQ(s.clear.pt, 1);
  EXPECT_EQ(s.clear.ml, 0);
  EXPECT_EQ(s.clear.tp, 4);
  EXPECT_NEAR(s.clear.mota, 0.6, kTol);
  EXPECT_NEAR(s.identity.idf1, 0.8, kTol);
  EXPECT_NEAR(s.hota.deta_mean, 4.0 / 6.0, kTol);
  EXPECT_NEAR(s.hota.hota_mean, 4.0 / 6.0, kTol);
}

// TrackEval quirk, in memory: a frame with no hypothesis at all is skipped without
// resetting the continuity, so the same sequence as `frag` but with frame 3 empty on
// the hypothesis side has Frag 0 (FN 1, FP 0).
TEST(MicroSequences, FrameWithoutHypothesesKeepsContinuity) {
  Sequence seq;
  seq.frames.resize(5);
  for (int t = 0; t < 5; ++t) {
    seq.frames[t].gt.push_back({1, {1, 1, 10, 10}});
    if (t != 2) seq.frames[t].hyp.push_back({10, {1, 1, 10, 10}});
  }
  const ClearMetrics c = ComputeClear(seq);
  EXPECT_EQ(c.frag, 0);
  EXPECT_EQ(c.fn, 1);
  EXPECT_EQ(c.fp, 0);
}

TEST(MicroSequences, EventsAsJsonLines) {
  std::vector<MotEvent> events = {{3, MotEventType::kSwitch, 1, 11, 0.5},
                                  {4, MotEventType::kFp, -1, 7, 0.0}};
  std::ostringstream out;
  WriteEventsJsonLines(out, events);
  EXPECT_EQ(out.str(),
            "{\"frame\":3,\"type\":\"SWITCH\",\"gt\":1,\"hyp\":11,\"iou\":0.5}\n"
            "{\"frame\":4,\"type\":\"FP\",\"gt\":-1,\"hyp\":7,\"iou\":0}\n");
}

}  // namespace
}  // namespace hcpf::metrics
