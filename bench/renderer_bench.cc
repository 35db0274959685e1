// Renderer speed: a 640x480 frame with terrain, 20 occluders, 5 vehicles and
// sun shadows, with and without the ground-truth passes; a realistic scene
// end to end; and the sensor effects alone.
//
//   build/<dir>/bench/renderer_bench
//
// It rasterises on the thread that draws, as every hcpf process does
// (GlContext::Create sets LP_NUM_THREADS=0 unless the environment sets it);
// LP_NUM_THREADS=N asks for N llvmpipe threads (docs/renderer.md).
//
// "BM_RenderFrame/gt:1" is a full frame (colour + ground truth + readback);
// "gt:0" skips the ground-truth passes, so the difference is their cost.
// "BM_RealisticFrame/w:800/h:600/cache:1" is the issue-13 scene (oblique view
// over relief and roads, three occluders, three vehicles, sensor noise 3, blur
// 0.7, JPEG 85) end to end: render + ground truth + sensor effects + frame
// cache write (FrameCache::Store, PNG + JSON into a temporary directory);
// cache:0 leaves the write out; pipe:2 runs the sensor effects and the write
// on a second thread while the next frame renders, as `hcpf run` does (its
// fps is then the wall-clock rate; cpu_ms_per_frame still counts every
// thread); pipe:3 as `hcpf run --threads 8`: eight threads apply the sensor
// effects of several frames at once and eight store them. "BM_SensorEffects" times
// ApplySensorEffects alone on a rendered 800x600 frame, all effects and each one by itself. The
// label is the GL_RENDERER string of the backend that ran. cpu_ms_per_frame is the process CPU time
// (all threads) per frame: rasterising on the drawing thread it is the single-core cost even when
// other jobs share the machine; fps is wall-clock.

#include <benchmark/benchmark.h>
#include <fmt/format.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hcpf/core/parallel.h"
#include "hcpf/renderer/renderer.h"

