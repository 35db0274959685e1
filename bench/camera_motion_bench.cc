// Camera-motion evidence benchmarks (issue 12, items 2 and 3), one core
// (cv::setNumThreads(1)), 640 x 480:
//   BM_TrackBackgroundPoints/flow_percent:F/window:W
//       corners of frame t-1 tracked into frame t, the 5 vehicles' boxes
//       excluded (grown by 4 px); Lucas-Kanade at F % of full resolution
//       with a W px window (0/0: the PointTrackerOptions defaults);
//       target <= 5 ms per frame
//   BM_RansacSimilarity
//       the RANSAC similarity of the default tracks
// The frames: bench/aerial_frames.h's frame 0 and frame 1 (every vehicle
// moved and turned) seen by a camera that moved by the similarity kMotion
// (frame 1 warped by cv::warpAffine, bilinear). Counters: tracks, and the
// RANSAC fit's corner displacement from kMotion (px; the warp's bilinear
// resampling included). docs/vision.md has the figures.
//
//   build/ci/bench/camera_motion_bench --benchmark_repetitions=5

#include <benchmark/benchmark.h>

#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <vector>

#include "aerial_frames.h"
#include "hcpf/vision/point_tracks.h"

namespace {

using namespace hcpf;
using namespace hcpf::bench;

// About what the climb scenario's camera does in one frame.
const SimilarityMotion kMotion{
    .tx_px = 2.3, .ty_px = -1.7, .log_scale = 0.004, .rotation_rad = 0.002};

struct Pair {
  RgbImage previous, current;
  std::vector<BoxPx> exclude;  // frame 0's vehicle boxes
};

const Pair& GetPair() {
  static const Pair pair = [] {
    Pair p;
    p.previous = MakeFrame(Vehicles(0), 0.0, 1);
    for (const Vehicle& v : Vehicles(0)) p.exclude.push_back(BoxOf(v));
    const RgbImage moved = MakeFrame(Vehicles(1), 0.0, 2);
    // kMotion in OpenCV's pixel convention (centres at integers; the
    // project's at +0.5): x_cv' = A x_cv + t + (A - I) (0.5, 0.5).
    const double k = std::exp(kMotion.log_scale);
    const double a = k * std::cos(kMotion.rotation_rad), b = k * std::sin(kMotion.rotation_rad);
    const cv::Matx23d warp(a, -b, kMotion.tx_px + 0.5 * (a - 1.0) - 0.5 * b,  //
                           b, a, kMotion.ty_px + 0.5 * b + 0.5 * (a - 1.0));
    p.current = moved;
    const cv::Mat src(kHeight, kWidth, CV_8UC3, const_cast<uint8_t*>(moved.pixels.data()));
    cv::Mat dst(kHeight, kWidth, CV_8UC3, p.current.pixels.data());
    cv::warpAffine(src, dst, warp, dst.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
    return p;
  }();
  return pair;
}

double CornerError(const SimilarityMotion& s) {
  const auto apply = [](const SimilarityMotion& m, double x, double y) {
    const double k = std::exp(m.log_scale);
    const double a = k * std::cos(m.rotation_rad), b = k * std::sin(m.rotation_rad);
    return std::pair(a * x - b * y + m.tx_px, b * x + a * y + m.ty_px);
  };
  double sum = 0.0;
  for (const auto& [x, y] : {std::pair(0.0, 0.0), std::pair(640.0, 0.0), std::pair(640.0, 480.0),
                             std::pair(0.0, 480.0)}) {
    const auto [ex, ey] = apply(s, x, y);
    const auto [tx, ty] = apply(kMotion, x, y);
    sum += std::hypot(ex - tx, ey - ty);
  }
  return sum / 4.0;
}

// Lucas-Kanade at flow_percent / 100 of full resolution with a window of
// window_px (0: the defaults).
vision::PointTrackerOptions Options(int64_t flow_percent, int64_t window_px) {
  vision::PointTrackerOptions o;
  if (flow_percent > 0) o.flow_scale = static_cast<double>(flow_percent) / 100.0;
  if (window_px > 0) o.window_px = static_cast<int>(window_px);
  return o;
}

void BM_TrackBackgroundPoints(benchmark::State& state) {
  cv::setNumThreads(1);
  const Pair& pair = GetPair();
  const vision::PointTrackerOptions options = Options(state.range(0), state.range(1));
  size_t tracks = 0;
  for (auto _ : state) {
    const std::vector<PointTrack> t =
        vision::TrackBackgroundPoints(pair.previous, pair.current, pair.exclude, 4.0, options);
    tracks = t.size();
    benchmark::DoNotOptimize(t.data());
  }
  state.counters["tracks"] = static_cast<double>(tracks);
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_TrackBackgroundPoints)
    ->ArgNames({"flow_percent", "window"})
    ->Args({0, 0})
    ->Args({100, 9})
    ->Args({100, 11})
    ->Args({100, 21})
    ->Args({50, 11})
    ->Unit(benchmark::kMillisecond);

void BM_RansacSimilarity(benchmark::State& state) {
  cv::setNumThreads(1);
  const Pair& pair = GetPair();
  const std::vector<PointTrack> tracks =
      vision::TrackBackgroundPoints(pair.previous, pair.current, pair.exclude, 4.0, Options(0, 0));
  std::optional<SimilarityMotion> s;
  for (auto _ : state) {
    s = vision::EstimateSimilarityRansac(tracks, vision::RansacOptions{});
    benchmark::DoNotOptimize(s);
  }
  state.counters["tracks"] = static_cast<double>(tracks.size());
  state.counters["corner_error_px"] = s ? CornerError(*s) : -1.0;
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_RansacSimilarity)->Unit(benchmark::kMillisecond);

}  // namespace
