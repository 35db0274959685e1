// SKS detector benchmark (issue 11 item 3 target):
//   BM_SksFrame/whole     640 x 480 frame, 5 target models, whole-frame search:
//                         <= 15 ms per frame on one core
//   BM_SksFrame/windowed  the same frame and models, each model searched in a
//                         window of 3 x its predicted box (the tracker's case)
// One core: OpenCV's own threads are switched off (cv::setNumThreads(1)).
// The frame: grass-like ground (two sinusoids, per-pixel texture, dark
// bushes), five vehicles (56 x 28 px, three designs, headings 0-150 deg)
// rendered with 4 x 4 supersampling, plus sensor noise; the models are cut
// from a first frame, the timed frame has every vehicle moved by a few pixels
// and turned by a few degrees.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <opencv2/core.hpp>
#include <vector>

#include "hcpf/core/image.h"
#include "hcpf/core/rng.h"
#include "hcpf/core/types.h"
#include "hcpf/vision/detector.h"
#include "hcpf/vision/sks.h"

namespace {

using namespace hcpf;
using namespace hcpf::vision;

constexpr int kWidth = 640, kHeight = 480;
constexpr double kLength = 56.0, kBreadth = 28.0;

// A vehicle part: a rectangle in the vehicle's own pixels (x forward from the
// rear, y across), its colour = body colour x shade + add.
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
    default:  // truck: cab, gap, cargo bed with a hatch and a rib
      return {{0, 0, 56, 28, 0.9, 50}, {44, 4, 6, 20, 0.15, 0}, {37, 0, 4, 28, 0.1, 10},
              {2, 2, 33, 24, 0.6, 0},  {9, 8, 14, 12, 1.0, 70}, {26, 2, 5, 24, 0.35, 0}};
  }
}

struct Vehicle {
  ObjectId id;
  int design;
  double cx, cy, heading_deg;
  std::array<double, 3> rgb;
};

double Sat(double v) { return std::clamp(v, 0.0, 255.0); }

RgbImage Render(const std::vector<Vehicle>& vehicles, uint64_t noise_seed) {
  RgbImage image{.width = kWidth, .height = kHeight};
  image.pixels.resize(3 * static_cast<size_t>(kWidth) * kHeight);
  Rng ground(5);  // the ground is the same in every frame; the noise is not
  std::vector<std::array<double, 3>> bushes(kWidth * kHeight / 4000);
  for (auto& b : bushes)
    b = {ground.Uniform(0, kWidth), ground.Uniform(0, kHeight), ground.Uniform(3, 9)};
  Rng noise(noise_seed);
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      double t = 12.0 * std::sin(0.11 * x + 1.0) * std::sin(0.07 * y + 2.0) +
                 8.0 * std::sin(0.31 * x + 0.23 * y + 0.5) + 6.0 * (ground.Uniform() - 0.5);
      double g = 1.0;
      for (const auto& b : bushes) {
        if (std::hypot(x + 0.5 - b[0], y + 0.5 - b[1]) < b[2]) g = 0.65;
      }
      uint8_t* p = image.at(x, y);
      p[0] = static_cast<uint8_t>(std::lround(Sat(g * (90 + t) + 4.0 * (noise.Uniform() - 0.5))));
      p[1] = static_cast<uint8_t>(std::lround(Sat(g * (120 + t) + 4.0 * (noise.Uniform() - 0.5))));
      p[2] = static_cast<uint8_t>(
          std::lround(Sat(g * (60 + 0.5 * t) + 4.0 * (noise.Uniform() - 0.5))));
    }
  }
  // Vehicles: 4 x 4 samples per pixel over each vehicle's bounding box; a
  // sample takes the last part containing it, else the ground pixel.
  for (const Vehicle& v : vehicles) {
    const std::vector<Part> parts = Design(v.design);
    const double a = v.heading_deg * std::numbers::pi / 180.0;
    const double c = std::cos(a), s = std::sin(a);
    const double half = 0.5 * std::hypot(kLength, kBreadth) + 1.0;
    for (int y = static_cast<int>(v.cy - half); y <= static_cast<int>(v.cy + half); ++y) {
      for (int x = static_cast<int>(v.cx - half); x <= static_cast<int>(v.cx + half); ++x) {
        if (x < 0 || y < 0 || x >= kWidth || y >= kHeight) continue;
        uint8_t* p = image.at(x, y);
        std::array<double, 3> sum{};
        for (int sy = 0; sy < 4; ++sy) {
          for (int sx = 0; sx < 4; ++sx) {
            const double dx = x + (sx + 0.5) / 4.0 - v.cx, dy = y + (sy + 0.5) / 4.0 - v.cy;
            // Into the vehicle's frame (heading counter-clockwise on screen).
            const double u = c * dx - s * dy + 0.5 * kLength, w = s * dx + c * dy + 0.5 * kBreadth;
            const Part* hit = nullptr;
            for (const Part& part : parts) {
              if (u >= part.x && u < part.x + part.w && w >= part.y && w < part.y + part.h)
                hit = &part;
            }
            for (int k = 0; k < 3; ++k)
              sum[k] += hit ? Sat(v.rgb[k] * hit->shade + hit->add) : p[k];
          }
        }
        for (int k = 0; k < 3; ++k) p[k] = static_cast<uint8_t>(std::lround(sum[k] / 16.0));
      }
    }
  }
  return image;
}

