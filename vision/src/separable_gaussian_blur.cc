// An exact sampled Gaussian of float images in a fixed summation order
// (stacked_integral_blur.h, SeparableGaussianBlur).

// No fused multiply-add here, whatever the build's flags
// (separable_blur_kernel.h).
#pragma GCC optimize("fp-contract=off")

#include <cmath>
#include <cstddef>
#include <vector>

#include "hcpf/core/check.h"
#include "hcpf/vision/stacked_integral_blur.h"
#include "separable_blur_kernel.h"

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

// The passes, cloned for AVX-512, AVX2 and the x86-64 baseline (SSE2): the
// loader picks the widest the CPU has. Every clone computes the same bytes
// (separable_blur_kernel.h; tests/separable_gaussian_blur_test.cc compares
// each with a scalar sum); the wider ones are faster (docs/performance.md).
__attribute__((target_clones("avx512f", "avx2", "default"))) void BlurPasses(const float* in, int w,
                                                                             int h, const float* k,
                                                                             int r, float* out,
                                                                             float* padded) {
  internal::SeparableBlurPasses(in, w, h, k, r, out, padded);
}

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
