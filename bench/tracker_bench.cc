// Tracker benchmarks (issue 4 targets):
//   BM_Resample/<method>/100000        systematic <= 5 ns per particle
//   BM_FilterStep/systematic/10000     predict + detections_mixture (10 dets) +
//                                      systematic: >= 30 M particle-steps/s
//   BM_FilterStep/charged_k10/10000    charged with K = 10: <= 2x the above
//   BM_TrackerFrame/<N>/<K>            whole bank, time per frame
//   BM_GatedAssignment/<gate>/<n>      n tentatives x n detections placed at
//                                      random in 640x480, gated at <gate> px
//   BM_DenseAssignment/<gate>/<n>      the same matrix solved whole (before
//                                      2026-12-07)
// items_per_second is particles (or particle-steps) per second on one core.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "hcpf/core/assignment.h"
#include "hcpf/core/normal.h"
#include "hcpf/core/rng.h"
#include "hcpf/tracker/dynamics.h"
#include "hcpf/tracker/hungarian.h"
#include "hcpf/tracker/likelihood.h"
#include "hcpf/tracker/particle_set.h"
#include "hcpf/tracker/resampler.h"
#include "hcpf/tracker/scene_motion.h"
#include "hcpf/tracker/tracker.h"

namespace {

using namespace hcpf;
using namespace hcpf::tracker;

// A cloud around (320, 240), spread 10 px, with weights from a Gaussian
// likelihood so the resamplers see a realistic, non-uniform weight vector.
ParticleSet MakeCloud(size_t n, uint64_t seed) {
  Rng rng(seed);
  ParticleSet set;
  set.Resize(n);
  for (size_t i = 0; i < n; ++i) {
    set.px[i] = 320.0 + 10.0 * rng.Normal();
    set.py[i] = 240.0 + 10.0 * rng.Normal();
    set.vx[i] = 0.5 * rng.Normal();
    set.vy[i] = 0.5 * rng.Normal();
    const double dx = set.px[i] - 322.0;
    const double dy = set.py[i] - 238.0;
    set.log_w[i] = -(dx * dx + dy * dy) / (2.0 * 9.0);
  }
  NormaliseLogWeights(set);
  return set;
}

// `detections` detections: dense = all within +-40 px of the cloud (worst
// case: every detection contributes to every particle); spread = one on the
// cloud and the others on a grid over a 640x480 image (a typical frame: the
// others are skipped by the likelihood's negligible-component cut-off).
Observation MakeObservation(int detections, bool spread = false) {
  Observation obs;
  for (int d = 0; d < detections; ++d) {
    double cx = 300.0 + 40.0 * std::cos(0.7 * d);
    double cy = 240.0 + 40.0 * std::sin(0.9 * d);
    if (spread) {
      cx = d == 0 ? 322.0 : 64.0 + 128.0 * (d % 5);
      cy = d == 0 ? 238.0 : (d < 5 ? 60.0 : 420.0);
    }
    obs.detections.push_back({.box = BoxPx::FromCentre(cx, cy, 20, 12), .score = 0.5 + 0.05 * d});
  }
  return obs;
}

void BM_Resample(benchmark::State& state, ResamplingMethod method) {
  const auto n = static_cast<size_t>(state.range(0));
  const ParticleSet set = MakeCloud(n, 1);
  ResamplerOptions options;
  options.method = method;
  const auto resampler = MakeResampler(options);
  std::vector<int32_t> ancestors(n);
  Rng rng(2);
  for (auto _ : state) {
    resampler->Resample(set, {}, rng, ancestors);
    benchmark::DoNotOptimize(ancestors.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * n));
}
BENCHMARK_CAPTURE(BM_Resample, multinomial, ResamplingMethod::kMultinomial)->Arg(100000);
BENCHMARK_CAPTURE(BM_Resample, systematic, ResamplingMethod::kSystematic)->Arg(100000);
BENCHMARK_CAPTURE(BM_Resample, stratified, ResamplingMethod::kStratified)->Arg(100000);
BENCHMARK_CAPTURE(BM_Resample, residual, ResamplingMethod::kResidual)->Arg(100000);

// Systematic resampling plus the ancestor gather (the full resampling cost
// a filter pays).
void BM_ResampleAndGather(benchmark::State& state) {
  const auto n = static_cast<size_t>(state.range(0));
  const ParticleSet base = MakeCloud(n, 1);
  ParticleSet set = base;
  ParticleSet scratch;
  SystematicResampler resampler;
  std::vector<int32_t> ancestors(n);
  Rng rng(2);
  for (auto _ : state) {
    resampler.Resample(base, {}, rng, ancestors);
    ApplyAncestors(set, ancestors, scratch);
    benchmark::DoNotOptimize(set.px.data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * n));
}
BENCHMARK(BM_ResampleAndGather)->Arg(100000);

// Calibration: the raw xoshiro256** draw every variate is built from (compare
// its ns/item with the others to see how loaded the machine is).
void BM_RawU64(benchmark::State& state) {
  std::vector<uint64_t> out(4096);
  Rng rng(3);
  for (auto _ : state) {
    for (uint64_t& v : out) v = rng.NextU64();
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * out.size()));
}
BENCHMARK(BM_RawU64);

