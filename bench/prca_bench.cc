// PRCA benchmarks (issue 11 item 3 target: <= 15 ms per 640x480 frame with 5
// target models on one core):
//   BM_PrcaFrame/<models>          whole-frame search, time per frame
//   BM_PrcaFrameWindowed/<models>  every model with a search window
//   BM_PrcaFormClusters            the scene's modified DBSCAN alone
//   BM_PrcaFormClusters/noise      the same with sensor noise (many small clusters)
// items_per_second is frames per second.
//
// The frame: bench/aerial_frames.h.
#include <benchmark/benchmark.h>

#include <span>

#include "aerial_frames.h"
#include "hcpf/vision/prca.h"

namespace {

using namespace hcpf;
using namespace hcpf::vision;
using namespace hcpf::bench;

// Times `detector` on `input` and reports how many detections it made.
void TimeDetect(benchmark::State& state, const PrcaOptions& options, const DetectorInput& input) {
  const auto detector = MakePrcaDetector(options);
  Rng rng(1);
  size_t found = 0;
  for (auto _ : state) {
    const DetectorOutput out = detector->Detect(input, rng);
    found = out.detections.size();
    benchmark::DoNotOptimize(out.maps.data());
  }
  state.counters["detections"] = static_cast<double>(found);
  state.SetItemsProcessed(state.iterations());
}

void BM_PrcaFrame(benchmark::State& state) {
  const Scene& scene = GetScene(0.0);
  const auto models = std::span(scene.models).first(static_cast<size_t>(state.range(0)));
  TimeDetect(state, PrcaOptions{}, {.image = scene.frame, .models = models});
}
BENCHMARK(BM_PrcaFrame)->Arg(1)->Arg(5)->Unit(benchmark::kMillisecond);

// 5 models, scales 0.5 ... 1 searched (observation.prca.scale_min = 0.5 with
// the default step 2^(1/4): 1, 0.84, 0.71, 0.59, 0.5): the scene is
// clustered once, each model matched and voted at five scales.
void BM_PrcaFrameScales(benchmark::State& state) {
  const Scene& scene = GetScene(0.0);
  PrcaOptions options;
  options.scale_min = 0.5;
  TimeDetect(state, options, {.image = scene.frame, .models = scene.models});
}
BENCHMARK(BM_PrcaFrameScales)->Unit(benchmark::kMillisecond);

void BM_PrcaFrameWindowed(benchmark::State& state) {
  const Scene& scene = GetScene(0.0);
  const auto models = std::span(scene.models).first(static_cast<size_t>(state.range(0)));
  TimeDetect(state, PrcaOptions{},
             {.image = scene.frame, .models = models, .windows = scene.windows});
}
BENCHMARK(BM_PrcaFrameWindowed)->Arg(5)->Unit(benchmark::kMillisecond);

void BM_PrcaFormClusters(benchmark::State& state, double noise_sigma) {
  const Scene& scene = GetScene(noise_sigma);
  const PrcaOptions options;
  int clusters = 0;
  for (auto _ : state) {
    const prca::ClusteredImage c = prca::FormClusters(scene.frame, options);
    clusters = c.count;
    benchmark::DoNotOptimize(c.labels.data());
  }
  state.counters["clusters"] = clusters;
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK_CAPTURE(BM_PrcaFormClusters, clean, 0.0)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_PrcaFormClusters, noise, 4.0)->Unit(benchmark::kMillisecond);

void BM_PrcaFrameNoise(benchmark::State& state) {
  const Scene& scene = GetScene(4.0);
  TimeDetect(state, PrcaOptions{}, {.image = scene.frame, .models = scene.models});
}
BENCHMARK(BM_PrcaFrameNoise)->Unit(benchmark::kMillisecond);

}  // namespace
