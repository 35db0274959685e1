// observation.detector: file: another program's detections (a MOTChallenge
// det.txt) read at load time, checked row by row, pinned by their digest in
// the resolved YAML.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "../src/rendering_check.h"
#include "hcpf/core/error.h"
#include "hcpf/core/text_file.h"
#include "support/process.h"
#include "support/test_scenarios.h"

namespace hcpf::scenarios {
namespace {

namespace fs = std::filesystem;
using testing::kMinimal;

// kMinimal (20 frames) on rendered frames with detector: file reading `path`.
std::vector<Override> FileDetector(const fs::path& path) {
  return {{"observation.source", "rendered"},
          {"observation.detector", "file"},
          {"observation.file.path", path.string()}};
}

// `overrides` and one more.
std::vector<Override> With(std::vector<Override> overrides, Override more) {
  overrides.push_back(std::move(more));
  return overrides;
}

// The message of the InputError loading throws ("" when it loads).
std::string FileLoadError(const std::string& text, const std::vector<Override>& overrides,
                          const std::string& name = "s.yaml") {
  try {
    LoadScenarioText(text, name, overrides);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A det.txt holding `text` in a fresh folder named after `name`.
fs::path DetFile(const std::string& name, const std::string& text) {
  const fs::path det = hcpf::testing::FreshDir(name) / "det.txt";
  WriteTextFile(det.string(), text);
  return det;
}

TEST(DetectionFile, RowsAreReadByFrameInZeroBasedPixelsAboveMinScore) {
  // Frames and pixels 1-based; ids ignored (-1 repeats); a row scoring below
  // min_score (0.1) left out; frame 20 is the scenario's last.
  const fs::path det = DetFile("detection-file",
                               "1,-1,11,21,30,15,0.9\n"
                               "1,-1,101,51,8,4,0.05\n"
                               "3,-1,1.5,1,2,2,0.4\n"
                               "20,-1,5,5,10,10,1\n");
  std::vector<Override> overrides = FileDetector(det);
  overrides.push_back({"observation.file.min_score", "0.1"});
  const Scenario s = LoadScenarioText(kMinimal, "s.yaml", overrides);
  ASSERT_TRUE(s.observation.from_file());
  EXPECT_FALSE(s.observation.model_based());
  ASSERT_NE(s.observation.file.frames, nullptr);
  const auto& frames = *s.observation.file.frames;
  ASSERT_EQ(frames.size(), 20u);
  ASSERT_EQ(frames[0].size(), 1u);
  EXPECT_EQ(frames[0][0].box, (BoxPx{10, 20, 30, 15}));
  EXPECT_EQ(frames[0][0].score, 0.9);
  EXPECT_FALSE(frames[0][0].target.has_value());
  EXPECT_TRUE(frames[1].empty());
  ASSERT_EQ(frames[2].size(), 1u);
  EXPECT_EQ(frames[2][0].box, (BoxPx{0.5, 0, 2, 2}));
  ASSERT_EQ(frames[19].size(), 1u);
  EXPECT_EQ(frames[19][0].score, 1.0);
  EXPECT_EQ(s.observation.file.left_out, 1);  // said by the run
  // The path held absolute; the digest, XXH3-128 of the content, 32 hex digits.
  EXPECT_EQ(s.observation.file.path, fs::weakly_canonical(det).string());
  ASSERT_EQ(s.observation.file.digest.size(), 32u);
  EXPECT_EQ(s.observation.file.digest.find_first_not_of("0123456789abcdef"), std::string::npos);

  // The resolved YAML writes the section, digest included, and reads back to
  // the same scenario.
  const std::string resolved = ToResolvedYaml(s);
  EXPECT_NE(resolved.find("digest: \"" + s.observation.file.digest + "\""), std::string::npos)
      << resolved;
  const Scenario again = LoadScenarioText(resolved, "scenario.resolved.yaml");
  EXPECT_EQ(ToResolvedYaml(again), resolved);
  EXPECT_EQ(*again.observation.file.frames, frames);

  // Another content is another run (config hash), and the resolved YAML of
  // the old content no longer loads: the file is not what it was run with.
  WriteTextFile(det.string(), "1,-1,11,21,30,15,0.8\n");
  const Scenario changed = LoadScenarioText(kMinimal, "s.yaml", overrides);
  EXPECT_NE(ConfigHash(changed), ConfigHash(s));
  const std::string error = FileLoadError(resolved, {}, "scenario.resolved.yaml");
  EXPECT_NE(error.find("scenario.resolved.yaml:"), std::string::npos) << error;
  EXPECT_NE(error.find("observation.file.digest"), std::string::npos) << error;
  EXPECT_NE(error.find("expected " + changed.observation.file.digest), std::string::npos) << error;
  EXPECT_NE(error.find("found \"" + s.observation.file.digest + "\""), std::string::npos) << error;
}

// Checked, then of no effect, with another detector: not written, so not
// part of the run's identity (as the options of a detector not chosen).
TEST(DetectionFile, WithAnotherDetectorThePathIsCheckedAndNotWritten) {
  const fs::path dir = hcpf::testing::FreshDir("detection-file-unused");
  const fs::path det = dir / "det.txt";
  WriteTextFile(det.string(), "1,-1,11,21,30,15,0.9\n");
  const Scenario plain = LoadScenarioText(kMinimal, "s.yaml", {});
  const Scenario s =
      LoadScenarioText(kMinimal, "s.yaml", {{"observation.file.path", det.string()}});
  EXPECT_EQ(s.observation.file.frames, nullptr);
  EXPECT_EQ(ToResolvedYaml(s), ToResolvedYaml(plain));
  const std::string missing =
      FileLoadError(kMinimal, {{"observation.file.path", (dir / "none.txt").string()}});
  EXPECT_NE(missing.find("observation.file.path: expected the path of an existing det.txt"),
            std::string::npos)
      << missing;
}

TEST(DetectionFile, BadRowsAndRulesAcrossKeysAreRejectedWhereTheyAre) {
  const fs::path dir = hcpf::testing::FreshDir("detection-file-bad");
  const auto file = [&](const std::string& name, const std::string& text) {
    WriteTextFile((dir / name).string(), text);
    return dir / name;
  };
  const fs::path good = file("good.txt", "1,-1,11,21,30,15,0.9\n");
  struct Case {
    std::string name;
    std::vector<Override> overrides;
    std::vector<std::string> must_contain;
  };
  const fs::path beyond = file("beyond.txt", "1,-1,11,21,30,15,0.9\n21,-1,11,21,30,15,0.9\n");
  const fs::path flat = file("flat.txt", "1,-1,11,21,30,0,0.9\n");
  const fs::path far = file("far.txt", "1,-1,1e9,21,30,4,0.9\n");
  const fs::path loud = file("loud.txt", "1,-1,11,21,30,15,0.5\n2,-1,11,21,30,15,7.5\n");
  const fs::path low = file("low.txt", "1,-1,11,21,30,15,0.5\n2,-1,11,21,30,15,-0.25\n");
  const fs::path words = file("words.txt", "1,-1,11,21,thirty,15,0.9\n");
  std::vector<Case> cases = {
      {"FrameBeyondTheScenario",
       FileDetector(beyond),
       {beyond.string() + ":2:1", "a frame in 1..20"}},
      {"ZeroHeight", FileDetector(flat), {flat.string() + ":1:6", "column 6 (height)"}},
      {"FarCoordinate",
       FileDetector(far),
       {far.string() + ":1:3", "column 3 (left)", "within 1e+07 px"}},
      {"NotANumber", FileDetector(words), {words.string() + ":1:", "\"thirty\""}},
      // The particle filter weighs each detection by its score.
      {"ScoreOutsideTheUnitInterval",
       FileDetector(loud),
       {loud.string() + ":2:7", "column 7 (score)", "a score in [0, 1]",
        "tracker.likelihood.use_scores", "found 7.5"}},
      {"NegativeScore",
       With(FileDetector(low), {"observation.file.min_score", "-1"}),
       {low.string() + ":2:7", "use_scores: false, or an observation.file.min_score above -0.25",
        "found -0.25"}},
      {"NoPath",
       {{"observation.source", "rendered"}, {"observation.detector", "file"}},
       {"observation.file.path", "the det.txt to read", "not written"}},
      {"OnSimulatedFrames",
       {{"observation.detector", "file"}, {"observation.file.path", good.string()}},
       {"observation.detector", "observation.source: rendered", "\"file\" with"}},
      {"SearchWindow",
       With(FileDetector(good), {"observation.search", "window"}),
       {"observation.search", "window with observation.detector: file"}},
      {"MapLikelihood",
       With(FileDetector(good), {"tracker.likelihood.model", "map"}),
       {"tracker.likelihood.model", "map with observation.detector: file"}},
      {"NotAFusedDetector",
       {{"observation.source", "rendered"}, {"observation.detectors", "[diff, file]"}},
       {"observation.detectors[1]", "\"file\""}},
      {"MinScoreNotANumber",
       With(FileDetector(good), {"observation.file.min_score", "high"}),
       {"observation.file.min_score", "a number"}},
      {"UnknownKey",
       With(FileDetector(good), {"observation.file.pth", "x"}),
       {"observation.file.pth"}},
      // With labels, column 2 names a target of the scenario (1 or 2), or -1.
      {"LabelNotATarget",
       With(FileDetector(file("stranger.txt", "1,2,11,21,30,15,0.9\n1,3,11,21,30,15,0.9\n")),
            {"observation.file.labels", "true"}),
       {"stranger.txt:2:2", "column 2 (id)", "one of the targets (1, 2), or -1", "found 3"}},
      {"LabelsWithoutGroundTruthInit",
       With(With(FileDetector(good), {"observation.file.labels", "true"}),
            {"tracker.init", "detections"}),
       {"observation.file.labels", "tracker.init: ground_truth",
        "true with tracker.init: detections"}},
      {"ReacquireWithoutLabels",
       With(FileDetector(good), {"tracker.management.reacquire", "own_detections"}),
       {"tracker.management.reacquire",
        "own_detections with observation.detector: file and "
        "file.labels: false"}},
  };
  for (const Case& c : cases) {
    const std::string error = FileLoadError(kMinimal, c.overrides);
    ASSERT_FALSE(error.empty()) << "accepted: " << c.name;
    for (const std::string& part : c.must_contain) {
      EXPECT_NE(error.find(part), std::string::npos)
          << c.name << ": lacks \"" << part << "\"\n  message: " << error;
    }
  }
  // What makes such files acceptable: scores not weighed, or the row left
  // out.
  std::vector<Override> unweighed = FileDetector(loud);
  unweighed.push_back({"tracker.likelihood.use_scores", "false"});
  EXPECT_EQ(FileLoadError(kMinimal, unweighed), "");
  std::vector<Override> cut = FileDetector(low);
  cut.push_back({"observation.file.min_score", "-0.2"});
  EXPECT_EQ(FileLoadError(kMinimal, cut), "");
  EXPECT_EQ(LoadScenarioText(kMinimal, "s.yaml", cut).observation.file.left_out, 1);
  // An external tracker reads the scores as they are.
  std::vector<Override> external = FileDetector(loud);
  external.push_back({"tracker.type", "external"});
  external.push_back({"tracker.command", "[/bin/cat]"});
  EXPECT_EQ(FileLoadError(kMinimal, external), "");
}

TEST(DetectionFile, WithLabelsColumnTwoNamesTheTargetEachDetectionIsOf) {
  // Target 2, a detection of none (-1), target 1; an id that names no target
  // (7) is accepted without labels, where ids are ignored.
  const fs::path det = DetFile("detection-file-labels",
                               "1,2,11,21,30,15,0.9\n"
                               "1,-1,101,51,8,4,0.5\n"
                               "2,1,5,5,10,10,1\n"
                               "3,7,5,5,10,10,1\n");
  const Scenario plain = LoadScenarioText(kMinimal, "s.yaml", FileDetector(det));
  for (const auto& frame : *plain.observation.file.frames) {
    for (const Detection& d : frame) EXPECT_FALSE(d.target.has_value());
  }
  EXPECT_FALSE(plain.observation.labelled());
  WriteTextFile(det.string(),
                "1,2,11,21,30,15,0.9\n"
                "1,-1,101,51,8,4,0.5\n"
                "2,1,5,5,10,10,1\n");
  const Scenario s = LoadScenarioText(kMinimal, "s.yaml",
                                      With(FileDetector(det), {"observation.file.labels", "true"}));
  EXPECT_TRUE(s.observation.labelled());
  EXPECT_FALSE(s.observation.model_based());  // no models: no windows, no maps
  const auto& frames = *s.observation.file.frames;
  ASSERT_EQ(frames[0].size(), 2u);
  EXPECT_EQ(frames[0][0].target, ObjectId{2});
  EXPECT_FALSE(frames[0][1].target.has_value());
  ASSERT_EQ(frames[1].size(), 1u);
  EXPECT_EQ(frames[1][0].target, ObjectId{1});
  // Labelled detections find a filter's target again.
  std::vector<Override> reacquire = FileDetector(det);
  reacquire.push_back({"observation.file.labels", "true"});
  reacquire.push_back({"tracker.management.reacquire", "own_detections"});
  EXPECT_EQ(FileLoadError(kMinimal, reacquire), "");
  EXPECT_NE(ToResolvedYaml(s).find("labels: true"), std::string::npos);
  // An external tracker gets each detection's target too (its "target").
  std::vector<Override> external = FileDetector(det);
  external.push_back({"observation.file.labels", "true"});
  external.push_back({"tracker.type", "external"});
  external.push_back({"tracker.command", "[/bin/cat]"});
  EXPECT_EQ(FileLoadError(kMinimal, external), "");
}

TEST(DetectionFile, WithAnotherDetectorTheRenderingIsCheckedAndNotWritten) {
  // Like the path: a folder that is no rendering is refused whatever the
  // detector; with another detector a good one has no effect.
  const fs::path dir = hcpf::testing::FreshDir("detection-file-rendering-unit");
  const std::vector<Override> rendered = {{"observation.source", "rendered"}};
  const std::string error =
      FileLoadError(kMinimal, With(rendered, {"observation.file.rendering", dir.string()}));
  EXPECT_NE(error.find("observation.file.rendering"), std::string::npos) << error;
  EXPECT_NE(error.find("holding manifest.json"), std::string::npos) << error;
  WriteTextFile((dir / "manifest.json").string(), "{}");
  const Scenario s = LoadScenarioText(kMinimal, "s.yaml",
                                      With(rendered, {"observation.file.rendering", dir.string()}));
  EXPECT_TRUE(s.observation.file.rendering.empty());
  EXPECT_EQ(ToResolvedYaml(s).find("rendering"), std::string::npos);
}

TEST(DetectionFile, ARenderingsManifestThatIsNotJsonIsRefusedAtItsFile) {
  const fs::path dir = hcpf::testing::FreshDir("detection-file-rendering-json");
  WriteTextFile((dir / "det.txt").string(), "1,-1,11,21,30,15,0.9\n");
  WriteTextFile((dir / "manifest.json").string(), "{\"pixel_hash\": ");
  const std::string error = FileLoadError(
      kMinimal, With(FileDetector(dir / "det.txt"), {"observation.file.rendering", dir.string()}));
  EXPECT_NE(error.find((dir / "manifest.json").string() + ":1:1"), std::string::npos) << error;
  EXPECT_NE(error.find("expected a manifest.json in JSON"), std::string::npos) << error;
}

// Values that cannot be what they name are said to be so (a bad-input
// audit: a digest "xyz" was "the digest before the file changed", a pixel
// hash "zz" "the frames of another rendering", and a file given as the
// rendering folder "afile/manifest.json, which does not exist").
TEST(DetectionFile, ADigestOrHashThatIsNoneOrAFileForTheRenderingIsSaidToBe) {
  const fs::path dir = hcpf::testing::FreshDir("detection-file-malformed");
  WriteTextFile((dir / "det.txt").string(), "1,-1,11,21,30,15,0.9\n");
  std::string error = FileLoadError(
      kMinimal, With(FileDetector(dir / "det.txt"), {"observation.file.digest", "xyz"}));
  EXPECT_NE(error.find("observation.file.digest: expected a digest: 32 lowercase hexadecimal "
                       "digits, as the manifest's detection_file writes it, found \"xyz\""),
            std::string::npos)
      << error;
  error = FileLoadError(kMinimal,
                        With(FileDetector(dir / "det.txt"), {"observation.file.pixel_hash", "zz"}));
  EXPECT_NE(error.find("observation.file.pixel_hash: expected a pixel hash: 32 lowercase "
                       "hexadecimal digits, as a manifest.json's pixel_hash, found \"zz\""),
            std::string::npos)
      << error;
  error = FileLoadError(kMinimal, With(FileDetector(dir / "det.txt"),
                                       {"observation.file.rendering", (dir / "det.txt").string()}));
  EXPECT_NE(error.find("observation.file.rendering"), std::string::npos) << error;
  EXPECT_NE(error.find("found \"" + (dir / "det.txt").string() + "\", a file ("), std::string::npos)
      << error;
  // A folder found beside the scenario is the rendering, though a file of
  // its name sits in the current folder (a review: refused as "a file").
  fs::create_directories(dir / "here");
  WriteTextFile((dir / "here" / "render").string(), "not a folder");
  fs::create_directories(dir / "render");
  WriteTextFile((dir / "render" / "manifest.json").string(),
                "{\"pixel_hash\": \"" + std::string(32, '0') + "\"}");
  const fs::path kept = fs::current_path();
  fs::current_path(dir / "here");
  error = FileLoadError(
      kMinimal, With(FileDetector(dir / "det.txt"), {"observation.file.rendering", "render"}),
      (dir / "s.yaml").string());
  fs::current_path(kept);
  EXPECT_EQ(error.find("a file ("), std::string::npos) << error;
  EXPECT_NE(error.find("the frames of another rendering: " + (dir / "render").string()),
            std::string::npos)
      << error;
}

// A model outside the project is written by its absolute path whatever
// folder hcpf is started from, so the run's configuration hash does not
// depend on it (a review reverted a day's rule that wrote it relative to the
// current folder: the hash then changed with the folder, and the resolved
// scenario did not load from another).
TEST(ModelPath, OutsideTheProjectItIsAbsoluteFromAnyFolder) {
  const fs::path dir = hcpf::testing::FreshDir("model-path-cwd");
  fs::create_directories(dir / "one" / "m");
  fs::copy_file(fs::path(HCPF_SOURCE_DIR) / "assets" / "vehicles" / "tank.glb",
                dir / "one" / "m" / "tank.glb");
  const auto written_from = [&](const fs::path& cwd) {
    const fs::path kept = fs::current_path();
    fs::current_path(cwd);
    const Scenario s =
        LoadScenarioText(kMinimal, (dir / "one" / "m" / "s.yaml").string(),
                         {{"targets.0", "{id: 1, model: tank.glb, path: {waypoints: [[0, 0]]}}"}});
    // Written (as a run writes it) in the folder it was started from.
    const auto written = std::pair{ToResolvedYaml(s), ConfigHash(s)};
    fs::current_path(kept);
    return written;
  };
  const auto [inside, inside_hash] = written_from(dir / "one");
  const auto [outside, outside_hash] = written_from(dir);
  EXPECT_NE(inside.find("model: \"" + (dir / "one" / "m" / "tank.glb").string() + "\""),
            std::string::npos)
      << inside;
  EXPECT_EQ(inside, outside);
  EXPECT_EQ(inside_hash, outside_hash);
}

}  // namespace
}  // namespace hcpf::scenarios
