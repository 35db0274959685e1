#pragma once
// The multi-target tracker: a bank of per-target particle filters assembled
// from injected components (dynamics, likelihood, interaction, resampler,
// associator) plus track management (birth, M-of-N confirmation, coasting,
// deletion). Library API: Options in, per-frame reports out; no YAML, no files,
// no ground truth (the run pipeline calls BirthTrack when a scenario asks for
// `init: ground_truth`).

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <span>
#include <string_view>
#include <vector>

#include "hcpf/core/enum_names.h"
#include "hcpf/core/fields.h"
#include "hcpf/core/rng.h"
#include "hcpf/core/types.h"
#include "hcpf/tracker/associator.h"
#include "hcpf/tracker/dynamics.h"
#include "hcpf/tracker/interaction.h"
#include "hcpf/tracker/likelihood.h"
#include "hcpf/tracker/particle_set.h"
#include "hcpf/tracker/resampler.h"
#include "hcpf/tracker/scene_motion.h"
#include "hcpf/tracker/track_management.h"

namespace hcpf::tracker {

enum class InitMode {
  kGroundTruth,  // "ground_truth": the pipeline calls BirthTrack(id, box)
  kDetections,   // "detections": M-of-N confirmation from unassigned detections
};

// init = ground_truth: the mean velocity of a newborn filter's particles.
enum class BirthVelocity {
  kZero,         // "zero": at rest (the spread birth_sigma_vel_px about it)
  kGroundTruth,  // "ground_truth": the target's image motion out of its birth frame
};

// init = ground_truth with target-specific detections: whether a filter that
// has lost its target is found again from that target's own detections.
enum class ReacquireMode {
  kNone,           // "none": a lost filter coasts and is deleted; it never returns
  kOwnDetections,  // "own_detections": M-of-N on the target's unclaimed detections
};
}  // namespace hcpf::tracker

template <>
struct hcpf::EnumNames<hcpf::tracker::ReacquireMode> {
  static constexpr std::array kNames = {
      std::pair{hcpf::tracker::ReacquireMode::kNone, std::string_view("none")},
      std::pair{hcpf::tracker::ReacquireMode::kOwnDetections, std::string_view("own_detections")}};
};

template <>
struct hcpf::EnumNames<hcpf::tracker::BirthVelocity> {
  static constexpr std::array kNames = {
      std::pair{hcpf::tracker::BirthVelocity::kZero, std::string_view("zero")},
      std::pair{hcpf::tracker::BirthVelocity::kGroundTruth, std::string_view("ground_truth")}};
};

template <>
struct hcpf::EnumNames<hcpf::tracker::InitMode> {
  static constexpr std::array kNames = {
      std::pair{hcpf::tracker::InitMode::kGroundTruth, std::string_view("ground_truth")},
      std::pair{hcpf::tracker::InitMode::kDetections, std::string_view("detections")}};
};

namespace hcpf::tracker {

struct TrackManagementOptions {
  // init = detections: a tentative track is confirmed (a filter is born) once
  // it has confirm_hits detections in its last confirm_window frames (M of N),
  // 1 <= M <= N <= 1000.
  int confirm_hits = 3;
  int confirm_window = 5;
  // init = detections: an unassigned detection continues a tentative track
  // when its centre is within this distance of the tentative's last centre, px.
  double tentative_gate_px = 20.0;
  // Delete a filter after this many consecutive frames without support
  // (no assigned/gated evidence). 0 = never delete.
  int max_missed_frames = 30;
  // Occlusion coasting: while a filter has no support it only predicts (no
  // likelihood, no interaction, no resampling). When false the likelihood is
  // applied anyway (the detections_mixture then pulls it to whatever is near).
  bool coast_without_support = true;
  // Spread of a newborn filter's particles about the birth box: centre (px),
  // velocity (px/frame) and log-scale (dimensionless) standard deviations.
  double birth_sigma_px = 2.0;
  double birth_sigma_vel_px = 0.5;
  double birth_sigma_log_scale = 0.05;
  // init = ground_truth: the velocity the pipeline passes to BirthTrack. zero:
  // none (a target moving several px/frame then outruns a filter with low
  // process noise before its velocity catches up); ground_truth: the
  // target's image displacement from its birth frame to the next (the run
  // pipeline computes it from the ground truth; docs/tracker.md).
  BirthVelocity birth_velocity = BirthVelocity::kZero;
  // init = ground_truth, target-specific detections (a model-based detector
  // labels each detection with its model's target): own_detections lets the
  // detections of a target whose filter is unsupported or deleted, and that
  // no filter was given, feed an M-of-N tentative per target (confirm_hits of
  // confirm_window, continued within tentative_gate_px); when it confirms, the
  // filter is re-seeded there (or, deleted, born again with its old id).
  ReacquireMode reacquire = ReacquireMode::kNone;

