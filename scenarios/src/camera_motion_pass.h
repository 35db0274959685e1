#pragma once
// Private: the hierarchical filter's scene half in the run pipeline. Each
// frame from the second on, it gives the tracker the camera's frame-to-frame
// motion (`tracker.camera_motion`): none, the scene filter's estimate from
// its evidence (`tracker.scene_filter.evidence`: simulated ground-point
// tracks, or the oracle homography), or the oracle's least-squares
// similarity of the true ground homography. It also scores every frame's
// motion (the one applied, identity for none) against the truth: the mean
// displacement of the four image corners (metrics/camera_motion.h).

#include <optional>
#include <span>
#include <vector>

#include "hcpf/core/ground_truth.h"
#include "hcpf/core/image.h"
#include "hcpf/core/rng.h"
#include "hcpf/core/similarity_motion.h"
#include "hcpf/metrics/camera_motion.h"
#include "hcpf/scenarios/scenario.h"
#include "hcpf/tracker/scene_motion.h"

namespace hcpf::scenarios::internal {

struct CameraMotionRecord {
  int frame = 0;
  SimilarityMotion motion;  // applied to the target particles (identity for none)
  double error_px = 0.0;    // corner displacement against the true motion
  double floor_px = 0.0;    // the same for the best similarity there is (CornerOptimalSimilarity)
  double ess = -1.0;        // scene filter ESS; -1 without a scene filter
};

// The least-squares 2-D similarity of a homography over a 10 x 10 grid of the
// width x height image (closed form: complex linear regression).
SimilarityMotion BestSimilarity(const Eigen::Matrix3d& h, int width, int height);

// tracker.management.birth_velocity: ground_truth. Target `id`'s image motion
// from `frame` to the next (from the frame before at the last frame, or when
// it is gone by the next); zero when neither pair of frames holds it. When
// tracker.camera_motion moves the particles, the tracker's model of the
// next centre is S(x) + sR v (tracker::ApplyCameraMotion, then the
// constant-velocity step), so the velocity is v = (sR)^-1 (x' - S(x)) with S
// the best similarity of the true frame-to-frame homography, as
// camera_motion: oracle applies it: born so, the filter's first prediction
// without noise lands on the truth's next centre.
Eigen::Vector2d GroundTruthBirthVelocity(const Scenario& scenario, int frame, ObjectId id);

class CameraMotionPass {
 public:
  explicit CameraMotionPass(const Scenario& scenario);
  // Whether Step needs each frame's rendered image (image evidence).
  bool needs_images() const { return needs_images_; }
  // The motion to apply before frame `current`'s prediction (nullopt on the
  // first frame and with camera_motion: none); `exclude` are the filters'
  // boxes of the previous frame (the feedback from targets to scene).
  // `image` is the rendered frame, required when needs_images().
  std::optional<SimilarityMotion> Step(const FrameGroundTruth& current,
                                       std::span<const BoxPx> exclude,
                                       const RgbImage* image = nullptr);
  const std::vector<CameraMotionRecord>& records() const { return records_; }
  // The per-frame errors summarised, and the per-frame floors alike.
  metrics::CameraMotionErrorSummary Summary() const {
    return Summarise(&CameraMotionRecord::error_px);
  }
  metrics::CameraMotionErrorSummary FloorSummary() const {
    return Summarise(&CameraMotionRecord::floor_px);
  }

 private:
  std::vector<PointTrack> SimulateTracks(const FrameGroundTruth& previous,
                                         const FrameGroundTruth& current) const;
  // The frame's point tracks from the configured evidence (simulated or image).
  std::vector<PointTrack> Tracks(const FrameGroundTruth& current, std::span<const BoxPx> exclude,
                                 const RgbImage* image) const;
  // One column of the records summarised.
  metrics::CameraMotionErrorSummary Summarise(double CameraMotionRecord::*column) const;
  // `tracks` without those starting inside the targets' dilated boxes (what
  // PointTrackEvidence ignores): the input of RANSAC, in the ransac mode and
  // the perspective stage.
  std::vector<PointTrack> Background(std::vector<PointTrack> tracks,
                                     std::span<const BoxPx> exclude) const;

  tracker::CameraMotionMode mode_;
  tracker::SceneMotionOptions options_;
  vision::PointTrackerOptions point_tracker_;
  vision::RansacOptions ransac_;
  bool perspective_ = false;  // UsesPerspective
  double perspective_inlier_px_ = 2.0;
  int width_;
  int height_;
  bool needs_images_ = false;
  std::optional<RgbImage> previous_image_;
  Rng points_rng_;
  std::optional<tracker::SceneMotionFilter> filter_;
  std::optional<FrameGroundTruth> previous_;
  std::vector<CameraMotionRecord> records_;
};

}  // namespace hcpf::scenarios::internal
