#include "hcpf/metrics/assignment.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "hcpf/core/check.h"

namespace hcpf::metrics {

std::span<const int> AssignmentSolver::Solve(std::span<const double> cost, int rows, int cols,
                                             AssignmentSense sense) {
  HCPF_CHECK(rows >= 0 && cols >= 0);
  HCPF_CHECK(cost.size() == static_cast<size_t>(rows) * static_cast<size_t>(cols));
  result_.assign(rows, -1);
  if (rows == 0 || cols == 0) return result_;
  // Work on an n x m matrix with n <= m (transpose if needed), minimising.
  const bool transposed = rows > cols;
  const int n = transposed ? cols : rows;
  const int m = transposed ? rows : cols;
  const double sign = sense == AssignmentSense::kMaximise ? -1.0 : 1.0;
  matrix_.resize(static_cast<size_t>(n) * m);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const double value = cost[static_cast<size_t>(r) * cols + c];
      HCPF_CHECK(std::isfinite(value)) << "assignment cost must be finite";
      if (transposed) {
        matrix_[static_cast<size_t>(c) * m + r] = sign * value;
      } else {
        matrix_[static_cast<size_t>(r) * m + c] = sign * value;
      }
    }
  }
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // 1-based potentials; p_[j] = row (1-based) assigned to column j, 0 = none.
  u_.assign(n + 1, 0.0);
  v_.assign(m + 1, 0.0);
  p_.assign(m + 1, 0);
  way_.assign(m + 1, 0);
  for (int i = 1; i <= n; ++i) {
    p_[0] = i;
    int j0 = 0;
    min_v_.assign(m + 1, kInf);
    used_.assign(m + 1, 0);
    do {
      used_[j0] = 1;
      const int i0 = p_[j0];
      double delta = kInf;
      int j1 = 0;
      const double* row = &matrix_[static_cast<size_t>(i0 - 1) * m];
      for (int j = 1; j <= m; ++j) {
        if (used_[j]) continue;
        const double cur = row[j - 1] - u_[i0] - v_[j];
        if (cur < min_v_[j]) {
          min_v_[j] = cur;
          way_[j] = j0;
        }
        if (min_v_[j] < delta) {
          delta = min_v_[j];
          j1 = j;
        }
      }
      HCPF_CHECK(j1 > 0);
      for (int j = 0; j <= m; ++j) {
        if (used_[j]) {
          u_[p_[j]] += delta;
          v_[j] -= delta;
        } else {
          min_v_[j] -= delta;
        }
      }
      j0 = j1;
    } while (p_[j0] != 0);
    do {
      const int j1 = way_[j0];
      p_[j0] = p_[j1];
      j0 = j1;
    } while (j0 != 0);
  }
  for (int j = 1; j <= m; ++j) {
    if (p_[j] == 0) continue;
    const int small = p_[j] - 1;  // index along the short side
    const int large = j - 1;
    if (transposed) {
      result_[large] = small;
    } else {
      result_[small] = large;
    }
  }
  return result_;
}

std::vector<int> SolveAssignment(std::span<const double> cost, int rows, int cols,
                                 AssignmentSense sense) {
  AssignmentSolver solver;
  const auto result = solver.Solve(cost, rows, cols, sense);
  return {result.begin(), result.end()};
}

int SparseMatcher::Find(int x) {
  while (parent_[x] != x) {
    parent_[x] = parent_[parent_[x]];
    x = parent_[x];
  }
  return x;
}

void SparseMatcher::Solve(std::span<const WeightedEdge> edges, int rows, int cols,
                          std::vector<int>* chosen) {
  chosen->clear();
  if (edges.empty()) return;
  const int nodes = rows + cols;
  parent_.resize(nodes);
  std::iota(parent_.begin(), parent_.end(), 0);
  for (const WeightedEdge& e : edges) {
    HCPF_CHECK(e.row >= 0 && e.row < rows && e.col >= 0 && e.col < cols);
    const int a = Find(e.row);
    const int b = Find(rows + e.col);
    if (a != b) parent_[a] = b;
  }
  // Count edges per component root; components with a single edge are matched
  // directly (the common case: one box overlapping one box).
  comp_edge_count_.assign(nodes, 0);
  for (const WeightedEdge& e : edges) ++comp_edge_count_[Find(e.row)];
  bool any_large = false;
  for (size_t k = 0; k < edges.size(); ++k) {
    const int root = Find(edges[k].row);
    if (comp_edge_count_[root] == 1) {
      chosen->push_back(static_cast<int>(k));
    } else {
      any_large = true;
    }
  }
  if (!any_large) return;
  // Group the edges of larger components: sort edge indices by root.
  order_.clear();
  for (size_t k = 0; k < edges.size(); ++k) {
    if (comp_edge_count_[Find(edges[k].row)] > 1) order_.push_back(static_cast<int>(k));
  }
  std::stable_sort(order_.begin(), order_.end(),
                   [&](int a, int b) { return Find(edges[a].row) < Find(edges[b].row); });
  local_row_.assign(rows, -1);
  local_col_.assign(cols, -1);
  size_t begin = 0;
  while (begin < order_.size()) {
    const int root = Find(edges[order_[begin]].row);
    size_t end = begin;
    while (end < order_.size() && Find(edges[order_[end]].row) == root) ++end;
    comp_rows_.clear();
    comp_cols_.clear();
    for (size_t q = begin; q < end; ++q) {
      const WeightedEdge& e = edges[order_[q]];
      if (local_row_[e.row] < 0) {
        local_row_[e.row] = static_cast<int>(comp_rows_.size());
        comp_rows_.push_back(e.row);
      }
      if (local_col_[e.col] < 0) {
        local_col_[e.col] = static_cast<int>(comp_cols_.size());
        comp_cols_.push_back(e.col);
      }
    }
    const int nr = static_cast<int>(comp_rows_.size());
    const int nc = static_cast<int>(comp_cols_.size());
    dense_.assign(static_cast<size_t>(nr) * nc, 0.0);
    for (size_t q = begin; q < end; ++q) {
      const WeightedEdge& e = edges[order_[q]];
      dense_[static_cast<size_t>(local_row_[e.row]) * nc + local_col_[e.col]] = e.weight;
    }
    const auto assignment = solver_.Solve(dense_, nr, nc, AssignmentSense::kMaximise);
    for (size_t q = begin; q < end; ++q) {
      const WeightedEdge& e = edges[order_[q]];
      if (assignment[local_row_[e.row]] == local_col_[e.col]) chosen->push_back(order_[q]);
    }
    for (int r : comp_rows_) local_row_[r] = -1;
    for (int c : comp_cols_) local_col_[c] = -1;
    begin = end;
  }
  std::sort(chosen->begin(), chosen->end());
}

}  // namespace hcpf::metrics
