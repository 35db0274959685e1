#include <gtest/gtest.h>

#include <algorithm>
#include <iterator>
#include <opencv2/imgproc.hpp>

#include "cv_image.h"
#include "hcpf/core/error.h"
#include "hcpf/core/rng.h"
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

// A faintly textured ground (8 px blocks, grey 100..115) that the camera
// crosses at (2, 1) px per frame, and four black-and-white chequered
// vehicles (32 x 16 px, 8 px squares) driving 4 px per frame: nearly all of
// the frame's strong corners are on the vehicles, which move. Registration
// must rest on the ground: each vehicle is then one detection, within its
// box extended 4 px backwards (the ghost of the footprint it left) plus 3 px
// of smoothing; and nothing else. Found when corners came from
// goodFeaturesToTrack's global best (quality 1 % of the strongest): all of
// them on the vehicles, a wrong similarity or none, so no detection on the
// benchmark frames (bench/detectors_bench.cc, BM_Diff).
struct Chequer {
  int x, y, dx, dy;  // top left at frame 0, px; motion, px per frame
};
constexpr Chequer kChequers[] = {
    {20, 20, 4, 0}, {120, 150, 0, 4}, {200, 40, -4, 0}, {60, 100, 0, -4}};
BoxPx ChequerBox(const Chequer& c, int f) {
  return {static_cast<double>(c.x + c.dx * f), static_cast<double>(c.y + c.dy * f), 32, 16};
}
RgbImage FaintGroundFrame(int f) {
  RgbImage image{.width = 320, .height = 240};
  image.pixels.resize(3 * 320 * 240);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      uint8_t level = 0;
      bool on_vehicle = false;
      for (const Chequer& c : kChequers) {
        const BoxPx b = ChequerBox(c, f);
        if (x < b.left || x >= b.right() || y < b.top || y >= b.bottom()) continue;
        on_vehicle = true;
        const int u = x - static_cast<int>(b.left), v = y - static_cast<int>(b.top);
        level = ((u / 8 + v / 8) % 2 == 0) ? 250 : 10;
      }
      if (!on_vehicle) {
        const uint64_t bx = static_cast<uint64_t>((x + 2 * f) / 8);
        const uint64_t by = static_cast<uint64_t>((y + f) / 8);
        level = static_cast<uint8_t>(100 + Rng(bx * 1000 + by).UniformInt(16));
      }
      uint8_t* p = image.at(x, y);
      p[0] = p[1] = p[2] = level;
    }
  }
  return image;
}

TEST(DiffDetector, RegistersOnTheGroundWhenTheStrongCornersMove) {
  const int f = 3;
  const RgbImage now = FaintGroundFrame(f), one = FaintGroundFrame(f - 1),
                 two = FaintGroundFrame(f - 2);
  const std::vector<ImageView> previous = {one, two};
  Rng rng(1);
  const DetectorOutput out = MakeDetector("diff", DetectorOptions{.diff = WithGap1({})})
                                 ->Detect({.image = now, .frame = f, .previous = previous}, rng);
  ASSERT_EQ(out.detections.size(), std::size(kChequers));
  for (const Chequer& c : kChequers) {
    BoxPx b = ChequerBox(c, f);
    // Extended 4 px backwards along its motion, and 3 px all round: the
    // smoothing's support reaches 3 px, and with 240 grey levels between
    // the squares its tail still passes the threshold there.
    if (c.dx > 0) b.left -= 4, b.width += 4;
    if (c.dx < 0) b.width += 4;
    if (c.dy > 0) b.top -= 4, b.height += 4;
    if (c.dy < 0) b.height += 4;
    b = BoxPx{b.left - 3, b.top - 3, b.width + 6, b.height + 6};
    const auto inside = [&](const Detection& d) {
      return d.box.left >= b.left && d.box.right() <= b.right() && d.box.top >= b.top &&
             d.box.bottom() <= b.bottom();
    };
    EXPECT_EQ(std::count_if(out.detections.begin(), out.detections.end(), inside), 1)
        << "vehicle at " << b.left << ", " << b.top;
  }
}

// The mover of the tests' video is striped: what differs from both earlier
// frames is its front, its stripe edges and the strip it left, fragments a
// few px apart. They are one detection (merge_px); without merging
// (merge_px 0) the same frames give several, each a false positive beside
// the one that matches.
TEST(DiffDetector, FragmentsOfOneVehicleAreOneDetection) {
  for (int f : {2, 3, 5}) {
    EXPECT_EQ(DiffAt(f).detections.size(), 1u) << "frame " << f;
  }
  DiffOptions unmerged;
  unmerged.merge_px = 0;
  EXPECT_GT(DiffAt(3, unmerged).detections.size(), 1u);
}

// The registration fits its warp on corners tracked at half resolution and
// applies it with cv::warpAffine at full resolution: the two must share one
// pixel frame. A bright pixel at full-resolution column 40, row 24 is
// brightest at half-resolution (20, 12) after cv::pyrDown, and that point
// maps back to (40, 24); a small square's centroid at half resolution maps
// back to its own, off the pixel grid too.
TEST(DiffDetector, HalfResolutionPointsMapBackToTheirFullResolutionPixels) {
  cv::Mat dot = cv::Mat::zeros(48, 80, CV_32F);
  dot.at<float>(24, 40) = 1.0f;
  cv::Mat half;
  cv::pyrDown(dot, half);
  cv::Point peak;
  cv::minMaxLoc(half, nullptr, nullptr, nullptr, &peak);
  EXPECT_EQ(peak, cv::Point(20, 12));
  const cv::Point2f back = internal::FullResolutionOfHalf(cv::Point2f(peak));
  EXPECT_FLOAT_EQ(back.x, 40.0f);
  EXPECT_FLOAT_EQ(back.y, 24.0f);
  // A 4 x 4 square over columns 30..33 and rows 16..19: centroid (31.5, 17.5).
  cv::Mat square = cv::Mat::zeros(48, 80, CV_32F);
  square(cv::Rect(30, 16, 4, 4)).setTo(1.0f);
  cv::pyrDown(square, half);
  const cv::Moments m = cv::moments(half);
  const cv::Point2f centroid = internal::FullResolutionOfHalf(
      cv::Point2f(static_cast<float>(m.m10 / m.m00), static_cast<float>(m.m01 / m.m00)));
  EXPECT_NEAR(centroid.x, 31.5f, 1e-3f);
  EXPECT_NEAR(centroid.y, 17.5f, 1e-3f);
}

TEST(DiffOptions, RangesAreChecked) {
  DiffOptions o;
  o.threshold = 0;
  EXPECT_THROW(o.Validate(), InputError);
  o = DiffOptions{};
  o.smooth_sigma_px = 0.1;
  EXPECT_THROW(o.Validate(), InputError);
  o = DiffOptions{};
  o.merge_px = -1;
  EXPECT_THROW(o.Validate(), InputError);
}

}  // namespace
}  // namespace hcpf::vision
