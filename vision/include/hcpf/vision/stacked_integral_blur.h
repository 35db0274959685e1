#pragma once
// Grey images for vision/, and the stacked integral image blur: a Gaussian
// blur approximated by a weighted sum of K concentric box filters, all read
// from ONE integral image (Bhatia 2011, ch. 4, "Stacked Integral Image").
// docs/vision.md ("Stacked integral image blur") gives the derivation of the
// radii and weights, their table, the measured accuracy and speed.

#include <cstdint>
#include <vector>

#include "hcpf/core/image.h"

namespace hcpf::vision {

// 8-bit grey, row-major, top row first, one byte per pixel, rows packed
// (pixels.size() == width * height). Plain data.
struct GreyImage {
  int width = 0;
  int height = 0;
  std::vector<uint8_t> pixels;
  uint8_t& at(int x, int y) { return pixels[static_cast<size_t>(y) * width + x]; }
  uint8_t at(int x, int y) const { return pixels[static_cast<size_t>(y) * width + x]; }
  uint8_t* row(int y) { return pixels.data() + static_cast<size_t>(y) * width; }
  const uint8_t* row(int y) const { return pixels.data() + static_cast<size_t>(y) * width; }
  friend bool operator==(const GreyImage&, const GreyImage&) = default;
};

// Single-precision grey (grey levels 0..255, not rounded), same layout.
struct GreyImageF {
  int width = 0;
  int height = 0;
  std::vector<float> pixels;
  float& at(int x, int y) { return pixels[static_cast<size_t>(y) * width + x]; }
  float at(int x, int y) const { return pixels[static_cast<size_t>(y) * width + x]; }
  float* row(int y) { return pixels.data() + static_cast<size_t>(y) * width; }
  const float* row(int y) const { return pixels.data() + static_cast<size_t>(y) * width; }
  friend bool operator==(const GreyImageF&, const GreyImageF&) = default;
};

// ITU-R BT.601 luma of an RGB view in integer arithmetic:
//   Y = (9798 R + 19235 G + 3735 B + 16384) >> 15,
// i.e. 0.299 R + 0.587 G + 0.114 B with 15-bit coefficients (they sum to
// 2^15, so greys stay exact), rounded half up. Bit for bit what OpenCV 4's
// cv::cvtColor(..., COLOR_RGB2GRAY) gives for 8-bit input (tested).
GreyImage ToGrey(const ImageView& rgb);

// K concentric square boxes, box k (2 r_k + 1) x (2 r_k + 1) pixels normalised
// by its area, weighted w_k. As a 2-D kernel:
//   h(dx, dy) = sum over k with max(|dx|, |dy|) <= r_k of w_k / (2 r_k + 1)^2.
// Plain data: a caller may build its own, as long as the invariants hold.
struct StackedBoxKernel {
  double sigma = 0.0;           // the Gaussian it stands for (px); informational
  std::vector<int> radii;       // r_k, strictly increasing, >= 0
  std::vector<double> weights;  // w_k > 0, summing to 1

