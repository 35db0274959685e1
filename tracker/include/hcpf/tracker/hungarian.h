#pragma once
// Minimum-cost rectangular assignment with forbidden pairs, for gated
// association: the project's one solver (hcpf/core/assignment.h), run on each
// block of rows and columns that finite entries join (no optimal assignment
// crosses blocks), with forbidden entries replaced by a cost above any finite
// assignment of the block.

#include <vector>

namespace hcpf::tracker {

// `cost` is row-major rows x cols. Entries may be +infinity (forbidden).
// Returns, per row, the assigned column or -1. Among all assignments it
// first maximises the number of rows matched through finite entries and then
// minimises their total cost. Finite costs must be >= 0 and < 1e12
// (HCPF_CHECK). Ties are broken deterministically (by the solver, within a
// block). Cost: the matrix's size plus O(n^2 m) per block of n x m.
std::vector<int> SolveAssignment(const std::vector<double>& cost, int rows, int cols);

}  // namespace hcpf::tracker
