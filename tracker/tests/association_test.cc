#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>

#include "hcpf/core/assignment.h"
#include "hcpf/core/rng.h"
#include "hcpf/tracker/associator.h"
#include "hcpf/tracker/hungarian.h"
#include "hcpf/tracker/interaction.h"

namespace hcpf::tracker {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Brute force over every partial injective row -> column map using finite
// entries only; best = most pairs, then least total cost.
void BruteForce(const std::vector<double>& cost, int rows, int cols, int row,
                std::vector<char>& used, int pairs, double total, int* best_pairs,
                double* best_total) {
  if (row == rows) {
    if (pairs > *best_pairs || (pairs == *best_pairs && total < *best_total)) {
      *best_pairs = pairs;
      *best_total = total;
    }
    return;
  }
  BruteForce(cost, rows, cols, row + 1, used, pairs, total, best_pairs, best_total);  // unassigned
  for (int c = 0; c < cols; ++c) {
    const double v = cost[static_cast<size_t>(row) * cols + c];
    if (used[c] || !std::isfinite(v)) continue;
    used[c] = 1;
    BruteForce(cost, rows, cols, row + 1, used, pairs + 1, total + v, best_pairs, best_total);
    used[c] = 0;
  }
}

TEST(SolveAssignment, MatchesBruteForceOnRandomSmallCases) {
  Rng rng(2024);
  for (int trial = 0; trial < 400; ++trial) {
    const int rows = 1 + static_cast<int>(rng.UniformInt(6));
    const int cols = 1 + static_cast<int>(rng.UniformInt(6));
    std::vector<double> cost(static_cast<size_t>(rows) * cols);
    for (double& c : cost) c = rng.Uniform() < 0.3 ? kInfinity : std::floor(rng.Uniform(0.0, 20.0));
    const std::vector<int> a = SolveAssignment(cost, rows, cols);
    ASSERT_EQ(a.size(), static_cast<size_t>(rows));
    std::vector<char> seen(static_cast<size_t>(cols), 0);
    int pairs = 0;
    double total = 0.0;
    for (int r = 0; r < rows; ++r) {
      if (a[r] < 0) continue;
      ASSERT_LT(a[r], cols);
      ASSERT_FALSE(seen[a[r]]) << "column used twice";
      seen[a[r]] = 1;
      const double v = cost[static_cast<size_t>(r) * cols + a[r]];
      ASSERT_TRUE(std::isfinite(v)) << "forbidden pair assigned";
      ++pairs;
      total += v;
    }
    std::vector<char> used(static_cast<size_t>(cols), 0);
    int best_pairs = -1;
    double best_total = kInfinity;
    BruteForce(cost, rows, cols, 0, used, 0, 0.0, &best_pairs, &best_total);
    EXPECT_EQ(pairs, best_pairs) << "trial " << trial;
    EXPECT_NEAR(total, best_total, 1e-9) << "trial " << trial;
  }
}

// Points gated as the M-of-N initiator gates them fall into many blocks (and,
// at this density, a few large ones): the block-by-block solution must pair
// as many rows and cost as little as one dense solve of the whole matrix with
// forbidden entries priced above any finite assignment (core/assignment.h,
// checked against scipy). Costs are integers so the totals compare exactly.
TEST(SolveAssignment, BlockByBlockEqualsOneDenseSolve) {
  Rng rng(77);
  for (int trial = 0; trial < 20; ++trial) {
    const int rows = 150 + static_cast<int>(rng.UniformInt(100));
    const int cols = 150 + static_cast<int>(rng.UniformInt(100));
    std::vector<double> x(static_cast<size_t>(rows + cols)), y(x.size());
    for (size_t k = 0; k < x.size(); ++k) {
      x[k] = std::floor(rng.Uniform(0.0, 320.0));
      y[k] = std::floor(rng.Uniform(0.0, 240.0));
    }
    std::vector<double> cost(static_cast<size_t>(rows) * cols, kInfinity);
    int finite = 0;
    for (int r = 0; r < rows; ++r) {
      for (int c = 0; c < cols; ++c) {
        const double dx = x[static_cast<size_t>(r)] - x[static_cast<size_t>(rows + c)];
        const double dy = y[static_cast<size_t>(r)] - y[static_cast<size_t>(rows + c)];
        if (dx * dx + dy * dy <= 400.0) {
          cost[static_cast<size_t>(r) * cols + c] = dx * dx + dy * dy;
          ++finite;
        }
      }
    }
    ASSERT_GT(finite, rows) << "the gate should join rows into blocks";
    const std::vector<int> a = SolveAssignment(cost, rows, cols);
    int pairs = 0;
    double total = 0.0;
    std::vector<char> seen(static_cast<size_t>(cols), 0);
    for (int r = 0; r < rows; ++r) {
      if (a[static_cast<size_t>(r)] < 0) continue;
      ASSERT_FALSE(seen[static_cast<size_t>(a[static_cast<size_t>(r)])]) << "column used twice";
      seen[static_cast<size_t>(a[static_cast<size_t>(r)])] = 1;
      const double v = cost[static_cast<size_t>(r) * cols + a[static_cast<size_t>(r)]];
      ASSERT_TRUE(std::isfinite(v)) << "forbidden pair assigned";
      ++pairs;
      total += v;
    }
    // One dense solve: each forbidden pair it must use costs more than all
    // finite pairs together, so it first uses as few as it can.
    std::vector<double> dense = cost;
    const double forbidden = 801.0 * static_cast<double>(std::min(rows, cols) + 1);
    for (double& v : dense) {
      if (!std::isfinite(v)) v = forbidden;
    }
    const std::vector<int> d = hcpf::SolveAssignment(dense, rows, cols, AssignmentSense::kMinimise);
    int dense_pairs = 0;
    double dense_total = 0.0;
    for (int r = 0; r < rows; ++r) {
      const int c = d[static_cast<size_t>(r)];
      if (c < 0 || !std::isfinite(cost[static_cast<size_t>(r) * cols + c])) continue;
      ++dense_pairs;
      dense_total += cost[static_cast<size_t>(r) * cols + c];
    }
    EXPECT_EQ(pairs, dense_pairs) << "trial " << trial;
    EXPECT_EQ(total, dense_total) << "trial " << trial;
  }
}

TEST(SolveAssignment, HandCase) {
  // [[4, 1, 3], [2, 0, 5], [3, 2, 2]]: optimum 1 + 2 + 2 = 5 by
  // (0->1, 1->0, 2->2); the alternatives are 6 or more.
  const std::vector<int> a = SolveAssignment({4, 1, 3, 2, 0, 5, 3, 2, 2}, 3, 3);
  EXPECT_EQ(a, (std::vector<int>{1, 0, 2}));
}

TEST(SolveAssignment, EmptyInputs) {
  EXPECT_EQ(SolveAssignment({}, 0, 3), std::vector<int>{});
  EXPECT_EQ(SolveAssignment({}, 2, 0), (std::vector<int>{-1, -1}));
}

TrackPrediction Track(double x, double y) {
  TrackPrediction t;
  t.mean = {x, y};
  t.box = BoxPx::FromCentre(x, y, 10, 10);
  return t;
}
Detection DetAt(double x, double y) { return {.box = BoxPx::FromCentre(x, y, 10, 10)}; }

TEST(GnnAssociator, BeatsGreedyWhereGreedyLosesAPair) {
  // Zero covariance, measurement sigma 1: cost = squared distance, gate 9.21.
  // T1 (0,0), T2 (3,0); D1 (1,0): costs 1 and 4; D2 (-1.5,0): 2.25 and 20.25
  // (outside T2's gate). Greedy takes T1-D1 first and strands T2; GNN pairs
  // T1-D2 and T2-D1.
  AssociationOptions o;
  o.measurement_sigma_px = 1.0;
  const std::vector<TrackPrediction> tracks = {Track(0, 0), Track(3, 0)};
  const std::vector<Detection> dets = {DetAt(1, 0), DetAt(-1.5, 0)};
  EXPECT_EQ(GnnAssociator(o).Associate(tracks, dets), (std::vector<int>{1, 0}));
  EXPECT_EQ(NearestNeighbourAssociator(o).Associate(tracks, dets), (std::vector<int>{0, -1}));
  EXPECT_EQ(NoAssociator().Associate(tracks, dets), (std::vector<int>{-1, -1}));
}

TEST(GatedCost, MahalanobisUsesCovariancePlusMeasurementNoise) {
  // cov diag(5, 0) + sigma 2 -> S = diag(9, 4); d = (3, 2): d^2 = 1 + 1 = 2.
  AssociationOptions o;
  o.measurement_sigma_px = 2.0;
  TrackPrediction t = Track(0, 0);
  t.cov << 5, 0, 0, 0;
  const auto c = GatedCost(t, DetAt(3, 2), o);
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(*c, 2.0, 1e-12);
  EXPECT_FALSE(GatedCost(t, DetAt(30, 2), o).has_value());
}

TEST(GatedCost, IouGate) {
  // Boxes 10x10 offset by 5 px in x: intersection 50, union 150, IoU 1/3.
  AssociationOptions o;
  o.gate = GateKind::kIou;
  o.min_iou = 0.3;
  const auto c = GatedCost(Track(0, 0), DetAt(5, 0), o);
  ASSERT_TRUE(c.has_value());
  EXPECT_NEAR(*c, 1.0 - 1.0 / 3.0, 1e-12);
  o.min_iou = 0.4;
  EXPECT_FALSE(GatedCost(Track(0, 0), DetAt(5, 0), o).has_value());
}

// A detection box with a non-finite side is never gated in, by either gate
// (the IoU gate took a NaN left for an overlap of 0.6: a review).
TEST(GatedCost, NonFiniteBoxesAreNeverGatedIn) {
  for (const GateKind gate : {GateKind::kIou, GateKind::kMahalanobis}) {
    AssociationOptions o;
    o.gate = gate;
    o.min_iou = 0.1;
    o.measurement_sigma_px = 5.0;
    ASSERT_TRUE(GatedCost(Track(0, 0), DetAt(1, 0), o).has_value());
    for (int side = 0; side < 4; ++side) {
      for (const double bad : {std::nan(""), std::numeric_limits<double>::infinity()}) {
        Detection d = DetAt(1, 0);
        (side == 0   ? d.box.left
         : side == 1 ? d.box.top
         : side == 2 ? d.box.width
                     : d.box.height) = bad;
        EXPECT_FALSE(GatedCost(Track(0, 0), d, o).has_value())
            << static_cast<int>(gate) << " side " << side << " " << bad;
      }
    }
  }
}

TEST(MrfInteraction, HandComputedPenalty) {
  // lambda 2, r 10, particle 10 px from the other filter's mean:
  // log w -= 2 exp(-100 / 200) = 2 e^-0.5 = 1.2130613.
  ParticleSet set;
  set.Resize(2);
  set.px = {10.0, 1000.0};
  std::fill(set.log_w.begin(), set.log_w.end(), 0.0);
  FilterSummary other;
  other.mean = {0.0, 0.0};
  MrfInteraction(2.0, 10.0).Apply(set, std::vector<FilterSummary>{other});
  EXPECT_NEAR(set.log_w[0], -1.2130613194252668, 1e-14);
  EXPECT_EQ(set.log_w[1], 0.0);
}

TEST(AssociationMethod, NamesRoundTrip) {
  for (const auto name : NamesOf<AssociationMethod>()) {
    const auto m = ParseName<AssociationMethod>(name);
    ASSERT_TRUE(m.has_value());
    AssociationOptions o;
    o.method = *m;
    EXPECT_EQ(MakeAssociator(o)->name(), name);
  }
  for (const auto name : NamesOf<GateKind>()) EXPECT_EQ(ToString(*ParseName<GateKind>(name)), name);
  for (const auto name : NamesOf<InteractionModel>()) {
    InteractionOptions o;
    o.model = *ParseName<InteractionModel>(name);
    EXPECT_EQ(MakeInteraction(o)->name(), name);
  }
}

}  // namespace
}  // namespace hcpf::tracker

