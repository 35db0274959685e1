// A rendered sweep renders each scene once: runs that differ only in tracker
// settings read every frame from the shared frame cache (needs GL: label gl).

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "support/process.h"

namespace hcpf {
namespace {

namespace fs = std::filesystem;

TEST(RenderedSweep, ScenesRenderOnceAndEveryRunSucceeds) {
  const fs::path dir = testing::FreshDir("sweep-rendered");
  const std::string base = testing::LibraryScenario("crossing-dominant");
  std::ofstream(dir / "sweep.yaml") << "base: " << base << "\n"
                                    << "grid:\n"
                                    << "  observation.source: [rendered]\n"
                                    << "  frames: [6]\n"
                                    << "  tracker.particles: [100, 200, 400, 800]\n";
  const auto r = testing::RunCommand(
      std::string(HCPF_EXE) + " sweep " + (dir / "sweep.yaml").string() + " --out " +
      (dir / "out").string() + " --jobs 2 --cache " + (dir / "cache").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("4 computed, 0 failed"), std::string::npos) << r.output;
  // One run renders the scene; the other three read all 6 frames from the
  // cache (their manifests say so). Inside a sweep a run's own lines (frames
  // from the cache, its detection quality) are at debug level: they wrote
  // over the sweep's progress line (an audit).
  int hits = 0;
  for (const auto& run : fs::directory_iterator(dir / "out" / "runs")) {
    const std::string manifest = testing::ReadFile(run.path() / "manifest.json");
    hits += manifest.find("\"frames_from_cache\": 6,") != std::string::npos ||
            manifest.find("\"frames_from_cache\":6,") != std::string::npos;
  }
  EXPECT_EQ(hits, 3);
  EXPECT_EQ(r.output.find("frames read from the frame cache"), std::string::npos) << r.output;
  // The report shows the rendered scene: the contact sheet the sweep wrote from
  // its own frame cache, embedded in the page. The report never renders: with
  // the sweep's cache gone and an empty default cache it still shows the
  // sheet, and it leaves that default cache empty.
  EXPECT_TRUE(fs::exists(dir / "out" / "contact_sheet.png"));
  fs::remove_all(dir / "cache");
  fs::create_directories(dir / "empty-cache");
  const auto report =
      testing::RunCommand("HCPF_CACHE_DIR=" + (dir / "empty-cache").string() + " " +
                          std::string(HCPF_EXE) + " report " + (dir / "out").string());
  ASSERT_EQ(report.exit_code, 0) << report.output;
  const std::string html = testing::ReadFile(dir / "out" / "report.html");
  EXPECT_NE(html.find("<img alt=\"contact sheet\""), std::string::npos);
  EXPECT_NE(html.find("data:image/png;base64,iVBORw0KGgo"), std::string::npos);  // PNG signature
  EXPECT_TRUE(fs::is_empty(dir / "empty-cache")) << "the report rendered frames";
  EXPECT_FALSE(fs::exists(dir / "cache")) << "the report rendered frames";
}

// A frame cache folder that cannot be made (under /proc, where no one can make
// one; an absent or read-only $HOME does the same) stops the sweep before its
// first run, naming the folder and the ways out; it failed every rendered run,
// each after making its GL context. The same command with --no-cache then
// computes them all.
TEST(RenderedSweep, AFrameCacheThatCannotBeMadeStopsTheSweepBeforeItsRuns) {
  const fs::path dir = testing::FreshDir("sweep-cache-blocked");
  std::ofstream(dir / "sweep.yaml")
      << "base: " << testing::LibraryScenario("crossing-dominant") << "\n"
      << "grid:\n"
      << "  observation.source: [rendered]\n"
      << "  frames: [4]\n"
      << "  tracker.particles: [100, 200]\n";
  const std::string sweep = std::string(HCPF_EXE) + " sweep " + (dir / "sweep.yaml").string() +
                            " --out " + (dir / "out").string();
  auto r = testing::RunCommand(sweep + " --cache /proc/hcpf-no-such-folder/frames");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("sweep failed: cannot create frame cache /proc/hcpf-no-such-folder/"
                          "frames: "),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("--no-cache"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("GL context"), std::string::npos) << "a run started:\n" << r.output;
  r = testing::RunCommand(sweep + " --no-cache");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("2 computed, 0 failed"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace hcpf
