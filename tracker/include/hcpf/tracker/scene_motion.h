#pragma once
// The scene level of the hierarchical filter (DESIGN.md, "Hierarchical
// filter"; thesis ch. 11): a particle filter over the frame-to-frame camera
// motion, a 2-D image similarity (tx, ty, log_scale, rotation), weighted by
// camera-motion evidence from which the current target boxes are masked out.
// Target filters then apply its estimate to their particles
// (ApplyCameraMotion, MultiTargetTracker::Step(observation, camera_motion)).
// docs/tracker.md, "Hierarchical filter: the scene-motion filter (core)",
// gives the model, dynamics and evidence formulas.

#include <Eigen/Core>
#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "hcpf/core/enum_names.h"
#include "hcpf/core/fields.h"
#include "hcpf/core/rng.h"
#include "hcpf/core/similarity_motion.h"
#include "hcpf/core/types.h"
#include "hcpf/tracker/particle_set.h"
#include "hcpf/tracker/resampler.h"

namespace hcpf::tracker {

// Evidence about the frame-to-frame camera motion, implemented outside the
// scene filter (from image feature tracks in vision/, from simulated point
// tracks, or the ground-truth oracle below).
// Contract:
// - Adds to log_w[i] the log-likelihood (up to one constant shared by every
//   hypothesis) of the evidence under hypotheses[i], a motion mapping frame
//   t-1 pixel coordinates to frame t pixel coordinates.
// - `exclude` are the current target boxes (frame t-1 estimates): targets
//   must not explain the scene, so evidence lying on them is ignored
//   (feedback from targets to scene). An implementation that cannot be
//   biased by targets (the oracle) may ignore them.
// - Precondition: log_w.size() == hypotheses.size().
// - Const and deterministic: no randomness, no hidden state.
class CameraMotionEvidence {
 public:
  virtual ~CameraMotionEvidence() = default;
  virtual void AddLogLikelihood(std::span<const SimilarityMotion> hypotheses,
                                std::span<const BoxPx> exclude, std::span<double> log_w) const = 0;
  // A robust estimate of the motion from the evidence alone (e.g. the
  // similarity most of its point tracks agree on), or none: a second start
  // for the scene filter's search of the evidence's mode (SceneMotionFilter).
  // Const and deterministic, as AddLogLikelihood. Default: none.
  virtual std::optional<SimilarityMotion> RobustStart(std::span<const BoxPx> /*exclude*/) const {
    return std::nullopt;
  }
};

// How the scene filter draws its particles each frame (SceneMotionFilter):
enum class SceneProposal {
  kLaplace,   // "laplace": the dynamics times a Gaussian fitted at the evidence's mode
  kDynamics,  // "dynamics": the dynamics alone (the bootstrap filter)
};

enum class PointLoss {
  kStudentT,  // "student_t": robust, heavy-tailed (the default)
  kGaussian,  // "gaussian": least squares; for comparison only (outliers vote)
};

// The evidence a run gives the scene filter (scenarios/ builds it):
enum class SceneEvidenceKind {
  kSimulated,  // "simulated": ground points through the true cameras, with noise and outliers
  kOracle,     // "oracle": the true frame-to-frame ground homography (HomographyEvidence)
  kImage,      // "image": corners of the rendered frame t-1 tracked into t (vision/point_tracks.h)
};

// How a run moves the target particles with the camera (scenarios/):
enum class CameraMotionMode {
  kNone,         // "none": no compensation (the non-hierarchical baseline)
  kSceneFilter,  // "scene_filter": the SceneMotionFilter's estimate (the hierarchical filter)
  kOracle,       // "oracle": the least-squares similarity of the true ground homography
  kRansac,       // "ransac": RANSAC similarity on the evidence's point tracks (the common recipe)
};
}  // namespace hcpf::tracker

template <>
struct hcpf::EnumNames<hcpf::tracker::SceneEvidenceKind> {
  static constexpr std::array kNames = {
      std::pair{hcpf::tracker::SceneEvidenceKind::kSimulated, std::string_view("simulated")},
      std::pair{hcpf::tracker::SceneEvidenceKind::kOracle, std::string_view("oracle")},
      std::pair{hcpf::tracker::SceneEvidenceKind::kImage, std::string_view("image")}};
};

template <>
struct hcpf::EnumNames<hcpf::tracker::CameraMotionMode> {
  static constexpr std::array kNames = {
      std::pair{hcpf::tracker::CameraMotionMode::kNone, std::string_view("none")},
      std::pair{hcpf::tracker::CameraMotionMode::kSceneFilter, std::string_view("scene_filter")},
      std::pair{hcpf::tracker::CameraMotionMode::kOracle, std::string_view("oracle")},
      std::pair{hcpf::tracker::CameraMotionMode::kRansac, std::string_view("ransac")}};
};

