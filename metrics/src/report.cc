#include "hcpf/metrics/report.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <vector>

#include "hcpf/core/error.h"
#include "hcpf/core/text_file.h"

namespace hcpf::metrics {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json Number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return v;
}

json SummaryJson(const MotSummary& s) {
  json j = json::object();
  const NamedMetrics named = ToNamedMetrics(s);
  for (const auto& [name, value] : named.scalars) {
    j[name] = IsCountMetric(name) ? json(static_cast<int64_t>(value)) : Number(value);
  }
  for (const auto& [name, values] : named.arrays) {
    json a = json::array();
    for (double v : values)
      a.push_back(IsCountMetric(name) ? json(static_cast<int64_t>(v)) : Number(v));
    j[name] = a;
  }
  return j;
}

int MaxFrame(const MotFile& f) {
  int m = 0;
  for (const MotRow& r : f.rows) m = std::max(m, r.frame);
  return m;
}

}  // namespace

ScoredSequence ScoreFiles(const ScoreFilesOptions& options) {
  std::optional<SeqInfo> info;
  if (!options.seqinfo_path.empty()) {
    info = ReadSeqInfo(options.seqinfo_path);
  } else {
    const fs::path dir = fs::path(options.gt_path).parent_path();
    for (const fs::path& candidate : {dir / "seqinfo.ini", dir.parent_path() / "seqinfo.ini"}) {
      if (fs::exists(candidate)) {
        info = ReadSeqInfo(candidate.string());
        break;
      }
    }
  }
  ScoredSequence out;
  std::optional<int> length;
  if (info) length = info->seq_length;
  const MotFile gt = ReadMotFile(options.gt_path, MotFileKind::kGroundTruth, length);
  const MotFile hyp = ReadMotFile(options.hyp_path, MotFileKind::kTracks, length);
  if (!length) {
    length = std::max(MaxFrame(gt), MaxFrame(hyp));
    // Two empty files and no seqinfo.ini: no frame at all to score, which
    // would print a row of zeros as if something had been measured.
    if (*length == 0) {
      throw InputError(SourceLocation{options.gt_path, 0, 0, {}},
                       "a sequence length: seqLength in a seqinfo.ini (--seqinfo, or next to GT "
                       "or in its parent folder), or a row in GT or HYP",
                       "no seqinfo.ini, and no row in either file",
                       "pass --seqinfo naming the sequence's seqinfo.ini");
    }
    spdlog::warn(
        "no seqinfo.ini next to {}: sequence length taken as the last frame in the files ({})",
        options.gt_path, *length);
  }
  out.seq_length = *length;
  out.benchmark = ResolveBenchmark(options.benchmark, gt);
  std::string name = options.name;
  if (name.empty())
    name = info && !info->name.empty() ? info->name : fs::path(options.gt_path).stem().string();
  // Sparse: memory follows the rows, not seqLength (the MOT metrics are the same).
  PreprocessOptions build = options.preprocess;
  build.sparse = true;
  const Sequence seq = BuildSequence(gt, hyp, out.seq_length, out.benchmark, build, name);
  out.summary = ComputeAll(seq, options.keep_events ? &out.events : nullptr);
  return out;
}

namespace {

// The sequences of a benchmark's seqmap (TrackEval: csv rows, the first row
// a header, rows with an empty first field skipped, the first field the
// name), in the seqmap's order, each once. Names that could leave the
// benchmark's folder are refused.
std::vector<std::string> ReadSeqmap(const fs::path& file) {
  const std::string text = ReadInputFile(file.string(), "a TrackEval seqmap", 64u << 20);
  std::vector<std::string> names;
  std::set<std::string> seen;
  size_t begin = 0;
  for (int line = 1; begin < text.size(); ++line) {
    size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    std::string row = text.substr(begin, end - begin);
    begin = end + 1;
    if (!row.empty() && row.back() == '\r') row.pop_back();
    if (line == 1) continue;  // the header ("name")
    std::string name = row.substr(0, row.find(','));
    if (name.empty()) continue;
    if (name == "." || name == ".." || name.find('/') != std::string::npos ||
        name.find('\0') != std::string::npos) {
      throw InputError(SourceLocation{file.string(), line, 1, {}},
                       "a sequence name (a folder of the benchmark)", fmt::format("\"{}\"", name));
    }
    if (seen.insert(name).second) names.push_back(std::move(name));
  }
  return names;
}

}  // namespace

