#pragma once
// Private: the CPU half of collecting a frame, split from the GL code so a
// unit test can check it against a per-pixel reference.

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <vector>

namespace hcpf::renderer::internal {

// The visible pixels of each instance id (the colour pass's alpha; 0 is
// scenery, index 0 unused): count and inclusive bounds.
struct VisibleIds {
  std::vector<int64_t> count;
  std::vector<int> x0, y0, x1, y1;
  VisibleIds(size_t ids, int width, int height)
      : count(ids, 0), x0(ids, width), y0(ids, height), x1(ids, -1), y1(ids, -1) {}
  void Add(uint32_t id, int x, int y) {
    ++count[id];
    x0[id] = std::min(x0[id], x);
    x1[id] = std::max(x1[id], x);
    y0[id] = std::min(y0[id], y);
    y1[id] = std::max(y1[id], y);
  }
};

// Splits the colour pass's RGBA image into RGB and, with `ids`, counts the
// instance ids in its alpha, in one pass. Four pixels a step as 32-bit words
// (three words out): most pixels are scenery, and four of them cost one
// test. Against a byte loop and a separate id scan, Collect's share of the
// benchmark frame's CPU fell from 4.8 % to 2.7 % (docs/performance.md).
inline void SplitRgba(const uint8_t* rgba, int width, int height, uint8_t* rgb, VisibleIds* ids) {
  static_assert(std::endian::native == std::endian::little, "RGBA words are read little-endian");
  for (int y = 0; y < height; ++y) {
    const uint8_t* in = rgba + 4 * static_cast<size_t>(y) * width;
    uint8_t* out = rgb + 3 * static_cast<size_t>(y) * width;
    int x = 0;
    for (; x + 4 <= width; x += 4, in += 16, out += 12) {
      uint32_t p[4];
      std::memcpy(p, in, 16);
      const uint32_t w[3] = {(p[0] & 0xFFFFFFu) | (p[1] << 24),
                             ((p[1] >> 8) & 0xFFFFu) | (p[2] << 16),
                             ((p[2] >> 16) & 0xFFu) | (p[3] << 8)};
      std::memcpy(out, w, 12);
      if (ids != nullptr && ((p[0] | p[1] | p[2] | p[3]) >> 24) != 0) {
        for (int k = 0; k < 4; ++k) {
          if ((p[k] >> 24) != 0) ids->Add(p[k] >> 24, x + k, y);
        }
      }
    }
    for (; x < width; ++x, in += 4, out += 3) {
      out[0] = in[0];
      out[1] = in[1];
      out[2] = in[2];
      if (ids != nullptr && in[3] != 0) ids->Add(in[3], x, y);
    }
  }
}

}  // namespace hcpf::renderer::internal