template <>
struct hcpf::EnumNames<hcpf::tracker::SceneProposal> {
  static constexpr std::array kNames = {
      std::pair{hcpf::tracker::SceneProposal::kLaplace, std::string_view("laplace")},
      std::pair{hcpf::tracker::SceneProposal::kDynamics, std::string_view("dynamics")}};
};

template <>
struct hcpf::EnumNames<hcpf::tracker::PointLoss> {
  static constexpr std::array kNames = {
      std::pair{hcpf::tracker::PointLoss::kStudentT, std::string_view("student_t")},
      std::pair{hcpf::tracker::PointLoss::kGaussian, std::string_view("gaussian")}};
};

namespace hcpf::tracker {

struct SceneMotionOptions {
  // Number of scene particles.
  int particles = 1000;

  // Prior of the first frame: independent normals centred on the identity
  // motion with these standard deviations (the translation is that of the
  // image centre; see SceneMotionFilter).
  double prior_translation_px = 8.0;
  double prior_log_scale = 0.01;
  double prior_rotation_rad = 0.01;

  // Random-walk dynamics of the frame-to-frame motion (per frame standard
  // deviations; see SceneMotionFilter).
  double sigma_translation_px = 0.5;
  double sigma_log_scale = 0.001;
  double sigma_rotation_rad = 0.001;

  // Proposal: laplace (default) or dynamics; with laplace, the fraction of
  // particles still drawn from the dynamics alone (a defensive mixture: a
  // mode fitted in the wrong place cannot capture every particle).
  SceneProposal proposal = SceneProposal::kLaplace;
  double dynamics_fraction = 0.1;

  // Resampling: any method of the family except charged (there is one scene
  // filter, nothing to repel); ESS gate as in ResamplerOptions.
  ResamplingMethod resampling = ResamplingMethod::kSystematic;
  double ess_threshold = 0.5;

  // Evidence (PointTrackEvidence; HomographyEvidence uses sigma_px only).
  // Residual scale sigma, px.
  double sigma_px = 1.0;
  PointLoss loss = PointLoss::kStudentT;
  // Degrees of freedom nu of the Student-t loss.
  double student_t_dof = 3.0;
  // Each exclude box is grown by this much on every side before masking, px.
  double mask_dilation_px = 4.0;

  // What the run pipeline feeds the filter (scenarios/): the evidence kind,
  // and for simulated evidence the number of ground points per frame, their
  // pixel noise (std. dev.) and the fraction replaced by random mis-tracks.
  // Points that fall on a target move with it (unless masked).
  SceneEvidenceKind evidence = SceneEvidenceKind::kSimulated;
  int points = 200;
  double point_noise_px = 0.3;
  double outlier_fraction = 0.1;

  // The scenario keys of these options, with unit, range and doc (core/fields.h);
  // Validate() checks their ranges, then the rules between fields.
  static std::span<const Field<SceneMotionOptions>> Fields();
  void Validate(std::string_view prefix = "tracker.scene_filter") const;
};

// Whether `p` lies inside (boundary included) any of the boxes grown by
// `dilation_px` on every side: the target mask of point-track evidence.
bool InsideDilatedBoxes(const Eigen::Vector2d& p, std::span<const BoxPx> boxes, double dilation_px);

// Evidence from point correspondences between consecutive frames.
// A track is ignored when its p lies inside (boundary included) any exclude
// box grown by mask_dilation_px on every side. For every other track, with
// residual r = |S(p) - q| (px) and sigma = sigma_px, the log-likelihood of
// hypothesis S is the sum over tracks of
//   student_t: -((nu + 2) / 2) * log(1 + r^2 / (nu sigma^2))
//              (the 2-D Student-t density with nu = student_t_dof, constants
//              dropped: a track far from S contributes a term that barely
//              changes with S, so moving vehicles and mis-tracks are
//              outliers, not votes);
//   gaussian:  -r^2 / (2 sigma^2).
// O(H M + M B) for H hypotheses, M tracks, B boxes.
class PointTrackEvidence final : public CameraMotionEvidence {
 public:
  // Reads sigma_px, loss, student_t_dof and mask_dilation_px; validates `options`.
  // A robust similarity of point tracks (e.g. RANSAC's), finite, or none
  // (vision::EstimateSimilarityRansac returns none for a fit of scale 0):
  // the source of RobustStart. Deterministic and const, as the evidence.
  using RobustFit = std::function<std::optional<SimilarityMotion>(std::span<const PointTrack>)>;
  PointTrackEvidence(std::vector<PointTrack> tracks, const SceneMotionOptions& options,
                     RobustFit robust_fit = {});
  void AddLogLikelihood(std::span<const SimilarityMotion> hypotheses,
                        std::span<const BoxPx> exclude, std::span<double> log_w) const override;
  // robust_fit (set by the pipeline: vision::EstimateSimilarityRansac, OpenCV's
  // RANSAC) applied to the tracks not excluded; none without one.
  std::optional<SimilarityMotion> RobustStart(std::span<const BoxPx> exclude) const override;