std::vector<TrackEvalResult> ScoreTrackEvalRoot(const std::string& root, Benchmark benchmark) {
  const fs::path gt_root = fs::path(root) / "gt" / "mot_challenge";
  const fs::path trackers_root = fs::path(root) / "trackers" / "mot_challenge";
  if (!fs::is_directory(gt_root) || !fs::is_directory(trackers_root)) {
    throw InputError(
        SourceLocation{root, 0, 0, {}},
        "a TrackEval folder with gt/mot_challenge/<bench>/ and trackers/mot_challenge/<bench>/",
        "no such folders");
  }
  std::vector<TrackEvalResult> results;
  std::vector<fs::path> benches;
  for (const auto& e : fs::directory_iterator(gt_root)) {
    // gt/mot_challenge/seqmaps holds the seqmaps, not a benchmark.
    if (e.is_directory() && e.path().filename() != "seqmaps") benches.push_back(e.path());
  }
  std::sort(benches.begin(), benches.end());
  for (const fs::path& bench_dir : benches) {
    const std::string bench = bench_dir.filename().string();
    Benchmark rules = benchmark;
    if (rules == Benchmark::kAuto) {
      if (bench.rfind("MOT15", 0) == 0 || bench.rfind("2D_MOT_2015", 0) == 0)
        rules = Benchmark::kMot15;
      if (bench.rfind("MOT16", 0) == 0 || bench.rfind("MOT17", 0) == 0 ||
          bench.rfind("MOT20", 0) == 0) {
        rules = Benchmark::kMot17;
      }
    }
    const fs::path bench_trackers = trackers_root / bench;
    if (!fs::is_directory(bench_trackers)) {
      spdlog::warn("{}: benchmark {} has no trackers folder ({}): not scored", root, bench,
                   bench_trackers.string());
      continue;
    }
    // The sequences: those of the benchmark's seqmap
    // (gt/mot_challenge/seqmaps/<bench>.txt), as TrackEval reads them; with
    // no seqmap (which TrackEval requires), every folder of the benchmark.
    // Either way a sequence without its gt.txt is an error, as TrackEval's
    // is (it was left out silently, and with it its share of COMBINED).
    std::vector<fs::path> seqs;
    const fs::path seqmap = gt_root / "seqmaps" / (bench + ".txt");
    std::string from;
    if (fs::exists(seqmap)) {
      for (const std::string& name : ReadSeqmap(seqmap)) seqs.push_back(bench_dir / name);
      from = fmt::format("a sequence of the seqmap {}", seqmap.string());
    } else {
      for (const auto& e : fs::directory_iterator(bench_dir)) {
        if (e.is_directory()) seqs.push_back(e.path());
      }
      std::sort(seqs.begin(), seqs.end());
      from = fmt::format("every folder of {} is a sequence when there is no seqmap {}",
                         bench_dir.string(), seqmap.string());
    }
    for (const fs::path& seq_dir : seqs) {
      const fs::path gt = seq_dir / "gt" / "gt.txt";
      if (!fs::is_regular_file(gt)) {
        throw InputError(
            SourceLocation{gt.string(), 0, 0, {}},
            fmt::format("the ground truth of sequence {} ({})", seq_dir.filename().string(), from),
            "no file");
      }
    }
    // TrackEval: "No sequences are selected to be evaluated." A COMBINED of
    // nothing would print as a row of zeros.
    if (seqs.empty()) {
      throw InputError(
          SourceLocation{fs::exists(seqmap) ? seqmap.string() : bench_dir.string(), 0, 0, {}},
          fmt::format("at least one sequence of benchmark {} to score", bench),
          fs::exists(seqmap) ? "a seqmap naming none" : "no sequence folder");
    }
    std::vector<fs::path> trackers;
    for (const auto& e : fs::directory_iterator(bench_trackers)) {
      if (e.is_directory()) trackers.push_back(e.path());
    }
    std::sort(trackers.begin(), trackers.end());
    if (trackers.empty())
      spdlog::warn("{}: no tracker folder in {}", root, bench_trackers.string());
    for (const fs::path& tracker_dir : trackers) {
      TrackEvalResult r;
      r.bench = bench;
      r.tracker = tracker_dir.filename().string();
      for (const fs::path& seq_dir : seqs) {
        const std::string seq = seq_dir.filename().string();
        const fs::path hyp = tracker_dir / "data" / (seq + ".txt");
        if (!fs::exists(hyp)) {
          throw InputError(SourceLocation{hyp.string(), 0, 0, {}},
                           fmt::format("tracker output for sequence {}", seq), "no file");
        }
        const fs::path seqinfo = seq_dir / "seqinfo.ini";
        ScoreFilesOptions o;
        o.gt_path = (seq_dir / "gt" / "gt.txt").string();
        o.hyp_path = hyp.string();
        o.seqinfo_path = fs::exists(seqinfo) ? seqinfo.string() : std::string();
        o.benchmark = rules;
        o.name = seq;
        r.sequences.push_back(ScoreFiles(o).summary);
      }
      r.combined = Pool(r.sequences, "COMBINED");
      results.push_back(std::move(r));
    }
  }
  return results;
}

