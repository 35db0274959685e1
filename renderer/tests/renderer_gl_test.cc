// Renderer tests that need a GL context (label gl). One context per test
// binary, shared by every case; GL errors are checked after each case.
// The backend is HCPF_TEST_GL_BACKEND (compiled in: "osmesa" or "egl").

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "gl_api.h"
#include "gl_texture.h"
#include "hcpf/core/error.h"
#include "hcpf/core/ground_truth.h"
#include "hcpf/renderer/renderer.h"
#include "textures.h"

#ifndef HCPF_TEST_GL_BACKEND
#define HCPF_TEST_GL_BACKEND "auto"
#endif

namespace hcpf::renderer {
namespace {

std::shared_ptr<GlContext> g_context;

// LP_NUM_THREADS as this process started (static initialisation, before the
// environment below makes the first context), unset = nullopt.
const std::optional<std::string> g_lp_num_threads_at_start =
    std::getenv("LP_NUM_THREADS") != nullptr
        ? std::optional<std::string>(std::getenv("LP_NUM_THREADS"))
        : std::nullopt;

class GlEnvironment final : public ::testing::Environment {
 public:
  void SetUp() override { g_context = GlContext::Create(ParseGlBackend(HCPF_TEST_GL_BACKEND)); }
  void TearDown() override { g_context.reset(); }
};
[[maybe_unused]] ::testing::Environment* const g_environment =
    ::testing::AddGlobalTestEnvironment(new GlEnvironment);

class RendererGl : public ::testing::Test {
 protected:
  void TearDown() override { EXPECT_NO_THROW(g_context->CheckNoError("end of test case")); }
  static std::unique_ptr<SceneRenderer> Make(const WorldSpec& world,
                                             const RendererOptions& options = {},
                                             uint64_t seed = 1) {
    return SceneRenderer::Create(world, options, Rng(seed), g_context);
  }
};

constexpr double kFocalPx = 400.0;
constexpr int kWidth = 160;
constexpr int kHeight = 120;

// A flat world seen by a nadir camera at `altitude_m` with fx = fy = 400 px
// on a 160 x 120 image (hfov = 2 atan(80 / 400)), image right = east, image
// down = south (CameraPose::LookAt uses north as "up" for vertical views).
WorldSpec NadirWorld(double altitude_m) {
  WorldSpec w;
  w.frames = 1;
  w.terrain.texture = "sand";
  w.sun.azimuth_deg = 135.0;
  w.sun.elevation_deg = 50.0;
  w.camera.width_px = kWidth;
  w.camera.height_px = kHeight;
  w.camera.hfov_deg = 2.0 * std::atan(0.5 * kWidth / kFocalPx) * 180.0 / std::numbers::pi;
  w.camera.path.push_back({0, {0.0, 0.0, altitude_m}, {0.0, 0.0, 0.0}});
  return w;
}

TargetSpec BoxTarget(int id, Eigen::Vector2d at, Eigen::Vector3d dims = {4.0, 2.0, 1.5}) {
  TargetSpec t;
  t.id = ObjectId{id};
  t.dimensions_m = dims;
  t.tint = {0.8, 0.2, 0.2};
  t.path.waypoints_m = {at};
  t.path.heading_deg = 0.0;  // length along x (east)
  return t;
}

const GroundTruthObject& Only(const RenderedFrame& f) {
  EXPECT_EQ(f.ground_truth.objects.size(), 1u);
  return f.ground_truth.objects.at(0);
}

TEST_F(RendererGl, ContextReportsItsDriver) {
  const GlInfo& info = g_context->info();
  EXPECT_FALSE(info.renderer.empty());
  EXPECT_TRUE(info.core_profile) << info.version;
  EXPECT_EQ(info.backend, HCPF_TEST_GL_BACKEND);
  EXPECT_TRUE(info.platform.starts_with(info.backend)) << info.platform;
}

// The machine's own EGL devices through the real selection: indices in
// order, and `auto` takes a hardware device when there is one, OSMesa when
// there is none (a CPU-only machine: Mesa lists only its software device).
TEST_F(RendererGl, AutoPrefersAHardwareEglDeviceElseOsMesa) {
  const std::vector<EglDeviceDescription> devices = QueryEglDevices();
  bool hardware = false;
  for (size_t i = 0; i < devices.size(); ++i) {
    EXPECT_EQ(devices[i].index, static_cast<int>(i));
    hardware = hardware || !devices[i].software();
  }
  // In a child process: an OSMesa context created beside this binary's EGL
  // context leaves the EGL one unable to compile shaders afterwards (Mesa's
  // one dispatch table), which broke every later case when the binary ran
  // whole rather than one case per process as under ctest.
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        const auto context = GlContext::Create(GlBackend::kAuto);
        std::fprintf(stderr, "platform: %s\n", context->info().platform.c_str());
        std::exit(0);
      },
      ::testing::ExitedWithCode(0),
      hardware ? "platform: egl.*\\(hardware\\)" : "platform: osmesa\n");
}

