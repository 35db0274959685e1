#include "hcpf/tracker/tracker.h"

#include <spdlog/spdlog.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <thread>

#include "hcpf/core/check.h"
#include "hcpf/core/normal.h"
#include "hcpf/core/parallel.h"
#include "hcpf/tracker/hungarian.h"

namespace hcpf::tracker {

std::span<const Field<TrackManagementOptions>> TrackManagementOptions::Fields() {
  using O = TrackManagementOptions;
  static const std::vector<Field<O>> fields = {
      IntegerField("confirm_hits", &O::confirm_hits, 1, 1000, "",
                   "init detections: M of M-of-N confirmation (M ≤ confirm_window)"),
      IntegerField("confirm_window", &O::confirm_window, 1, 1000, "frames",
                   "init detections: N of M-of-N confirmation"),
      NumberField("tentative_gate_px", &O::tentative_gate_px, Closed(1e-3, 1e5), "px",
                  "init detections: a detection continues a tentative track this close"),
      IntegerField("max_missed_frames", &O::max_missed_frames, 0, 1'000'000, "frames",
                   "delete a filter after this many frames without support; 0 = never"),
      FlagField("coast_without_support", &O::coast_without_support,
                "predict only while a filter has no support"),
      NumberField("birth_sigma_px", &O::birth_sigma_px, Closed(0, 1e4), "px",
                  "spread of a newborn filter's centre"),
      NumberField("birth_sigma_vel_px", &O::birth_sigma_vel_px, Closed(0, 1e4), "px/frame",
                  "spread of a newborn filter's velocity"),
      NumberField("birth_sigma_log_scale", &O::birth_sigma_log_scale, Closed(0, 10), "",
                  "spread of a newborn filter's log-scale"),
      ChoiceField<&O::birth_velocity>(
          "birth_velocity",
          "init ground_truth: a newborn filter's mean velocity. zero: at rest; ground_truth: "
          "its target's image displacement from its birth frame to the next (from the frame "
          "before at the last frame), less the camera's motion when tracker.camera_motion "
          "moves the particles"),
      ChoiceField<&O::reacquire>(
          "reacquire",
          "init ground_truth with a model-based detector. none: a filter that loses its target "
          "coasts and is deleted; own_detections: once its target's detections that no filter "
          "was given and no other filter is on confirm (confirm_hits of confirm_window, within "
          "tentative_gate_px), the filter is re-seeded there (born again with its id if it was "
          "deleted)"),
  };
  return fields;
}

void TrackManagementOptions::Validate(std::string_view prefix) const {
  CheckFields(*this, Fields(), prefix);
  if (confirm_hits > confirm_window) {
    FailOption(prefix, "confirm_hits",
               fmt::format("an integer in [1, confirm_window = {}]", confirm_window), confirm_hits);
  }
}

std::span<const Field<TrackerOptions>> TrackerOptions::Fields() {
  using O = TrackerOptions;
  static const std::vector<Field<O>> fields = {
      IntegerField("particles", &O::particles, 1, 10'000'000, "", "particles per filter"),
      IntegerField("keep_particles", &O::keep_particles, 0, 100'000, "",
                   "particles per filter kept per frame (overlays, particle-mass metric)"),
      ChoiceField<&O::init>("init",
                            "ground_truth: a filter is born at each target's first in-frame "
                            "appearance, from its box (with a model-based detector when the "
                            "target's model is cut, from the same box; with a labelled detection "
                            "file at its first labelled row, from that frame's box); detections: "
                            "M-of-N confirmation"),
      ChoiceField<&O::camera_motion>(
          "camera_motion",
          "none: target dynamics alone; scene_filter: the scene filter's estimate of the "
          "camera's frame-to-frame motion moves every particle first (hierarchical); ransac: "
          "a RANSAC similarity on the same point tracks (the common recipe); oracle: the true "
          "motion's best similarity"),
  };
  return fields;
}

void TrackerOptions::Validate() const {
  CheckFields(*this, Fields(), "tracker");
  if (threads < 1 || threads > 256) {
    FailOption("tracker", "threads", "an integer in [1, 256]", threads);
  }
  dynamics.Validate("tracker.dynamics");
  likelihood.Validate("tracker.likelihood");
  resampling.Validate("tracker.resampling");
  interaction.Validate("tracker.interaction");
  association.Validate("tracker.association");
  management.Validate("tracker.management");
  if (init == InitMode::kDetections && management.birth_velocity != BirthVelocity::kZero) {
    FailOption("tracker.management", "birth_velocity",
               "zero (tracker.init is detections: a confirmed track's velocity comes from its "
               "detections)",
               "ground_truth with tracker.init: detections");
  }
  if (init == InitMode::kDetections && management.reacquire != ReacquireMode::kNone) {
    FailOption("tracker.management", "reacquire",
               "none (tracker.init is detections: unclaimed detections already begin new tracks)",
               "own_detections with tracker.init: detections");
  }
  scene_filter.Validate("tracker.scene_filter");
  if (camera_motion == CameraMotionMode::kRansac &&
      scene_filter.evidence == SceneEvidenceKind::kOracle) {
    FailOption("tracker.scene_filter", "evidence",
               "simulated or image (tracker.camera_motion: ransac fits point tracks)", "oracle");
  }
  if (likelihood.model == LikelihoodModel::kAssociated &&
      association.method == AssociationMethod::kNone) {
    FailOption("tracker.association", "method",
               "gnn or nearest (tracker.likelihood.model is associated)", "none");
  }
  if (dynamics.model == DynamicsModel::kConstantVelocityScale &&
      likelihood.model != LikelihoodModel::kMap && likelihood.sigma_log_size == 0.0) {
    FailOption(
        "tracker.likelihood", "sigma_log_size",
        "> 0 when tracker.dynamics.model is constant_velocity_scale (else the scale is unobserved)",
        likelihood.sigma_log_size);
  }
}

std::vector<TrackEstimate> ToTrackEstimates(const FrameReport& report, int particles) {
  std::vector<TrackEstimate> out;
  out.reserve(report.filters.size());
  for (const FilterReport& f : report.filters) {
    out.push_back({.id = f.id, .box = f.box, .confidence = f.ess / std::max(1, particles)});
  }
  return out;
}

struct MultiTargetTracker::Filter {
  TrackId id{};
  Rng rng;
  ParticleSet set;
  ParticleSet scratch;
  std::vector<int32_t> ancestors;
  double base_w_px = 1.0;
  double base_h_px = 1.0;
  bool just_born = true;
  int missed_frames = 0;
  // This frame:
  bool supported = false;
  bool coasting = false;
};

namespace {

// A filter's box: its mean centre, its birth size times its mean scale.
BoxPx EstimateBox(const FilterSummary& s, double base_w_px, double base_h_px) {
  return BoxPx::FromCentre(s.mean.x(), s.mean.y(), base_w_px * s.mean_scale,
                           base_h_px * s.mean_scale);
}

}  // namespace

MultiTargetTracker::MultiTargetTracker(const TrackerOptions& options, TrackerComponents components,
                                       Rng rng)
    : options_(options), components_(std::move(components)), rng_(rng) {
  options_.Validate();
  HCPF_CHECK(components_.dynamics && components_.likelihood && components_.interaction &&
             components_.resampler && components_.associator && components_.initiator &&
             components_.deleter)
      << "every tracker component must be set";
}

MultiTargetTracker::~MultiTargetTracker() = default;

size_t MultiTargetTracker::num_filters() const { return filters_.size(); }

std::vector<TrackId> MultiTargetTracker::track_ids() const {
  std::vector<TrackId> ids;
  for (const auto& f : filters_) ids.push_back(f->id);
  return ids;
}

const ParticleSet* MultiTargetTracker::particles(TrackId id) const {
  for (const auto& f : filters_) {
    if (f->id == id) return &f->set;
  }
  return nullptr;
}

void MultiTargetTracker::BirthTrack(TrackId id, const BoxPx& initial_box,
                                    Eigen::Vector2d velocity_px) {
  Bear(id, rng_.Fork("tracker/filter", Value(id)), initial_box, velocity_px);
}

MultiTargetTracker::Filter& MultiTargetTracker::Bear(TrackId id, Rng rng, const BoxPx& box,
                                                     const Eigen::Vector2d& velocity_px) {
  HCPF_CHECK(!box.empty()) << "birth box must have positive size";
  HCPF_CHECK(particles(id) == nullptr) << "track " << Value(id) << " already exists";
  auto f = std::make_unique<Filter>();
  f->id = id;
  f->rng = rng;
  Seed(*f, box, velocity_px);
  ever_born_.insert(Value(id));
  const auto pos =
      std::lower_bound(filters_.begin(), filters_.end(), id,
                       [](const auto& a, TrackId b) { return Value(a->id) < Value(b); });
  return **filters_.insert(pos, std::move(f));
}

void MultiTargetTracker::Seed(Filter& f, const BoxPx& box,
                              const Eigen::Vector2d& velocity_px) const {
  f.base_w_px = box.width;
  f.base_h_px = box.height;
  const auto n = static_cast<size_t>(options_.particles);
  f.set.Resize(n);
  f.ancestors.resize(n);
  const TrackManagementOptions& m = options_.management;
  std::vector<double> noise(5 * n);
  FillStandardNormal(f.rng, noise);
  const double cx = box.centre_x();
  const double cy = box.centre_y();
  for (size_t i = 0; i < n; ++i) {
    f.set.px[i] = cx + m.birth_sigma_px * noise[i];
    f.set.py[i] = cy + m.birth_sigma_px * noise[n + i];
    f.set.vx[i] = velocity_px.x() + m.birth_sigma_vel_px * noise[2 * n + i];
    f.set.vy[i] = velocity_px.y() + m.birth_sigma_vel_px * noise[3 * n + i];
    f.set.s[i] = std::exp(m.birth_sigma_log_scale * noise[4 * n + i]);
  }
}

template <typename Fn>
void MultiTargetTracker::ForEachFilter(Fn&& fn) {
  // Each filter touches only its own state and stream, so which thread runs
  // it never changes the numbers.
  ParallelFor(filters_.size(), options_.threads, fn);
}

// Per filter: the observation it sees (the frame, or its own target's part
// of a target-specific frame), the index of its detection in that view (or
// -1), whether the associator found evidence for it, and its detection's
// index in the whole frame (or -1).
struct MultiTargetTracker::FrameViews {
  std::vector<const Observation*> seen;
  std::vector<int> local;
  std::vector<uint8_t> evidence;
  std::vector<int> assignment;
  std::vector<Observation> own;  // target-specific frames: each filter's part
};

FrameReport MultiTargetTracker::Step(const Observation& observation,
                                     const std::optional<SimilarityMotion>& camera_motion) {
  FrameReport report;
  report.frame = observation.frame;
  Predict(camera_motion);
  const std::vector<FilterSummary> predicted = Summaries();
  const std::vector<TrackPrediction> predictions = Predictions(predicted);
  const FrameViews views = Associate(observation, predictions);
  Update(views, predicted, report);
  Resample(PosteriorSummaries(report), report);
  ManageTracks(observation, views.assignment, predictions, camera_motion, report);
  return report;
}

MultiTargetTracker::FrameViews MultiTargetTracker::Associate(
    const Observation& observation, const std::vector<TrackPrediction>& predictions) const {
  FrameViews v;
  const size_t n = filters_.size();
  if (!observation.target_specific()) {
    v.assignment = components_.associator->Associate(predictions, observation.detections);
    v.evidence =
        components_.associator->Evidence(predictions, observation.detections, v.assignment);
    v.local = v.assignment;
    v.seen.assign(n, &observation);
    return v;
  }
  // Target-specific: filter i sees only the detections and the map of the
  // target whose id its TrackId carries, and is associated with those alone.
  v.own.resize(n);
  v.seen.resize(n);
  v.local.assign(n, -1);
  v.evidence.assign(n, 0);
  v.assignment.assign(n, -1);
  for (size_t i = 0; i < n; ++i) {
    const ObjectId target{Value(filters_[i]->id)};
    Observation& own = v.own[i];
    own.frame = observation.frame;
    std::vector<int> index;
    for (size_t d = 0; d < observation.detections.size(); ++d) {
      if (observation.detections[d].target == target) {
        own.detections.push_back(observation.detections[d]);
        index.push_back(static_cast<int>(d));
      }
    }
    for (const TargetMap& m : observation.target_maps) {
      if (m.target == target) own.likelihood = m.map;
    }
    const std::span<const TrackPrediction> one(&predictions[i], 1);
    const std::vector<int> local = components_.associator->Associate(one, own.detections);
    v.local[i] = local[0];
    v.evidence[i] = components_.associator->Evidence(one, own.detections, local)[0];
    v.assignment[i] = local[0] >= 0 ? index[static_cast<size_t>(local[0])] : -1;
    v.seen[i] = &own;
  }
  return v;
}

void MultiTargetTracker::Predict(const std::optional<SimilarityMotion>& camera_motion) {
  ForEachFilter([&](size_t i) {
    Filter& f = *filters_[i];
    if (f.just_born) return;  // born for this frame: already describes it
    if (camera_motion) ApplyCameraMotion(*camera_motion, f.set);
    components_.dynamics->Predict(f.set, f.rng);
  });
}

std::vector<FilterSummary> MultiTargetTracker::Summaries() const {
  std::vector<FilterSummary> out;
  out.reserve(filters_.size());
  for (const auto& f : filters_) out.push_back(Summarise(f->set, f->id));
  return out;
}

std::vector<TrackPrediction> MultiTargetTracker::Predictions(
    const std::vector<FilterSummary>& predicted) const {
  std::vector<TrackPrediction> out;
  out.reserve(filters_.size());
  for (size_t i = 0; i < filters_.size(); ++i) {
    const Filter& f = *filters_[i];
    const FilterSummary& s = predicted[i];
    out.push_back({.id = f.id,
                   .mean = s.mean,
                   .cov = s.cov,
                   .box = EstimateBox(s, f.base_w_px, f.base_h_px)});
  }
  return out;
}

std::vector<FilterSummary> MultiTargetTracker::PosteriorSummaries(const FrameReport& report) {
  std::vector<FilterSummary> out;
  out.reserve(report.filters.size());
  for (const FilterReport& f : report.filters) {
    out.push_back({.id = f.id, .mean = f.mean, .cov = f.cov, .ess = f.ess});
  }
  return out;
}

namespace {

std::vector<FilterSummary> Others(const std::vector<FilterSummary>& all, size_t self) {
  std::vector<FilterSummary> others;
  others.reserve(all.size());
  for (size_t j = 0; j < all.size(); ++j) {
    if (j != self) others.push_back(all[j]);
  }
  return others;
}

std::vector<ParticlePoint> Decimate(const ParticleSet& set, int keep) {
  std::vector<ParticlePoint> out;
  if (keep <= 0 || set.size() == 0) return out;
  const size_t n = set.size();
  const size_t stride = (n + static_cast<size_t>(keep) - 1) / static_cast<size_t>(keep);
  out.reserve(n / stride + 1);
  for (size_t i = 0; i < n; i += stride) {
    out.push_back({static_cast<float>(set.px[i]), static_cast<float>(set.py[i]),
                   static_cast<float>(set.w[i])});
  }
  return out;
}

// The estimate part of a filter's report row (Update's and a seeded filter's).
void DescribeEstimate(FilterReport& r, TrackId id, const FilterSummary& s, double base_w_px,
                      double base_h_px, const ParticleSet& set, int keep_particles) {
  r.id = id;
  r.mean = s.mean;
  r.cov = s.cov;
  r.ess = s.ess;
  r.box = EstimateBox(s, base_w_px, base_h_px);
  r.particles = Decimate(set, keep_particles);
}

}  // namespace

void MultiTargetTracker::Update(const FrameViews& views,
                                const std::vector<FilterSummary>& predicted, FrameReport& report) {
  report.filters.resize(filters_.size());
  ForEachFilter([&](size_t i) {
    Filter& f = *filters_[i];
    const Observation& seen = *views.seen[i];
    const int local = views.local[i];
    const LikelihoodInput input{
        .observation = &seen,
        .assigned = local >= 0 ? &seen.detections[static_cast<size_t>(local)] : nullptr,
        .detection_evidence = views.evidence[i] != 0,
        .base_w_px = f.base_w_px,
        .base_h_px = f.base_h_px};
    // Support: the likelihood's verdict on this frame's evidence.
    f.supported = components_.likelihood->HasEvidence(input);
    f.coasting = !f.supported && options_.management.coast_without_support;
    if (!f.coasting) {
      components_.likelihood->AddLogLikelihood(f.set, input);
      components_.interaction->Apply(f.set, Others(predicted, i));
    }
    const NormaliseResult normalised = NormaliseLogWeights(f.set);
    const FilterSummary s = Summarise(f.set, f.id);
    FilterReport& r = report.filters[i];
    DescribeEstimate(r, f.id, s, f.base_w_px, f.base_h_px, f.set, options_.keep_particles);
    r.recovered_degenerate = normalised.recovered_degenerate;
    r.coasting = f.coasting;
    r.assigned_detection = views.assignment[i];
  });
  for (const FilterReport& r : report.filters) {
    if (r.recovered_degenerate) ++report.degenerate_filters;
  }
  if (report.degenerate_filters > 0) {
    spdlog::debug("tracker: frame {}: {} filter(s) with vanished weights reset to uniform",
                  report.frame, report.degenerate_filters);
  }
}

void MultiTargetTracker::Resample(const std::vector<FilterSummary>& posterior,
                                  FrameReport& report) {
  ForEachFilter([&](size_t i) {
    Filter& f = *filters_[i];
    FilterReport& r = report.filters[i];
    if (f.coasting) return;  // predict only while the evidence is gone
    const std::vector<FilterSummary> others = Others(posterior, i);
    const ResampleResult result =
        components_.resampler->Resample(f.set, ResampleContext{others}, f.rng, f.ancestors);
    r.resampled = result.resampled;
    r.rejections = result.rejections;
    r.potential_terms = result.potential_terms;
    if (result.resampled) ApplyAncestors(f.set, f.ancestors, f.scratch);
  });
}

void MultiTargetTracker::ReportSeeded(const Filter& f, int detection, FrameReport& report) const {
  const FilterSummary s = Summarise(f.set, f.id);
  const auto pos =
      std::lower_bound(report.filters.begin(), report.filters.end(), f.id,
                       [](const FilterReport& r, TrackId id) { return Value(r.id) < Value(id); });
  FilterReport& r = pos != report.filters.end() && pos->id == f.id
                        ? *pos
                        : *report.filters.insert(pos, FilterReport{});
  DescribeEstimate(r, f.id, s, f.base_w_px, f.base_h_px, f.set, options_.keep_particles);
  r.coasting = false;
  r.assigned_detection = detection;
  r.missed_frames = 0;
}

void MultiTargetTracker::ManageTracks(const Observation& observation,
                                      const std::vector<int>& assignment,
                                      const std::vector<TrackPrediction>& predictions,
                                      const std::optional<SimilarityMotion>& camera_motion,
                                      FrameReport& report) {
  // Support counters and deletion.
  std::vector<std::unique_ptr<Filter>> kept;
  kept.reserve(filters_.size());
  for (size_t i = 0; i < filters_.size(); ++i) {
    Filter& f = *filters_[i];
    f.just_born = false;
    f.missed_frames = f.supported ? 0 : f.missed_frames + 1;
    report.filters[i].missed_frames = f.missed_frames;
    if (components_.deleter->Delete(f.missed_frames)) {
      report.deleted.push_back(f.id);
    } else {
      kept.push_back(std::move(filters_[i]));
    }
  }
  filters_ = std::move(kept);
  std::vector<char> assigned(observation.detections.size(), 0);
  for (const int d : assignment) {
    if (d >= 0) assigned[static_cast<size_t>(d)] = 1;
  }
  // A frame without labelled detections (none at all, say) still steps the
  // open tentatives: it is a miss, and the camera's motion carries their
  // centres (skipped, it was neither: review).
  if (options_.management.reacquire == ReacquireMode::kOwnDetections &&
      (observation.target_specific() || !reacquiring_.empty())) {
    Reacquire(observation, assigned, predictions, camera_motion, report);
  }

  // Births from the detections no filter claims: not assigned and not inside
  // any filter's gate (so association = none does not spawn duplicates of
  // existing tracks).
  std::vector<size_t> free_detections;
  for (size_t d = 0; d < observation.detections.size(); ++d) {
    if (assigned[d]) continue;
    // A box with a non-finite side (a broken detector output) is no
    // position: never gated in, never a birth (a review: with confirm_hits 1
    // a NaN left was born as a NaN filter, a NaN width aborted).
    if (!observation.detections[d].box.finite()) continue;
    const bool gated = std::any_of(predictions.begin(), predictions.end(), [&](const auto& p) {
      return GatedCost(p, observation.detections[d], options_.association).has_value();
    });
    if (!gated) free_detections.push_back(d);
  }
  for (const Birth& birth :
       components_.initiator->Step(observation, free_detections, camera_motion)) {
    const TrackId id{next_track_id_++};
    // Born from this frame's detection, so it describes this frame: it is
    // reported in it, and it predicts at the next Step (unlike a BirthTrack
    // before a Step).
    Filter& f = Bear(id, rng_.Fork("tracker/filter", Value(id)), birth.box, birth.velocity_px);
    f.just_born = false;
    ReportSeeded(f, birth.detection, report);
    report.born.push_back(id);
  }
}

void MultiTargetTracker::Reacquire(const Observation& observation,
                                   const std::vector<char>& assigned,
                                   const std::vector<TrackPrediction>& predictions,
                                   const std::optional<SimilarityMotion>& camera_motion,
                                   FrameReport& report) {
  // A filter with support this frame has its target: its tentative ends.
  for (const auto& f : filters_) {
    if (f->supported) reacquiring_.erase(Value(f->id));
  }
  // Each target's best detection (highest score, then first) that no filter
  // was given and whose centre lies in no other filter's predicted box (that
  // filter is on whatever the detector found there), for the targets ever
  // born whose filter is gone or unsupported.
  std::map<int32_t, size_t> best;
  for (size_t d = 0; d < observation.detections.size(); ++d) {
    const Detection& det = observation.detections[d];
    if (!det.target) continue;
    const int32_t target = Value(*det.target);
    if (!ever_born_.contains(target) || assigned[d]) continue;
    const auto f = std::find_if(filters_.begin(), filters_.end(),
                                [&](const auto& g) { return Value(g->id) == target; });
    if (f != filters_.end() && (*f)->supported) continue;
    const double x = det.box.centre_x();
    const double y = det.box.centre_y();
    const bool explained = std::any_of(predictions.begin(), predictions.end(), [&](const auto& p) {
      return Value(p.id) != target && x >= p.box.left && x < p.box.right() && y >= p.box.top &&
             y < p.box.bottom();
    });
    if (explained) continue;
    const auto [it, inserted] = best.try_emplace(target, d);
    if (!inserted && det.score > observation.detections[it->second].score) it->second = d;
  }
  // Every open tentative steps each frame, with or without a detection, so
  // that one which can no longer reach confirm_hits ends as under init:
  // detections.
  std::set<int32_t> targets;
  for (const auto& [target, tentative] : reacquiring_) targets.insert(target);
  for (const auto& [target, d] : best) targets.insert(target);
  for (const int32_t target : targets) {
    auto tentative = reacquiring_.try_emplace(target, options_.management).first;
    const auto candidate = best.find(target);
    const std::vector<Birth> confirmed =
        candidate == best.end()
            ? tentative->second.Step(observation, {}, camera_motion)
            : tentative->second.Step(observation, std::span<const size_t>(&candidate->second, 1),
                                     camera_motion);
    if (confirmed.empty()) continue;
    reacquiring_.erase(tentative);
    const Birth& birth = confirmed.front();
    const TrackId id{target};
    const auto f =
        std::find_if(filters_.begin(), filters_.end(), [&](const auto& g) { return g->id == id; });
    Filter* seeded = nullptr;
    if (f != filters_.end()) {
      // Lost but not deleted: its particles start again at its target, drawn
      // from its own stream; its support count starts again too.
      seeded = f->get();
      Seed(*seeded, birth.box, birth.velocity_px);
      seeded->missed_frames = 0;
    } else {
      // Born from this frame's detection: it predicts at the next Step.
      seeded =
          &Bear(id, rng_.Fork("tracker/filter", target).Fork("reacquired", ++rebirths_[target]),
                birth.box, birth.velocity_px);
      seeded->just_born = false;
    }
    // Its row for this frame is its re-seeded estimate, not the lost one (nor
    // the deleted filter's, if it ended this frame and is born again).
    ReportSeeded(*seeded, birth.detection, report);
    report.reacquired.push_back(id);
  }
}

std::unique_ptr<Initiator> MakeInitiator(const TrackerOptions& options) {
  if (options.init == InitMode::kDetections) {
    return std::make_unique<MofNInitiator>(options.management);
  }
  return std::make_unique<NoInitiator>();
}

std::unique_ptr<MultiTargetTracker> MakeTracker(const TrackerOptions& options, Rng rng) {
  options.Validate();
  TrackerComponents components{
      .dynamics = MakeDynamics(options.dynamics),
      .likelihood = MakeLikelihood(options.likelihood),
      .interaction = MakeInteraction(options.interaction),
      .resampler = MakeResampler(options.resampling),
      .associator = MakeAssociator(options.association),
      .initiator = MakeInitiator(options),
      .deleter = std::make_unique<MissedFramesDeleter>(options.management.max_missed_frames)};
  return std::make_unique<MultiTargetTracker>(options, std::move(components), rng);
}

}  // namespace hcpf::tracker
