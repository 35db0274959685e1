// The Detector contract's cost clause, measured (vision/include/hcpf/vision/
// detector.h: "cost O(pixels) per model"): every registered detector, and
// SKS + PRCA fused, on the benchmark frame of bench/aerial_frames.h tiled
// k x k (k = 1, 2, 3: 640x480, 1280x960, 1920x1440, so the content per pixel
// stays the same: 5 vehicles, a road and three trees per tile) with the same
// 5 target models, whole-frame search. Google Benchmark fits time = a * N
// (N = pixels) and prints the coefficient (BigO, time per pixel) and the
// fit's relative RMS error: a linear cost fits with a small RMS; a cost
// growing faster than the pixels (e.g. N log N or N^2) leaves a large one.
// items_per_second is pixels per second at each size. One core: OpenCV's own
// threads are switched off (cv::setNumThreads(1)).
//   BM_DetectorCost/<name>/<k>
#include <benchmark/benchmark.h>

#include <algorithm>
#include <opencv2/core/utility.hpp>
#include <string>
#include <vector>

#include "aerial_frames.h"
#include "hcpf/vision/detectors.h"

namespace {

using namespace hcpf;
using namespace hcpf::vision;
using namespace hcpf::bench;

// `image` repeated k times across and k times down.
RgbImage Tile(const RgbImage& image, int k) {
  RgbImage out{.width = image.width * k, .height = image.height * k};
  out.pixels.resize(3 * static_cast<size_t>(out.width) * out.height);
  const size_t row = 3 * static_cast<size_t>(image.width);
  for (int y = 0; y < out.height; ++y) {
    const uint8_t* src = image.pixels.data() + static_cast<size_t>(y % image.height) * row;
    for (int i = 0; i < k; ++i) std::copy(src, src + row, out.at(i * image.width, y));
  }
  return out;
}

void BM_DetectorCost(benchmark::State& state, const std::string& name) {
  cv::setNumThreads(1);
  const int k = static_cast<int>(state.range(0));
  const Scene& scene = GetScene(0.0);
  const DetectorOptions options;
  const auto detector = MakeDetector(name, options);
  // A detector that reads earlier frames (the differencing) sees
  // bench/aerial_frames.h's DiffVideo, as BM_Diff in detectors_bench; every
  // frame tiled alike.
  const bool video = detector->history() > 0;
  const int g = options.diff.frame_gap;
  const DiffVideo frames = [&] {
    if (!video) return DiffVideo{.now = Tile(scene.frame, k)};
    const DiffVideo one = MakeDiffVideo(g);
    return DiffVideo{Tile(one.now, k), Tile(one.before, k), Tile(one.earlier, k)};
  }();
  const RgbImage& now = frames.now;
  const std::vector<ImageView> previous = video ? frames.Previous(g) : std::vector<ImageView>();
  Rng rng(1);
  size_t found = 0;
  for (auto _ : state) {
    const DetectorOutput out = detector->Detect(
        {.image = now,
         .previous = previous,
         .models = detector->uses_models() ? std::span<const TargetModel>(scene.models)
                                           : std::span<const TargetModel>()},
        rng);
    found = out.detections.size();
    benchmark::DoNotOptimize(out.maps.data());
  }
  const auto pixels = static_cast<int64_t>(now.width) * now.height;
  state.SetComplexityN(pixels);
  state.counters["detections"] = static_cast<double>(found);
  state.SetItemsProcessed(state.iterations() * pixels);
}

const bool kRegistered = [] {
  std::vector<std::string> names;
  for (std::string_view n : DetectorNames()) names.emplace_back(n);
  names.emplace_back("sks+prca");
  for (const std::string& name : names) {
    benchmark::RegisterBenchmark(("BM_DetectorCost/" + name).c_str(), BM_DetectorCost, name)
        ->DenseRange(1, 3)
        ->Complexity(benchmark::oN)
        ->Unit(benchmark::kMillisecond);
  }
  return true;
}();

}  // namespace