TEST_F(RendererGl, NadirVehicleSpansThePredictedPixelCount) {
  WorldSpec w = NadirWorld(100.0);
  w.targets.push_back(BoxTarget(1, {0.0, 0.0}));
  const RenderedFrame f = Make(w)->Render(0);
  const GroundTruthObject& o = Only(f);
  // Seen from straight above, the box's outline is its top face at height
  // 1.5 m, i.e. depth 98.5 m: 4 m spans 400 * 4 / 98.5 = 16.24 px and 2 m
  // spans 8.12 px, centred on the principal point (80, 60).
  EXPECT_NEAR(o.visible_box.width, 400.0 * 4.0 / 98.5, 1.0);
  EXPECT_NEAR(o.visible_box.height, 400.0 * 2.0 / 98.5, 1.0);
  EXPECT_NEAR(o.visible_box.centre_x(), 80.0, 0.5);
  EXPECT_NEAR(o.visible_box.centre_y(), 60.0, 0.5);
  EXPECT_EQ(o.pixels_visible, o.pixels_total);
  EXPECT_DOUBLE_EQ(o.visible_fraction, 1.0);
  EXPECT_DOUBLE_EQ(o.truncation, 0.0);
  EXPECT_TRUE(o.in_frame);
  // Pixel centres inside [71.88, 88.12] x [55.94, 64.06]: columns 72..87 (16)
  // and rows 56..63 (8), so exactly 128 pixels.
  EXPECT_EQ(o.pixels_total, 16 * 8);
}

TEST_F(RendererGl, PixelBoxesAgreeWithAnalyticProjectionUnderShake) {
  WorldSpec w = NadirWorld(80.0);
  w.camera.path[0] = {0, {-30.0, -60.0, 70.0}, {0.0, 0.0, 0.0}};  // oblique
  w.camera.shake_px = 3.0;
  w.camera.shake_seed = 11;
  w.frames = 4;
  w.targets.push_back(BoxTarget(1, {0.0, 0.0}));
  w.targets.push_back(BoxTarget(2, {12.0, 8.0}, {6.0, 2.5, 3.0}));
  w.targets.back().path.heading_deg = 35.0;
  w.targets.push_back(BoxTarget(3, {-10.0, 10.0}, {4.5, 1.8, 1.5}));
  w.targets.back().path.heading_deg = -70.0;
  auto renderer = Make(w);
  for (int frame = 0; frame < 4; ++frame) {
    const RenderedFrame f = renderer->Render(frame);
    const FrameGroundTruth analytic = ComputeGroundTruth(w, frame);
    EXPECT_EQ(f.ground_truth.camera.intrinsics, analytic.camera.intrinsics);
    ASSERT_EQ(f.ground_truth.objects.size(), analytic.objects.size());
    for (size_t i = 0; i < analytic.objects.size(); ++i) {
      const BoxPx& p = f.ground_truth.objects[i].amodal_box;
      const BoxPx& a = analytic.objects[i].amodal_box;
      // The rendered box is the analytic box; its pixel bounds differ from
      // the projected corners only by pixel snapping (< 1 px per side).
      EXPECT_NEAR(p.left, a.left, 1.0) << "frame " << frame << " target " << i;
      EXPECT_NEAR(p.top, a.top, 1.0) << "frame " << frame << " target " << i;
      EXPECT_NEAR(p.right(), a.right(), 1.0) << "frame " << frame << " target " << i;
      EXPECT_NEAR(p.bottom(), a.bottom(), 1.0) << "frame " << frame << " target " << i;
    }
  }
}

TEST_F(RendererGl, HalfCoveredByABridgeIsHalfVisible) {
  WorldSpec w = NadirWorld(100.0);
  w.targets.push_back(BoxTarget(1, {0.0, 0.0}));
  // A deck along y covering x in [0, 10] at 5..6 m, piers far outside the
  // view. Its west edge (x = 0) projects onto the principal point column, so
  // it hides the east half of the vehicle's top face: 8 of 16 columns.
  OccluderSpec bridge;
  bridge.kind = OccluderKind::kBridge;
  bridge.from_m = {5.0, -40.0};
  bridge.to_m = {5.0, 40.0};
  bridge.width_m = 10.0;
  bridge.height_m = 6.0;
  w.occluders.push_back(bridge);
  const RenderedFrame f = Make(w)->Render(0);
  const GroundTruthObject& o = Only(f);
  EXPECT_NEAR(o.visible_fraction, 0.5, 0.05);
  EXPECT_EQ(o.pixels_total, 128);
  EXPECT_LT(o.visible_box.width, o.amodal_box.width);
  EXPECT_NEAR(o.visible_box.right(), 80.0, 1.0);
  // The analytic estimate (rays against occluder boxes) agrees.
  const FrameGroundTruth analytic = ComputeGroundTruth(w, 0);
  EXPECT_NEAR(analytic.objects.at(0).visible_fraction, 0.5, 0.05);
}

