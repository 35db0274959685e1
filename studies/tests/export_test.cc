// hcpf export --trackeval: a small sweep laid out in TrackEval's layout and
// read back with metrics' TrackEval reader (what `hcpf score --trackeval-root`
// runs), which must give every run's own MOTA, IDF1 and HOTA; bad inputs.

#include "hcpf/studies/export.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "hcpf/core/error.h"
#include "hcpf/metrics/report.h"
#include "hcpf/studies/results_store.h"
#include "hcpf/studies/sweep.h"
#include "sweep_fixture.h"

namespace hcpf::studies {
namespace {

namespace fs = std::filesystem;

using hcpf::testing::ReadFile;

std::vector<std::string> SplitLine(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream s(line);
  std::string field;
  while (std::getline(s, field, ',')) out.push_back(field);
  return out;
}

// Two observation noises × two seeds = four ground truths (sequences), each
// tracked by two resampling methods (trackers): eight runs of 20 frames.
// With `shard_count` > 1 only shard 0 of it.
fs::path SmallSweep(const fs::path& dir, int shard_count = 1) {
  const SweepSpec spec = LoadSweepFile(testing::WriteSweep(
      dir,
      "base: base.yaml\nseeds: 2\ngrid:\n  tracker.resampling.method: [systematic, charged]\n"
      "  observation.simulated.sigma_px: [1, 3]\n"));
  SweepOptions o;
  o.out_dir = (dir / "sweep").string();
  o.jobs = 2;
  o.progress = false;
  o.shard_count = shard_count;
  RunSweep(spec, ExpandSweep(spec), o);
  return o.out_dir;
}

TEST(ExportTrackEval, LayoutReadsBackToEveryRunsMetrics) {
  const auto dir = testing::SweepFolder("export");
  const fs::path sweep = SmallSweep(dir);
  const fs::path out = dir / "te";
  const TrackEvalExportResult r = ExportTrackEval({.dir = sweep.string(), .out = out.string()});
  EXPECT_EQ(r.sequences, 4);
  EXPECT_EQ(r.trackers, 2);
  EXPECT_EQ(r.runs, 8);
  EXPECT_EQ(r.skipped, 0);
  EXPECT_EQ(r.missing, 0);
  EXPECT_EQ(r.bench, "HCPF-train");

  // TrackEval's MotChallenge2DBox layout (BENCHMARK HCPF, SPLIT_TO_EVAL train):
  // the seqmap at GT_FOLDER/seqmaps/HCPF-train.txt, a header row then the names.
  const std::vector<std::string> seqs = {
      "observation.simulated.sigma_px-1_seed0", "observation.simulated.sigma_px-1_seed1",
      "observation.simulated.sigma_px-3_seed0", "observation.simulated.sigma_px-3_seed1"};
  const std::vector<std::string> trackers = {"resampling.method-charged",
                                             "resampling.method-systematic"};
  std::string seqmap = "name\n";
  for (const std::string& s : seqs) seqmap += s + "\n";
  EXPECT_EQ(ReadFile(out / "gt" / "mot_challenge" / "seqmaps" / "HCPF-train.txt"), seqmap);
  for (const std::string& s : seqs) {
    const fs::path seq = out / "gt" / "mot_challenge" / "HCPF-train" / s;
    EXPECT_TRUE(fs::is_regular_file(seq / "gt" / "gt.txt")) << s;
    EXPECT_NE(ReadFile(seq / "seqinfo.ini").find("name=" + s + "\n"), std::string::npos) << s;
    for (const std::string& t : trackers) {
      EXPECT_TRUE(fs::is_regular_file(out / "trackers" / "mot_challenge" / "HCPF-train" / t /
                                      "data" / (s + ".txt")))
          << t << " " << s;
    }
  }

  // export.csv maps (sequence, tracker) back to the run.
  auto store = ResultsStore::Open((sweep / "results.sqlite").string());
  std::map<std::string, RunRecord> by_key;
  for (const RunRecord& rec : store->Runs()) by_key[rec.key] = rec;
  std::map<std::pair<std::string, std::string>, RunRecord> run_of;
  std::stringstream csv(ReadFile(out / "export.csv"));
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line,
            "sequence,tracker,run_key,run_index,seed_index,seed,run_dir,tracker.resampling.method,"
            "observation.simulated.sigma_px");
  while (std::getline(csv, line)) {
    const std::vector<std::string> f = SplitLine(line);
    ASSERT_EQ(f.size(), 9U) << line;
    ASSERT_EQ(by_key.count(f[2]), 1U) << line;
    const RunRecord& rec = by_key[f[2]];
    // The names follow from the run's swept values and seed index.
    EXPECT_EQ(f[0], "observation.simulated.sigma_px-" + rec.values[1] + "_seed" +
                        std::to_string(rec.seed_index));
    EXPECT_EQ(f[1], "resampling.method-" + rec.values[0]);
    run_of[{f[0], f[1]}] = rec;
  }
  ASSERT_EQ(run_of.size(), 8U);

