#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <utility>
#include <vector>

#include "hcpf/core/error.h"
#include "hcpf/vision/detectors.h"
#include "synthetic_scene.h"

namespace hcpf::vision {
namespace {

using testing::Frame;
using testing::Targets;

// Each model's histogram back-projects onto its own vehicle (distinct hues on
// green ground), so the model-sized box of highest mean covers the moved
// vehicle exactly; its contrast is well above the 0.3 threshold.
TEST(ColourDetector, FindsEachTargetByItsColours) {
  const RgbImage first = Frame(Targets());
  std::vector<TargetModel> models;
  for (const auto& t : Targets()) models.push_back(CutTargetModel(first, t.box, t.id, 0));
  const RgbImage moved = Frame(Targets(5.0, 4.0));
  Rng rng(1);
  const DetectorOutput out =
      MakeDetector("colour", DetectorOptions{})->Detect({.image = moved, .models = models}, rng);
  ASSERT_EQ(out.detections.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    const Detection& d = out.detections[i];
    const BoxPx truth = Targets(5.0, 4.0)[i].box;
    EXPECT_EQ(d.target, models[i].target);
    EXPECT_NEAR(d.box.centre_x(), truth.centre_x(), 1.0);
    EXPECT_NEAR(d.box.centre_y(), truth.centre_y(), 1.0);
    EXPECT_GT(d.score, 0.5);
  }
}

// A window is only where the peak is sought: the contrast is against the
// frame's mean and each box reads the frame's pixels beyond the window, so a
// window that holds the whole-frame peak gives the whole frame's detection,
// the same box and score, however tight. (A window of the target's own size
// was blurred alone, zero beyond it, against its own mean: contrast 0 and no
// detection at window_scale 1, lower scores at 1.5 and 3; a review.)
TEST(ColourDetector, AWindowGivesTheWholeFramesDetectionWhereItHoldsItsPeak) {
  const RgbImage first = Frame(Targets());
  std::vector<TargetModel> models;
  for (const auto& t : Targets()) models.push_back(CutTargetModel(first, t.box, t.id, 0));
  const RgbImage moved = Frame(Targets(2.0, 1.0));
  std::vector<SearchWindow> windows;
  for (const auto& t : Targets(2.0, 1.0)) windows.push_back({t.id, t.box});
  Rng rng(1);
  const DetectorOutput whole =
      MakeDetector("colour", DetectorOptions{})->Detect({.image = moved, .models = models}, rng);
  ASSERT_EQ(whole.detections.size(), 3u);
  for (const double scale : {1.0, 1.5, 3.0}) {
    SCOPED_TRACE(scale);
    DetectorOptions o;
    o.colour.window_scale = scale;
    const DetectorOutput windowed =
        MakeDetector("colour", o)
            ->Detect({.image = moved, .models = models, .windows = windows}, rng);
    ASSERT_EQ(windowed.detections.size(), 3u);
    for (size_t i = 0; i < 3; ++i) {
      EXPECT_EQ(windowed.detections[i].target, whole.detections[i].target);
      EXPECT_EQ(windowed.detections[i].box, whole.detections[i].box);
      EXPECT_EQ(windowed.detections[i].score, whole.detections[i].score);
    }
  }
}

TEST(ColourDetector, GroundWithoutTheModelsColoursGivesNothing) {
  const RgbImage first = Frame(Targets());
  std::vector<TargetModel> models;
  for (const auto& t : Targets()) models.push_back(CutTargetModel(first, t.box, t.id, 0));
  Rng rng(1);
  const DetectorOutput out = MakeDetector("colour", DetectorOptions{})
                                 ->Detect({.image = Frame({}), .models = models}, rng);
  EXPECT_TRUE(out.detections.empty());
}

// Plain grey ground (no saturation: a bin of neither colour below) with
// `side` x `side` blocks of `rgb` whose top-left corners are `at`.
RgbImage Blocks(int width, int height, std::vector<std::pair<int, int>> at, int side,
                std::array<uint8_t, 3> rgb) {
  RgbImage image{.width = width, .height = height};
  image.pixels.assign(static_cast<size_t>(3) * width * height, 128);
  for (const auto& [x0, y0] : at) {
    for (int y = y0; y < y0 + side; ++y) {
      for (int x = x0; x < x0 + side; ++x) std::copy(rgb.begin(), rgb.end(), image.at(x, y));
    }
  }
  return image;
}

// The back-projection carries each bin's share of the largest bin, not 0 or
// 1. The model: an 8 x 8 patch, 48 pixels red and 16 blue, so after scaling
// red's bin is 1 and blue's 16/48 = 1/3. On grey ground holding one 8 x 8
// block of the blue alone, the box of highest mean back-projection is that
// block at 1/3, the frame's mean m = 64 (1/3) / 64^2, and the detection's
// contrast (1/3 - m) / (1 - m) = 0.32986 (to 1/255: the back-projection is
// quantised to 8 bits). Before: blue's 1/3 rounded to 0, and nothing was
// found.
TEST(ColourDetector, BackProjectsEachBinsShareOfTheLargest) {
  RgbImage patch = Blocks(8, 8, {}, 0, {});
  for (int y = 0; y < 8; ++y) {
    for (int x = 0; x < 8; ++x) {
      const std::array<uint8_t, 3> rgb =
          y < 6 ? std::array<uint8_t, 3>{200, 30, 30} : std::array<uint8_t, 3>{30, 30, 200};
      std::copy(rgb.begin(), rgb.end(), patch.at(x, y));
    }
  }
  const std::vector<TargetModel> models{CutTargetModel(patch, BoxPx{0, 0, 8, 8}, ObjectId{4}, 0)};
  const RgbImage frame = Blocks(64, 64, {{20, 30}}, 8, {30, 30, 200});
  DetectorOptions options;
  options.colour.min_contrast = 0.1;
  Rng rng(1);
  const DetectorOutput out =
      MakeDetector("colour", options)->Detect({.image = frame, .models = models}, rng);
  ASSERT_EQ(out.detections.size(), 1u);
  const double m = 64.0 / 3.0 / (64.0 * 64.0);
  EXPECT_NEAR(out.detections[0].score, (1.0 / 3.0 - m) / (1.0 - m), 1.0 / 255.0);
  // The map's cell holding the block's centre (24, 34) has the block's mean.
  ASSERT_EQ(out.maps.size(), 1u);
  const LikelihoodMap& map = out.maps[0].map;
  EXPECT_NEAR(map.values[static_cast<size_t>(34 / 4) * map.width + 24 / 4], 1.0 / 3.0, 1.0 / 255.0);
}

// The box is centred on the block found, for a model of even and of odd side
// (OpenCV's box mean at index x covers x - floor(w/2) ... : centred on x for
// even w, x + 0.5 for odd). Before: +0.5 px on each axis of even side.
TEST(ColourDetector, TheBoxIsCentredOnTheBlockForEvenAndOddSides) {
  for (const int side : {8, 7}) {
    const RgbImage patch = Blocks(side, side, {{0, 0}}, side, {200, 30, 30});
    const std::vector<TargetModel> models{CutTargetModel(
        patch, BoxPx{0, 0, static_cast<double>(side), static_cast<double>(side)}, ObjectId{4}, 0)};
    const RgbImage frame = Blocks(64, 64, {{20, 30}}, side, {200, 30, 30});
    Rng rng(1);
    const DetectorOutput out =
        MakeDetector("colour", DetectorOptions{})->Detect({.image = frame, .models = models}, rng);
    ASSERT_EQ(out.detections.size(), 1u) << side;
    EXPECT_DOUBLE_EQ(out.detections[0].box.centre_x(), 20 + side / 2.0) << side;
    EXPECT_DOUBLE_EQ(out.detections[0].box.centre_y(), 30 + side / 2.0) << side;
  }
}

// The map holds a box mean at the centre of the box it averages (the middle
// of a pixel for an odd side): a block at (71, 30) of side 7 is centred at
// (74.5, 33.5), in cell (33, 14) of 2.25 px (74.5 / 2.25 = 33.1, 33.5 / 2.25
// = 14.9); of side 8 at (75, 34), cell (33, 15) (33.3, 15.1). Pooled by the
// index of the mean's pixel (74 / 2.25 = 32.9) the odd block's peak went to
// cell 32, before its centre's.
TEST(ColourDetector, TheMapHoldsEachMeanAtItsBoxsCentre) {
  for (const auto& [side, cx, cy] : {std::array{7, 33, 14}, std::array{8, 33, 15}}) {
    const RgbImage patch = Blocks(side, side, {{0, 0}}, side, {200, 30, 30});
    const std::vector<TargetModel> models{CutTargetModel(
        patch, BoxPx{0, 0, static_cast<double>(side), static_cast<double>(side)}, ObjectId{4}, 0)};
    DetectorOptions options;
    options.colour.cell_px = 2.25;
    Rng rng(1);
    const DetectorOutput out =
        MakeDetector("colour", options)
            ->Detect({.image = Blocks(96, 64, {{71, 30}}, side, {200, 30, 30}), .models = models},
                     rng);
    ASSERT_EQ(out.maps.size(), 1u);
    const LikelihoodMap& map = out.maps[0].map;
    const auto best = std::max_element(map.values.begin(), map.values.end()) - map.values.begin();
    EXPECT_EQ(best % map.width, cx) << side;
    EXPECT_EQ(best / map.width, cy) << side;
    EXPECT_NEAR(map.values[static_cast<size_t>(best)], 1.0, 1.0 / 255.0) << side;
  }
}

TEST(ColourOptions, RangesAreChecked) {
  ColourOptions o;
  o.hue_bins = 1;
  EXPECT_THROW(o.Validate(), InputError);
  o = ColourOptions{};
  o.min_contrast = 0.0;
  EXPECT_THROW(o.Validate(), InputError);
}

}  // namespace
}  // namespace hcpf::vision