void BM_Normals(benchmark::State& state) {
  std::vector<double> out(4096);
  Rng rng(3);
  for (auto _ : state) {
    FillStandardNormal(rng, out);
    benchmark::DoNotOptimize(out.data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * out.size()));
}
BENCHMARK(BM_Normals);

// K - 1 neighbour summaries around the cloud (the charged resampler's context
// for a bank of K filters): all within 25 px (worst case, every charge acts on
// every particle) or spread 60 px apart over the image (typical: only the
// nearest few are within range).
std::vector<FilterSummary> Neighbours(int k, bool spread) {
  std::vector<FilterSummary> others;
  for (int j = 1; j < k; ++j) {
    FilterSummary s;
    s.id = TrackId{j};
    if (spread) {
      s.mean = {320.0 + 60.0 * ((j % 5) - 2), 240.0 + 60.0 * (j / 5 + 1)};
    } else {
      s.mean = {320.0 + 25.0 * std::cos(j), 240.0 + 25.0 * std::sin(j)};
    }
    s.cov << 25.0, 3.0, 3.0, 16.0;
    others.push_back(s);
  }
  return others;
}

// One filter step: constant-velocity predict, detections_mixture over 10
// detections, normalise, resample (systematic, or charged against K-1
// neighbours), gather. state.range(0) = N, state.range(1) = K (0 = systematic),
// state.range(2) = 1 for spread neighbours, state.range(3) = 1 for spread
// detections.
void BM_FilterStep(benchmark::State& state) {
  const auto n = static_cast<size_t>(state.range(0));
  const int k = static_cast<int>(state.range(1));
  ParticleSet set = MakeCloud(n, 4);
  ParticleSet scratch;
  ConstantVelocityDynamics dynamics(1.5, 0.3);
  LikelihoodOptions lo;
  DetectionsMixtureLikelihood likelihood(lo);
  const Observation obs = MakeObservation(10, state.range(3) != 0);
  ResamplerOptions ro;
  ro.method = k > 0 ? ResamplingMethod::kCharged : ResamplingMethod::kSystematic;
  const auto resampler = MakeResampler(ro);
  const std::vector<FilterSummary> others =
      k > 0 ? Neighbours(k, state.range(2) != 0) : std::vector<FilterSummary>{};
  std::vector<int32_t> ancestors(n);
  Rng rng(5);
  const ParticleSet start = set;
  int64_t rejections = 0;
  for (auto _ : state) {
    dynamics.Predict(set, rng);
    likelihood.AddLogLikelihood(set, {.observation = &obs, .base_w_px = 20, .base_h_px = 12});
    NormaliseLogWeights(set);
    rejections += resampler->Resample(set, ResampleContext{others}, rng, ancestors).rejections;
    ApplyAncestors(set, ancestors, scratch);
    // Keep the cloud where the detections are (else it drifts off over
    // millions of iterations and the numbers change).
    state.PauseTiming();
    if (state.iterations() % 64 == 0) set = start;
    state.ResumeTiming();
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * n));
  state.counters["rejections_per_step"] =
      benchmark::Counter(static_cast<double>(rejections), benchmark::Counter::kAvgIterations);
}
BENCHMARK(BM_FilterStep)->Args({10000, 0, 0, 0})->Name("BM_FilterStep/systematic_dense");
BENCHMARK(BM_FilterStep)->Args({10000, 10, 0, 0})->Name("BM_FilterStep/charged_k10_close_dense");
BENCHMARK(BM_FilterStep)->Args({10000, 0, 0, 1})->Name("BM_FilterStep/systematic_spread");
BENCHMARK(BM_FilterStep)->Args({10000, 10, 1, 1})->Name("BM_FilterStep/charged_k10_spread");

