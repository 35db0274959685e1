#pragma once
// A synthetic 640x480 aerial frame pair for the detector benchmarks
// (prca_bench, detectors_bench): a grass-like ground built the way the
// renderer builds its ground texture (value-noise octaves from 160 px down to
// a 2 px grain), an asphalt road, tree crowns, and 5 vehicles (oriented
// 28 x 14 px boxes with windscreen, rear window, roof and a cast shadow),
// anti-aliased by 4 x 4 supersampling. Models are cut from frame 0; frame 1
// has every vehicle moved and turned a little; `windows` are frame 1's boxes.

#include <algorithm>
#include <cmath>
#include <vector>

#include "hcpf/core/rng.h"
#include "hcpf/vision/detector.h"

namespace hcpf::bench {

using namespace hcpf::vision;

constexpr int kWidth = 640;
constexpr int kHeight = 480;

// Smooth value noise in [0, 1) over a lattice of `cell` px.
class ValueNoise {
 public:
  ValueNoise(double cell, uint64_t seed) : cell_(cell) {
    nx_ = static_cast<int>(std::ceil(kWidth / cell)) + 2;
    ny_ = static_cast<int>(std::ceil(kHeight / cell)) + 2;
    Rng rng(seed);
    lattice_.resize(static_cast<size_t>(nx_) * ny_);
    for (double& v : lattice_) v = rng.Uniform();
  }
  double operator()(double x, double y) const {
    const double fx = x / cell_;
    const double fy = y / cell_;
    const int x0 = static_cast<int>(fx);
    const int y0 = static_cast<int>(fy);
    const double tx = Smooth(fx - x0);
    const double ty = Smooth(fy - y0);
    const double a = At(x0, y0) + tx * (At(x0 + 1, y0) - At(x0, y0));
    const double b = At(x0, y0 + 1) + tx * (At(x0 + 1, y0 + 1) - At(x0, y0 + 1));
    return a + ty * (b - a);
  }

