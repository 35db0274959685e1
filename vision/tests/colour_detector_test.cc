#include <gtest/gtest.h>

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

TEST(ColourDetector, GroundWithoutTheModelsColoursGivesNothing) {
  const RgbImage first = Frame(Targets());
  std::vector<TargetModel> models;
  for (const auto& t : Targets()) models.push_back(CutTargetModel(first, t.box, t.id, 0));
  Rng rng(1);
  const DetectorOutput out = MakeDetector("colour", DetectorOptions{})
                                 ->Detect({.image = Frame({}), .models = models}, rng);
  EXPECT_TRUE(out.detections.empty());
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