  // Read back: one result per tracker, every sequence's metrics those of its run.
  const std::vector<metrics::TrackEvalResult> scored = metrics::ScoreTrackEvalRoot(out.string());
  ASSERT_EQ(scored.size(), 2U);
  for (const metrics::TrackEvalResult& t : scored) {
    EXPECT_EQ(t.bench, "HCPF-train");
    ASSERT_EQ(t.sequences.size(), 4U) << t.tracker;
    for (const metrics::MotSummary& s : t.sequences) {
      SCOPED_TRACE(t.tracker + " " + s.name);
      ASSERT_EQ(run_of.count({s.name, t.tracker}), 1U);
      const RunRecord& rec = run_of[{s.name, t.tracker}];
      EXPECT_DOUBLE_EQ(s.clear.mota, rec.metrics.at("mota"));
      EXPECT_DOUBLE_EQ(s.identity.idf1, rec.metrics.at("idf1"));
      EXPECT_DOUBLE_EQ(s.hota.hota_mean, rec.metrics.at("hota"));
    }
  }

  // Deterministic: a second export is byte-identical.
  const fs::path again = dir / "te2";
  ExportTrackEval({.dir = sweep.string(), .out = again.string()});
  EXPECT_EQ(ReadFile(again / "export.csv"), ReadFile(out / "export.csv"));
  EXPECT_EQ(ReadFile(again / "gt" / "mot_challenge" / "HCPF-train" / seqs[2] / "seqinfo.ini"),
            ReadFile(out / "gt" / "mot_challenge" / "HCPF-train" / seqs[2] / "seqinfo.ini"));

  // A run folder without its tracks: that run's sequence is left out for all
  // trackers (TrackEval needs every tracker on every sequence), other names stay.
  const RunRecord& broken = run_of[{seqs[1], trackers[0]}];
  fs::remove(sweep / broken.run_dir / "tracks.txt");
  const TrackEvalExportResult partial =
      ExportTrackEval({.dir = sweep.string(), .out = (dir / "te3").string(), .split = "val"});
  EXPECT_EQ(partial.sequences, 3);
  EXPECT_EQ(partial.runs, 6);
  EXPECT_EQ(partial.not_ok, 1);
  EXPECT_EQ(partial.skipped, 1);
  EXPECT_EQ(ReadFile(dir / "te3" / "gt" / "mot_challenge" / "seqmaps" / "HCPF-val.txt"),
            "name\n" + seqs[0] + "\n" + seqs[2] + "\n" + seqs[3] + "\n");

  // Emptied or replaced, not removed (a bad-input audit: exported as a
  // tracker that found nothing, exit 0): left out as resume and merge leave
  // it out, by the manifest's file sizes.
  const RunRecord& emptied = run_of[{seqs[3], trackers[1]}];
  std::ofstream(sweep / emptied.run_dir / "tracks.txt", std::ios::trunc).flush();
  const TrackEvalExportResult damaged =
      ExportTrackEval({.dir = sweep.string(), .out = (dir / "te4").string()});
  EXPECT_EQ(damaged.not_ok, 2);
  EXPECT_EQ(damaged.skipped, 2);
  EXPECT_EQ(ReadFile(dir / "te4" / "gt" / "mot_challenge" / "seqmaps" / "HCPF-train.txt"),
            "name\n" + seqs[0] + "\n" + seqs[2] + "\n");

