// The renderer's own mipmap levels (private header src/textures.h).

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "hcpf/core/rng.h"
#include "textures.h"

namespace hcpf::renderer::internal {
namespace {

Texture8 Grey(int size, std::vector<uint8_t> texels) {
  return Texture8{.size = size, .channels = 1, .texels = std::move(texels)};
}

// Each 2 x 2 block's sum 4q + r: r = 1 rounds down, r = 3 up, r = 2 to the
// even q (ties neither always up nor always down).
TEST(HalveTexture, RoundsTheMeanToNearestAndTiesToEven) {
  const std::vector<std::pair<std::vector<uint8_t>, uint8_t>> cases = {
      {{0, 0, 0, 0}, 0},          {{0, 0, 0, 1}, 0},           {{0, 0, 1, 1}, 0},
      {{0, 1, 1, 1}, 1},          {{1, 1, 1, 1}, 1},           {{1, 1, 2, 2}, 2},
      {{1, 1, 1, 2}, 1},          {{255, 255, 255, 254}, 255}, {{10, 20, 30, 40}, 25},
      {{255, 255, 255, 253}, 254}};  // 1018 = 4 * 254 + 2: 254 is even
  for (const auto& [block, expected] : cases) {
    const Texture8 half = HalveTexture(Grey(2, block));
    ASSERT_EQ(half.size, 1);
    EXPECT_EQ(half.texels.at(0), expected)
        << int{block[0]} << " " << int{block[1]} << " " << int{block[2]} << " " << int{block[3]};
  }
}

// A 4 x 4 RGB texture: each output texel is its own 2 x 2 block, each
// channel on its own; a 1 x 1 level halves to itself.
TEST(HalveTexture, AveragesEachBlockAndChannelOnItsOwn) {
  Texture8 t{.size = 4, .channels = 3, .texels = std::vector<uint8_t>(48)};
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 4; ++x) {
      uint8_t* p = &t.texels[(y * 4 + x) * 3];
      p[0] = static_cast<uint8_t>(10 * x);           // varies along x only
      p[1] = static_cast<uint8_t>(100 + 20 * y);     // along y only
      p[2] = static_cast<uint8_t>(x < 2 ? 0 : 200);  // left half 0, right 200
    }
  }
  const Texture8 half = HalveTexture(t);
  ASSERT_EQ(half.size, 2);
  ASSERT_EQ(half.channels, 3);
  // Block (1, 0): x in {2, 3}, y in {0, 1}.
  const uint8_t* p = &half.texels[(0 * 2 + 1) * 3];
  EXPECT_EQ(p[0], 25);   // (20 + 30 + 20 + 30) / 4
  EXPECT_EQ(p[1], 110);  // (100 + 100 + 120 + 120) / 4
  EXPECT_EQ(p[2], 200);
  // Block (0, 1): x in {0, 1}, y in {2, 3}.
  p = &half.texels[(1 * 2 + 0) * 3];
  EXPECT_EQ(p[0], 5);    // (0 + 10 + 0 + 10) / 4 = 5
  EXPECT_EQ(p[1], 150);  // (140 + 140 + 160 + 160) / 4
  EXPECT_EQ(p[2], 0);
  const Texture8 one = HalveTexture(HalveTexture(half));
  EXPECT_EQ(one.size, 1);
  EXPECT_EQ(one.texels, HalveTexture(half).texels);
}

double ChannelMean(const Texture8& t, int k) {
  double sum = 0.0;
  for (size_t i = k; i < t.texels.size(); i += t.channels) sum += t.texels[i];
  return sum / (static_cast<double>(t.texels.size()) / t.channels);
}

// The chain keeps the texture's brightness: on every procedural ground
// texture, the levels down to 16 x 16 have the base level's mean per channel
// within 0.15 grey levels. A texel's rounding error lies in [-1/2, 1/2] with
// mean 0 under ties to even; over 4 halvings the mean's error is a few
// hundredths (its spread at 16 x 16 is ~0.3 / 16 per level). Rounding ties up
// drifts by +1/8 per level (+0.5 at 16 x 16), and Mesa 22.3's glGenerateMipmap
// by +0.37 per level (+1.5): either fails.
TEST(HalveTexture, TheChainKeepsTheMeanOfEveryGroundTexture) {
  for (const char* kind : {"grass", "dirt", "asphalt", "sand"}) {
    const Texture8 base = GroundTexture(kind, 256, Rng(5).Fork("ground"));
    Texture8 level = base;
    while (level.size > 16) {
      level = HalveTexture(level);
      for (int k = 0; k < 3; ++k) {
        EXPECT_NEAR(ChannelMean(level, k), ChannelMean(base, k), 0.15)
            << kind << ", " << level.size << " x " << level.size << ", channel " << k;
      }
    }
  }
}

}  // namespace
}  // namespace hcpf::renderer::internal
