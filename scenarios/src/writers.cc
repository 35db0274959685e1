#include "writers.h"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "hcpf/core/error.h"
#include "hcpf/core/ground_truth_json.h"
#include "hcpf/scenarios/version.h"

namespace hcpf::scenarios {

std::vector<metrics::MotRow> GroundTruthRows(const std::vector<FrameGroundTruth>& frames) {
  std::vector<metrics::MotRow> rows;
  for (const FrameGroundTruth& f : frames) {
    for (const GroundTruthObject& o : f.objects) {
      if (!o.in_frame) continue;
      metrics::MotRow row;
      row.frame = f.frame + 1;
      row.id = Value(o.id);
      row.box = metrics::PxToMotBox(o.amodal_box);
      row.conf = 1.0;
      row.col8 = 1.0;
      row.col9 = o.visible_fraction;
      rows.push_back(row);
    }
  }
  return rows;
}

std::vector<metrics::MotRow> TrackRows(const std::vector<tracker::FrameReport>& reports,
                                       int particles) {
  std::vector<metrics::MotRow> rows;
  for (const tracker::FrameReport& report : reports) {
    for (const TrackEstimate& e : tracker::ToTrackEstimates(report, particles)) {
      metrics::MotRow row;
      row.frame = report.frame + 1;
      row.id = Value(e.id);
      row.box = metrics::PxToMotBox(e.box);
      row.conf = e.confidence;
      rows.push_back(row);
    }
  }
  return rows;
}

std::vector<metrics::MotRow> ExternalTrackRows(
    const std::vector<std::vector<internal::ExternalTrack>>& frames) {
  std::vector<metrics::MotRow> rows;
  for (size_t f = 0; f < frames.size(); ++f) {
    for (const internal::ExternalTrack& t : frames[f]) {
      metrics::MotRow row;
      row.frame = static_cast<int>(f) + 1;
      row.id = t.id;
      row.box = metrics::PxToMotBox(t.box);
      row.conf = t.score;
      rows.push_back(row);
    }
  }
  return rows;
}

metrics::FilterSequence FilterInputs(const std::vector<FrameGroundTruth>& truth,
                                     const std::vector<tracker::FrameReport>& reports,
                                     const tracker::TrackerOptions& tracker) {
  metrics::FilterSequence seq;
  if (tracker.management.reacquire != tracker::ReacquireMode::kNone) seq.reacquired.emplace();
  std::set<int64_t> filter_ids;
  for (size_t f = 0; f < truth.size(); ++f) {
    metrics::FilterFrame frame;
    for (const GroundTruthObject& o : truth[f].objects) {
      if (!o.in_frame) continue;
      frame.targets.push_back({Value(o.id), o.amodal_box.centre_x(), o.amodal_box.centre_y(),
                               o.amodal_box.width, o.amodal_box.height, o.visible_fraction});
    }
    for (const tracker::FilterReport& r : reports[f].filters) {
      metrics::FilterEstimate e;
      e.id = Value(r.id);
      e.box = r.box;
      if (!r.particles.empty()) {
        metrics::ParticleCloud cloud;
        for (const tracker::ParticlePoint& p : r.particles) {
          cloud.x.push_back(p.x_px);
          cloud.y.push_back(p.y_px);
          cloud.weight.push_back(p.weight);
        }
        e.particles = std::move(cloud);
      }
      filter_ids.insert(e.id);
      frame.filters.push_back(std::move(e));
    }
    for (const TrackId id : reports[f].reacquired) {
      seq.reacquired->emplace_back(static_cast<int>(f), Value(id));
    }
    seq.frames.push_back(std::move(frame));
  }
  if (tracker.init == tracker::InitMode::kGroundTruth) {
    std::vector<std::pair<int64_t, int64_t>> birth;
    for (int64_t id : filter_ids) birth.emplace_back(id, id);
    seq.birth_target = std::move(birth);
  }
  return seq;
}

std::string FormatCameraMotionCsv(const std::vector<internal::CameraMotionRecord>& records) {
  std::string csv = "frame,tx_px,ty_px,log_scale,rotation_rad,error_px,ess,floor_px\n";
  for (const internal::CameraMotionRecord& r : records) {
    // Frames count from 1, as in gt/gt.txt, tracks.txt and filters.csv: the
    // first row is frame 2 (the motion from frame 1 to 2). It counted from 0
    // before 2026-12-05, one off from every other file (docs audit).
    csv += fmt::format("{},{},{},{},{},{},{},{}\n", r.frame + 1, FormatNumber(r.motion.tx_px),
                       FormatNumber(r.motion.ty_px), FormatNumber(r.motion.log_scale),
                       FormatNumber(r.motion.rotation_rad), FormatNumber(r.error_px),
                       r.ess < 0 ? "" : FormatNumber(r.ess), FormatNumber(r.floor_px));
  }
  return csv;
}

std::string FormatFiltersCsv(const std::vector<tracker::FrameReport>& reports,
                             const std::optional<metrics::FilterMetrics>& filter_metrics) {
  std::string out = "frame,filter,cx,cy,w,h,spread_px,ess,rejections,coasting,degenerate,state\n";
  size_t record = 0;
  for (const tracker::FrameReport& report : reports) {
    for (const tracker::FilterReport& r : report.filters) {
      std::string state = "-";
      // Records are frame-major with filters in report order (FilterInputs).
      if (filter_metrics && record < filter_metrics->records.size()) {
        state = metrics::FilterStateName(filter_metrics->records[record].state);
      }
      ++record;
      out += fmt::format("{},{},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{:.2f},{},{},{},{}\n",
                         report.frame + 1, Value(r.id), r.box.centre_x(), r.box.centre_y(),
                         r.box.width, r.box.height, std::sqrt(std::max(0.0, r.cov.trace())), r.ess,
                         r.rejections, r.coasting ? 1 : 0, r.recovered_degenerate ? 1 : 0, state);
    }
  }
  return out;
}

std::string FormatDetectionsMot(const std::vector<Observation>& observations) {
  std::string out;
  for (const Observation& obs : observations) {
    for (const Detection& d : obs.detections) {
      // Column 2: the target a target-specific detector found (what
      // observation.file.labels reads back), else MOTChallenge's -1.
      out += fmt::format("{},{},{:.3f},{:.3f},{:.3f},{:.3f},{:.4f},-1,-1,-1\n", obs.frame + 1,
                         d.target ? Value(*d.target) : -1, d.box.left + 1.0, d.box.top + 1.0,
                         d.box.width, d.box.height, d.score);
    }
  }
  return out;
}

metrics::SeqInfo SeqInfoOf(const Scenario& s) {
  metrics::SeqInfo info;
  info.name = s.name;
  info.im_dir = "frames";
  info.frame_rate = s.world.fps;
  info.seq_length = s.world.frames;
  info.im_width = s.world.camera.width_px;
  info.im_height = s.world.camera.height_px;
  info.im_ext = ".png";
  return info;
}

std::string FormatGroundTruthJson(const Scenario& s, const std::vector<FrameGroundTruth>& frames,
                                  bool pixel_exact) {
  nlohmann::json root;
  root["format"] = "hcpf-gt/1";
  root["scenario"] = s.name;
  root["source"] = pixel_exact ? "rendered" : "analytic";
  root["conventions"] = {
      {"frame", "0-based here; MOT files are 1-based"},
      {"boxes", "[left, top, width, height] in pixels, pixel (0,0) covers [0,1)x[0,1)"},
      {"world", "x east, y north, z up, metres"},
      {"camera", "OpenCV: x right, y down, z forward; world_from_camera columns = camera axes"},
      {"image_from_ground", "homography of the plane z = 0 to homogeneous pixels"},
      {"visible_fraction",
       pixel_exact ? "pixel-exact: pixels_visible / pixels_total from the renderer's instance-id "
                     "pass (not MOTChallenge's box-overlap heuristic); gt.txt's visibility column"
                   : "analytic estimate: unblocked / target rays of a 24x24 lattice over the "
                     "amodal box (docs/conventions.md); gt.txt's visibility column"},
  };
  nlohmann::json list = nlohmann::json::array();
  for (const FrameGroundTruth& f : frames) list.push_back(GroundTruthToJson(f));
  root["frames"] = std::move(list);
  return root.dump(1) + "\n";
}

nlohmann::json ManifestProvenance(const std::string& format, const Scenario& scenario,
                                  const SceneFrames& scene) {
  nlohmann::json m;
  m["format"] = format;
  m["hcpf_version"] = ProjectVersion();
  m["git_revision"] = GitRevision();
  m["scenario"] = scenario.name;
  m["config_hash"] = ConfigHash(scenario);
  m["seed"] = scenario.seed;
  m["seeds"] = {{"world", scenario.seeds.world},
                {"observation", scenario.seeds.observation},
                {"tracker", scenario.seeds.tracker},
                {"renderer", scenario.seeds.renderer}};
  m["libraries"] = LibraryVersions();
  if (const std::optional<renderer::GlInfo>& gl = scene.gl) {
    m["gl_renderer"] = {{"backend", gl->backend},
                        {"platform", gl->platform},
                        {"vendor", gl->vendor},
                        {"renderer", gl->renderer},
                        {"version", gl->version}};
  } else {
    m["gl_renderer"] = nullptr;
  }
  // What the frames show, whichever machine rendered them: a det.txt made on
  // them names this folder (observation.file.rendering) or this hash.
  if (!scene.pixel_hash.empty()) m["pixel_hash"] = scene.pixel_hash;
  m["frames_rendered"] = scene.frames_rendered;
  m["frames_from_cache"] = scene.frames_from_cache;
  // The GL renderers that stored frames in the cache folder the frames came
  // from (FrameCache::NoteRenderer); gl_renderer is this process's, if any.
  if (scene.frames_from_cache > 0) m["frame_cache_renderers"] = scene.cache_renderers;
  // The pixels of every frame, in order (SceneFrames::frame_digests).
  if (!scene.frame_digests.empty()) m["frame_digests"] = scene.frame_digests;
  return m;
}

}  // namespace hcpf::scenarios
