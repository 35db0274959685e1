#include "hcpf/core/types.h"

#include <gtest/gtest.h>

#include <limits>

namespace hcpf {
namespace {

TEST(BoxPx, IouOfHandWorkedBoxes) {
  // [0,10]x[0,10] and [5,15]x[0,10]: intersection 50, union 150.
  EXPECT_DOUBLE_EQ(Iou({0, 0, 10, 10}, {5, 0, 10, 10}), 50.0 / 150.0);
  EXPECT_DOUBLE_EQ(Iou({0, 0, 10, 10}, {0, 0, 10, 10}), 1.0);
  EXPECT_DOUBLE_EQ(Iou({0, 0, 10, 10}, {10, 0, 10, 10}), 0.0);  // touching edges
  EXPECT_DOUBLE_EQ(Iou({0, 0, 0, 10}, {0, 0, 10, 10}), 0.0);    // empty box
}

TEST(BoxPx, UnionAndIntersect) {
  const BoxPx u = Union({0, 0, 2, 2}, {5, 5, 1, 1});
  EXPECT_EQ(u, (BoxPx{0, 0, 6, 6}));
  EXPECT_EQ(Union({}, {1, 2, 3, 4}), (BoxPx{1, 2, 3, 4}));
  EXPECT_TRUE(Intersect({0, 0, 1, 1}, {2, 2, 1, 1}).empty());
  EXPECT_EQ(Intersect({0, 0, 4, 4}, {2, 1, 4, 4}), (BoxPx{2, 1, 2, 3}));
}

TEST(BoxPx, FiniteOnlyWhenEverySideIsANumber) {
  EXPECT_TRUE((BoxPx{1, 2, 3, 4}).finite());
  EXPECT_TRUE((BoxPx{-1e300, 0, 0, -5}).finite());  // empty or negative, still numbers
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  for (int side = 0; side < 4; ++side) {
    for (double bad : {nan, inf, -inf}) {
      BoxPx b{1, 2, 3, 4};
      (side == 0 ? b.left : side == 1 ? b.top : side == 2 ? b.width : b.height) = bad;
      EXPECT_FALSE(b.finite()) << "side " << side << " = " << bad;
    }
  }
}

TEST(LikelihoodMap, BilinearSampleBetweenCellCentres) {
  LikelihoodMap m;
  m.width = 2;
  m.height = 1;
  m.cell_px = 10.0;
  m.values = {0.0f, 1.0f};
  // Cell centres at x = 5 and 15: halfway (x = 10) is the mean.
  EXPECT_DOUBLE_EQ(m.Sample(10.0, 5.0), 0.5);
  EXPECT_DOUBLE_EQ(m.Sample(12.5, 5.0), 0.75);
  EXPECT_DOUBLE_EQ(m.Sample(-100.0, 5.0), 0.0);  // clamped at the border
  EXPECT_DOUBLE_EQ(m.Sample(100.0, 5.0), 1.0);
}

}  // namespace
}  // namespace hcpf
