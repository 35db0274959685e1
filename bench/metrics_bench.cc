// Benchmarks of the box metrics on a seeded synthetic sequence of the size the
// issue names: 2,000 frames x 30 objects (~45k gt boxes, ~44k tracker boxes with
// noise, misses, false positives and id switches).
//
//   metrics_bench                         run the benchmarks
//   metrics_bench --write-sequence DIR    also write DIR/gt/gt.txt, DIR/seqinfo.ini and
//                                         DIR/tracks.txt, to time `hcpf score` on them
//
// Generator: 30 target slots; each slot holds a target that lives 100-400 frames
// (then a new id takes the slot after a 0-158 frame gap, ~23 objects on average), moves with a
// random walk velocity, box 30-80 x 60-160 px in a 1920x1080 image. Tracker: each visible target is
// reported with p = 0.92, box jitter sigma 3 px (position) and 4% (size), track id changes with p =
// 0.002 per frame (an id switch), plus Poisson(1.0) false positives per frame.

#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "hcpf/core/rng.h"
#include "hcpf/metrics/mot_io.h"
#include "hcpf/metrics/mot_metrics.h"
#include "hcpf/metrics/report.h"

namespace {

using hcpf::metrics::MotRow;

struct Generated {
  std::vector<MotRow> gt;
  std::vector<MotRow> hyp;
  int frames = 0;
};

Generated Generate(uint64_t seed, int frames = 2000, int slots = 30) {
  hcpf::Rng rng(seed);
  hcpf::Rng gt_rng = rng.Fork("bench/metrics/gt");
  hcpf::Rng hyp_rng = rng.Fork("bench/metrics/hyp");
  struct Slot {
    int64_t id = 0;
    int life = 0;
    int gap = 0;
    double x = 0, y = 0, vx = 0, vy = 0, w = 0, h = 0;
    int64_t track = 0;
  };
  std::vector<Slot> slot(slots);
  int64_t next_id = 1;
  int64_t next_track = 1;
  auto spawn = [&](Slot& s) {
    s.id = next_id++;
    s.track = next_track++;
    s.life = 100 + static_cast<int>(gt_rng.UniformInt(301));
    s.gap = 0;
    s.w = gt_rng.Uniform(30, 80);
    s.h = gt_rng.Uniform(60, 160);
    s.x = gt_rng.Uniform(0, 1920 - s.w);
    s.y = gt_rng.Uniform(0, 1080 - s.h);
    s.vx = gt_rng.Normal(0, 2);
    s.vy = gt_rng.Normal(0, 1);
  };
  for (Slot& s : slot) spawn(s);
  Generated g;
  g.frames = frames;
  for (int f = 1; f <= frames; ++f) {
    for (Slot& s : slot) {
      if (s.life <= 0) {
        if (s.gap-- <= 0) spawn(s);
        continue;
      }
      if (--s.life == 0) s.gap = static_cast<int>(gt_rng.UniformInt(159));
      s.vx += gt_rng.Normal(0, 0.2);
      s.vy += gt_rng.Normal(0, 0.1);
      s.x = std::clamp(s.x + s.vx, 0.0, 1920 - s.w);
      s.y = std::clamp(s.y + s.vy, 0.0, 1080 - s.h);
      g.gt.push_back({.frame = f,
                      .id = s.id,
                      .box = {s.x + 1, s.y + 1, s.w, s.h},
                      .conf = 1,
                      .col8 = 1,
                      .col9 = 1});
      if (hyp_rng.Bernoulli(0.002)) s.track = next_track++;  // id switch
      if (!hyp_rng.Bernoulli(0.92)) continue;                // miss
      const double w = s.w * (1 + hyp_rng.Normal(0, 0.04));
      const double h = s.h * (1 + hyp_rng.Normal(0, 0.04));
      g.hyp.push_back(
          {.frame = f,
           .id = s.track,
           .box = {s.x + 1 + hyp_rng.Normal(0, 3), s.y + 1 + hyp_rng.Normal(0, 3), w, h},
           .conf = 0.9});
    }
    const int64_t clutter = hyp_rng.Poisson(1.0);
    for (int64_t c = 0; c < clutter; ++c) {
      g.hyp.push_back({.frame = f,
                       .id = 1000000 + next_track++,
                       .box = {hyp_rng.Uniform(0, 1850), hyp_rng.Uniform(0, 950), 50, 110},
                       .conf = 0.3});
    }
  }
  return g;
}

const Generated& Data() {
  static const Generated g = Generate(2024);
  return g;
}

hcpf::metrics::Sequence MakeSequence() {
  hcpf::metrics::MotFile gt{.path = "gt",
                            .kind = hcpf::metrics::MotFileKind::kGroundTruth,
                            .num_columns = 9,
                            .rows = Data().gt};
  hcpf::metrics::MotFile hyp{.path = "hyp",
                             .kind = hcpf::metrics::MotFileKind::kTracks,
                             .num_columns = 10,
                             .rows = Data().hyp};
  return hcpf::metrics::BuildSequence(gt, hyp, Data().frames, hcpf::metrics::Benchmark::kMot17);
}

void BM_ComputeAll(benchmark::State& state) {
  const hcpf::metrics::Sequence seq = MakeSequence();
  for (auto _ : state) {
    auto s = hcpf::metrics::ComputeAll(seq);
    benchmark::DoNotOptimize(s);
  }
  state.counters["gt_boxes"] = static_cast<double>(Data().gt.size());
  state.counters["hyp_boxes"] = static_cast<double>(Data().hyp.size());
}
BENCHMARK(BM_ComputeAll)->Unit(benchmark::kMillisecond);

void BM_Clear(benchmark::State& state) {
  const hcpf::metrics::Sequence seq = MakeSequence();
  for (auto _ : state) benchmark::DoNotOptimize(hcpf::metrics::ComputeClear(seq));
}
BENCHMARK(BM_Clear)->Unit(benchmark::kMillisecond);

void BM_Identity(benchmark::State& state) {
  const hcpf::metrics::Sequence seq = MakeSequence();
  for (auto _ : state) benchmark::DoNotOptimize(hcpf::metrics::ComputeIdentity(seq));
}
BENCHMARK(BM_Identity)->Unit(benchmark::kMillisecond);

void BM_Hota(benchmark::State& state) {
  const hcpf::metrics::Sequence seq = MakeSequence();
  for (auto _ : state) benchmark::DoNotOptimize(hcpf::metrics::ComputeHota(seq));
}
BENCHMARK(BM_Hota)->Unit(benchmark::kMillisecond);

// Parse + preprocess (MOT17 distractor step) + all metrics from text in memory.
void BM_ParseAndScore(benchmark::State& state) {
  const std::string gt_text = hcpf::metrics::FormatMotGroundTruth(Data().gt);
  const std::string hyp_text = hcpf::metrics::FormatMotTracks(Data().hyp);
  for (auto _ : state) {
    const auto gt = hcpf::metrics::ParseMotText(
        gt_text, "gt.txt", hcpf::metrics::MotFileKind::kGroundTruth, Data().frames);
    const auto hyp = hcpf::metrics::ParseMotText(
        hyp_text, "tracks.txt", hcpf::metrics::MotFileKind::kTracks, Data().frames);
    auto s = hcpf::metrics::ComputeAll(
        hcpf::metrics::BuildSequence(gt, hyp, Data().frames, hcpf::metrics::Benchmark::kMot17));
    benchmark::DoNotOptimize(s);
  }
}
BENCHMARK(BM_ParseAndScore)->Unit(benchmark::kMillisecond);

// Parse only: both files' text (already in memory) -> MotFile rows.
void BM_ParseOnly(benchmark::State& state) {
  const std::string gt_text = hcpf::metrics::FormatMotGroundTruth(Data().gt);
  const std::string hyp_text = hcpf::metrics::FormatMotTracks(Data().hyp);
  for (auto _ : state) {
    auto gt = hcpf::metrics::ParseMotText(gt_text, "gt.txt",
                                          hcpf::metrics::MotFileKind::kGroundTruth, Data().frames);
    auto hyp = hcpf::metrics::ParseMotText(hyp_text, "tracks.txt",
                                           hcpf::metrics::MotFileKind::kTracks, Data().frames);
    benchmark::DoNotOptimize(gt);
    benchmark::DoNotOptimize(hyp);
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) *
                          static_cast<int64_t>(gt_text.size() + hyp_text.size()));
}
BENCHMARK(BM_ParseOnly)->Unit(benchmark::kMillisecond);

