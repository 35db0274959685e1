#include <gtest/gtest.h>

#include <algorithm>

#include "hcpf/core/error.h"
#include "hcpf/vision/detectors.h"
#include "synthetic_scene.h"

namespace hcpf::vision {
namespace {

using testing::Frame;
using testing::ModelsAtFrame0;
using testing::Targets;

TEST(TargetModel, CutsTheBoxRoundedOutwardsAndClipped) {
  const RgbImage image = Frame(Targets());
  const TargetModel m = CutTargetModel(image, BoxPx{10.5, 20.2, 5.0, 3.0}, ObjectId{4}, 7);
  EXPECT_EQ(m.patch.width, 6);   // columns 10 .. 15
  EXPECT_EQ(m.patch.height, 4);  // rows 20 .. 23
  EXPECT_EQ(m.target, ObjectId{4});
  EXPECT_EQ(m.frame, 7);
  EXPECT_EQ(m.patch.at(0, 0)[1], image.at(10, 20)[1]);
  EXPECT_EQ(m.patch.at(5, 3)[2], image.at(15, 23)[2]);
  const TargetModel edge = CutTargetModel(image, BoxPx{315, 235, 20, 20}, ObjectId{5}, 0);
  EXPECT_EQ(edge.patch.width, 5);
  EXPECT_EQ(edge.patch.height, 5);
  EXPECT_EQ(CutTargetModel(image, BoxPx{400, 10, 5, 5}, ObjectId{6}, 0).patch.width, 0);
}

// The vehicles move by (3, -2) px; each model's patch reappears exactly, so
// the whole-frame match is at the moved box with correlation 1 (up to float
// rounding in OpenCV's sums: 1e-4).
TEST(NccDetector, FindsEachTargetWhereItMovedInTheWholeFrame) {
  const std::vector<TargetModel> models = ModelsAtFrame0();
  const RgbImage moved = Frame(Targets(3.0, -2.0));
  Rng rng(1);
  const DetectorOutput out =
      MakeDetector("ncc", DetectorOptions{})->Detect({.image = moved, .models = models}, rng);
  ASSERT_EQ(out.detections.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    const Detection& d = out.detections[i];
    EXPECT_EQ(d.target, models[i].target);
    EXPECT_EQ(d.box, Targets(3.0, -2.0)[i].box);
    EXPECT_NEAR(d.score, 1.0, 1e-4);
  }
}

// Windowed: the template is scaled to the predicted box (here 20 % larger
// than the model), and the search is limited to the window, so a second
// vehicle of the same colour outside the window is not found.
TEST(NccDetector, WindowedSearchScalesTheTemplateAndIgnoresLookAlikesOutside) {
  const std::vector<TargetModel> models = ModelsAtFrame0();
  std::vector<testing::SyntheticTarget> scene = Targets(3.0, -2.0);
  scene.push_back({ObjectId{9}, BoxPx{250, 200, 24, 12}, {200, 40, 30}});  // a red twin
  const RgbImage moved = Frame(scene);
  const BoxPx truth = scene[0].box;
  const std::vector<SearchWindow> windows = {
      {ObjectId{1}, BoxPx::FromCentre(truth.centre_x() + 2, truth.centre_y() - 1, 28.8, 14.4)}};
  Rng rng(1);
  const DetectorOutput out =
      MakeDetector("ncc", DetectorOptions{})
          ->Detect({.image = moved, .models = std::span(models).first(1), .windows = windows}, rng);
  ASSERT_EQ(out.detections.size(), 1u);
  const Detection& d = out.detections[0];
  EXPECT_EQ(d.box.width, 29);  // the predicted size, rounded
  EXPECT_EQ(d.box.height, 14);
  // The scaled template's best alignment puts its centre within 3 px of the
  // vehicle's (a 1.2x template over a 24 x 12 vehicle).
  EXPECT_NEAR(d.box.centre_x(), truth.centre_x(), 3.0);
  EXPECT_NEAR(d.box.centre_y(), truth.centre_y(), 3.0);
}

// The map holds a match at its template's centre, which for a template of
// odd width is the middle of a pixel. A model of 23 x 11 px cut from inside
// vehicle 1 (columns 60-82, rows 50-60) and the vehicle moved by (3, 0): the
// best match's top-left is (63, 50), its centre (63 + 11.5, 50 + 5.5) =
// (74.5, 55.5), which with cells of 2.25 px lies in cell (33, 24) (74.5 /
// 2.25 = 33.1, 55.5 / 2.25 = 24.7). Pooled by the centre pixel's index
// (74 / 2.25 = 32.9), it went to cell 32, before its centre's.
TEST(NccDetector, TheMapHoldsAMatchAtItsTemplatesCentre) {
  const TargetModel model = CutTargetModel(Frame(Targets()), BoxPx{60, 50, 23, 11}, ObjectId{1}, 0);
  ASSERT_EQ(model.patch.width, 23);
  DetectorOptions options;
  options.ncc.cell_px = 2.25;
  Rng rng(1);
  const DetectorOutput out =
      MakeDetector("ncc", options)
          ->Detect({.image = Frame(Targets(3.0, 0.0)), .models = std::span(&model, 1)}, rng);
  ASSERT_EQ(out.detections.size(), 1u);
  EXPECT_EQ(out.detections[0].box, (BoxPx{63, 50, 23, 11}));
  ASSERT_EQ(out.maps.size(), 1u);
  const LikelihoodMap& map = out.maps[0].map;
  const auto best = std::max_element(map.values.begin(), map.values.end()) - map.values.begin();
  EXPECT_EQ(best % map.width, 33);
  EXPECT_EQ(best / map.width, 24);
  EXPECT_NEAR(map.values[static_cast<size_t>(best)], 1.0, 1e-4);
}

TEST(NccDetector, BelowTheThresholdNothingIsDetected) {
  const std::vector<TargetModel> models = ModelsAtFrame0();
  const RgbImage empty_ground = Frame({});
  Rng rng(1);
  const DetectorOutput out = MakeDetector("ncc", DetectorOptions{})
                                 ->Detect({.image = empty_ground, .models = models}, rng);
  EXPECT_TRUE(out.detections.empty());
  ASSERT_EQ(out.maps.size(), 3u);
}

TEST(NccOptions, RangesAreChecked) {
  NccOptions o;
  o.min_correlation = 0.0;
  EXPECT_THROW(o.Validate(), InputError);
  o = NccOptions{};
  o.window_scale = 0.5;
  EXPECT_THROW(o.Validate(), InputError);
}

}  // namespace
}  // namespace hcpf::vision
