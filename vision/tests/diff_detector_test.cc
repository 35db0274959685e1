#include <gtest/gtest.h>

#include "hcpf/core/error.h"
#include "hcpf/vision/detectors.h"
#include "synthetic_scene.h"

namespace hcpf::vision {
namespace {

using testing::VideoFrame;
using testing::VideoTargets;

// The tests' video moves 4 px per frame, so consecutive frames (gap 1).
DiffOptions WithGap1(DiffOptions o) {
  o.frame_gap = 1;
  return o;
}

DetectorOutput DiffAt(int f, const DiffOptions& options = {}) {
  const RgbImage now = VideoFrame(f);
  const RgbImage one = VideoFrame(f - 1), two = VideoFrame(f - 2);
  const std::vector<ImageView> previous = {one, two};
  Rng rng(1);
  return MakeDetector("diff", DetectorOptions{.diff = WithGap1(options)})
      ->Detect({.image = now, .frame = f, .previous = previous}, rng);
}

// The camera moves (2, 1) px per frame and vehicle 1 drives 4 px per frame
// (+x): after registration only vehicle 1 differs from both earlier frames:
// where it is now and was not (its front, its roof and stripe edges), and
// the 4 px behind it that it covered in both earlier frames and has left.
// Every detection lies within its current box extended 4 px backwards, with
// 2 px of smoothing and closing margin; the parked vehicles 2 and 3 give none.
TEST(DiffDetector, FindsTheMovingVehicleNotTheParkedOnesUnderCameraMotion) {
  for (int f : {2, 3, 5}) {
    const DetectorOutput out = DiffAt(f);
    ASSERT_FALSE(out.detections.empty()) << "frame " << f;
    const BoxPx mover = VideoTargets(f)[0].box;
    for (const Detection& d : out.detections) {
      EXPECT_FALSE(d.target.has_value());
      EXPECT_GE(d.box.left, mover.left - 4 - 2) << f;
      EXPECT_LE(d.box.right(), mover.right() + 2) << f;
      EXPECT_GE(d.box.top, mover.top - 2) << f;
      EXPECT_LE(d.box.bottom(), mover.bottom() + 2) << f;
      EXPECT_GT(d.score, 0.0);
      EXPECT_LE(d.score, 1.0);
    }
    EXPECT_TRUE(out.maps.empty());
  }
}

// Without registration (a threshold no registered difference reaches, and
// the same frames): nothing; before two earlier frames exist: nothing.
TEST(DiffDetector, NeedsTwoEarlierFramesAndRealMotion) {
  const RgbImage now = VideoFrame(2);
  Rng rng(1);
  const auto diff = MakeDetector("diff", DetectorOptions{.diff = WithGap1({})});
  EXPECT_EQ(diff->history(), 2);
  EXPECT_EQ(MakeDetector("diff", DetectorOptions{})->history(), 10);  // default gap 5
  EXPECT_FALSE(diff->uses_models());
  const std::vector<ImageView> one = {VideoFrame(1)};
  EXPECT_TRUE(diff->Detect({.image = now, .previous = one}, rng).detections.empty());
  const std::vector<ImageView> same = {now, now};
  EXPECT_TRUE(diff->Detect({.image = now, .previous = same}, rng).detections.empty());
}

// With a gap of 2 frames the detector reads previous[1] and previous[3]
// (newest first) and nothing else: the gap-1 video's two earlier frames put
// in those slots, and an unrelated frame in the others, give the gap-1
// result.
TEST(DiffDetector, FrameGapPicksTheEarlierFrames) {
  const RgbImage now = VideoFrame(2), one = VideoFrame(1), two = VideoFrame(0);
  const RgbImage other = VideoFrame(7);  // never read at gap 2
  const std::vector<ImageView> previous = {other, one, other, two};
  DiffOptions o;
  o.frame_gap = 2;
  Rng rng(1);
  const DetectorOutput gap2 = MakeDetector("diff", DetectorOptions{.diff = o})
                                  ->Detect({.image = now, .previous = previous}, rng);
  EXPECT_EQ(gap2.detections, DiffAt(2).detections);
  EXPECT_FALSE(gap2.detections.empty());
}

TEST(DiffOptions, RangesAreChecked) {
  DiffOptions o;
  o.threshold = 0;
  EXPECT_THROW(o.Validate(), InputError);
  o = DiffOptions{};
  o.smooth_sigma_px = 0.1;
  EXPECT_THROW(o.Validate(), InputError);
}

}  // namespace
}  // namespace hcpf::vision
