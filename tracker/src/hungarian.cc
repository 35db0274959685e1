#include "hcpf/tracker/hungarian.h"

#include <cmath>
#include <limits>

#include "hcpf/core/assignment.h"
#include "hcpf/core/check.h"

namespace hcpf::tracker {

std::vector<int> SolveAssignment(const std::vector<double>& cost, int rows, int cols) {
  HCPF_CHECK(rows >= 0 && cols >= 0);
  HCPF_CHECK(cost.size() == static_cast<size_t>(rows) * static_cast<size_t>(cols));
  std::vector<int> assignment(static_cast<size_t>(rows), -1);
  if (rows == 0 || cols == 0) return assignment;
  // Forbidden entries cost more than any assignment of finite entries, so the
  // minimiser first uses as few forbidden pairs as possible (= as many finite
  // pairs as possible), then minimises the finite total.
  double max_finite = 0.0;
  for (const double c : cost) {
    if (std::isfinite(c)) {
      HCPF_CHECK(c >= 0.0 && c < 1e12) << "assignment cost " << c << " outside [0, 1e12)";
      max_finite = std::max(max_finite, c);
    } else {
      HCPF_CHECK(c == std::numeric_limits<double>::infinity()) << "assignment cost " << c;
    }
  }
  const int n = std::min(rows, cols);
  const double forbidden = (max_finite + 1.0) * static_cast<double>(n + 1);
  std::vector<double> finite(cost.size());
  for (size_t k = 0; k < cost.size(); ++k) finite[k] = std::isfinite(cost[k]) ? cost[k] : forbidden;
  AssignmentSolver solver;
  const std::span<const int> chosen = solver.Solve(finite, rows, cols, AssignmentSense::kMinimise);
  for (int i = 0; i < rows; ++i) {
    const int j = chosen[static_cast<size_t>(i)];
    // A forbidden pair the minimiser had to use is left unassigned.
    if (j >= 0 && std::isfinite(cost[static_cast<size_t>(i) * cols + j])) {
      assignment[static_cast<size_t>(i)] = j;
    }
  }
  return assignment;
}

}  // namespace hcpf::tracker
