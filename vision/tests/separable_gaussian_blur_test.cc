// SeparableGaussianBlur: the exact sampled Gaussian of float images that SKS
// smooths its structure tensor with, in one fixed summation order so that
// every x86-64 machine gets the same bytes (a determinism audit found
// cv::GaussianBlur's float result, and so SKS's boxes, changing with the
// CPU's vector extensions).

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <utility>
#include <vector>

#include "hcpf/core/instruction_set.h"
#include "hcpf/core/rng.h"
#include "hcpf/vision/stacked_integral_blur.h"

namespace hcpf::vision {
namespace {

GreyImageF RandomFloatImage(int w, int h, uint64_t seed) {
  Rng rng(seed);
  GreyImageF image{w, h, {}};
  for (int i = 0; i < w * h; ++i) image.pixels.push_back(static_cast<float>(rng.Uniform() * 1e4));
  return image;
}

GreyImageF Blurred(const GreyImageF& in, double sigma) {
  GreyImageF out;
  SeparableGaussianBlur(in, sigma, out);
  return out;
}

// The kernel by its definition: radius round(4 sigma) (OpenCV's float
// ksize, round(8 sigma + 1) | 1), exp(-i^2 / 2 sigma^2) over their sum.
std::vector<double> HandKernel(double sigma, int radius) {
  std::vector<double> k;
  double sum = 0.0;
  for (int i = -radius; i <= radius; ++i) {
    k.push_back(std::exp(-i * i / (2.0 * sigma * sigma)));
    sum += k.back();
  }
  for (double& v : k) v /= sum;
  return k;
}

// A unit impulse gives the kernel's outer product: at sigma 2 the radius is
// 8 (ksize 17), so the image of 41 x 41 holds it whole and nothing reaches
// the border.
TEST(SeparableGaussianBlur, ImpulseGivesTheSampledGaussian) {
  GreyImageF in{41, 41, std::vector<float>(41 * 41, 0.0f)};
  in.at(20, 20) = 1.0f;
  const GreyImageF out = Blurred(in, 2.0);
  const std::vector<double> k = HandKernel(2.0, 8);
  for (int y = 0; y < 41; ++y) {
    for (int x = 0; x < 41; ++x) {
      const int dx = x - 20, dy = y - 20;
      const double expected = std::abs(dx) <= 8 && std::abs(dy) <= 8
                                  ? k[static_cast<size_t>(dx + 8)] * k[static_cast<size_t>(dy + 8)]
                                  : 0.0;
      // Float weights (rounded to 2^-24 relative) times each other.
      EXPECT_NEAR(out.at(x, y), expected, 1e-7) << x << ", " << y;
    }
  }
}

// The same filter as OpenCV's for float images with replicate borders, to
// float rounding: the two sum the taps in different orders (OpenCV pairs
// them as this does but vectorises differently by CPU), so each pixel may
// differ by a few float ulps of the sum (seen: 4 ulps, 0.0039 at values
// near 8000; one ulp is 2^-23 of the value); 1e-2 is 1e-6 of the values'
// range (up to 1e4 here), about 10 ulps.
TEST(SeparableGaussianBlur, MatchesOpenCvsFloatGaussianToRounding) {
  const GreyImageF in = RandomFloatImage(97, 61, 5);
  const cv::Mat src(in.height, in.width, CV_32F, const_cast<float*>(in.pixels.data()));
  for (double sigma : {0.6, 1.2, 2.0, 3.3, 4.0, 9.0}) {
    SCOPED_TRACE(sigma);
    cv::Mat reference;
    cv::GaussianBlur(src, reference, cv::Size(), sigma, sigma, cv::BORDER_REPLICATE);
    const GreyImageF out = Blurred(in, sigma);
    double worst = 0.0;
    for (int y = 0; y < in.height; ++y) {
      for (int x = 0; x < in.width; ++x) {
        worst = std::max(worst, std::abs(double(out.at(x, y)) - reference.at<float>(y, x)));
      }
    }
    EXPECT_LT(worst, 1e-2);
  }
}

// The half kernel k_0 .. k_r by its definition, as floats.
std::vector<float> HalfKernelByHand(double sigma) {
  const int r = static_cast<int>(std::lround(sigma * 8.0 + 1.0) | 1) / 2;
  const std::vector<double> kd = HandKernel(sigma, r);
  std::vector<float> k;
  for (int i = 0; i <= r; ++i) k.push_back(static_cast<float>(kd[static_cast<size_t>(r + i)]));
  return k;
}

// Bit for bit the documented order, written out with scalar floats: down the
// columns, then along the rows; per pixel the centre tap, then for i = 1 ..
// r the pair k_i (p[-i] + p[+i]) added, edges repeated.
GreyImageF FixedOrderSum(const GreyImageF& in, const std::vector<float>& k) {
  const int r = static_cast<int>(k.size()) - 1;
  const int w = in.width, h = in.height;
  const auto clamp = [](int v, int n) { return std::clamp(v, 0, n - 1); };
  GreyImageF columns{w, h, std::vector<float>(in.pixels.size())};
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      float acc = k[0] * in.at(x, y);
      for (int i = 1; i <= r; ++i) {
        acc += k[static_cast<size_t>(i)] * (in.at(x, clamp(y - i, h)) + in.at(x, clamp(y + i, h)));
      }
      columns.at(x, y) = acc;
    }
  }
  GreyImageF expected{w, h, std::vector<float>(in.pixels.size())};
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      float acc = k[0] * columns.at(x, y);
      for (int i = 1; i <= r; ++i) {
        acc += k[static_cast<size_t>(i)] *
               (columns.at(clamp(x - i, w), y) + columns.at(clamp(x + i, w), y));
      }
      expected.at(x, y) = acc;
    }
  }
  return expected;
}

