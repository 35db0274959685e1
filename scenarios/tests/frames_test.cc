// ProduceFrames: rendering in stages (this thread renders frame f + 1 while
// workers apply the sensor effects of frame f and the frames before it, and
// one more thread finishes them in order) gives Render's frames, in order,
// with the cache and without, for any number of workers.

#include "hcpf/scenarios/frames.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <stdexcept>
#include <thread>
#include <utility>
#include <vector>

#include "hcpf/renderer/renderer.h"
#include "support/process.h"
#include "support/test_scenarios.h"

namespace hcpf::scenarios {
namespace {

namespace fs = std::filesystem;
using ::hcpf::testing::FreshDir;
using testing::kMinimal;

class Frames : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!HCPF_UNIT_TESTS_MAY_RENDER) {
      GTEST_SKIP() << "renders with OSMesa: not in a build with HCPF_GL_TESTS=OFF (the "
                      "sanitizer build, where OSMesa's own context allocations leak)";
    }
  }

  // kMinimal, rendered small, with every sensor effect.
  static Scenario Noisy() {
    return LoadScenarioText(
        kMinimal, "noisy.yaml",
        {ParseOverride("frames=6"), ParseOverride("camera.resolution=[160, 120]"),
         ParseOverride("observation.source=rendered"), ParseOverride("sensor.noise_sigma=3"),
         ParseOverride("sensor.blur_px=0.7"), ParseOverride("sensor.jpeg_quality=85")});
  }
};

TEST_F(Frames, TwoStagesGiveRendersFramesInOrder) {
  const Scenario s = Noisy();
  auto reference =
      renderer::SceneRenderer::Create(s.world, RendererOptionsOf(s), Rng(s.seeds.renderer));
  std::vector<renderer::RenderedFrame> expected;
  for (int f = 0; f < s.world.frames; ++f) expected.push_back(reference->Render(f));

  for (const auto& [cached, workers] :
       {std::pair(false, 1), std::pair(true, 1), std::pair(false, 3), std::pair(true, 3)}) {
    SCOPED_TRACE(fmt::format("{} worker(s), {}", workers, cached ? "cached" : "no cache"));
    const fs::path dir = FreshDir("frames-two-stage");
    FrameSourceOptions options;
    options.workers = workers;
    options.show_progress = false;
    if (cached) options.cache_dir = (dir / "cache").string();
    std::vector<int> order;
    std::vector<std::thread::id> threads;
    std::vector<RgbImage> images;  // each frame's colour image, as on_frame saw it
    options.on_frame = [&](const renderer::RenderedFrame& frame) {
      order.push_back(frame.frame);
      images.push_back(frame.rgb);
      threads.push_back(std::this_thread::get_id());
      EXPECT_EQ(frame.rgb, expected.at(static_cast<size_t>(frame.frame)).rgb)
          << "frame " << frame.frame << (cached ? ", cached run" : "");
    };
    // Twice with a cache: rendered and stored, then all read back.
    for (int pass = 0; pass < (cached ? 2 : 1); ++pass) {
      order.clear();
      threads.clear();
      images.clear();
      const SceneFrames out = ProduceFrames(s, options);
      EXPECT_EQ(out.frames_rendered, pass == 0 ? s.world.frames : 0);
      ASSERT_EQ(images.size(), expected.size());
      ASSERT_EQ(out.truth.size(), expected.size());
      for (size_t f = 0; f < expected.size(); ++f) {
        EXPECT_EQ(images[f], expected[f].rgb) << "frame " << f;
        EXPECT_EQ(out.truth[f].frame, static_cast<int>(f));
        ASSERT_EQ(out.truth[f].objects.size(), expected[f].ground_truth.objects.size());
        for (size_t k = 0; k < out.truth[f].objects.size(); ++k) {
          EXPECT_EQ(out.truth[f].objects[k].pixels_visible,
                    expected[f].ground_truth.objects[k].pixels_visible);
        }
      }
      ASSERT_EQ(order.size(), expected.size());
      for (size_t f = 0; f < order.size(); ++f) EXPECT_EQ(order[f], static_cast<int>(f));
      // Finished on one thread, not on the thread that renders.
      for (const std::thread::id& t : threads) {
        EXPECT_EQ(t, threads.front());
        EXPECT_NE(t, std::this_thread::get_id());
      }
    }
    fs::remove_all(dir);
  }
}