  // A run written before manifests listed their files (2026-11-23), which
  // also had no camera_motion.csv: exported as before, asked only for the
  // files the export copies (a review: all such runs were left out).
  const fs::path old_run = sweep / run_of[{seqs[0], trackers[0]}].run_dir;
  auto manifest = nlohmann::json::parse(ReadFile(old_run / "manifest.json"));
  manifest.erase("files");
  std::ofstream(old_run / "manifest.json", std::ios::trunc) << manifest.dump(2);
  fs::remove(old_run / "camera_motion.csv");
  const TrackEvalExportResult older =
      ExportTrackEval({.dir = sweep.string(), .out = (dir / "te5").string()});
  EXPECT_EQ(older.not_ok, 2);
  EXPECT_EQ(ReadFile(dir / "te5" / "gt" / "mot_challenge" / "seqmaps" / "HCPF-train.txt"),
            "name\n" + seqs[0] + "\n" + seqs[2] + "\n");
}

// An export killed before its rename leaves OUT.partial-<pid>; the next
// export into OUT removes it (it used to stay for good), and leaves the
// staging folder of a process that runs (init's pid here) alone.
// One shard of two exported: the runs it holds, with a count of the missing
// ones (a bad-input audit: an export of a shard or of a sweep stopped early
// looked whole, exit 0 and no word).
TEST(ExportTrackEval, OfAShardCountsTheMissingRuns) {
  const auto dir = testing::SweepFolder("export-shard");
  const fs::path sweep = SmallSweep(dir, 2);
  const TrackEvalExportResult r =
      ExportTrackEval({.dir = sweep.string(), .out = (dir / "te").string()});
  EXPECT_EQ(r.missing, 4);
  EXPECT_EQ(r.runs + r.skipped + r.not_ok, 4);
}

// A swept `seed` (a sweep of explicit seeds) is the column `swept.seed`,
// beside the run's `seed`, as in the store (a bad-input audit: the header
// named `seed` twice).
TEST(ExportTrackEval, ASweptSeedIsItsOwnColumn) {
  const auto dir = testing::SweepFolder("export-swept-seed");
  const SweepSpec spec =
      LoadSweepFile(testing::WriteSweep(dir, "base: base.yaml\ngrid:\n  seed: [11, 12]\n"));
  SweepOptions o;
  o.out_dir = (dir / "sweep").string();
  o.progress = false;
  RunSweep(spec, ExpandSweep(spec), o);
  ExportTrackEval({.dir = o.out_dir, .out = (dir / "te").string()});
  std::stringstream csv(ReadFile(dir / "te" / "export.csv"));
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, "sequence,tracker,run_key,run_index,seed_index,seed,run_dir,swept.seed");
}

TEST(ExportTrackEval, RemovesTheStagingFoldersOfKilledExports) {
  const auto dir = testing::SweepFolder("export-stale");
  const fs::path sweep = SmallSweep(dir);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) ::_exit(0);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  const fs::path stale = dir / ("te.partial-" + std::to_string(child));
  fs::create_directories(stale / "gt");
  std::ofstream(stale / "gt" / "half.txt") << "1,1,";
  fs::create_directories(dir / "te.partial-1");
  ExportTrackEval({.dir = sweep.string(), .out = (dir / "te").string()});
  EXPECT_TRUE(fs::is_regular_file(dir / "te" / "export.csv"));
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(dir / "te.partial-1"));
}

// Names: list values keep their digits, no tracker key gives "hcpf", and two
// values that sanitise alike get "-2" in run order.
TEST(ExportTrackEval, NamesAreSanitisedAndUnique) {
  const auto dir = testing::SweepFolder("export-names");
  const SweepSpec spec = LoadSweepFile(testing::WriteSweep(
      dir,
      "base: base.yaml\ngrid:\n  camera.resolution: [[320, 240]]\n  name: [\"a b\", \"a/b\"]\n"));
  SweepOptions o;
  o.out_dir = (dir / "sweep").string();
  o.progress = false;
  RunSweep(spec, ExpandSweep(spec), o);
  const TrackEvalExportResult r = ExportTrackEval({.dir = o.out_dir, .out = (dir / "te").string()});
  EXPECT_EQ(r.sequences, 2);
  EXPECT_EQ(r.trackers, 1);
  EXPECT_EQ(ReadFile(dir / "te" / "gt" / "mot_challenge" / "seqmaps" / "HCPF-train.txt"),
            "name\ncamera.resolution-320_240_name-a_b_seed0\n"
            "camera.resolution-320_240_name-a_b_seed0-2\n");
  EXPECT_TRUE(fs::is_regular_file(dir / "te" / "trackers" / "mot_challenge" / "HCPF-train" /
                                  "hcpf" / "data" /
                                  "camera.resolution-320_240_name-a_b_seed0.txt"));
}

