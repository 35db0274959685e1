// Vision benchmarks (issue 11, item 2): the stacked integral image blur
// against OpenCV's Gaussian blur on the same 640x480 8-bit grey frame.
//
//   build/<dir>/bench/vision_bench --benchmark_filter=Blur
//
// Targets: BM_StackedIntegralBlur/<sigma> <= 1.5 ms per frame for every
// sigma <= 20, and >= 3x faster than BM_CvGaussianBlur/10.
//   BM_StackedIntegralBlur/<sigma>      K = 4 boxes, kernel built once outside
//                                       the loop (BM_MakeStackedBoxKernel
//                                       times that separately)
//   BM_StackedIntegralBlurFloat/<sigma> the same with float output
//   BM_CvGaussianBlur/<sigma>           cv::GaussianBlur, ksize (0, 0) so
//                                       OpenCV picks it (round(6 sigma + 1) | 1
//                                       taps for 8-bit: 61 at sigma = 10),
//                                       BORDER_REPLICATE like the stacked
//                                       blur; one OpenCV thread
//                                       (cv::setNumThreads(1)): both sides
//                                       run on one core.
//   BM_SeparableGaussianBlur/<10 sigma> the project's float Gaussian (SKS's
//                                       structure tensor; one summation order)
//   BM_CvGaussianBlurFloat/<10 sigma>   cv::GaussianBlur on the same float frame
// Report CPU time when the machine is shared (docs/vision.md has figures).
// items_per_second is pixels per second.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "hcpf/core/rng.h"
#include "hcpf/vision/stacked_integral_blur.h"

namespace {

using hcpf::vision::GreyImage;

constexpr int kWidth = 640;
constexpr int kHeight = 480;

// A frame-like test image (the timings do not depend on content): smooth
// shading, a noisy texture and sharp-edged rectangles, fixed seed.
const GreyImage& Frame() {
  static const GreyImage frame = [] {
    GreyImage g{kWidth, kHeight, std::vector<uint8_t>(kWidth * kHeight)};
    hcpf::Rng rng(42);
    for (int y = 0; y < kHeight; ++y) {
      for (int x = 0; x < kWidth; ++x) {
        double v = 90.0 + 40.0 * std::sin(x / 37.0) * std::cos(y / 23.0) + 12.0 * rng.Normal();
        if ((x / 80 + y / 60) % 5 == 0) v = 30.0 + 0.5 * v;  // "vehicles" and "shadows"
        g.at(x, y) = static_cast<uint8_t>(std::clamp(v, 0.0, 255.0));
      }
    }
    return g;
  }();
  return frame;
}

void SetPixels(benchmark::State& state) {
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(kWidth) * kHeight);
}

void BM_StackedIntegralBlur(benchmark::State& state) {
  const auto kernel = hcpf::vision::MakeStackedBoxKernel(static_cast<double>(state.range(0)), 4);
  GreyImage out;
  for (auto _ : state) {
    hcpf::vision::StackedIntegralBlur(Frame(), kernel, out);
    benchmark::DoNotOptimize(out.pixels.data());
    benchmark::ClobberMemory();
  }
  SetPixels(state);
}
BENCHMARK(BM_StackedIntegralBlur)
    ->Arg(1)
    ->Arg(2)
    ->Arg(5)
    ->Arg(10)
    ->Arg(20)
    ->Unit(benchmark::kMillisecond);

void BM_StackedIntegralBlurFloat(benchmark::State& state) {
  const auto kernel = hcpf::vision::MakeStackedBoxKernel(static_cast<double>(state.range(0)), 4);
  hcpf::vision::GreyImageF out;
  for (auto _ : state) {
    hcpf::vision::StackedIntegralBlur(Frame(), kernel, out);
    benchmark::DoNotOptimize(out.pixels.data());
    benchmark::ClobberMemory();
  }
  SetPixels(state);
}
BENCHMARK(BM_StackedIntegralBlurFloat)->Arg(2)->Arg(10)->Arg(20)->Unit(benchmark::kMillisecond);

// cv::GaussianBlur of `in` at `sigma` on one OpenCV thread, timed.
void TimeCvGaussianBlur(benchmark::State& state, const cv::Mat& in, double sigma) {
  cv::setNumThreads(1);
  cv::Mat out;
  for (auto _ : state) {
    cv::GaussianBlur(in, out, cv::Size(0, 0), sigma, sigma, cv::BORDER_REPLICATE);
    benchmark::DoNotOptimize(out.data);
    benchmark::ClobberMemory();
  }
  SetPixels(state);
}

void BM_CvGaussianBlur(benchmark::State& state) {
  TimeCvGaussianBlur(state,
                     cv::Mat(kHeight, kWidth, CV_8UC1, const_cast<uint8_t*>(Frame().pixels.data())),
                     static_cast<double>(state.range(0)));
}
BENCHMARK(BM_CvGaussianBlur)
    ->Arg(1)
    ->Arg(2)
    ->Arg(5)
    ->Arg(10)
    ->Arg(20)
    ->Unit(benchmark::kMillisecond);

// Float input, as SKS smooths its structure tensor's products (sigma 1 to 4
// there): the project's SeparableGaussianBlur (the same bytes on every
// machine) against cv::GaussianBlur on the same float image (OpenCV's
// vector kernels, which differ by CPU). The argument is sigma in tenths.
const hcpf::vision::GreyImageF& FloatFrame() {
  static const hcpf::vision::GreyImageF frame = [] {
    hcpf::vision::GreyImageF f{kWidth, kHeight, {}};
    for (uint8_t v : Frame().pixels) f.pixels.push_back(static_cast<float>(v) * 0.37f);
    return f;
  }();
  return frame;
}

void BM_SeparableGaussianBlur(benchmark::State& state) {
  const double sigma = static_cast<double>(state.range(0)) / 10.0;
  hcpf::vision::GreyImageF out;
  for (auto _ : state) {
    hcpf::vision::SeparableGaussianBlur(FloatFrame(), sigma, out);
    benchmark::DoNotOptimize(out.pixels.data());
    benchmark::ClobberMemory();
  }
  SetPixels(state);
}
BENCHMARK(BM_SeparableGaussianBlur)->Arg(12)->Arg(20)->Arg(40)->Unit(benchmark::kMillisecond);

void BM_CvGaussianBlurFloat(benchmark::State& state) {
  TimeCvGaussianBlur(
      state, cv::Mat(kHeight, kWidth, CV_32F, const_cast<float*>(FloatFrame().pixels.data())),
      static_cast<double>(state.range(0)) / 10.0);
}
BENCHMARK(BM_CvGaussianBlurFloat)->Arg(12)->Arg(20)->Arg(40)->Unit(benchmark::kMillisecond);

void BM_MakeStackedBoxKernel(benchmark::State& state) {
  const double sigma = static_cast<double>(state.range(0));
  for (auto _ : state) benchmark::DoNotOptimize(hcpf::vision::MakeStackedBoxKernel(sigma, 4));
}
BENCHMARK(BM_MakeStackedBoxKernel)
    ->Arg(1)
    ->Arg(2)
    ->Arg(5)
    ->Arg(7)
    ->Arg(10)
    ->Arg(20)
    ->Arg(64)
    ->Unit(benchmark::kMillisecond);

}  // namespace