  int boxes() const { return static_cast<int>(radii.size()); }
  int max_radius() const { return radii.empty() ? 0 : radii.back(); }
  // Per-axis variance of the kernel, px^2: sum_k w_k (n_k^2 - 1) / 12 with
  // n_k = 2 r_k + 1 (the variance of a discrete uniform on n_k points). Its
  // covariance is this times the identity (the boxes are squares).
  double Variance() const;
  friend bool operator==(const StackedBoxKernel&, const StackedBoxKernel&) = default;
};

// The K-box kernel for a Gaussian of standard deviation `sigma` (px):
// - exact second moment: Variance() == sigma^2 and sum w_k == 1, both
//   equality constraints of the fit (met to ~1e-15 relative);
// - radii and weights minimise the L2 distance between the kernel's 1-D
//   marginal (a sum of 1-D boxes) and the sampled, normalised Gaussian
//   profile exp(-x^2 / 2 sigma^2) / Z under those constraints: the weights
//   by the exact KKT solve for each candidate radius set, the radii
//   (r_K <= ceil(3 sigma) + K) by exhaustive search when there are at most
//   5,000 candidate sets, else by coordinate descent from four fixed
//   starts. Only sets whose weights are all positive count.
// - `boxes` boxes whenever a set of that size has positive weights (from
//   sigma = 0.67 on, checked on a 0.01 grid); below, K = 4 or 5 may give the
//   best set of 3 or 4 boxes, so boxes() may be < `boxes`.
// Preconditions (HCPF_CHECK, a bug to violate): 0.5 <= sigma <= 64 and
// 3 <= boxes <= 5. Below 0.5 the Gaussian is nearly a delta: its sampled
// profile's variance is already 14 % below sigma^2 at 0.5 and 50 % at 0.4,
// so matching sigma^2 no longer approximates it. 64 is far beyond what a
// 640 x 480 frame needs (the largest box is then 325 px wide).
// Deterministic (no randomness, fixed search order); at most ~2 ms on one
// core (bench/vision_bench.cc, BM_MakeStackedBoxKernel): build it once per
// sigma, not per frame.
StackedBoxKernel MakeStackedBoxKernel(double sigma, int boxes = 4);

// Blurs `input` with `kernel` (any StackedBoxKernel satisfying its invariants,
// 1 to 5 boxes). Output pixel (x, y) is
//   sum_k w_k / n_k^2 * sum of input over the box of radius r_k at (x, y),
// with replicate (clamp-to-edge) borders: pixels outside the image take the
// value of the nearest edge pixel. The 8-bit version rounds half up, so a
// constant image stays exactly constant.
// - `output` is resized to the input's size; it may be `input` itself.
// - One integral image of the input padded by max_radius() on every side
//   (uint32, wrapping: each box sum is < 2^31, so differences stay exact);
//   then 4 reads per box per pixel, independent of sigma. Cost
//   O((W + 2R)(H + 2R) + K W H), R = max_radius(); about 0.3 ms for a
//   640 x 480 frame at any sigma <= 20 on one core (docs/vision.md).
// - Deterministic, stateless, thread-safe; no global or thread-local state
//   (scratch memory is allocated per call).
// Preconditions (HCPF_CHECK): input.pixels.size() == width * height; the
// kernel's invariants; 255 (2 max_radius() + 1)^2 < 2^31.
void StackedIntegralBlur(const GreyImage& input, const StackedBoxKernel& kernel, GreyImage& output);
// The same, without rounding (each pixel within 1e-4 grey levels of the
// exact weighted box sums: float scales w_k / n_k^2).
void StackedIntegralBlur(const GreyImage& input, const StackedBoxKernel& kernel,
                         GreyImageF& output);

// An exact sampled Gaussian of a float image, separable, with replicate
// borders: the kernel of OpenCV's cv::GaussianBlur for float images (size
// round(8 sigma + 1) | 1, so radius round(8 sigma + 1) | 1 over 2: 4 at
// sigma 0.84, where round(4 sigma) is 3; weights exp(-i^2 / 2 sigma^2)
// normalised in double, then float), applied down the columns and then along the rows, each output
// pixel summed in one fixed order (the centre tap, then the pairs of taps
// i and -i outward). For inputs the stacked blur cannot hold (SKS's products
// of derivatives). Unlike cv::GaussianBlur, whose float kernels OpenCV picks
// by the CPU's vector extensions at run time (AVX2 and the baseline round
// differently: a determinism audit saw SKS's boxes and a run's metrics
// change), the result is the same bytes on every x86-64 machine: each
// value is computed element by element in that order, with no FMA
// contraction, by whichever build of the loops (AVX-512, AVX2 or the SSE2
// baseline) the CPU runs, and every build gives the same bytes.
// - `output` is resized to the input's size; it must not be `input`.
// - About as fast as cv::GaussianBlur's float kernels, or faster, on an
//   AVX-512 machine (bench/vision_bench.cc, BM_SeparableGaussianBlur;
//   docs/performance.md).
// Preconditions (HCPF_CHECK): 0 < sigma <= 64; input.pixels.size() ==
// width * height; &output != &input.
void SeparableGaussianBlur(const GreyImageF& input, double sigma, GreyImageF& output);

}  // namespace hcpf::vision
