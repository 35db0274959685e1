// Bad input: every case must be rejected with an InputError whose message
// names the file, the line (and column), the dotted key, what was expected and
// what was found. Each case lists substrings that must all be in the message.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "hcpf/core/error.h"
#include "hcpf/core/names.h"
#include "hcpf/scenarios/scenario.h"
#include "support/test_scenarios.h"

namespace hcpf::scenarios {
namespace {

using testing::kMinimal;

struct BadCase {
  std::string name;
  std::string text;  // scenario text (file "bad.yaml")
  std::vector<Override> overrides;
  std::vector<std::string> must_contain;
};

void PrintTo(const BadCase& c, std::ostream* os) { *os << c.name; }

std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  if (at == std::string::npos) throw std::logic_error("test text lacks: " + from);
  return text.replace(at, from.size(), to);
}

// kMinimal with `n` targets (ids 1 … n, each on its own lane) in place of its two.
std::string ManyTargets(const std::string& m, int n) {
  std::string targets = "targets:\n";
  for (int i = 1; i <= n; ++i) {
    targets += fmt::format(
        "  - {{id: {}, dimensions_m: [4, 2, 1.5], path: {{waypoints: [[-20, {}], [20, {}]], "
        "speed_mps: 6}}}}\n",
        i, i % 40 - 20, i % 40 - 20);
  }
  const size_t from = m.find("targets:\n"), to = m.find("tracker:\n");
  return m.substr(0, from) + targets + m.substr(to);
}

std::vector<BadCase> Cases() {
  const std::string m = kMinimal;
  return {
      {"UnknownTopLevelKey",
       m + "tracer: {particles: 5}\n",
       {},
       {"bad.yaml:19:1:", "tracer", "unknown key", "did you mean \"tracker\"?"}},
      {"UnknownNestedKey",
       Replace(m, "beta: 2.0", "betta: 2.0"),
       {},
       {"bad.yaml:18:", "tracker.resampling.betta", "did you mean \"beta\"?"}},
      {"WrongTypeForInteger",
       Replace(m, "frames: 20", "frames: many"),
       {},
       {"bad.yaml:3:9:", "frames", "expected an integer", "found \"many\""}},
      {"OutOfRange",
       Replace(m, "particles: 100", "particles: 0"),
       {},
       {"bad.yaml:17:14:", "tracker.particles", "[1, 10000000]", "found \"0\""}},
      {"MissingRequiredTopLevel",
       Replace(m, "frames: 20\n", ""),
       {},
       {"bad.yaml:", "frames", "required key \"frames\"", "missing"}},
      {"MissingRequiredNested",
       Replace(m, "  resolution: [320, 240]\n", ""),
       {},
       {"bad.yaml:4:", "camera.resolution", "required key"}},
      {"EnumTypo",
       Replace(m, "method: charged", "method: charge"),
       {},
       {"bad.yaml:18:", "tracker.resampling.method", "one of", "found \"charge\"",
        "did you mean \"charged\"?"}},
      {"WrongListLength",
       Replace(m, "resolution: [320, 240]", "resolution: [320]"),
       {},
       {"bad.yaml:5:", "camera.resolution", "a list of 2 numbers", "a list of 1 item"}},
      {"ListItemNotANumber",
       Replace(m, "position: [0, -20, 120]", "position: [0, x, 120]"),
       {},
       {"bad.yaml:8:", "camera.path[0].position[1]", "expected a number", "found \"x\""}},
      {"ModelDoesNotExist",
       Replace(m, "    dimensions_m: [4.5, 2.0, 1.6]\n", "    model: no/such/tank.glb\n"),
       {},
       {"bad.yaml:11:", "targets[0].model", "existing model file", "no/such/tank.glb"}},
      {"DuplicateTargetId",
       Replace(m, "  - id: 2\n", "  - id: 1\n"),
       {},
       {"bad.yaml:13:", "targets[1].id", "an id used by no other target"}},
      {"StrengthForUnknownTarget",
       m + "observation: {simulated: {strength: {1: 1.0, 7: 0.4}}}\n",
       {},
       {"bad.yaml:19:", "observation.simulated.strength.7", "there is no target with id 7"}},
      {"KeyframesNotIncreasing",
       Replace(m, "    - {frame: 0, position: [0, -20, 120], look_at: [0, 0, 0]}\n",
               "    - {frame: 5, position: [0, -20, 120], look_at: [0, 0, 0]}\n"
               "    - {frame: 3, position: [0, -20, 150], look_at: [0, 0, 0]}\n"),
       {},
       {"bad.yaml:9:", "camera.path[1].frame", "after the previous keyframe"}},
      {"YamlSyntaxError",
       Replace(m, "  fov_deg: 40\n", "  fov_deg: [40\n"),
       {},
       {"bad.yaml:", "valid YAML", "syntax error"}},
      {"DuplicateKey",
       Replace(m, "seed: 7\n", "seed: 7\nseed: 8\n"),
       {},
       {"bad.yaml:3:1:", "seed", "each key once"}},
      {"BoolNotTrueFalse",
       m + "world: {sun: {shadows: yes}}\n",
       {},
       {"bad.yaml:19:", "world.sun.shadows", "true or false", "found \"yes\""}},
      {"EndBeforeStart",
       Replace(m, "start_frame: 2}", "start_frame: 5, end_frame: 3}"),
       {},
       {"bad.yaml:15:", "targets[1].path.end_frame", ">= start_frame (5)"}},
      {"NeitherModelNorDimensions",
       Replace(m, "    dimensions_m: [5, 2.2, 2]\n", ""),
       {},
       {"bad.yaml:13:", "targets[1].dimensions_m", "required key"}},
      {"OverrideUnknownKey",
       m,
       {{"tracker.particels", "10"}},
       {"--set tracker.particels=10", "tracker.particels", "did you mean \"particles\"?"}},
      {"OverrideWrongType",
       m,
       {{"tracker.particles", "lots"}},
       {"--set tracker.particles=lots", "tracker.particles", "expected an integer",
        "found \"lots\""}},
      // An item of a list set on the command line is reported at the --set,
      // not at the file's first line.
      {"OverrideListItem",
       m,
       {{"camera.resolution", "[320, abc]"}},
       {"--set camera.resolution=[320, abc]", "camera.resolution[1]", "found \"abc\""}},
      {"OverrideWordsItem",
       m,
       {{"observation.source", "rendered"}, {"observation.detectors", "[sks, prka]"}},
       {"--set observation.detectors=[sks, prka]", "observation.detectors[1]",
        "did you mean \"prca\"?"}},
      {"FrameOutOfRange",
       Replace(m, "start_frame: 2}", "start_frame: 20}"),
       {},
       {"bad.yaml:15:", "targets[1].path.start_frame", "[0, 19]", "found \"20\""}},
      // Issue 15, item 3: the renderer's ranges, located at the key (validate
      // accepted these; a rendered run then failed without a location).
      {"SensorExposureAboveRendererRange",
       m + "sensor:\n  exposure: 50\n",
       {},
       {"bad.yaml:20:13:", "sensor.exposure", "found \"50\""}},
      {"SensorExposureZero",
       m + "sensor:\n  exposure: 0\n",
       {},
       {"bad.yaml:20:13:", "sensor.exposure", "(0, 16]", "found \"0\""}},
      {"SensorNoiseAboveRendererRange",
       m + "sensor:\n  noise_sigma: 255\n",
       {},
       {"bad.yaml:20:16:", "sensor.noise_sigma", "found \"255\""}},
      {"SensorBlurAboveRendererRange",
       m + "sensor:\n  blur_px: 100\n",
       {},
       {"bad.yaml:20:12:", "sensor.blur_px", "found \"100\""}},
      {"SensorValueFromOverride",
       m,
       {{"sensor.exposure", "50"}},
       {"--set sensor.exposure=50", "sensor.exposure"}},
      // A module's cross-field rule, reported at the line of the key it names.
      {"CrossFieldRuleAtItsKey",
       m + "  likelihood: {model: associated}\n  association: {method: none}\n",
       {},
       {"bad.yaml:20:", "tracker.association.method", "gnn or nearest"}},
      // A birth velocity from ground truth needs births from ground truth.
      {"BirthVelocityWithoutGroundTruthBirths",
       m + "  init: detections\n  management: {birth_velocity: ground_truth}\n",
       {},
       {"bad.yaml:20:", "tracker.management.birth_velocity", "zero (tracker.init is detections",
        "ground_truth with tracker.init: detections"}},
      // Re-acquisition reads target-specific detections: a model-based detector.
      {"ReacquireWithTheOracle",
       m + "  management: {reacquire: own_detections}\n",
       {},
       {"bad.yaml:19:", "tracker.management.reacquire", "a model-based observation.detector",
        "own_detections with observation.detector: oracle"}},
      {"ReacquireWithAModelFreeDetector",
       m + "  management: {reacquire: own_detections}\nobservation: {source: rendered, detector: "
           "diff}\n",
       {},
       {"bad.yaml:19:", "tracker.management.reacquire", "a model-based observation.detector",
        "own_detections with observation.detector: diff"}},
      {"ReacquireWithDetectionBirths",
       m + "  init: detections\n  management: {reacquire: own_detections}\n",
       {},
       {"bad.yaml:20:", "tracker.management.reacquire", "none (tracker.init is detections",
        "own_detections with tracker.init: detections"}},
      // Issue 15, item 4: a second YAML document used to drop the rest of the
      // file silently (here: the whole tracker section).
      {"StrayDocumentSeparator",
       Replace(m, "tracker:\n", "---\ntracker:\n"),
       {},
       {"bad.yaml:16:1:", "one YAML document", "'---' or '...'"}},
      {"StrayDocumentEnd",
       Replace(m, "tracker:\n", "...\ntracker:\n"),
       {},
       {"bad.yaml:16:1:", "one YAML document"}},
      {"TrailingSeparator", m + "---\n", {}, {"bad.yaml:19:1:", "one YAML document"}},
      {"SecondDocumentInOverride",
       m,
       {{"tracker.particles", "5\n---\n6"}},
       {"--set tracker.particles=", "one YAML document"}},
      // Issue 15, item 5: an explicit empty or null value took the default.
      {"EmptyScalarValue",
       Replace(m, "particles: 100", "particles:"),
       {},
       {"bad.yaml:17:", "tracker.particles", "expected an integer", "found nothing"}},
      {"NullScalarValue",
       Replace(m, "fov_deg: 40", "fov_deg: ~"),
       {},
       {"bad.yaml:6:", "camera.fov_deg", "expected a number", "found nothing"}},
      {"NullRequiredValue",
       Replace(m, "frames: 20", "frames: ~"),
       {},
       {"bad.yaml:3:", "frames", "expected an integer", "found nothing"}},
      {"EmptyOverrideValue",
       m,
       {{"tracker.particles", ""}},
       {"--set tracker.particles=", "tracker.particles", "found nothing"}},
      {"NullOverrideValue",
       m,
       {{"camera.fov_deg", "~"}},
       {"--set camera.fov_deg=~", "camera.fov_deg", "found nothing"}},
      // A fourth bad-input audit: `tracker={}` reset the file's tracker
      // section to its defaults, exit 0.
      {"EmptyMappingOverrideValue",
       m,
       {{"tracker", "{}"}},
       {"--set tracker={}", "found an empty mapping, which would reset the file's keys there",
        "leave it out of the file"}},
      // Issue 15, items 12 and 13. (Spelled 01 until 2026-12-06, when a
      // leading zero became an error of its own.)
      {"DuplicateStrengthId",
       m + "observation: {simulated: {strength: {1: 1.0, +1: 0.3}}}\n",
       {},
       {"bad.yaml:19:", "observation.simulated.strength", "each target id once", "\"1\""}},
      {"ControlCharacterInName",
       Replace(m, "name: minimal\n", "name: \"two\\nlines\"\n"),
       {},
       {"bad.yaml:1:", "name", "without control characters"}},
      // A bad-input audit: NEL and U+2028 passed, and break lines in editors.
      {"NextLineInName",
       Replace(m, "name: minimal\n", "name: \"a\\x85b\"\n"),
       {},
       {"bad.yaml:1:", "name", "without control characters", "U+0085"}},
      {"LineSeparatorInName",
       Replace(m, "name: minimal\n",
               "name: \"a\xE2\x80\xA8"
               "b\"\n"),
       {},
       {"bad.yaml:1:", "name", "without control characters", "U+2028"}},
      // Issue 15, item 14: unknown keys made by an override name the override.
      {"OverrideUnknownTopLevelKey",
       m,
       {{"trackr.particles", "10"}},
       {"--set trackr.particles=10", "trackr", "did you mean \"tracker\"?"}},
      {"OverrideNumericMapKey", m, {{"tracker.0", "3"}}, {"--set tracker.0=3", "tracker.0"}},
      {"OverrideNonAsciiKey", m, {{"trackér.particles", "5"}}, {"--set trackér.particles=5"}},
      {"TopLevelNotAMapping",
       "- a\n- b\n",
       {},
       {"bad.yaml:1:1:", "a scenario mapping", "found a list"}},
      // Issue 15, item 16: locations and readable messages for odd files.
      {"EmptyFile", "", {}, {"bad.yaml:1:1:", "found an empty file"}},
      {"CommentOnlyFile", "# nothing here\n\n", {}, {"bad.yaml:1:1:", "found an empty file"}},
      {"NullKey", m + "~: 3\n", {}, {"bad.yaml:19:1:", "a key name", "found a null key"}},
      {"EmptyKey", m + ": 3\n", {}, {"bad.yaml:19:", "found a null key"}},
      {"ListAsKey", m + "[a, b]: 3\n", {}, {"bad.yaml:19:1:", "found a list used as a key"}},
      {"MappingAsKey",
       m + "? {x: 1}\n: 3\n",
       {},
       {"bad.yaml:19:", "found a mapping used as a key"}},
      {"DeepNesting",
       m + "tracker: " + std::string(3000, '[') + std::string(3000, ']') + "\n",
       {},
       {"bad.yaml:19:", "YAML nested less deeply", "levels deep"}},
      // A bad-input audit: a folder named as a model "does not exist".
      {"ModelIsAFolder",
       m,
       {{"targets.0.model", "assets"}},
       {"targets[0].model", "found \"assets\", which is a folder, not a file"}},
      // A second bad-input audit: /dev/null as a model "does not exist".
      {"ModelIsADevice",
       m,
       {{"targets.0.model", "/dev/null"}},
       {"targets[0].model", "found \"/dev/null\", which is a device, not a file"}},
      // A second bad-input audit: a width that is not whole, set on the
      // command line, was blamed on the file's line ("found a list of 2
      // item(s)"); now at the item, and at its --set.
      {"ResolutionItemNotWholeFromTheCommandLine",
       m,
       {{"camera.resolution.0", "320.5"}},
       {"--set camera.resolution.0=320.5: camera.resolution[0]: expected a whole number in [16, "
        "8192] (item 0 of [width, height]), found \"320.5\""}},
      {"ResolutionItemNotWholeInTheFile",
       Replace(m, "resolution: [320, 240]", "resolution: [320, 240.5]"),
       {},
       {"bad.yaml:5:", "camera.resolution[1]: expected a whole number", "item 1 of"}},
      // A second bad-input audit: a file of `~` was "an empty file".
      {"NullDocument", "~\n", {}, {"bad.yaml:1:1:", "found a null value (~ or null)"}},
      // A second bad-input audit: a merge key left its keys "missing".
      {"MergeKeyInATarget",
       Replace(Replace(m, "dimensions_m: [4.5, 2.0, 1.6]", "dimensions_m: &d [4.5, 2.0, 1.6]"),
               "    dimensions_m: [5, 2.2, 2]", "    <<: {dimensions_m: *d}"),
       {},
       {"targets[1].<<: expected keys written out in full, found a YAML merge key"}},
      // A second bad-input audit: an override inside a node an alias shares
      // changed every copy (both targets' dimensions here).
      {"OverrideInsideAnAliasedNode",
       Replace(Replace(m, "dimensions_m: [4.5, 2.0, 1.6]", "dimensions_m: &d [4.5, 2.0, 1.6]"),
               "dimensions_m: [5, 2.2, 2]", "dimensions_m: *d"),
       {{"targets.0.dimensions_m.0", "3"}},
       {"--set targets.0.dimensions_m.0=3", "a YAML alias shares", "write that node out"}},
      // A second bad-input audit: with its dimensions given, a target's model
      // was not read until the rendered run, which then failed.
      {"UnreadableModelWithDimensions",
       m,
       {{"targets.0.model", "README.md"}},
       {"targets[0].model", "expected a readable mesh file", "found extension \".md\""}},
      // A bad-input audit: a sweep file where a scenario goes.
      {"SweepFileAsScenario",
       "seeds: 2\ngrid:\n  tracker.particles: [10, 20]\n",
       {},
       {"bad.yaml:2:1:", "grid", "expected a scenario file", "found a sweep file", "hcpf sweep"}},
      // A fourth bad-input audit: these two enums were written "a, b, found
      // charged", every other "a | b, found \"x\"".
      {"SceneFilterChargedResampling",
       m,
       {{"tracker.scene_filter.resampling", "charged"}},
       {"tracker.scene_filter.resampling: expected one of multinomial | systematic | stratified | "
        "residual (not charged",
        "found \"charged\""}},
      {"ChargedCandidates",
       m,
       {{"tracker.resampling.candidates", "charged"}},
       {"tracker.resampling.candidates: expected one of multinomial | systematic",
        "found \"charged\""}},
      // A fourth bad-input audit: a regression suite (or baseline) where a
      // scenario goes was "required key frames missing".
      {"RegressSuiteAsScenario",
       "scenes:\n  - {name: a, scenario: crossing.yaml}\nmetrics:\n  mota: {tolerance: 0.01}\n",
       {},
       {"bad.yaml:1:1:", "scenes", "expected a scenario file",
        "found a regression suite or baseline (it has `scenes:` at the top)", "hcpf regress"}},
      // A bad-input audit: a map likelihood with nothing making maps.
      {"MapLikelihoodWithoutMaps",
       m,
       {{"tracker.likelihood.model", "map"}},
       {"tracker.likelihood.model", "likelihood_map: true", "sks",
        "found map with the oracle and observation.simulated.likelihood_map: false"}},
      {"MapLikelihoodWithAModelFreeDetector",
       m + "observation: {source: rendered, detector: diff}\n",
       {{"tracker.likelihood.model", "map"}},
       {"tracker.likelihood.model", "found map with observation.detector: diff"}},
      // Issue 11 item 6: detectors fused (thesis chapter 10).
      {"FusedDetectorUnknown",
       m + "observation: {source: rendered, detectors: [sks, prka]}\n",
       {},
       {"bad.yaml:19:", "observation.detectors[1]", "one of ncc | colour",
        "did you mean \"prca\"?"}},
      {"FusedDetectorTwice",
       m + "observation: {source: rendered, detectors: [sks, sks]}\n",
       {},
       {"bad.yaml:19:", "observation.detectors[1]", "distinct", "\"sks\" is listed twice"}},
      {"FusedDetectorAlone",
       m + "observation: {source: rendered, detectors: [sks]}\n",
       {},
       {"bad.yaml:19:", "observation.detectors", "at least 2 distinct names"}},
      {"FusedDetectorWithDetector",
       m + "observation: {source: rendered, detector: ncc, detectors: [sks, prca]}\n",
       {},
       {"observation.detector", "fusion", "\"ncc\" with observation.detectors"}},
      {"FusionWithoutDetectors",
       m + "observation: {source: rendered, detector: fusion}\n",
       {},
       {"observation.detectors", "at least 2", "not written"}},
      {"FusedModelFreeWithModelBased",
       m + "observation: {source: rendered, detectors: [sks, diff]}\n",
       {},
       {"observation.detectors", "target models", "\"sks\" with \"diff\""}},
      {"FusedDetectorOnSimulated",
       m + "observation: {detectors: [sks, prca]}\n",
       {},
       {"observation.detector", "observation.source: rendered", "\"sks+prca\""}},
      {"SearchWindowWithOracle",
       m + "observation: {source: rendered, search: window}\n",
       {},
       {"observation.search", "model-based", "window with observation.detector: oracle"}},
      {"SearchWindowModelFree",
       m + "observation: {source: rendered, search: window, detector: diff}\n",
       {},
       {"observation.search", "model-based", "window with observation.detector: diff"}},
      // The point is named (it was "found a list of 3 item(s)": a bad-input
      // audit).
      {"LookAtTheCameraPosition",
       Replace(m, "look_at: [0, 0, 0]", "look_at: [0, -20, 120]"),
       {},
       {"bad.yaml:8:", "camera.path[0].look_at",
        "expected a point different from the camera position, found [0, -20, 120], the camera's "
        "position there"}},
      // The camera along its whole path (an audit of valid input): keyframes
      // each valid whose interpolated camera reaches its look-at point at
      // frame 9 (the run aborted there), a camera below the ground (it ran,
      // seeing targets through the terrain), and a half turn between two
      // frames (the run's camera-motion metric failed naming no key).
      {"CameraReachesItsLookAtBetweenKeyframes",
       Replace(m, "    - {frame: 0, position: [0, -20, 120], look_at: [0, 0, 0]}\n",
               "    - {frame: 0, position: [0, -10, 50], look_at: [0, 10, 40]}\n"
               "    - {frame: 18, position: [0, 10, 30], look_at: [0, -10, 40]}\n"),
       {},
       {"bad.yaml:8:5:", "camera.path",
        "expected a path on which the camera never reaches the point it looks at, found the "
        "camera and its look_at both at [0, 0, 40] at frame 9, between the keyframes of frames 0 "
        "and 18"}},
      {"CameraBelowTheGround",
       Replace(m, "position: [0, -20, 120]", "position: [0, -20, -50]"),
       {},
       {"bad.yaml:8:5:", "camera.path",
        "expected a camera above the ground at every frame: higher than 0 m, found a camera at "
        "height -50 m at the keyframe of frame 0"}},
      {"CameraTurnsHalfAroundBetweenTwoFrames",
       Replace(m, "    - {frame: 0, position: [0, -20, 120], look_at: [0, 0, 0]}\n",
               "    - {frame: 0, position: [0, 0, 10], look_at: [0, 100, 0]}\n"
               "    - {frame: 1, position: [0, 0, 10], look_at: [0, -100, 0]}\n"),
       {},
       {"bad.yaml:8:5:", "camera.path", "the ground seen at each image corner stays in front",
        "found corner (0, 0) mapped to homogeneous z = -1.03425 from frame 0 to 1 (the camera "
        "turns or moves too far between them) at the keyframe of frame 1"}},
      // A blank name left seqinfo.ini's name= empty (a bad-input audit).
      {"BlankName",
       Replace(m, "name: minimal", "name: \"  \""),
       {},
       {"bad.yaml:1:7:", "name", "expected a name with a visible character", "found \"  \""}},
      // What the renderer can draw, refused at load where the run renders
      // (a scale audit: validated, then every run failed at no line).
      {"InstanceIdsPastSixteenBits",
       Replace(m, "  - id: 2\n", "  - id: 70000\n") + "renderer: {write_instance_ids: true}\n",
       {},
       {"bad.yaml:13:9:", "expected an id of at most 65534 with renderer.write_instance_ids",
        "found \"70000\""}},
      {"MoreTargetsThanTheRendererDraws",
       ManyTargets(m, 256) + "observation: {source: rendered}\n",
       {},
       {"bad.yaml:10:3:", "targets", "expected at most 255 targets where the run renders",
        "found a list of 256 item(s)"}},
      {"NulByteIsEscaped",
       Replace(m, "frames: 20\n",
               std::string("frames: 2\0"
                           "0\n",
                           12)),
       {},
       {"bad.yaml:", "frames", "\\x00"}},
  };
}

class BadInput : public ::testing::TestWithParam<BadCase> {};

TEST_P(BadInput, IsRejectedWithLocationKeyExpectedAndFound) {
  const BadCase& c = GetParam();
  try {
    LoadScenarioText(c.text, "bad.yaml", c.overrides);
    FAIL() << "accepted: " << c.name;
  } catch (const InputError& e) {
    const std::string message = e.what();
    for (const std::string& part : c.must_contain) {
      EXPECT_NE(message.find(part), std::string::npos)
          << "message lacks \"" << part << "\"\n  message: " << message;
    }
  }
}

// What a map likelihood needs, accepted: the oracle's maps, a model-based
// detector's.
// Past the renderer's 255 targets and 16-bit ids, a run that does not
// render is valid.
TEST(BadInputFile, ManyTargetsAndLargeIdsAreValidWithoutRendering) {
  EXPECT_NO_THROW(LoadScenarioText(ManyTargets(kMinimal, 256), "ok.yaml"));
  EXPECT_NO_THROW(LoadScenarioText(
      Replace(kMinimal, "  - id: 2\n", "  - id: 70000\n") + "observation: {source: rendered}\n",
      "ok.yaml"));
}

// `hcpf render` always renders: past 255 targets a scenario is refused at
// the line of `targets` though it is at detection level (ScenarioUse).
TEST(BadInputFile, RenderRefusesMoreTargetsThanTheRendererDraws) {
  try {
    LoadScenarioText(ManyTargets(kMinimal, 256), "bad.yaml", {}, ScenarioUse::kRender);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  "bad.yaml:10:3: targets: expected at most 255 targets for hcpf render"),
              std::string::npos)
        << e.what();
  }
  EXPECT_NO_THROW(
      LoadScenarioText(ManyTargets(kMinimal, 255), "ok.yaml", {}, ScenarioUse::kRender));
}