std::string FormatMotTable(std::span<const MotSummary> rows) {
  size_t width = 8;
  for (const MotSummary& s : rows) width = std::max(width, s.name.size());
  std::string out = fmt::format(
      "{:<{}} {:>6} {:>6} {:>6} {:>6} {:>7} {:>6} {:>6} {:>6} {:>6} {:>7} {:>7} {:>5} {:>4} {:>4} "
      "{:>4}\n",
      "sequence", width, "HOTA", "DetA", "AssA", "LocA", "MOTA", "MOTP", "IDF1", "IDP", "IDR", "FP",
      "FN", "IDSW", "MT", "PT", "ML");
  for (const MotSummary& s : rows) {
    out += fmt::format(
        "{:<{}} {:>6.2f} {:>6.2f} {:>6.2f} {:>6.2f} {:>7.2f} {:>6.2f} {:>6.2f} {:>6.2f} {:>6.2f} "
        "{:>7} {:>7} {:>5} {:>4} {:>4} {:>4}\n",
        s.name, width, 100 * s.hota.hota_mean, 100 * s.hota.deta_mean, 100 * s.hota.assa_mean,
        100 * s.hota.loca_mean, 100 * s.clear.mota, 100 * s.clear.motp, 100 * s.identity.idf1,
        100 * s.identity.idp, 100 * s.identity.idr, s.clear.fp, s.clear.fn, s.clear.idsw,
        s.clear.mt, s.clear.pt, s.clear.ml);
  }
  return out;
}

// An audit: "HOTA 80.17" beside metrics.json's and the reports' 0.8017,
// with nothing to say why.
std::string MotTablePercentNote() {
  return "HOTA to IDR in percent, as TrackEval prints them (metrics.json, the --json file, the "
         "reports and summary.csv hold fractions); FP to ML are counts.\n";
}

std::string MotSummariesToJson(std::span<const MotSummary> sequences, const MotSummary* combined) {
  json j;
  j["sequences"] = json::object();
  for (const MotSummary& s : sequences) j["sequences"][s.name] = SummaryJson(s);
  if (combined) j["combined"] = SummaryJson(*combined);
  return j.dump(1) + "\n";
}

RunMetrics ComputeRunMetrics(const RunMetricsInput& input) {
  RunMetrics m;
  m.mot = ComputeAll(input.sequence);
  m.points = ComputePointMetrics(PointFramesFromSequence(input.sequence), input.point_options);
  if (input.filters) m.filters = ComputeFilterMetrics(*input.filters, input.filter_options);
  if (input.detections) {
    DetectionQualityOptions options;
    options.min_visible = input.filter_options.min_visible;
    m.detection = ScoreDetections(*input.detections, options);
  }
  return m;
}

