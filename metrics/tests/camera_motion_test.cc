// Camera-motion error on hand-worked examples.
#include "hcpf/metrics/camera_motion.h"

#include <gtest/gtest.h>

#include <Eigen/LU>
#include <cmath>
#include <numbers>
#include <random>
#include <vector>

#include "hcpf/core/error.h"

namespace hcpf::metrics {
namespace {

const Eigen::Matrix3d kIdentity = Eigen::Matrix3d::Identity();

TEST(CameraMotionErrorTest, IdentityAgainstIdentityIsZero) {
  EXPECT_EQ(CornerDisplacementPx(SimilarityMotion{}, kIdentity, 640, 480), 0.0);
}

TEST(CameraMotionErrorTest, TranslationIsItsLengthAtEveryCorner) {
  // Every corner is off by (3, 4): |(3, 4)| = 5.
  EXPECT_NEAR(CornerDisplacementPx(SimilarityMotion{3.0, 4.0, 0.0, 0.0}, kIdentity, 640, 480), 5.0,
              1e-12);
  // The same error from the other side: estimate identity, truth translates by (-3, 4).
  Eigen::Matrix3d h = kIdentity;
  h(0, 2) = -3.0;
  h(1, 2) = 4.0;
  EXPECT_NEAR(CornerDisplacementPx(SimilarityMotion{}, h, 640, 480), 5.0, 1e-12);
}

TEST(CameraMotionErrorTest, ScaleAboutTheOrigin) {
  // Estimate: scale 2 about the origin; truth: identity; image 4 x 3.
  // Corners (0,0) (4,0) (4,3) (0,3) map to (0,0) (8,0) (8,6) (0,6): displacements
  // 0, 4, 5, 3; mean 12 / 4 = 3.
  EXPECT_NEAR(CornerDisplacementPx(SimilarityMotion{0.0, 0.0, std::log(2.0), 0.0}, kIdentity, 4, 3),
              3.0, 1e-12);
}

TEST(CameraMotionErrorTest, QuarterTurnAboutTheOrigin) {
  // Rotation pi/2: (x, y) -> (-y, x). Corners of 4 x 3 go to (0,0) (0,4) (-3,4)
  // (-3,0): displacements 0, |(-4,4)| = 4 sqrt2, |(-7,1)| = 5 sqrt2, |(-3,-3)| = 3 sqrt2;
  // mean 12 sqrt2 / 4 = 3 sqrt2.
  EXPECT_NEAR(
      CornerDisplacementPx(SimilarityMotion{0.0, 0.0, 0.0, std::numbers::pi / 2}, kIdentity, 4, 3),
      3.0 * std::sqrt(2.0), 1e-12);
}

TEST(CameraMotionErrorTest, ProjectiveDivide) {
  // H = diag(1, 1, 2) maps c to c / 2. Against the identity estimate, the corners
  // of 4 x 3 are off by |c| / 2: 0, 2, 2.5, 1.5; mean 6 / 4 = 1.5.
  Eigen::Matrix3d h = kIdentity;
  h(2, 2) = 2.0;
  EXPECT_NEAR(CornerDisplacementPx(SimilarityMotion{}, h, 4, 3), 1.5, 1e-12);
}

// The homography (from four correspondences, DLT with h33 = 1) that keeps
// three corners of the 4 x 3 image and moves (4, 3) by (0.4, 0.2).
Eigen::Matrix3d OneCornerMoved() {
  const double src[4][2] = {{0, 0}, {4, 0}, {4, 3}, {0, 3}};
  double dst[4][2] = {{0, 0}, {4, 0}, {4.4, 3.2}, {0, 3}};
  Eigen::Matrix<double, 8, 8> a;
  Eigen::Matrix<double, 8, 1> b;
  for (int i = 0; i < 4; ++i) {
    const double x = src[i][0], y = src[i][1], u = dst[i][0], v = dst[i][1];
    a.row(2 * i) << x, y, 1, 0, 0, 0, -u * x, -u * y;
    b(2 * i) = u;
    a.row(2 * i + 1) << 0, 0, 0, x, y, 1, -v * x, -v * y;
    b(2 * i + 1) = v;
  }
  const Eigen::Matrix<double, 8, 1> h = a.fullPivLu().solve(b);
  Eigen::Matrix3d m;
  m << h(0), h(1), h(2), h(3), h(4), h(5), h(6), h(7), 1.0;
  return m;
}

TEST(CameraMotionErrorTest, FloorOfAPureSimilarityIsZero) {
  // H is itself a similarity: scale 1.02, 0.01 rad, shift (3, -2).
  const SimilarityMotion s{3.0, -2.0, std::log(1.02), 0.01};
  Eigen::Matrix3d h = kIdentity;
  const double a = 1.02 * std::cos(0.01), b = 1.02 * std::sin(0.01);
  h << a, -b, 3.0, b, a, -2.0, 0.0, 0.0, 1.0;
  const SimilarityMotion f = CornerOptimalSimilarity(h, 640, 480);
  EXPECT_NEAR(CornerDisplacementPx(f, h, 640, 480), 0.0, 1e-9);
  EXPECT_NEAR(f.tx_px, s.tx_px, 1e-9);
  EXPECT_NEAR(f.log_scale, s.log_scale, 1e-12);
  EXPECT_NEAR(f.rotation_rad, s.rotation_rad, 1e-12);
}

TEST(CameraMotionErrorTest, FloorFitsThreeCornersExactlyWhenOneMoves) {
  // Three corners stay and (4, 3) moves by (0.4, 0.2). The identity leaves
  // only that corner's |(0.4, 0.2)| = 0.4472: mean 0.1118. It is the optimum
  // (a sum of norms: moving to reduce the one residual costs at least as much
  // on the three exact ones), while the corners' least-squares similarity
  // spreads the error over all four: 0.1342 (worked out with numpy).
  const Eigen::Matrix3d h = OneCornerMoved();
  const SimilarityMotion f = CornerOptimalSimilarity(h, 4, 3);
  EXPECT_NEAR(CornerDisplacementPx(f, h, 4, 3), std::hypot(0.4, 0.2) / 4.0, 1e-9);
  EXPECT_NEAR(f.tx_px, 0.0, 1e-6);
  EXPECT_NEAR(f.ty_px, 0.0, 1e-6);
  EXPECT_NEAR(f.log_scale, 0.0, 1e-6);
  EXPECT_NEAR(f.rotation_rad, 0.0, 1e-6);
}

TEST(CameraMotionErrorTest, FloorIsAMinimumOnAnObliqueHomography) {
  // A 9-degree off-nadir frame-to-frame motion like climb's (perspective row
  // non-zero): no perturbation of the floor's similarity, at any of three
  // scales and in any of 200 random directions, gives a lower error (the
  // problem is convex, so a local minimum is the global one).
  Eigen::Matrix3d h;
  h << 1.0071, 0.0052, -2.31, -0.0047, 1.0135, 1.87, 1.1e-6, 2.4e-5, 1.0;
  const SimilarityMotion f = CornerOptimalSimilarity(h, 640, 480);
  const double floor = CornerDisplacementPx(f, h, 640, 480);
  EXPECT_GT(floor, 0.0);
  std::mt19937 random(7);
  std::normal_distribution<double> normal;
  for (const double step : {1e-2, 1e-4, 1e-6}) {
    for (int k = 0; k < 200; ++k) {
      SimilarityMotion g = f;
      g.tx_px += step * normal(random);
      g.ty_px += step * normal(random);
      g.log_scale += step * 1e-3 * normal(random);
      g.rotation_rad += step * 1e-3 * normal(random);
      EXPECT_GE(CornerDisplacementPx(g, h, 640, 480), floor - 1e-12) << "step " << step;
    }
  }
  EXPECT_THROW(CornerOptimalSimilarity(h, 0, 480), InputError);
}

TEST(CameraMotionErrorTest, RejectsBadInput) {
  Eigen::Matrix3d behind = kIdentity;
  behind(2, 2) = -1.0;
  EXPECT_THROW(CornerDisplacementPx(SimilarityMotion{}, behind, 4, 3), InputError);
  EXPECT_THROW(CornerDisplacementPx(SimilarityMotion{}, kIdentity, 0, 3), InputError);
  const std::vector<double> negative = {1.0, -0.5};
  EXPECT_THROW(SummariseCameraMotionError(negative), InputError);
}

TEST(CameraMotionErrorTest, SummaryOnHandValues) {
  // Sorted: 1 2 3 4 10. Mean 20 / 5 = 4; median 3; p95 at position 0.95 * 4 = 3.8:
  // 4 + 0.8 * (10 - 4) = 8.8; max 10.
  const std::vector<double> values = {4.0, 1.0, 3.0, 2.0, 10.0};
  const CameraMotionErrorSummary s = SummariseCameraMotionError(values);
  EXPECT_EQ(s.frames, 5);
  EXPECT_NEAR(s.mean_px, 4.0, 1e-12);
  EXPECT_NEAR(s.median_px, 3.0, 1e-12);
  EXPECT_NEAR(s.p95_px, 8.8, 1e-12);
  EXPECT_EQ(s.max_px, 10.0);

  // Two values 1, 3: median at 0.5 -> 2; p95 at 0.95 -> 1 + 0.95 * 2 = 2.9.
  const std::vector<double> two = {3.0, 1.0};
  const CameraMotionErrorSummary t = SummariseCameraMotionError(two);
  EXPECT_NEAR(t.median_px, 2.0, 1e-12);
  EXPECT_NEAR(t.p95_px, 2.9, 1e-12);
  EXPECT_NEAR(t.mean_px, 2.0, 1e-12);

  EXPECT_EQ(SummariseCameraMotionError({}), CameraMotionErrorSummary{});
}

}  // namespace
}  // namespace hcpf::metrics
