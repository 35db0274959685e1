// What a run holds while it runs: frame by frame data the tracker has read
// is not kept for every frame.

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <optional>
#include <string>

#include "hcpf/renderer/renderer.h"
#include "hcpf/scenarios/frames.h"
#include "hcpf/scenarios/run.h"
#include "hcpf/scenarios/scenario.h"
#include "support/test_scenarios.h"

namespace hcpf::scenarios {
namespace {

namespace fs = std::filesystem;

// This process's resident memory now, in KB (/proc/self/status VmRSS).
long ResidentKb() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  }
  return 0;
}

// Runs `s` into `out` in a child process and returns how far its peak
// resident memory rose above this process's now, in KB (below it, negative,
// when the child touched less than the test holds); nullopt when the run
// failed.
std::optional<long> RunPeakAboveKb(const Scenario& s, const fs::path& out, bool video) {
  fs::remove_all(out);
  const long before_kb = ResidentKb();
  const pid_t child = fork();
  if (child < 0) return std::nullopt;
  if (child == 0) {
    try {
      RunScenario(s, {.out_dir = out.string(), .video = video, .show_progress = false});
    } catch (...) {
      _exit(3);
    }
    _exit(0);
  }
  int status = 0;
  rusage usage{};
  if (wait4(child, &status, 0, &usage) != child || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    return std::nullopt;
  }
  return usage.ru_maxrss - before_kb;
}

// The oracle's likelihood maps (observation.simulated.likelihood_map) are
// made frame by frame beside the tracker and dropped once read: made for
// every frame before the tracker started, a long run's maps filled memory (a
// scale audit: 1.2 MB a frame at 640x480 and map_cell_px 1, 4.8 GB at 4000
// frames). Here 1000 frames of 320x240 maps of 4-byte cells are 307 MB; the
// run, in a child, must peak less than 100 MB above the test's own memory
// (its truth, reports and files take about 10 KB a frame).
TEST(RunMemory, TheOraclesLikelihoodMapsAreNotKeptForEveryFrame) {
#if defined(__SANITIZE_ADDRESS__)
  // AddressSanitizer keeps freed memory in its quarantine (256 MB by
  // default), so a run that frees each map peaks as one that keeps them.
  GTEST_SKIP() << "peak memory is not measured under AddressSanitizer (its quarantine holds "
                  "freed memory)";
#endif
  const Scenario s =
      LoadScenarioText(testing::kMinimal, "minimal.yaml",
                       {ParseOverride("frames=1000"), ParseOverride("tracker.particles=20"),
                        ParseOverride("tracker.resampling.method=systematic"),
                        ParseOverride("tracker.likelihood.model=map"),
                        ParseOverride("observation.simulated.likelihood_map=true"),
                        ParseOverride("observation.simulated.map_cell_px=1")});
  const fs::path out =
      fs::path(::testing::TempDir()) / ("hcpf-run-memory-" + std::to_string(::getpid()));
  const std::optional<long> peak_kb = RunPeakAboveKb(s, out, false);
  ASSERT_TRUE(peak_kb) << "the run failed";
  EXPECT_TRUE(fs::exists(out / "metrics.json"));
  EXPECT_LT(*peak_kb, 100 * 1024) << "peak " << *peak_kb << " KB above the test";
  fs::remove_all(out);
}

// A rendered run's overlay video reads its frames back one at a time (from
// the frame cache, or here, without one, from a spool in the run's folder)
// instead of keeping them all until the video is written (a scale audit: 1.8
// GB for 2000 frames of 640x480). Here 200 frames of 640x480 are 184 MB;
// the run, in a child, must peak less than 120 MB above the test's own
// memory: it peaks 77 MB above (llvmpipe's context, the encoder), and 258 MB
// above when it keeps the frames. The video
// shows the rendered frames, and the spool is gone from the run's folder.
TEST(RunMemory, ARenderedRunsVideoFramesAreReadBackNotKept) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "peak memory is not measured under AddressSanitizer (its quarantine holds "
                  "freed memory)";