namespace {

json CountsJson(const DetectionCounts& c) {
  return {{"tp", c.tp},
          {"fp", c.fp},
          {"fn", c.fn},
          {"precision", Number(c.precision())},
          {"recall", Number(c.recall())},
          {"f1", Number(c.f1())}};
}

json BinsJson(const std::vector<DetectionBin>& bins) {
  json out = json::array();
  for (const DetectionBin& b : bins) {
    out.push_back({{"lo", Number(b.lo)},
                   {"hi", Number(b.hi)},
                   {"iou", CountsJson(b.iou)},
                   {"centre", CountsJson(b.centre)}});
  }
  return out;
}

// Increasing frame indices as inclusive runs [[first, last], ...].
json FrameRuns(const std::vector<int>& frames) {
  json out = json::array();
  for (size_t i = 0; i < frames.size();) {
    size_t j = i;
    while (j + 1 < frames.size() && frames[j + 1] == frames[j] + 1) ++j;
    out.push_back({frames[i], frames[j]});
    i = j + 1;
  }
  return out;
}

json TargetsJson(const std::vector<TargetDetections>& targets) {
  json out = json::array();
  for (const TargetDetections& t : targets) {
    out.push_back({{"target", Value(t.target)},
                   {"found", t.found},
                   {"missed", t.missed},
                   {"recall", Number(t.recall())},
                   {"found_centre", t.found_centre},
                   {"missed_centre", t.missed_centre},
                   {"recall_centre", Number(t.recall_centre())},
                   {"found_frames", FrameRuns(t.found_frames)},
                   {"missed_frames", FrameRuns(t.missed_frames)}});
  }
  return out;
}

json PrecisionRecallJson(const PrecisionRecall& pr) {
  json recall = json::array(), precision = json::array(), min_score = json::array();
  for (const PrecisionAtRecall& p : pr.curve) {
    recall.push_back(Number(p.recall));
    precision.push_back(Number(p.precision));
    min_score.push_back(Number(p.min_score));
  }
  return {{"average_precision", Number(pr.average_precision)},
          {"best_f1",
           {{"f1", Number(pr.best_f1)},
            {"precision", Number(pr.best_f1_precision)},
            {"recall", Number(pr.best_f1_recall)},
            {"min_score", Number(pr.best_f1_min_score)}}},
          {"curve", {{"recall", recall}, {"precision", precision}, {"min_score", min_score}}}};
}

json DetectionJson(const DetectionQuality& d) {
  json j = {{"iou", CountsJson(d.iou)},
            {"centre", CountsJson(d.centre)},
            {"mean_centre_error_px", Number(d.mean_centre_error_px)},
            {"mean_iou", Number(d.mean_iou)},
            {"median_size_px", Number(d.median_size_px)},
            {"by_size_px", BinsJson(d.by_size)},
            {"by_visibility", BinsJson(d.by_visibility)},
            {"by_truncation", BinsJson(d.by_truncation)},
            {"by_target", TargetsJson(d.by_target)},
            {"precision_recall", PrecisionRecallJson(d.precision_recall)},
            {"mostly_visible",
             {{"min_visible", kMostlyVisible},
              {"iou", CountsJson(d.iou_mostly_visible)},
              {"precision_recall", PrecisionRecallJson(d.precision_recall_mostly_visible)}}}};
  // Only where a detection carries a label: nothing was measured otherwise.
  if (d.labels) {
    j["labels"] = {{"matched", d.labels->matched},
                   {"right", d.labels->right},
                   {"accuracy", Number(d.labels->accuracy())}};
  }
  return j;
}

// A table's number: three decimals, "-" for an undefined one (NaN).
std::string Fixed3(double v) { return std::isfinite(v) ? fmt::format("{:.3f}", v) : "-"; }

// One table row: counts under the IoU rule, the centre rule's recall.
std::string DetectionRow(const std::string& label, const DetectionCounts& iou,
                         const DetectionCounts* centre, bool with_false) {
  return fmt::format("{:<26} {:>7} {:>7} {:>7} {:>9} {:>7} {:>13}\n", label, iou.tp, iou.fn,
                     with_false ? fmt::format("{}", iou.fp) : "-",
                     with_false ? Fixed3(iou.precision()) : "-", Fixed3(iou.recall()),
                     centre != nullptr ? Fixed3(centre->recall()) : "-");
}

std::string BinLabel(const char* what, const DetectionBin& b, const char* unit) {
  if (!std::isfinite(b.hi)) return fmt::format("{} >= {:g}{}", what, b.lo, unit);
  return fmt::format("{} {:g}-{:g}{}", what, b.lo, b.hi, unit);
}

}  // namespace

