// An exact sampled Gaussian of float images in a fixed summation order
// (stacked_integral_blur.h, SeparableGaussianBlur).

// The same bytes on every x86-64 CPU rest on two things: each output value
// is one expression evaluated in a fixed order, element by element (vector
// lanes of any width and the scalar ends of the loops compute it alike), and
// no multiply-add is fused, which the project's -ffp-contract=off
// (CMakeLists.txt) guarantees and this file asks for itself as well; built
// with GCC's default (fast) contraction and -mfma the AVX-512 build would
// differ.
// (Clang has no such pragma; its builds, the fuzz preset, take the flag.)
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC optimize("fp-contract=off")
#endif

#include <cmath>
#include <cstddef>
#include <vector>

#include "hcpf/core/check.h"
#include "hcpf/core/instruction_set.h"
#include "hcpf/vision/stacked_integral_blur.h"

namespace hcpf::vision {

namespace {

// Taps 0..radius of the symmetric kernel: OpenCV's getGaussianKernel for a
// float image (ksize = round(8 sigma + 1) | 1), in double, normalised, then
// float.
std::vector<float> HalfKernel(double sigma) {
  const int ksize = static_cast<int>(std::lround(sigma * 8.0 + 1.0)) | 1;
  const int radius = ksize / 2;
  std::vector<double> w(static_cast<size_t>(ksize));
  double sum = 0.0;
  for (int i = 0; i < ksize; ++i) {
    const double d = i - radius;
    w[static_cast<size_t>(i)] = std::exp(-d * d / (2.0 * sigma * sigma));
    sum += w[static_cast<size_t>(i)];
  }
  std::vector<float> half(static_cast<size_t>(radius) + 1);
  for (int i = 0; i <= radius; ++i) {
    half[static_cast<size_t>(i)] = static_cast<float>(w[static_cast<size_t>(radius + i)] / sum);
  }
  return half;
}

// The two passes on raw rows, always inlined, so that each instruction-set
// build below vectorises them for its own instruction set.

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

// The passes built for AVX-512, AVX2 and the x86-64 baseline (SSE2); a call
// runs the build of the CPU's widest set, or of the set a test chose
// (hcpf/core/instruction_set.h). Every build computes the same bytes
// (tests/separable_gaussian_blur_test.cc runs each and compares it with a
// scalar sum); the wider ones are faster (docs/performance.md).
HCPF_DISPATCHED(void, BlurPasses,
                (const float* in, int w, int h, const float* k, int r, float* out, float* padded),
                (in, w, h, k, r, out, padded),
                { SeparableBlurPasses(in, w, h, k, r, out, padded); })

}  // namespace

void SeparableGaussianBlur(const GreyImageF& input, double sigma, GreyImageF& output) {
  HCPF_CHECK(sigma > 0.0 && sigma <= 64.0) << "sigma " << sigma;
  HCPF_CHECK(&input != &output);
  const int w = input.width, h = input.height;
  HCPF_CHECK(w >= 0 && h >= 0 &&
             input.pixels.size() == static_cast<size_t>(w) * static_cast<size_t>(h));
  output.width = w;
  output.height = h;
  output.pixels.resize(input.pixels.size());
  if (w == 0 || h == 0) return;
  const std::vector<float> k = HalfKernel(sigma);
  const int r = static_cast<int>(k.size()) - 1;

  std::vector<float> padded(static_cast<size_t>(w + 2 * r));
  BlurPasses(input.pixels.data(), w, h, k.data(), r, output.pixels.data(), padded.data());
}

}  // namespace hcpf::vision
