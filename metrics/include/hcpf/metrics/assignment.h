#pragma once
// Linear assignment (the "Hungarian" problem) on a dense rectangular matrix of
// doubles, and a sparse maximum-weight matching built on it.
//
// SolveAssignment finds a one-to-one assignment of rows to columns that
// minimises (or maximises) the sum of the chosen entries; min(rows, cols)
// pairs are always assigned, exactly like scipy.optimize.linear_sum_assignment.
// Algorithm: shortest augmenting paths with row/column potentials (Kuhn–Munkres
// in the Jonker–Volgenant formulation), O(n² m) for n = min(rows, cols),
// m = max(rows, cols). Entries must be finite.

#include <cstdint>
#include <span>
#include <vector>

namespace hcpf::metrics {

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

// One candidate pair of a sparse matching problem.
struct WeightedEdge {
  int row = 0;
  int col = 0;
  double weight = 0.0;  // > 0; absent pairs have weight 0
};

// Maximum-weight matching of a bipartite graph given by its positive edges
// (all other pairs weigh 0). Equivalent to SolveAssignment(kMaximise) on the
// dense matrix with zeros elsewhere, restricted to the assigned pairs that are
// edges, but solved per connected component, which is what makes per-frame
// matching of mostly disjoint boxes cheap. Writes the indices (into `edges`)
// of the chosen edges to `chosen` (cleared first), in increasing order.
class SparseMatcher final {
 public:
  void Solve(std::span<const WeightedEdge> edges, int rows, int cols, std::vector<int>* chosen);

 private:
  int Find(int x);
  AssignmentSolver solver_;
  std::vector<int> parent_, comp_of_node_, comp_edge_count_, order_, local_row_, local_col_;
  std::vector<int> comp_rows_, comp_cols_;
  std::vector<double> dense_;
};

}  // namespace hcpf::metrics