TEST(BadInputFile, MapLikelihoodWithMapsIsAccepted) {
  const std::string m = kMinimal;
  EXPECT_NO_THROW(LoadScenarioText(
      m, "ok.yaml",
      {{"tracker.likelihood.model", "map"}, {"observation.simulated.likelihood_map", "true"}}));
  EXPECT_NO_THROW(LoadScenarioText(m + "observation: {source: rendered, detector: sks}\n",
                                   "ok.yaml", {{"tracker.likelihood.model", "map"}}));
}

// Replacing an aliased node as a whole is refused as well (yaml-cpp assigns
// into the shared node, so the alias would change too); overrides elsewhere
// in the file go through, and leave both places alike.
TEST(BadInputFile, AliasedNodesAreOverriddenNowhere) {
  const std::string m = Replace(
      Replace(kMinimal, "dimensions_m: [4.5, 2.0, 1.6]", "dimensions_m: &d [4.5, 2.0, 1.6]"),
      "dimensions_m: [5, 2.2, 2]", "dimensions_m: *d");
  EXPECT_THROW(LoadScenarioText(m, "ok.yaml", {{"targets.0.dimensions_m", "[3, 2, 1]"}}),
               InputError);
  EXPECT_THROW(LoadScenarioText(m, "ok.yaml", {{"targets.1.dimensions_m", "[3, 2, 1]"}}),
               InputError);
  const Scenario s = LoadScenarioText(m, "ok.yaml", {{"targets.1.id", "3"}});
  EXPECT_EQ(s.world.targets[0].dimensions_m.x(), 4.5);
  EXPECT_EQ(s.world.targets[1].dimensions_m.x(), 4.5);
}

// A NUL byte, a newline or NEL is never written into a message raw.
TEST(BadInputFile, MessagesHoldNoControlCharacters) {
  for (const BadCase& c : Cases()) {
    try {
      LoadScenarioText(c.text, "bad.yaml", c.overrides);
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_EQ(FirstControlCharacter(message), "") << c.name << ": " << message;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Scenario, BadInput, ::testing::ValuesIn(Cases()),
                         [](const auto& info) { return info.param.name; });

TEST(BadInputFile, UnreadableFileNamesThePath) {
  try {
    LoadScenarioFile("/nonexistent/dir/scenario.yaml");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/dir/scenario.yaml"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("cannot be opened"), std::string::npos);
  }
}

TEST(BadInputFile, OverrideWithoutEquals) {
  EXPECT_THROW(ParseOverride("tracker.particles"), InputError);
  EXPECT_THROW(ParseOverride("=5"), InputError);
  const Override o = ParseOverride("a.b=c=d");
  EXPECT_EQ(o.key, "a.b");
  EXPECT_EQ(o.value, "c=d");
}

}  // namespace
}  // namespace hcpf::scenarios
