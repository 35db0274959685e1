#pragma once
// Private: the two passes of SeparableGaussianBlur on raw rows, always
// inlined, so that each instruction-set clone of the library's blur
// (separable_gaussian_blur.cc) and of the test that checks the clones
// (tests/separable_gaussian_blur_test.cc) vectorises them for its own
// instruction set.
//
// The same bytes on every x86-64 CPU rest on two things: each output value
// is one expression evaluated in a fixed order, element by element (vector
// lanes of any width and the scalar ends of the loops compute it alike),
// and no multiply-add is fused, which the project's -ffp-contract=off
// (CMakeLists.txt) guarantees and separable_gaussian_blur.cc asks for
// itself as well; built with GCC's default (fast) contraction and -mfma the
// results would differ.

#include <cstddef>

namespace hcpf::vision::internal {

// acc[x] = k c[x].
[[gnu::always_inline]] inline void ScaledRow(float* __restrict acc, const float* __restrict c,
                                             float k, int w) {
  for (int x = 0; x < w; ++x) acc[x] = k * c[x];
}

// acc[x] += k (a[x] + b[x]) (a may be b: the clamped rows at an edge).
[[gnu::always_inline]] inline void AddPairRow(float* __restrict acc, const float* __restrict a,
                                              const float* __restrict b, float k, int w) {
  for (int x = 0; x < w; ++x) acc[x] += k * (a[x] + b[x]);
}

// The blur of the w x h image `in` (rows of w floats, w, h >= 1) by the
// symmetric kernel of taps k[0..r], into `out` (not `in`): down the columns,
// row y = k0 row(y) + sum_{i=1..r} k_i (row(y - i) + row(y + i)), rows
// clamped; then along each row of `out` in place, from a copy padded by r
// edge values on each side in `padded` (w + 2r floats).
[[gnu::always_inline]] inline void SeparableBlurPasses(const float* in, int w, int h,
                                                       const float* k, int r, float* out,
                                                       float* padded) {
  const auto row = [w](const float* image, int y) {
    return image + static_cast<std::ptrdiff_t>(y) * w;
  };
  for (int y = 0; y < h; ++y) {
    float* acc = out + static_cast<std::ptrdiff_t>(y) * w;
    ScaledRow(acc, row(in, y), k[0], w);
    for (int i = 1; i <= r; ++i) {
      AddPairRow(acc, row(in, y - i < 0 ? 0 : y - i), row(in, y + i > h - 1 ? h - 1 : y + i), k[i],
                 w);
    }
  }
  for (int y = 0; y < h; ++y) {
    float* acc = out + static_cast<std::ptrdiff_t>(y) * w;
    for (int x = 0; x < r; ++x) padded[x] = acc[0];
    for (int x = 0; x < w; ++x) padded[r + x] = acc[x];
    for (int x = 0; x < r; ++x) padded[r + w + x] = acc[w - 1];
    const float* p = padded + r;
    ScaledRow(acc, p, k[0], w);
    for (int i = 1; i <= r; ++i) AddPairRow(acc, p - i, p + i, k[i], w);
  }
}

}  // namespace hcpf::vision::internal