std::string DetectionQualityToJson(const DetectionQuality& quality) {
  return DetectionJson(quality).dump(1) + "\n";
}

std::string FormatDetectionTable(const DetectionQuality& d) {
  std::string out = fmt::format("{:<26} {:>7} {:>7} {:>7} {:>9} {:>7} {:>13}\n", "targets", "found",
                                "missed", "false", "precision", "recall", "centre recall");
  out += DetectionRow("all", d.iou, &d.centre, true);
  // The rest don't care (DetectionQuality::iou_mostly_visible).
  out += DetectionRow(fmt::format("only visible >= {:g}", kMostlyVisible), d.iou_mostly_visible,
                      nullptr, true);
  for (const DetectionBin& b : d.by_size)
    out += DetectionRow(BinLabel("size", b, " px"), b.iou, &b.centre, true);
  for (const DetectionBin& b : d.by_visibility)
    out += DetectionRow(BinLabel("visible", b, ""), b.iou, &b.centre, false);
  for (const DetectionBin& b : d.by_truncation)
    out += DetectionRow(BinLabel("truncated", b, ""), b.iou, &b.centre, false);
  for (const TargetDetections& t : d.by_target) {
    const DetectionCounts iou{.tp = t.found, .fp = 0, .fn = t.missed};
    const DetectionCounts centre{.tp = t.found_centre, .fp = 0, .fn = t.missed_centre};
    out += DetectionRow(fmt::format("target {}", Value(t.target)), iou, &centre, false);
  }
  const PrecisionRecall& pr = d.precision_recall;
  out += fmt::format(
      "F1 {} (IoU >= 0.5), mean IoU of the matches {}, mean centre error {} px, median target "
      "size {} px\n",
      Fixed3(d.iou.f1()), Fixed3(d.mean_iou), Fixed3(d.mean_centre_error_px),
      Fixed3(d.median_size_px));
  out += fmt::format(
      "average precision (AP50, 101 recalls) {}; visible >= {:g}: {}; best F1 {} at score >= "
      "{} (precision {}, recall {})\n",
      Fixed3(pr.average_precision), kMostlyVisible,
      Fixed3(d.precision_recall_mostly_visible.average_precision), Fixed3(pr.best_f1),
      Fixed3(pr.best_f1_min_score), Fixed3(pr.best_f1_precision), Fixed3(pr.best_f1_recall));
  if (d.labels) {
    out += fmt::format(
        "labels: {} of the {} labelled detections on a target (IoU >= 0.5, labels ignored) name "
        "it: label accuracy {}\n",
        d.labels->right, d.labels->matched, Fixed3(d.labels->accuracy()));
  }
  return out;
}

