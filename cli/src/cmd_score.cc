// hcpf score GT HYP [--seqinfo FILE] [--benchmark MOT15|MOT17|auto] [--json FILE] [--events FILE]
// hcpf score --trackeval-root DIR [--benchmark ...] [--json FILE]
// hcpf score --detections GT.json DET.txt [--min-visible V] [--json FILE]
//
// Scores MOTChallenge files with CLEAR MOT, Identity and HOTA (TrackEval's
// rules, see docs/metrics.md): a table on stdout, every value with --json.
// With --detections, a detector's output against the pixel-exact truth of a
// gt.json instead (docs/vision.md, "Scoring a detector of your own").

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>
#include <vector>

#include "command.h"
#include "hcpf/core/error.h"
#include "hcpf/core/text_file.h"
#include "hcpf/metrics/detection_quality.h"
#include "hcpf/metrics/detection_truth.h"
#include "hcpf/metrics/mot_io.h"
#include "hcpf/metrics/report.h"

namespace hcpf::cli {

namespace fs = std::filesystem;

namespace {

// Where the table goes: standard output, or standard error when --json or
// --events writes to standard output (`--json /dev/stdout | jq`), which then
// carries that file alone.
std::ostream& TableStream(const std::string& json_path, const std::string& events_path = "") {
  return IsStandardOutput(json_path) || IsStandardOutput(events_path) ? std::cerr : std::cout;
}

// hcpf score --detections GT.json DET.txt: the detections of a detector (a
// MOTChallenge det.txt: frame, id, left, top, width, height, score; 1-based
// frames and pixels; ids read as targets with `labels`, else ignored) scored
// as `hcpf run` scores its own.
// Rows scoring below `min_score` (nullopt: none) are left out, as
// observation.file.min_score leaves them out of a run.
int ScoreDetectionFiles(const std::string& gt_path, const std::string& det_path, double min_visible,
                        std::optional<double> min_score, bool labels,
                        const std::string& json_path) {
  // The folder of `hcpf render` or `hcpf run` stands for its gt.json.
  std::error_code ec;
  const std::string gt_file =
      fs::is_directory(gt_path, ec) && fs::exists(fs::path(gt_path) / "gt.json", ec)
          ? (fs::path(gt_path) / "gt.json").string()
          : gt_path;
  const metrics::GroundTruthFile gt = metrics::ReadGroundTruthJson(gt_file);
  const int frame_count = static_cast<int>(gt.frames.size());
  const metrics::MotFile det =
      metrics::ReadMotFile(det_path, metrics::MotFileKind::kDetections, frame_count);
  std::vector<metrics::DetectionFrame> frames(gt.frames.size());
  for (size_t f = 0; f < frames.size(); ++f)
    frames[f].truth = metrics::DetectionTruthOf(gt.frames[f]);
  std::vector<metrics::DetectionFileRow> rows = metrics::DetectionRowsOf(det);
  if (labels) {
    // A labelled detection may only match its target (ScoreDetections), as
    // in a run with observation.file.labels: true.
    std::set<int64_t> targets;
    for (const FrameGroundTruth& frame : gt.frames) {
      for (const GroundTruthObject& o : frame.objects) targets.insert(Value(o.id));
    }
    metrics::ReadDetectionLabels(det, targets, "--labels", &rows);
  }
  int left_out = 0;
  for (const metrics::DetectionFileRow& row : rows) {
    if (min_score && row.detection.score < *min_score) {
      ++left_out;
      continue;
    }
    frames[static_cast<size_t>(row.frame)].detections.push_back(row.detection);
  }
  if (gt.source != "rendered") {
    spdlog::warn(
        "{}: the truth is analytic (a detection-level run: visible fractions estimated, no "
        "pixels rendered); render the scene (hcpf render) for pixel-exact truth",
        gt_file);
  }
  const metrics::DetectionQuality quality =
      metrics::ScoreDetections(frames, {.iou_threshold = 0.5, .min_visible = min_visible});
  const std::string kept = min_score ? fmt::format("{} detections, {} scoring below {:g} left out",
                                                   det.rows.size(), left_out, *min_score)
                                     : fmt::format("{} detections", det.rows.size());
  TableStream({json_path}) << fmt::format(
                                  "{} ({}) against {} ({} frames, {} truth; targets visible less "
                                  "than {:g} don't care)\n",
                                  det_path, kept, gt_file, frame_count, gt.source, min_visible)
                           << metrics::FormatDetectionTable(quality);
  if (!json_path.empty()) WriteTextFile(json_path, metrics::DetectionQualityToJson(quality));
  return 0;
}

// Bad input: `option` was given in a mode that does not read it.
[[noreturn]] void RefuseOption(const std::string& option, const std::string& mode,
                               const std::string& belongs_to, const std::string& found) {
  throw InputError(SourceLocation{"command line", 0, 0, option},
                   fmt::format("no {} with {} (it goes with {})", option, mode, belongs_to), found);
}

}  // namespace

Command AddScoreCommand(CLI::App& parent) {
  struct Options {
    std::string gt;
    std::string hyp;
    std::string seqinfo;
    std::string benchmark = "auto";
    std::string json;
    std::string events;
    std::string trackeval_root;
    bool detections = false;
    double min_visible = metrics::DetectionQualityOptions{}.min_visible;
    double min_score = 0.0;
    bool labels = false;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand(
      "score",
      "Score tracker output against ground truth (MOTChallenge files): HOTA, CLEAR MOT, IDF1; "
      "or, with --detections, a detector's output against a gt.json");
  app->add_option("gt", options->gt,
                  "Ground-truth file (MOT15 6/10 or MOT16/17 9 columns; a gt.json with "
                  "--detections)");
  app->add_option("hyp", options->hyp,
                  "Tracker output (MOT 10 columns; detections, det.txt, with --detections)");
  app->add_option("--seqinfo", options->seqinfo,
                  "seqinfo.ini giving seqLength (default: next to GT or in its parent folder)");
  app->add_option(
         "--benchmark", options->benchmark,
         "Preprocessing rules: MOT15, MOT17 (also MOT16/MOT20) or auto (9-column gt = MOT17)")
      ->check(CLI::IsMember({"MOT15", "MOT16", "MOT17", "MOT20", "auto"}))
      ->capture_default_str();
  app->add_option("--json", options->json,
                  "Write every metric value to this JSON file (- for standard output)")
      ->transform(DashIsStandardOutput);
  app->add_option("--events", options->events,
                  "Write the per-frame event log (MATCH, SWITCH, ...) as JSON lines to this file "
                  "(- for standard output)")
      ->transform(DashIsStandardOutput);
  app->add_option("--trackeval-root", options->trackeval_root,
                  "Score a TrackEval folder (gt/mot_challenge/<bench>/<seq>, "
                  "trackers/mot_challenge/<bench>/<tracker>/data; the sequences of "
                  "gt/mot_challenge/seqmaps/<bench>.txt when there is one) instead of GT HYP");
  app->add_flag("--detections", options->detections,
                "Score a detector instead: GT is a gt.json (or the folder of hcpf render or hcpf "
                "run holding one), HYP its "
                "detections in MOTChallenge det.txt format (frame,id,left,top,w,h,score); "
                "precision, recall, F1 and AP50 by target size, visibility and truncation");
  app->add_option("--min-visible", options->min_visible,
                  "With --detections: targets visible less than this are don't care (not missed; "
                  "a detection on one is neither true nor false)")
      ->check(CLI::Range(0.0, 1.0))
      ->capture_default_str();
  app->add_option("--min-score", options->min_score,
                  "With --detections: detections scoring below this are left out, as "
                  "observation.file.min_score leaves them out of a run (default: none)")
      ->check(CLI::Range(-1e9, 1e9));
  app->add_flag("--labels", options->labels,
                "With --detections: column 2 names the target each detection is of (-1: none), "
                "as observation.file.labels reads it, and a detection may only match its target");
  return {app, [options, app]() -> int {
            using namespace hcpf::metrics;
            const Benchmark benchmark = *ParseBenchmark(options->benchmark);
            // What only detection scoring takes: each option and what was given.
            for (const auto& [option, found] :
                 {std::pair<const char*, std::string>{"--min-visible",
                                                      fmt::format("{}", options->min_visible)},
                  {"--min-score", fmt::format("{}", options->min_score)},
                  {"--labels", "--labels given"}}) {
              if (!options->detections && app->count(option) > 0) {
                throw InputError(SourceLocation{"command line", 0, 0, option},
                                 std::string(option) + " only with --detections", found);
              }
            }
            if (options->detections) {
              // What only tracker scoring takes (ignored here otherwise).
              for (const auto& [given, option] :
                   {std::pair{!options->trackeval_root.empty(), "--trackeval-root"},
                    {!options->events.empty(), "--events"},
                    {!options->seqinfo.empty(), "--seqinfo"},
                    {app->count("--benchmark") > 0, "--benchmark"}}) {
                if (given) {
                  RefuseOption(option, "--detections", "tracker scoring",
                               std::string(option) + " given");
                }
              }
              if (options->gt.empty() || options->hyp.empty()) {
                throw InputError(SourceLocation{{}, 0, 0, "score --detections"},
                                 "a gt.json and a detections file (MOTChallenge det.txt)",
                                 "missing arguments");
              }
              if (!options->json.empty()) {
                CheckFilesToWrite({{options->json, "--json"}},
                                  {{options->gt, "the ground truth (GT)"},
                                   {options->hyp, "the detections (HYP)"}},
                                  {}, "score", "nothing was written");
              }
              return ScoreDetectionFiles(
                  options->gt, options->hyp, options->min_visible,
                  app->count("--min-score") > 0 ? std::optional(options->min_score) : std::nullopt,
                  options->labels, options->json);
            }
            if (!options->trackeval_root.empty()) {
              if (!options->gt.empty() || !options->hyp.empty()) {
                throw InputError(SourceLocation{{}, 0, 0, "score"},
                                 "either GT HYP or --trackeval-root DIR", "both");
              }
              // What only GT HYP takes (a third bad-input audit: ignored).
              for (const auto& [value, option] :
                   {std::pair{&options->events, "--events"}, {&options->seqinfo, "--seqinfo"}}) {
                if (!value->empty()) RefuseOption(option, "--trackeval-root", "GT HYP", *value);
              }
              // --json checked before anything is read (a third bad-input
              // audit: a folder or a missing parent failed after the table).
              if (!options->json.empty()) {
                const fs::path root(options->trackeval_root);
                CheckFilesToWrite({{options->json, "--json"}}, {}, {root / "gt", root / "trackers"},
                                  "score", "nothing was written");
              }
              const auto results = ScoreTrackEvalRoot(options->trackeval_root, benchmark);
              std::string json = "[\n";
              for (size_t i = 0; i < results.size(); ++i) {
                const TrackEvalResult& r = results[i];
                std::vector<MotSummary> rows = r.sequences;
                rows.push_back(r.combined);
                TableStream({options->json}) << r.bench << " / " << r.tracker << "\n"
                                             << FormatMotTable(rows) << "\n";
                // Once, under the last table.
                if (i + 1 == results.size()) TableStream({options->json}) << MotTablePercentNote();
                json += "{\"bench\":" + nlohmann::json(r.bench).dump() +
                        ",\"tracker\":" + nlohmann::json(r.tracker).dump() +
                        ",\"metrics\":" + MotSummariesToJson(r.sequences, &r.combined) + "}" +
                        (i + 1 < results.size() ? ",\n" : "\n");
              }
              json += "]\n";
              if (results.empty())
                spdlog::warn("{}: no tracker folders found", options->trackeval_root);
              if (!options->json.empty()) WriteTextFile(options->json, json);
              return 0;
            }
            if (options->gt.empty() || options->hyp.empty()) {
              throw InputError(SourceLocation{{}, 0, 0, "score"},
                               "GT and HYP files (or --trackeval-root DIR)", "missing arguments");
            }
            // --json and --events checked before anything is read (a third
            // bad-input audit: --json naming the tracker file replaced it,
            // exit 0; both naming one file lost the JSON).
            std::vector<FileToWrite> writes;
            if (!options->json.empty()) writes.push_back({options->json, "--json"});
            if (!options->events.empty()) writes.push_back({options->events, "--events"});
            CheckFilesToWrite(writes,
                              {{options->gt, "the ground truth (GT)"},
                               {options->hyp, "the tracker output (HYP)"},
                               {options->seqinfo, "the --seqinfo file"}},
                              {}, "score", "nothing was written");
            ScoreFilesOptions o;
            o.gt_path = options->gt;
            o.hyp_path = options->hyp;
            o.seqinfo_path = options->seqinfo;
            o.benchmark = benchmark;
            o.keep_events = !options->events.empty();
            const ScoredSequence s = ScoreFiles(o);
            TableStream({options->json, options->events})
                << FormatMotTable({&s.summary, 1}) << MotTablePercentNote();
            if (!options->json.empty())
              WriteTextFile(options->json, MotSummariesToJson({&s.summary, 1}, nullptr));
            if (!options->events.empty()) {
              std::ostringstream events;
              WriteEventsJsonLines(events, s.events);
              WriteTextFile(options->events, events.str());
            }
            return 0;
          }};
}

}  // namespace hcpf::cli