TEST_F(RendererGl, AmodalBoxContainsVisibleBox) {
  WorldSpec w = NadirWorld(60.0);
  w.camera.path[0] = {0, {-20.0, -50.0, 45.0}, {0.0, 5.0, 0.0}};
  OccluderSpec building;
  building.kind = OccluderKind::kBuilding;
  building.at_m = {0.0, -4.0};
  building.size_m = {6.0, 3.0, 5.0};
  w.occluders.push_back(building);
  OccluderSpec tree;
  tree.kind = OccluderKind::kTree;
  tree.at_m = {8.0, 0.0};
  tree.height_m = 8.0;
  w.occluders.push_back(tree);
  w.targets.push_back(BoxTarget(1, {0.0, 0.0}));
  w.targets.push_back(BoxTarget(2, {9.0, 2.0}));
  w.targets.push_back(BoxTarget(3, {-32.0, 6.0}));  // near the left border
  w.targets.push_back(BoxTarget(4, {2.0, 1.5}));    // overlaps target 1
  const RenderedFrame f = Make(w)->Render(0);
  ASSERT_EQ(f.ground_truth.objects.size(), 4u);
  int partly_hidden = 0;
  for (const GroundTruthObject& o : f.ground_truth.objects) {
    if (o.pixels_visible == 0) continue;
    EXPECT_LE(o.amodal_box.left, o.visible_box.left) << Value(o.id);
    EXPECT_LE(o.amodal_box.top, o.visible_box.top) << Value(o.id);
    EXPECT_GE(o.amodal_box.right(), o.visible_box.right()) << Value(o.id);
    EXPECT_GE(o.amodal_box.bottom(), o.visible_box.bottom()) << Value(o.id);
    EXPECT_LE(o.pixels_visible, o.pixels_total);
    if (o.visible_fraction < 0.95) ++partly_hidden;
  }
  EXPECT_GE(partly_hidden, 1);  // the scene is built so something is hidden
}

TEST_F(RendererGl, TruncationAtTheImageBorder) {
  WorldSpec w = NadirWorld(100.0);
  // Top-face centre on the left image border: u = 400 x / 98.5 + 80 = 0.
  w.targets.push_back(BoxTarget(1, {-80.0 * 98.5 / 400.0, 0.0}));
  w.targets.push_back(BoxTarget(2, {-60.0, 0.0}));  // entirely outside
  const RenderedFrame f = Make(w)->Render(0);
  ASSERT_EQ(f.ground_truth.objects.size(), 2u);
  const GroundTruthObject& half = f.ground_truth.objects[0];
  // The camera (x = 0) is east of the box, so besides the top face (u in
  // [-8.12, 8.12]) it sees the east side face, whose bottom edge (x = -17.7,
  // depth 100) projects to u = 400 (-17.7) / 100 + 80 = 9.2. The amodal box
  // is u in [-8.12, 9.2]: truncation = 8.12 / 17.32 = 0.469.
  EXPECT_NEAR(half.truncation, 8.12 / 17.32, 0.01);
  EXPECT_TRUE(half.in_frame);
  EXPECT_NEAR(half.amodal_box.left, -8.12, 0.05);
  EXPECT_EQ(half.pixels_visible, half.pixels_total);  // nothing occludes it
  // Columns 0..8 (centres 0.5 .. 8.5 <= 9.2) x rows 56..63 = 72 pixels.
  EXPECT_EQ(half.pixels_total, 72);
  const GroundTruthObject& out = f.ground_truth.objects[1];
  EXPECT_FALSE(out.in_frame);
  EXPECT_EQ(out.pixels_total, 0);
  EXPECT_DOUBLE_EQ(out.visible_fraction, 0.0);
}

TEST_F(RendererGl, DepthAndInstanceImages) {
  WorldSpec w = NadirWorld(100.0);
  w.targets.push_back(BoxTarget(7, {0.0, 0.0}));
  RendererOptions options;
  options.output_depth = true;
  options.output_instance_ids = true;
  const RenderedFrame f = Make(w, options)->Render(0);
  ASSERT_TRUE(f.depth.has_value());
  ASSERT_TRUE(f.instance_ids.has_value());
  // Nadir over flat ground: every ground pixel is at depth 100 m, the box top
  // at 98.5 m. Float depth over [0.5, ~120] m resolves well below 1 cm here.
  EXPECT_NEAR(f.depth->depth_m[60 * kWidth + 80], 98.5, 0.01);
  EXPECT_NEAR(f.depth->depth_m[5 * kWidth + 5], 100.0, 0.01);
  int64_t id_pixels = 0;
  for (int32_t id : f.instance_ids->ids) {
    if (id == 7) ++id_pixels;
    EXPECT_TRUE(id == 7 || id == -1);
  }
  EXPECT_EQ(id_pixels, Only(f).pixels_visible);
}

// Luminance (Rec. 601) of a pixel.
double Luma(const RgbImage& img, int x, int y) {
  const uint8_t* p = img.at(x, y);
  return 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
}

struct ShadowStats {
  int64_t pixels = 0;
  double angle_deg = 0.0;  // world direction (counter-clockwise from east) of the centroid
  double shaded_luma_on = 0.0;
  double shaded_luma_off = 0.0;
  double lit_luma_off = 0.0;
};

// Renders a 6 x 6 x 15 m building under a nadir camera at 200 m with the
// sun at `azimuth_deg`, elevation 45, with and without shadows; a pixel is
// shadow when shadows make it at least 40 % darker.
ShadowStats BuildingShadow(double azimuth_deg, const std::shared_ptr<GlContext>& context) {
  WorldSpec w = NadirWorld(200.0);
  w.sun.azimuth_deg = azimuth_deg;
  w.sun.elevation_deg = 45.0;
  OccluderSpec building;
  building.kind = OccluderKind::kBuilding;
  building.size_m = {6.0, 6.0, 15.0};
  w.occluders.push_back(building);
  RendererOptions on;
  RendererOptions off;
  off.shadows = false;
  const RgbImage a = SceneRenderer::Create(w, on, Rng(1), context)->Render(0).rgb;
  const RgbImage b = SceneRenderer::Create(w, off, Rng(1), context)->Render(0).rgb;
  ShadowStats s;
  double sx = 0.0, sy = 0.0, lit = 0.0;
  int64_t lit_n = 0;
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      const double la = Luma(a, x, y);
      const double lb = Luma(b, x, y);
      if (la < 0.6 * lb) {
        ++s.pixels;
        sx += x + 0.5 - 80.0;
        sy += y + 0.5 - 60.0;
        s.shaded_luma_on += la;
        s.shaded_luma_off += lb;
      } else if (std::abs(x - 80) > 10 || std::abs(y - 60) > 10) {
        lit += lb;
        ++lit_n;
      }
    }
  }
  if (s.pixels > 0) {
    // Image right = east, image down = south.
    s.angle_deg = std::atan2(-sy, sx) * 180.0 / std::numbers::pi;
    s.shaded_luma_on /= static_cast<double>(s.pixels);
    s.shaded_luma_off /= static_cast<double>(s.pixels);
  }
  s.lit_luma_off = lit / static_cast<double>(std::max<int64_t>(lit_n, 1));
  return s;
}