std::string RunMetricsToJson(const RunMetrics& m) {
  json j;
  j["mot"] = SummaryJson(m.mot);
  json ospa;
  ospa["mean"] = Number(m.points.mean_ospa);
  ospa["per_frame"] = json::array();
  for (double v : m.points.ospa) ospa["per_frame"].push_back(Number(v));
  j["ospa"] = ospa;
  json gospa;
  gospa["mean"] = Number(m.points.mean_gospa);
  gospa["total_switches"] = m.points.total_switches;
  gospa["per_frame"] = json::array();
  for (const GospaTerms& g : m.points.gospa) {
    gospa["per_frame"].push_back({{"distance", Number(g.distance)},
                                  {"localisation", g.localisation},
                                  {"missed", g.missed},
                                  {"false", g.false_alarm},
                                  {"switching", g.switching},
                                  {"switches", g.switches}});
  }
  j["gospa"] = gospa;
  if (m.detection) j["detection"] = DetectionJson(*m.detection);
  if (m.camera_motion) {
    // No frame pair (a run of one frame): nothing was measured, null, not a
    // perfect 0 px that a sweep's mean would take in (an audit).
    const auto summary = [](const CameraMotionErrorSummary& e) {
      const auto value = [&e](double v) { return e.frames > 0 ? Number(v) : json(nullptr); };
      return json{{"mean_px", value(e.mean_px)},
                  {"median_px", value(e.median_px)},
                  {"p95_px", value(e.p95_px)},
                  {"max_px", value(e.max_px)}};
    };
    json& camera = j["camera_motion"] = summary(m.camera_motion->error);
    camera["mode"] = m.camera_motion->mode;
    camera["frames"] = m.camera_motion->error.frames;
    camera["floor"] = summary(m.camera_motion->floor);
  }
  if (m.filters) {
    const FilterMetrics& f = *m.filters;
    json fj;
    fj["da_accuracy"] = f.da_accuracy;
    fj["scored"] = f.scored;
    json counts;
    for (int s = 0; s < kNumFilterStates; ++s)
      counts[FilterStateName(static_cast<FilterState>(s))] = f.state_counts[s];
    fj["states"] = counts;
    fj["encounters"] = static_cast<int64_t>(f.encounters.size());
    fj["hijacked_encounters"] = f.hijacked_encounters;
    fj["swaps"] = f.swaps;
    fj["hijack_rate"] = f.hijack_rate;
    fj["hijacked_fraction"] = f.hijacked_fraction_overall;
    fj["hijacked_fraction_per_frame"] = f.hijacked_fraction;
    fj["mean_mass_on_other"] = f.mean_mass_on_other;
    fj["frames_with_cloud"] = f.frames_with_cloud;
    if (f.reacquisitions) {
      const Reacquisitions& r = *f.reacquisitions;
      json reacquisitions = {
          {"count", r.count}, {"scored_after", r.scored_after}, {"correct_after", r.correct_after}};
      // A fraction of nothing is absent, not 0.
      if (r.scored_after > 0) {
        reacquisitions["correct_fraction"] = static_cast<double>(r.correct_after) / r.scored_after;
      }
      fj["reacquisitions"] = std::move(reacquisitions);
    }
    json mapping = json::array();
    for (const auto& [filter, target] : f.mapping)
      mapping.push_back({{"filter", filter}, {"target", target}});
    fj["mapping"] = mapping;
    json bins = json::array();
    for (const VisibilityBin& b : f.da_by_visibility) {
      json bin = {{"lo", b.lo}, {"hi", b.hi}, {"scored", b.scored}, {"correct", b.correct}};
      if (b.scored > 0) bin["accuracy"] = b.accuracy;  // a fraction of nothing is absent
      bins.push_back(std::move(bin));
    }
    fj["da_by_visibility"] = bins;
    json enc = json::array();
    for (const Encounter& e : f.encounters) {
      enc.push_back({{"targets", {e.target_a, e.target_b}},
                     {"first_frame", e.first_frame},
                     {"last_frame", e.last_frame},
                     {"eval_frame", e.eval_frame},
                     {"hijacked", e.hijacked},
                     {"swapped", e.swapped}});
    }
    fj["encounter_list"] = enc;
    json states = json::array();
    for (const FilterFrameRecord& r : f.records) {
      json rec = {{"frame", r.frame},
                  {"filter", r.filter},
                  {"target", r.target},
                  {"covered", r.covered},
                  {"state", FilterStateName(r.state)}};
      if (r.mass_on_other >= 0.0) rec["mass_on_other"] = r.mass_on_other;
      states.push_back(rec);
    }
    fj["per_frame_states"] = states;
    j["filters"] = fj;
  }
  return j.dump(1) + "\n";
}

}  // namespace hcpf::metrics