namespace {

using hcpf::ObjectId;
using hcpf::OccluderKind;
using hcpf::OccluderSpec;
using hcpf::RgbImage;
using hcpf::TargetSpec;
using hcpf::WorldSpec;
using hcpf::renderer::SensorOptions;

WorldSpec BenchWorld() {
  WorldSpec w;
  w.frames = 300;
  w.fps = 30.0;
  w.terrain.relief_m = 2.0;
  w.terrain.roads = true;
  w.terrain.seed = 9;
  w.sun.azimuth_deg = 135.0;
  w.sun.elevation_deg = 35.0;
  // 20 occluders: 8 buildings, 10 trees, 2 bridges, spread over the view.
  for (int i = 0; i < 8; ++i) {
    OccluderSpec b;
    b.kind = OccluderKind::kBuilding;
    b.at_m = {-50.0 + 14.0 * i, (i % 2 == 0) ? 35.0 : -38.0};
    b.size_m = {10.0, 8.0, 6.0 + 2.0 * i};
    b.yaw_deg = 10.0 * i;
    w.occluders.push_back(b);
  }
  for (int i = 0; i < 10; ++i) {
    OccluderSpec t;
    t.kind = OccluderKind::kTree;
    t.at_m = {-45.0 + 10.0 * i, (i % 2 == 0) ? 15.0 : -18.0};
    t.height_m = 7.0 + (i % 3);
    w.occluders.push_back(t);
  }
  for (int i = 0; i < 2; ++i) {
    OccluderSpec br;
    br.kind = OccluderKind::kBridge;
    br.from_m = {-20.0 + 40.0 * i, -25.0};
    br.to_m = {-20.0 + 40.0 * i, 25.0};
    br.width_m = 8.0;
    br.height_m = 6.0;
    w.occluders.push_back(br);
  }
  const std::string dir = std::string(HCPF_SOURCE_DIR) + "/assets/vehicles/";
  const char* models[] = {"tank.glb", "truck.glb", "car.glb", "tank.glb", "truck.glb"};
  const Eigen::Vector3d dims[] = {
      {6.9, 3.6, 2.3}, {8.0, 2.5, 3.2}, {4.5, 1.84, 1.5}, {6.9, 3.6, 2.3}, {8.0, 2.5, 3.2}};
  for (int i = 0; i < 5; ++i) {
    TargetSpec t;
    t.id = ObjectId{i + 1};
    t.model = dir + models[i];
    t.dimensions_m = dims[i];
    t.tint = {0.2 + 0.15 * i, 0.5 - 0.07 * i, 0.3};
    const double y = -30.0 + 15.0 * i;
    t.path.waypoints_m = {{-70.0, y}, {70.0, y + (i % 2 == 0 ? 10.0 : -10.0)}};
    t.path.speed_mps = 6.0 + i;
    w.targets.push_back(t);
  }
  w.camera.width_px = 640;
  w.camera.height_px = 480;
  w.camera.hfov_deg = 60.0;
  w.camera.path.push_back({0, {0.0, -90.0, 110.0}, {0.0, 0.0, 0.0}});
  w.camera.path.push_back({299, {10.0, -60.0, 140.0}, {5.0, 0.0, 0.0}});
  w.camera.shake_px = 0.5;
  w.camera.shake_seed = 3;
  return w;
}

// The issue-13 scene: an oblique camera over 2 m of relief with roads, three
// occluders (a building, a tree, a bridge) and three vehicles, at the given
// resolution (the field of view is fixed, so larger images are finer).
WorldSpec RealisticWorld(int width_px, int height_px) {
  WorldSpec w;
  w.frames = 180;
  w.fps = 30.0;
  w.terrain.relief_m = 2.0;
  w.terrain.roads = true;
  w.terrain.seed = 21;
  w.sun.azimuth_deg = 200.0;
  w.sun.elevation_deg = 40.0;
  OccluderSpec building;
  building.kind = OccluderKind::kBuilding;
  building.at_m = {-25.0, 20.0};
  building.size_m = {12.0, 9.0, 10.0};
  building.yaw_deg = 15.0;
  w.occluders.push_back(building);
  OccluderSpec tree;
  tree.kind = OccluderKind::kTree;
  tree.at_m = {18.0, -12.0};
  tree.height_m = 9.0;
  w.occluders.push_back(tree);
  OccluderSpec bridge;
  bridge.kind = OccluderKind::kBridge;
  bridge.from_m = {5.0, -30.0};
  bridge.to_m = {5.0, 30.0};
  bridge.width_m = 10.0;
  bridge.height_m = 6.0;
  w.occluders.push_back(bridge);
  const std::string dir = std::string(HCPF_SOURCE_DIR) + "/assets/vehicles/";
  const char* models[] = {"truck.glb", "car.glb", "tank.glb"};
  const Eigen::Vector3d dims[] = {{8.0, 2.5, 3.2}, {4.5, 1.84, 1.5}, {6.9, 3.6, 2.3}};
  const std::vector<Eigen::Vector2d> paths[] = {
      {{-50.0, -6.0}, {50.0, -6.0}}, {{40.0, 8.0}, {-40.0, 8.0}}, {{-8.0, -45.0}, {-8.0, 45.0}}};
  for (int i = 0; i < 3; ++i) {
    TargetSpec t;
    t.id = ObjectId{i + 1};
    t.model = dir + models[i];
    t.dimensions_m = dims[i];
    t.path.waypoints_m = paths[i];
    t.path.speed_mps = 5.0 + i;
    w.targets.push_back(t);
  }
  w.camera.width_px = width_px;
  w.camera.height_px = height_px;
  w.camera.hfov_deg = 50.0;
  // Oblique: about 40 degrees below the horizon, drifting and climbing.
  w.camera.path.push_back({0, {0.0, -110.0, 90.0}, {0.0, 0.0, 0.0}});
  w.camera.path.push_back({179, {15.0, -95.0, 105.0}, {5.0, 5.0, 0.0}});
  w.camera.shake_px = 0.5;
  w.camera.shake_seed = 4;
  return w;
}

// The issue-13 sensor: noise 3 grey levels, blur sigma 0.7 px, JPEG 85.
SensorOptions RealisticSensor() {
  SensorOptions s;
  s.noise_sigma = 3.0;
  s.blur_px = 0.7;
  s.jpeg_quality = 85;
  return s;
}

// CPU time of the whole process (all threads, llvmpipe's included), ms. On a
// loaded machine wall time also counts waiting for a core; this does not.
double ProcessCpuMs() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return (u.ru_utime.tv_sec + u.ru_stime.tv_sec) * 1e3 +
         (u.ru_utime.tv_usec + u.ru_stime.tv_usec) / 1e3;
}

