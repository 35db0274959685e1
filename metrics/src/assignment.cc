#include "hcpf/metrics/assignment.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "hcpf/core/check.h"

namespace hcpf::metrics {

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
