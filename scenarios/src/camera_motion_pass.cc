#include "camera_motion_pass.h"

#include <Eigen/LU>
#include <cmath>
#include <complex>

#include "hcpf/core/error.h"
#include "hcpf/vision/point_tracks.h"

namespace hcpf::scenarios::internal {
namespace {

using Complex = std::complex<double>;

// Where the image point `p` of the previous frame's ground plane lands in the
// current frame; nullopt when the ray misses the ground (behind the camera).
std::optional<Eigen::Vector2d> Transfer(const Eigen::Matrix3d& h, const Eigen::Vector2d& p) {
  const Eigen::Vector3d q = h * Eigen::Vector3d(p.x(), p.y(), 1.0);
  if (!(q.z() > 1e-12)) return std::nullopt;
  return Eigen::Vector2d(q.x() / q.z(), q.y() / q.z());
}

Eigen::Matrix3d FrameToFrame(const FrameGroundTruth& previous, const FrameGroundTruth& current) {
  return current.image_from_ground * previous.image_from_ground.inverse();
}

}  // namespace

SimilarityMotion BestSimilarity(const Eigen::Matrix3d& h, int width, int height) {
  constexpr int kGrid = 10;
  std::vector<Complex> p, q;
  for (int j = 0; j < kGrid; ++j) {
    for (int i = 0; i < kGrid; ++i) {
      const Eigen::Vector2d g((i + 0.5) * width / kGrid, (j + 0.5) * height / kGrid);
      if (const auto t = Transfer(h, g)) {
        p.emplace_back(g.x(), g.y());
        q.emplace_back(t->x(), t->y());
      }
    }
  }
  if (p.size() < 2) return {};
  return FitComplexSimilarity(p, q).motion();
}

Eigen::Vector2d GroundTruthBirthVelocity(const Scenario& scenario, int frame, ObjectId id) {
  const bool compensated = scenario.tracker.camera_motion != tracker::CameraMotionMode::kNone;
  const auto truth = [&](int f) { return ComputeGroundTruth(scenario.world, f); };
  if (frame >= 0 && frame + 1 < scenario.world.frames) {
    const FrameGroundTruth now = truth(frame), next = truth(frame + 1);
    if (const auto d = ImageVelocity(now, next, id, false)) {
      if (!compensated) return *d;
      // x(t+1) = S(x(t)) + sR v: v = (sR)^-1 (x(t+1) - S(x(t))), with S the
      // best similarity of the true homography (what camera_motion: oracle
      // applies).
      const SimilarityMotion m = BestSimilarity(
          FrameToFrame(now, next), scenario.world.camera.width_px, scenario.world.camera.height_px);
      // (sR)^-1 as a similarity of its own, without translation.
      const SimilarityMotion linear_inverse{.log_scale = -m.log_scale,
                                            .rotation_rad = -m.rotation_rad};
      for (const GroundTruthObject& o : now.objects) {
        if (o.id != id) continue;
        const Eigen::Vector2d before(o.amodal_box.centre_x(), o.amodal_box.centre_y());
        const Eigen::Vector2d v = Apply(linear_inverse, before + *d - Apply(m, before));
        if (v.allFinite()) return v;
      }
    }
  }
  if (frame >= 1 && frame < scenario.world.frames) {
    if (const auto v = ImageVelocity(truth(frame - 1), truth(frame), id, compensated)) return *v;
  }
  return Eigen::Vector2d::Zero();
}

CameraMotionPass::CameraMotionPass(const Scenario& scenario)
    : mode_(scenario.tracker.camera_motion),
      options_(scenario.tracker.scene_filter),
      point_tracker_(scenario.point_tracker),
      ransac_(scenario.ransac),
      perspective_(UsesPerspective(scenario)),
      perspective_inlier_px_(scenario.perspective.inlier_px),
      width_(scenario.world.camera.width_px),
      height_(scenario.world.camera.height_px),
      points_rng_(Rng(scenario.seeds.observation).Fork("scene_points")) {
  needs_images_ = UsesPointTracker(scenario);
  if (mode_ == tracker::CameraMotionMode::kSceneFilter) {
    filter_.emplace(options_, width_, height_, Rng(scenario.seeds.tracker).Fork("scene"));
  }
}

std::vector<PointTrack> CameraMotionPass::SimulateTracks(const FrameGroundTruth& previous,
                                                         const FrameGroundTruth& current) const {
  // Each frame draws from its own stream: a frame's points do not depend on
  // the frames before it.
  Rng rng = points_rng_.Fork("frame", current.frame);
  const Eigen::Matrix3d h = FrameToFrame(previous, current);
  std::vector<PointTrack> tracks;
  tracks.reserve(static_cast<size_t>(options_.points));
  for (int i = 0; i < options_.points; ++i) {
    const Eigen::Vector2d p(rng.Uniform(0.0, width_), rng.Uniform(0.0, height_));
    std::optional<Eigen::Vector2d> q = Transfer(h, p);
    // A point on a target moves with it: the feature tracker follows the
    // vehicle, not the ground below it.
    for (const GroundTruthObject& o : previous.objects) {
      const BoxPx& b = o.amodal_box;
      if (!o.in_frame || p.x() < b.left || p.x() > b.right() || p.y() < b.top ||
          p.y() > b.bottom()) {
        continue;
      }
      for (const GroundTruthObject& now : current.objects) {
        if (now.id != o.id) continue;
        q = p + Eigen::Vector2d(now.amodal_box.centre_x() - b.centre_x(),
                                now.amodal_box.centre_y() - b.centre_y());
      }
      break;
    }
    const double nx = rng.Normal() * options_.point_noise_px;
    const double ny = rng.Normal() * options_.point_noise_px;
    const bool outlier = rng.Uniform() < options_.outlier_fraction;
    const Eigen::Vector2d random(rng.Uniform(0.0, width_), rng.Uniform(0.0, height_));
    if (!q) continue;  // the ground point is behind the camera now: lost
    tracks.push_back({.p = p, .q = outlier ? random : *q + Eigen::Vector2d(nx, ny)});
  }
  return tracks;
}

std::vector<PointTrack> CameraMotionPass::Tracks(const FrameGroundTruth& current,
                                                 std::span<const BoxPx> exclude,
                                                 const RgbImage* image) const {
  if (!needs_images_) return SimulateTracks(*previous_, current);
  // The image tracker masks the targets itself (corners are not even found
  // on them); the evidence's mask then has nothing left to remove.
  return vision::TrackBackgroundPoints(*previous_image_, *image, exclude, options_.mask_dilation_px,
                                       point_tracker_);
}

std::vector<PointTrack> CameraMotionPass::Background(std::vector<PointTrack> tracks,
                                                     std::span<const BoxPx> exclude) const {
  std::erase_if(tracks, [&](const PointTrack& t) {
    return tracker::InsideDilatedBoxes(t.p, exclude, options_.mask_dilation_px);
  });
  return tracks;
}

std::optional<SimilarityMotion> CameraMotionPass::Step(const FrameGroundTruth& current,
                                                       std::span<const BoxPx> exclude,
                                                       const RgbImage* image) {
  if (needs_images_ && image == nullptr) {
    throw RunError("camera motion: image evidence needs the rendered frames");
  }
  if (!previous_) {
    previous_ = current;
    if (needs_images_) previous_image_ = *image;
    return std::nullopt;
  }
  const Eigen::Matrix3d truth = FrameToFrame(*previous_, current);
  CameraMotionRecord record{.frame = current.frame};
  switch (mode_) {
    case tracker::CameraMotionMode::kNone:
      break;
    case tracker::CameraMotionMode::kOracle:
      record.motion = BestSimilarity(truth, width_, height_);
      break;
    case tracker::CameraMotionMode::kSceneFilter:
      if (options_.evidence == tracker::SceneEvidenceKind::kOracle) {
        record.motion = filter_->Step(
            tracker::HomographyEvidence(truth, width_, height_, options_.sigma_px), exclude);
      } else {
        std::vector<PointTrack> tracks = Tracks(current, exclude, image);
        // The perspective stage (tracker.perspective): the homography's
        // perspective terms fitted to the RANSAC similarity's inliers, taken
        // out of the tracks, so the filter estimates the similarity that is
        // the homography's numerator; the applied motion is the similarity
        // closest to the whole homography at the corners.
        std::optional<Eigen::Vector2d> gh;
        const Eigen::Vector2d centre(0.5 * width_, 0.5 * height_);
        if (perspective_) {
          const std::vector<PointTrack> background = Background(tracks, exclude);
          if (const auto guide = vision::EstimateSimilarityRansac(background, ransac_)) {
            gh = vision::FitPerspective(background, *guide, perspective_inlier_px_, centre);
          }
          if (gh) tracks = vision::RemovePerspective(tracks, *gh, centre);
        }
        // RANSAC's similarity of the unmasked tracks: the scene filter's second
        // start where its particles sit in a weaker mode (docs/tracker.md).
        const auto ransac = [this](std::span<const PointTrack> t) {
          return vision::EstimateSimilarityRansac(t, ransac_);
        };
        record.motion = filter_->Step(
            tracker::PointTrackEvidence(std::move(tracks), options_, ransac), exclude);
        if (gh) {
          record.motion = metrics::CornerOptimalSimilarity(
              vision::PerspectiveHomography(record.motion, *gh, centre), width_, height_);
        }
      }
      record.ess = filter_->LastReport().ess;
      break;
    case tracker::CameraMotionMode::kRansac: {
      // The common recipe: RANSAC on the same tracks, targets masked as for
      // the scene filter; identity when too few tracks survive (the
      // documented fallback of a low-texture frame).
      record.motion = vision::EstimateSimilarityRansac(
                          Background(Tracks(current, exclude, image), exclude), ransac_)
                          .value_or(SimilarityMotion{});
      break;
    }
  }
  record.error_px = metrics::CornerDisplacementPx(record.motion, truth, width_, height_);
  record.floor_px = metrics::CornerDisplacementPx(
      metrics::CornerOptimalSimilarity(truth, width_, height_), truth, width_, height_);
  records_.push_back(record);
  previous_ = current;
  if (needs_images_) previous_image_ = *image;
  if (mode_ == tracker::CameraMotionMode::kNone) return std::nullopt;
  return record.motion;
}

metrics::CameraMotionErrorSummary CameraMotionPass::Summarise(
    double CameraMotionRecord::*column) const {
  std::vector<double> values;
  values.reserve(records_.size());
  for (const CameraMotionRecord& r : records_) values.push_back(r.*column);
  return metrics::SummariseCameraMotionError(values);
}

}  // namespace hcpf::scenarios::internal
