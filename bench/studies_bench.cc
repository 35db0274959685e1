// Sweep expansion: a base scenario (scenarios/library/crossing.yaml) times
// `seeds` seeds in 2 cells. BM_ExpandSweep is ExpandSweep as shipped (seed
// indices >= 2 reseeded from each cell's first run); BM_ExpandSweepFullLoad
// loads every run in full, as the expansion did before (the figure that
// justifies the reseeding, docs/performance.md).

#include <benchmark/benchmark.h>

#include <string>

#include "hcpf/studies/sweep.h"

namespace {

hcpf::studies::SweepSpec Spec(int seeds) {
  const std::string text = "base: " + std::string(HCPF_SOURCE_DIR) +
                           "/scenarios/library/crossing.yaml\nseeds: " + std::to_string(seeds) +
                           "\ngrid: {tracker.particles: [100, 200]}\n";
  return hcpf::studies::LoadSweepText(text, "bench.yaml", ".");
}

void BM_ExpandSweep(benchmark::State& state) {
  const hcpf::studies::SweepSpec spec = Spec(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(hcpf::studies::ExpandSweep(spec));
  state.SetItemsProcessed(state.iterations() * spec.RunCount());
}
BENCHMARK(BM_ExpandSweep)->Arg(100)->Arg(2000)->Unit(benchmark::kMillisecond);

void BM_ExpandSweepFullLoad(benchmark::State& state) {
  const hcpf::studies::SweepSpec spec = Spec(static_cast<int>(state.range(0)));
  const std::vector<hcpf::studies::SweepRun> runs = hcpf::studies::ExpandSweep(spec);
  for (auto _ : state) {
    for (const hcpf::studies::SweepRun& run : runs) {
      const hcpf::scenarios::Scenario s =
          hcpf::scenarios::LoadScenarioFile(spec.base_path, run.overrides);
      benchmark::DoNotOptimize(hcpf::scenarios::ConfigHash(s));
    }
  }
  state.SetItemsProcessed(state.iterations() * spec.RunCount());
}
BENCHMARK(BM_ExpandSweepFullLoad)->Arg(100)->Unit(benchmark::kMillisecond);

}  // namespace
