// Frame cache formats (issue 13 item 2): one rendered 640x480 frame written
// and read in the cache's .frame format (left-differenced planes, zstd level 1,
// content checksum) against PNG through the same library calls `hcpf render`
// used before (libpng, its default level). Argument: sensor noise sigma (0 or
// 3 grey levels; noise is what makes frames hard to compress).
//   build/<dir>/bench/frame_cache_bench
// Counters: bytes = file size, ratio = file size / raw RGB size. Also the
// frame digest of the manifests' frame_digests (BM_FrameDigest), and the
// detection cache's digest of the code that detects (BM_ProgramDigest),
// computed once by every process that detects with a cache.

#include <benchmark/benchmark.h>
#include <unistd.h>

#include <filesystem>
#include <memory>
#include <string>
#include <system_error>
#include <vector>

#include "detection_cache.h"
#include "hcpf/renderer/renderer.h"
#include "hcpf/scenarios/frames.h"

namespace {

using hcpf::ObjectId;
using hcpf::OccluderKind;
using hcpf::OccluderSpec;
using hcpf::TargetSpec;
using hcpf::WorldSpec;
using hcpf::renderer::RenderedFrame;

WorldSpec Scene() {
  WorldSpec w;
  w.frames = 20;
  w.terrain.relief_m = 2.0;
  w.terrain.roads = true;
  w.terrain.seed = 9;
  w.sun.azimuth_deg = 135.0;
  w.sun.elevation_deg = 35.0;
  for (int i = 0; i < 3; ++i) {
    OccluderSpec b;
    b.kind = OccluderKind::kBuilding;
    b.at_m = {-30.0 + 30.0 * i, (i % 2 == 0) ? 25.0 : -28.0};
    b.size_m = {10.0, 8.0, 8.0 + 2.0 * i};
    w.occluders.push_back(b);
  }
  const std::string dir = std::string(HCPF_SOURCE_DIR) + "/assets/vehicles/";
  for (int i = 0; i < 3; ++i) {
    TargetSpec t;
    t.id = ObjectId{i + 1};
    t.model = dir + (i == 1 ? "truck.glb" : "car.glb");
    t.dimensions_m = i == 1 ? Eigen::Vector3d(8.0, 2.5, 3.2) : Eigen::Vector3d(4.5, 1.84, 1.5);
    t.tint = {0.2 + 0.2 * i, 0.4, 0.3};
    t.path.waypoints_m = {{-60.0, -20.0 + 20.0 * i}, {60.0, -10.0 + 20.0 * i}};
    t.path.speed_mps = 8.0;
    w.targets.push_back(t);
  }
  w.camera.width_px = 640;
  w.camera.height_px = 480;
  w.camera.hfov_deg = 60.0;
  w.camera.path.push_back({0, {0.0, -80.0, 120.0}, {0.0, 0.0, 0.0}});
  w.camera.path.push_back({19, {5.0, -70.0, 125.0}, {0.0, 0.0, 0.0}});
  return w;
}

// Frame 10 of the scene, rendered once per noise level.
const RenderedFrame& Frame(double noise_sigma) {
  static std::unique_ptr<RenderedFrame> frames[2];
  std::unique_ptr<RenderedFrame>& slot = frames[noise_sigma > 0 ? 1 : 0];
  if (!slot) {
    hcpf::renderer::RendererOptions options;
    options.sensor.noise_sigma = noise_sigma;
    auto scene = hcpf::renderer::SceneRenderer::Create(Scene(), options, hcpf::Rng(1));
    slot = std::make_unique<RenderedFrame>(scene->Render(10));
  }
  return *slot;
}

// This process's scratch folder (named by pid: two runs may overlap), removed
// when the program exits.
struct ScratchFolder {
  std::filesystem::path dir = std::filesystem::temp_directory_path() /
                              ("hcpf_frame_cache_bench_" + std::to_string(::getpid()));
  ~ScratchFolder() {
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
  }
};

std::filesystem::path Scratch() {
  static const ScratchFolder scratch;
  std::filesystem::create_directories(scratch.dir);
  return scratch.dir;
}

void Report(benchmark::State& state, const RenderedFrame& f, const std::filesystem::path& file) {
  const double bytes = static_cast<double>(std::filesystem::file_size(file));
  state.counters["bytes"] = bytes;
  state.counters["ratio"] = bytes / static_cast<double>(f.rgb.pixels.size());
}

void BM_CacheStore(benchmark::State& state) {
  const RenderedFrame& f = Frame(static_cast<double>(state.range(0)));
  const hcpf::renderer::FrameCache cache(Scratch(), "store");
  for (auto _ : state) cache.Store(f);
  Report(state, f, cache.dir() / "000010.frame");
}

void BM_CacheLoad(benchmark::State& state) {
  const RenderedFrame& f = Frame(static_cast<double>(state.range(0)));
  const hcpf::renderer::FrameCache cache(Scratch(), "load");
  cache.Store(f);
  for (auto _ : state) {
    auto loaded = cache.Load(10);
    if (!loaded || loaded->rgb != f.rgb) state.SkipWithError("the cache gave another frame");
    benchmark::DoNotOptimize(loaded);
  }
  Report(state, f, cache.dir() / "000010.frame");
}

void BM_PngWrite(benchmark::State& state) {
  const RenderedFrame& f = Frame(static_cast<double>(state.range(0)));
  const auto file = Scratch() / "frame.png";
  for (auto _ : state) hcpf::renderer::WritePng(f.rgb, file.string());
  Report(state, f, file);
}

void BM_PngRead(benchmark::State& state) {
  const RenderedFrame& f = Frame(static_cast<double>(state.range(0)));
  const auto file = Scratch() / "frame_read.png";
  hcpf::renderer::WritePng(f.rgb, file.string());
  for (auto _ : state) {
    hcpf::RgbImage image = hcpf::renderer::ReadPng(file.string());
    benchmark::DoNotOptimize(image.pixels.data());
  }
  Report(state, f, file);
}

// The digest every rendered frame gets for the manifest's frame_digests
// (scenarios::FrameDigest), once per frame in the frames' ordered stage.
void BM_FrameDigest(benchmark::State& state) {
  const RenderedFrame& f = Frame(static_cast<double>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(hcpf::scenarios::FrameDigest(f.rgb));
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) *
                          static_cast<int64_t>(f.rgb.pixels.size()));
}