// Preprocessing only: MotFiles -> Sequence (per-frame buckets + MOT17 distractor matching).
void BM_BuildSequence(benchmark::State& state) {
  const hcpf::metrics::MotFile gt{.path = "gt",
                                  .kind = hcpf::metrics::MotFileKind::kGroundTruth,
                                  .num_columns = 9,
                                  .rows = Data().gt};
  const hcpf::metrics::MotFile hyp{.path = "hyp",
                                   .kind = hcpf::metrics::MotFileKind::kTracks,
                                   .num_columns = 10,
                                   .rows = Data().hyp};
  for (auto _ : state) {
    auto seq =
        hcpf::metrics::BuildSequence(gt, hyp, Data().frames, hcpf::metrics::Benchmark::kMot17);
    benchmark::DoNotOptimize(seq);
  }
}
BENCHMARK(BM_BuildSequence)->Unit(benchmark::kMillisecond);

// What `hcpf score GT HYP` does after start-up: ScoreFiles on files written to a
// temporary folder (read + parse + seqinfo + preprocess + all metrics) and the table.
void BM_ScoreFiles(benchmark::State& state) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                    ("hcpf_metrics_bench_sequence_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir / "gt");
  hcpf::metrics::WriteMotGroundTruth((dir / "gt" / "gt.txt").string(), Data().gt);
  hcpf::metrics::WriteSeqInfo(
      (dir / "seqinfo.ini").string(),
      {.name = "BENCH-2000x30", .seq_length = Data().frames, .im_width = 1920, .im_height = 1080});
  hcpf::metrics::WriteMotTracks((dir / "tracks.txt").string(), Data().hyp);
  hcpf::metrics::ScoreFilesOptions options;
  options.gt_path = (dir / "gt" / "gt.txt").string();
  options.hyp_path = (dir / "tracks.txt").string();
  for (auto _ : state) {
    const hcpf::metrics::ScoredSequence s = hcpf::metrics::ScoreFiles(options);
    std::string table = hcpf::metrics::FormatMotTable({&s.summary, 1});
    benchmark::DoNotOptimize(table);
  }
  std::filesystem::remove_all(dir);
}
BENCHMARK(BM_ScoreFiles)->Unit(benchmark::kMillisecond);