double AngleDiffDeg(double a, double b) {
  double d = std::fmod(a - b, 360.0);
  if (d > 180.0) d -= 360.0;
  if (d < -180.0) d += 360.0;
  return d;
}

TEST_F(RendererGl, BuildingShadowTurnsWithTheSun) {
  const ShadowStats east = BuildingShadow(90.0, g_context);    // sun in the east
  const ShadowStats south = BuildingShadow(180.0, g_context);  // sun in the south
  // The shadow points away from the sun: compass azimuth + 180, i.e. a math
  // angle of -90 - azimuth: 180 deg (west) and 90 deg (north). Its centroid
  // lies ~10 m = 20 px from the building axis; half a pixel of asymmetry is
  // 1.5 deg, so 3 deg is a safe bound.
  EXPECT_NEAR(AngleDiffDeg(east.angle_deg, 180.0), 0.0, 3.0);
  EXPECT_NEAR(AngleDiffDeg(south.angle_deg, 90.0), 0.0, 3.0);
  EXPECT_NEAR(AngleDiffDeg(east.angle_deg, south.angle_deg), 90.0, 3.0);
  // Area: the roof edge 15 m up at 45 deg throws a 6 m x 15 m strip beyond
  // the base = 90 m^2; at 200 m with f = 400 px a ground metre is 2 px, so
  // 360 px (minus ~6 px hidden under the roof's overhang in perspective).
  // PCF softens the edge over ~1 px on a ~84 px perimeter: +-25 %.
  EXPECT_NEAR(static_cast<double>(east.pixels), 354.0, 90.0);
  EXPECT_NEAR(static_cast<double>(south.pixels), 354.0, 90.0);
}

TEST_F(RendererGl, ShadowsOffRemovesTheShade) {
  const ShadowStats s = BuildingShadow(135.0, g_context);
  ASSERT_GT(s.pixels, 100);
  // With shadows the strip is dark: ambient only, 0.36 / (0.36 + 0.95 sin 45)
  // = 0.35 of the sunlit value. Without shadows the same pixels are as
  // bright as the rest of the sunlit ground (texture varies by ~10 %).
  EXPECT_LT(s.shaded_luma_on / s.shaded_luma_off, 0.45);
  EXPECT_NEAR(s.shaded_luma_off / s.lit_luma_off, 1.0, 0.1);
}

// A small scene with everything: relief, roads, the stock vehicles, every
// primitive occluder, an oblique camera.
WorldSpec GoldenWorld() {
  WorldSpec w;
  w.frames = 12;
  w.fps = 10.0;
  w.terrain.relief_m = 2.0;
  w.terrain.roads = true;
  w.terrain.seed = 5;
  w.terrain.texture = "grass";
  w.sun.azimuth_deg = 120.0;
  w.sun.elevation_deg = 40.0;
  OccluderSpec building;
  building.kind = OccluderKind::kBuilding;
  building.at_m = {15.0, 10.0};
  building.size_m = {10.0, 8.0, 12.0};
  w.occluders.push_back(building);
  OccluderSpec tree;
  tree.kind = OccluderKind::kTree;
  tree.at_m = {-12.0, 8.0};
  tree.height_m = 9.0;
  w.occluders.push_back(tree);
  OccluderSpec bridge;
  bridge.kind = OccluderKind::kBridge;
  bridge.from_m = {-5.0, -18.0};
  bridge.to_m = {-5.0, 2.0};
  bridge.width_m = 7.0;
  bridge.height_m = 6.0;
  w.occluders.push_back(bridge);
  const std::string dir = std::string(HCPF_SOURCE_DIR) + "/assets/vehicles/";
  const struct {
    const char* model;
    Eigen::Vector3d dims;
    Eigen::Vector3d tint;
    Eigen::Vector2d from;
    Eigen::Vector2d to;
  } vehicles[] = {
      {"tank.glb", {6.9, 3.6, 2.3}, {0.35, 0.38, 0.22}, {-30.0, -8.0}, {30.0, -8.0}},
      {"truck.glb", {8.0, 2.5, 3.2}, {0.7, 0.2, 0.15}, {5.0, -30.0}, {5.0, 30.0}},
      {"car.glb", {4.5, 1.84, 1.5}, {0.2, 0.3, 0.8}, {25.0, 25.0}, {-25.0, -5.0}},
  };
  int id = 1;
  for (const auto& v : vehicles) {
    TargetSpec t;
    t.id = ObjectId{id++};
    t.model = dir + v.model;
    t.dimensions_m = v.dims;
    t.tint = v.tint;
    t.path.waypoints_m = {v.from, v.to};
    t.path.speed_mps = 8.0;
    w.targets.push_back(t);
  }
  w.camera.width_px = 160;
  w.camera.height_px = 120;
  w.camera.hfov_deg = 55.0;
  w.camera.path.push_back({0, {0.0, -55.0, 50.0}, {0.0, 0.0, 0.0}});
  w.camera.path.push_back({11, {10.0, -40.0, 60.0}, {5.0, 0.0, 0.0}});
  return w;
}

