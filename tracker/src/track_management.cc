#include "hcpf/tracker/track_management.h"

#include <algorithm>
#include <limits>

#include "hcpf/tracker/hungarian.h"
#include "hcpf/tracker/tracker.h"

namespace hcpf::tracker {

struct MofNInitiator::Tentative {
  struct Hit {
    int frame = 0;
    // The detection's centre, carried through every camera motion since, so
    // in the current frame's coordinates.
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  };
  BoxPx box;              // the last hit's detection box
  int detection = -1;     // the last hit's index into its frame's detections
  std::vector<Hit> hits;  // hits within the last confirm_window frames, oldest first
};

MofNInitiator::MofNInitiator(const TrackManagementOptions& options)
    : confirm_hits_(options.confirm_hits),
      confirm_window_(options.confirm_window),
      gate_px_(options.tentative_gate_px) {}

MofNInitiator::~MofNInitiator() = default;

std::vector<Birth> MofNInitiator::Step(const Observation& observation,
                                       std::span<const size_t> free_detections,
                                       const std::optional<SimilarityMotion>& camera_motion) {
  // The tentatives' centres are in the previous frame's coordinates: the
  // camera's motion moves them into this frame's, as it moves the filters'
  // particles, so the gate and the birth velocity see the targets' own motion.
  if (camera_motion) {
    for (Tentative& t : tentatives_) {
      for (Tentative::Hit& hit : t.hits) hit.centre = hcpf::Apply(*camera_motion, hit.centre);
    }
  }
  // Match free detections to tentatives by centre distance (optimal, gated).
  const double gate2 = gate_px_ * gate_px_;
  const int rows = static_cast<int>(tentatives_.size());
  const int cols = static_cast<int>(free_detections.size());
  std::vector<double> cost(static_cast<size_t>(rows) * cols,
                           std::numeric_limits<double>::infinity());
  for (int r = 0; r < rows; ++r) {
    const Eigen::Vector2d& last = tentatives_[r].hits.back().centre;
    for (int c = 0; c < cols; ++c) {
      const BoxPx& b = observation.detections[free_detections[c]].box;
      const double dx = b.centre_x() - last.x();
      const double dy = b.centre_y() - last.y();
      const double d2 = dx * dx + dy * dy;
      if (d2 <= gate2) cost[static_cast<size_t>(r) * cols + c] = d2;
    }
  }
  const std::vector<int> match = SolveAssignment(cost, rows, cols);
  const auto hit_at = [&](Tentative& t, int c) {
    const size_t d = free_detections[static_cast<size_t>(c)];
    t.box = observation.detections[d].box;
    t.detection = static_cast<int>(d);
    t.hits.push_back({observation.frame, {t.box.centre_x(), t.box.centre_y()}});
  };
  std::vector<char> used(static_cast<size_t>(cols), 0);
  for (int r = 0; r < rows; ++r) {
    if (match[r] < 0) continue;
    hit_at(tentatives_[r], match[r]);
    used[match[r]] = 1;
  }
  for (int c = 0; c < cols; ++c) {
    if (used[c]) continue;
    hit_at(tentatives_.emplace_back(), c);
  }
  // Confirm (M hits among the last N frames), keep, or drop (the last hit is
  // more than N - M frames old, so no window that holds any of its hits can
  // hold M: see the class comment).
  std::vector<Birth> births;
  std::vector<Tentative> remaining;
  const int window_start = observation.frame - confirm_window_ + 1;
  for (Tentative& t : tentatives_) {
    std::erase_if(t.hits, [&](const Tentative::Hit& h) { return h.frame < window_start; });
    // Never empty: a tentative matched or started this frame has a hit now,
    // and one kept from the last frame had its last hit at most N - M frames
    // before it, so at most N - M + 1 <= N - 1 frames before this one (M >= 2
    // whenever one is kept: with M = 1 every tentative confirms at once).
    const Tentative::Hit& first = t.hits.front();
    const Tentative::Hit& last = t.hits.back();
    if (static_cast<int>(t.hits.size()) >= confirm_hits_) {
      // Hits only arrive in their own frame, so a tentative reaches M hits in
      // a frame in which it has one: `last` is this frame's detection.
      Birth birth;
      birth.box = t.box;
      birth.detection = t.detection;
      if (last.frame > first.frame) {
        birth.velocity_px =
            (last.centre - first.centre) / static_cast<double>(last.frame - first.frame);
      }
      births.push_back(birth);
    } else if (observation.frame - last.frame <= confirm_window_ - confirm_hits_) {
      remaining.push_back(std::move(t));
    }
  }
  tentatives_ = std::move(remaining);
  return births;
}

}  // namespace hcpf::tracker