std::vector<Vehicle> Vehicles(double shift, double turn_deg) {
  return {{ObjectId{1}, 0, 120 + shift, 110 - shift, 0 + turn_deg, {200, 40, 30}},
          {ObjectId{2}, 1, 420 - shift, 90 + shift, 30 + turn_deg, {40, 70, 190}},
          {ObjectId{3}, 2, 300 + shift, 250 + shift, 90 + turn_deg, {210, 200, 40}},
          {ObjectId{4}, 0, 150 - shift, 380 + shift, 150 + turn_deg, {60, 60, 70}},
          {ObjectId{5}, 2, 520 + shift, 370 - shift, 120 + turn_deg, {230, 230, 225}}};
}

// The vehicle's axis-aligned box.
BoxPx BoxOf(const Vehicle& v) {
  const double a = v.heading_deg * std::numbers::pi / 180.0;
  const double c = std::abs(std::cos(a)), s = std::abs(std::sin(a));
  return BoxPx::FromCentre(v.cx, v.cy, c * kLength + s * kBreadth, s * kLength + c * kBreadth);
}

void BM_SksFrame(benchmark::State& state, bool windowed) {
  cv::setNumThreads(1);
  const RgbImage first = Render(Vehicles(0.0, 0.0), 1);
  std::vector<TargetModel> models;
  for (const Vehicle& v : Vehicles(0.0, 0.0)) {
    models.push_back(CutTargetModel(first, BoxOf(v), v.id, 0));
  }
  const RgbImage frame = Render(Vehicles(3.0, 4.0), 2);
  std::vector<SearchWindow> windows;
  if (windowed) {
    for (const Vehicle& v : Vehicles(2.0, 0.0)) windows.push_back({v.id, BoxOf(v)});
  }
  const auto detector = MakeSksDetector(SksOptions{});
  Rng rng(1);
  size_t found = 0;
  for (auto _ : state) {
    const DetectorOutput out =
        detector->Detect({.image = frame, .frame = 1, .models = models, .windows = windows}, rng);
    found = out.detections.size();
    benchmark::DoNotOptimize(out.maps.data());
  }
  // How many of the 5 models were detected in the timed frame (a sanity
  // check on the workload, not a figure of merit).
  state.counters["detections"] = static_cast<double>(found);
  state.SetItemsProcessed(state.iterations());  // frames
}
BENCHMARK_CAPTURE(BM_SksFrame, whole, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_SksFrame, windowed, true)->Unit(benchmark::kMillisecond);

}  // namespace