// A failure in the finishing stage (here on_frame) reaches the caller, and
// the frames queued behind the failed one are not finished.
TEST_F(Frames, AFailureWhileFinishingAFrameStopsTheRun) {
  Scenario s = Noisy();
  s.world.frames = 40;
  FrameSourceOptions options;
  options.show_progress = false;
  int finished = 0;
  options.on_frame = [&](const renderer::RenderedFrame& frame) {
    ++finished;
    if (frame.frame == 2) throw std::runtime_error("on_frame failed at frame 2");
  };
  EXPECT_THROW(ProduceFrames(s, options), std::runtime_error);
  EXPECT_EQ(finished, 3);
}

// A rendered run's overlay video reads its frames back one at a time
// (FrameReader) instead of holding them all (a scale audit: 1.8 GB for
// 2000 frames of 640x480). Without a frame cache they are spooled, with one
// they are read from it; a frame the cache lost, or holds with other pixels,
// is rendered again.
TEST_F(Frames, ReadBackGivesEachFrameFromTheSpoolOrTheCache) {
  const Scenario s = Noisy();
  auto reference =
      renderer::SceneRenderer::Create(s.world, RendererOptionsOf(s), Rng(s.seeds.renderer));
  std::vector<RgbImage> expected;
  for (int f = 0; f < s.world.frames; ++f) expected.push_back(reference->Render(f).rgb);
  const fs::path dir = FreshDir("frames-read-back");
  FrameSourceOptions options;
  options.show_progress = false;
  options.spool_dir = (dir / "spool").string();
  {
    SCOPED_TRACE("no cache: spooled");
    const SceneFrames out = ProduceFrames(s, options);
    EXPECT_EQ(out.readback_root, options.spool_dir);
    EXPECT_TRUE(out.readback_is_spool);
    FrameReader read(s, out);
    for (int f = 0; f < s.world.frames; ++f) EXPECT_EQ(read.Read(f), expected[f]) << "frame " << f;
    EXPECT_EQ(read.rendered_again(), 0) << "every frame read from the spool";
    const renderer::FrameCache spool(options.spool_dir, out.pixel_hash);
    for (int f = 0; f < s.world.frames; ++f) EXPECT_TRUE(spool.Contains(f)) << "frame " << f;
  }
  fs::remove_all(options.spool_dir);
  options.cache_dir = (dir / "cache").string();
  const SceneFrames out = ProduceFrames(s, options);
  EXPECT_EQ(out.readback_root, options.cache_dir);
  EXPECT_FALSE(out.readback_is_spool);
  EXPECT_FALSE(fs::exists(options.spool_dir)) << "the frame cache holds the frames already";
  {
    FrameReader read(s, out);
    for (int f = 0; f < s.world.frames; ++f) EXPECT_EQ(read.Read(f), expected[f]) << "frame " << f;
    EXPECT_EQ(read.rendered_again(), 0) << "every frame read from the cache";
  }
  // Frame 2 lost, frame 4 holding frame 3's pixels: both rendered again.
  const fs::path scene = fs::path(options.cache_dir) / out.pixel_hash;
  fs::remove(scene / "000002.frame");
  fs::copy_file(scene / "000003.frame", scene / "000004.frame",
                fs::copy_options::overwrite_existing);
  ASSERT_NE(expected[3], expected[4]);
  FrameReader read(s, out);
  for (int f = 0; f < s.world.frames; ++f) EXPECT_EQ(read.Read(f), expected[f]) << "frame " << f;
  EXPECT_EQ(read.rendered_again(), 2) << "frames 2 and 4";
}

}  // namespace
}  // namespace hcpf::scenarios
