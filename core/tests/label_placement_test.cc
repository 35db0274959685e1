// hcpf/core/label_placement.h: labels beside boxes, apart from each other
// and off the other boxes where there is room. Every place below is worked
// out by hand from the candidates' offsets (above: 4 px up; below: 2 px
// down; right and left: 3 px aside, level with the box's top).

#include "hcpf/core/label_placement.h"

#include <gtest/gtest.h>

#include <utility>
#include <vector>

namespace hcpf {
namespace {

std::pair<int, int> Xy(const PixelRect& r) { return {r.x, r.y}; }

// In a 320 x 240 image, three labels 50 x 10 on one box at (100, 100) of
// 20 x 20: the first above it (y = 100 − 4 − 10), the second below it
// (y = 100 + 20 + 2), the third, below first, right of it (x = 100 + 20 + 3).
// A box at the top edge gets its label below; one under a taken rectangle
// (the overlay's header) too. (These were the overlay's own tests.)
TEST(PlaceLabels, LabelsArePlacedApart) {
  const PixelRect image{0, 0, 320, 240};
  const PixelRect box{100, 100, 20, 20};
  const std::vector<PixelRect> placed = PlaceLabels(
      {LabelRequest{.box = box, .text_width = 50, .text_height = 10},
       LabelRequest{.box = box, .text_width = 50, .text_height = 10},
       LabelRequest{.box = box, .text_width = 50, .text_height = 10, .first = LabelSide::kBelow}},
      image, {});
  ASSERT_EQ(placed.size(), 3u);
  EXPECT_EQ(Xy(placed[0]), std::pair(100, 86));
  EXPECT_EQ(Xy(placed[1]), std::pair(100, 122));
  EXPECT_EQ(Xy(placed[2]), std::pair(123, 100));
  // At the top edge: above would leave the image.
  EXPECT_EQ(
      Xy(PlaceLabels({LabelRequest{.box = {10, 5, 20, 20}, .text_width = 50, .text_height = 10}},
                     image, {})[0]),
      std::pair(10, 27));
  // Under a taken rectangle: below instead of above.
  EXPECT_EQ(
      Xy(PlaceLabels({LabelRequest{.box = {10, 30, 20, 20}, .text_width = 50, .text_height = 10}},
                     image, {PixelRect{6, 6, 100, 12}})[0]),
      std::pair(10, 52));
  // Every candidate taken: the first inside the image (below, the box at the
  // top edge having no room above), not one off it.
  EXPECT_EQ(
      Xy(PlaceLabels({LabelRequest{.box = {10, 5, 20, 20}, .text_width = 50, .text_height = 10}},
                     image, {PixelRect{0, 0, 320, 240}})[0]),
      std::pair(10, 27));
  // No candidate inside the image (a box as large as it): the first, above
  // (0, −14), moved inside the image so that it is drawn (a review: a box as
  // tall as a thumbnail lost its label).
  EXPECT_EQ(
      Xy(PlaceLabels({LabelRequest{.box = {0, 0, 320, 240}, .text_width = 50, .text_height = 10}},
                     image, {PixelRect{0, 0, 320, 240}})[0]),
      std::pair(0, 0));
}

// A label keeps off the other boxes where it can (an audit: on the contact
// sheet and in the overlay, labels of targets side by side covered each
// other's boxes). Box A (50, 40) 8 x 20 and box B (60, 25) 8 x 10, labels
// 30 x 10: A's above (50, 26) would cover B (60..68 x 25..35), its below
// (50, 62) does not; B's above (60, 11) covers nothing.
TEST(PlaceLabels, LabelsKeepOffOtherBoxes) {
  const PixelRect image{0, 0, 200, 100};
  const std::vector<PixelRect> placed =
      PlaceLabels({LabelRequest{.box = {50, 40, 8, 20}, .text_width = 30, .text_height = 10},
                   LabelRequest{.box = {60, 25, 8, 10}, .text_width = 30, .text_height = 10}},
                  image, {});
  EXPECT_EQ(Xy(placed[0]), std::pair(50, 62));
  EXPECT_EQ(Xy(placed[1]), std::pair(60, 11));
  // Only places that cover a box: the first of them free of labels. A box
  // with others above, below and on both sides, in a 40 x 40 image: every
  // candidate inside covers a box; above (10, 6) is taken, below (10, 27) is
  // not (the first inside, above, if that step were missing).
  const std::vector<PixelRect> boxed =
      PlaceLabels({LabelRequest{.box = {10, 20, 10, 5}, .text_width = 10, .text_height = 10},
                   LabelRequest{.box = {0, 0, 40, 14}, .text_width = 0, .text_height = 0},
                   LabelRequest{.box = {0, 26, 40, 14}, .text_width = 0, .text_height = 0},
                   LabelRequest{.box = {0, 14, 9, 12}, .text_width = 0, .text_height = 0},
                   LabelRequest{.box = {21, 14, 19, 12}, .text_width = 0, .text_height = 0}},
                  {0, 0, 40, 40}, {PixelRect{10, 6, 10, 10}});
  EXPECT_EQ(Xy(boxed[0]), std::pair(10, 27));
  // The boxes of its own target (they overlap its box: a filter's on the
  // truth's) do not move it: a truth box 6 px above the filter's, both
  // 20 x 20, the filter's label still goes above and the truth's below (a
  // review: they swapped sides, and would flicker as a filter jitters).
  const std::vector<PixelRect> own =
      PlaceLabels({LabelRequest{.box = {100, 100, 20, 20}, .text_width = 50, .text_height = 10},
                   LabelRequest{.box = {100, 94, 20, 20},
                                .text_width = 30,
                                .text_height = 10,
                                .first = LabelSide::kBelow}},
                  PixelRect{0, 0, 320, 240}, {});
  EXPECT_EQ(Xy(own[0]), std::pair(100, 86));
  EXPECT_EQ(Xy(own[1]), std::pair(100, 116));
}

// A detection's label tries the right of its box first.
TEST(PlaceLabels, RightFirst) {
  EXPECT_EQ(Xy(PlaceLabels({LabelRequest{.box = {100, 100, 20, 20},
                                         .text_width = 40,
                                         .text_height = 8,
                                         .first = LabelSide::kRight}},
                           {0, 0, 320, 240}, {})[0]),
            std::pair(123, 100));
}

}  // namespace
}  // namespace hcpf
