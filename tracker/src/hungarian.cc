#include "hcpf/tracker/hungarian.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>

#include "hcpf/core/assignment.h"
#include "hcpf/core/check.h"
#include "hcpf/core/union_find.h"

namespace hcpf::tracker {

namespace {

// One connected block of the gated matrix: its rows and columns, ascending.
struct Block {
  std::vector<int> rows, cols;
};

// Solves one block densely: forbidden entries cost more than any assignment of
// finite entries, so the minimiser first uses as few forbidden pairs as
// possible (= as many finite pairs as possible), then minimises the finite
// total.
void SolveBlock(const std::vector<double>& cost, int cols, const Block& block,
                AssignmentSolver& solver, std::vector<double>& sub, std::vector<int>& assignment) {
  const int r = static_cast<int>(block.rows.size());
  const int c = static_cast<int>(block.cols.size());
  double max_finite = 0.0;
  sub.resize(static_cast<size_t>(r) * static_cast<size_t>(c));
  for (int i = 0; i < r; ++i) {
    for (int j = 0; j < c; ++j) {
      const double v = cost[static_cast<size_t>(block.rows[static_cast<size_t>(i)]) * cols +
                            block.cols[static_cast<size_t>(j)]];
      sub[static_cast<size_t>(i) * c + j] = v;
      if (std::isfinite(v)) max_finite = std::max(max_finite, v);
    }
  }
  const double forbidden = (max_finite + 1.0) * static_cast<double>(std::min(r, c) + 1);
  for (double& v : sub) {
    if (!std::isfinite(v)) v = forbidden;
  }
  const std::span<const int> chosen = solver.Solve(sub, r, c, AssignmentSense::kMinimise);
  for (int i = 0; i < r; ++i) {
    const int j = chosen[static_cast<size_t>(i)];
    if (j < 0) continue;
    const int row = block.rows[static_cast<size_t>(i)];
    const int col = block.cols[static_cast<size_t>(j)];
    // A forbidden pair the minimiser had to use is left unassigned.
    if (std::isfinite(cost[static_cast<size_t>(row) * cols + col])) {
      assignment[static_cast<size_t>(row)] = col;
    }
  }
}

}  // namespace

std::vector<int> SolveAssignment(const std::vector<double>& cost, int rows, int cols) {
  HCPF_CHECK(rows >= 0 && cols >= 0);
  HCPF_CHECK(cost.size() == static_cast<size_t>(rows) * static_cast<size_t>(cols));
  std::vector<int> assignment(static_cast<size_t>(rows), -1);
  if (rows == 0 || cols == 0) return assignment;
  // The rows and columns joined by finite entries fall into blocks that no
  // pair crosses (a gate leaves most pairs forbidden). The best assignment of
  // the whole is the best of each block together, since both what is
  // maximised (finite pairs) and what is minimised (their cost) add over
  // blocks; so each block is solved alone. The dense solver costs
  // O(n^2 m) in the matrix's sides, so a frame of C clutter detections and as
  // many tentative tracks cost O(C^3); in blocks it costs about the matrix's
  // size (docs/performance.md).
  std::vector<int> parent(static_cast<size_t>(rows + cols));
  for (size_t k = 0; k < parent.size(); ++k) parent[k] = static_cast<int>(k);
  for (int i = 0; i < rows; ++i) {
    for (int j = 0; j < cols; ++j) {
      const double c = cost[static_cast<size_t>(i) * cols + j];
      if (std::isfinite(c)) {
        HCPF_CHECK(c >= 0.0 && c < 1e12) << "assignment cost " << c << " outside [0, 1e12)";
        const int a = FindRoot(parent, i);
        const int b = FindRoot(parent, rows + j);
        if (a != b) parent[static_cast<size_t>(std::max(a, b))] = std::min(a, b);
      } else {
        HCPF_CHECK(c == std::numeric_limits<double>::infinity()) << "assignment cost " << c;
      }
    }
  }
  // Blocks in the order of their first row; rows and columns ascending in
  // each (a root is its block's smallest member, so a block with a row has a
  // row as its root).
  std::vector<int> block_of(static_cast<size_t>(rows), -1);
  std::vector<Block> blocks;
  for (int i = 0; i < rows; ++i) {
    const int root = FindRoot(parent, i);
    if (root == i) {
      block_of[static_cast<size_t>(i)] = static_cast<int>(blocks.size());
      blocks.emplace_back();
    }
  }
  for (int i = 0; i < rows; ++i) {
    blocks[static_cast<size_t>(block_of[static_cast<size_t>(FindRoot(parent, i))])].rows.push_back(
        i);
  }
  for (int j = 0; j < cols; ++j) {
    const int root = FindRoot(parent, rows + j);
    if (root < rows) {
      blocks[static_cast<size_t>(block_of[static_cast<size_t>(root)])].cols.push_back(j);
    }
  }
  AssignmentSolver solver;
  std::vector<double> sub;
  for (const Block& block : blocks) {
    if (block.cols.empty()) continue;  // a row with no finite entry
    if (block.rows.size() == 1 && block.cols.size() == 1) {
      assignment[static_cast<size_t>(block.rows[0])] = block.cols[0];  // joined by a finite entry
      continue;
    }
    SolveBlock(cost, cols, block, solver, sub, assignment);
  }
  return assignment;
}

}  // namespace hcpf::tracker