 private:
  static double Smooth(double t) { return t * t * (3.0 - 2.0 * t); }
  double At(int i, int j) const { return lattice_[static_cast<size_t>(j) * nx_ + i]; }
  double cell_;
  int nx_ = 0;
  int ny_ = 0;
  std::vector<double> lattice_;
};

struct Vehicle {
  ObjectId id;
  double cx, cy;     // centre, px
  double angle_deg;  // heading
  double rgb[3];     // body colour, 0..1
};

// Colour of a vehicle at body coordinates (u along, v across, both in
// [-1, 1]), or nothing (alpha 0) outside it.
inline bool VehicleColour(const Vehicle& v, double u, double w, double out[3]) {
  if (std::abs(u) > 1.0 || std::abs(w) > 1.0) return false;
  double k = 1.0;
  if (u > 0.30 && u < 0.55 && std::abs(w) < 0.85) k = 0.2;     // windscreen
  if (u < -0.55 && u > -0.75 && std::abs(w) < 0.85) k = 0.25;  // rear window
  if (u >= -0.55 && u <= 0.30 && std::abs(w) < 0.8) k = 1.25;  // roof
  for (int c = 0; c < 3; ++c) out[c] = std::min(1.0, v.rgb[c] * k);
  return true;
}

inline RgbImage MakeFrame(const std::vector<Vehicle>& vehicles, double noise_sigma, uint64_t seed) {
  const ValueNoise low(160, 11), mid(80, 12), fine(20, 13), grain(2.5, 14);
  const double base[3] = {0.30, 0.42, 0.18};
  const double variation[3] = {0.10, 0.12, 0.06};
  constexpr double kLength = 28.0, kBreadth = 14.0;
  RgbImage image{.width = kWidth, .height = kHeight};
  image.pixels.resize(3 * static_cast<size_t>(kWidth) * kHeight);
  Rng noise(seed);
  for (int y = 0; y < kHeight; ++y) {
    for (int x = 0; x < kWidth; ++x) {
      double acc[3] = {0, 0, 0};
      // 4 x 4 samples per pixel: anti-aliased edges, as a renderer's
      // multisampling gives.
      for (int s = 0; s < 16; ++s) {
        const double px = x + (s % 4 + 0.5) / 4.0;
        const double py = y + (s / 4 + 0.5) / 4.0;
        const double broad = 0.65 * (low(px, py) - 0.5) + 0.35 * (mid(px, py) - 0.5);
        const double detail = 0.6 * (fine(px, py) - 0.5) + 0.4 * (grain(px, py) - 0.5);
        double c[3];
        for (int k = 0; k < 3; ++k) c[k] = base[k] + 2.0 * variation[k] * broad + 0.2 * detail;
        // A road across the frame and three tree crowns.
        if (std::abs(py - (0.35 * px + 150.0)) < 22.0) {
          for (int k = 0; k < 3; ++k) c[k] = 0.25 + 0.08 * detail;
        }
        const double trees[3][3] = {{520, 90, 26}, {90, 380, 20}, {420, 400, 30}};
        for (const auto& t : trees) {
          if (std::hypot(px - t[0], py - t[1]) < t[2]) {
            c[0] = 0.10 + 0.1 * detail;
            c[1] = 0.22 + 0.2 * detail;
            c[2] = 0.08;
          }
        }
        for (const Vehicle& v : vehicles) {
          const double a = v.angle_deg * M_PI / 180.0;
          const double dx = px - v.cx, dy = py - v.cy;
          const double u = (std::cos(a) * dx + std::sin(a) * dy) / (0.5 * kLength);
          const double w = (-std::sin(a) * dx + std::cos(a) * dy) / (0.5 * kBreadth);
          // Shadow: the body's footprint shifted 4 px right and down.
          const double su = (std::cos(a) * (dx - 4) + std::sin(a) * (dy - 4)) / (0.5 * kLength);
          const double sw = (-std::sin(a) * (dx - 4) + std::cos(a) * (dy - 4)) / (0.5 * kBreadth);
          if (std::abs(su) <= 1.0 && std::abs(sw) <= 1.0) {
            for (double& k : c) k *= 0.45;
          }
          double body[3];
          if (VehicleColour(v, u, w, body)) std::copy(body, body + 3, c);
        }
        for (int k = 0; k < 3; ++k) acc[k] += c[k] / 16.0;
      }
      uint8_t* p = image.at(x, y);
      for (int k = 0; k < 3; ++k) {
        const double n = noise_sigma > 0.0 ? noise_sigma * noise.Normal() : 0.0;
        p[k] = static_cast<uint8_t>(std::clamp(std::lround(255.0 * acc[k] + n), 0L, 255L));
      }
    }
  }
  return image;
}

inline std::vector<Vehicle> Vehicles(int frame) {
  const double t = frame;
  return {{ObjectId{1}, 120 + 3 * t, 100 + 1 * t, 10 + 4 * t, {0.80, 0.15, 0.12}},
          {ObjectId{2}, 300 + 2 * t, 260 - 2 * t, 20 + 4 * t, {0.15, 0.25, 0.75}},
          {ObjectId{3}, 470 - 3 * t, 200 + 2 * t, 95 + 4 * t, {0.85, 0.80, 0.20}},
          {ObjectId{4}, 200 + 1 * t, 400 - 3 * t, 150 + 4 * t, {0.90, 0.90, 0.88}},
          {ObjectId{5}, 560 - 2 * t, 330 + 1 * t, 250 + 4 * t, {0.10, 0.10, 0.12}}};
}

// The vehicle's axis-aligned box (its 28 x 14 footprint turned by the angle).
inline BoxPx BoxOf(const Vehicle& v) {
  const double a = v.angle_deg * M_PI / 180.0;
  const double w = 28.0 * std::abs(std::cos(a)) + 14.0 * std::abs(std::sin(a));
  const double h = 28.0 * std::abs(std::sin(a)) + 14.0 * std::abs(std::cos(a));
  return BoxPx::FromCentre(v.cx, v.cy, w, h);
}

// What the differencing detector reads, which looks g frames back and 2g
// (g = frame_gap): the vehicles of frames 2g (now), g (before) and 0
// (earlier) over the same ground, a still camera (its registration still
// runs: corners, LK, RANSAC).
struct DiffVideo {
  RgbImage now, before, earlier;
  // DetectorInput::previous: previous[i] is frame 2g - 1 - i; the detector
  // reads only frames g and 0. Views of this video's frames.
  std::vector<ImageView> Previous(int g) const {
    std::vector<ImageView> previous(2 * static_cast<size_t>(g), ImageView(before));
    previous.back() = earlier;
    return previous;
  }
};

inline DiffVideo MakeDiffVideo(int g) {
  return {MakeFrame(Vehicles(2 * g), 0.0, 3), MakeFrame(Vehicles(g), 0.0, 2),
          MakeFrame(Vehicles(0), 0.0, 1)};
}

struct Scene {
  RgbImage frame;
  std::vector<TargetModel> models;
  std::vector<SearchWindow> windows;
};

inline const Scene& GetScene(double noise_sigma) {
  static const Scene clean = [] {
    Scene s;
    const RgbImage first = MakeFrame(Vehicles(0), 0.0, 1);
    for (const Vehicle& v : Vehicles(0)) {
      s.models.push_back(CutTargetModel(first, BoxOf(v), v.id, 0));
    }
    s.frame = MakeFrame(Vehicles(1), 0.0, 2);
    for (const Vehicle& v : Vehicles(1)) s.windows.push_back({v.id, BoxOf(v)});
    return s;
  }();
  static const Scene noisy = [] {
    Scene s = clean;
    s.frame = MakeFrame(Vehicles(1), 4.0, 2);
    return s;
  }();
  return noise_sigma > 0.0 ? noisy : clean;
}

}  // namespace hcpf::bench
