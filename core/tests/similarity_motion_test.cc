// The complex least-squares similarity fit shared by the oracle camera motion
// (scenarios) and the camera-motion floor (metrics).

#include "hcpf/core/similarity_motion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

namespace hcpf {
namespace {

using Complex = std::complex<double>;

// Points mapped by a known similarity come back exactly (to rounding), and
// the motion reads as the same similarity through Apply.
TEST(FitComplexSimilarity, RecoversAnExactSimilarity) {
  const double scale = 1.02;
  const double theta = 0.05;
  const Complex a = std::polar(scale, theta);
  const Complex b(3.5, -2.0);
  const std::vector<Complex> p = {{0, 0}, {640, 0}, {640, 480}, {0, 480}, {100, 37}};
  std::vector<Complex> q;
  for (const Complex& x : p) q.push_back(a * x + b);
  const ComplexSimilarity fit = FitComplexSimilarity(p, q);
  EXPECT_NEAR(std::abs(fit.a - a), 0.0, 1e-12);
  EXPECT_NEAR(std::abs(fit.b - b), 0.0, 1e-9);
  const SimilarityMotion m = fit.motion();
  EXPECT_NEAR(m.log_scale, std::log(scale), 1e-12);
  EXPECT_NEAR(m.rotation_rad, theta, 1e-12);
  EXPECT_NEAR(m.tx_px, 3.5, 1e-9);
  EXPECT_NEAR(m.ty_px, -2.0, 1e-9);
  const Eigen::Vector2d mapped = Apply(m, Eigen::Vector2d(100, 37));
  EXPECT_NEAR(mapped.x(), q[4].real(), 1e-9);
  EXPECT_NEAR(mapped.y(), q[4].imag(), 1e-9);
}

// By hand: p = 0, 2 and q = 0, 2 + 2i, 10 (an outlier at p = 1).
// Unweighted: p_m = 1, q_m = (12 + 2i) / 3; a = sum (q - q_m) conj(p - p_m) /
// sum |p - p_m|^2 = ((-q_m)(-1) + (2 + 2i - q_m)(1) + 0) / 2 = (2 + 2i) / 2 =
// 1 + i, b = q_m - a p_m = (12 + 2i) / 3 - (1 + i) = 3 - i / 3.
// With the outlier's weight 0 the fit is the line through the other two:
// a = 1 + i, b = 0.
TEST(FitComplexSimilarity, WeightsAsByHand) {
  const std::vector<Complex> p = {{0, 0}, {2, 0}, {1, 0}};
  const std::vector<Complex> q = {{0, 0}, {2, 2}, {10, 0}};
  const ComplexSimilarity plain = FitComplexSimilarity(p, q);
  EXPECT_NEAR(std::abs(plain.a - Complex(1, 1)), 0.0, 1e-15);
  EXPECT_NEAR(std::abs(plain.b - Complex(3, -1.0 / 3.0)), 0.0, 1e-15);
  const std::vector<double> weights = {1.0, 1.0, 0.0};
  const ComplexSimilarity weighted = FitComplexSimilarity(p, q, weights);
  EXPECT_NEAR(std::abs(weighted.a - Complex(1, 1)), 0.0, 1e-15);
  EXPECT_NEAR(std::abs(weighted.b), 0.0, 1e-15);
  // Uniform weights of any size give the unweighted fit.
  const std::vector<double> twos = {2.0, 2.0, 2.0};
  const ComplexSimilarity doubled = FitComplexSimilarity(p, q, twos);
  EXPECT_NEAR(std::abs(doubled.a - plain.a), 0.0, 1e-15);
  EXPECT_NEAR(std::abs(doubled.b - plain.b), 0.0, 1e-15);
  EXPECT_NEAR(weighted.motion().rotation_rad, std::numbers::pi / 4.0, 1e-15);
  EXPECT_NEAR(weighted.motion().log_scale, 0.5 * std::log(2.0), 1e-15);
}

}  // namespace
}  // namespace hcpf
