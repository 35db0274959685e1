#include "hcpf/tracker/scene_motion.h"

#include <fmt/format.h>

#include <cmath>
#include <utility>

#include "hcpf/core/check.h"
#include "hcpf/core/error.h"

namespace hcpf::tracker {

std::span<const Field<SceneMotionOptions>> SceneMotionOptions::Fields() {
  using O = SceneMotionOptions;
  static const std::vector<Field<O>> fields = {
      IntegerField("particles", &O::particles, 1, 10'000'000, "", "number of scene particles"),
      NumberField("prior_translation_px", &O::prior_translation_px, Closed(0, 1e4), "px",
                  "first frame: std. dev. of tx and ty around 0"),
      NumberField("prior_log_scale", &O::prior_log_scale, Closed(0, 1), "",
                  "first frame: std. dev. of the log-scale around 0"),
      NumberField("prior_rotation_rad", &O::prior_rotation_rad, Closed(0, 1), "rad",
                  "first frame: std. dev. of the rotation around 0"),
      NumberField("sigma_translation_px", &O::sigma_translation_px, Closed(0, 1000), "px/frame",
                  "random walk of tx and ty"),
      NumberField("sigma_log_scale", &O::sigma_log_scale, Closed(0, 1), "/frame",
                  "random walk of the log-scale"),
      NumberField("sigma_rotation_rad", &O::sigma_rotation_rad, Closed(0, 1), "rad/frame",
                  "random walk of the rotation"),
      ChoiceField<&O::resampling>("resampling", "resampling algorithm (any method but charged)"),
      NumberField("ess_threshold", &O::ess_threshold, Closed(0, 1), "",
                  "resample only when ESS < threshold · N (0 = every frame)"),
      NumberField("sigma_px", &O::sigma_px, AboveUpTo(0, 1e4), "px", "evidence residual scale σ"),
      ChoiceField<&O::loss>("loss", "point-track residual loss"),
      NumberField("student_t_dof", &O::student_t_dof, AboveUpTo(0, 1e6), "",
                  "degrees of freedom ν of the student_t loss"),
      NumberField("mask_dilation_px", &O::mask_dilation_px, Closed(0, 1e4), "px",
                  "target boxes grown by this on every side before masking"),
      ChoiceField<&O::evidence>("evidence",
                                "simulated: ground points through the true cameras (detection "
                                "level); oracle: the true frame-to-frame ground homography"),
      IntegerField("points", &O::points, 1, 1'000'000, "", "simulated: ground points per frame"),
      NumberField("point_noise_px", &O::point_noise_px, Closed(0, 100), "px",
                  "simulated: std. dev. of a tracked point's position"),
      NumberField("outlier_fraction", &O::outlier_fraction, Closed(0, 1), "",
                  "simulated: fraction of tracks replaced by random mis-tracks"),
  };
  return fields;
}

void SceneMotionOptions::Validate(std::string_view prefix) const {
  CheckFields(*this, Fields(), prefix);
  if (resampling == ResamplingMethod::kCharged) {
    FailOption(prefix, "resampling", "one of multinomial, systematic, stratified, residual",
               "charged");
  }
}

Eigen::Vector2d Apply(const SimilarityMotion& motion, const Eigen::Vector2d& p) {
  const double scale = std::exp(motion.log_scale);
  const double a = scale * std::cos(motion.rotation_rad);
  const double b = scale * std::sin(motion.rotation_rad);
  return {a * p.x() - b * p.y() + motion.tx_px, b * p.x() + a * p.y() + motion.ty_px};
}

PointTrackEvidence::PointTrackEvidence(std::vector<PointTrack> tracks,
                                       const SceneMotionOptions& options)
    : tracks_(std::move(tracks)), options_(options) {
  options_.Validate();
}

bool PointTrackEvidence::Excluded(const PointTrack& track, std::span<const BoxPx> exclude) const {
  const double d = options_.mask_dilation_px;
  for (const BoxPx& box : exclude) {
    if (track.p.x() >= box.left - d && track.p.x() <= box.right() + d &&
        track.p.y() >= box.top - d && track.p.y() <= box.bottom() + d) {
      return true;
    }
  }
  return false;
}

void PointTrackEvidence::AddLogLikelihood(std::span<const SimilarityMotion> hypotheses,
                                          std::span<const BoxPx> exclude,
                                          std::span<double> log_w) const {
  HCPF_CHECK(log_w.size() == hypotheses.size())
      << "log_w has " << log_w.size() << " entries for " << hypotheses.size() << " hypotheses";
  std::vector<Eigen::Vector2d> p, q;
  p.reserve(tracks_.size());
  q.reserve(tracks_.size());
  for (const PointTrack& track : tracks_) {
    if (Excluded(track, exclude)) continue;
    p.push_back(track.p);
    q.push_back(track.q);
  }
  const double sigma2 = options_.sigma_px * options_.sigma_px;
  const double nu = options_.student_t_dof;
  const bool student = options_.loss == PointLoss::kStudentT;
  for (size_t h = 0; h < hypotheses.size(); ++h) {
    const SimilarityMotion& s = hypotheses[h];
    const double scale = std::exp(s.log_scale);
    const double a = scale * std::cos(s.rotation_rad);
    const double b = scale * std::sin(s.rotation_rad);
    double sum = 0.0;
    for (size_t k = 0; k < p.size(); ++k) {
      const double dx = a * p[k].x() - b * p[k].y() + s.tx_px - q[k].x();
      const double dy = b * p[k].x() + a * p[k].y() + s.ty_px - q[k].y();
      const double r2 = dx * dx + dy * dy;
      sum += student ? -0.5 * (nu + 2.0) * std::log1p(r2 / (nu * sigma2)) : -0.5 * r2 / sigma2;
    }
    log_w[h] += sum;
  }
}

HomographyEvidence::HomographyEvidence(const Eigen::Matrix3d& frame_from_previous, int width,
                                       int height, double sigma_px)
    : sigma_px_(sigma_px) {
  if (width < 1 || height < 1) {
    throw InputError(fmt::format(
        "HomographyEvidence: image size must be at least 1 x 1, got {} x {}", width, height));
  }
  if (!(sigma_px > 0.0) || !std::isfinite(sigma_px)) {
    throw InputError(
        fmt::format("HomographyEvidence: sigma_px must be a positive number, got {}", sigma_px));
  }
  for (int j = 0; j < kGrid; ++j) {
    for (int i = 0; i < kGrid; ++i) {
      const Eigen::Vector2d g((i + 0.5) * width / kGrid, (j + 0.5) * height / kGrid);
      const Eigen::Vector3d h = frame_from_previous * Eigen::Vector3d(g.x(), g.y(), 1.0);
      if (!(h.z() > 0.0) || !h.allFinite()) {
        throw InputError(fmt::format(
            "HomographyEvidence: the homography maps grid point ({}, {}) to homogeneous z = {}, "
            "expected a positive number",
            g.x(), g.y(), h.z()));
      }
      grid_.push_back(g);
      target_.emplace_back(h.x() / h.z(), h.y() / h.z());
    }
  }
}

void HomographyEvidence::AddLogLikelihood(std::span<const SimilarityMotion> hypotheses,
                                          std::span<const BoxPx> /*exclude*/,
                                          std::span<double> log_w) const {
  HCPF_CHECK(log_w.size() == hypotheses.size())
      << "log_w has " << log_w.size() << " entries for " << hypotheses.size() << " hypotheses";
  const double inv = 1.0 / (2.0 * sigma_px_ * sigma_px_ * static_cast<double>(grid_.size()));
  for (size_t h = 0; h < hypotheses.size(); ++h) {
    double sum = 0.0;
    for (size_t k = 0; k < grid_.size(); ++k) {
      sum += (Apply(hypotheses[h], grid_[k]) - target_[k]).squaredNorm();
    }
    log_w[h] -= sum * inv;
  }
}

SceneMotionFilter::SceneMotionFilter(const SceneMotionOptions& options, Rng rng)
    : options_(options), rng_(std::move(rng)) {
  options_.Validate();
  ResamplerOptions resampling;
  resampling.method = options_.resampling;
  resampling.ess_threshold = options_.ess_threshold;
  resampler_ = MakeResampler(resampling);
  const auto n = static_cast<size_t>(options_.particles);
  particles_.resize(n);
  scratch_.resize(n);
  ancestors_.resize(n);
  weights_.Resize(n);
  weights_.SetUniformWeights();
}

void SceneMotionFilter::Propagate() {
  const bool first = frames_ == 0;
  const double st = first ? options_.prior_translation_px : options_.sigma_translation_px;
  const double ss = first ? options_.prior_log_scale : options_.sigma_log_scale;
  const double sr = first ? options_.prior_rotation_rad : options_.sigma_rotation_rad;
  for (SimilarityMotion& m : particles_) {
    // At the first frame every particle is the identity, so the same lines
    // draw the prior.
    m.tx_px += st * rng_.Normal();
    m.ty_px += st * rng_.Normal();
    m.log_scale += ss * rng_.Normal();
    m.rotation_rad += sr * rng_.Normal();
  }
}

SimilarityMotion SceneMotionFilter::Step(const CameraMotionEvidence& evidence,
                                         std::span<const BoxPx> exclude) {
  Propagate();
  evidence.AddLogLikelihood(particles_, exclude, weights_.log_w);
  const NormaliseResult normalised = NormaliseLogWeights(weights_);

  SceneMotionReport report;
  report.recovered_degenerate = normalised.recovered_degenerate;
  report.ess = EffectiveSampleSize(weights_.w);
  SimilarityMotion mean;
  for (size_t i = 0; i < particles_.size(); ++i) {
    const double w = weights_.w[i];
    mean.tx_px += w * particles_[i].tx_px;
    mean.ty_px += w * particles_[i].ty_px;
    mean.log_scale += w * particles_[i].log_scale;
    mean.rotation_rad += w * particles_[i].rotation_rad;
  }
  double vt_x = 0.0, vt_y = 0.0, v_s = 0.0, v_r = 0.0;
  for (size_t i = 0; i < particles_.size(); ++i) {
    const double w = weights_.w[i];
    const SimilarityMotion& m = particles_[i];
    vt_x += w * (m.tx_px - mean.tx_px) * (m.tx_px - mean.tx_px);
    vt_y += w * (m.ty_px - mean.ty_px) * (m.ty_px - mean.ty_px);
    v_s += w * (m.log_scale - mean.log_scale) * (m.log_scale - mean.log_scale);
    v_r += w * (m.rotation_rad - mean.rotation_rad) * (m.rotation_rad - mean.rotation_rad);
  }
  report.estimate = mean;
  report.sd_tx_px = std::sqrt(vt_x);
  report.sd_ty_px = std::sqrt(vt_y);
  report.sd_log_scale = std::sqrt(v_s);
  report.sd_rotation_rad = std::sqrt(v_r);

  const ResampleResult resampled = resampler_->Resample(weights_, {}, rng_, ancestors_);
  report.resampled = resampled.resampled;
  if (resampled.resampled) {
    for (size_t i = 0; i < particles_.size(); ++i) {
      scratch_[i] = particles_[static_cast<size_t>(ancestors_[i])];
    }
    std::swap(particles_, scratch_);
    weights_.SetUniformWeights();
  }
  report_ = report;
  ++frames_;
  return mean;
}

}  // namespace hcpf::tracker