std::shared_ptr<hcpf::renderer::GlContext> Context() {
  static std::shared_ptr<hcpf::renderer::GlContext> context(hcpf::renderer::GlContext::Create());
  return context;
}

void BM_RenderFrame(benchmark::State& state) {
  hcpf::renderer::RendererOptions options;
  options.ground_truth = state.range(0) != 0;
  options.shadows = state.range(1) != 0;
  options.pcf_radius = static_cast<int>(state.range(2));
  auto renderer =
      hcpf::renderer::SceneRenderer::Create(BenchWorld(), options, hcpf::Rng(1), Context());
  // pipe: frame t + 1 is submitted before frame t is collected (readback
  // into pixel-buffer objects; SceneRenderer::Submit / Collect).
  const bool pipelined = state.range(3) != 0;
  int frame = 0;
  if (pipelined) renderer->Submit(frame);
  const double cpu_start = ProcessCpuMs();
  for (auto _ : state) {
    frame = (frame + 1) % 300;
    if (pipelined) renderer->Submit(frame);
    hcpf::renderer::RenderedFrame f = pipelined ? renderer->Collect() : renderer->Render(frame);
    benchmark::DoNotOptimize(f.rgb.pixels.data());
  }
  if (pipelined) renderer->Collect();
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["cpu_ms_per_frame"] =
      (ProcessCpuMs() - cpu_start) / static_cast<double>(state.iterations());
  state.SetLabel(Context()->info().renderer);
}
BENCHMARK(BM_RenderFrame)
    ->ArgNames({"gt", "shadows", "pcf", "pipe"})
    ->Args({1, 1, 1, 0})
    ->Args({1, 1, 1, 1})
    ->Args({0, 1, 1, 0})
    ->Args({1, 1, 0, 0})
    ->Args({1, 1, 0, 1})
    ->Args({1, 0, 1, 0})
    ->Args({0, 0, 1, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()  // llvmpipe rasterises on its own threads: wall time is the cost
    ->MinTime(3.0);

constexpr int kBenchWorkers = 8;

void BM_RealisticFrame(benchmark::State& state) {
  const int width = static_cast<int>(state.range(0));
  const int height = static_cast<int>(state.range(1));
  const bool cache = state.range(2) != 0;
  hcpf::renderer::RendererOptions options;
  options.sensor = RealisticSensor();
  const WorldSpec world = RealisticWorld(width, height);
  auto renderer = hcpf::renderer::SceneRenderer::Create(world, options, hcpf::Rng(1), Context());
  const std::filesystem::path root =
      std::filesystem::temp_directory_path() / fmt::format("hcpf-renderer-bench-{}", ::getpid());
  const hcpf::renderer::FrameCache frame_cache(root, hcpf::renderer::PixelHash(world, options, 1));
  // pipe:0 Render; pipe:1 frame t + 1 submitted before frame t is
  // collected; pipe:2 two stages as in `hcpf run` (scenarios' ProduceFrames):
  // this thread collects frame t and renders frame t + 1 while a worker
  // applies frame t's sensor effects and stores it.
  // pipe:3 as `hcpf run --threads 8` (ProduceFrames): 8 threads apply the
  // sensor effects, several frames at once, and 8 store frames in the cache,
  // while this thread renders.
  const int64_t pipe = state.range(3);
  hcpf::SerialWorker finisher;
  std::optional<hcpf::OrderedWorkers> workers;
  std::optional<hcpf::renderer::FrameCacheWriter> writer;
  if (pipe == 3) {
    workers.emplace(kBenchWorkers);
    if (cache) writer.emplace(frame_cache, 4, kBenchWorkers);
  }
  int frame = 0;
  if (pipe != 0) renderer->Submit(frame);
  const double cpu_start = ProcessCpuMs();
  for (auto _ : state) {
    if (pipe == 3) {
      auto f = std::make_shared<hcpf::renderer::RenderedFrame>(renderer->CollectClean());
      workers->Post([&, f] { renderer->ApplySensor(*f); },
                    [&, f] {
                      benchmark::DoNotOptimize(f->rgb.pixels.data());
                      if (writer) writer->Submit(std::move(*f));
                    });
      frame = (frame + 1) % world.frames;
      renderer->Submit(frame);
      continue;
    }
    if (pipe == 2) {
      finisher.Post([&, f = renderer->CollectClean()]() mutable {
        renderer->ApplySensor(f);
        if (cache) frame_cache.Store(f);
        benchmark::DoNotOptimize(f.rgb.pixels.data());
      });
      frame = (frame + 1) % world.frames;
      renderer->Submit(frame);
      continue;
    }
    frame = (frame + 1) % world.frames;
    if (pipe == 1) renderer->Submit(frame);
    hcpf::renderer::RenderedFrame f = pipe == 1 ? renderer->Collect() : renderer->Render(frame);
    if (cache) frame_cache.Store(f);
    benchmark::DoNotOptimize(f.rgb.pixels.data());
  }
  finisher.Wait();
  if (workers) workers->Wait();
  if (writer) writer->Finish();
  if (pipe != 0) renderer->Collect();
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["cpu_ms_per_frame"] =
      (ProcessCpuMs() - cpu_start) / static_cast<double>(state.iterations());
  state.SetLabel(Context()->info().renderer);
  std::error_code ec;
  std::filesystem::remove_all(root, ec);
}
BENCHMARK(BM_RealisticFrame)
    ->ArgNames({"w", "h", "cache", "pipe"})
    ->Args({800, 600, 1, 0})
    ->Args({800, 600, 1, 1})
    ->Args({800, 600, 1, 2})
    ->Args({800, 600, 1, 3})
    ->Args({800, 600, 0, 3})
    ->Args({800, 600, 0, 0})
    ->Args({640, 480, 1, 0})
    ->Args({1280, 720, 1, 0})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(3.0);

// One rendered 800x600 frame of the realistic scene without sensor effects:
// real image content for the JPEG coder, as the pipeline sees it.
const RgbImage& CleanRealisticFrame() {
  static const RgbImage image = [] {
    hcpf::renderer::RendererOptions options;
    options.ground_truth = false;
    auto renderer = hcpf::renderer::SceneRenderer::Create(RealisticWorld(800, 600), options,
                                                          hcpf::Rng(1), Context());
    return renderer->Render(60).rgb;
  }();
  return image;
}

void BM_SensorEffects(benchmark::State& state) {
  const SensorOptions all = RealisticSensor();
  SensorOptions s;
  if (state.range(0) != 0) s.noise_sigma = all.noise_sigma;
  if (state.range(1) != 0) s.blur_px = all.blur_px;
  if (state.range(2) != 0) s.jpeg_quality = all.jpeg_quality;
  const RgbImage& clean = CleanRealisticFrame();
  RgbImage image = clean;
  int64_t frame = 0;
  const hcpf::Rng rng(1);
  for (auto _ : state) {
    // The copy (1.4 MB, ~0.1 ms) restores the clean frame so that every
    // iteration sees the same content; it is included in the time.
    std::copy(clean.pixels.begin(), clean.pixels.end(), image.pixels.begin());
    hcpf::renderer::ApplySensorEffects(s, rng.Fork("renderer/sensor", frame++), image);
    benchmark::DoNotOptimize(image.pixels.data());
  }
  state.counters["fps"] =
      benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_SensorEffects)
    ->ArgNames({"noise", "blur", "jpeg"})
    ->Args({1, 1, 1})
    ->Args({1, 0, 0})
    ->Args({0, 1, 0})
    ->Args({0, 0, 1})
    ->Unit(benchmark::kMillisecond)
    ->MinTime(2.0);

}  // namespace