// The --json output of `hcpf score` for one sequence.
void BM_SummaryJson(benchmark::State& state) {
  const hcpf::metrics::MotSummary summary = hcpf::metrics::ComputeAll(MakeSequence());
  for (auto _ : state) {
    std::string json = hcpf::metrics::MotSummariesToJson({&summary, 1}, nullptr);
    benchmark::DoNotOptimize(json);
  }
}
BENCHMARK(BM_SummaryJson)->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], "--write-sequence") == 0) {
      const std::filesystem::path dir = argv[i + 1];
      std::filesystem::create_directories(dir / "gt");
      hcpf::metrics::WriteMotGroundTruth((dir / "gt" / "gt.txt").string(), Data().gt);
      hcpf::metrics::WriteSeqInfo((dir / "seqinfo.ini").string(), {.name = "BENCH-2000x30",
                                                                   .seq_length = Data().frames,
                                                                   .im_width = 1920,
                                                                   .im_height = 1080});
      hcpf::metrics::WriteMotTracks((dir / "tracks.txt").string(), Data().hyp);
      std::printf("wrote %zu gt and %zu tracker boxes to %s\n", Data().gt.size(), Data().hyp.size(),
                  dir.c_str());
      // Drop the two arguments before handing the rest to Google Benchmark.
      for (int j = i; j + 2 < argc; ++j) argv[j] = argv[j + 2];
      argc -= 2;
      break;
    }
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
