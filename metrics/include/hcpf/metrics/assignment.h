#pragma once
// A sparse maximum-weight matching built on the project's one dense
// assignment solver (hcpf/core/assignment.h), which this header re-exports.

#include <cstdint>
#include <span>
#include <vector>

#include "hcpf/core/assignment.h"

namespace hcpf::metrics {

using hcpf::AssignmentSense;
using hcpf::AssignmentSolver;
using hcpf::SolveAssignment;

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
