#include "hcpf/metrics/report.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "hcpf/core/error.h"
#include "support/process.h"

namespace hcpf::metrics {
namespace {

namespace fs = std::filesystem;

std::string ReportDataPath(const std::string& name) {
  return std::string(HCPF_SOURCE_DIR) + "/metrics/tests/data/" + name;
}

void WriteText(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream(path) << text;
}

std::string ReadData(const std::string& name) {
  std::ifstream in(ReportDataPath(name));
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

// The message of the InputError ScoreTrackEvalRoot throws for `root`, or ""
// when it scores the folder.
std::string RootError(const fs::path& root) {
  try {
    ScoreTrackEvalRoot(root.string());
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// The switch micro-sequence (values by hand in micro_sequences_test.cc: MOTA 2/3,
// IDSW 1) scored through the file entry point, table and JSON.
TEST(Report, ScoreFilesTableAndJson) {
  ScoreFilesOptions o;
  o.gt_path = ReportDataPath("switch_gt.txt");
  o.hyp_path = ReportDataPath("switch_hyp.txt");
  o.keep_events = true;
  const ScoredSequence s = ScoreFiles(o);
  EXPECT_EQ(s.seq_length, 3);  // no seqinfo: last frame in the files
  EXPECT_EQ(s.benchmark, Benchmark::kMot15);
  EXPECT_EQ(s.summary.name, "switch_gt");
  EXPECT_EQ(s.summary.clear.idsw, 1);
  EXPECT_EQ(s.events.size(), 4u);
  const std::string table = FormatMotTable({&s.summary, 1});
  EXPECT_NE(table.find("switch_gt"), std::string::npos);
  EXPECT_NE(table.find("66.67"), std::string::npos) << table;  // MOTA in percent
  EXPECT_EQ(MotTablePercentNote().find("HOTA to IDR in percent, as TrackEval prints them"), 0U);
  const auto j = nlohmann::json::parse(MotSummariesToJson({&s.summary, 1}, &s.summary));
  EXPECT_EQ(j["sequences"]["switch_gt"]["IDSW"], 1);
  EXPECT_NEAR(j["combined"]["MOTA"].get<double>(), 2.0 / 3.0, 1e-12);
  EXPECT_EQ(j["combined"]["HOTA_alpha"].size(), 19u);
}

// Issue 15 item 7: a 48-byte file with one row at frame 999999999 and no
// seqinfo.ini took 33 s and 5.9 GB (per-frame storage for every frame); it now
// costs what its rows cost, and the frame count is still the sequence's.
TEST(Report, ScoreFilesOfAHugeFrameNumberCostsWhatItsRowsCost) {
  const fs::path dir = hcpf::testing::FreshDir("metrics-huge-frame");
  WriteText(dir / "gt" / "gt.txt", "999999999,1,10,10,20,20,1,1,1\n");
  WriteText(dir / "hyp.txt", "999999999,4,10,10,20,20,1,-1,-1,-1\n");
  ScoreFilesOptions o;
  o.gt_path = (dir / "gt" / "gt.txt").string();
  o.hyp_path = (dir / "hyp.txt").string();
  const ScoredSequence s = ScoreFiles(o);
  EXPECT_EQ(s.seq_length, 999999999);
  EXPECT_EQ(s.summary.num_frames, 999999999);
  EXPECT_EQ(s.summary.clear.tp, 1);
  EXPECT_DOUBLE_EQ(s.summary.clear.mota, 1.0);
  // seqLength = 2^31 - 1 from a seqinfo.ini: the same.
  WriteText(dir / "seqinfo.ini", "[Sequence]\nseqLength=2147483647\n");
  o.seqinfo_path = (dir / "seqinfo.ini").string();
  EXPECT_EQ(ScoreFiles(o).summary.num_frames, 2147483647);
}

// TrackEval layout with two copies of the switch sequence: each row as above, COMBINED
// sums the counts (IDSW 2, TP 6) and keeps MOTA (6-0-2)/6 = 2/3.
TEST(Report, TrackEvalRootWithCombinedRow) {
  const fs::path root = hcpf::testing::FreshDir("metrics-trackeval-root");
  const std::string gt = ReadData("switch_gt.txt");
  const std::string hyp = ReadData("switch_hyp.txt");
  for (const std::string seq : {"SEQ-A", "SEQ-B"}) {
    WriteText(root / "gt/mot_challenge/MOT15-train" / seq / "gt/gt.txt", gt);
    WriteText(root / "gt/mot_challenge/MOT15-train" / seq / "seqinfo.ini",
              "[Sequence]\nname=" + seq + "\nseqLength=3\n");
    WriteText(root / "trackers/mot_challenge/MOT15-train/mine/data" / (seq + ".txt"), hyp);
  }
  const auto results = ScoreTrackEvalRoot(root.string());
  ASSERT_EQ(results.size(), 1u);
  EXPECT_EQ(results[0].tracker, "mine");
  ASSERT_EQ(results[0].sequences.size(), 2u);
  EXPECT_EQ(results[0].sequences[1].name, "SEQ-B");
  EXPECT_EQ(results[0].combined.clear.idsw, 2);
  EXPECT_EQ(results[0].combined.clear.tp, 6);
  EXPECT_NEAR(results[0].combined.clear.mota, 2.0 / 3.0, 1e-12);
  // A sequence folder without its gt.txt is bad input (a bad-input audit
  // found it left out of the sequences and of COMBINED silently).
  fs::remove(root / "gt/mot_challenge/MOT15-train/SEQ-A/gt/gt.txt");
  EXPECT_NE(RootError(root).find("SEQ-A/gt/gt.txt: expected the ground truth of sequence SEQ-A"),
            std::string::npos);
  WriteText(root / "gt/mot_challenge/MOT15-train/SEQ-A/gt/gt.txt", gt);
  // A missing tracker file is bad input.
  fs::remove(root / "trackers/mot_challenge/MOT15-train/mine/data/SEQ-B.txt");
  EXPECT_THROW(ScoreTrackEvalRoot(root.string()), InputError);
  EXPECT_THROW(ScoreTrackEvalRoot((root / "nope").string()), InputError);
}

// TrackEval reads the sequences of a benchmark from its seqmap
// (gt/mot_challenge/seqmaps/<bench>.txt: a header row, then one name a row,
// the first csv field, rows with an empty one skipped) and scores those only,
// in that order; so does --trackeval-root. Three folders SEQ-A..C, the switch
// sequence in each; the seqmap names SEQ-C then SEQ-A (SEQ-A twice: once),
// so SEQ-B (whose tracker file is missing, an error were it scored) is left
// out and COMBINED holds two copies. The seqmaps folder is not a benchmark.
TEST(Report, TrackEvalRootReadsTheSeqmapLikeTrackEval) {
  const fs::path root = hcpf::testing::FreshDir("metrics-trackeval-seqmap");
  const std::string gt = ReadData("switch_gt.txt");
  const std::string hyp = ReadData("switch_hyp.txt");
  const fs::path bench = root / "gt/mot_challenge/MOT15-train";
  for (const std::string seq : {"SEQ-A", "SEQ-B", "SEQ-C"}) {
    WriteText(bench / seq / "gt/gt.txt", gt);
    WriteText(bench / seq / "seqinfo.ini", "[Sequence]\nname=" + seq + "\nseqLength=3\n");
    if (seq != "SEQ-B")
      WriteText(root / "trackers/mot_challenge/MOT15-train/mine/data" / (seq + ".txt"), hyp);
  }
  const fs::path seqmap = root / "gt/mot_challenge/seqmaps/MOT15-train.txt";
  WriteText(seqmap, "name\r\nSEQ-C,extra\r\n\n,ignored\nSEQ-A\nSEQ-A\n");
  auto results = ScoreTrackEvalRoot(root.string());
  ASSERT_EQ(results.size(), 1u);
  ASSERT_EQ(results[0].sequences.size(), 2u);
  EXPECT_EQ(results[0].sequences[0].name, "SEQ-C");
  EXPECT_EQ(results[0].sequences[1].name, "SEQ-A");
  EXPECT_EQ(results[0].combined.clear.idsw, 2);
  EXPECT_EQ(results[0].combined.clear.tp, 6);

  // A seqmap sequence without a folder (or its gt.txt): an error naming the seqmap.
  WriteText(seqmap, "name\nSEQ-A\nSEQ-D\n");
  EXPECT_NE(RootError(root).find("SEQ-D/gt/gt.txt: expected the ground truth of sequence SEQ-D "
                                 "(a sequence of the seqmap"),
            std::string::npos);
  // A name that would leave the benchmark's folder: refused at its line.
  WriteText(seqmap, "name\nSEQ-A\n../MOT15-train/SEQ-A\n");
  EXPECT_NE(RootError(root).find("MOT15-train.txt:3:1: expected a sequence name"),
            std::string::npos);
  // A seqmap naming no sequence: TrackEval's "No sequences are selected".
  WriteText(seqmap, "name\n");
  EXPECT_NE(RootError(root).find("a seqmap naming none"), std::string::npos);
  // No seqmap: every folder is a sequence, and SEQ-B's missing tracker file is an error.
  fs::remove(seqmap);
  EXPECT_NE(RootError(root).find("SEQ-B.txt: expected tracker output for sequence SEQ-B"),
            std::string::npos);
  // A benchmark with ground truth but no trackers folder is skipped (with a
  // warning), not an error: nothing of it to score.
  WriteText(seqmap, "name\nSEQ-A\n");
  WriteText(root / "gt/mot_challenge/MOT17-train/SEQ-X/gt/gt.txt", gt);
  results = ScoreTrackEvalRoot(root.string());
  ASSERT_EQ(results.size(), 1u);
  EXPECT_EQ(results[0].bench, "MOT15-train");
}

// Two empty files and no seqinfo.ini leave no frame to score: bad input
// (it printed a row of zeros). With a seqinfo.ini they are a sequence of
// seqLength frames with nothing in them.
TEST(Report, EmptyFilesWithoutASequenceLengthAreBadInput) {
  const fs::path dir = hcpf::testing::FreshDir("metrics-empty-files");
  WriteText(dir / "gt" / "gt.txt", "");
  WriteText(dir / "hyp.txt", "");
  ScoreFilesOptions o;
  o.gt_path = (dir / "gt" / "gt.txt").string();
  o.hyp_path = (dir / "hyp.txt").string();
  try {
    ScoreFiles(o);
    ADD_FAILURE() << "two empty files without seqinfo.ini were scored";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no seqinfo.ini, and no row in either file"),
              std::string::npos)
        << e.what();
  }
  WriteText(dir / "seqinfo.ini", "[Sequence]\nseqLength=4\n");
  EXPECT_EQ(ScoreFiles(o).summary.num_frames, 4);
}

TEST(Report, RunMetricsJsonHasEveryFamily) {
  RunMetricsInput in;
  in.sequence.frames.resize(2);
  for (auto& f : in.sequence.frames) {
    f.gt.push_back({1, {0, 0, 10, 10}});
    f.hyp.push_back({5, {0, 0, 10, 10}});
  }
  FilterSequence filters;
  filters.birth_target = {{{5, 1}}};
  for (int t = 0; t < 2; ++t) {
    filters.frames.push_back({{{1, 5, 5, 10, 10, 1.0}}, {{5, BoxPx{0, 0, 10, 10}, std::nullopt}}});
  }
  in.filters = filters;
  const RunMetrics m = ComputeRunMetrics(in);
  const auto j = nlohmann::json::parse(RunMetricsToJson(m));
  EXPECT_EQ(j["mot"]["TP"], 2);
  EXPECT_EQ(j["ospa"]["mean"], 0.0);  // identical centres
  EXPECT_EQ(j["filters"]["da_accuracy"], 1.0);
  EXPECT_EQ(j["filters"]["states"]["CORRECT"], 2);
  EXPECT_EQ(j["filters"]["per_frame_states"].size(), 2u);
  EXPECT_FALSE(j.contains("detection")) << "no detector, no detection block";
  EXPECT_FALSE(j.contains("camera_motion"));
  // A camera-motion score of no frame pair (a run of one frame) is no
  // measurement: null, not 0 px; with one pair, its error.
  RunMetrics with_camera = m;
  with_camera.camera_motion = CameraMotionScore{.mode = "scene_filter"};
  auto camera = nlohmann::json::parse(RunMetricsToJson(with_camera))["camera_motion"];
  EXPECT_EQ(camera["frames"], 0);
  for (const char* key : {"mean_px", "median_px", "p95_px", "max_px"}) {
    EXPECT_TRUE(camera[key].is_null()) << key;
    EXPECT_TRUE(camera["floor"][key].is_null()) << key;
  }
  const std::vector<double> one_pair{2.5};
  with_camera.camera_motion->error = SummariseCameraMotionError(one_pair);
  camera = nlohmann::json::parse(RunMetricsToJson(with_camera))["camera_motion"];
  EXPECT_EQ(camera["mean_px"], 2.5);
  EXPECT_EQ(camera["max_px"], 2.5);
  EXPECT_FALSE(j["filters"].contains("reacquisitions")) << "the tracker did not re-acquire";
  // It could have, and did not: a count of 0 and no fraction of nothing.
  in.filters->reacquired.emplace();
  EXPECT_EQ(
      nlohmann::json::parse(RunMetricsToJson(ComputeRunMetrics(in)))["filters"]["reacquisitions"],
      nlohmann::json::parse(R"({"count": 0, "scored_after": 0, "correct_after": 0})"));
  // Re-acquired in frame 0: frames 0 and 1 (both CORRECT) from it on.
  in.filters->reacquired = {{{0, 5}}};
  const auto again = nlohmann::json::parse(RunMetricsToJson(ComputeRunMetrics(in)));
  EXPECT_EQ(again["filters"]["reacquisitions"],
            nlohmann::json::parse(
                R"({"count": 1, "scored_after": 2, "correct_after": 2, "correct_fraction": 1.0})"));
}

// The detection block's per-target records: frames 0-based (as elsewhere in
// metrics.json) as inclusive runs. Target 7 is found in frames 0, 1 and 3
// (a detection on its box) and missed in frame 2 (none): found runs [0, 1]
// and [3, 3], missed [2, 2], recall 3 / 4.
TEST(Report, RunMetricsJsonHasPerTargetDetectionRuns) {
  RunMetricsInput in;
  in.sequence.frames.resize(4);
  std::vector<DetectionFrame> frames(4);
  for (int t = 0; t < 4; ++t) {
    frames[t].truth = {{ObjectId{7}, BoxPx{0, 0, 10, 10}, 1.0}};
    if (t != 2) frames[t].detections = {Detection{.box = BoxPx{0, 0, 10, 10}}};
  }
  in.detections = frames;
  const auto j = nlohmann::json::parse(RunMetricsToJson(ComputeRunMetrics(in)));
  ASSERT_EQ(j["detection"]["by_target"].size(), 1u);
  const auto& t = j["detection"]["by_target"][0];
  EXPECT_EQ(t["target"], 7);
  EXPECT_EQ(t["found"], 3);
  EXPECT_EQ(t["missed"], 1);
  EXPECT_EQ(t["recall"], 0.75);
  EXPECT_EQ(t["found_centre"], 3);
  EXPECT_EQ(t["found_frames"], nlohmann::json::parse("[[0, 1], [3, 3]]"));
  EXPECT_EQ(t["missed_frames"], nlohmann::json::parse("[[2, 2]]"));
}

}  // namespace
}  // namespace hcpf::metrics