#endif
  if (!HCPF_UNIT_TESTS_MAY_RENDER) GTEST_SKIP() << "renders with OSMesa";
  const Scenario s = LoadScenarioText(
      testing::kMinimal, "minimal.yaml",
      {ParseOverride("frames=200"), ParseOverride("camera.resolution=[640, 480]"),
       ParseOverride("observation.source=rendered"), ParseOverride("tracker.particles=20")});
  const fs::path out =
      fs::path(::testing::TempDir()) / ("hcpf-run-video-memory-" + std::to_string(::getpid()));
  const std::optional<long> peak_kb = RunPeakAboveKb(s, out, true);
  ASSERT_TRUE(peak_kb) << "the run failed";
  EXPECT_LT(*peak_kb, 120 * 1024) << "peak " << *peak_kb << " KB above the test";
  EXPECT_FALSE(fs::exists(out / ".video-frames"));
  // Frames 0, 99 and 199 of the video against the renderer's: H.264 and the
  // boxes drawn over them differ by 3.5-3.7 grey levels on average; the plain
  // background drawn for a frame without pixels differs by 20.
  auto renderer =
      renderer::SceneRenderer::Create(s.world, RendererOptionsOf(s), Rng(s.seeds.renderer));
  cv::VideoCapture video((out / "overlay.mp4").string());
  cv::Mat decoded;
  for (int f = 0; f < s.world.frames; ++f) {
    ASSERT_TRUE(video.read(decoded)) << "frame " << f;
    if (f != 0 && f != 99 && f != 199) continue;
    const RgbImage rgb = renderer->Render(f).rgb;
    cv::Mat expected;
    cv::cvtColor(cv::Mat(rgb.height, rgb.width, CV_8UC3, const_cast<uint8_t*>(rgb.pixels.data())),
                 expected, cv::COLOR_RGB2BGR);
    cv::Mat difference;
    cv::absdiff(decoded(cv::Rect(0, 0, rgb.width, rgb.height)), expected, difference);
    EXPECT_LT(cv::mean(difference)[1], 6.0) << "frame " << f;
  }
  fs::remove_all(out);
}

// Charged resampling among many filters within reach of one another costs
// about N K^2 and said nothing (a scale audit: 80 packed targets). 200 frames
// of 80 filters whose 5000 draws each met 47 charges: 3.76e9 terms, ~7.5 s
// at 2 ns a term, said while that is at least 5 s and half the tracker's
// time; a run whose tracker took 20 s, a sparse one, and one without charged
// resampling (no terms) say nothing.
TEST(ChargedResamplingNote, NamesTheTermsWhenTheyAreMuchOfTheTrackersTime) {
  std::vector<tracker::FrameReport> reports(200);
  for (tracker::FrameReport& report : reports) {
    report.filters.resize(80);
    for (tracker::FilterReport& r : report.filters) r.potential_terms = 5000 * 47;
  }
  const std::string note = ChargedResamplingNote(reports, 5000, 9.0);
  EXPECT_NE(note.find("3.76e+09 potential terms"), std::string::npos) << note;
  EXPECT_NE(note.find("about 7.52 s of the tracker's 9 s"), std::string::npos) << note;
  EXPECT_NE(note.find("5000 draws a frame met 47 other filters' charges"), std::string::npos)
      << note;
  EXPECT_NE(note.find("tracker.resampling.softening_px"), std::string::npos) << note;
  EXPECT_EQ(ChargedResamplingNote(reports, 5000, 20.0), "");
  for (tracker::FrameReport& report : reports) {
    for (tracker::FilterReport& r : report.filters) r.potential_terms = 5000 * 5;
  }
  EXPECT_EQ(ChargedResamplingNote(reports, 5000, 1.0), "");  // 0.8 s
  for (tracker::FrameReport& report : reports) {
    for (tracker::FilterReport& r : report.filters) r.potential_terms = 0;
  }
  EXPECT_EQ(ChargedResamplingNote(reports, 5000, 0.0), "");
}

}  // namespace
}  // namespace hcpf::scenarios