// Where two frames of one size differ: how many pixels (in any channel), by
// how much at most, and the box that holds them.
struct PixelDifference {
  int count = 0;
  int max_diff = 0;
  double mean_abs = 0.0;  // over every channel value, differing or not
  int x0 = 0, y0 = 0, x1 = -1, y1 = -1;
  int pixels = 0;
  // For a failure message a person can act on.
  std::string Describe() const {
    if (count == 0) return "no pixel differs";
    return fmt::format(
        "{} of {} pixels differ, by at most {} levels, within columns {}-{}, rows {}-{}", count,
        pixels, max_diff, x0, x1, y0, y1);
  }
};

PixelDifference Compare(const RgbImage& a, const RgbImage& b) {
  PixelDifference r{.x0 = a.width, .y0 = a.height, .pixels = a.width * a.height};
  double sum = 0.0;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) {
      int d = 0;
      for (int c = 0; c < 3; ++c) {
        const size_t i = (static_cast<size_t>(y) * a.width + x) * 3 + c;
        const int channel = std::abs(int{a.pixels[i]} - int{b.pixels[i]});
        sum += channel;
        d = std::max(d, channel);
      }
      if (d == 0) continue;
      ++r.count;
      r.max_diff = std::max(r.max_diff, d);
      r.x0 = std::min(r.x0, x), r.x1 = std::max(r.x1, x);
      r.y0 = std::min(r.y0, y), r.y1 = std::max(r.y1, y);
    }
  }
  r.mean_abs = sum / static_cast<double>(a.pixels.size());
  return r;
}

// With HCPF_TEST_IMAGE_DIR set, a failing image comparison leaves its frames
// there (a GPU run's frames come back for a person to look at).
void KeepImageIfAsked(const RgbImage& image, const std::string& name) {
  const char* dir = std::getenv("HCPF_TEST_IMAGE_DIR");
  if (dir == nullptr || *dir == '\0') return;
  std::filesystem::create_directories(dir);
  WritePng(image, std::string(dir) + "/" + name);
}

void CompareWithGolden(const RgbImage& image, const std::string& name) {
  const std::string path = std::string(HCPF_SOURCE_DIR) + "/renderer/tests/golden/" + name;
  const char* regenerate = std::getenv("HCPF_REGENERATE_GOLDENS");
  if (regenerate != nullptr && std::string(regenerate) == "1") {
    WritePng(image, path);
    GTEST_SKIP() << "regenerated " << path;
  }
  ASSERT_TRUE(std::filesystem::exists(path))
      << path << " missing; run with HCPF_REGENERATE_GOLDENS=1";
  const RgbImage golden = ReadPng(path);
  ASSERT_EQ(golden.width, image.width);
  ASSERT_EQ(golden.height, image.height);
  const PixelDifference diff = Compare(image, golden);
  // Max: a pixel whose centre sits on an edge can flip to the neighbouring
  // surface when another Mesa/LLVM version rounds differently; neighbouring
  // surfaces in these scenes differ by up to ~100 grey levels (tinted
  // vehicle vs. ground), so 128 catches anything worse (a missing object,
  // a wrong colour) without failing on edge flips.
  // Mean: edge flips touch well under 1 % of pixels and filtering changes
  // are +-1 level, so a mean above 1.0 level means a systematic change
  // (lighting, shadows, texture) rather than rounding.
  constexpr int kMaxDiff = 128;
  constexpr double kMaxMean = 1.0;
  EXPECT_LE(diff.max_diff, kMaxDiff) << name << ": " << diff.Describe();
  EXPECT_LE(diff.mean_abs, kMaxMean) << name << ": " << diff.Describe();
  if (diff.max_diff > kMaxDiff || diff.mean_abs > kMaxMean) KeepImageIfAsked(image, name);
}

TEST_F(RendererGl, GoldenObliqueScene) {
  auto renderer = Make(GoldenWorld());
  CompareWithGolden(renderer->Render(0).rgb, "oblique_frame0.png");
  CompareWithGolden(renderer->Render(11).rgb, "oblique_frame11.png");
}

TEST_F(RendererGl, GoldenNadirShadows) {
  WorldSpec w = NadirWorld(120.0);
  w.terrain.texture = "grass";
  OccluderSpec building;
  building.kind = OccluderKind::kBuilding;
  building.at_m = {-8.0, 6.0};
  building.size_m = {8.0, 6.0, 10.0};
  building.yaw_deg = 20.0;
  w.occluders.push_back(building);
  w.targets.push_back(BoxTarget(1, {8.0, -5.0}));
  w.targets.back().model = std::string(HCPF_SOURCE_DIR) + "/assets/vehicles/tank.glb";
  w.targets.back().dimensions_m = {6.9, 3.6, 2.3};
  RendererOptions options;
  options.pcf_radius = 2;
  CompareWithGolden(Make(w, options)->Render(0).rgb, "nadir_shadows.png");
}