  // Whether `track` is ignored given `exclude` (exposed for tests and overlays).
  bool Excluded(const PointTrack& track, std::span<const BoxPx> exclude) const;

 private:
  std::vector<PointTrack> tracks_;
  SceneMotionOptions options_;
  RobustFit robust_fit_;
};

// ORACLE evidence from the true frame-to-frame image homography H (frame t-1
// pixels to frame t pixels); reads ground truth, so results using it must be
// labelled oracle. Over the fixed grid of G x G = 10 x 10 points
//   g_ij = ((i + 1/2) width / G, (j + 1/2) height / G),  i, j = 0 .. G-1,
// the log-likelihood of S is
//   -(1 / G^2) sum_ij |S(g_ij) - H(g_ij)|^2 / (2 sigma^2)
// where H(g) is the projective image (H (g, 1))_xy / (H (g, 1))_z. `exclude`
// is ignored: the truth cannot be biased by targets. O(H G^2).
class HomographyEvidence final : public CameraMotionEvidence {
 public:
  static constexpr int kGrid = 10;
  // Throws InputError when width or height < 1, sigma_px <= 0, or H maps a grid
  // point to infinity (or behind the camera: non-positive homogeneous z).
  HomographyEvidence(const Eigen::Matrix3d& frame_from_previous, int width, int height,
                     double sigma_px);
  void AddLogLikelihood(std::span<const SimilarityMotion> hypotheses,
                        std::span<const BoxPx> exclude, std::span<double> log_w) const override;

 private:
  std::vector<Eigen::Vector2d> grid_;    // g_ij
  std::vector<Eigen::Vector2d> target_;  // H(g_ij)
  double sigma_px_;
};

// Per-frame diagnostics of the scene filter.
struct SceneMotionReport {
  // The estimate returned by Step.
  SimilarityMotion estimate;
  // Kish ESS of the weights after this frame's evidence, in [1, N].
  double ess = 0.0;
  // Weighted standard deviations of the particles after this frame's evidence
  // (before resampling), in the filter's parameters (SceneMotionFilter): the
  // translation of the image centre, the log-scale and the rotation.
  double sd_tx_px = 0.0;
  double sd_ty_px = 0.0;
  double sd_log_scale = 0.0;
  double sd_rotation_rad = 0.0;
  // Whether the particles were resampled this frame (ESS gate).
  bool resampled = false;
  // Every weight was -inf/NaN: weights were reset to uniform (particle_set.h).
  bool recovered_degenerate = false;
  // laplace proposal: whether the evidence had a usable mode this frame
  // (negative-definite curvature there); false means every particle was drawn
  // from the dynamics (no tracks, flat or degenerate evidence: the fallback).
  bool laplace = false;
  // Newton iterations spent finding the mode (0 without one).
  int newton_iterations = 0;
  // laplace proposal: the mode came from the evidence's robust start, which
  // explained the evidence better than the mode found from the particles'
  // mean (that start had settled on a weaker mode).
  bool robust_start = false;
  friend bool operator==(const SceneMotionReport&, const SceneMotionReport&) = default;
};

// Particle filter over the frame-to-frame camera motion of a width x height
// image.
//
// Parameters. A motion is held as u = (cx, cy, L log_scale, L rotation): the
// displacement (cx, cy) of the image centre c = (width/2, height/2), and the
// log-scale and rotation about c times the half diagonal L (so that every
// component is in pixels, the displacement it causes at the image corners).
// The SimilarityMotion about the origin is t = c + (cx, cy) - s R c.
//
// Step, for frame t:
//   1. dynamics: at the first Step the prior N(0, P0), P0 = diag(prior_*^2)
//      (log-scale and rotation rows times L^2); afterwards a random walk
//      N(u_i, Q), Q = diag(sigma_*^2) likewise. The state is the
//      frame-to-frame motion, i.e. the camera's image-plane velocity, so a
//      random walk on it is a constant-velocity model of the camera.
//   2. proposal (`proposal`):
//      - dynamics: u'_i ~ N(u_i, Q); log w_i += log p(y | u'_i).
//      - laplace (the locally linearised optimal proposal of Doucet, Godsill
//        and Andrieu 2000): find the mode m of the evidence's
//        log-likelihood l(u) = log p(y | u) by damped Newton from the
//        particles' mean, with gradient and Hessian by central differences
//        of l (step 0.05 sigma_px; the evidence is used only through
//        AddLogLikelihood, so any CameraMotionEvidence works). Where -H is
//        positive definite, l ~ N(m, (-H)^-1) and the Gaussian product with
//        the dynamics gives
//          S = (Q^-1 - H)^-1,  mu_i = S (Q^-1 u_i - H m);
//        each particle is drawn from the mixture
//          q_i = a N(u_i, Q) + (1 - a) N(mu_i, S),  a = dynamics_fraction,
//        and weighted by the exact ratio
//          log w_i += l(u'_i) + log N(u'_i; u_i, Q) - log q_i(u'_i),
//        so the filter's target is the same as the bootstrap filter's; only
//        the variance of the weights changes. When the evidence has a robust
//        start (CameraMotionEvidence::RobustStart: in a run, RANSAC's
//        similarity of the unmasked tracks) outside the mode found, more than 8 nats below it
//        by the mode's own curvature, Newton runs from it as well and its
//        mode is taken if it explains the evidence better by more than 1 nat
//        (unmasked coherent target tracks can hold the particles' mean in a
//        wrong mode; report.robust_start). If Newton found no mode, or the
//        best particle then explains the evidence better than m by more than
//        1 nat (m was a local mode), Newton restarts from that particle and the
//        frame is drawn again. Without a usable mode (no tracks, flat evidence) the frame
//        falls back to the dynamics proposal (report.laplace = false).
//      Weights not reset by the previous frame (ESS gate declined) carry
//      over; then normalise (log-sum-exp, particle_set.h).
//   3. estimate: the weighted mean of u, mapped back to a SimilarityMotion.
//   4. resample with the configured resampler (MakeResampler; the ESS gate
//      included). Adapter: the resamplers read only the normalised weights of
//      a ParticleSet (charged, the one that reads positions, is not allowed),
//      so the scene filter keeps its weights in a ParticleSet whose state
//      arrays are unused zeros, and gathers its own particles by the returned
//      ancestor indices.
// All randomness from the Rng given at construction (the caller passes a named
// fork, e.g. Rng(seed).Fork("scene")): identical seeds and evidence give
// identical estimates. Cost per frame: the evidence at N + ~33 k hypotheses
// (k Newton iterations, typically 2-4) plus O(N).
class SceneMotionFilter {
 public:
  // Validates `options` (throws InputError naming the field) and the image
  // size (>= 1 x 1).
  SceneMotionFilter(const SceneMotionOptions& options, int width, int height, Rng rng);