// Components alone at N = 1e4 (to see where the step's time goes).
void BM_PredictCv(benchmark::State& state) {
  const auto n = static_cast<size_t>(state.range(0));
  ParticleSet set = MakeCloud(n, 4);
  ConstantVelocityDynamics dynamics(1.5, 0.3);
  Rng rng(6);
  for (auto _ : state) {
    dynamics.Predict(set, rng);
    benchmark::DoNotOptimize(set.px.data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * n));
}
BENCHMARK(BM_PredictCv)->Arg(10000);

void BM_Mixture10(benchmark::State& state) {
  const auto n = static_cast<size_t>(state.range(0));
  ParticleSet set = MakeCloud(n, 4);
  LikelihoodOptions lo;
  DetectionsMixtureLikelihood likelihood(lo);
  const Observation obs = MakeObservation(10);
  for (auto _ : state) {
    likelihood.AddLogLikelihood(set, {.observation = &obs, .base_w_px = 20, .base_h_px = 12});
    benchmark::DoNotOptimize(set.log_w.data());
    state.PauseTiming();
    std::fill(set.log_w.begin(), set.log_w.end(), 0.0);
    state.ResumeTiming();
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * n));
}
BENCHMARK(BM_Mixture10)->Arg(10000);

// The whole bank: K targets on a grid 60 px apart, one detection each (plus
// the bank's association, summaries, charged resampling), time per frame.
void BM_TrackerFrame(benchmark::State& state, ResamplingMethod method) {
  const int n = static_cast<int>(state.range(0));
  const int k = static_cast<int>(state.range(1));
  TrackerOptions options;
  options.particles = n;
  options.resampling.method = method;
  options.management.max_missed_frames = 0;
  auto tracker = MakeTracker(options, Rng(7));
  Observation obs;
  for (int j = 0; j < k; ++j) {
    const BoxPx box = BoxPx::FromCentre(40.0 + 60.0 * (j % 8), 40.0 + 60.0 * (j / 8), 20, 12);
    tracker->BirthTrack(TrackId{j + 1}, box);
    obs.detections.push_back({.box = box, .score = 1.0});
  }
  for (auto _ : state) {
    const FrameReport report = tracker->Step(obs);
    benchmark::DoNotOptimize(report.filters.data());
    ++obs.frame;
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * n * k);
}
BENCHMARK_CAPTURE(BM_TrackerFrame, systematic, ResamplingMethod::kSystematic)
    ->ArgsProduct({{100, 1000, 10000, 100000}, {2, 5, 10, 20}})
    ->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(BM_TrackerFrame, charged, ResamplingMethod::kCharged)
    ->ArgsProduct({{100, 1000, 10000, 100000}, {2, 5, 10, 20}})
    ->Unit(benchmark::kMicrosecond);

