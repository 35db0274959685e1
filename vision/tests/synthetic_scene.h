#pragma once
// A small synthetic aerial frame for detector tests: smooth seeded ground
// texture with three distinctly coloured, striped vehicles at known boxes.

#include <cmath>
#include <vector>

#include "hcpf/core/image.h"
#include "hcpf/core/rng.h"
#include "hcpf/core/types.h"
#include "hcpf/vision/detector.h"

namespace hcpf::vision::testing {

struct SyntheticTarget {
  ObjectId id;
  BoxPx box;
  uint8_t rgb[3];
};

// Three vehicles (red, blue, yellow; 24 x 12 px with a dark stripe and a
// light roof) on a 320 x 240 ground; `shift` moves every vehicle by (dx, dy).
inline std::vector<SyntheticTarget> Targets(double dx = 0.0, double dy = 0.0) {
  return {{ObjectId{1}, BoxPx{60 + dx, 50 + dy, 24, 12}, {200, 40, 30}},
          {ObjectId{2}, BoxPx{200 + dx, 80 + dy, 24, 12}, {30, 60, 190}},
          {ObjectId{3}, BoxPx{120 + dx, 170 + dy, 24, 12}, {210, 200, 40}}};
}

inline RgbImage Frame(const std::vector<SyntheticTarget>& targets) {
  RgbImage image{.width = 320, .height = 240};
  image.pixels.resize(3 * 320 * 240);
  // Ground: grass-like green with seeded low-amplitude texture (deterministic).
  Rng rng(7);
  std::vector<double> phase(6);
  for (double& p : phase) p = 6.283185307 * rng.Uniform();
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const double t = 12.0 * std::sin(0.11 * x + phase[0]) * std::sin(0.07 * y + phase[1]) +
                       8.0 * std::sin(0.31 * x + 0.23 * y + phase[2]);
      uint8_t* p = image.at(x, y);
      p[0] = static_cast<uint8_t>(std::lround(90 + t));
      p[1] = static_cast<uint8_t>(std::lround(120 + t));
      p[2] = static_cast<uint8_t>(std::lround(60 + 0.5 * t));
    }
  }
  for (const SyntheticTarget& t : targets) {
    const int x0 = static_cast<int>(std::lround(t.box.left));
    const int y0 = static_cast<int>(std::lround(t.box.top));
    for (int y = y0; y < y0 + static_cast<int>(t.box.height); ++y) {
      for (int x = x0; x < x0 + static_cast<int>(t.box.width); ++x) {
        if (x < 0 || y < 0 || x >= image.width || y >= image.height) continue;
        uint8_t* p = image.at(x, y);
        const int u = x - x0, v = y - y0;
        const bool stripe = u >= 6 && u < 9;                     // dark windscreen stripe
        const bool roof = u >= 11 && u < 20 && v >= 3 && v < 9;  // light roof
        for (int c = 0; c < 3; ++c) {
          p[c] = stripe ? static_cast<uint8_t>(t.rgb[c] / 4)
                 : roof ? static_cast<uint8_t>(std::min(255, t.rgb[c] + 50))
                        : t.rgb[c];
        }
      }
    }
  }
  return image;
}

// One model per target of Targets(), cut from Frame(Targets()) at frame 0.
inline std::vector<TargetModel> ModelsAtFrame0() {
  const RgbImage first = Frame(Targets());
  std::vector<TargetModel> models;
  for (const auto& t : Targets()) models.push_back(CutTargetModel(first, t.box, t.id, 0));
  return models;
}

// Frame `f` of a short video for model-free detectors: ground of 8 x 8 px
// grey blocks of seeded levels (corners everywhere, for registration) seen
// by a camera moving (2, 1) px per frame, and the three vehicles of
// Targets(): 2 and 3 parked (they move with the ground in the image),
// vehicle 1 driving 4 px per frame along +x on the ground.
inline std::vector<SyntheticTarget> VideoTargets(int f) {
  std::vector<SyntheticTarget> targets = Targets(-2.0 * f, -1.0 * f);
  targets[0].box.left += 4.0 * f;
  return targets;
}

inline RgbImage VideoFrame(int f) {
  RgbImage image = Frame(VideoTargets(f));
  const std::vector<SyntheticTarget> targets = VideoTargets(f);
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      bool on_vehicle = false;
      for (const SyntheticTarget& t : targets) {
        on_vehicle = on_vehicle ||
                     (x >= t.box.left && x < t.box.right() && y >= t.box.top && y < t.box.bottom());
      }
      if (on_vehicle) continue;
      // Ground block (bx, by) in ground coordinates: image + camera offset.
      const uint64_t bx = static_cast<uint64_t>((x + 2 * f) / 8);
      const uint64_t by = static_cast<uint64_t>((y + f) / 8);
      const uint8_t level = static_cast<uint8_t>(60 + Rng(bx * 1000 + by).UniformInt(121));
      uint8_t* p = image.at(x, y);
      p[0] = level;
      p[1] = static_cast<uint8_t>(level + 20);
      p[2] = level;
    }
  }
  return image;
}

}  // namespace hcpf::vision::testing
