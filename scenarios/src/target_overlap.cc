// Targets that drive through each other: their ground footprints (the
// length x width rectangle about the base, turned to the heading) overlap.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <tuple>
#include <unordered_map>

#include "hcpf/scenarios/scenario.h"

namespace hcpf::scenarios {

namespace {

// A target's footprint at one frame: centre, unit axes along and across its
// heading, half length and half width.
struct Footprint {
  Eigen::Vector2d centre;
  std::array<Eigen::Vector2d, 2> axes;
  Eigen::Vector2d half;
  double radius = 0.0;  // of the circle through its corners
};

Footprint FootprintOf(const TargetSpec& target, const TargetPose& pose) {
  const double yaw = pose.heading_deg * std::numbers::pi / 180.0;
  Footprint f;
  f.centre = pose.position_m.head<2>();
  f.axes = {Eigen::Vector2d(std::cos(yaw), std::sin(yaw)),
            Eigen::Vector2d(-std::sin(yaw), std::cos(yaw))};
  f.half = 0.5 * target.dimensions_m.head<2>();
  f.radius = f.half.norm();
  return f;
}

// The overlap of two rectangles' projections on `axis` (negative when the
// projections are apart).
double ProjectionOverlap(const Footprint& a, const Footprint& b, const Eigen::Vector2d& axis) {
  const auto reach = [&axis](const Footprint& f) {
    return f.half.x() * std::abs(f.axes[0].dot(axis)) + f.half.y() * std::abs(f.axes[1].dot(axis));
  };
  return reach(a) + reach(b) - std::abs((b.centre - a.centre).dot(axis));
}

// The depth by which two rectangles interpenetrate: the least projection
// overlap over their four edge normals (separating axis theorem), <= 0 when
// they do not overlap.
double PenetrationDepth(const Footprint& a, const Footprint& b) {
  if ((b.centre - a.centre).norm() >= a.radius + b.radius) return 0.0;
  double depth = std::numeric_limits<double>::infinity();
  for (const Footprint* f : {&a, &b}) {
    for (const Eigen::Vector2d& axis : f->axes) {
      depth = std::min(depth, ProjectionOverlap(a, b, axis));
    }
  }
  return depth;
}

}  // namespace

std::vector<TargetOverlap> TargetOverlaps(const WorldSpec& world) {
  const size_t n = world.targets.size();
  std::vector<TargetOverlap> overlaps;
  // Each pair's entry in `overlaps`, keyed by its two indices.
  std::unordered_map<uint64_t, size_t> entry;
  struct Present {
    size_t index;
    Footprint footprint;
  };
  std::vector<Present> present;
  struct Met {
    size_t i, j;  // i < j, indices into world.targets
    double depth;
  };
  std::vector<Met> met;
  for (int frame = 0; frame < world.frames; ++frame) {
    present.clear();
    for (size_t i = 0; i < n; ++i) {
      const TargetSpec& t = world.targets[i];
      const TargetPose pose = EvaluatePath(t.path, frame, world.fps);
      if (pose.present) present.push_back({i, FootprintOf(t, pose)});
    }
    // Sweep and prune on x: only footprints whose circles' x-extents meet
    // are compared (a scene of thousands of targets is not n^2 a frame).
    std::sort(present.begin(), present.end(), [](const Present& p, const Present& q) {
      return p.footprint.centre.x() - p.footprint.radius <
             q.footprint.centre.x() - q.footprint.radius;
    });
    met.clear();
    for (size_t p = 0; p < present.size(); ++p) {
      const Footprint& f = present[p].footprint;
      for (size_t q = p + 1; q < present.size(); ++q) {
        const Footprint& g = present[q].footprint;
        if (g.centre.x() - g.radius >= f.centre.x() + f.radius) break;
        const double depth = PenetrationDepth(f, g);
        if (!(depth > kTargetOverlapDepthM)) continue;
        met.push_back({std::min(present[p].index, present[q].index),
                       std::max(present[p].index, present[q].index), depth});
      }
    }
    // In the targets' order, so that pairs first seen on one frame are listed so.
    std::sort(met.begin(), met.end(),
              [](const Met& a, const Met& b) { return std::tie(a.i, a.j) < std::tie(b.i, b.j); });
    for (const auto& [i, j, depth] : met) {
      const auto [it, added] = entry.try_emplace(i * n + j, overlaps.size());
      if (added) {
        overlaps.push_back({.a = world.targets[i].id,
                            .b = world.targets[j].id,
                            .first_frame = frame,
                            .last_frame = frame});
      }
      TargetOverlap& o = overlaps[it->second];
      ++o.frames;
      if (o.last_frame >= frame - 1) o.last_frame = frame;  // still the first stretch
      o.deepest_m = std::max(o.deepest_m, depth);
    }
  }
  return overlaps;
}

std::string TargetOverlapNote(const Scenario& scenario) {
  const std::vector<TargetOverlap> overlaps = TargetOverlaps(scenario.world);
  if (overlaps.empty()) return "";
  const TargetOverlap& o = overlaps.front();
  const std::string stretch = o.frames == o.last_frame - o.first_frame + 1
                                  ? fmt::format("at frames {}-{}", o.first_frame, o.last_frame)
                                  : fmt::format("first at frames {}-{} ({} frames in all)",
                                                o.first_frame, o.last_frame, o.frames);
  return fmt::format(
      "targets {} and {} drive through each other {}: their footprints (length x width about the "
      "base, from dimensions_m or the model's bounds) overlap, by up to {:.1f} m (how far one "
      "must move to clear the other), so the frames show one vehicle inside the other{}. Give "
      "one a later path.start_frame, another speed or another path",
      Value(o.a), Value(o.b), stretch, o.deepest_m,
      overlaps.size() == 1 ? std::string()
                           : fmt::format("; {} pairs of targets overlap", overlaps.size()));
}

std::vector<std::string> SceneNotes(const Scenario& scenario) {
  std::vector<std::string> notes;
  for (std::string note : {CameraTurnNote(scenario), TargetOverlapNote(scenario)}) {
    if (!note.empty()) notes.push_back(std::move(note));
  }
  return notes;
}

}  // namespace hcpf::scenarios
