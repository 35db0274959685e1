#include <gtest/gtest.h>

#include <algorithm>

#include "hcpf/vision/detectors.h"
#include "synthetic_scene.h"

namespace hcpf::vision {
namespace {

using testing::Frame;
using testing::Targets;

struct Scene {
  std::vector<TargetModel> models;
  RgbImage frame;
};

Scene MovedScene() {
  Scene s;
  const RgbImage first = Frame(Targets());
  for (const auto& t : Targets()) s.models.push_back(CutTargetModel(first, t.box, t.id, 0));
  s.frame = Frame(Targets(3.0, -2.0));
  return s;
}

DetectorOutput DetectOn(const Detector& d, const Scene& s) {
  Rng rng(11);
  return d.Detect({.image = s.frame, .frame = 1, .models = s.models}, rng);
}

TEST(FusedDetector, NamesItsPartsAndTakesTheirNeeds) {
  const DetectorOptions options;
  const auto fused = MakeDetector("ncc+diff", options);
  ASSERT_NE(fused, nullptr);
  EXPECT_EQ(fused->name(), "ncc+diff");
  EXPECT_TRUE(fused->uses_models());
  EXPECT_EQ(fused->history(), MakeDetector("diff", options)->history());
  EXPECT_GT(fused->history(), 0);
}

TEST(FusedDetector, RejectsRepeatedUnknownAndEmptyParts) {
  const DetectorOptions options;
  EXPECT_EQ(MakeDetector("sks+sks", options), nullptr);
  EXPECT_EQ(MakeDetector("sks+", options), nullptr);
  EXPECT_EQ(MakeDetector("+sks", options), nullptr);
  EXPECT_EQ(MakeDetector("sks+prca2", options), nullptr);
  EXPECT_NE(MakeDetector("sks+prca+ncc", options), nullptr);
}

// NCC and colour both find every vehicle where it moved: fused, each target
// keeps one detection (the two agree at IoU >= 0.5), whose score is the
// noisy-OR of the two parts' scores.
TEST(FusedDetector, AgreeingDetectionsBecomeOneWithTheNoisyOrScore) {
  const DetectorOptions options;
  const Scene s = MovedScene();
  const DetectorOutput ncc = DetectOn(*MakeDetector("ncc", options), s);
  const DetectorOutput colour = DetectOn(*MakeDetector("colour", options), s);
  const DetectorOutput fused = DetectOn(*MakeDetector("ncc+colour", options), s);
  ASSERT_EQ(ncc.detections.size(), 3u);
  ASSERT_EQ(colour.detections.size(), 3u);
  ASSERT_EQ(fused.detections.size(), 3u);
  for (const Detection& f : fused.detections) {
    const auto of = [&](const DetectorOutput& o) {
      return *std::find_if(o.detections.begin(), o.detections.end(),
                           [&](const Detection& d) { return d.target == f.target; });
    };
    const Detection a = of(ncc);
    const Detection b = of(colour);
    ASSERT_GE(Iou(a.box, b.box), 0.5) << "the parts agree on target " << Value(*f.target);
    EXPECT_NEAR(f.score, 1.0 - (1.0 - a.score) * (1.0 - b.score), 1e-12);
    // The kept box is the higher-scoring part's.
    EXPECT_EQ(f.box, a.score >= b.score ? a.box : b.box);
  }
}

// Each fused map is the mean of the parts' maps scaled to a peak of 1, on the
// finer part's grid: checked cell by cell against the parts' own maps.
TEST(FusedDetector, MapIsTheMeanOfThePartsPeakNormalisedMaps) {
  DetectorOptions options;
  options.ncc.cell_px = 4.0;
  options.colour.cell_px = 8.0;
  const Scene s = MovedScene();
  const DetectorOutput ncc = DetectOn(*MakeDetector("ncc", options), s);
  const DetectorOutput colour = DetectOn(*MakeDetector("colour", options), s);
  const DetectorOutput fused = DetectOn(*MakeDetector("colour+ncc", options), s);
  ASSERT_EQ(fused.maps.size(), s.models.size());
  for (size_t m = 0; m < s.models.size(); ++m) {
    const LikelihoodMap& f = fused.maps[m].map;
    EXPECT_EQ(fused.maps[m].target, s.models[m].target);
    EXPECT_EQ(f.cell_px, 4.0);
    EXPECT_EQ(f.width, 80);
    EXPECT_EQ(f.height, 60);
    const LikelihoodMap& a = ncc.maps[m].map;
    const LikelihoodMap& b = colour.maps[m].map;
    const double pa = *std::max_element(a.values.begin(), a.values.end());
    const double pb = *std::max_element(b.values.begin(), b.values.end());
    ASSERT_GT(pa, 0.0);
    ASSERT_GT(pb, 0.0);
    for (int cy = 0; cy < f.height; cy += 7) {
      for (int cx = 0; cx < f.width; cx += 5) {
        const double x = (cx + 0.5) * 4.0;
        const double y = (cy + 0.5) * 4.0;
        const double expected = 0.5 * (a.Sample(x, y) / pa + b.Sample(x, y) / pb);
        EXPECT_NEAR(f.At(cx, cy), expected, 1e-5) << "cell " << cx << ", " << cy;
      }
    }
  }
}

}  // namespace
}  // namespace hcpf::vision