// Labels longer than a file name may be keep their first 183 bytes and end
// in a hash of the whole label: two long names that differ only at the end
// give two sequences, each name at most 200 bytes (a second bad-input audit:
// the export failed with "File name too long").
TEST(ExportTrackEval, LongLabelsAreBoundedAndDistinct) {
  const auto dir = testing::SweepFolder("export-long");
  const std::string stem(300, 'a');
  const SweepSpec spec = LoadSweepFile(
      testing::WriteSweep(dir, "base: base.yaml\ngrid:\n  name: [" + stem + "1, " + stem + "2]\n"));
  SweepOptions o;
  o.out_dir = (dir / "sweep").string();
  o.progress = false;
  RunSweep(spec, ExpandSweep(spec), o);
  const TrackEvalExportResult r = ExportTrackEval({.dir = o.out_dir, .out = (dir / "te").string()});
  EXPECT_EQ(r.sequences, 2);
  const std::string seqmap =
      ReadFile(dir / "te" / "gt" / "mot_challenge" / "seqmaps" / "HCPF-train.txt");
  std::vector<std::string> names;
  std::stringstream lines(seqmap);
  for (std::string line; std::getline(lines, line);) names.push_back(line);
  ASSERT_EQ(names.size(), 3u) << seqmap;
  for (size_t i = 1; i < 3; ++i) {
    EXPECT_EQ(names[i].size(), 200u) << names[i];
    EXPECT_EQ(names[i].rfind("name-aaaa", 0), 0u) << names[i];
    EXPECT_TRUE(fs::is_directory(dir / "te" / "gt" / "mot_challenge" / "HCPF-train" / names[i]));
  }
  EXPECT_NE(names[1], names[2]);
  EXPECT_EQ(names[1].substr(0, 183), names[2].substr(0, 183));
}