// Terrain cells the road mask cannot touch are drawn without the road
// lookups, and those no shadow can reach without the shadow lookup too
// (RendererOptions::split_road_cells); that must change no pixel. The golden
// scene at 320x240 has roads crossing the view and shadows of a building, a
// tree, a bridge and three vehicles, next to cells with neither: a cell
// wrongly taken as road-free loses its road, one wrongly taken as
// shadow-free loses its shadow (both checked by breaking the classifier).
TEST_F(RendererGl, CheaperTerrainVariantsChangeNoPixel) {
  // Each frame the terrain's cells are drawn with the cheapest variant that
  // gives the same pixels (no road lookups where no road is, no shadow
  // lookups where no caster's shadow can fall in that frame: the vehicles
  // are placed per frame). Against the unsplit path, every frame: the golden
  // scene, and a low sun with a wide filter, whose long vehicle shadows reach
  // furthest from the cells under the vehicles.
  WorldSpec w = GoldenWorld();
  w.camera.width_px = 320;
  w.camera.height_px = 240;
  WorldSpec low_sun = w;
  low_sun.sun.elevation_deg = 12.0;
  low_sun.sun.azimuth_deg = 250.0;
  RendererOptions wide;
  wide.pcf_radius = 2;
  // On llvmpipe, where the claim was made, not one pixel differs. Elsewhere
  // a difference of one level in at most one pixel in 10,000: the variants
  // are separately compiled programs, and GLSL 3.30 lets a compiler contract
  // a * b + c into a fused multiply-add in one program and not in another, so
  // one expression may differ in its last bit and flip the rounding of a
  // colour within that bit of a half level (NVIDIA H200, driver 580: one
  // pixel of 76,800, by one level). A misclassified cell loses a road or a
  // shadow over a region, by tens of levels, and is still caught.
  const bool exact = g_context->info().renderer.starts_with("llvmpipe");
  for (const auto& [world, options] : {std::pair(w, RendererOptions{}), std::pair(low_sun, wide)}) {
    RendererOptions whole = options;
    whole.split_road_cells = false;
    auto a = SceneRenderer::Create(world, options, Rng(3), g_context);
    auto b = SceneRenderer::Create(world, whole, Rng(3), g_context);
    WorldSpec no_roads = world;
    no_roads.terrain.roads = false;
    auto c = SceneRenderer::Create(no_roads, options, Rng(3), g_context);
    for (int frame = 0; frame < world.frames; ++frame) {
      const RgbImage with_split = a->Render(frame).rgb;
      const RgbImage unsplit = b->Render(frame).rgb;
      const PixelDifference diff = Compare(with_split, unsplit);
      const bool within =
          exact ? diff.count == 0 : diff.max_diff <= 1 && diff.count <= diff.pixels / 10000;
      EXPECT_TRUE(within) << "frame " << frame << ", sun elevation " << world.sun.elevation_deg
                          << ": " << diff.Describe();
      if (!within) {
        const std::string tag = fmt::format("split_sun{}_frame{}", world.sun.elevation_deg, frame);
        KeepImageIfAsked(with_split, tag + "_split.png");
        KeepImageIfAsked(unsplit, tag + "_whole.png");
      }
      // And the roads are there to be kept: without them the frame differs.
      EXPECT_NE(with_split.pixels, c->Render(frame).rgb.pixels) << "frame " << frame;
    }
  }
}

// What the GL samples is the project's own mipmap chain, level by level, and
// not the GL's glGenerateMipmap (whose filter each implementation picks: Mesa
// 22.3's levels differ from the rounded means in a third of the texels).
TEST_F(RendererGl, TexturesAreSampledFromTheRenderersOwnMipmapLevels) {
  const internal::GlApi& gl = g_context->api();
  const internal::Texture8 base = internal::GroundTexture("grass", 64, Rng(2).Fork("ground"));
  const GLuint tex = internal::UploadTexture(gl, base, /*repeat=*/true);
  gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
  internal::Texture8 expected = base;
  for (int level = 0;; ++level) {
    std::vector<uint8_t> got(expected.texels.size());
    gl.GetTexImage(GL_TEXTURE_2D, level, GL_RGB, GL_UNSIGNED_BYTE, got.data());
    EXPECT_TRUE(got == expected.texels)
        << "level " << level << " (" << expected.size << " x " << expected.size << ")";
    if (expected.size == 1) break;
    expected = internal::HalveTexture(expected);
  }
  gl.DeleteTextures(1, &tex);
}

TEST_F(RendererGl, SameSceneRendersByteIdenticalFramesTwice) {
  const WorldSpec w = GoldenWorld();
  RendererOptions options;
  options.sensor.noise_sigma = 3.0;
  options.sensor.jpeg_quality = 90;
  auto first = Make(w, options, 42);
  auto second = Make(w, options, 42);
  for (int frame : {0, 5, 11}) {
    const RenderedFrame a = first->Render(frame);
    const RenderedFrame b = second->Render(frame);
    EXPECT_EQ(a.rgb, b.rgb) << "frame " << frame;
    ASSERT_EQ(a.ground_truth.objects.size(), b.ground_truth.objects.size());
    for (size_t i = 0; i < a.ground_truth.objects.size(); ++i) {
      EXPECT_EQ(a.ground_truth.objects[i].pixels_visible, b.ground_truth.objects[i].pixels_visible);
      EXPECT_EQ(a.ground_truth.objects[i].pixels_total, b.ground_truth.objects[i].pixels_total);
      EXPECT_EQ(a.ground_truth.objects[i].amodal_box, b.ground_truth.objects[i].amodal_box);
    }
  }
  // Rendering again on the same renderer is also identical (no state leaks
  // between frames), and another seed changes the sensor noise.
  EXPECT_EQ(first->Render(5).rgb, second->Render(5).rgb);
  EXPECT_NE(Make(w, options, 43)->Render(5).rgb, first->Render(5).rgb);
}

