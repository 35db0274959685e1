#include "textures.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "hcpf/core/error.h"

namespace hcpf::renderer::internal {
namespace {

// Periodic value noise: `cells` x `cells` random lattice, smoothstep
// interpolation, wraps at the texture edge.
std::vector<float> PeriodicNoise(int size, int cells, Rng& rng) {
  std::vector<float> lattice(static_cast<size_t>(cells) * cells);
  for (float& v : lattice) v = static_cast<float>(rng.Uniform());
  std::vector<float> out(static_cast<size_t>(size) * size);
  const float scale = static_cast<float>(cells) / static_cast<float>(size);
  for (int y = 0; y < size; ++y) {
    const float fy = (static_cast<float>(y) + 0.5f) * scale;
    const int y0 = static_cast<int>(std::floor(fy));
    float ty = fy - static_cast<float>(y0);
    ty = ty * ty * (3.0f - 2.0f * ty);
    for (int x = 0; x < size; ++x) {
      const float fx = (static_cast<float>(x) + 0.5f) * scale;
      const int x0 = static_cast<int>(std::floor(fx));
      float tx = fx - static_cast<float>(x0);
      tx = tx * tx * (3.0f - 2.0f * tx);
      const auto at = [&](int i, int j) {
        return lattice[static_cast<size_t>(((j % cells) + cells) % cells) * cells +
                       static_cast<size_t>(((i % cells) + cells) % cells)];
      };
      const float a = at(x0, y0) + tx * (at(x0 + 1, y0) - at(x0, y0));
      const float b = at(x0, y0 + 1) + tx * (at(x0 + 1, y0 + 1) - at(x0, y0 + 1));
      out[static_cast<size_t>(y) * size + x] = a + ty * (b - a);
    }
  }
  return out;
}

struct Palette {
  float base[3];
  float variation[3];  // amplitude of the low-frequency colour change
  float grain;         // amplitude of the high-frequency speckle
};

}  // namespace

Texture8 GroundTexture(const std::string& kind, int size, Rng rng) {
  Palette p;
  if (kind == "grass") {
    p = {{0.30f, 0.42f, 0.18f}, {0.10f, 0.12f, 0.06f}, 0.10f};
  } else if (kind == "dirt") {
    p = {{0.42f, 0.33f, 0.22f}, {0.10f, 0.08f, 0.06f}, 0.10f};
  } else if (kind == "asphalt") {
    p = {{0.25f, 0.25f, 0.26f}, {0.04f, 0.04f, 0.04f}, 0.08f};
  } else if (kind == "sand") {
    p = {{0.70f, 0.62f, 0.45f}, {0.08f, 0.07f, 0.05f}, 0.06f};
  } else {
    throw InputError(SourceLocation{.key = "world.terrain.texture"},
                     "one of grass, dirt, asphalt, sand", fmt::format("\"{}\"", kind));
  }
  // Octaves: 4, 8, 32 and 128 lattice cells across the texture (clamped to size).
  std::vector<float> low = PeriodicNoise(size, std::min(4, size), rng);
  std::vector<float> mid = PeriodicNoise(size, std::min(8, size), rng);
  std::vector<float> fine = PeriodicNoise(size, std::min(32, size), rng);
  std::vector<float> grain = PeriodicNoise(size, std::min(128, size), rng);
  Texture8 t;
  t.size = size;
  t.channels = 3;
  t.texels.resize(static_cast<size_t>(size) * size * 3);
  for (size_t i = 0; i < low.size(); ++i) {
    const float broad = 0.65f * (low[i] - 0.5f) + 0.35f * (mid[i] - 0.5f);
    const float detail = 0.6f * (fine[i] - 0.5f) + 0.4f * (grain[i] - 0.5f);
    for (int c = 0; c < 3; ++c) {
      const float v = p.base[c] + 2.0f * p.variation[c] * broad + 2.0f * p.grain * detail;
      t.texels[3 * i + static_cast<size_t>(c)] =
          static_cast<uint8_t>(std::clamp(v, 0.0f, 1.0f) * 255.0f + 0.5f);
    }
  }
  return t;
}

Texture8 RoadMask(const WorldSpec& world, int size, double width_m) {
  Texture8 t;
  t.size = size;
  t.channels = 1;
  t.texels.assign(static_cast<size_t>(size) * size, 0);
  const Eigen::Vector2d extent = world.terrain.size_m;
  const Eigen::Vector2d origin = -0.5 * extent;
  // Polylines: waypoint paths as given, other paths sampled once per frame.
  std::vector<std::vector<Eigen::Vector2d>> lines;
  for (const TargetSpec& target : world.targets) {
    if (target.path.kind == PathKind::kWaypoints) {
      if (target.path.waypoints_m.size() >= 2) lines.push_back(target.path.waypoints_m);
    } else {
      std::vector<Eigen::Vector2d> line;
      const int frames = std::max(world.frames, 2);
      for (int f = 0; f < frames; f += std::max(1, frames / 200)) {
        const TargetPose pose = EvaluatePath(target.path, f, world.fps);
        if (pose.present) line.push_back(pose.position_m.head<2>());
      }
      if (line.size() >= 2) lines.push_back(line);
    }
  }
  const double texel_m = extent.x() / size;
  const double half = 0.5 * width_m;
  for (const auto& line : lines) {
    for (size_t s = 1; s < line.size(); ++s) {
      const Eigen::Vector2d a = line[s - 1];
      const Eigen::Vector2d b = line[s];
      const Eigen::Vector2d lo = a.cwiseMin(b).array() - half - texel_m;
      const Eigen::Vector2d hi = a.cwiseMax(b).array() + half + texel_m;
      const int x0 = std::max(0, static_cast<int>((lo.x() - origin.x()) / extent.x() * size));
      const int x1 =
          std::min(size - 1, static_cast<int>((hi.x() - origin.x()) / extent.x() * size));
      const int y0 = std::max(0, static_cast<int>((lo.y() - origin.y()) / extent.y() * size));
      const int y1 =
          std::min(size - 1, static_cast<int>((hi.y() - origin.y()) / extent.y() * size));
      const Eigen::Vector2d ab = b - a;
      const double len2 = std::max(ab.squaredNorm(), 1e-12);
      for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
          const Eigen::Vector2d p = origin + Eigen::Vector2d((x + 0.5) / size * extent.x(),
                                                             (y + 0.5) / size * extent.y());
          const double f = std::clamp((p - a).dot(ab) / len2, 0.0, 1.0);
          const double d = (p - (a + f * ab)).norm();
          const double cover = std::clamp((half - d) / texel_m + 0.5, 0.0, 1.0);
          uint8_t& m = t.texels[static_cast<size_t>(y) * size + x];
          m = std::max(m, static_cast<uint8_t>(cover * 255.0 + 0.5));
        }
      }
    }
  }
  return t;
}

