#pragma once
// The charged resampler's inner loop (the potential of the other filters'
// charges at every candidate and its acceptance probability), shared by
// resampler.cc (which builds it for AVX-512, AVX2 and the baseline:
// HCPF_DISPATCHED) and by tests/isa_clones_test.cc, which builds it for each
// set itself and checks those builds against a scalar one, bit for bit (and
// the library's builds against the library's baseline one).

#include <cstddef>

#include "fast_math.h"

namespace hcpf::tracker::internal {

// One other filter's charge, precomputed: mean and the symmetric matrix
// M = (Sigma + eps^2 I)^-1 = [[a, b], [b, c]] (gaussian only).
struct Charge {
  double mx, my, a, b, c;
};

inline double GaussianTerm(const Charge& ch, double x, double y) {
  const double dx = x - ch.mx;
  const double dy = y - ch.my;
  return FastExp(-0.5 * (ch.a * dx * dx + 2.0 * ch.b * dx * dy + ch.c * dy * dy));
}

inline double CoulombTerm(const Charge& ch, double x, double y, double eps2) {
  const double dx = x - ch.mx;
  const double dy = y - ch.my;
  return 1.0 / (dx * dx + dy * dy + eps2);
}

// u[i] = q * sum over charges of the potential term at (x[i], y[i]), and
// accept[i] = exp(-beta u[i]). Charge-outer, candidate-inner so the inner loop
// is a plain map; each candidate's sum is accumulated in charge order whatever
// the vector width, and the project builds with -ffp-contract=off (no FMA), so
// every instruction set computes the same bits.
__attribute__((always_inline)) inline void AcceptanceKernel(const Charge* charges,
                                                            size_t num_charges, bool gaussian,
                                                            double q, double beta, double eps2,
                                                            const double* x, const double* y,
                                                            double* u, double* accept, size_t n) {
  for (size_t i = 0; i < n; ++i) u[i] = 0.0;
  for (size_t k = 0; k < num_charges; ++k) {
    const Charge ch = charges[k];
    if (gaussian) {
      for (size_t i = 0; i < n; ++i) u[i] += GaussianTerm(ch, x[i], y[i]);
    } else {
      for (size_t i = 0; i < n; ++i) u[i] += CoulombTerm(ch, x[i], y[i], eps2);
    }
  }
  for (size_t i = 0; i < n; ++i) {
    u[i] *= q;
    accept[i] = FastExp(-beta * u[i]);
  }
}

}  // namespace hcpf::tracker::internal
