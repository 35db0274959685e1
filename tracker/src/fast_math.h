#pragma once
// Branch-free exp and log for the hot per-particle loops. Written with plain
// double arithmetic and bit operations only, so GCC vectorises loops that call
// them (SSE2 two-wide on the x86-64 baseline, four-wide in the AVX2 builds) and
// every lane computes exactly the same bits as the scalar code: results do not
// depend on which build runs (AVX-512, AVX2 or baseline: HCPF_DISPATCHED). No
// fused multiply-add is used: the project compiles with -ffp-contract=off,
// because the AVX-512 build has FMA and GCC would otherwise contract a*b+c
// there. Checked by tests/isa_clones_test.cc.
//
// Accuracy (checked in fast_math_test.cc against std::exp/std::log): relative
// error below 1e-14 over the ranges documented on each function.

#include <bit>
#include <cstdint>
#include <limits>

namespace hcpf::tracker::internal {

// exp(x) for any finite x: returns 0 for x < -708 (where exp is subnormal or
// zero anyway) and clamps at x = 709. Reduction x = k ln2 + r, |r| <= ln2/2,
// then a degree-10 polynomial: the Chebyshev fit of exp on [-ln2/2, ln2/2]
// (mpmath 1.3 chebyfit at 40 digits, coefficients rounded to double; fit
// error 2.2e-16, 4.6e-16 relative measured with double Horner evaluation at
// 2e5 points). Two degrees fewer than the Taylor polynomial of the same
// accuracy: this function is the cost of the mixture likelihood.
inline double FastExp(double x) {
  const bool underflow = x < -708.0;
  x = x > 709.0 ? 709.0 : x;
  x = underflow ? 0.0 : x;
  constexpr double kLog2e = 1.4426950408889634;
  constexpr double kShift = 0x1.8p52;              // adding it rounds to an integer in the low bits
  constexpr double kLn2Hi = 0x1.62e42fefa3800p-1;  // ln2 split: hi has trailing zeros so
  constexpr double kLn2Lo = 0x1.ef35793c76730p-45;  // k * kLn2Hi is exact for |k| < 2^11
  double kd = x * kLog2e + kShift;
  const uint64_t ki = std::bit_cast<uint64_t>(kd);
  kd -= kShift;
  const double r = (x - kd * kLn2Hi) - kd * kLn2Lo;
  double p = 2.7626357241447223e-07;
  p = p * r + 2.764018079620985e-06;
  p = p * r + 2.4801504346997686e-05;
  p = p * r + 0.00019841170270440067;
  p = p * r + 0.0013888888932488599;
  p = p * r + 0.008333333385667782;
  p = p * r + 0.04166666666657314;
  p = p * r + 0.16666666666554406;
  p = p * r + 0.5000000000000006;
  p = p * r + 1.0000000000000067;
  p = p * r + 1.0;
  // The low bits of ki hold k (two's complement); shifting (k + 1023) into the
  // exponent field builds 2^k for k in [-1021, 1023].
  const double scale = std::bit_cast<double>((ki + 1023) << 52);
  const double result = p * scale;
  return underflow ? 0.0 : result;
}

// Single-precision exp for the mixture likelihood, whose terms are weights:
// a relative error of 1e-7 moves a log-weight by 1e-7, far below any effect
// of the model's own approximations, and float lanes are twice as many per
// vector as double lanes. Returns 0 for x < -87 (exp(-87) = 1.6e-38 is the
// last normal float) and clamps at x = 88. Reduction x = k ln2 + r, |r| <=
// ln2/2, then exp(r) = 1 + r q(r) with q of degree 5 interpolating
// expm1(r)/r at the six Chebyshev nodes of [-ln2/2, ln2/2] (coefficients
// rounded to float). Relative error below 1.5e-7 (2.5 float ulp) over
// [-87, 88], measured against std::exp in fast_math_test.cc.
inline float FastExpF(float x) {
  const bool underflow = x < -87.0f;
  x = x > 88.0f ? 88.0f : x;
  x = underflow ? 0.0f : x;
  constexpr float kLog2e = 1.44269504f;
  constexpr float kShift = 0x1.8p23f;     // adding it rounds to an integer in the low bits
  constexpr float kLn2Hi = 0x1.62e4p-1f;  // 16 significant bits: k * kLn2Hi is exact for |k| < 2^8
  constexpr float kLn2Lo = 1.42860677e-06f;  // ln2 - kLn2Hi
  float kf = x * kLog2e + kShift;
  const uint32_t ki = std::bit_cast<uint32_t>(kf);
  kf -= kShift;
  const float r = (x - kf * kLn2Hi) - kf * kLn2Lo;
  float q = 0.0013933641603216529f;
  q = q * r + 0.008369148708879948f;
  q = q * r + 0.04166646674275398f;
  q = q * r + 0.16666504740715027f;
  q = q * r + 0.5f;
  q = q * r + 1.0f;
  const float p = r * q + 1.0f;
  // The low bits of ki hold k (two's complement); shifting (k + 127) into the
  // exponent field builds 2^k for k in [-126, 127].
  const float scale = std::bit_cast<float>((ki + 127u) << 23);
  const float result = p * scale;
  return underflow ? 0.0f : result;
}

// log(x) for normal positive x (x >= DBL_MIN); returns -inf for x <= 0 and
// garbage-free but inexact values for subnormal x (callers guard those).
// x = m 2^e with m in [sqrt(1/2), sqrt(2)); log m = 2 atanh(f), f = (m-1)/(m+1),
// |f| <= 0.1716; the series to f^21 leaves f^23/23 ~ 1e-19 relative.
inline double FastLog(double x) {
  const bool nonpositive = !(x > 0.0);
  const double safe = nonpositive ? 1.0 : x;
  const uint64_t bits = std::bit_cast<uint64_t>(safe);
  constexpr uint64_t kMantissa = 0x000FFFFFFFFFFFFFULL;
  constexpr uint64_t kOneExponent = 0x3FF0000000000000ULL;
  double m = std::bit_cast<double>((bits & kMantissa) | kOneExponent);  // [1, 2)
  // Biased exponent as a double without an int64 -> double conversion (which
  // SSE2 cannot vectorise): OR it into the mantissa of 2^52 and subtract 2^52.
  double e = std::bit_cast<double>((bits >> 52) | 0x4330000000000000ULL) - 0x1p52 - 1023.0;
  const bool big = m > 1.4142135623730951;
  m = big ? 0.5 * m : m;
  e = big ? e + 1.0 : e;
  const double f = (m - 1.0) / (m + 1.0);
  const double f2 = f * f;
  double p = 1.0 / 21.0;
  p = p * f2 + 1.0 / 19.0;
  p = p * f2 + 1.0 / 17.0;
  p = p * f2 + 1.0 / 15.0;
  p = p * f2 + 1.0 / 13.0;
  p = p * f2 + 1.0 / 11.0;
  p = p * f2 + 1.0 / 9.0;
  p = p * f2 + 1.0 / 7.0;
  p = p * f2 + 1.0 / 5.0;
  p = p * f2 + 1.0 / 3.0;
  p = p * f2 + 1.0;
  constexpr double kLn2 = 0.6931471805599453;
  const double result = e * kLn2 + 2.0 * f * p;
  return nonpositive ? -std::numeric_limits<double>::infinity() : result;
}

}  // namespace hcpf::tracker::internal
