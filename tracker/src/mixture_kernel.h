#pragma once
// The inner loop of the detections_mixture likelihood, shared by
// likelihood.cc (which builds it for AVX-512, AVX2 and the baseline:
// HCPF_DISPATCHED) and by tests/isa_clones_test.cc, which builds it for each
// set itself and checks those builds against a scalar one, bit for bit (and
// the library's builds against the library's baseline one).

#include <cstddef>

#include "fast_math.h"

namespace hcpf::tracker::internal {

struct MixtureComponent {
  double cx, cy;
  double log_weight;       // log of the component's mixture weight times its normaliser
  double weight;           // exp(log_weight)
  double log_size_offset;  // log(base_w / detection width), 0 when size is off
};

// Exponents below this contribute exactly zero (FastExpF flushes them).
constexpr double kMixtureUnderflow = -87.0;

// Detection-outer, particle-inner so the inner loop is a plain vectorisable map
// over particles. Positions, exponents and sums are double; only the exp is
// single precision, which doubles the lanes per vector in the most expensive
// part. Each term's relative error is below 1.5e-7 + 2^-24 |e| (FastExpF's,
// plus rounding the exponent e to float): 2e-7 near a detection, 5e-6 at the
// flush limit e = -87, where a term weighs e^-87 against one on the detection.
// Every instruction set computes identical bits: no FMA (the project builds
// with -ffp-contract=off), and each particle's sum is accumulated in detection
// order whatever the vector width.
// kSize: whether the log-size term is on (a compile-time switch keeps the
// position-only loop free of the three extra operations per component).
template <bool kSize>
__attribute__((always_inline)) inline void MixtureKernel(const MixtureComponent* comps,
                                                         size_t num_comps, const double* px,
                                                         const double* py, const double* log_s,
                                                         double inv_2s2, double inv_2ss2,
                                                         double* sum, size_t m) {
  for (size_t i = 0; i < m; ++i) sum[i] = 0.0;
  for (size_t d = 0; d < num_comps; ++d) {
    const MixtureComponent c = comps[d];
    for (size_t i = 0; i < m; ++i) {
      const double dx = px[i] - c.cx;
      const double dy = py[i] - c.cy;
      double e = -(dx * dx + dy * dy) * inv_2s2;
      if constexpr (kSize) {
        const double dl = log_s[i] + c.log_size_offset;
        e -= dl * dl * inv_2ss2;
      }
      sum[i] += c.weight * static_cast<double>(FastExpF(static_cast<float>(e)));
    }
  }
}

}  // namespace hcpf::tracker::internal
