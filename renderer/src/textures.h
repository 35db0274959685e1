#pragma once
// Private: procedural textures generated at load time (seeded, no files).

#include <cstdint>
#include <string>
#include <vector>

#include "hcpf/core/rng.h"
#include "hcpf/core/world.h"

namespace hcpf::renderer::internal {

struct Texture8 {
  int size = 0;      // square
  int channels = 3;  // 3 = RGB, 1 = R
  std::vector<uint8_t> texels;
};

// Tileable ground texture: "grass" | "dirt" | "asphalt" | "sand" (InputError
// otherwise, key terrain.texture). Value noise over a periodic lattice (so the
// texture repeats seamlessly), 4 octaves, tinted per material.
Texture8 GroundTexture(const std::string& kind, int size, Rng rng);

// Road mask over the terrain extent (R channel, 255 = road): a band
// `width_m` wide along every target's path with a one-texel soft edge.
Texture8 RoadMask(const WorldSpec& world, int size, double width_m);

// The next level of a mipmap chain: half the size (at least 1), each texel the
// mean of the 2 x 2 texels it covers, per channel, rounded to nearest with
// ties to even, so the chain keeps the texture's mean. `level.size` must be a
// power of two.
Texture8 HalveTexture(const Texture8& level);

}  // namespace hcpf::renderer::internal
