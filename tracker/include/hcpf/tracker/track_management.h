#pragma once
// Track management roles (Stone Soup's initiator and deleter): which filters
// begin and which end. The tracker asks its Initiator for new tracks from the
// detections no filter claims, and its Deleter whether a filter that has gone
// without support for some frames ends.

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "hcpf/core/similarity_motion.h"
#include "hcpf/core/types.h"

namespace hcpf::tracker {

struct TrackManagementOptions;

// A track to begin: its box (centre and size, px), its velocity (px/frame,
// scene-relative: the camera's motion taken out when the tracker applies it)
// and the index into observation.detections of the detection it was
// confirmed from (-1 if none).
struct Birth {
  BoxPx box;
  Eigen::Vector2d velocity_px = Eigen::Vector2d::Zero();
  int detection = -1;
};

// Turns detections that no filter claims into new tracks.
// Contract: Step is called once per frame, in frame order, with the indices
// (into observation.detections, increasing) of the detections no filter
// claims, and `camera_motion`, the camera's motion from the previous frame to
// this one that the tracker applied to its particles this frame (nullopt when
// it applies none); it returns the tracks confirmed this frame, in a
// deterministic order. Unlike the tracker's other components an initiator keeps state
// between frames (its tentative tracks), so one instance serves one tracker
// and is not shared between threads. Deterministic; no randomness.
class Initiator {
 public:
  virtual ~Initiator() = default;
  virtual std::vector<Birth> Step(const Observation& observation,
                                  std::span<const size_t> free_detections,
                                  const std::optional<SimilarityMotion>& camera_motion) = 0;
  virtual std::string_view name() const = 0;
};

// init: ground_truth. Births come from outside the tracker (the run pipeline
// calls MultiTargetTracker::BirthTrack at each target's first appearance);
// this initiator never proposes one.
class NoInitiator final : public Initiator {
 public:
  std::vector<Birth> Step(const Observation&, std::span<const size_t>,
                          const std::optional<SimilarityMotion>&) override {
    return {};
  }
  std::string_view name() const override { return "ground_truth"; }
};

// init: detections. M-of-N confirmation (M = confirm_hits, N =
// confirm_window): a free detection continues the nearest tentative track
// within tentative_gate_px of its last centre (an optimal one-to-one matching
// by squared centre distance) or starts a new one. A tentative track with M
// hits among the last N frames (this one included) is confirmed, with the
// velocity from the first to the last of those hits. One whose last hit is
// more than N - M frames old is dropped: every later window that still holds
// that hit ends by frame last + N - 1 and so holds at most N - (frames since
// the last hit) hits, fewer than M, and later windows hold none of its hits
// (a new tentative does as well). Every centre it keeps is carried through
// each frame's camera motion, so the gate compares positions in the current
// frame and the velocity is the target's own, not the camera's. O(T·(D + N))
// per frame for T tentatives and D free detections (plus the matching).
class MofNInitiator final : public Initiator {
 public:
  explicit MofNInitiator(const TrackManagementOptions& options);
  ~MofNInitiator() override;
  std::vector<Birth> Step(const Observation& observation, std::span<const size_t> free_detections,
                          const std::optional<SimilarityMotion>& camera_motion) override;
  std::string_view name() const override { return "detections"; }

 private:
  struct Tentative;
  int confirm_hits_;
  int confirm_window_;
  double gate_px_;
  std::vector<Tentative> tentatives_;
};

// Decides whether a filter ends. Const and stateless.
class Deleter {
 public:
  virtual ~Deleter() = default;
  // `missed_frames`: consecutive frames, this one included, without support.
  virtual bool Delete(int missed_frames) const = 0;
  virtual std::string_view name() const = 0;
};

// Ends a filter after max_missed_frames consecutive frames without support;
// max_missed_frames = 0 never ends one.
class MissedFramesDeleter final : public Deleter {
 public:
  explicit MissedFramesDeleter(int max_missed_frames) : max_missed_frames_(max_missed_frames) {}
  bool Delete(int missed_frames) const override {
    return max_missed_frames_ > 0 && missed_frames >= max_missed_frames_;
  }
  std::string_view name() const override { return "missed_frames"; }

 private:
  int max_missed_frames_;
};

}  // namespace hcpf::tracker
