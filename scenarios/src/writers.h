#pragma once
// Writers of a run's files. Numbers are formatted with fixed precision so the
// same inputs give byte-identical files.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "camera_motion_pass.h"
#include "external_tracker.h"
#include "hcpf/core/ground_truth.h"
#include "hcpf/core/text_file.h"
#include "hcpf/core/types.h"
#include "hcpf/metrics/filter_metrics.h"
#include "hcpf/metrics/mot_io.h"
#include "hcpf/scenarios/frames.h"
#include "hcpf/scenarios/scenario.h"
#include "hcpf/tracker/tracker.h"

namespace hcpf::scenarios {

// MOT17 ground-truth rows (written by metrics::FormatMotGroundTruth): one per
// in-frame target per frame, 1-based frames and coordinates, consider 1,
// class 1 (evaluated), visibility = visible fraction. Targets entirely outside
// the image are not listed.
std::vector<metrics::MotRow> GroundTruthRows(const std::vector<FrameGroundTruth>& frames);
// Tracker output rows (10 columns): every filter reported in each frame, its
// estimate box, confidence = ESS / N.
std::vector<metrics::MotRow> TrackRows(const std::vector<tracker::FrameReport>& reports,
                                       int particles);
// The same rows of an external tracker's replies, one list per frame:
// confidence = the track's score.
std::vector<metrics::MotRow> ExternalTrackRows(
    const std::vector<std::vector<internal::ExternalTrack>>& frames);
// Filter-level metric inputs: in-frame targets and the filters' estimates per
// frame (with their particle clouds when kept); filters born from ground truth
// map to the target of the same id; under management.reacquire the filters
// re-acquired (none otherwise: the metric is then absent, not 0).
metrics::FilterSequence FilterInputs(const std::vector<FrameGroundTruth>& truth,
                                     const std::vector<tracker::FrameReport>& reports,
                                     const tracker::TrackerOptions& tracker);
// filters.csv: frame,filter,cx,cy,w,h,spread_px,ess,rejections,coasting,degenerate,state.
std::string FormatFiltersCsv(const std::vector<tracker::FrameReport>& reports,
                             const std::optional<metrics::FilterMetrics>& filter_metrics);
// camera_motion.csv: frame,tx_px,ty_px,log_scale,rotation_rad,error_px,ess
// (ess empty without a scene filter).
std::string FormatCameraMotionCsv(const std::vector<internal::CameraMotionRecord>& records);
// MOT detections: frame,target,left,top,w,h,score,-1,-1,-1 (target: the
// detection's Detection::target, -1 when it has none).
std::string FormatDetectionsMot(const std::vector<Observation>& observations);
// seqinfo.ini for TrackEval's MOTChallenge loader.
metrics::SeqInfo SeqInfoOf(const Scenario& scenario);
// gt.json: every field of every frame's ground truth (see docs/outputs.md).
// `pixel_exact`: the truth came from the renderer's pixel counts.
std::string FormatGroundTruthJson(const Scenario& scenario,
                                  const std::vector<FrameGroundTruth>& frames, bool pixel_exact);

// The provenance part of a manifest.json (format, version, git revision,
// scenario, config hash, seeds, library versions) and where the frames came
// from: pixel_hash when frames were rendered, this process's GL renderer or
// null, frames_rendered, frames_from_cache and, with frames from the cache,
// frame_cache_renderers.
nlohmann::json ManifestProvenance(const std::string& format, const Scenario& scenario,
                                  const SceneFrames& scene);

}  // namespace hcpf::scenarios
