// `hcpf run` on a rendered scenario: pixel-exact ground truth from the
// renderer, frames cached by pixel hash and reused by a run with other
// tracker settings.

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "support/process.h"

namespace hcpf {
namespace {

namespace fs = std::filesystem;
using testing::FreshDir;
using testing::ReadelfBuildId;
using testing::ReadFile;
using testing::RunCommand;

// Each filter's first and last frame in filters.csv (1-based), by filter id.
std::map<int, std::pair<int, int>> FilterLifetimes(const std::string& csv) {
  std::map<int, std::pair<int, int>> lifetimes;
  std::istringstream lines(csv);
  std::string line;
  std::getline(lines, line);  // the header
  while (std::getline(lines, line)) {
    int frame = 0, filter = 0;
    char comma = 0;
    std::istringstream fields(line);
    fields >> frame >> comma >> filter;
    auto [it, fresh] = lifetimes.try_emplace(filter, frame, frame);
    if (!fresh) it->second.second = frame;
  }
  return lifetimes;
}

TEST(RenderedRun, PixelExactTruthAndFrameCacheReuse) {
  const fs::path dir = FreshDir("rendered-run");
  const std::string scenario = testing::LibraryScenario("crossing");
  const std::string common = std::string(HCPF_EXE) + " run " + scenario +
                             " --set observation.source=rendered --set frames=24"
                             " --set 'camera.resolution=[160, 120]' --cache " +
                             (dir / "cache").string();
  auto r = RunCommand(common + " --out " + (dir / "a").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  auto manifest = nlohmann::json::parse(ReadFile(dir / "a" / "manifest.json"));
  EXPECT_EQ(manifest["ground_truth"], "rendered (pixel-exact)");
  EXPECT_EQ(manifest["frames_rendered"], 24);
  EXPECT_NE(manifest["gl_renderer"]["renderer"].get<std::string>(), "");
  // How the context was made (issue 13 item 3): "osmesa", "egl surfaceless"
  // or "egl device N (hardware|software)", starting with the backend.
  EXPECT_TRUE(manifest["gl_renderer"]["platform"].get<std::string>().starts_with(
      manifest["gl_renderer"]["backend"].get<std::string>()))
      << manifest["gl_renderer"].dump();
  // The renderer counts pixels: gt.json carries pixels_visible and pixels_total.
  const auto gt = nlohmann::json::parse(ReadFile(dir / "a" / "gt.json"));
  EXPECT_GT(gt["frames"][0]["objects"][0]["pixels_total"].get<int64_t>(), 0);

  // Other tracker settings: no frame is rendered again, the truth is the same;
  // the scene's folder (dated two days back) is marked used (hcpf cache).
  std::vector<fs::path> scenes;
  for (const auto& e : fs::directory_iterator(dir / "cache")) {
    if (e.is_directory() && e.path().filename().string().size() == 32) scenes.push_back(e.path());
  }
  ASSERT_EQ(scenes.size(), 1u);
  // The folder notes its scene (its name, a hash, says none of it), and
  // `hcpf cache` lists it so.
  const auto note = nlohmann::json::parse(ReadFile(scenes[0] / "scene.json"));
  EXPECT_EQ(note, nlohmann::json::parse(R"({"scenario": "crossing", "seed": 7, "frames": 24, )"
                                        R"("width_px": 160, "height_px": 120})"));
  const auto listing =
      RunCommand(std::string(HCPF_EXE) + " cache --cache " + (dir / "cache").string());
  EXPECT_NE(listing.output.find("  crossing, seed 7, 24 frame(s), 160 x 120  " +
                                scenes[0].filename().string() + "\n"),
            std::string::npos)
      << listing.output;
  const auto two_days_ago = fs::file_time_type::clock::now() - std::chrono::hours(48);
  fs::last_write_time(scenes[0], two_days_ago);
  r = RunCommand(common + " --set tracker.particles=50 --out " + (dir / "b").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_GT(fs::last_write_time(scenes[0]), two_days_ago + std::chrono::hours(47));
  manifest = nlohmann::json::parse(ReadFile(dir / "b" / "manifest.json"));
  EXPECT_EQ(manifest["frames_rendered"], 0);
  EXPECT_EQ(manifest["frames_from_cache"], 24);
  // No GL context was made, but the frames' renderer is known: the one run
  // (a) noted in the cache.
  EXPECT_TRUE(manifest["gl_renderer"].is_null());
  const nlohmann::json a_gl =
      nlohmann::json::parse(ReadFile(dir / "a" / "manifest.json"))["gl_renderer"];
  const std::string line =
      a_gl["platform"].get<std::string>() + "; " + a_gl["vendor"].get<std::string>() + "; " +
      a_gl["renderer"].get<std::string>() + "; " + a_gl["version"].get<std::string>();
  EXPECT_EQ(manifest["frame_cache_renderers"], nlohmann::json::array({line}));
  EXPECT_EQ(r.output.find("GL renderers"), std::string::npos) << r.output;
  EXPECT_EQ(ReadFile(dir / "a" / "gt" / "gt.txt"), ReadFile(dir / "b" / "gt" / "gt.txt"));
  EXPECT_EQ(ReadFile(dir / "a" / "detections.txt"), ReadFile(dir / "b" / "detections.txt"));
  EXPECT_NE(ReadFile(dir / "a" / "tracks.txt"), ReadFile(dir / "b" / "tracks.txt"));

  // A rendered run's folder (it holds det/det.txt) is an earlier output that
  // the same command replaces; a file of the user's inside det/ is not.
  r = RunCommand(common + " --set tracker.particles=50 --out " + (dir / "a").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(ReadFile(dir / "a" / "tracks.txt"), ReadFile(dir / "b" / "tracks.txt"));
  std::ofstream(dir / "a" / "det" / "mine.txt") << "mine";
  r = RunCommand(common + " --out " + (dir / "a").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("holds \"det/mine.txt\", which no run writes"), std::string::npos)
      << r.output;
  EXPECT_EQ(ReadFile(dir / "a" / "det" / "mine.txt"), "mine");
}

// Rendering is pipelined one frame ahead (SceneRenderer::Submit / Collect),
// looking ahead only at frames the cache lacks: a cache with holes (single
// frames, a run of frames, the first and the last) is filled exactly, and the
// run's truth, detections and tracks are those of the uncached run.
TEST(RenderedRun, CacheWithHolesRendersOnlyTheMissingFramesAndChangesNothing) {
  const fs::path dir = FreshDir("rendered-holes");
  const std::string common = std::string(HCPF_EXE) + " run " +
                             testing::LibraryScenario("crossing") +
                             " --set observation.source=rendered --set frames=24"
                             " --set 'camera.resolution=[160, 120]' --cache " +
                             (dir / "cache").string();
  auto r = RunCommand(common + " --out " + (dir / "a").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  fs::path frames;
  for (const auto& entry : fs::directory_iterator(dir / "cache")) frames = entry.path();
  ASSERT_TRUE(fs::exists(frames / "000023.frame")) << frames;
  const std::vector<int> holes = {0, 5, 6, 7, 12, 23};
  std::map<int, std::string> before;
  for (int f : holes) {
    const fs::path file = frames / fmt::format("{:06d}.frame", f);
    before[f] = ReadFile(file);
    fs::remove(file);
  }
  // What killed writes left: the temporary file of a process that no longer
  // runs is removed when the scene is rendered into again; one of a live
  // process (this one: a concurrent run's write) stays.
  const fs::path stale = frames / ".000005.frame.tmp-99999999-0";
  const fs::path live = frames / fmt::format(".000006.frame.tmp-{}-0", ::getpid());
  std::ofstream(stale) << "partial";
  std::ofstream(live) << "partial";
  r = RunCommand(common + " --out " + (dir / "b").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(live));
  fs::remove(live);
  const auto manifest = nlohmann::json::parse(ReadFile(dir / "b" / "manifest.json"));
  EXPECT_EQ(manifest["frames_rendered"], static_cast<int>(holes.size()));
  EXPECT_EQ(manifest["frames_from_cache"], 24 - static_cast<int>(holes.size()));
  for (int f : holes) {
    EXPECT_EQ(ReadFile(frames / fmt::format("{:06d}.frame", f)), before[f]) << "frame " << f;
  }
  for (const char* file : {"gt/gt.txt", "detections.txt", "tracks.txt"}) {
    EXPECT_EQ(ReadFile(dir / "a" / file), ReadFile(dir / "b" / file)) << file;
  }

  // Frames of another GL renderer in the same scene folder (a GPU machine
  // sharing the cache): the run says its frames may mix two renderers, and
  // its manifest names both.
  const std::string other = "egl device 0 (hardware); NVIDIA Corporation; NVIDIA H200; 4.6.0";
  std::ofstream(frames / "renderers.txt", std::ios::app) << other << "\n";
  fs::remove(frames / "000004.frame");
  r = RunCommand(common + " --out " + (dir / "c").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("holds frames of 2 GL renderers"), std::string::npos) << r.output;
  const auto mixed = nlohmann::json::parse(ReadFile(dir / "c" / "manifest.json"));
  ASSERT_EQ(mixed["frame_cache_renderers"].size(), 2U) << mixed.dump();
  EXPECT_EQ(mixed["frame_cache_renderers"][1], other);
  // The renderers file is the cache's own: hcpf cache counts the scene.
  const auto cache =
      RunCommand(std::string(HCPF_EXE) + " cache --cache " + (dir / "cache").string());
  ASSERT_EQ(cache.exit_code, 0) << cache.output;
  EXPECT_NE(cache.output.find("1 scene(s) of rendered frames"), std::string::npos) << cache.output;
  EXPECT_EQ(cache.output.find("renderers.txt"), std::string::npos) << cache.output;
}

// A run with SKS gives the same bytes on a CPU without AVX2 and its kin
// (OpenCV's own switch OPENCV_CPU_DISABLE makes this machine one): a
// determinism audit found cv::GaussianBlur's float result, and with it
// tracks.txt from frame 2 on, changing. SKS's float smoothing is now the
// project's own, summed in one order (SeparableGaussianBlur).
TEST(RenderedRun, SksGivesTheSameBytesWithoutTheCpusVectorExtensions) {
  const fs::path dir = FreshDir("sks-cpu");
  const std::string args = " run " + testing::LibraryScenario("crossing") +
                           " --set observation.source=rendered --set observation.detector=sks "
                           "--set frames=40 --no-cache --out ";
  const auto a = RunCommand(std::string(HCPF_EXE) + args + (dir / "a").string());
  ASSERT_EQ(a.exit_code, 0) << a.output;
  const auto b = RunCommand("OPENCV_CPU_DISABLE=AVX2,FMA3,AVX " + std::string(HCPF_EXE) + args +
                            (dir / "b").string());
  ASSERT_EQ(b.exit_code, 0) << b.output;
  for (const char* file :
       {"det/det.txt", "detections.txt", "tracks.txt", "filters.csv", "metrics.json"}) {
    EXPECT_EQ(ReadFile(dir / "a" / file), ReadFile(dir / "b" / file)) << file;
  }
}

// Pixels reach the tracker: a vision/ detector on the rendered frames, with
// target models cut when each target is first wholly in view, gives the
// filters their own target's detections; det/det.txt holds them in
// MOTChallenge's format; the manifest names the detector and its models.
TEST(RenderedRun, ADetectorOnTheRenderedFramesFeedsTheTracker) {
  const fs::path dir = FreshDir("detector-run");
  const std::string common =
      std::string(HCPF_EXE) + " run " + testing::LibraryScenario("crossing") +
      " --set observation.source=rendered --set frames=90 --cache " + (dir / "cache").string();
  for (const std::string detector : {"ncc", "colour"}) {
    const fs::path out = dir / detector;
    const auto r =
        RunCommand(common + " --set observation.detector=" + detector + " --out " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto manifest = nlohmann::json::parse(ReadFile(out / "manifest.json"));
    EXPECT_EQ(manifest["detector"], detector);
    EXPECT_EQ(manifest["target_models"], "model from ground truth");
    // Target 1 is wholly in view at frame 0. Target 2 starts at frame 12
    // outside the image and enters across the bottom edge from frame 32: its
    // model is cut once it is wholly inside, a whole vehicle, not a sliver.
    ASSERT_EQ(manifest["target_model_sources"].size(), 2u);
    EXPECT_EQ(manifest["target_model_sources"][0]["frame"], 0);
    EXPECT_GT(manifest["target_model_sources"][1]["frame"].get<int>(), 32);
    for (const auto& m : manifest["target_model_sources"]) {
      EXPECT_GE(m["patch"][0].get<int>(), 10) << m;
      EXPECT_GE(m["patch"][1].get<int>(), 10) << m;
    }
    // Each filter is born with its target's model, from the same box
    // (filters.csv counts frames from 1): target 2's is not born at the
    // sliver, 41 frames before anything can detect it, and deleted unseen
    // after max_missed_frames (30), but tracks the truck to the last frame.
    const auto lifetimes = FilterLifetimes(ReadFile(out / "filters.csv"));
    ASSERT_EQ(lifetimes.size(), 2u) << detector;
    EXPECT_EQ(lifetimes.at(1), std::make_pair(1, 90)) << detector;
    EXPECT_EQ(lifetimes.at(2).first, manifest["target_model_sources"][1]["frame"].get<int>() + 1)
        << detector;
    EXPECT_EQ(lifetimes.at(2).second, 90) << detector;
    const std::string det = ReadFile(out / "det" / "det.txt");
    EXPECT_EQ(det, ReadFile(out / "detections.txt"));
    // One detection per model at most per frame (at most 90 + 58 rows), and
    // on this clear scene most frames find target 1.
    const auto rows = std::count(det.begin(), det.end(), '\n');
    EXPECT_GT(rows, 80) << det;
    EXPECT_LE(rows, 148) << det;
    // Column 2 names the target each detection was found for (what
    // observation.file.labels reads back), never MOTChallenge's -1 here.
    std::istringstream lines(det);
    for (std::string line; std::getline(lines, line);) {
      const std::string id = line.substr(line.find(',') + 1, 2);
      EXPECT_TRUE(id == "1," || id == "2,") << detector << ": " << line;
    }
    const auto metrics = nlohmann::json::parse(ReadFile(out / "metrics.json"));
    EXPECT_GT(metrics["filters"]["da_accuracy"].get<double>(), 0.8) << detector;
    // Truncation bins: target 2 enters across the border more than half
    // outside the image (bin [0.5, 1]) before its model exists, so no
    // target-specific detector finds it there; the bins add up to the total.
    const auto& detection = metrics["detection"];
    const auto& truncated = detection["by_truncation"];
    ASSERT_EQ(truncated.size(), 4u);
    EXPECT_GT(truncated[3]["iou"]["fn"].get<int>(), 0) << truncated;
    EXPECT_EQ(truncated[3]["iou"]["tp"].get<int>(), 0) << truncated;
    int targets = 0;
    for (const auto& bin : truncated) {
      targets += bin["iou"]["tp"].get<int>() + bin["iou"]["fn"].get<int>();
    }
    EXPECT_EQ(targets, detection["iou"]["tp"].get<int>() + detection["iou"]["fn"].get<int>());
    // Per target (frames counted from 0, as in the manifest): target 2 is
    // counted from its first frame in view but found only from its model's
    // frame on; the per-target counts add up to the total.
    const auto& by_target = detection["by_target"];
    ASSERT_EQ(by_target.size(), 2u);
    EXPECT_EQ(by_target[1]["target"], 2);
    const int model_frame = manifest["target_model_sources"][1]["frame"].get<int>();
    ASSERT_FALSE(by_target[1]["found_frames"].empty()) << detector;
    EXPECT_GE(by_target[1]["found_frames"][0][0].get<int>(), model_frame) << detector;
    EXPECT_LT(by_target[1]["missed_frames"][0][0].get<int>(), model_frame) << detector;
    EXPECT_EQ(by_target[0]["found"].get<int>() + by_target[1]["found"].get<int>(),
              detection["iou"]["tp"].get<int>());
    EXPECT_EQ(by_target[0]["missed"].get<int>() + by_target[1]["missed"].get<int>(),
              detection["iou"]["fn"].get<int>());
    // Every score threshold: 101 precisions, monotone (interpolated), AP
    // their mean. The lowest threshold is one of the curve's points, and on
    // this scene (two targets apart, at most one detection per model and
    // frame) the greedy and the optimal matching agree there, so the best F1
    // is at least the counts' F1. Both detectors find the targets at
    // precision 1 and recall 0.72 here (the truck is missed only before its
    // model exists): AP 73/101 = 0.72 when measured; 0.6 leaves room for a
    // frame or two and still fails a curve that loses its matches.
    const auto& pr = detection["precision_recall"];
    const auto& precision = pr["curve"]["precision"];
    ASSERT_EQ(precision.size(), 101u) << detector;
    double sum = 0.0;
    for (size_t i = 0; i < precision.size(); ++i) {
      sum += precision[i].get<double>();
      if (i > 0) {
        EXPECT_LE(precision[i].get<double>(), precision[i - 1].get<double>()) << i;
      }
    }
    EXPECT_NEAR(pr["average_precision"].get<double>(), sum / 101.0, 1e-12) << detector;
    EXPECT_GT(pr["average_precision"].get<double>(), 0.6) << detector;
    EXPECT_GE(pr["best_f1"]["f1"].get<double>(), detection["iou"]["f1"].get<double>() - 1e-12)
        << detector;
    // The mostly visible subset: the bin [0.75, 1]'s true positives and
    // misses (the same matching), and as many false detections as in all or
    // fewer (those on less visible targets are ignored there).
    const auto& mostly = detection["mostly_visible"];
    const auto& bin = detection["by_visibility"][3]["iou"];
    EXPECT_EQ(mostly["min_visible"].get<double>(), 0.75);
    EXPECT_EQ(mostly["iou"]["tp"].get<int>(), bin["tp"].get<int>()) << detector;
    EXPECT_EQ(mostly["iou"]["fn"].get<int>(), bin["fn"].get<int>()) << detector;
    EXPECT_LE(mostly["iou"]["fp"].get<int>(), detection["iou"]["fp"].get<int>()) << detector;
    EXPECT_EQ(mostly["precision_recall"]["curve"]["precision"].size(), 101u) << detector;
    // A detector of one's own is scored the same way from the files: hcpf
    // score --detections on the run's gt.json and det/det.txt gives the run's
    // counts, with the detections' targets read from column 2 (--labels) or
    // not. (The file holds boxes to 1/1000 px and scores to 1/10000; the two
    // targets never overlap here, so neither the rounding nor the labels
    // change a match.)
    for (const std::string labels : {"", " --labels"}) {
      const auto scored =
          RunCommand(std::string(HCPF_EXE) + " score --detections " + (out / "gt.json").string() +
                     " " + (out / "det" / "det.txt").string() + labels + " --json " +
                     (out / "scored.json").string());
      ASSERT_EQ(scored.exit_code, 0) << scored.output;
      const auto from_files = nlohmann::json::parse(ReadFile(out / "scored.json"));
      for (const char* rule : {"iou", "centre"}) {
        for (const char* count : {"tp", "fp", "fn"}) {
          EXPECT_EQ(from_files[rule][count], detection[rule][count])
              << detector << " " << rule << labels;
        }
      }
      EXPECT_EQ(from_files["mostly_visible"]["iou"], mostly["iou"]) << detector << labels;
      EXPECT_EQ(from_files["by_target"], detection["by_target"]) << detector << labels;
      // The labels' accuracy only where they are read; the run reads its own.
      EXPECT_EQ(from_files.contains("labels"), !labels.empty()) << detector;
      if (!labels.empty()) {
        EXPECT_EQ(from_files["labels"], detection["labels"]) << detector;
      }
    }
  }
  // The oracle on rendered frames also writes det/det.txt and keeps its label.
  const auto r = RunCommand(common + " --out " + (dir / "oracle").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir / "oracle" / "det" / "det.txt"));
  EXPECT_EQ(nlohmann::json::parse(ReadFile(dir / "oracle" / "manifest.json"))["detector"],
            "oracle (noisy ground truth)");
  // Its detections carry no target: no label accuracy.
  EXPECT_FALSE(
      nlohmann::json::parse(ReadFile(dir / "oracle" / "metrics.json"))["detection"].contains(
          "labels"));
  // Without target models a filter is born at its target's first in-frame
  // appearance: target 2's in frame 33, as it starts to cross the border.
  EXPECT_EQ(FilterLifetimes(ReadFile(dir / "oracle" / "filters.csv")).at(2).first, 33);
}

// observation.detector: file: the detections of a program of one's own, made
// on the frames of `hcpf render` (here: the truth's boxes, a perfect
// detector, with one false detection and one row below min_score), feed the
// tracker and are scored against the pixel-exact truth; the run's identity
// follows the file's content.
TEST(RenderedRun, AnotherProgramsDetectionsFeedTheTracker) {
  const fs::path dir = FreshDir("detection-file-run");
  const std::string scenario = testing::LibraryScenario("crossing");
  const std::string cache = " --cache " + (dir / "cache").string();
  const std::string frames = " --set frames=24";
  const auto rendered = RunCommand(std::string(HCPF_EXE) + " render " + scenario + frames + cache +
                                   " --out " + (dir / "render").string());
  ASSERT_EQ(rendered.exit_code, 0) << rendered.output;
  // det.txt in MOTChallenge's 1-based pixels, from the render's truth.
  const auto gt = nlohmann::json::parse(ReadFile(dir / "render" / "gt.json"));
  std::string det;
  int truth = 0;
  for (const auto& frame : gt["frames"]) {
    const int f = frame["frame"].get<int>() + 1;
    for (const auto& o : frame["objects"]) {
      if (!o["in_frame"].get<bool>()) continue;
      const auto& b = o["amodal_box"];
      det += fmt::format("{},-1,{},{},{},{},0.9\n", f, b[0].get<double>() + 1.0,
                         b[1].get<double>() + 1.0, b[2].get<double>(), b[3].get<double>());
      ++truth;
    }
  }
  ASSERT_EQ(truth, 24);                // target 1 alone, wholly in view, in every frame
  det += "5,-1,401,301,20,10,0.3\n";   // nothing there: a false detection
  det += "6,-1,401,301,20,10,0.05\n";  // below min_score 0.1: left out
  const fs::path det_path = dir / "my_det.txt";
  { std::ofstream(det_path) << det; }
  const std::string run = std::string(HCPF_EXE) + " run " + scenario + frames + cache +
                          " --set observation.source=rendered --set observation.detector=file"
                          " --set observation.file.min_score=0.1 --set observation.file.path=" +
                          det_path.string();
  const auto r = RunCommand(run + " --out " + (dir / "a").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("26 rows, 1 of them left out"), std::string::npos) << r.output;
  const auto manifest = nlohmann::json::parse(ReadFile(dir / "a" / "manifest.json"));
  EXPECT_EQ(manifest["detector"], "file");
  EXPECT_EQ(manifest["detection_file"]["path"], fs::weakly_canonical(det_path).string());
  EXPECT_EQ(manifest["detection_file"]["digest"].get<std::string>().size(), 32u);
  EXPECT_FALSE(manifest.contains("target_models"));
  // Scored like any detector: all 24 found, the one false detection, none
  // missed; the tracker, fed the truth's boxes, tracks the target throughout.
  const auto metrics = nlohmann::json::parse(ReadFile(dir / "a" / "metrics.json"));
  const auto& iou = metrics["detection"]["iou"];
  EXPECT_EQ(iou["tp"], 24) << iou;
  EXPECT_EQ(iou["fp"], 1) << iou;
  EXPECT_EQ(iou["fn"], 0) << iou;
  EXPECT_EQ(metrics["filters"]["da_accuracy"].get<double>(), 1.0) << metrics["filters"];
  // det/det.txt: the rows the tracker got (25: the one below min_score left
  // out), boxes to 1/1000 px.
  const std::string written = ReadFile(dir / "a" / "det" / "det.txt");
  EXPECT_EQ(std::count(written.begin(), written.end(), '\n'), 25) << written;
  EXPECT_NE(written.find("5,-1,401.000,301.000,20.000,10.000,0.3000"), std::string::npos)
      << written;
  EXPECT_EQ(written.find(",0.0500"), std::string::npos) << written;
  // hcpf score --detections on the same file counts as the run does with the
  // same --min-score; without it, the row below 0.1 is a second false
  // detection.
  const std::string score = std::string(HCPF_EXE) + " score --detections " +
                            (dir / "render").string() + " " + det_path.string() + " --json ";
  const auto at = RunCommand(score + (dir / "at.json").string() + " --min-score 0.1");
  ASSERT_EQ(at.exit_code, 0) << at.output;
  EXPECT_NE(at.output.find("26 detections, 1 scoring below 0.1 left out"), std::string::npos)
      << at.output;
  EXPECT_EQ(nlohmann::json::parse(ReadFile(dir / "at.json"))["iou"], iou);
  const auto all = RunCommand(score + (dir / "all.json").string());
  ASSERT_EQ(all.exit_code, 0) << all.output;
  EXPECT_EQ(nlohmann::json::parse(ReadFile(dir / "all.json"))["iou"]["fp"], 2);
  // Another content is another run; the first run's resolved scenario names
  // the content it ran with, and no longer validates.
  { std::ofstream(det_path, std::ios::app) << "7,-1,401,301,20,10,0.3\n"; }
  const auto b = RunCommand(run + " --out " + (dir / "b").string());
  ASSERT_EQ(b.exit_code, 0) << b.output;
  EXPECT_NE(nlohmann::json::parse(ReadFile(dir / "b" / "manifest.json"))["config_hash"],
            manifest["config_hash"]);
  const auto stale = RunCommand(std::string(HCPF_EXE) + " validate " +
                                (dir / "a" / "scenario.resolved.yaml").string());
  EXPECT_EQ(stale.exit_code, 2) << stale.output;
  EXPECT_NE(stale.output.find("observation.file.digest: expected"), std::string::npos)
      << stale.output;
}

// observation.file.labels: column 2 names the target each detection is of,
// and each filter sees only its own target's detections. Perfect boxes from
// the render's truth, labelled right and swapped (crossing cut at 80 frames,
// both vehicles in view from about frame 33): right labels track perfectly;
// swapped ones feed each filter the other vehicle's boxes; without labels
// the ids are ignored, so the swapped file tracks exactly as the right one.
// Each filter is born at its target's first labelled row.
TEST(RenderedRun, DetectionLabelsGiveEachFilterItsOwnTargetsDetections) {
  const fs::path dir = FreshDir("detection-file-labels");
  const std::string scenario = testing::LibraryScenario("crossing") + " --set frames=80";
  const std::string cache = " --cache " + (dir / "cache").string();
  const auto rendered = RunCommand(std::string(HCPF_EXE) + " render " + scenario + cache +
                                   " --out " + (dir / "render").string());
  ASSERT_EQ(rendered.exit_code, 0) << rendered.output;
  const auto gt = nlohmann::json::parse(ReadFile(dir / "render" / "gt.json"));
  std::string right;
  std::string swapped;
  std::string late;                  // target 2's rows from frame 51 (1-based) on only
  std::string without;               // no row of target 2
  std::map<int, int> first_in_view;  // 1-based
  constexpr int kLate = 51;
  for (const auto& frame : gt["frames"]) {
    const int f = frame["frame"].get<int>() + 1;
    for (const auto& o : frame["objects"]) {
      if (!o["in_frame"].get<bool>()) continue;
      const int id = o["id"].get<int>();
      first_in_view.try_emplace(id, f);
      const auto& b = o["amodal_box"];
      const std::string box =
          fmt::format("{},{},{},{},0.9\n", b[0].get<double>() + 1.0, b[1].get<double>() + 1.0,
                      b[2].get<double>(), b[3].get<double>());
      right += fmt::format("{},{},", f, id) + box;
      swapped += fmt::format("{},{},", f, 3 - id) + box;
      if (id == 1 || f >= kLate) late += fmt::format("{},{},", f, id) + box;
      if (id == 1) without += fmt::format("{},{},", f, id) + box;
    }
  }
  ASSERT_EQ(first_in_view, (std::map<int, int>{{1, 1}, {2, 33}}));
  { std::ofstream(dir / "right.txt") << right; }
  { std::ofstream(dir / "swapped.txt") << swapped; }
  { std::ofstream(dir / "late.txt") << late; }
  { std::ofstream(dir / "without.txt") << without; }
  const auto run = [&](const std::string& file, bool labels, const std::string& out) {
    const auto r = RunCommand(std::string(HCPF_EXE) + " run " + scenario + cache +
                              " --set observation.source=rendered --set "
                              "observation.detector=file --set observation.file.path=" +
                              (dir / file).string() + " --set observation.file.labels=" +
                              (labels ? "true" : "false") + " --out " + (dir / out).string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return nlohmann::json::parse(ReadFile(dir / out / "metrics.json"));
  };
  const auto labelled = run("right.txt", true, "right");
  EXPECT_EQ(labelled["filters"]["da_accuracy"].get<double>(), 1.0) << labelled["filters"];
  EXPECT_EQ(labelled["mot"]["MOTA"].get<double>(), 1.0) << labelled;
  // The labels written back (the run's det/det.txt is the file as read).
  EXPECT_NE(ReadFile(dir / "right" / "det" / "det.txt").find("80,2,"), std::string::npos);
  // Swapped: each filter follows boxes of the other vehicle, far off from
  // frame 33 on, so most of target 2's frames and target 1's after it are
  // misses and false tracks (MOTA -0.06 with these seeds; below 0.5 leaves
  // room for any change of tracker detail that keeps a filter on its boxes).
  const auto wrong = run("swapped.txt", true, "swapped");
  EXPECT_LT(wrong["mot"]["MOTA"].get<double>(), 0.5) << wrong;
  EXPECT_LT(wrong["filters"]["da_accuracy"].get<double>(), 1.0) << wrong["filters"];
  // Without labels the ids are not read: the swapped file is the right one.
  run("right.txt", false, "right-plain");
  run("swapped.txt", false, "swapped-plain");
  EXPECT_EQ(ReadFile(dir / "swapped-plain" / "tracks.txt"),
            ReadFile(dir / "right-plain" / "tracks.txt"));
  EXPECT_EQ(ReadFile(dir / "swapped-plain" / "det" / "det.txt"),
            ReadFile(dir / "right-plain" / "det" / "det.txt"));

  // A labelled file knows a target from its first row labelled with it, as a
  // model-based detector knows it once its model is cut: the target's filter
  // is born then, at that frame's box. Rows of target 2 from frame 51 on: its
  // filter is born at 51, not at its first appearance (33), where the same
  // file read without labels births it.
  const auto birth = [&](const std::string& out) {
    return FilterLifetimes(ReadFile(dir / out / "filters.csv"));
  };
  EXPECT_EQ(birth("right").at(2).first, 33);
  run("late.txt", true, "late");
  EXPECT_EQ(birth("late").at(1).first, 1);
  EXPECT_EQ(birth("late").at(2).first, kLate);
  run("late.txt", false, "late-plain");
  EXPECT_EQ(birth("late-plain").at(2).first, 33);
  // No row of target 2: no filter for it, and the run says why.
  const auto none =
      RunCommand(std::string(HCPF_EXE) + " run " + scenario + cache +
                 " --set observation.source=rendered --set "
                 "observation.detector=file --set observation.file.labels=true"
                 " --set observation.file.path=" +
                 (dir / "without.txt").string() + " --out " + (dir / "without").string());
  ASSERT_EQ(none.exit_code, 0) << none.output;
  EXPECT_EQ(birth("without").count(2), 0u);
  EXPECT_NE(none.output.find("target 2: no row of " + (dir / "without.txt").string() +
                             " is labelled 2 (and init: ground_truth gave it no filter)"),
            std::string::npos)
      << none.output;
}

// observation.file.rendering: a det.txt is tied to the frames it was made on
// (the render's manifest pixel_hash). A scenario that renders other frames (a
// sun moved) is refused by validate and run alike, naming the keys that
// differ; the resolved YAML pins the hash; the run's manifest says what the
// file was checked against.
TEST(RenderedRun, ADetectionFileIsCheckedAgainstTheRenderingItWasMadeOn) {
  const fs::path dir = FreshDir("detection-file-rendering");
  const std::string scenario = testing::LibraryScenario("crossing");
  const std::string cache = " --cache " + (dir / "cache").string();
  const std::string common = scenario + " --set frames=14";
  const auto rendered = RunCommand(std::string(HCPF_EXE) + " render " + common + cache + " --out " +
                                   (dir / "render").string());
  ASSERT_EQ(rendered.exit_code, 0) << rendered.output;
  const auto render_manifest = nlohmann::json::parse(ReadFile(dir / "render" / "manifest.json"));
  const std::string hash = render_manifest["pixel_hash"].get<std::string>();
  EXPECT_EQ(hash.size(), 32u);
  EXPECT_EQ(hash.find_first_not_of("0123456789abcdef"), std::string::npos) << hash;
  const fs::path det_path = dir / "det.txt";
  { std::ofstream(det_path) << "1,-1,101,101,40,20,0.9\n"; }
  const std::string file = common +
                           " --set observation.source=rendered --set observation.detector=file"
                           " --set observation.file.path=" +
                           det_path.string() + " --set observation.file.rendering=";
  const std::string validate = std::string(HCPF_EXE) + " validate ";
  const std::string run = std::string(HCPF_EXE) + " run" + cache + " ";

  // The frames it was made on: accepted; the folder's manifest.json itself
  // may be named too.
  const auto ok = RunCommand(validate + file + (dir / "render").string());
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
  EXPECT_EQ(RunCommand(validate + file + (dir / "render" / "manifest.json").string()).exit_code, 0);
  const auto a =
      RunCommand(run + file + (dir / "render").string() + " --out " + (dir / "a").string());
  ASSERT_EQ(a.exit_code, 0) << a.output;
  EXPECT_NE(a.output.find("were made on this scenario's frames (pixel hash " + hash),
            std::string::npos)
      << a.output;
  const auto manifest = nlohmann::json::parse(ReadFile(dir / "a" / "manifest.json"));
  EXPECT_EQ(manifest["pixel_hash"], hash);  // the run rendered the same frames
  EXPECT_EQ(manifest["detection_file"]["made_on_pixel_hash"], hash);
  EXPECT_EQ(manifest["detection_file"]["rendering"], fs::weakly_canonical(dir / "render").string());
  EXPECT_EQ(a.output.find("were rendered by"), std::string::npos) << a.output;  // one renderer
  // Pixel by pixel: every frame's digest is the rendering's, and the manifests
  // of the render and the run hold the same 14.
  EXPECT_NE(a.output.find("the pixels of all 14 frames are those of"), std::string::npos)
      << a.output;
  ASSERT_EQ(render_manifest["frame_digests"].size(), 14u);
  EXPECT_EQ(manifest["frame_digests"], render_manifest["frame_digests"]);
  EXPECT_EQ(render_manifest["frame_digests"][3].get<std::string>().size(), 32u);
  EXPECT_EQ(manifest["detection_file"]["frames_with_other_pixels"], nlohmann::json::array());
  const auto write_manifest = [&](const nlohmann::json& m) {
    std::ofstream(dir / "render" / "manifest.json") << m.dump(2);
  };
  // The rendering as if made by another GL renderer (a GPU elsewhere) whose
  // pixels differ in frames 4 and 9: the hash, which leaves the GL renderer
  // out, still matches; the run names the frames and the renderers, and its
  // manifest lists the frames (1-based, as det.txt).
  {
    auto edited = render_manifest;
    edited["gl_renderer"]["renderer"] = "another renderer";
    edited.erase("frame_cache_renderers");
    edited["frame_digests"][3] = std::string(32, '0');
    edited["frame_digests"][8] = std::string(32, 'f');
    write_manifest(edited);
  }
  const auto c =
      RunCommand(run + file + (dir / "render").string() + " --out " + (dir / "c").string());
  ASSERT_EQ(c.exit_code, 0) << c.output;
  EXPECT_NE(c.output.find("2 of 14 frames differ in their pixels from those of"), std::string::npos)
      << c.output;
  EXPECT_NE(c.output.find("(frames 4, 9): the detections tracked and scored here were made on "
                          "other pixels; "),
            std::string::npos)
      << c.output;
  EXPECT_NE(c.output.find("; another renderer; "), std::string::npos) << c.output;
  EXPECT_EQ(nlohmann::json::parse(ReadFile(
                dir / "c" / "manifest.json"))["detection_file"]["frames_with_other_pixels"],
            nlohmann::json::array({4, 9}));
  // Another renderer with the same pixels: nothing to warn about.
  {
    auto edited = render_manifest;
    edited["gl_renderer"]["renderer"] = "another renderer";
    edited.erase("frame_cache_renderers");
    write_manifest(edited);
  }
  const auto same =
      RunCommand(run + file + (dir / "render").string() + " --out " + (dir / "same").string());
  ASSERT_EQ(same.exit_code, 0) << same.output;
  EXPECT_EQ(same.output.find("were rendered by"), std::string::npos) << same.output;
  EXPECT_NE(same.output.find("the pixels of all 14 frames are those of"), std::string::npos)
      << same.output;
  // A rendering written before frame digests: no pixels to compare, so the
  // GL renderers are, and the manifest says nothing was compared.
  {
    auto edited = render_manifest;
    edited["gl_renderer"]["renderer"] = "another renderer";
    edited.erase("frame_cache_renderers");
    edited.erase("frame_digests");
    write_manifest(edited);
  }
  const auto older =
      RunCommand(run + file + (dir / "render").string() + " --out " + (dir / "older").string());
  ASSERT_EQ(older.exit_code, 0) << older.output;
  EXPECT_NE(older.output.find("were rendered by"), std::string::npos) << older.output;
  EXPECT_EQ(older.output.find("frames differ in their pixels"), std::string::npos) << older.output;
  EXPECT_TRUE(nlohmann::json::parse(ReadFile(
      dir / "older" / "manifest.json"))["detection_file"]["frames_with_other_pixels"]
                  .is_null());
  write_manifest(render_manifest);
  // The resolved scenario pins the hash, and validates.
  const std::string resolved = ReadFile(dir / "a" / "scenario.resolved.yaml");
  EXPECT_NE(resolved.find("pixel_hash: \"" + hash + "\""), std::string::npos) << resolved;
  EXPECT_EQ(RunCommand(validate + (dir / "a" / "scenario.resolved.yaml").string()).exit_code, 0);

  // Another sun: other frames. Refused by validate and run, at the key, with
  // both hashes and the key that differs; the run leaves no folder.
  const std::string moved = " --set world.sun.elevation_deg=60";
  const auto v = RunCommand(validate + file + (dir / "render").string() + moved);
  EXPECT_EQ(v.exit_code, 2) << v.output;
  EXPECT_NE(v.output.find("observation.file.rendering: expected this scenario's frames"),
            std::string::npos)
      << v.output;
  EXPECT_NE(v.output.find("pixel hash " + hash), std::string::npos) << v.output;
  EXPECT_NE(v.output.find("world.sun.elevation_deg (there 35, here 60)"), std::string::npos)
      << v.output;
  const auto b =
      RunCommand(run + file + (dir / "render").string() + moved + " --out " + (dir / "b").string());
  EXPECT_EQ(b.exit_code, 2) << b.output;
  EXPECT_NE(b.output.find("world.sun.elevation_deg (there 35, here 60)"), std::string::npos)
      << b.output;
  EXPECT_FALSE(fs::exists(dir / "b"));
  // A hash written by hand is checked the same way.
  const std::string pinned = common +
                             " --set observation.source=rendered --set observation.detector=file"
                             " --set observation.file.path=" +
                             det_path.string() + " --set observation.file.pixel_hash=" + hash;
  EXPECT_EQ(RunCommand(validate + pinned).exit_code, 0);
  const auto p = RunCommand(validate + pinned + moved);
  EXPECT_EQ(p.exit_code, 2) << p.output;
  EXPECT_NE(p.output.find("observation.file.pixel_hash: expected"), std::string::npos) << p.output;

  // A folder that is no rendering, and a manifest without a pixel hash.
  const auto none = RunCommand(validate + file + dir.string());
  EXPECT_EQ(none.exit_code, 2) << none.output;
  EXPECT_NE(none.output.find("a folder of `hcpf render` or of a rendered `hcpf run`"),
            std::string::npos)
      << none.output;
  fs::create_directories(dir / "old");
  { std::ofstream(dir / "old" / "manifest.json") << R"({"format": "hcpf-render/1"})"; }
  const auto old = RunCommand(validate + file + (dir / "old").string());
  EXPECT_EQ(old.exit_code, 2) << old.output;
  EXPECT_NE(old.output.find("whose manifest has no pixel_hash"), std::string::npos) << old.output;
}

// A target that is never wholly in view gets no model, so a model-based
// detector cannot find it and init: ground_truth gives it no filter: the run
// says so by name, and the oracle still gives it a filter. On crossing cut
// at 40 frames the truck is still crossing the bottom edge.
TEST(RenderedRun, ATargetWithoutAModelIsNamedAndGetsNoFilter) {
  const fs::path dir = FreshDir("detector-unmodelled");
  const std::string common =
      std::string(HCPF_EXE) + " run " + testing::LibraryScenario("crossing") +
      " --set observation.source=rendered --set frames=40 --cache " + (dir / "cache").string();
  const auto r =
      RunCommand(common + " --set observation.detector=colour --out " + (dir / "colour").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("target 2: never wholly inside the image and at least 75 % visible, so "
                          "no model was cut and colour cannot detect it (and init: ground_truth "
                          "gave it no filter)"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("target 1:"), std::string::npos) << r.output;
  const auto manifest = nlohmann::json::parse(ReadFile(dir / "colour" / "manifest.json"));
  ASSERT_EQ(manifest["target_model_sources"].size(), 1u);
  EXPECT_EQ(manifest["target_model_sources"][0]["target"], 1);
  const auto lifetimes = FilterLifetimes(ReadFile(dir / "colour" / "filters.csv"));
  EXPECT_EQ(lifetimes.size(), 1u);
  EXPECT_EQ(lifetimes.count(2), 0u);
  const auto oracle = RunCommand(common + " --out " + (dir / "oracle").string());
  ASSERT_EQ(oracle.exit_code, 0) << oracle.output;
  EXPECT_EQ(oracle.output.find("never wholly inside"), std::string::npos) << oracle.output;
  EXPECT_EQ(FilterLifetimes(ReadFile(dir / "oracle" / "filters.csv")).at(2),
            std::make_pair(33, 40));
}

// tracker.management.reacquire through the pipeline. An IoU gate of 1 lets no
// detection support the tank's filter (target 1, the only one modelled in
// these 40 frames), so it coasts and is deleted after 2 frames. With none it
// never returns; with own_detections the colour detector's detections of the
// tank (3 of 5 frames) bear it again, over and over: filters.csv has it in
// late frames, and the manifest lists each time, in frame order. In each
// frame it is born again it has one row, its re-seeded estimate (not
// coasting); before 2026-12-05 those frames had none (docs/tracker.md, F6).
TEST(RenderedRun, ReacquireBearsADeletedFilterAgainFromItsTargetsDetections) {
  const fs::path dir = FreshDir("detector-reacquire");
  const std::string common =
      std::string(HCPF_EXE) + " run " + testing::LibraryScenario("crossing") +
      " --set observation.source=rendered --set frames=40 --set observation.detector=colour"
      " --set tracker.association.gate=iou --set tracker.association.min_iou=1"
      " --set tracker.management.max_missed_frames=2 --cache " +
      (dir / "cache").string();
  std::map<std::string, nlohmann::json> manifests;
  std::map<std::string, std::string> filters;
  for (const std::string mode : {"none", "own_detections"}) {
    const auto r = RunCommand(common + " --set tracker.management.reacquire=" + mode + " --out " +
                              (dir / mode).string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    manifests[mode] = nlohmann::json::parse(ReadFile(dir / mode / "manifest.json"));
    filters[mode] = ReadFile(dir / mode / "filters.csv");
  }
  EXPECT_FALSE(manifests["none"]["tracker"].contains("reacquired"));
  EXPECT_FALSE(nlohmann::json::parse(ReadFile(dir / "none" / "metrics.json"))["filters"].contains(
      "reacquisitions"));
  const auto none = FilterLifetimes(filters["none"]);
  ASSERT_EQ(none.count(1), 1u);
  EXPECT_LE(none.at(1).second, 3) << "deleted after 2 unsupported frames";
  const nlohmann::json& reacquired = manifests["own_detections"]["tracker"]["reacquired"];
  ASSERT_TRUE(reacquired.is_array());
  ASSERT_GE(reacquired.size(), 3u) << reacquired.dump();
  int previous = -1;
  for (const auto& e : reacquired) {
    EXPECT_EQ(e["filter"], 1);
    EXPECT_GT(e["frame"].get<int>(), previous);
    previous = e["frame"].get<int>();
  }
  EXPECT_GE(FilterLifetimes(filters["own_detections"]).at(1).second, 35);
  const auto metrics = nlohmann::json::parse(ReadFile(dir / "own_detections" / "metrics.json"));
  EXPECT_EQ(metrics["filters"]["reacquisitions"]["count"], reacquired.size());
  EXPECT_GT(metrics["filters"]["reacquisitions"]["scored_after"].get<int>(), 0);
  // filters.csv: frame (from 1), filter, ..., coasting (column 10).
  std::map<int, std::vector<int>> coasting;  // filter 1's rows, by frame
  std::istringstream lines(filters["own_detections"]);
  std::string line;
  std::getline(lines, line);  // the header
  while (std::getline(lines, line)) {
    std::vector<std::string> cells;
    std::istringstream fields(line);
    for (std::string cell; std::getline(fields, cell, ',');) cells.push_back(cell);
    ASSERT_EQ(cells.size(), 12u) << line;
    if (cells[1] == "1") coasting[std::stoi(cells[0])].push_back(std::stoi(cells[9]));
  }
  for (const auto& e : reacquired) {
    const int frame = e["frame"].get<int>() + 1;
    EXPECT_EQ(coasting[frame], std::vector<int>{0}) << "frame " << frame;
  }
}

// Issue 11 item 6: the detection cache. Runs that differ only in tracker
// settings read the first run's detections; a change of a detector option
// misses; a damaged entry is recomputed; the output is the same either way.
TEST(RenderedRun, TheDetectionCacheServesTrackerSweepsAndNeverMisreads) {
  const fs::path dir = FreshDir("detection-cache");
  const std::string common =
      std::string(HCPF_EXE) + " run " + testing::LibraryScenario("crossing") +
      " --set observation.source=rendered --set frames=30 --set observation.detector=ncc --cache " +
      (dir / "cache").string();
  const auto run = [&](const std::string& name, const std::string& sets) {
    const auto r = RunCommand(common + sets + " --out " + (dir / name).string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return nlohmann::json::parse(ReadFile(dir / name / "manifest.json"));
  };
  const nlohmann::json first = run("a", "");
  EXPECT_EQ(first["detections_from_cache"], 0);
  // Every hit marks its entry used (hcpf cache --max-size prunes the least
  // recently used): entries dated two days back are dated now after run b.
  const auto two_days_ago = fs::file_time_type::clock::now() - std::chrono::hours(48);
  for (const auto& e : fs::directory_iterator(dir / "cache" / "detections")) {
    fs::last_write_time(e.path(), two_days_ago);
  }
  // A killed write's temporary file (its process gone) is removed when a run
  // next opens the cache; a live process's stays.
  const fs::path stale = dir / "cache" / "detections" / ".0123.det.tmp-99999999-0";
  const fs::path live =
      dir / "cache" / "detections" / fmt::format(".0123.det.tmp-{}-0", ::getpid());
  std::ofstream(stale) << "partial";
  std::ofstream(live) << "partial";
  EXPECT_EQ(run("b", " --set tracker.particles=60")["detections_from_cache"], 30);
  EXPECT_FALSE(fs::exists(stale));
  EXPECT_TRUE(fs::exists(live));
  fs::remove(live);
  for (const auto& e : fs::directory_iterator(dir / "cache" / "detections")) {
    EXPECT_GT(fs::last_write_time(e.path()), two_days_ago + std::chrono::hours(47)) << e.path();
  }
  EXPECT_EQ(ReadFile(dir / "a" / "det" / "det.txt"), ReadFile(dir / "b" / "det" / "det.txt"));
  // Each entry is stored compressed: "HCPFDET3", its label (a byte count,
  // then the scene's frame folder and the detector), the payload's size,
  // then zstd's frame of it, smaller than the payload (NCC's two maps of
  // floats).
  const std::string label = first["pixel_hash"].get<std::string>() + " ncc";
  for (const auto& e : fs::directory_iterator(dir / "cache" / "detections")) {
    const std::string bytes = ReadFile(e.path());
    ASSERT_GT(bytes.size(), 25 + label.size());
    EXPECT_EQ(bytes.substr(0, 8), "HCPFDET3");
    EXPECT_EQ(static_cast<uint8_t>(bytes[8]), label.size());
    EXPECT_EQ(bytes.substr(9, label.size()), label) << e.path();
    uint64_t payload = 0;
    std::memcpy(&payload, bytes.data() + 9 + label.size(), sizeof(payload));
    EXPECT_LT(bytes.size(), payload) << e.path();
  }
  // hcpf cache lists the outputs under their scene, by detector (they were
  // one line apart from every scene before they carried a label).
  const auto listed =
      RunCommand(std::string(HCPF_EXE) + " cache --cache " + (dir / "cache").string());
  EXPECT_NE(listed.output.find(first["pixel_hash"].get<std::string>() +
                               "\n      and its detector outputs: ncc 30 ("),
            std::string::npos)
      << listed.output;
  // Another detector option: other detections, none from the cache.
  EXPECT_EQ(run("c", " --set observation.ncc.min_correlation=0.95")["detections_from_cache"], 0);
  EXPECT_NE(ReadFile(dir / "a" / "det" / "det.txt"), ReadFile(dir / "c" / "det" / "det.txt"));
  // Another seed draws another scene: misses too.
  EXPECT_EQ(run("d", " --set seed=99")["detections_from_cache"], 0);
  // Another build of the program never reads this build's detections. The
  // detectors live in libhcpf_cli.so, which the `hcpf` launcher loads from
  // its own folder first, and the key names it by its GNU build ID (the
  // linker's hash of its contents, so a relink of changed code gives another):
  // a launcher copied next to a rebuilt library (here: a copy whose build ID
  // has one byte flipped, which still loads) misses every frame; next to an
  // unchanged copy of the library it reads them all, and so it does next to
  // a copy with a byte appended (the same code: keyed by the file's bytes, as
  // until 2026-12-07, that missed too). (Keyed by the launcher's bytes, as
  // until 2026-11-28, the rebuilt library's run read the old build's
  // detections.)
  const std::string build_id = ReadelfBuildId(HCPF_CLI_LIBRARY);
  ASSERT_EQ(build_id.size(), 40u) << "libhcpf_cli.so has no SHA-1 build ID";
  const auto run_with = [&](const std::string& folder, const std::string& change) {
    const fs::path bin = dir / folder;
    fs::create_directories(bin);
    fs::copy_file(HCPF_EXE, bin / "hcpf");
    fs::copy_file(HCPF_CLI_LIBRARY, bin / "libhcpf_cli.so");
    if (change == "append") {
      std::ofstream(bin / "libhcpf_cli.so", std::ios::app | std::ios::binary) << 'x';
    } else if (change == "build-id") {
      std::string bytes = ReadFile(bin / "libhcpf_cli.so");
      std::string id;
      for (size_t i = 0; i < build_id.size(); i += 2)
        id += static_cast<char>(std::stoi(build_id.substr(i, 2), nullptr, 16));
      const size_t at = bytes.find(id);
      EXPECT_NE(at, std::string::npos);
      EXPECT_EQ(bytes.find(id, at + 1), std::string::npos);
      bytes[at + id.size() - 1] = static_cast<char>(bytes[at + id.size() - 1] ^ 1);
      std::ofstream(bin / "libhcpf_cli.so", std::ios::binary | std::ios::trunc) << bytes;
    }
    std::string command = common + " --out " + (bin / "out").string();
    command.replace(0, std::string(HCPF_EXE).size(), (bin / "hcpf").string());
    const auto r = RunCommand(command);
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(ReadFile(dir / "a" / "det" / "det.txt"), ReadFile(bin / "out" / "det" / "det.txt"));
    return nlohmann::json::parse(ReadFile(bin / "out" / "manifest.json"))["detections_from_cache"];
  };
  EXPECT_EQ(run_with("same-build", ""), 30);
  EXPECT_EQ(run_with("byte-appended", "append"), 30);
  EXPECT_EQ(run_with("rebuilt", "build-id"), 0);
  // Another CPU, whose OpenCV kernels (NCC's matchTemplate here) run on other
  // instruction sets, as OPENCV_CPU_DISABLE makes this one: misses too (a
  // review: the key covered the code but not the CPU it dispatches to).
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx2")) {
    const auto r =
        RunCommand("OPENCV_CPU_DISABLE=AVX2 " + common + " --out " + (dir / "other-cpu").string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(nlohmann::json::parse(
                  ReadFile(dir / "other-cpu" / "manifest.json"))["detections_from_cache"],
              0);
  }
  // Damage three entries (one truncated, one with a byte of its label
  // flipped, one with a byte of its compressed payload flipped): all are
  // recomputed, and the detections are unchanged.
  fs::remove_all(dir / "cache" / "detections");
  EXPECT_EQ(run("f", "")["detections_from_cache"], 0);
  std::vector<fs::path> entries;
  for (const auto& e : fs::directory_iterator(dir / "cache" / "detections")) {
    entries.push_back(e.path());
  }
  std::sort(entries.begin(), entries.end());
  ASSERT_EQ(entries.size(), 30u);
  fs::resize_file(entries[0], fs::file_size(entries[0]) / 2);
  for (const auto& [entry, at] : {std::pair(entries[1], static_cast<uintmax_t>(20)),
                                  std::pair(entries[2], fs::file_size(entries[2]) - 20)}) {
    std::fstream f(entry, std::ios::in | std::ios::out | std::ios::binary);
    f.seekg(static_cast<std::streamoff>(at));
    const char was = static_cast<char>(f.get());
    f.seekp(static_cast<std::streamoff>(at));
    f.put(static_cast<char>(was ^ 0x5a));
  }
  const auto damaged = run("e", " --set tracker.particles=70");
  EXPECT_EQ(damaged["detections_from_cache"], 27) << "a damaged entry was read";
  EXPECT_EQ(ReadFile(dir / "a" / "det" / "det.txt"), ReadFile(dir / "e" / "det" / "det.txt"));
}

// observation.search: window: the detector searches around each filter's
// estimate of the previous frame, the tracker stepping with it. NCC then
// matches the model scaled to the filter's box inside the window, so its
// detections differ from the whole-frame search's, and the tracker still
// follows both targets.
TEST(RenderedRun, WindowedSearchFollowsTheFilters) {
  const fs::path dir = FreshDir("detector-window");
  const std::string common =
      std::string(HCPF_EXE) + " run " + testing::LibraryScenario("crossing") +
      " --set observation.source=rendered --set frames=90 --set observation.detector=ncc --cache " +
      (dir / "cache").string();
  for (const std::string search : {"frame", "window"}) {
    const auto r = RunCommand(common + " --set observation.search=" + search + " --out " +
                              (dir / search).string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto metrics = nlohmann::json::parse(ReadFile(dir / search / "metrics.json"));
    EXPECT_GT(metrics["filters"]["da_accuracy"].get<double>(), 0.8) << search;
    EXPECT_GT(metrics["detection"]["centre"]["recall"].get<double>(), 0.5) << search;
  }
  EXPECT_NE(ReadFile(dir / "frame" / "det" / "det.txt"),
            ReadFile(dir / "window" / "det" / "det.txt"));
  const std::string resolved = ReadFile(dir / "window" / "scenario.resolved.yaml");
  EXPECT_NE(resolved.find("search: window"), std::string::npos);
}

// Issue 12 (part): tracker.camera_motion moves every particle by the
// camera's frame-to-frame motion. On `climb` (detection level, the camera
// climbs 100 -> 400 m with 0.8 px shake) the corner error of applying no
// motion is the camera's own motion (over 1 px a frame); the oracle's
// similarity leaves only the homography's projective part (an oblique
// camera), a small fraction of that; the scene filter on the oracle
// homography lands between the two. Every run writes camera_motion.csv (one
// row per frame from the second, numbered from 1 as filters.csv is: 2 … 120)
// and the summary in metrics.json.
TEST(CameraMotion, ModesAreScoredAgainstTheTrueMotion) {
  const fs::path dir = FreshDir("camera-motion");
  const std::string common =
      std::string(HCPF_EXE) + " run " + testing::LibraryScenario("climb") +
      " --set frames=120 --set camera.path.1.frame=60 --set camera.path.2.frame=119";
  std::map<std::string, double> mean;
  std::map<std::string, double> floor;
  for (const std::string mode : {"none", "oracle", "scene_filter"}) {
    const std::string sets =
        " --set tracker.camera_motion=" + mode +
        (mode == "scene_filter" ? " --set tracker.scene_filter.evidence=oracle" : "");
    const auto r = RunCommand(common + sets + " --out " + (dir / mode).string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto metrics = nlohmann::json::parse(ReadFile(dir / mode / "metrics.json"));
    EXPECT_EQ(metrics["camera_motion"]["mode"], mode);
    EXPECT_EQ(metrics["camera_motion"]["frames"], 119);
    mean[mode] = metrics["camera_motion"]["mean_px"].get<double>();
    floor[mode] = metrics["camera_motion"]["floor"]["mean_px"].get<double>();
    const std::string csv = ReadFile(dir / mode / "camera_motion.csv");
    EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 120) << "header + 119 frames";
    EXPECT_TRUE(csv.starts_with("frame,tx_px,ty_px,log_scale,rotation_rad,error_px,ess,floor_px\n"))
        << csv.substr(0, 80);
    EXPECT_NE(csv.find("\n2,"), std::string::npos) << "the first row is frame 2";
    EXPECT_NE(csv.find("\n120,"), std::string::npos) << "the last row is frame 120";
    EXPECT_EQ(csv.find("\n1,"), std::string::npos) << "frame 1 has no motion";
    // The same numbering in filters.csv, where a filter lives to the end
    // (without compensation both are lost on this shortened climb: by frame
    // 84 on the frames of 2026-12-07, whose roll no longer jumps).
    const std::string filters = ReadFile(dir / mode / "filters.csv");
    if (mode != "none") {
      EXPECT_NE(filters.find("\n120,"), std::string::npos) << "the same numbering";
    }
    EXPECT_EQ(filters.find("\n121,"), std::string::npos) << "the same numbering";
  }
  EXPECT_GT(mean["none"], 1.0);
  EXPECT_LT(mean["oracle"], 0.2 * mean["none"]);
  EXPECT_LT(mean["scene_filter"], mean["none"]);
  EXPECT_GT(mean["scene_filter"], mean["oracle"]);
  // The floor (the similarity closest to the true motion at the corners)
  // depends on the frames only, and nothing similar beats it, not even the
  // oracle (a least-squares fit over a 10 x 10 grid of the image).
  EXPECT_EQ(floor["none"], floor["oracle"]);
  EXPECT_EQ(floor["none"], floor["scene_filter"]);
  EXPECT_GT(floor["none"], 0.0);
  EXPECT_LT(floor["none"], mean["oracle"]);
  // The scene filter is deterministic: a second run gives the same files.
  const auto r = RunCommand(common +
                            " --set tracker.camera_motion=scene_filter --set "
                            "tracker.scene_filter.evidence=oracle --out " +
                            (dir / "again").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(ReadFile(dir / "scene_filter" / "camera_motion.csv"),
            ReadFile(dir / "again" / "camera_motion.csv"));
  EXPECT_EQ(ReadFile(dir / "scene_filter" / "tracks.txt"), ReadFile(dir / "again" / "tracks.txt"));
  // A resampler the scene filter cannot use is bad input naming the key.
  const auto bad =
      RunCommand(std::string(HCPF_EXE) + " validate " + testing::LibraryScenario("climb") +
                 " --set tracker.scene_filter.resampling=charged");
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("tracker.scene_filter.resampling"), std::string::npos) << bad.output;
}

// Issue 12's climb target, on the scenario's own seed: the thesis's filter,
// hierarchical (scene filter on the rendered frames' corners) and charged,
// keeps both vehicles through the climb and the crossing: DA accuracy >= 0.97
// and MOTA > 0 (this seed: 1.000 and 0.986); the same charged filters without
// camera motion lag the zoom and lose their targets (0.65 and -0.35). The
// 20-seed intervals are scenarios/sweeps/climb-hierarchical.yaml
// (docs/tracker.md). The run is deterministic, so the bounds are the issue's
// targets, not a tolerance.
TEST(CameraMotion, HierarchicalChargedFilterMeetsTheClimbTarget) {
  const fs::path dir = FreshDir("camera-motion-climb");
  const std::string common = std::string(HCPF_EXE) + " run " + testing::LibraryScenario("climb") +
                             " --set observation.source=rendered"
                             " --set tracker.scene_filter.evidence=image"
                             " --set tracker.resampling.method=charged";
  std::map<std::string, nlohmann::json> metrics;
  for (const std::string mode : {"none", "scene_filter"}) {
    const auto r = RunCommand(common + " --set tracker.camera_motion=" + mode + " --out " +
                              (dir / mode).string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    metrics[mode] = nlohmann::json::parse(ReadFile(dir / mode / "metrics.json"));
  }
  EXPECT_GE(metrics["scene_filter"]["filters"]["da_accuracy"].get<double>(), 0.97);
  EXPECT_GT(metrics["scene_filter"]["mot"]["MOTA"].get<double>(), 0.0);
  EXPECT_EQ(metrics["scene_filter"]["filters"]["hijack_rate"].get<double>(), 0.0);
  EXPECT_LT(metrics["none"]["mot"]["MOTA"].get<double>(), 0.0);
  EXPECT_LT(metrics["none"]["filters"]["da_accuracy"].get<double>(),
            metrics["scene_filter"]["filters"]["da_accuracy"].get<double>());
}

// Issue 12's camera-motion targets, with the scene filter's perspective
// stage (tracker.perspective.enabled): on rendered climb the mean error is
// <= 0.07 px and below the common recipe's (RANSAC similarity on the same
// tracks: 0.0734; with the stage 0.0690, the similarity floor 0.0656); on
// the strong-motion scene mean and p95 are both below the recipe's (0.535 /
// 0.924 against 0.596 / 1.011). Deterministic runs: the bounds are the
// issue's targets. The section is written to the resolved YAML only when it
// takes effect, and bad combinations name the key.
TEST(CameraMotion, PerspectiveStageMeetsTheCameraMotionTargets) {
  const fs::path dir = FreshDir("camera-motion-perspective");
  std::map<std::string, nlohmann::json> camera;
  for (const std::string scene : {"climb", "climb-yaw-dive"}) {
    for (const std::string mode : {"ransac", "perspective"}) {
      const std::string sets = mode == "ransac" ? " --set tracker.camera_motion=ransac"
                                                : " --set tracker.camera_motion=scene_filter"
                                                  " --set tracker.perspective.enabled=true";
      const fs::path out = dir / (scene + "-" + mode);
      const auto r = RunCommand(std::string(HCPF_EXE) + " run " + testing::LibraryScenario(scene) +
                                " --set observation.source=rendered"
                                " --set tracker.scene_filter.evidence=image" +
                                sets + " --out " + out.string());
      ASSERT_EQ(r.exit_code, 0) << r.output;
      camera[scene + "-" + mode] =
          nlohmann::json::parse(ReadFile(out / "metrics.json")).at("camera_motion");
      const std::string resolved = ReadFile(out / "scenario.resolved.yaml");
      EXPECT_EQ(resolved.find("perspective:") != std::string::npos, mode == "perspective")
          << resolved;
    }
  }
  const auto mean = [&](const std::string& k) { return camera[k]["mean_px"].get<double>(); };
  const auto p95 = [&](const std::string& k) { return camera[k]["p95_px"].get<double>(); };
  EXPECT_LE(mean("climb-perspective"), 0.07);
  EXPECT_LT(mean("climb-perspective"), mean("climb-ransac"));
  EXPECT_GE(mean("climb-perspective"),
            camera["climb-perspective"]["floor"]["mean_px"].get<double>());
  EXPECT_LT(mean("climb-yaw-dive-perspective"), mean("climb-yaw-dive-ransac"));
  EXPECT_LT(p95("climb-yaw-dive-perspective"), p95("climb-yaw-dive-ransac"));

  for (const std::string bad :
       {" --set tracker.camera_motion=ransac --set tracker.perspective.enabled=true",
        " --set tracker.camera_motion=scene_filter --set tracker.scene_filter.evidence=oracle"
        " --set tracker.perspective.enabled=true",
        " --set tracker.perspective.inlier_px=0"}) {
    const auto r =
        RunCommand(std::string(HCPF_EXE) + " validate " + testing::LibraryScenario("climb") + bad);
    EXPECT_EQ(r.exit_code, 2) << bad << "\n" << r.output;
    EXPECT_NE(r.output.find("tracker.perspective"), std::string::npos) << r.output;
  }
}

TEST(CameraMotion, ImageEvidenceFeedsTheSceneFilterAndTheRansacBaseline) {
  // Rendered climb, corners tracked by pyramidal LK (issue 12 items 2 and 3).
  // The oracle mode (a least-squares similarity of the true motion on a
  // grid, not the floor: docs/tracker.md) is the reference here; both
  // estimators from the pixels must land within 25 % of it (on the full
  // climb both are within 3 %, docs/tracker.md), far below no compensation.
  const fs::path dir = FreshDir("camera-motion-image");
  const std::string common =
      std::string(HCPF_EXE) + " run " + testing::LibraryScenario("climb") +
      " --set frames=120 --set camera.path.1.frame=60 --set camera.path.2.frame=119"
      " --set observation.source=rendered --set tracker.scene_filter.evidence=image";
  std::map<std::string, double> mean;
  for (const std::string mode : {"oracle", "ransac", "scene_filter"}) {
    const auto r = RunCommand(common + " --set tracker.camera_motion=" + mode + " --out " +
                              (dir / mode).string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto metrics = nlohmann::json::parse(ReadFile(dir / mode / "metrics.json"));
    EXPECT_EQ(metrics["camera_motion"]["mode"], mode);
    EXPECT_EQ(metrics["camera_motion"]["frames"], 119);
    mean[mode] = metrics["camera_motion"]["mean_px"].get<double>();
  }
  EXPECT_LT(mean["ransac"], 1.25 * mean["oracle"]);
  EXPECT_LT(mean["scene_filter"], 1.25 * mean["oracle"]);
  // tracker.point_tracker and tracker.ransac reach the run: two corners are
  // too few for RANSAC, so every frame falls back to the identity (an error of
  // pixels, not hundredths). The resolved YAML holds each section only when it
  // takes effect (the oracle run tracks no points).
  const auto few = RunCommand(common +
                              " --set tracker.camera_motion=ransac"
                              " --set tracker.point_tracker.max_corners=2"
                              " --set tracker.ransac.threshold_px=3 --out " +
                              (dir / "few").string());
  ASSERT_EQ(few.exit_code, 0) << few.output;
  const auto few_metrics = nlohmann::json::parse(ReadFile(dir / "few" / "metrics.json"));
  EXPECT_GT(few_metrics["camera_motion"]["mean_px"].get<double>(), 10 * mean["oracle"]);
  const std::string resolved = ReadFile(dir / "few" / "scenario.resolved.yaml");
  EXPECT_NE(resolved.find("max_corners: 2"), std::string::npos) << resolved;
  EXPECT_NE(resolved.find("threshold_px: 3"), std::string::npos) << resolved;
  const std::string oracle_resolved = ReadFile(dir / "oracle" / "scenario.resolved.yaml");
  EXPECT_EQ(oracle_resolved.find("point_tracker"), std::string::npos);
  EXPECT_EQ(oracle_resolved.find("ransac:"), std::string::npos);
  // Image evidence without rendered frames, and RANSAC on the oracle
  // homography, are bad input naming the key.
  for (const std::string& sets : {std::string(" --set tracker.camera_motion=scene_filter"
                                              " --set tracker.scene_filter.evidence=image"),
                                  std::string(" --set tracker.camera_motion=ransac"
                                              " --set tracker.scene_filter.evidence=oracle")}) {
    const auto bad =
        RunCommand(std::string(HCPF_EXE) + " validate " + testing::LibraryScenario("climb") + sets);
    EXPECT_EQ(bad.exit_code, 2) << sets << "\n" << bad.output;
    EXPECT_NE(bad.output.find("tracker.scene_filter.evidence"), std::string::npos) << bad.output;
  }
}

// A frame cache folder that cannot be made fails the run before any frame is
// stored, naming the folder and the ways out; --no-cache then runs. Here it
// is under /proc, where no one can make a folder; the default cache of a
// service user whose $HOME is absent or read-only fails the same way (found
// running as nobody, HOME=/nonexistent: "cannot create frame cache
// /nonexistent/.cache/hcpf/frames/...: Permission denied", and nothing more).
TEST(RenderedRun, AFrameCacheThatCannotBeMadeSaysHowToChooseAnother) {
  const fs::path dir = FreshDir("cache-blocked");
  const fs::path cache = "/proc/hcpf-no-such-folder/frames";
  const std::string run = std::string(HCPF_EXE) + " run " + testing::LibraryScenario("crossing") +
                          " --set observation.source=rendered --set frames=16"
                          " --set 'camera.resolution=[64, 48]' --out " +
                          (dir / "o").string();
  auto r = RunCommand(run + " --cache " + cache.string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("cannot create frame cache " + cache.string()), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("--cache DIR or HCPF_CACHE_DIR, or render without one: --no-cache"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir / "o"));
  r = RunCommand(run + " --no-cache");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

// A detector needs rendered frames and, with target models, filters born
// from ground truth: both are bad input naming the keys, for validate and run.
TEST(RenderedRun, DetectorWithoutItsPrerequisitesIsBadInput) {
  const fs::path dir = FreshDir("detector-bad");
  const std::string scenario = testing::LibraryScenario("crossing");
  for (const std::string& sets :
       {std::string(" --set observation.detector=ncc"),
        std::string(" --set observation.detector=colour --set observation.source=rendered"
                    " --set tracker.init=detections")}) {
    for (const std::string& command :
         {std::string(HCPF_EXE) + " validate " + scenario + sets,
          std::string(HCPF_EXE) + " run " + scenario + sets + " --out " + (dir / "o").string()}) {
      const auto r = RunCommand(command);
      EXPECT_EQ(r.exit_code, 2) << command << "\n" << r.output;
      EXPECT_NE(r.output.find("observation.detector"), std::string::npos) << r.output;
      EXPECT_NE(r.output.find(sets.find("init") != std::string::npos ? "tracker.init"
                                                                     : "observation.source"),
                std::string::npos)
          << r.output;
      EXPECT_FALSE(fs::exists(dir / "o"));
    }
  }
}

// Issue 15 item 9: renderer.write_frames / write_depth / write_instance_ids
// were documented for `hcpf run` and ignored. A detection-level run that
// writes its frames keeps its analytic truth, so its metrics are unchanged.
TEST(RenderedRun, WriteFramesKeysWriteTheRunsFrames) {
  const fs::path dir = FreshDir("run-write-frames");
  const std::string common = std::string(HCPF_EXE) + " run " +
                             testing::LibraryScenario("crossing") +
                             " --set frames=16 --set 'camera.resolution=[160, 120]' --no-cache";
  auto r = RunCommand(common + " --out " + (dir / "plain").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = RunCommand(common +
                 " --set renderer.write_frames=true --set renderer.write_depth=true"
                 " --set renderer.write_instance_ids=true --out " +
                 (dir / "frames").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* name : {"000001.png", "000006.png", "000001_depth.png", "000006_ids.png"}) {
    EXPECT_TRUE(fs::exists(dir / "frames" / "frames" / name)) << name;
  }
  EXPECT_FALSE(fs::exists(dir / "plain" / "frames"));
  EXPECT_EQ(ReadFile(dir / "plain" / "metrics.json"), ReadFile(dir / "frames" / "metrics.json"));
  EXPECT_EQ(ReadFile(dir / "plain" / "gt.json"), ReadFile(dir / "frames" / "gt.json"));
  const auto manifest = nlohmann::json::parse(ReadFile(dir / "frames" / "manifest.json"));
  EXPECT_EQ(manifest["ground_truth"], "analytic");
  // Depth only: no colour frames.
  r = RunCommand(common + " --set renderer.write_depth=true --out " + (dir / "depth").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir / "depth" / "frames" / "000003_depth.png"));
  EXPECT_FALSE(fs::exists(dir / "depth" / "frames" / "000003.png"));
  // crossing's camera is ~120 m from the ground: past the 65.5 m of 1 mm
  // units, so the run says so and names the unit that holds it; at 10 mm
  // nothing is past it (every pixel was written 65535, unsaid: a review).
  EXPECT_NE(r.output.find("pixel(s) lie beyond the depth PNG's 65535 units of "
                          "renderer.depth_unit_mm 1 (65.535 m) and are written 65535; "
                          "renderer.depth_unit_mm: 10 holds 655.35 m"),
            std::string::npos)
      << r.output;
  r = RunCommand(common +
                 " --set renderer.write_depth=true --set renderer.depth_unit_mm=10 --out " +
                 (dir / "depth-cm").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("depth PNG"), std::string::npos) << r.output;
}

}  // namespace
}  // namespace hcpf

namespace hcpf {
namespace {

TEST(RenderCommand, WritesFramesTruthAndContactSheet) {
  const fs::path dir = testing::FreshDir("render-command");
  const std::string scenario = testing::LibraryScenario("bridge-three");
  const auto r = testing::RunCommand(std::string(HCPF_EXE) + " render " + scenario +
                                     " --set frames=30 --set 'camera.resolution=[160, 120]'"
                                     " --no-cache --sheet-frames 4 --out " +
                                     (dir / "r").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* f :
       {"frames/000001.png", "frames/000030.png", "gt/gt.txt", "seqinfo.ini", "gt.json",
        "contact_sheet.png", "scenario.resolved.yaml", "manifest.json"}) {
    EXPECT_TRUE(fs::exists(dir / "r" / f)) << f;
  }
  EXPECT_FALSE(fs::exists(dir / "r" / "frames" / "000031.png"));
  // gt.json says where visibility comes from, and the counts are there.
  const auto gt = nlohmann::json::parse(testing::ReadFile(dir / "r" / "gt.json"));
  EXPECT_EQ(gt["source"], "rendered");
  int64_t visible_pixels = 0;
  for (const auto& object : gt["frames"][0]["objects"]) {
    EXPECT_LE(object["pixels_visible"].get<int64_t>(), object["pixels_total"].get<int64_t>());
    visible_pixels += object["pixels_visible"].get<int64_t>();
  }
  EXPECT_GT(visible_pixels, 0);
  // With a cache: the second render reads every frame and its manifest names
  // the renderer the first noted there (no GL context of its own).
  const std::string cached = std::string(HCPF_EXE) + " render " + scenario +
                             " --set frames=30 --set 'camera.resolution=[160, 120]' --cache " +
                             (dir / "cache").string() + " --out ";
  for (const char* out : {"c1", "c2"}) {
    const auto c = testing::RunCommand(cached + (dir / out).string());
    ASSERT_EQ(c.exit_code, 0) << c.output;
  }
  const auto first = nlohmann::json::parse(testing::ReadFile(dir / "c1" / "manifest.json"));
  const auto second = nlohmann::json::parse(testing::ReadFile(dir / "c2" / "manifest.json"));
  EXPECT_FALSE(first.contains("frame_cache_renderers")) << "nothing came from the cache";
  EXPECT_EQ(second["frames_from_cache"], 30);
  EXPECT_TRUE(second["gl_renderer"].is_null());
  ASSERT_EQ(second["frame_cache_renderers"].size(), 1U) << second.dump();
  EXPECT_NE(second["frame_cache_renderers"][0].get<std::string>().find(
                first["gl_renderer"]["renderer"].get<std::string>()),
            std::string::npos);
  EXPECT_EQ(testing::ReadFile(dir / "c1" / "gt.json"), testing::ReadFile(dir / "c2" / "gt.json"));
  // --threads 3: frames made and their PNG files written three at a time,
  // rendered (no cache) or read from the cache; every file the same as with
  // one thread (the manifest aside: timings).
  const std::string args = " --set frames=30 --set 'camera.resolution=[160, 120]' --sheet-frames 4";
  for (const auto& [out, cache] : std::vector<std::pair<std::string, std::string>>{
           {"t3", " --no-cache"}, {"t3c", " --cache " + (dir / "cache").string()}}) {
    const auto t = testing::RunCommand(std::string(HCPF_EXE) + " render " + scenario + args +
                                       cache + " --threads 3 --out " + (dir / out).string());
    ASSERT_EQ(t.exit_code, 0) << t.output;
    int files = 0;
    for (const auto& e : fs::recursive_directory_iterator(dir / "r")) {
      if (!e.is_regular_file() || e.path().filename() == "manifest.json") continue;
      const fs::path rel = fs::relative(e.path(), dir / "r");
      EXPECT_EQ(testing::ReadFile(dir / out / rel), testing::ReadFile(e.path())) << out << rel;
      ++files;
    }
    EXPECT_EQ(files, 35) << out;  // 30 frames, gt.txt, gt.json, seqinfo, sheet, resolved YAML
  }
  // A bad scenario key is bad input, and nothing is written.
  const auto bad =
      testing::RunCommand(std::string(HCPF_EXE) + " render " + scenario +
                          " --set renderer.backend=vulkan --out " + (dir / "bad").string());
  EXPECT_EQ(bad.exit_code, 2) << bad.output;
  EXPECT_NE(bad.output.find("renderer.backend"), std::string::npos) << bad.output;
  EXPECT_FALSE(fs::exists(dir / "bad"));
}

}  // namespace
}  // namespace hcpf