  // The scenario keys of these options, with unit, range and doc (core/fields.h);
  // Validate() checks their ranges, then the rules between fields.
  static std::span<const Field<TrackManagementOptions>> Fields();
  void Validate(std::string_view prefix = "tracker.management") const;
};

struct TrackerOptions {
  // Particles per filter.
  int particles = 500;
  InitMode init = InitMode::kGroundTruth;
  DynamicsOptions dynamics;
  LikelihoodOptions likelihood;
  ResamplerOptions resampling;
  InteractionOptions interaction;
  AssociationOptions association;
  TrackManagementOptions management;
  // The hierarchical filter: how the camera's frame-to-frame motion moves
  // every target particle before its own dynamics (`camera_motion`), and the
  // scene filter that estimates it (`scene_filter.*`). The run pipeline
  // (scenarios/) builds the evidence and calls Step(observation, motion).
  CameraMotionMode camera_motion = CameraMotionMode::kNone;
  SceneMotionOptions scene_filter;
  // Particle clouds kept per filter per frame in the report, decimated to at
  // most this many particles (0 = none).
  int keep_particles = 0;
  // Worker threads for the per-filter stages (1 = the calling thread only).
  // Results are identical for every value: each filter draws from its own
  // stream "tracker/filter/<id>" and all filters see the same summaries.
  int threads = 1;

  // The top-level `tracker.*` keys (the nested Options declare their own).
  static std::span<const Field<TrackerOptions>> Fields();
  // Validates every nested Options and the combinations; throws InputError
  // naming the dotted key ("tracker.resampling.beta").
  void Validate() const;
};

// One particle of a decimated cloud.
struct ParticlePoint {
  float x_px = 0.0F;
  float y_px = 0.0F;
  float weight = 0.0F;  // normalised posterior weight before resampling
  friend bool operator==(const ParticlePoint&, const ParticlePoint&) = default;
};

// One filter in one frame (posterior, before resampling).
struct FilterReport {
  TrackId id{};
  BoxPx box;                                       // weighted-mean centre, base size * mean scale
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();  // px
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();   // px^2
  double ess = 0.0;                                // effective sample size, [1, N]
  int64_t rejections = 0;                          // charged resampling rejections
  int64_t potential_terms = 0;                     // charged: ResampleResult::potential_terms
  bool recovered_degenerate = false;               // all weights vanished; reset (docs)
  bool coasting = false;                           // predicted only this frame
  bool resampled = false;
  int assigned_detection = -1;           // index into Observation::detections
  int missed_frames = 0;                 // consecutive frames without support
  std::vector<ParticlePoint> particles;  // decimated cloud (keep_particles)
};

struct FrameReport {
  int frame = 0;
  // Every filter that ran this frame, and every filter born or re-seeded at
  // its end (its estimate as seeded from this frame's detection), by TrackId.
  std::vector<FilterReport> filters;
  std::vector<TrackId> born;     // filters born at the end of this frame
  std::vector<TrackId> deleted;  // filters deleted at the end of this frame
  // Filters re-seeded (or, deleted earlier, born again) at the end of this
  // frame from their own target's detections (management.reacquire).
  std::vector<TrackId> reacquired;
  int64_t degenerate_filters = 0;  // filters whose weights were reset this frame
};

// Estimates for the MOT output: one per reported filter (confidence = ESS / N).
std::vector<TrackEstimate> ToTrackEstimates(const FrameReport& report, int particles);

// Components the tracker is assembled from (all shared, const, stateless).
struct TrackerComponents {
  std::unique_ptr<Dynamics> dynamics;
  std::unique_ptr<Likelihood> likelihood;
  std::unique_ptr<Interaction> interaction;
  std::unique_ptr<Resampler> resampler;
  std::unique_ptr<Associator> associator;
  std::unique_ptr<Initiator> initiator;  // owned by this tracker (it keeps tentatives)
  std::unique_ptr<Deleter> deleter;
};

class MultiTargetTracker {
 public:
  // `rng` is the tracker's root stream; filter k draws from
  // rng.Fork("tracker/filter/<k>").
  MultiTargetTracker(const TrackerOptions& options, TrackerComponents components, Rng rng);
  ~MultiTargetTracker();
  MultiTargetTracker(const MultiTargetTracker&) = delete;
  MultiTargetTracker& operator=(const MultiTargetTracker&) = delete;

