// Every sweep shipped in scenarios/sweeps/ loads and expands: each of its
// runs is a valid scenario (ExpandSweep validates every one), so a user who
// runs it never meets a bad run halfway.

#include <gtest/gtest.h>

#include <filesystem>

#include "hcpf/studies/sweep.h"

namespace hcpf::studies {
namespace {

namespace fs = std::filesystem;

TEST(ShippedSweeps, EveryFileLoadsAndExpands) {
  const fs::path dir = fs::path(HCPF_SOURCE_DIR) / "scenarios" / "sweeps";
  int files = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".yaml") continue;
    ++files;
    SCOPED_TRACE(entry.path().string());
    const SweepSpec spec = LoadSweepFile(entry.path().string());
    const std::vector<SweepRun> runs = ExpandSweep(spec);
    EXPECT_EQ(static_cast<int64_t>(runs.size()), spec.RunCount());
    EXPECT_GT(runs.size(), 0u);
  }
  EXPECT_GE(files, 7) << "default, detector-size, detector-sun, thesis-ch10-crossing/parallel, "
                         "crossing-rendered, thesis-ch11";
}

}  // namespace
}  // namespace hcpf::studies