  SimilarityMotion Step(const CameraMotionEvidence& evidence, std::span<const BoxPx> exclude);

  // The diagnostics of the last Step (default-constructed before the first).
  const SceneMotionReport& LastReport() const { return report_; }
  // Number of Steps taken.
  int frames() const { return frames_; }
  // The particles and their normalised weights after the last Step.
  std::span<const SimilarityMotion> particles() const { return motions_; }
  std::span<const double> weights() const { return weights_.w; }

 private:
  using Vec = Eigen::Matrix<double, 4, 1>;
  SimilarityMotion ToMotion(const Vec& u) const;
  Vec FromMotion(const SimilarityMotion& motion) const;
  // Log-likelihood of each u in `us` under the evidence.
  void Evaluate(const CameraMotionEvidence& evidence, std::span<const BoxPx> exclude,
                std::span<const Vec> us, std::span<double> out);
  // Damped Newton ascent of the evidence from `start`; returns the mode and
  // the Hessian there, or nullopt when the curvature is not negative definite.
  struct Mode {
    Vec u;
    Eigen::Matrix4d hessian;
    double log_likelihood = 0.0;
  };
  std::optional<Mode> FindMode(const CameraMotionEvidence& evidence, std::span<const BoxPx> exclude,
                               Vec start, int& iterations);
  // Draws every particle from the proposal and adds its log weight increment.
  void Propose(const CameraMotionEvidence& evidence, std::span<const BoxPx> exclude,
               const std::optional<Mode>& mode, std::span<const Vec> from,
               std::span<const double> carried_log_w);

  SceneMotionOptions options_;
  Eigen::Vector2d centre_;
  double half_diagonal_;
  Rng rng_;
  std::unique_ptr<Resampler> resampler_;
  std::vector<Vec> particles_;
  std::vector<SimilarityMotion> motions_;
  // The resampler adapter: only log_w and w are meaningful.
  ParticleSet weights_;
  std::vector<Vec> scratch_;
  std::vector<double> log_lik_;
  std::vector<int32_t> ancestors_;
  SceneMotionReport report_;
  int frames_ = 0;
};

}  // namespace hcpf::tracker
