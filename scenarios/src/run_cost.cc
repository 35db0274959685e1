// The cost model behind `hcpf validate`'s note on large scenarios.

#include <fmt/format.h>

#include "hcpf/scenarios/scenario.h"

namespace hcpf::scenarios {
namespace {

// Per frame, and per frame and target, measured with /usr/bin/time on
// detection-level runs of 20,000 frames with 1 and 8 targets (the `Large
// scenarios` table of docs/scenario.md gives the figures): peak resident
// memory 8.2 and 32.4 KB per frame, output 2.1 and 9.5 KB per frame.
constexpr double kMemoryPerFrame = 4.8e3;
constexpr double kMemoryPerTargetFrame = 3.4e3;
constexpr double kOutputPerFrame = 1.05e3;
constexpr double kOutputPerTargetFrame = 1.06e3;
// tracker.keep_particles: every frame's kept particles stay in its report
// until the files are written; 100,000 kept of 2 targets' filters took 6.8
// MB a frame more (crossing, 100 and 400 frames, /usr/bin/time; a scale
// audit found them left out of this estimate).
constexpr double kMemoryPerKeptParticle = 34.0;
// The executable, its libraries and the GL stack before the first frame.
constexpr double kMemoryBase = 60e6;
// Raw RGB.
constexpr double kBytesPerPixel = 3.0;

std::string Bytes(double bytes) {
  if (bytes >= 1e9) return fmt::format("{:.1f} GB", bytes / 1e9);
  return fmt::format("{:.0f} MB", bytes / 1e6);
}

}  // namespace

RunCost EstimateRunCost(const Scenario& scenario) {
  const double frames = scenario.world.frames;
  const double targets = static_cast<double>(scenario.world.targets.size());
  RunCost cost;
  cost.memory_bytes =
      kMemoryBase + frames * (kMemoryPerFrame +
                              targets * (kMemoryPerTargetFrame +
                                         kMemoryPerKeptParticle * scenario.tracker.keep_particles));
  cost.output_bytes = frames * (kOutputPerFrame + targets * kOutputPerTargetFrame);
  if (scenario.observation.source == ObservationSource::kRendered) {
    // Rendered frames go to the frame cache as lossless PNG, about half the raw size.
    const double pixels =
        static_cast<double>(scenario.world.camera.width_px) * scenario.world.camera.height_px;
    cost.cache_bytes = frames * pixels * kBytesPerPixel * 0.5;
  }
  return cost;
}

std::string LargeScenarioNote(const Scenario& scenario) {
  constexpr double kLarge = 256.0 * 1024 * 1024;
  const RunCost cost = EstimateRunCost(scenario);
  if (cost.memory_bytes < kLarge && cost.output_bytes + cost.cache_bytes < kLarge) return "";
  return fmt::format(
      "large scenario ({} frames, {} target{}): a run needs about {} of memory and writes about "
      "{}{} (a `hcpf sweep` needs that memory per job)",
      scenario.world.frames, scenario.world.targets.size(),
      scenario.world.targets.size() == 1 ? "" : "s", Bytes(cost.memory_bytes),
      Bytes(cost.output_bytes),
      cost.cache_bytes > 0 ? fmt::format(" plus about {} of cached frames", Bytes(cost.cache_bytes))
                           : std::string());
}

}  // namespace hcpf::scenarios
