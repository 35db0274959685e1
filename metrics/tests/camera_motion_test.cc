// Camera-motion error on hand-worked examples.
#include "hcpf/metrics/camera_motion.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
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
