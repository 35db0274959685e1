#include "hcpf/scenarios/run.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>

#include "camera_motion_pass.h"
#include "detection_pass.h"
#include "external_tracker.h"
#include "hcpf/core/error.h"
#include "hcpf/core/ground_truth.h"
#include "hcpf/metrics/detection_truth.h"
#include "hcpf/metrics/mot_io.h"
#include "hcpf/metrics/report.h"
#include "hcpf/scenarios/frames.h"
#include "hcpf/scenarios/models.h"
#include "hcpf/scenarios/observation_simulator.h"
#include "hcpf/scenarios/output_folder.h"
#include "hcpf/scenarios/overlay.h"
#include "hcpf/scenarios/progress.h"
#include "hcpf/scenarios/version.h"
#include "hcpf/tracker/tracker.h"
#include "rendering_check.h"
#include "writers.h"

namespace hcpf::scenarios {

namespace fs = std::filesystem;

namespace {

// Charged resampling's cost per potential term, the acceptance tests and
// redraws included: 2.0-2.6 ns (5000 particles, 20, 40 and 80 targets packed
// 2 m apart under parallel.yaml's camera, 200 frames: the charged run's time
// over the systematic one's, over its terms; 2026-12-07, docs/tracker.md).
constexpr double kSecondsPerChargedTerm = 2e-9;
// ChargedResamplingNote speaks when the charges cost at least this long and
// at least this share of the tracker's time.
constexpr double kChargedNoteSeconds = 5.0;
constexpr double kChargedNoteShare = 0.5;

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

// Frees a frame's likelihood maps once the tracker has read them: nothing
// after the tracker needs them, and kept for every frame they grew without
// bound (a scale audit: a model-based detector's per-target maps, 155 KB a
// frame for SKS and PRCA at 640x480; the oracle's likelihood_map, 1.2 MB a
// frame at map_cell_px 1).
void DropMaps(Observation& observation) {
  std::vector<TargetMap>().swap(observation.target_maps);
  observation.likelihood.reset();
}

}  // namespace

std::string ChargedResamplingNote(std::span<const tracker::FrameReport> reports, int particles,
                                  double tracker_seconds) {
  int64_t terms = 0, filter_frames = 0;
  for (const tracker::FrameReport& report : reports) {
    for (const tracker::FilterReport& r : report.filters) {
      terms += r.potential_terms;
      filter_frames += r.potential_terms > 0 ? 1 : 0;
    }
  }
  const double seconds = static_cast<double>(terms) * kSecondsPerChargedTerm;
  if (seconds < kChargedNoteSeconds || seconds < kChargedNoteShare * tracker_seconds) return "";
  return fmt::format(
      "charged resampling weighed {:.3g} potential terms, about {:.3g} s of the tracker's {:.3g} s "
      "at ~{:g} ns each: each of a filter's {} draws a frame met {:.3g} other filters' charges on "
      "average, redraws included. Its cost grows with the filters within reach of one another, "
      "about N K^2 for K filters all within reach (docs/tracker.md); "
      "tracker.resampling.softening_px and the filters' spread set the reach, tracker.particles "
      "and tracker.resampling.max_tries the draws",
      static_cast<double>(terms), seconds, tracker_seconds, kSecondsPerChargedTerm * 1e9, particles,
      static_cast<double>(terms) / (static_cast<double>(filter_frames) * particles));
}

RunSummary RunScenario(const Scenario& scenario, const RunOptions& options) {
  const auto start = Clock::now();
  // A file named as the cache failed mid-run (exit 1) creating a scene there.
  if (!options.frame_cache_dir.empty()) CheckFolderArgument(options.frame_cache_dir, "--cache");
  if (options.video) {
    CheckVideoFits(scenario, "--video");
    if (const std::string note = VideoLevelNote(scenario); !note.empty()) {
      spdlog::warn("run \"{}\": {}", scenario.name, note);
    }
  }
  if (const std::string slow = SceneFilterCostWarning(scenario); !slow.empty()) {
    spdlog::warn("run \"{}\": {}", scenario.name, slow);
  }
  StagedFolder staged(options.out_dir, options.remove_stale_siblings);
  const fs::path& partial = staged.partial();
  std::error_code ec;
  fs::create_directories(partial / "gt", ec);
  if (ec) throw RunError(fmt::format("cannot create {}: {}", partial.string(), ec.message()));

  RunSummary summary;
  summary.out_dir = staged.out().string();
  summary.frames = scenario.world.frames;
  nlohmann::json timings;
  // 1. Ground truth, frame by frame: analytic, or pixel-exact from the
  // renderer (frames cached on disk by pixel hash).
  auto t0 = Clock::now();
  FrameSourceOptions frame_options;
  frame_options.cache_dir = options.frame_cache_dir;
  // A rendered run's video reads its frames back (FrameReader): from the
  // frame cache, else from a spool in the run's folder removed once the video
  // is written. Kept in memory, 2000 frames of 640x480 took 1.8 GB (a scale
  // audit).
  const fs::path video_spool = partial / ".video-frames";
  if (options.video && scenario.observation.source == ObservationSource::kRendered) {
    frame_options.spool_dir = video_spool.string();
  }
  frame_options.show_progress = options.show_progress;
  frame_options.workers = options.threads;
  // renderer.write_frames / write_depth / write_instance_ids: the run's frames
  // go to frames/ as `hcpf render` writes them. A detection-level run renders
  // them for the user to see and keeps its analytic ground truth.
  const RendererConfig& images = scenario.renderer;
  const bool external = scenario.tracker_choice.external();
  // An external tracker is sent the path of each rendered frame, so a
  // rendered run with one writes frames/NNNNNN.png as write_frames does.
  const bool write_colour = images.write_frames || (external && scenario.observation.source ==
                                                                    ObservationSource::kRendered);
  const fs::path frames_dir = fs::absolute(partial / "frames");
  std::atomic<int64_t> saturated{0};  // depth pixels past the PNG's range
  if (write_colour || images.write_depth || images.write_instance_ids) {
    fs::create_directories(frames_dir, ec);
    if (ec) throw RunError(fmt::format("cannot create {}: {}", frames_dir.string(), ec.message()));
    frame_options.render = true;
    frame_options.analytic_truth = scenario.observation.source != ObservationSource::kRendered;
    // On the frames' worker threads (--threads): an external tracker, sent a
    // frame's path from on_frame, finds its file written.
    frame_options.on_frame_work = [write_colour, dir = frames_dir.string(),
                                   unit = images.depth_unit_mm,
                                   &saturated](const renderer::RenderedFrame& frame) {
      WriteFrameImages(frame, dir, write_colour, unit, &saturated);
    };
  }
  // The tracker. Filters are born from ground truth at each target's first
  // in-frame appearance when the scenario asks for it (the pipeline passes
  // the box; the tracker never sees ground truth otherwise); with a
  // model-based detector, in the frame its target's model is cut, from the
  // same box (detection_pass.h): before it nothing can support the filter.
  tracker::TrackerOptions tracker_options = scenario.tracker;
  tracker_options.threads = options.threads;
  double tracker_seconds = 0.0;
  std::unique_ptr<tracker::MultiTargetTracker> tracker;
  // Or an external program (docs/external-trackers.md): started now, sent
  // each frame's detections as the built-in tracker would see them. Its
  // tracks also become FrameReports (id and box only) for the overlay.
  std::unique_ptr<internal::ExternalTracker> external_tracker;
  std::vector<std::vector<internal::ExternalTrack>> external_tracks;
  if (external) {
    const auto started = Clock::now();
    const CameraSpec& camera = scenario.world.camera;
    external_tracker = std::make_unique<internal::ExternalTracker>(
        scenario.tracker_choice.command, scenario.tracker_choice.timeout_s,
        internal::ExternalHello{.scenario = scenario.name,
                                .frames = scenario.world.frames,
                                .fps = scenario.world.fps,
                                .width_px = camera.width_px,
                                .height_px = camera.height_px,
                                .hfov_deg = camera.hfov_deg,
                                .images = write_colour});
    tracker_seconds += Seconds(started);
  } else {
    tracker = tracker::MakeTracker(tracker_options, Rng(scenario.seeds.tracker));
  }
  if (scenario.observation.from_file()) {
    const DetectionFileOptions& file = scenario.observation.file;
    spdlog::info(
        "detections from {}: {} rows, {} of them left out (score below "
        "observation.file.min_score {:g})",
        file.path, file.rows, file.left_out, file.min_score);
    if (file.pixel_hash.empty()) {
      spdlog::info(
          "the detections are not checked to be made on this scenario's frames (name the "
          "rendering they were made on: observation.file.rendering)");
    } else {
      spdlog::info("the detections were made on this scenario's frames (pixel hash {})",
                   file.pixel_hash);
    }
  }
  std::set<int32_t> born;
  // The vision/ detector's pass over the frames (none with the oracle), made
  // below.
  std::unique_ptr<internal::DetectionPass> detection;
  std::vector<tracker::FrameReport> reports;
  reports.reserve(static_cast<size_t>(scenario.world.frames));
  // The hierarchical filter's scene half: the camera's motion from frame to
  // frame, estimated with the filters' previous boxes masked out, moves every
  // target particle before its own dynamics (tracker.camera_motion).
  internal::CameraMotionPass camera_motion(scenario);
  const auto step = [&](const FrameGroundTruth& gt, const Observation& observation,
                        const RgbImage* image) {
    const auto t = Clock::now();
    std::vector<BoxPx> exclude;
    if (!reports.empty()) {
      for (const tracker::FilterReport& r : reports.back().filters) exclude.push_back(r.box);
    }
    const std::optional<SimilarityMotion> motion = camera_motion.Step(gt, exclude, image);
    if (external_tracker) {
      const int frame = static_cast<int>(reports.size());
      const std::string path =
          write_colour ? fmt::format("{}/{:06d}.png", frames_dir.string(), frame + 1) : "";
      external_tracks.push_back(external_tracker->Step(frame, path, observation));
      tracker::FrameReport report;
      report.frame = frame;
      for (const internal::ExternalTrack& t : external_tracks.back()) {
        tracker::FilterReport r;
        r.id = TrackId{t.id};
        r.box = t.box;
        report.filters.push_back(r);
      }
      reports.push_back(std::move(report));
      tracker_seconds += Seconds(t);
      return;
    }
    if (tracker_options.init == tracker::InitMode::kGroundTruth) {
      for (const GroundTruthObject& o : gt.objects) {
        if (o.in_frame && (!detection || detection->Detects(o.id)) &&
            born.insert(Value(o.id)).second) {
          // tracker.management.birth_velocity: at rest, or the target's own.
          Eigen::Vector2d velocity = Eigen::Vector2d::Zero();
          if (tracker_options.management.birth_velocity == tracker::BirthVelocity::kGroundTruth) {
            velocity = internal::GroundTruthBirthVelocity(scenario, gt.frame, o.id);
          }
          tracker->BirthTrack(TrackId{Value(o.id)}, o.amodal_box, velocity);
        }
      }
    }
    reports.push_back(tracker->Step(observation, motion));
    tracker_seconds += Seconds(t);
  };

  // A vision/ detector sees each rendered frame as it is produced (the run
  // never holds every image), and the tracker steps right after it: with
  // `observation.search: window` the detector searches around each filter's
  // estimate of the previous frame.
  if (!scenario.observation.oracle()) {
    detection = std::make_unique<internal::DetectionPass>(scenario, options.frame_cache_dir);
    const bool windowed = scenario.observation.search == SearchMode::kWindow;
    frame_options.on_frame = [&, windowed](const renderer::RenderedFrame& frame) {
      std::vector<vision::SearchWindow> windows;
      if (windowed && !reports.empty()) {
        for (const tracker::FilterReport& r : reports.back().filters) {
          windows.push_back({.target = ObjectId{Value(r.id)}, .box = r.box});
        }
      }
      Observation& observation = detection->Add(frame, windows);
      step(frame.ground_truth, observation, &frame.rgb);
      DropMaps(observation);
    };
  }
  // Image evidence for the camera motion with oracle observations: the
  // tracker steps as each rendered frame arrives too (the scene half reads
  // the pixels of consecutive frames; the run never holds every image).
  std::vector<Observation> interleaved;
  const bool interleave_oracle = !detection && camera_motion.needs_images();
  if (interleave_oracle) {
    frame_options.on_frame = [&](const renderer::RenderedFrame& frame) {
      interleaved.push_back(SimulateObservation(frame.ground_truth, scenario.observation.simulated,
                                                scenario.seeds.observation));
      step(frame.ground_truth, interleaved.back(), &frame.rgb);
      DropMaps(interleaved.back());
    };
  }
  SceneFrames scene = ProduceFrames(scenario, frame_options);
  if (const std::string note = DepthSaturationNote(saturated, images.depth_unit_mm);
      !note.empty()) {
    spdlog::warn("run \"{}\": {}", scenario.name, note);
  }
  const std::vector<FrameGroundTruth>& truth = scene.truth;
  // A det.txt made on a named rendering: its frames' pixels against this
  // run's, frame by frame, where both have digests; else (a rendering from
  // before they were written) whether the GL renderers differ.
  std::optional<internal::PixelComparison> pixels;
  if (scenario.observation.from_file() && !scenario.observation.file.rendering.empty()) {
    const std::string& rendering = scenario.observation.file.rendering;
    pixels = internal::ComparePixels(rendering, scene);
    if (pixels && pixels->differing.empty()) {
      spdlog::info("the pixels of all {} frames are those of {}, which the det.txt was made on",
                   pixels->frames, rendering);
    } else if (const std::string renderers = internal::RendererDifference(rendering, scene);
               pixels) {
      std::vector<int> shown;  // 1-based, as det.txt numbers frames
      for (size_t i = 0; i < pixels->differing.size() && i < 8; ++i)
        shown.push_back(pixels->differing[i] + 1);
      spdlog::warn(
          "{} of {} frames differ in their pixels from those of {}, which the det.txt was made "
          "on (frame{} {}{}): the detections tracked and scored here were made on other "
          "pixels{}",
          pixels->differing.size(), pixels->frames, rendering, shown.size() > 1 ? "s" : "",
          fmt::join(shown, ", "), pixels->differing.size() > shown.size() ? ", …" : "",
          renderers.empty() ? std::string() : "; " + renderers);
    } else if (!renderers.empty()) {
      spdlog::warn("{}", renderers);
    }
  }
  timings["ground_truth_s"] = Seconds(t0) - tracker_seconds;

  // 2. Observations: the oracle (noisy ground truth), or the detector's
  // output gathered while the frames were produced (its time is in
  // ground_truth_s then).
  t0 = Clock::now();
  std::vector<Observation> observations;
  if (detection) {
    observations = detection->Take();
    // A target in view that never got a model was never detectable, and
    // under init: ground_truth never got a filter: say so, by name.
    std::set<int32_t> unmodelled;
    for (const FrameGroundTruth& gt : truth) {
      for (const GroundTruthObject& o : gt.objects) {
        if (o.in_frame && !detection->Detects(o.id)) unmodelled.insert(Value(o.id));
      }
    }
    const char* no_filter = tracker_options.init == tracker::InitMode::kGroundTruth && !external
                                ? " (and init: ground_truth gave it no filter)"
                                : "";
    for (int32_t id : unmodelled) {
      if (scenario.observation.from_file()) {
        // Only a labelled file knows targets one by one (Detects).
        spdlog::warn("target {}: no row of {} is labelled {}{}; its frames count as missed", id,
                     scenario.observation.file.path, id, no_filter);
      } else {
        spdlog::warn(
            "target {}: never wholly inside the image and at least {:g} % visible, so no model "
            "was cut and {} cannot detect it{}; its frames count as missed",
            id, 100.0 * internal::DetectionPass::kModelVisible, scenario.observation.DetectorName(),
            no_filter);
      }
    }
  } else if (interleave_oracle) {
    observations = std::move(interleaved);
  }
  double observation_seconds = Seconds(t0);

  // 3. Tracker, frame by frame (already done, with the detector, when the
  // observations come from one). The oracle's observations are made here one
  // frame at a time, each frame's map dropped once read (DropMaps): made for
  // every frame first, a long run's maps filled memory (4.8 GB at 4000).
  if (!detection && !interleave_oracle) {
    observations.reserve(truth.size());
    Progress progress("run", static_cast<int64_t>(truth.size()), options.show_progress);
    for (size_t f = 0; f < truth.size(); ++f) {
      const auto t = Clock::now();
      observations.push_back(SimulateObservation(truth[f], scenario.observation.simulated,
                                                 scenario.seeds.observation));
      observation_seconds += Seconds(t);
      step(truth[f], observations[f], nullptr);
      DropMaps(observations[f]);
      progress.Advance();
    }
    progress.Finish();
  }
  for (const Observation& o : observations)
    summary.detections += static_cast<int>(o.detections.size());
  timings["observations_s"] = observation_seconds;
  if (external_tracker) {
    const auto t = Clock::now();
    external_tracker->Finish();
    tracker_seconds += Seconds(t);
  }
  timings["tracker_s"] = tracker_seconds;
  if (const std::string note =
          ChargedResamplingNote(reports, tracker_options.particles, tracker_seconds);
      !note.empty()) {
    spdlog::warn("run \"{}\": {}", scenario.name, note);
  }

  // 4. MOT files, then the metrics computed from exactly those files, so
  // `hcpf score` on the outputs reproduces metrics.json.
  t0 = Clock::now();
  const std::string gt_text = metrics::FormatMotGroundTruth(GroundTruthRows(truth));
  const std::string tracks_text =
      metrics::FormatMotTracks(external ? ExternalTrackRows(external_tracks)
                                        : TrackRows(reports, tracker_options.particles));
  summary.gt_boxes = static_cast<int>(std::count(gt_text.begin(), gt_text.end(), '\n'));
  if (summary.gt_boxes == 0) {
    // A camera looking away or a target path outside the view validates (a
    // third bad-input audit): say that every score is of nothing.
    spdlog::warn(
        "run \"{}\": no target is ever in the image (0 ground-truth boxes), so the metrics "
        "score nothing and DA accuracy is absent; check camera.path, camera.fov_deg and the "
        "targets' paths",
        scenario.name);
  }
  const metrics::MotFile gt_file = metrics::ParseMotText(
      gt_text, "gt/gt.txt", metrics::MotFileKind::kGroundTruth, summary.frames);
  const metrics::MotFile tracks_file = metrics::ParseMotText(
      tracks_text, "tracks.txt", metrics::MotFileKind::kTracks, summary.frames);
  metrics::RunMetricsInput metrics_input;
  metrics_input.sequence = metrics::BuildSequence(gt_file, tracks_file, summary.frames,
                                                  metrics::Benchmark::kMot17, {}, scenario.name);
  // Filter-level metrics (DA accuracy, hijacks) need the particle filters'
  // identities: absent for an external tracker.
  if (!external) metrics_input.filters = FilterInputs(truth, reports, tracker_options);
  metrics_input.point_options = scenario.metrics.points;
  if (scene.rendered) {
    // Detection quality against the pixel-exact truth: each in-frame
    // target's box clipped to the image, with its visible fraction and its
    // truncation by the image border.
    std::vector<metrics::DetectionFrame> frames(truth.size());
    for (size_t f = 0; f < truth.size(); ++f) {
      frames[f].truth = metrics::DetectionTruthOf(truth[f]);
      frames[f].detections = observations[f].detections;
    }
    metrics_input.detections = std::move(frames);
  }
  metrics_input.filter_options = scenario.metrics.filters;
  metrics::RunMetrics scores = metrics::ComputeRunMetrics(metrics_input);
  scores.camera_motion =
      metrics::CameraMotionScore{.mode = std::string(NameOf(scenario.tracker.camera_motion)),
                                 .error = camera_motion.Summary(),
                                 .floor = camera_motion.FloorSummary()};
  timings["metrics_s"] = Seconds(t0);
  if (scores.detection) {
    // Inside a sweep only at debug: the run's metrics.json has it.
    spdlog::log(RunSummaryLevel(options.show_progress),
                "detection ({}): precision {:.3f}  recall {:.3f}  F1 {:.3f} (IoU >= 0.5)",
                scenario.observation.DetectorName(), scores.detection->iou.precision(),
                scores.detection->iou.recall(), scores.detection->iou.f1());
  }
  summary.mota = scores.mot.clear.mota;
  summary.idf1 = scores.mot.identity.idf1;
  summary.hota = scores.mot.hota.hota_mean;
  summary.da_accuracy = std::numeric_limits<double>::quiet_NaN();
  summary.hijack_rate = std::numeric_limits<double>::quiet_NaN();
  if (scores.filters) {
    summary.da_accuracy = scores.filters->da_accuracy;
    summary.hijack_rate = scores.filters->hijack_rate;
  }

  // 5. Files.
  t0 = Clock::now();
  WriteTextFile((partial / "scenario.resolved.yaml").string(), ToResolvedYaml(scenario));
  WriteTextFile((partial / "gt" / "gt.txt").string(), gt_text);
  metrics::WriteSeqInfo((partial / "seqinfo.ini").string(), SeqInfoOf(scenario));
  WriteTextFile((partial / "gt.json").string(),
                FormatGroundTruthJson(scenario, truth, scene.rendered));
  const std::string detections_text = FormatDetectionsMot(observations);
  WriteTextFile((partial / "detections.txt").string(), detections_text);
  if (scene.rendered) {
    // MOTChallenge's layout: det/det.txt beside gt/ and seqinfo.ini.
    fs::create_directories(partial / "det", ec);
    if (ec)
      throw RunError(fmt::format("cannot create {}: {}", (partial / "det").string(), ec.message()));
    WriteTextFile((partial / "det" / "det.txt").string(), detections_text);
  }
  WriteTextFile((partial / "tracks.txt").string(), tracks_text);
  if (!external) {
    WriteTextFile((partial / "filters.csv").string(), FormatFiltersCsv(reports, scores.filters));
  }
  WriteTextFile((partial / "metrics.json").string(), metrics::RunMetricsToJson(scores));
  WriteTextFile((partial / "camera_motion.csv").string(),
                FormatCameraMotionCsv(camera_motion.records()));
  std::optional<OverlayVideo> video;
  if (options.video) {
    // At detection level there are no pixels: the overlay is drawn on a
    // plain background.
    OverlayFrameSource frame_at;
    std::shared_ptr<FrameReader> reader;
    if (scene.rendered) {
      reader = std::make_shared<FrameReader>(scenario, scene);
      frame_at = [reader](int f) -> std::optional<RgbImage> { return reader->Read(f); };
    }
    video = WriteOverlayVideo((partial / "overlay.mp4").string(), scenario,
                              {.truth = truth,
                               .reports = reports,
                               .observations = observations,
                               .filters = scores.filters ? &*scores.filters : nullptr},
                              frame_at);
    if (reader) reader->Finish();
    fs::remove_all(video_spool, ec);
    if (ec) throw RunError(fmt::format("cannot remove {}: {}", video_spool.string(), ec.message()));
  }
  timings["write_s"] = Seconds(t0);
  summary.wall_time_s = Seconds(start);
  timings["total_s"] = summary.wall_time_s;
  nlohmann::json manifest = ManifestProvenance("hcpf-run/1", scenario, scene);
  manifest["observation_source"] =
      scenario.observation.source == ObservationSource::kRendered ? "rendered" : "simulated";
  // What hcpf validate, run and render warn of the scene, for the report.
  manifest["scene_notes"] = SceneNotes(scenario);
  if (scenario.observation.oracle()) {
    manifest["detector"] = "oracle (noisy ground truth)";
  } else {
    manifest["detector"] = scenario.observation.DetectorName();
    if (scenario.observation.from_file()) {
      const DetectionFileOptions& file = scenario.observation.file;
      manifest["detection_file"] = {
          {"path", file.path}, {"digest", file.digest}, {"min_score", file.min_score}};
      // The frames it was checked to be made on (observation.file.rendering
      // or pixel_hash), else null: nothing tied the file to this scene.
      manifest["detection_file"]["made_on_pixel_hash"] =
          file.pixel_hash.empty() ? nlohmann::json(nullptr) : nlohmann::json(file.pixel_hash);
      if (!file.rendering.empty()) manifest["detection_file"]["rendering"] = file.rendering;
      // The frames whose pixels differ from the rendering's (1-based), or
      // null when they could not be compared.
      if (pixels) {
        nlohmann::json differing = nlohmann::json::array();
        for (int f : pixels->differing) differing.push_back(f + 1);
        manifest["detection_file"]["frames_with_other_pixels"] = differing;
      } else {
        manifest["detection_file"]["frames_with_other_pixels"] = nullptr;
      }
    }
    if (detection && !detection->models().empty()) {
      manifest["target_models"] = "model from ground truth";
      nlohmann::json models = nlohmann::json::array();
      for (const vision::TargetModel& m : detection->models()) {
        models.push_back({{"target", Value(m.target)},
                          {"frame", m.frame},
                          {"box", {m.box.left, m.box.top, m.box.width, m.box.height}},
                          {"patch", {m.patch.width, m.patch.height}}});
      }
      manifest["target_model_sources"] = models;
    }
  }
  if (external) {
    nlohmann::json command = scenario.tracker_choice.command;
    if (command[0].get<std::string>().find('/') != std::string::npos) {
      command[0] = PortableModelPath(command[0].get<std::string>());
    }
    manifest["tracker"] = {{"type", "external"},
                           {"command", command},
                           {"protocol", internal::kExternalProtocolVersion},
                           {"name", external_tracker->name()}};
  } else {
    manifest["tracker"] = {{"type", "particle_filter"}};
    if (metrics_input.filters && metrics_input.filters->reacquired) {
      // Each filter found again from its target's own detections: the frame
      // (from 0, as target_model_sources) at whose end it was re-seeded.
      nlohmann::json reacquired = nlohmann::json::array();
      for (const auto& [frame, filter] : *metrics_input.filters->reacquired) {
        reacquired.push_back({{"frame", frame}, {"filter", filter}});
      }
      manifest["tracker"]["reacquired"] = std::move(reacquired);
    }
  }
  manifest["ground_truth"] = scene.rendered ? "rendered (pixel-exact)" : "analytic";
  if (detection) manifest["detections_from_cache"] = detection->frames_from_cache();
  manifest["frames"] = scenario.world.frames;
  if (video) {
    // What the report needs to show the video (docs/outputs.md).
    manifest["video"] = {{"file", "overlay.mp4"},   {"fourcc", video->fourcc},
                         {"codec", video->codec},   {"plays_in_browsers", video->plays_in_browsers},
                         {"frames", video->frames}, {"fps", video->fps},
                         {"width", video->width},   {"height", video->height}};
  }
  manifest["gt_boxes"] = summary.gt_boxes;
  manifest["detections"] = summary.detections;
  manifest["timings"] = timings;
  manifest["nondeterministic_fields"] = {"timings",           "frames_rendered",
                                         "frames_from_cache", "detections_from_cache",
                                         "gl_renderer",       "frame_cache_renderers"};
  // Every file written above, by its size: a run folder later found with one
  // missing or of another size is not reused or merged (RunFolderIntact).
  manifest["files"] = FileSizesOf(partial);
  // Written last: a folder with a manifest is a finished run.
  WriteTextFile((partial / "manifest.json").string(), manifest.dump(2) + "\n");
  staged.Publish();
  return summary;
}

}  // namespace hcpf::scenarios
