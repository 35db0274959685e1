#include "hcpf/tracker/track_management.h"

#include <algorithm>
#include <limits>

#include "hcpf/tracker/hungarian.h"
#include "hcpf/tracker/tracker.h"

namespace hcpf::tracker {

struct MofNInitiator::Tentative {
  BoxPx box;
  std::vector<int> hit_frames;  // frames with a detection, oldest first
  Eigen::Vector2d first_centre = Eigen::Vector2d::Zero();
  int first_frame = 0;
  int last_frame = 0;
};

MofNInitiator::MofNInitiator(const TrackManagementOptions& options)
    : confirm_hits_(options.confirm_hits),
      confirm_window_(options.confirm_window),
      gate_px_(options.tentative_gate_px) {}

MofNInitiator::~MofNInitiator() = default;

std::vector<Birth> MofNInitiator::Step(const Observation& observation,
                                       std::span<const size_t> free_detections) {
  // Match free detections to tentatives by centre distance (optimal, gated).
  const double gate2 = gate_px_ * gate_px_;
  const int rows = static_cast<int>(tentatives_.size());
  const int cols = static_cast<int>(free_detections.size());
  std::vector<double> cost(static_cast<size_t>(rows) * cols,
                           std::numeric_limits<double>::infinity());
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      const BoxPx& b = observation.detections[free_detections[c]].box;
      const double dx = b.centre_x() - tentatives_[r].box.centre_x();
      const double dy = b.centre_y() - tentatives_[r].box.centre_y();
      const double d2 = dx * dx + dy * dy;
      if (d2 <= gate2) cost[static_cast<size_t>(r) * cols + c] = d2;
    }
  }
  const std::vector<int> match = SolveAssignment(cost, rows, cols);
  std::vector<char> used(static_cast<size_t>(cols), 0);
  for (int r = 0; r < rows; ++r) {
    if (match[r] < 0) continue;
    Tentative& t = tentatives_[r];
    t.box = observation.detections[free_detections[match[r]]].box;
    t.hit_frames.push_back(observation.frame);
    t.last_frame = observation.frame;
    used[match[r]] = 1;
  }
  for (int c = 0; c < cols; ++c) {
    if (used[c]) continue;
    Tentative t;
    t.box = observation.detections[free_detections[c]].box;
    t.hit_frames = {observation.frame};
    t.first_centre = {t.box.centre_x(), t.box.centre_y()};
    t.first_frame = t.last_frame = observation.frame;
    tentatives_.push_back(t);
  }
  // Confirm (M hits in the window) or drop (M hits no longer reachable:
  // misses in the window exceed N - M, counting frames since creation).
  std::vector<Birth> births;
  std::vector<Tentative> remaining;
  for (Tentative& t : tentatives_) {
    // Hits within the last confirm_window frames (this one included).
    const int window_start = observation.frame - confirm_window_ + 1;
    std::erase_if(t.hit_frames, [&](int f) { return f < window_start; });
    const int hits = static_cast<int>(t.hit_frames.size());
    const int age = observation.frame - t.first_frame + 1;
    const int window_frames = std::min(age, confirm_window_);
    const int misses = window_frames - hits;
    if (hits >= confirm_hits_) {
      Birth birth;
      birth.box = t.box;
      if (t.last_frame > t.first_frame) {
        birth.velocity_px = (Eigen::Vector2d(t.box.centre_x(), t.box.centre_y()) - t.first_centre) /
                            static_cast<double>(t.last_frame - t.first_frame);
      }
      births.push_back(birth);
    } else if (misses <= confirm_window_ - confirm_hits_) {
      remaining.push_back(t);
    }
  }
  tentatives_ = std::move(remaining);
  return births;
}

}  // namespace hcpf::tracker
