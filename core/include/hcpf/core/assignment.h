#pragma once
// Linear assignment (the "Hungarian" problem) on a dense rectangular matrix,
// the one solver of the project: the metrics (TrackEval's matching, OSPA) and
// the tracker (gated track-to-detection association, with forbidden pairs)
// both use it.
//
// AssignmentSolver finds a one-to-one assignment of rows to columns that
// minimises (or maximises) the sum of the chosen entries; min(rows, cols)
// pairs are always assigned, exactly like scipy.optimize.linear_sum_assignment.
// Algorithm: shortest augmenting paths with row/column potentials (Kuhn 1955,
// Munkres 1957, in the Jonker–Volgenant formulation), O(n² m) for
// n = min(rows, cols), m = max(rows, cols). Entries must be finite; ties are
// broken deterministically (the first column of least reduced cost).

#include <span>
#include <vector>

namespace hcpf {

enum class AssignmentSense { kMinimise, kMaximise };

// Reusable solver: keeps its work buffers between calls so that solving many
// small problems (one per frame) does not allocate.
class AssignmentSolver final {
 public:
  // `cost` is row-major rows x cols. Returns, for every row, the assigned
  // column or -1 (only when rows > cols). The returned span stays valid until
  // the next call.
  std::span<const int> Solve(std::span<const double> cost, int rows, int cols,
                             AssignmentSense sense);

 private:
  std::vector<double> matrix_;  // n x m working copy, n <= m, minimisation form
  std::vector<double> u_, v_, min_v_;
  std::vector<int> p_, way_, result_;
  std::vector<char> used_;
};

// Convenience wrapper around AssignmentSolver.
std::vector<int> SolveAssignment(std::span<const double> cost, int rows, int cols,
                                 AssignmentSense sense);

}  // namespace hcpf
