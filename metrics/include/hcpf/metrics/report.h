#pragma once
// Scoring entry points used by `hcpf score` and by the `hcpf run` pipeline:
// files -> sequences -> every metric -> a readable table and JSON.
//
//   ScoredSequence s = ScoreFiles({.gt_path = "gt.txt", .hyp_path = "tracks.txt"});
//   std::string json = MotSummariesToJson({s.summary}, nullptr);
//
//   RunMetrics m = ComputeRunMetrics({.sequence = seq, .filters = filter_seq});
//   std::string json = RunMetricsToJson(m);   // metrics.json of one run
//
// JSON stays out of this header (strings in, strings out).

#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hcpf/metrics/camera_motion.h"
#include "hcpf/metrics/detection_quality.h"
#include "hcpf/metrics/filter_metrics.h"
#include "hcpf/metrics/mot_io.h"
#include "hcpf/metrics/mot_metrics.h"
#include "hcpf/metrics/point_metrics.h"

namespace hcpf::metrics {

struct ScoreFilesOptions {
  std::string gt_path;
  std::string hyp_path;
  // seqinfo.ini; when empty: <gt dir>/seqinfo.ini, then <gt dir>/../seqinfo.ini, else the
  // sequence length is the largest frame in either file (logged as a warning).
  std::string seqinfo_path;
  Benchmark benchmark = Benchmark::kAuto;
  PreprocessOptions preprocess;
  std::string name;  // defaults to the seqinfo name, else the gt file's stem
  bool keep_events = false;
};

struct ScoredSequence {
  MotSummary summary;
  std::vector<MotEvent> events;  // filled when keep_events
  Benchmark benchmark = Benchmark::kMot15;
  int seq_length = 0;
};

// Reads, preprocesses and scores one gt/hyp pair. Bad files throw hcpf::InputError.
ScoredSequence ScoreFiles(const ScoreFilesOptions& options);

// TrackEval's folder layout under `root`:
//   gt/mot_challenge/<bench>/<seq>/gt/gt.txt and <seq>/seqinfo.ini
//   trackers/mot_challenge/<bench>/<tracker>/data/<seq>.txt
// The sequences are those of gt/mot_challenge/seqmaps/<bench>.txt in its
// order, as TrackEval reads a seqmap; with no seqmap, every folder of <bench>
// (sorted by name). One result per (bench, tracker): every sequence plus
// COMBINED. A benchmark without a trackers folder is skipped with a warning;
// one with no sequence is an InputError.
// The benchmark rules come from <bench>'s prefix (MOT15 / MOT16, MOT17, MOT20)
// unless `benchmark` is not kAuto.
struct TrackEvalResult {
  std::string bench;
  std::string tracker;
  std::vector<MotSummary> sequences;
  MotSummary combined;
};
std::vector<TrackEvalResult> ScoreTrackEvalRoot(const std::string& root,
                                                Benchmark benchmark = Benchmark::kAuto);

// A fixed-width table, one row per summary (ratios in percent, as MOTChallenge shows them).
std::string FormatMotTable(std::span<const MotSummary> rows);

// The line said under FormatMotTable's table(s), once: its ratios are in
// percent, where metrics.json and the reports hold fractions.
std::string MotTablePercentNote();

// {"sequences": {name: {every ToNamedMetrics value}}, "combined": {...}} (combined omitted
// when null). Non-finite numbers are written as the strings "nan", "inf", "-inf".
std::string MotSummariesToJson(std::span<const MotSummary> sequences, const MotSummary* combined);

// Everything one run of the pipeline scores.
struct RunMetricsInput {
  Sequence sequence;                      // gt and tracker boxes per frame
  std::optional<FilterSequence> filters;  // filter-level inputs, when available
  PointMetricsOptions point_options;      // OSPA / GOSPA
  FilterMetricsOptions filter_options;
  // Per-frame truth and detections, for detection quality (runs with
  // pixel-exact or analytic truth; absent for `hcpf score`).
  std::optional<std::vector<DetectionFrame>> detections;
};
// The camera-motion error of a run (metrics/camera_motion.h): the mode that
// produced the motions ("none", "scene_filter", "oracle") and the summary of
// their per-frame corner displacement against the true motion.
struct CameraMotionScore {
  std::string mode;
  CameraMotionErrorSummary error;
  // Per frame, the error of CornerOptimalSimilarity: what any similarity
  // estimate could reach on these frames (the same for every mode).
  CameraMotionErrorSummary floor;
};
struct RunMetrics {
  MotSummary mot;
  PointMetrics points;
  std::optional<FilterMetrics> filters;
  std::optional<DetectionQuality> detection;
  std::optional<CameraMotionScore> camera_motion;  // set by the run pipeline
};
RunMetrics ComputeRunMetrics(const RunMetricsInput& input);
// {"mot": {...}, "ospa": {...}, "gospa": {...}, "filters": {...}, "detection": {...}}
// with per-frame arrays.
std::string RunMetricsToJson(const RunMetrics& metrics);

// metrics.json's "detection" object on its own (hcpf score --detections --json).
std::string DetectionQualityToJson(const DetectionQuality& quality);
// Detection quality as a fixed-width table: found / missed / false,
// precision, recall (IoU rule) and the centre rule's recall, overall and by
// size, visibility, truncation and target; then F1, AP50 and the best F1.
std::string FormatDetectionTable(const DetectionQuality& quality);

}  // namespace hcpf::metrics
