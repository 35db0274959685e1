// Sweep expansion: a base scenario (scenarios/library/crossing.yaml) times
// `seeds` seeds in 2 cells. BM_ExpandSweep is ExpandSweep as shipped (seed
// indices >= 2 reseeded from each cell's first run); BM_ExpandSweepFullLoad
// loads every run in full, as the expansion did before (the figure that
// justifies the reseeding, docs/performance.md). BM_HolmTarone: the
// report's multiple-comparison correction over m comparisons (a sweep of
// m / 5 compared cells and 5 metrics), a third of them with few seeds that
// differ, against BM_Holm, Holm's correction alone.

#include <benchmark/benchmark.h>
#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "hcpf/studies/results_store.h"
#include "hcpf/studies/statistics.h"
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

// Reading a results store of `runs` rows (a grid of 2 keys × 10 seeds, every
// row put): BM_StoreRuns is Runs(), which holds each row's labels to the
// recorded expansion; BM_StoreRunsAsStored reads them as they are (the
// sweep's read). The difference is the cost of the check.
std::string StoreOf(int runs) {
  namespace st = hcpf::studies;
  const std::string path = fmt::format("/tmp/hcpf-bench-store-{}-{}.sqlite", runs, ::getpid());
  std::filesystem::remove(path);
  const int side = static_cast<int>(std::sqrt(runs / 10));
  st::StoreMeta meta;
  meta.sweep_hash = "bench";
  meta.swept_keys = {"tracker.particles", "camera.fov_deg"};
  meta.report = {"tracker.particles", {"mota"}, ""};
  st::StoredExpansion e;
  e.grid = {{"tracker.particles", {}}, {"camera.fov_deg", {}}};
  for (int i = 0; i < side; ++i) {
    e.grid[0].values.push_back(std::to_string(100 + i));
    e.grid[1].values.push_back(std::to_string(20 + i));
  }
  e.seeds = 10;
  meta.root_seed = "1";
  meta.root_seed_from = "sweep file";
  meta.run_count = e.RunCount();
  meta.expansion = e;
  auto store = st::ResultsStore::OpenOrCreate(path, meta);
  for (int64_t i = 0; i < meta.run_count; ++i) {
    st::RunRecord r;
    r.key = fmt::format("{:016x}", i);
    r.index = i;
    r.seed_index = e.SeedIndex(i);
    r.seed = st::SweepSeed(1, r.seed_index);
    r.values = e.Values(i);
    r.ok = true;
    r.run_dir = "runs/" + r.key;
    r.metrics["mota"] = 0.5;
    store->Put(r);
  }
  return path;
}

void StoreRead(benchmark::State& state, bool checked) {
  const std::string path = StoreOf(static_cast<int>(state.range(0)));
  const auto store = hcpf::studies::ResultsStore::Open(path);
  size_t rows = 0;
  for (auto _ : state) {
    const auto runs = checked ? store->Runs() : store->RunsAsStored();
    rows = runs.size();
    benchmark::DoNotOptimize(runs.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(rows));
  std::filesystem::remove(path);
}
void BM_StoreRuns(benchmark::State& state) { StoreRead(state, true); }
void BM_StoreRunsAsStored(benchmark::State& state) { StoreRead(state, false); }
BENCHMARK(BM_StoreRuns)->Arg(10000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_StoreRunsAsStored)->Arg(10000)->Unit(benchmark::kMillisecond);

// m comparisons: p spread over (0, 1) by a fixed rule, floors 2 / 2^20 for
// two in three, 2 / 2^6 for the rest (p raised to its floor where below).
struct Comparisons {
  std::vector<double> p, floors;
};
Comparisons MakeComparisons(int m) {
  Comparisons c;
  for (int i = 0; i < m; ++i) {
    const double floor = i % 3 == 2 ? std::ldexp(2.0, -6) : std::ldexp(2.0, -20);
    const double p = std::fmod(0.6180339887 * (i + 1), 1.0) * std::pow(10.0, -(i % 7));
    c.floors.push_back(floor);
    c.p.push_back(std::max(p, floor));
  }
  return c;
}

void BM_HolmTarone(benchmark::State& state) {
  const Comparisons c = MakeComparisons(static_cast<int>(state.range(0)));
  for (auto _ : state) {
    benchmark::DoNotOptimize(hcpf::studies::HolmTaroneAdjusted(c.p, c.floors, 0.05));
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_HolmTarone)->Arg(100)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);

void BM_Holm(benchmark::State& state) {
  const Comparisons c = MakeComparisons(static_cast<int>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(hcpf::studies::HolmAdjusted(c.p));
  state.SetItemsProcessed(state.iterations() * state.range(0));
}
BENCHMARK(BM_Holm)->Arg(100)->Arg(1000)->Arg(10000)->Unit(benchmark::kMillisecond);

}  // namespace