void ExpectSameFrame(const RenderedFrame& a, const RenderedFrame& b) {
  EXPECT_EQ(a.frame, b.frame);
  EXPECT_EQ(a.rgb, b.rgb) << "frame " << a.frame;
  ASSERT_EQ(a.depth.has_value(), b.depth.has_value());
  if (a.depth) {
    EXPECT_EQ(a.depth->depth_m, b.depth->depth_m) << "frame " << a.frame;
  }
  ASSERT_EQ(a.instance_ids.has_value(), b.instance_ids.has_value());
  if (a.instance_ids) {
    EXPECT_EQ(a.instance_ids->ids, b.instance_ids->ids) << "frame " << a.frame;
  }
  ASSERT_EQ(a.ground_truth.objects.size(), b.ground_truth.objects.size());
  for (size_t i = 0; i < a.ground_truth.objects.size(); ++i) {
    const GroundTruthObject& x = a.ground_truth.objects[i];
    const GroundTruthObject& y = b.ground_truth.objects[i];
    EXPECT_EQ(x.id, y.id);
    EXPECT_EQ(x.pixels_visible, y.pixels_visible) << "frame " << a.frame << " object " << i;
    EXPECT_EQ(x.pixels_total, y.pixels_total) << "frame " << a.frame << " object " << i;
    EXPECT_EQ(x.visible_box, y.visible_box);
    EXPECT_EQ(x.amodal_box, y.amodal_box);
  }
}

// Pipelined rendering (issue 13 item 4): with two frames submitted, each
// frame's readbacks go to its own pixel-buffer objects while the next frame
// is drawn into the same framebuffer; what comes back must be what Render
// gives, colour, depth, instance ids and the count pass's totals alike.
TEST_F(RendererGl, PipelinedFramesEqualRenderedOnes) {
  const WorldSpec w = GoldenWorld();
  RendererOptions options;
  options.output_depth = true;
  options.output_instance_ids = true;
  options.sensor.noise_sigma = 2.0;
  auto reference = Make(w, options, 7);
  auto pipelined = Make(w, options, 7);
  std::vector<RenderedFrame> expected;
  for (int frame = 0; frame < w.frames; ++frame) expected.push_back(reference->Render(frame));
  int collected = 0;
  for (int frame = 0; frame < w.frames; ++frame) {
    pipelined->Submit(frame);
    if (pipelined->in_flight() == SceneRenderer::kMaxInFlight) {
      ExpectSameFrame(pipelined->Collect(), expected.at(collected++));
    }
  }
  while (pipelined->in_flight() > 0)
    ExpectSameFrame(pipelined->Collect(), expected.at(collected++));
  EXPECT_EQ(collected, w.frames);
  // Out of order too (the slots are a ring, not tied to frame numbers), and
  // Render works again once everything is collected.
  pipelined->Submit(9);
  pipelined->Submit(2);
  ExpectSameFrame(pipelined->Collect(), expected.at(9));
  ExpectSameFrame(pipelined->Collect(), expected.at(2));
  ExpectSameFrame(pipelined->Render(4), expected.at(4));
  // Without ground truth the count pass is skipped; colour is unchanged.
  options.ground_truth = false;
  auto no_truth = Make(w, options, 7);
  no_truth->Submit(3);
  no_truth->Submit(4);
  EXPECT_EQ(no_truth->Collect().rgb, expected.at(3).rgb);
  EXPECT_EQ(no_truth->Collect().rgb, expected.at(4).rgb);
}

// Collect in two steps (scenarios' ProduceFrames): CollectClean gives the
// frame before the sensor effects, and ApplySensor, run on another thread
// while this one renders the next frame, makes it Render's frame.
TEST_F(RendererGl, SensorEffectsOnAnotherThreadGiveRendersFrames) {
  const WorldSpec w = GoldenWorld();
  RendererOptions options;
  options.sensor.noise_sigma = 3.0;
  options.sensor.blur_px = 0.7;
  options.sensor.jpeg_quality = 85;
  auto reference = Make(w, options, 7);
  auto two_step = Make(w, options, 7);
  RendererOptions clean_options = options;
  clean_options.sensor = {};
  auto clean = Make(w, clean_options, 7);
  for (int frame = 0; frame < 4; ++frame) {
    two_step->Submit(frame);
    RenderedFrame f = two_step->CollectClean();
    EXPECT_EQ(f.rgb, clean->Render(frame).rgb) << "frame " << frame;
    std::thread finisher([&] { two_step->ApplySensor(f); });
    two_step->Submit(frame + 1);  // renders while the other thread works
    finisher.join();
    ExpectSameFrame(f, reference->Render(frame));
    ExpectSameFrame(two_step->Collect(), reference->Render(frame + 1));
  }
}