// The program digest of the detection cache's keys: build_ids 1 as every
// process computes it (each loaded object's build ID, from memory), 0 with
// the build IDs left out, so each file is read and hashed as before
// 2026-12-07 (this executable, where the modules are linked in, as
// libhcpf_cli.so is under hcpf; then OpenCV's libraries and libm). Counter
// bytes: what is read from disk.
void BM_ProgramDigest(benchmark::State& state) {
  namespace internal = hcpf::scenarios::internal;
  std::vector<internal::CodeObject> objects = internal::CodeObjects();
  int64_t bytes = 0;
  for (internal::CodeObject& o : objects) {
    if (state.range(0) == 0) o.build_id.clear();
    std::error_code ec;
    if (o.build_id.empty()) bytes += static_cast<int64_t>(std::filesystem::file_size(o.path, ec));
  }
  for (auto _ : state) benchmark::DoNotOptimize(internal::ComputeProgramDigest(objects));
  state.counters["bytes"] = static_cast<double>(bytes);
}

BENCHMARK(BM_CacheStore)->Arg(0)->Arg(3)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CacheLoad)->Arg(0)->Arg(3)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PngWrite)->Arg(0)->Arg(3)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PngRead)->Arg(0)->Arg(3)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FrameDigest)->Arg(3)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ProgramDigest)->ArgName("build_ids")->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
