// An exact sampled Gaussian of float images in a fixed summation order
// (stacked_integral_blur.h, SeparableGaussianBlur).

// No fused multiply-add here, whatever the build's flags (see Row below).
#pragma GCC optimize("fp-contract=off")

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <vector>

#include "hcpf/core/check.h"
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

// The same bytes on every x86-64 CPU rest on two things: each output value
// is one expression evaluated in a fixed order (vector lanes and the scalar
// ends of Eigen's loops compute it alike), and no multiply-add is fused,
// which the project's -ffp-contract=off (CMakeLists.txt) guarantees; built
// with GCC's default (fast) contraction and -mfma the results would differ
// (a review checked both), so this file asks for it itself as well.
using Row = Eigen::Map<Eigen::ArrayXf>;
using ConstRow = Eigen::Map<const Eigen::ArrayXf>;

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

  // Down the columns, a whole row at a time, into `output`: its row y is
  // k0 row(y) + sum_i k_i (row(y - i) + row(y + i)), rows clamped.
  for (int y = 0; y < h; ++y) {
    Row acc(output.row(y), w);
    acc = k[0] * ConstRow(input.row(y), w);
    for (int i = 1; i <= r; ++i) {
      acc += k[static_cast<size_t>(i)] * (ConstRow(input.row(std::max(0, y - i)), w) +
                                          ConstRow(input.row(std::min(h - 1, y + i)), w));
    }
  }
  // Along each row of `output`, in place: from a copy of the row padded by
  // r edge values on each side (the only buffer: one row, not a frame).
  std::vector<float> padded(static_cast<size_t>(w + 2 * r));
  for (int y = 0; y < h; ++y) {
    const float* src = output.row(y);
    std::fill(padded.begin(), padded.begin() + r, src[0]);
    std::copy(src, src + w, padded.begin() + r);
    std::fill(padded.begin() + r + w, padded.end(), src[w - 1]);
    Row acc(output.row(y), w);
    acc = k[0] * ConstRow(padded.data() + r, w);
    for (int i = 1; i <= r; ++i) {
      acc += k[static_cast<size_t>(i)] *
             (ConstRow(padded.data() + r - i, w) + ConstRow(padded.data() + r + i, w));
    }
  }
}

}  // namespace hcpf::vision