  // Births a filter for `id` at `initial_box` (centre, size; velocity
  // `velocity_px` per frame). The filter joins the next Step without a predict
  // (its particles already describe that frame). HCPF_CHECKs that `id` is new
  // and the box is non-empty.
  void BirthTrack(TrackId id, const BoxPx& initial_box,
                  Eigen::Vector2d velocity_px = Eigen::Vector2d::Zero());

  // Processes one frame: (camera motion +) predict, associate, update, resample,
  // manage tracks. Returns the per-filter report.
  FrameReport Step(const Observation& observation,
                   const std::optional<SimilarityMotion>& camera_motion = std::nullopt);

  size_t num_filters() const;
  std::vector<TrackId> track_ids() const;
  // Read access to a filter's particles (tests, overlays); nullptr if unknown.
  const ParticleSet* particles(TrackId id) const;
  const TrackerOptions& options() const { return options_; }

 private:
  struct Filter;

  void Predict(const std::optional<SimilarityMotion>& camera_motion);
  std::vector<FilterSummary> Summaries() const;
  std::vector<TrackPrediction> Predictions(const std::vector<FilterSummary>& predicted) const;
  static std::vector<FilterSummary> PosteriorSummaries(const FrameReport& report);
  // What each filter sees of a frame and the detection it was given.
  struct FrameViews;
  FrameViews Associate(const Observation& observation,
                       const std::vector<TrackPrediction>& predictions) const;
  void Update(const FrameViews& views, const std::vector<FilterSummary>& predicted,
              FrameReport& report);
  void Resample(const std::vector<FilterSummary>& posterior, FrameReport& report);
  // `camera_motion`: this frame's, for the initiators' tentatives.
  void ManageTracks(const Observation& observation, const std::vector<int>& assignment,
                    const std::vector<TrackPrediction>& predictions,
                    const std::optional<SimilarityMotion>& camera_motion, FrameReport& report);
  // management.reacquire: feeds each lost target's best unclaimed detection
  // to its tentative and re-seeds (or re-births) the filters confirmed.
  // `assigned`: per detection, whether a filter was given it this frame.
  void Reacquire(const Observation& observation, const std::vector<char>& assigned,
                 const std::vector<TrackPrediction>& predictions,
                 const std::optional<SimilarityMotion>& camera_motion, FrameReport& report);
  // Makes f's row of `report` (added in id order, or the row of its id
  // replaced) its estimate as just seeded from this frame's detection
  // `detection`: a filter born or re-seeded at the end of a frame describes
  // that frame.
  void ReportSeeded(const Filter& f, int detection, FrameReport& report) const;
  // Draws f's particles about `box` (centre, size) with mean velocity
  // `velocity_px` and the birth spreads, from f's own stream; sets its base size.
  void Seed(Filter& f, const BoxPx& box, const Eigen::Vector2d& velocity_px) const;
  // A new filter `id` drawing from `rng`, seeded at `box`, in id order (it
  // joins the next Step without a predict until just_born is cleared).
  // HCPF_CHECKs that `id` is new and the box is non-empty.
  Filter& Bear(TrackId id, Rng rng, const BoxPx& box, const Eigen::Vector2d& velocity_px);
  template <typename Fn>
  void ForEachFilter(Fn&& fn);

  TrackerOptions options_;
  TrackerComponents components_;
  Rng rng_;
  std::vector<std::unique_ptr<Filter>> filters_;  // sorted by TrackId
  int32_t next_track_id_ = 1;
  // management.reacquire: every id ever born, the tentative of each target
  // whose filter is lost, and how often each id was born again (its stream).
  std::set<int32_t> ever_born_;
  std::map<int32_t, MofNInitiator> reacquiring_;
  std::map<int32_t, int> rebirths_;
};

// The initiator of `options.init`: MofNInitiator for detections, else NoInitiator.
std::unique_ptr<Initiator> MakeInitiator(const TrackerOptions& options);

// Validates the options, builds every component and the tracker.
std::unique_ptr<MultiTargetTracker> MakeTracker(const TrackerOptions& options, Rng rng);

}  // namespace hcpf::tracker