// The library's blur (whichever build of its passes this CPU runs) is that sum, bit for
// bit, wherever the vectorised loops split their work.
TEST(SeparableGaussianBlur, IsExactlyTheFixedOrderSum) {
  const GreyImageF in = RandomFloatImage(37, 23, 9);
  EXPECT_EQ(Blurred(in, 1.7), FixedOrderSum(in, HalfKernelByHand(1.7)));
}

// Each of the library's builds of the passes (AVX-512, AVX2, the SSE2
// baseline) that this CPU can run, on frames whose widths are multiples of
// no vector width (the remainder loops run too) and on tiny ones: each gives
// the scalar sum's bytes, so a machine with AVX-512, one with AVX2 only and
// one with neither agree. (A build that fused a multiply-add would not: the
// AVX-512 target has FMA, which -ffp-contract=off keeps out.) The builds
// were once the test's own copies of the kernel, as the library's clones
// were the loader's to pick: a review.
TEST(SeparableGaussianBlur, EveryInstructionSetGivesTheScalarSum) {
  const auto same_bytes = [](const GreyImageF& a, const GreyImageF& b) {
    return a.width == b.width && a.height == b.height && a.pixels.size() == b.pixels.size() &&
           std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(float)) == 0;
  };
  hcpf::testing::ForEachInstructionSetOfThisCpu([&](InstructionSet set) {
    for (const auto& [w, h] : {std::pair{203, 61}, std::pair{1, 1}, std::pair{3, 2},
                               std::pair{17, 1}, std::pair{1, 9}}) {
      const GreyImageF in = RandomFloatImage(w, h, 4);
      for (const double sigma : {0.8, 1.7, 4.0}) {
        EXPECT_TRUE(same_bytes(Blurred(in, sigma), FixedOrderSum(in, HalfKernelByHand(sigma))))
            << NameOf(set) << ", " << w << " x " << h << ", sigma " << sigma;
      }
    }
  });
}

// A constant image stays constant to the rounding of the float weights'
// sum; an empty image gives an empty one.
TEST(SeparableGaussianBlur, ConstantStaysConstantAndEmptyStaysEmpty) {
  const GreyImageF in{30, 20, std::vector<float>(600, 250.0f)};
  for (float v : Blurred(in, 3.0).pixels) EXPECT_NEAR(v, 250.0f, 250.0f * 1e-6f);
  const GreyImageF empty = Blurred(GreyImageF{}, 2.0);
  EXPECT_EQ(empty.width, 0);
  EXPECT_TRUE(empty.pixels.empty());
}

}  // namespace
}  // namespace hcpf::vision
