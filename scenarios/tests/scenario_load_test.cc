#include <gtest/gtest.h>

#include "hcpf/scenarios/scenario.h"
#include "support/test_scenarios.h"

namespace hcpf::scenarios {
namespace {

using testing::kMinimal;

TEST(LoadScenario, ReadsValuesAndFillsDefaults) {
  const Scenario s = LoadScenarioText(kMinimal, "minimal.yaml");
  EXPECT_EQ(s.name, "minimal");
  EXPECT_EQ(s.seed, 7u);
  EXPECT_EQ(s.world.frames, 20);
  EXPECT_EQ(s.world.fps, 30.0);  // default
  EXPECT_EQ(s.world.camera.width_px, 320);
  ASSERT_EQ(s.world.targets.size(), 2u);
  EXPECT_EQ(s.world.targets[1].path.start_frame, 2);
  EXPECT_EQ(s.tracker.particles, 100);
  EXPECT_EQ(s.tracker.resampling.method, tracker::ResamplingMethod::kCharged);
  EXPECT_EQ(s.tracker.resampling.beta, 2.0);
  EXPECT_EQ(s.tracker.resampling.max_tries, 20);  // default
  EXPECT_EQ(s.observation.source, ObservationSource::kSimulated);
}

TEST(LoadScenario, SeedsAreDerivedPerStreamAndCanBePinned) {
  const Scenario a = LoadScenarioText(kMinimal, "a.yaml");
  EXPECT_NE(a.seeds.observation, a.seeds.tracker);
  EXPECT_EQ(a.world.terrain.seed, a.seeds.world);
  const Scenario b = LoadScenarioText(std::string(kMinimal) + "seeds: {tracker: 99}\n", "b.yaml");
  EXPECT_EQ(b.seeds.tracker, 99u);
  EXPECT_EQ(b.seeds.observation, a.seeds.observation);
  const Scenario c = LoadScenarioText(kMinimal, "c.yaml", {{"seed", "8"}});
  EXPECT_NE(c.seeds.observation, a.seeds.observation);
}

TEST(LoadScenario, ResolvedYamlRoundTrips) {
  const Scenario s = LoadScenarioText(kMinimal, "minimal.yaml");
  const std::string first = ToResolvedYaml(s);
  const Scenario again = LoadScenarioText(first, "scenario.resolved.yaml");
  EXPECT_EQ(ToResolvedYaml(again), first);
  EXPECT_EQ(ConfigHash(again), ConfigHash(s));
  // Every section is written out.
  for (const char* key : {"seeds:", "world:", "camera:", "targets:", "sensor:", "observation:",
                          "renderer:", "tracker:", "metrics:", "max_tries: 20", "beta: 2"}) {
    EXPECT_NE(first.find(key), std::string::npos) << key;
  }
}

// Issue 11 item 6: `observation.detectors` alone fuses them; the resolved
// YAML writes `detector: fusion` with the list and each fused detector's
// section (and no other), and reads back to the same scenario.
TEST(LoadScenario, DetectorsListFusesThem) {
  const Scenario s = LoadScenarioText(
      std::string(kMinimal) + "observation: {source: rendered, detectors: [sks, prca]}\n",
      "f.yaml");
  EXPECT_EQ(s.observation.detector, "fusion");
  EXPECT_EQ(s.observation.fused, (std::vector<std::string>{"sks", "prca"}));
  EXPECT_EQ(s.observation.DetectorName(), "sks+prca");
  const std::string resolved = ToResolvedYaml(s);
  EXPECT_NE(resolved.find("detector: fusion"), std::string::npos) << resolved;
  EXPECT_NE(resolved.find("detectors: [sks, prca]"), std::string::npos) << resolved;
  EXPECT_NE(resolved.find("\n  sks:"), std::string::npos) << resolved;
  EXPECT_NE(resolved.find("\n  prca:"), std::string::npos) << resolved;
  EXPECT_EQ(resolved.find("\n  ncc:"), std::string::npos) << resolved;
  const Scenario again = LoadScenarioText(resolved, "scenario.resolved.yaml");
  EXPECT_EQ(ToResolvedYaml(again), resolved);
  EXPECT_EQ(ConfigHash(again), ConfigHash(s));
  // The order of the list is the order the detectors run in: part of the identity.
  const Scenario swapped = LoadScenarioText(
      std::string(kMinimal) + "observation: {source: rendered, detectors: [prca, sks]}\n",
      "f.yaml");
  EXPECT_NE(ConfigHash(swapped), ConfigHash(s));
  // A single detector writes no list.
  const Scenario one = LoadScenarioText(
      kMinimal, "m.yaml", {{"observation.source", "rendered"}, {"observation.detector", "sks"}});
  EXPECT_EQ(ToResolvedYaml(one).find("detectors:"), std::string::npos);
}

TEST(LoadScenario, OverridesApplyWithDottedKeysAndIndices) {
  const Scenario s = LoadScenarioText(kMinimal, "minimal.yaml",
                                      {{"tracker.particles", "1000"},
                                       {"targets.1.path.speed_mps", "3.5"},
                                       {"camera.resolution", "[640, 480]"},
                                       {"observation.simulated.strength", "{1: 1.0, 2: 0.3}"}});
  EXPECT_EQ(s.tracker.particles, 1000);
  EXPECT_EQ(s.world.targets[1].path.speed_mps, 3.5);
  EXPECT_EQ(s.world.camera.width_px, 640);
  EXPECT_EQ(s.observation.simulated.StrengthOf(2), 0.3);
  EXPECT_NE(ConfigHash(s), ConfigHash(LoadScenarioText(kMinimal, "minimal.yaml")));
}

TEST(LoadScenario, AssociationShorthand) {
  const Scenario s = LoadScenarioText(kMinimal, "m.yaml", {{"tracker.association", "nearest"}});
  EXPECT_EQ(s.tracker.association.method, tracker::AssociationMethod::kNearestNeighbour);
}

TEST(LoadScenario, ModelDimensionsComeFromTheModelFile) {
  const std::string text = std::string(kMinimal) +
                           "world: {occluders: [{kind: bridge, from: [-20, 10], to: [20, 10]}]}\n";
  Scenario s = LoadScenarioText(text, "m.yaml",
                                {{"targets.0",
                                  "{id: 1, model: assets/vehicles/tank.glb, "
                                  "path: {waypoints: [[0, 0]]}}"}});
  const Eigen::Vector3d d = s.world.targets[0].dimensions_m;
  // The generated tank is several metres long, longer than wide, lower than long.
  EXPECT_GT(d.x(), 3.0);
  EXPECT_GT(d.x(), d.y());
  EXPECT_GT(d.x(), d.z());
  EXPECT_EQ(s.world.occluders.size(), 1u);
}

// The scene filter's evidence terms a frame: its hypotheses (its particles,
// and with the laplace proposal, the default, ~169 of its Newton search)
// times the points each is weighed on, by evidence (simulated:
// scene_filter.points; image: at most point_tracker.max_corners; oracle: the
// 10 x 10 grid); none without the scene filter. Above a second a frame at
// ~10 ns a term the run warns, naming the keys (both ranges allow 10^13
// terms a frame). A scale audit: 10 particles x 10^6 points counted 10^7
// terms and no warning for a run of 2.0 s a frame (the Newton search's
// terms left out).
TEST(LoadScenario, SceneFilterCostIsCountedAndAVerySlowOneIsNamed) {
  const auto load = [](std::vector<Override> overrides) {
    overrides.push_back({"tracker.camera_motion", "scene_filter"});
    return LoadScenarioText(kMinimal, "m.yaml", overrides);
  };
  EXPECT_EQ(SceneFilterEvaluationsPerFrame(LoadScenarioText(kMinimal, "m.yaml")), 0);
  EXPECT_EQ(SceneFilterEvaluationsPerFrame(load({})), (1000 + 169) * 200);
  EXPECT_EQ(SceneFilterEvaluationsPerFrame(load({{"tracker.scene_filter.proposal", "dynamics"}})),
            1000 * 200);
  EXPECT_EQ(SceneFilterEvaluationsPerFrame(load({{"tracker.scene_filter.evidence", "oracle"}})),
            (1000 + 169) * 100);
  EXPECT_EQ(SceneFilterEvaluationsPerFrame(load({{"observation.source", "rendered"},
                                                 {"tracker.scene_filter.evidence", "image"},
                                                 {"tracker.point_tracker.max_corners", "300"}})),
            (1000 + 169) * 300);
  EXPECT_EQ(SceneFilterCostWarning(load({})), "");
  const Scenario slow = load({{"tracker.scene_filter.particles", "1000000"},
                              {"tracker.scene_filter.points", "1000"},
                              {"tracker.scene_filter.proposal", "dynamics"},
                              {"frames", "360"}});
  EXPECT_EQ(SceneFilterCostWarning(slow),
            "the scene filter weighs (tracker.scene_filter.particles (1000000)) x "
            "tracker.scene_filter.points (1000) = 1e+09 evidence terms a frame: about 10 s a "
            "frame at ~10 ns each (BM_SceneFilterStep), 1 h for 360 frames; fewer particles or "
            "points make it faster");
  const Scenario points = load({{"tracker.scene_filter.particles", "10"},
                                {"tracker.scene_filter.points", "1000000"},
                                {"frames", "20"}});
  EXPECT_EQ(SceneFilterCostWarning(points),
            "the scene filter weighs (tracker.scene_filter.particles (10) + at least ~169 of the "
            "laplace proposal's Newton search) x tracker.scene_filter.points (1000000) = "
            "1.79e+08 evidence terms a frame: about 1.79 s a frame at ~10 ns each "
            "(BM_SceneFilterStep), 0.00994 h for 20 frames; fewer particles or points make it "
            "faster, as does tracker.scene_filter.proposal: dynamics (no Newton search)");
}

}  // namespace
}  // namespace hcpf::scenarios

namespace hcpf::scenarios {
namespace {

// Only a section may be empty: it means "all defaults" (issue 15, item 5).
TEST(LoadScenario, AnEmptySectionTakesEveryDefault) {
  const Scenario s =
      LoadScenarioText(std::string(testing::kMinimal) + "metrics:\nsensor: ~\n", "sections.yaml");
  EXPECT_EQ(s.metrics.filters.iou_threshold, metrics::FilterMetricsOptions{}.iou_threshold);
  EXPECT_EQ(s.sensor.exposure, SensorOptions{}.exposure);
  // A leading document marker is one document, not two.
  EXPECT_NO_THROW(LoadScenarioText("---\n" + std::string(testing::kMinimal), "marker.yaml"));
}

}  // namespace
}  // namespace hcpf::scenarios
