// The CPU half of collecting a frame (src/rgba_split.h): the word-wise RGBA
// split and instance-id count against a plain per-pixel reference.

#include "rgba_split.h"

#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

namespace hcpf::renderer::internal {
namespace {

// Widths around the four-pixel step (the tail loop runs for 1-3 leftover
// pixels) and the sixteen-pixel step (0-15 leftover), ids sparse as in a
// frame (most pixels 0) and dense, ids up to 255; both paths (the sixteen-
// pixel one runs only where the CPU has AVX-512 VBMI).
TEST(RgbaSplit, MatchesAPerPixelSplitAtEveryWidth) {
  std::mt19937 random(7);
  for (int width : {1, 2, 3, 4, 5, 6, 7, 8, 9, 13, 15, 16, 17, 20, 31, 32, 33, 64, 67, 650}) {
    for (int dense : {0, 1}) {
      const int height = 5;
      const size_t pixels = static_cast<size_t>(width) * height;
      std::vector<uint8_t> rgba(4 * pixels);
      for (size_t i = 0; i < pixels; ++i) {
        for (int c = 0; c < 3; ++c) rgba[4 * i + c] = static_cast<uint8_t>(random() & 0xFF);
        const bool target = dense == 1 ? random() % 2 == 0 : random() % 17 == 0;
        rgba[4 * i + 3] = target ? static_cast<uint8_t>(1 + random() % 255) : 0;
      }
      // The reference: byte by byte.
      std::vector<uint8_t> expected_rgb(3 * pixels);
      std::vector<int64_t> count(256, 0);
      std::vector<int> x0(256, width), y0(256, height), x1(256, -1), y1(256, -1);
      for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
          const size_t i = static_cast<size_t>(y) * width + x;
          for (int c = 0; c < 3; ++c) expected_rgb[3 * i + c] = rgba[4 * i + c];
          const int id = rgba[4 * i + 3];
          if (id == 0) continue;
          ++count[id];
          x0[id] = std::min(x0[id], x);
          x1[id] = std::max(x1[id], x);
          y0[id] = std::min(y0[id], y);
          y1[id] = std::max(y1[id], y);
        }
      }
      for (const bool words_only : {false, true}) {
        std::vector<uint8_t> rgb(3 * pixels, 0xAB);
        VisibleIds ids(256, width, height);
        SplitRgba(rgba.data(), width, height, rgb.data(), &ids, words_only);
        EXPECT_EQ(rgb, expected_rgb) << "width " << width << " words only " << words_only;
        EXPECT_EQ(ids.count, count) << "width " << width << " words only " << words_only;
        EXPECT_EQ(ids.x0, x0) << "width " << width << " words only " << words_only;
        EXPECT_EQ(ids.x1, x1) << "width " << width << " words only " << words_only;
        EXPECT_EQ(ids.y0, y0) << "width " << width << " words only " << words_only;
        EXPECT_EQ(ids.y1, y1) << "width " << width << " words only " << words_only;
        // Without ids (no ground truth) the colour is the same.
        std::vector<uint8_t> colour_only(3 * pixels, 0xCD);
        SplitRgba(rgba.data(), width, height, colour_only.data(), nullptr, words_only);
        EXPECT_EQ(colour_only, expected_rgb) << "width " << width << " words only " << words_only;
      }
    }
  }
}

}  // namespace
}  // namespace hcpf::renderer::internal
