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
  EXPECT_GE(files, 10) << "default, detector-size, detector-sun, thesis-ch10-crossing/parallel/"
                          "hierarchical, external-sort, crossing-rendered, thesis-ch11, "
                          "climb-hierarchical";
}

// The honest baselines (#14): the main job and the thesis ch. 10 sweeps
// compare the resamplers under both likelihood models, one panel each, with
// systematic as the paired reference.
TEST(ShippedSweeps, ResamplerComparisonsSweepBothLikelihoodModels) {
  const fs::path dir = fs::path(HCPF_SOURCE_DIR) / "scenarios" / "sweeps";
  for (const char* name :
       {"default.yaml", "thesis-ch10-crossing.yaml", "thesis-ch10-parallel.yaml"}) {
    SCOPED_TRACE(name);
    const SweepSpec spec = LoadSweepFile((dir / name).string());
    const SweepAxis* likelihood = nullptr;
    for (const SweepAxis& a : spec.grid) {
      if (a.key == "tracker.likelihood.model") likelihood = &a;
    }
    ASSERT_NE(likelihood, nullptr);
    EXPECT_EQ(likelihood->values, (std::vector<std::string>{"detections_mixture", "associated"}));
    EXPECT_EQ(spec.report.series, "tracker.resampling.method");
    EXPECT_EQ(spec.report.panels, "tracker.likelihood.model");
    EXPECT_EQ(spec.report.reference, "systematic");
  }
}

// A shipped sweep that names a reference to compare with has the seeds for
// its comparisons to survive Holm's correction (SeedsForHolmNote says
// nothing). Left out: crossing-rendered.yaml, the speed sweep issue 11
// specifies at 10 seeds, whose report is read for its curves; and
// detector-sun-confirm.yaml, a test stated and run on 2026-12-04 with 6
// seeds when pooled azimuths counted as pairs, kept as it ran (its second
// claim is re-tested with the seeds by detector-sun-low.yaml). The
// descriptive detector-size and detector-sun sweeps name none. Before the
// rule the main job (default.yaml, 10 seeds, 84 comparisons) could keep none.
TEST(ShippedSweeps, ComparisonsHaveTheSeedsHolmNeeds) {
  const fs::path dir = fs::path(HCPF_SOURCE_DIR) / "scenarios" / "sweeps";
  int checked = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (entry.path().extension() != ".yaml" || name == "crossing-rendered.yaml" ||
        name == "detector-sun-confirm.yaml")
      continue;
    const SweepSpec spec = LoadSweepFile(entry.path().string());
    EXPECT_EQ(ZippedPoolNote(spec), "") << entry.path();
    if (spec.report.reference.empty()) continue;
    ++checked;
    EXPECT_EQ(SeedsForHolmNote(spec), "") << entry.path();
  }
  EXPECT_GE(checked, 12);
}

}  // namespace
}  // namespace hcpf::studies