Texture8 HalveTexture(const Texture8& level) {
  Texture8 half;
  half.size = std::max(1, level.size / 2);
  half.channels = level.channels;
  half.texels.resize(static_cast<size_t>(half.size) * half.size * half.channels);
  const int c = level.channels;
  // A 1-texel level "halves" to itself; otherwise 2 x 2 blocks.
  const int step = level.size > 1 ? 2 : 1;
  const auto at = [&](int x, int y, int k) {
    return int{level.texels[(static_cast<size_t>(y) * level.size + x) * c + k]};
  };
  for (int y = 0; y < half.size; ++y) {
    for (int x = 0; x < half.size; ++x) {
      for (int k = 0; k < c; ++k) {
        const int x0 = x * step, y0 = y * step, x1 = x0 + step - 1, y1 = y0 + step - 1;
        const int sum = at(x0, y0, k) + at(x1, y0, k) + at(x0, y1, k) + at(x1, y1, k);
        // Round to nearest, a tie (sum = 4q + 2) to even q: no drift over
        // the chain (half up would brighten each level by 1/8 on average).
        int q = sum / 4;
        const int r = sum % 4;
        if (r == 3 || (r == 2 && q % 2 == 1)) ++q;
        half.texels[(static_cast<size_t>(y) * half.size + x) * c + k] = static_cast<uint8_t>(q);
      }
    }
  }
  return half;
}

}  // namespace hcpf::renderer::internal
