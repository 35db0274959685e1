#include "hcpf/metrics/assignment.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

#include "hcpf/core/rng.h"

namespace hcpf::metrics {
namespace {

// 3x3 worked by hand (all six permutations listed below).
TEST(AssignmentSolver, SmallSquareMinimum) {
  const std::vector<double> cost = {4, 1, 3,  //
                                    2, 0, 5,  //
                                    3, 2, 2};
  // Permutations (col of row 0,1,2): 012: 4+0+2=6, 021: 4+5+2=11, 102: 1+2+2=5,
  // 120: 1+5+3=9, 201: 3+2+2=7, 210: 3+0+3=6 -> 102 is the unique minimum.
  EXPECT_EQ(SolveAssignment(cost, 3, 3, AssignmentSense::kMinimise), (std::vector<int>{1, 0, 2}));
  // Maximum: 021 = 11.
  EXPECT_EQ(SolveAssignment(cost, 3, 3, AssignmentSense::kMaximise), (std::vector<int>{0, 2, 1}));
}

TEST(AssignmentSolver, RectangularBothWays) {
  // 2x3 maximise, rows {7,1,9} and {5,2,8}; (col of row 0, col of row 1):
  // (0,1)=9, (0,2)=15, (1,0)=6, (1,2)=9, (2,0)=14, (2,1)=11 -> (0,2).
  const std::vector<double> wide = {7, 1, 9, 5, 2, 8};
  EXPECT_EQ(SolveAssignment(wide, 2, 3, AssignmentSense::kMaximise), (std::vector<int>{0, 2}));
  // Transposed (3x2): the same pairs, the row left over gets -1.
  const std::vector<double> tall = {7, 5, 1, 2, 9, 8};
  EXPECT_EQ(SolveAssignment(tall, 3, 2, AssignmentSense::kMaximise), (std::vector<int>{0, -1, 1}));
  EXPECT_TRUE(SolveAssignment({}, 0, 4, AssignmentSense::kMinimise).empty());
}

double BruteForceBest(const std::vector<double>& w, int n) {
  std::vector<int> perm(n);
  std::iota(perm.begin(), perm.end(), 0);
  double best = -1e300;
  do {
    double s = 0;
    for (int i = 0; i < n; ++i) s += w[i * n + perm[i]];
    best = std::max(best, s);
  } while (std::next_permutation(perm.begin(), perm.end()));
  return best;
}

TEST(AssignmentSolver, MatchesBruteForceOnRandomMatrices) {
  Rng rng(42);
  AssignmentSolver solver;
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 1 + static_cast<int>(rng.UniformInt(6));
    std::vector<double> w(n * n);
    for (double& x : w) x = rng.Uniform() < 0.3 ? 0.0 : rng.Uniform(0, 10);
    const auto result = solver.Solve(w, n, n, AssignmentSense::kMaximise);
    double total = 0;
    for (int i = 0; i < n; ++i) total += w[i * n + result[i]];
    EXPECT_NEAR(total, BruteForceBest(w, n), 1e-9) << "trial " << trial;
    // The sparse matcher reaches the same optimum from the positive entries alone.
    std::vector<WeightedEdge> edges;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        if (w[i * n + j] > 0) edges.push_back({i, j, w[i * n + j]});
      }
    }
    SparseMatcher matcher;
    std::vector<int> chosen;
    matcher.Solve(edges, n, n, &chosen);
    double sparse_total = 0;
    std::vector<int> row_used(n, 0), col_used(n, 0);
    for (int k : chosen) {
      sparse_total += edges[k].weight;
      EXPECT_EQ(row_used[edges[k].row]++, 0);
      EXPECT_EQ(col_used[edges[k].col]++, 0);
    }
    EXPECT_NEAR(sparse_total, BruteForceBest(w, n), 1e-9) << "trial " << trial;
  }
}

}  // namespace
}  // namespace hcpf::metrics