// One scene-filter frame (issue 12 target: <= 3 ms with 200 particles and
// <= 500 points on one core): state.range(0) particles, state.range(1)
// point tracks of a known similarity with 0.3 px noise and 10 % mis-tracks,
// the laplace proposal (default). Each iteration is one Step on a filter that
// has already converged (its steady state in a run).
void BM_SceneFilterStep(benchmark::State& state) {
  SceneMotionOptions options;
  options.particles = static_cast<int>(state.range(0));
  const SimilarityMotion truth{2.0, -1.0, 0.004, 0.002};
  Rng rng(3);
  std::vector<PointTrack> tracks;
  for (int k = 0; k < state.range(1); ++k) {
    PointTrack t;
    t.p = {rng.Uniform(0, 640), rng.Uniform(0, 480)};
    t.q = Apply(truth, t.p) + Eigen::Vector2d(0.3 * rng.Normal(), 0.3 * rng.Normal());
    if (rng.Uniform() < 0.1) t.q = {rng.Uniform(0, 640), rng.Uniform(0, 480)};
    tracks.push_back(t);
  }
  const PointTrackEvidence evidence(tracks, options);
  SceneMotionFilter filter(options, 640, 480, Rng(5).Fork("scene"));
  for (int f = 0; f < 5; ++f) filter.Step(evidence, {});
  for (auto _ : state) benchmark::DoNotOptimize(filter.Step(evidence, {}));
}
BENCHMARK(BM_SceneFilterStep)->Args({200, 500})->Args({1000, 200})->Unit(benchmark::kMillisecond);

// The M-of-N initiator's matrix under clutter: n tentatives and n free
// detections uniform in a 640x480 frame, cost the squared distance within
// the gate, forbidden beyond. 20 px is the default tentative gate; at 800
// points and 20 px each point has ~3 neighbours, near the plane's
// percolation threshold, so one block holds a sizeable share of them.
std::vector<double> GatedMatrix(int n, double gate) {
  Rng rng(7);
  std::vector<double> x(static_cast<size_t>(2 * n)), y(static_cast<size_t>(2 * n));
  for (size_t k = 0; k < x.size(); ++k) {
    x[k] = rng.Uniform(0.0, 640.0);
    y[k] = rng.Uniform(0.0, 480.0);
  }
  std::vector<double> cost(static_cast<size_t>(n) * n, std::numeric_limits<double>::infinity());
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) {
      const double dx = x[static_cast<size_t>(r)] - x[static_cast<size_t>(n + c)];
      const double dy = y[static_cast<size_t>(r)] - y[static_cast<size_t>(n + c)];
      const double d2 = dx * dx + dy * dy;
      if (d2 <= gate * gate) cost[static_cast<size_t>(r) * n + c] = d2;
    }
  }
  return cost;
}

void BM_GatedAssignment(benchmark::State& state) {
  const int n = static_cast<int>(state.range(1));
  const std::vector<double> cost = GatedMatrix(n, static_cast<double>(state.range(0)));
  for (auto _ : state) benchmark::DoNotOptimize(SolveAssignment(cost, n, n));
}
BENCHMARK(BM_GatedAssignment)
    ->ArgsProduct({{20, 60}, {100, 400, 1600}})
    ->Unit(benchmark::kMicrosecond);

// The whole matrix in one dense solve, forbidden entries priced above any
// finite assignment: what SolveAssignment did before it split blocks.
void BM_DenseAssignment(benchmark::State& state) {
  const int n = static_cast<int>(state.range(1));
  std::vector<double> cost = GatedMatrix(n, static_cast<double>(state.range(0)));
  double max_finite = 0.0;
  for (const double c : cost) {
    if (std::isfinite(c)) max_finite = std::max(max_finite, c);
  }
  for (double& c : cost) {
    if (!std::isfinite(c)) c = (max_finite + 1.0) * (n + 1);
  }
  AssignmentSolver solver;
  for (auto _ : state)
    benchmark::DoNotOptimize(solver.Solve(cost, n, n, AssignmentSense::kMinimise));
}
BENCHMARK(BM_DenseAssignment)
    ->ArgsProduct({{20, 60}, {100, 400, 1600}})
    ->Unit(benchmark::kMicrosecond);

}  // namespace
