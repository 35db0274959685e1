#include "hcpf/core/assignment.h"

#include <cmath>
#include <limits>

#include "hcpf/core/check.h"

namespace hcpf {

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

}  // namespace hcpf
