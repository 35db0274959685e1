#include "hcpf/tracker/hungarian.h"

#include <cmath>
#include <limits>

#include "hcpf/core/check.h"

namespace hcpf::tracker {

std::vector<int> SolveAssignment(const std::vector<double>& cost, int rows, int cols) {
  HCPF_CHECK(rows >= 0 && cols >= 0);
  HCPF_CHECK(cost.size() == static_cast<size_t>(rows) * static_cast<size_t>(cols));
  std::vector<int> assignment(static_cast<size_t>(rows), -1);
  if (rows == 0 || cols == 0) return assignment;

  // Work on n <= m (transpose if needed).
  const bool transposed = rows > cols;
  const int n = transposed ? cols : rows;
  const int m = transposed ? rows : cols;
  auto at = [&](int i, int j) {  // 0-based, in the n x m orientation
    return transposed ? cost[static_cast<size_t>(j) * cols + i]
                      : cost[static_cast<size_t>(i) * cols + j];
  };
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
  const double forbidden = (max_finite + 1.0) * static_cast<double>(n + 1);
  std::vector<double> a(static_cast<size_t>(n + 1) * (m + 1), 0.0);
  for (int i = 1; i <= n; ++i) {
    for (int j = 1; j <= m; ++j) {
      const double c = at(i - 1, j - 1);
      a[static_cast<size_t>(i) * (m + 1) + j] = std::isfinite(c) ? c : forbidden;
    }
  }
  // Shortest augmenting paths with potentials u (rows), v (columns); p[j] is
  // the row matched to column j (0 = none), way[j] the previous column on the
  // alternating path. 1-based, column 0 is the virtual start.
  constexpr double kInf = std::numeric_limits<double>::infinity();
  std::vector<double> u(n + 1, 0.0), v(m + 1, 0.0), minv(m + 1);
  std::vector<int> p(m + 1, 0), way(m + 1, 0);
  std::vector<char> used(m + 1);
  for (int i = 1; i <= n; ++i) {
    p[0] = i;
    int j0 = 0;
    std::fill(minv.begin(), minv.end(), kInf);
    std::fill(used.begin(), used.end(), 0);
    do {
      used[j0] = 1;
      const int i0 = p[j0];
      double delta = kInf;
      int j1 = 0;
      for (int j = 1; j <= m; ++j) {
        if (used[j]) continue;
        const double cur = a[static_cast<size_t>(i0) * (m + 1) + j] - u[i0] - v[j];
        if (cur < minv[j]) {
          minv[j] = cur;
          way[j] = j0;
        }
        if (minv[j] < delta) {
          delta = minv[j];
          j1 = j;
        }
      }
      for (int j = 0; j <= m; ++j) {
        if (used[j]) {
          u[p[j]] += delta;
          v[j] -= delta;
        } else {
          minv[j] -= delta;
        }
      }
      j0 = j1;
    } while (p[j0] != 0);
    do {
      const int j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0 != 0);
  }
  for (int j = 1; j <= m; ++j) {
    if (p[j] == 0) continue;
    const int i = p[j] - 1;
    const int col = j - 1;
    if (!std::isfinite(at(i, col))) continue;  // forbidden pair: leave unassigned
    if (transposed) {
      assignment[static_cast<size_t>(col)] = i;
    } else {
      assignment[static_cast<size_t>(i)] = col;
    }
  }
  return assignment;
}

}  // namespace hcpf::tracker
