// Detector benchmarks (issue 11 targets, one core, 640x480, 5 target
// models): NCC in windows <= 2 ms, differencing <= 10 ms; also NCC and colour
// over the whole frame, colour in windows, and PRCA + SKS fused. The frames:
// bench/aerial_frames.h. items_per_second is frames per second. One core:
// OpenCV's own threads are switched off (cv::setNumThreads(1)).
//   BM_Ncc/frame, BM_Ncc/windows        NCC template matching
//   BM_Colour/frame, BM_Colour/windows  colour-histogram back-projection
//   BM_Diff                             motion-compensated 3-frame differencing
//   BM_FusedSksPrca                     SKS and PRCA run together and fused
#include <benchmark/benchmark.h>

#include <opencv2/core/utility.hpp>
#include <span>
#include <string>
#include <vector>

#include "aerial_frames.h"
#include "hcpf/vision/detectors.h"

namespace {

using namespace hcpf;
using namespace hcpf::vision;
using namespace hcpf::bench;

void RunDetector(benchmark::State& state, const std::string& name, bool windows) {
  cv::setNumThreads(1);
  const Scene& scene = GetScene(0.0);
  const auto detector = MakeDetector(name, DetectorOptions{});
  Rng rng(1);
  size_t found = 0;
  for (auto _ : state) {
    const DetectorOutput out =
        detector->Detect({.image = scene.frame,
                          .models = scene.models,
                          .windows = windows ? std::span<const SearchWindow>(scene.windows)
                                             : std::span<const SearchWindow>()},
                         rng);
    found = out.detections.size();
    benchmark::DoNotOptimize(out.maps.data());
  }
  state.counters["detections"] = static_cast<double>(found);
  state.SetItemsProcessed(state.iterations());
}

BENCHMARK_CAPTURE(RunDetector, ncc_frame, std::string("ncc"), false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(RunDetector, ncc_windows, std::string("ncc"), true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(RunDetector, colour_frame, std::string("colour"), false)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(RunDetector, colour_windows, std::string("colour"), true)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(RunDetector, fused_sks_prca_frame, std::string("sks+prca"), false)
    ->Unit(benchmark::kMillisecond);

// Differencing on bench/aerial_frames.h's DiffVideo (g = frame_gap, default
// 5: the vehicles of frames 10, 5 and 0).
void BM_Diff(benchmark::State& state) {
  cv::setNumThreads(1);
  const DiffOptions options;
  const DiffVideo video = MakeDiffVideo(options.frame_gap);
  const std::vector<ImageView> previous = video.Previous(options.frame_gap);
  DetectorOptions all;
  all.diff = options;
  const auto detector = MakeDetector("diff", all);
  Rng rng(1);
  size_t found = 0;
  for (auto _ : state) {
    const DetectorOutput out = detector->Detect({.image = video.now, .previous = previous}, rng);
    found = out.detections.size();
    benchmark::DoNotOptimize(out.detections.data());
  }
  state.counters["detections"] = static_cast<double>(found);
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_Diff)->Unit(benchmark::kMillisecond);

}  // namespace