std::string ErrorOf(const TrackEvalExportOptions& o) {
  try {
    ExportTrackEval(o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

// A third bad-input audit: the scenario `name` zipped with the tracker keys
// (as the shipped external-sort sweep labels its trackers) split the runs
// into one sequence per tracker, so the sweep could never be exported; with
// tracker keys swept, `name` labels the tracker. And a tracker whose runs all
// failed was left out of a complete-looking export; now every sequence lacks
// it and the export is refused, naming it.
TEST(ExportTrackEval, ANameZippedWithTheTrackerLabelsItAndATrackerWithoutRunsIsNamed) {
  const auto dir = testing::SweepFolder("export-zip-name");
  const SweepSpec spec = LoadSweepFile(
      testing::WriteSweep(dir,
                          "base: base.yaml\nseeds: 2\nzip:\n  name: [pf-systematic, pf-charged]\n"
                          "  tracker.resampling.method: [systematic, charged]\n"));
  SweepOptions o;
  o.out_dir = (dir / "sweep").string();
  o.progress = false;
  const std::vector<SweepRun> runs = ExpandSweep(spec);
  RunSweep(spec, runs, o);
  const TrackEvalExportResult r = ExportTrackEval({.dir = o.out_dir, .out = (dir / "te").string()});
  EXPECT_EQ(r.sequences, 2);  // the two seeds
  EXPECT_EQ(r.trackers, 2);
  EXPECT_EQ(r.runs, 4);
  EXPECT_TRUE(fs::is_directory(dir / "te" / "trackers" / "mot_challenge" / "HCPF-train" /
                               "name-pf-charged_resampling.method-charged"));
  // The same sweep where both runs of pf-charged fail (their run folders hold
  // a file of the user's, which a run refuses to replace).
  SweepOptions failing = o;
  failing.out_dir = (dir / "failing").string();
  for (const SweepRun& run : runs) {
    if (run.values[0] != "pf-charged") continue;
    fs::create_directories(dir / "failing" / "runs" / run.key);
    std::ofstream(dir / "failing" / "runs" / run.key / "notes.txt") << "mine\n";
  }
  EXPECT_EQ(RunSweep(spec, runs, failing).failed, 2);
  const std::string e = ErrorOf({.dir = failing.out_dir, .out = (dir / "te-failing").string()});
  EXPECT_NE(e.find("expected a sequence with an ok run of every tracker, found none: no ok run of "
                   "the tracker(s) name-pf-charged_resampling.method-charged"),
            std::string::npos)
      << e;
  EXPECT_FALSE(fs::exists(dir / "te-failing"));
}

// A tracker key zipped with a scene key runs each tracker on its own
// sequences: refused, saying so (an audit of valid input: the message
// implied failed runs).
TEST(ExportTrackEval, TrackersZippedWithSceneKeysAreSaidToBe) {
  const auto dir = testing::SweepFolder("export-zip-scene");
  const SweepSpec spec =
      LoadSweepFile(testing::WriteSweep(dir,
                                        "base: base.yaml\nzip:\n  tracker.particles: [40, 80]\n"
                                        "  observation.simulated.sigma_px: [1, 2]\n"));
  SweepOptions o;
  o.out_dir = (dir / "sweep").string();
  o.progress = false;
  ASSERT_EQ(RunSweep(spec, ExpandSweep(spec), o).failed, 0);
  const std::string e = ErrorOf({.dir = o.out_dir, .out = (dir / "te").string()});
  EXPECT_NE(e.find("found none: every tracker has ok runs, but on other sequences (a tracker key "
                   "zipped with a scene key"),
            std::string::npos)
      << e;
}

TEST(ExportTrackEval, BadInputs) {
  const auto dir = testing::SweepFolder("export-bad");
  // A folder without a results store.
  std::string e = ErrorOf({.dir = dir.string(), .out = (dir / "o1").string()});
  EXPECT_NE(e.find("results.sqlite"), std::string::npos) << e;
  EXPECT_FALSE(fs::exists(dir / "o1"));
  const fs::path sweep = SmallSweep(dir);
  // OUT not empty, or a file: refused, left as it was.
  fs::create_directories(dir / "full");
  std::ofstream(dir / "full" / "keep.txt") << "mine";
  e = ErrorOf({.dir = sweep.string(), .out = (dir / "full").string()});
  EXPECT_NE(e.find("not empty"), std::string::npos) << e;
  EXPECT_EQ(ReadFile(dir / "full" / "keep.txt"), "mine");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir / "full"), fs::directory_iterator()), 1);
  std::ofstream(dir / "file") << "x";
  e = ErrorOf({.dir = sweep.string(), .out = (dir / "file").string()});
  EXPECT_NE(e.find("--trackeval: expected a folder (new or existing), found an existing file"),
            std::string::npos)
      << e;
  // A link to nothing, or a path below a file: refused before anything is
  // written (both failed with exit 1 before).
  fs::create_symlink(dir / "nowhere", dir / "dangling");
  e = ErrorOf({.dir = sweep.string(), .out = (dir / "dangling").string()});
  EXPECT_NE(e.find("a symbolic link to nothing"), std::string::npos) << e;
  EXPECT_FALSE(fs::exists(dir / "nowhere"));
  e = ErrorOf({.dir = sweep.string(), .out = (dir / "file" / "te").string()});
  EXPECT_NE(e.find("a path below the file"), std::string::npos) << e;
  // Names TrackEval joins as <BENCHMARK>-<SPLIT>: no '-' or '/', and short.
  e = ErrorOf(
      {.dir = sweep.string(), .out = (dir / "o2").string(), .benchmark = std::string(101, 'B')});
  EXPECT_NE(e.find("1 to 100 letters"), std::string::npos) << e;
  e = ErrorOf({.dir = sweep.string(), .out = (dir / "o2").string(), .benchmark = "MOT-17"});
  EXPECT_NE(e.find("--benchmark"), std::string::npos) << e;
  e = ErrorOf({.dir = sweep.string(), .out = (dir / "o2").string(), .split = "../x"});
  EXPECT_NE(e.find("--split"), std::string::npos) << e;
  // An existing empty folder is fine, and nothing is left beside it.
  fs::create_directories(dir / "empty");
  EXPECT_EQ(ErrorOf({.dir = sweep.string(), .out = (dir / "empty").string() + "/"}), "(no error)");
  EXPECT_TRUE(fs::is_regular_file(dir / "empty" / "export.csv"));
  for (const auto& entry : fs::directory_iterator(dir)) {
    EXPECT_EQ(entry.path().filename().string().find(".partial-"), std::string::npos)
        << entry.path();
  }
}

}  // namespace
}  // namespace hcpf::studies