// Threads of this process named "llvmpipe-N": Mesa's rasteriser threads.
int LlvmpipeThreads() {
  int n = 0;
  for (const auto& task : std::filesystem::directory_iterator("/proc/self/task")) {
    std::string name;
    std::ifstream(task.path() / "comm") >> name;
    n += name.rfind("llvmpipe-", 0) == 0 ? 1 : 0;
  }
  return n;
}

// llvmpipe's rasteriser threads race on fences (gl_context.h): the first
// context of a process sets LP_NUM_THREADS=0, so frames are rasterised on
// the thread that draws them, when the environment did not ask for threads.
TEST_F(RendererGl, RasterisesOnTheDrawingThreadUnlessAskedForThreads) {
  if (g_context->info().renderer.find("llvmpipe") == std::string::npos) {
    GTEST_SKIP() << "not llvmpipe: " << g_context->info().renderer;
  }
  if (g_lp_num_threads_at_start) {
    GTEST_SKIP() << "LP_NUM_THREADS=" << *g_lp_num_threads_at_start
                 << " set for this test: kept (ContextsOfOneProcessShareOneRasteriser)";
  }
  const RenderedFrame f = Make(NadirWorld(50.0))->Render(0);
  EXPECT_EQ(f.rgb.width, kWidth);
  ASSERT_NE(std::getenv("LP_NUM_THREADS"), nullptr);
  EXPECT_STREQ(std::getenv("LP_NUM_THREADS"), "0");
  EXPECT_EQ(LlvmpipeThreads(), 0);
}

// A process has one llvmpipe rasteriser for all its GL contexts, so contexts
// drawing on two threads render in turn, whence hcpf sweep's rendered runs in
// processes of their own (SweepOptions::render_exe). This checks that
// premise on the Mesa in use, in a child process asking for two rasteriser
// threads (an explicit LP_NUM_THREADS is kept): a second context, drawing on
// a second thread, starts no rasteriser thread of its own.
TEST_F(RendererGl, ContextsOfOneProcessShareOneRasteriser) {
  if (g_context->info().renderer.find("llvmpipe") == std::string::npos) {
    GTEST_SKIP() << "not llvmpipe: " << g_context->info().renderer;
  }
  // The child is this binary run again with this environment: its first
  // context (the test environment's) is made with two threads.
  ::setenv("LP_NUM_THREADS", "2", /*overwrite=*/1);
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_EXIT(
      {
        Make(NadirWorld(50.0))->Render(0);
        const int first = LlvmpipeThreads();
        int beside = -1;
        std::thread second([&] {
          const std::shared_ptr<GlContext> context =
              GlContext::Create(ParseGlBackend(HCPF_TEST_GL_BACKEND));
          SceneRenderer::Create(NadirWorld(50.0), {}, Rng(1), context)->Render(0);
          beside = LlvmpipeThreads();
        });
        second.join();
        std::fprintf(stderr, "rasteriser threads: %d %d\n", first, beside);
        std::exit(0);
      },
      ::testing::ExitedWithCode(0), "rasteriser threads: 2 2\n");
  if (g_lp_num_threads_at_start) {
    ::setenv("LP_NUM_THREADS", g_lp_num_threads_at_start->c_str(), 1);
  } else {
    ::setenv("LP_NUM_THREADS", "0", 1);  // as the first context left it
  }
}

using RendererGlDeathTest = RendererGl;

TEST_F(RendererGlDeathTest, PipelineMisuseIsAProgrammingError) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_DEATH(Make(GoldenWorld())->Collect(), "no submitted frame");
  EXPECT_DEATH(
      {
        auto r = Make(GoldenWorld());
        r->Submit(0);
        r->Submit(1);
        r->Submit(2);
      },
      "already submitted");
  EXPECT_DEATH(
      {
        auto r = Make(GoldenWorld());
        r->Submit(0);
        r->Render(1);
      },
      "submitted frame");
}

TEST_F(RendererGl, FrameCacheGivesBackTheRenderedFrame) {
  const WorldSpec w = GoldenWorld();
  const RendererOptions options;
  const RenderedFrame f = Make(w, options)->Render(3);
  const auto root = std::filesystem::temp_directory_path() /
                    (std::string("hcpf_gl_cache_test_") + HCPF_TEST_GL_BACKEND);
  std::filesystem::remove_all(root);
  const FrameCache cache(root, PixelHash(w, options, 1));
  cache.Store(f);
  const auto loaded = cache.Load(3);
  ASSERT_TRUE(loaded.has_value());
  EXPECT_EQ(loaded->rgb, f.rgb);  // the .frame format is lossless
  ASSERT_EQ(loaded->ground_truth.objects.size(), f.ground_truth.objects.size());
  for (size_t i = 0; i < f.ground_truth.objects.size(); ++i) {
    EXPECT_EQ(loaded->ground_truth.objects[i].amodal_box, f.ground_truth.objects[i].amodal_box);
    EXPECT_EQ(loaded->ground_truth.objects[i].visible_fraction,
              f.ground_truth.objects[i].visible_fraction);
  }
  std::filesystem::remove_all(root);
}

TEST_F(RendererGl, MissingModelIsAnInputError) {
  WorldSpec w = NadirWorld(100.0);
  w.targets.push_back(BoxTarget(1, {0.0, 0.0}));
  w.targets.back().model = "/nonexistent/vehicle.glb";
  EXPECT_THROW(Make(w), InputError);
}

}  // namespace
}  // namespace hcpf::renderer