namespace hcpf::tracker {
namespace {

// Contract suite over every associator: one entry per track, each detection
// used at most once, only gated pairs, deterministic.
class AssociatorContract : public ::testing::TestWithParam<AssociationMethod> {};

TEST_P(AssociatorContract, AssignsOnlyGatedPairsAndEachDetectionOnce) {
  AssociationOptions o;
  o.method = GetParam();
  o.measurement_sigma_px = 2.0;
  const auto assoc = MakeAssociator(o);
  Rng rng(31);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<TrackPrediction> tracks(rng.UniformInt(6));
    for (auto& t : tracks) {
      t = Track(rng.Uniform(0, 40), rng.Uniform(0, 40));
      t.cov << rng.Uniform(0, 9), 0, 0, rng.Uniform(0, 9);
    }
    std::vector<Detection> dets(rng.UniformInt(6));
    for (auto& d : dets) d = DetAt(rng.Uniform(0, 40), rng.Uniform(0, 40));
    const std::vector<int> a = assoc->Associate(tracks, dets);
    ASSERT_EQ(a.size(), tracks.size());
    std::vector<int> used(dets.size(), 0);
    for (size_t t = 0; t < a.size(); ++t) {
      if (a[t] < 0) continue;
      ASSERT_LT(a[t], static_cast<int>(dets.size()));
      ASSERT_EQ(used[a[t]]++, 0) << "detection assigned twice";
      ASSERT_TRUE(GatedCost(tracks[t], dets[a[t]], o).has_value()) << "ungated pair";
    }
    EXPECT_EQ(a, assoc->Associate(tracks, dets));
  }
}

INSTANTIATE_TEST_SUITE_P(AllAssociators, AssociatorContract,
                         ::testing::ValuesIn(EnumValues<AssociationMethod>()),
                         [](const auto& info) { return std::string(ToString(info.param)); });

}  // namespace
}  // namespace hcpf::tracker
