#pragma once
// Private: the CPU half of collecting a frame, split from the GL code so a
// unit test can check it against a per-pixel reference.

#include <immintrin.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <vector>

#include "hcpf/core/instruction_set.h"

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

// Pixels [x, width) of row y, four a step as 32-bit words (three words
// out): most pixels are scenery, and four of them cost one test.
inline void SplitRgbaRowWords(const uint8_t* in, uint8_t* out, int x, int width, int y,
                              VisibleIds* ids) {
  static_assert(std::endian::native == std::endian::little, "RGBA words are read little-endian");
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

// Sixteen pixels a step: one byte permute packs 64 bytes of RGBA into 48 of
// RGB (a masked store writes just those), one test finds the non-zero
// alphas; the row's last 0-15 pixels go word-wise.
__attribute__((target("avx512f,avx512bw,avx512vbmi"))) inline void SplitRgbaVbmi(
    const uint8_t* rgba, int width, int height, uint8_t* rgb, VisibleIds* ids) {
  alignas(64) uint8_t order[64] = {};
  for (int j = 0; j < 48; ++j) order[j] = static_cast<uint8_t>(4 * (j / 3) + j % 3);
  const __m512i pack = _mm512_load_si512(order);
  const __m512i alpha = _mm512_set1_epi32(static_cast<int>(0xFF000000u));
  constexpr __mmask64 kRgbBytes = (__mmask64{1} << 48) - 1;
  for (int y = 0; y < height; ++y) {
    const uint8_t* in = rgba + 4 * static_cast<size_t>(y) * width;
    uint8_t* out = rgb + 3 * static_cast<size_t>(y) * width;
    int x = 0;
    for (; x + 16 <= width; x += 16, in += 64, out += 48) {
      const __m512i v = _mm512_loadu_si512(in);
      _mm512_mask_storeu_epi8(out, kRgbBytes, _mm512_maskz_permutexvar_epi8(kRgbBytes, pack, v));
      if (ids == nullptr) continue;
      for (__mmask16 m = _mm512_test_epi32_mask(v, alpha); m != 0; m &= m - 1) {
        const int k = std::countr_zero(static_cast<unsigned>(m));
        ids->Add(in[4 * k + 3], x + k, y);
      }
    }
    SplitRgbaRowWords(in, out, x, width, y, ids);
  }
}

// Splits the colour pass's RGBA image into RGB and, with `ids`, counts the
// instance ids in its alpha, in one pass: sixteen pixels a step where the
// CPU has AVX-512 VBMI, else (or with `words_only`) four. Against a byte
// loop and a separate id scan the word-wise pass took Collect's share of the
// benchmark frame's CPU from 4.8 % to 2.7 %; the permute is ~12x faster
// again (docs/performance.md).
inline void SplitRgba(const uint8_t* rgba, int width, int height, uint8_t* rgb, VisibleIds* ids,
                      bool words_only = false) {
  static const bool vbmi = __builtin_cpu_supports("avx512f") &&
                           __builtin_cpu_supports("avx512bw") &&
                           __builtin_cpu_supports("avx512vbmi");
  // And the active set AVX-512 (a test may choose a narrower one).
  if (vbmi && !words_only && ActiveInstructionSet() == InstructionSet::kAvx512) {
    SplitRgbaVbmi(rgba, width, height, rgb, ids);
    return;
  }
  for (int y = 0; y < height; ++y) {
    SplitRgbaRowWords(rgba + 4 * static_cast<size_t>(y) * width,
                      rgb + 3 * static_cast<size_t>(y) * width, 0, width, y, ids);
  }
}

}  // namespace hcpf::renderer::internal
