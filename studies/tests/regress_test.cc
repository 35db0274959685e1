// Regression gate: verdicts by hand, suite validation, baseline round trip and a planted
// regression.

#include "hcpf/studies/regress.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "hcpf/core/error.h"
#include "hcpf/core/rng.h"
#include "sweep_fixture.h"

namespace hcpf::studies {
namespace {

namespace fs = std::filesystem;
using V = std::vector<double>;

TEST(Regress, CompareMetricByHand) {
  const RegressTolerance higher{"idf1", 0.01, true};
  const RegressTolerance lower{"hijack_rate", 0.0, false};
  EXPECT_EQ(CompareMetric(0.80, 0.80, higher), RegressVerdict::kSame);
  EXPECT_EQ(CompareMetric(0.80, 0.795, higher), RegressVerdict::kSame);  // 0.005 worse, within 0.01
  EXPECT_EQ(CompareMetric(0.80, 0.785, higher), RegressVerdict::kWorse);  // 0.015 worse
  EXPECT_EQ(CompareMetric(0.80, 0.815, higher), RegressVerdict::kBetter);
  EXPECT_EQ(CompareMetric(0.5, 0.6, lower), RegressVerdict::kWorse);  // higher hijack rate is worse
  EXPECT_EQ(CompareMetric(0.5, 0.4, lower), RegressVerdict::kBetter);
  EXPECT_EQ(CompareMetric(0.5, 0.5, lower), RegressVerdict::kSame);
  EXPECT_EQ(CompareMetric(std::nan(""), 0.5, lower), RegressVerdict::kWorse);
  EXPECT_EQ(CompareMetric(std::nan(""), std::nan(""), lower), RegressVerdict::kSame);
  // A change of exactly the tolerance does not exceed it, whatever its last
  // digits: 0.9375 − 0.9575 is −0.020000000000000018 in doubles (it was
  // WORSE: an audit), and the same gain is not better.
  const RegressTolerance two{"da_accuracy", 0.02, true};
  EXPECT_EQ(CompareMetric(0.9575, 0.9375, two), RegressVerdict::kSame);
  EXPECT_EQ(CompareMetric(0.9375, 0.9575, two), RegressVerdict::kSame);
  EXPECT_EQ(CompareMetric(0.9575, 0.9374, two), RegressVerdict::kWorse);
}

// Five seeds, idf1 (higher is better). d_i = current_i − baseline_i =
// −0.01, −0.02, −0.03, −0.04, −0.05: mean −0.03; deviations ±0.02, ±0.01, 0
// give Σ(d − d̄)² = 0.001, s² = 0.001 / 4 = 0.00025, s = 0.0158113883,
// s/√5 = 0.0070710678; t(0.975, 4) = 2.776 (table), half-width
// 2.776 · 0.0070710678 = 0.0196292843: interval [−0.0496292843, −0.0103707157].
TEST(Regress, CompareSeedsFiveSeedsByHand) {
  const std::vector<double> baseline = {0.80, 0.80, 0.80, 0.80, 0.80};
  const std::vector<double> current = {0.79, 0.78, 0.77, 0.76, 0.75};
  RegressRow r = CompareSeeds(baseline, current, {"idf1", 0.02, true});
  EXPECT_EQ(r.seeds, 5);
  EXPECT_EQ(r.pairs, 5);
  EXPECT_EQ(r.nan_mismatches, 0);
  EXPECT_NEAR(r.baseline, 0.80, 1e-12);
  EXPECT_NEAR(r.current, 0.77, 1e-12);
  EXPECT_NEAR(r.difference, -0.03, 1e-12);
  EXPECT_NEAR(r.lower, -0.0496292843, 1e-9);
  EXPECT_NEAR(r.upper, -0.0103707157, 1e-9);
  // −0.03 is beyond −0.02 and the interval is below zero.
  EXPECT_EQ(r.verdict, RegressVerdict::kWorse);
  // A tolerance of 0.035: the mean is not beyond it (the interval alone is not enough).
  EXPECT_EQ(CompareSeeds(baseline, current, {"idf1", 0.035, true}).verdict, RegressVerdict::kSame);
  // The same numbers for a lower-is-better metric are an improvement of 0.03.
  r = CompareSeeds(baseline, current, {"ospa", 0.02, false});
  EXPECT_EQ(r.verdict, RegressVerdict::kBetter);
  EXPECT_NEAR(r.difference, -0.03, 1e-12);  // shown as current − baseline
  // ... and swapped, a deterioration.
  EXPECT_EQ(CompareSeeds(current, baseline, {"ospa", 0.02, false}).verdict, RegressVerdict::kWorse);
  // The text outputs state the difference, the interval and the seeds.
  r = CompareSeeds(baseline, current, {"idf1", 0.02, true});
  r.scene = "s";
  const std::string junit = FormatRegressJunit({r});
  EXPECT_NE(junit.find("mean paired difference -0.03"), std::string::npos) << junit;
  EXPECT_NE(junit.find("[-0.0496293, -0.0103707]"), std::string::npos) << junit;
  EXPECT_NE(junit.find("over 5 of 5 seeds"), std::string::npos) << junit;
  EXPECT_NE(junit.find("<failure"), std::string::npos) << junit;
  RegressResult result;
  result.rows = {r};
  result.worse = 1;
  const std::string md = FormatRegressMarkdown(result);
  EXPECT_NE(md.find("| s | idf1 | 0.8 | 0.77 | -0.03 | [-0.0496293, -0.0103707] | 5 | −0.02 | "
                    "**WORSE** |"),
            std::string::npos)
      << md;
  const std::string table = FormatRegressTable({r});
  EXPECT_NE(table.find("[-0.0496293, -0.0103707]"), std::string::npos) << table;
}

// No seed with a number on both sides: the row shows each side's own mean
// (the baseline NaN, the current 1, 1, 0: 0.666667), beside its WORSE
// verdict (three seeds NaN on one side only); the table read "nan nan".
TEST(Regress, WithNoPairEachSideShowsItsOwnMean) {
  const double nan = std::nan("");
  const RegressRow r =
      CompareSeeds(V{nan, nan, nan}, V{1.0, 1.0, 0.0}, {"hijack_rate", 0.5, false});
  EXPECT_EQ(r.pairs, 0);
  EXPECT_EQ(r.nan_mismatches, 3);
  EXPECT_EQ(r.verdict, RegressVerdict::kWorse);
  EXPECT_TRUE(std::isnan(r.baseline));
  EXPECT_NEAR(r.current, 2.0 / 3.0, 1e-12);
  EXPECT_NE(FormatRegressTable({r}).find("0.666667"), std::string::npos) << FormatRegressTable({r});
}

// A consistent drop of 0.02 on every seed (tolerance 0.01) fails: d_i = −0.02,
// s = 0, interval [−0.02, −0.02]. One noisy seed with the same mean does not:
// d = −0.1, 0, 0, 0, 0 has mean −0.02, Σ(d − d̄)² = 0.08² + 4 · 0.02² = 0.008,
// s = √0.002 = 0.0447214, s/√5 = 0.02, half-width 2.776 · 0.02 = 0.05552:
// [−0.07552, 0.03552] holds zero.
TEST(Regress, ConsistentDropFailsWhereOneNoisySeedOfTheSameMeanDoesNot) {
  const RegressTolerance t{"idf1", 0.01, true};
  const std::vector<double> baseline = {0.9, 0.9, 0.9, 0.9, 0.9};
  RegressRow consistent = CompareSeeds(baseline, V{0.88, 0.88, 0.88, 0.88, 0.88}, t);
  EXPECT_EQ(consistent.verdict, RegressVerdict::kWorse);
  EXPECT_NEAR(consistent.difference, -0.02, 1e-12);
  EXPECT_NEAR(consistent.upper, -0.02, 1e-12);
  RegressRow noisy = CompareSeeds(baseline, V{0.8, 0.9, 0.9, 0.9, 0.9}, t);
  EXPECT_EQ(noisy.verdict, RegressVerdict::kSame);
  EXPECT_NEAR(noisy.difference, -0.02, 1e-12);
  EXPECT_NEAR(noisy.lower, -0.07552, 1e-9);
  EXPECT_NEAR(noisy.upper, 0.03552, 1e-9);
  // The exact mode would call the noisy seed alone WORSE (0.1 beyond 0.01).
  EXPECT_EQ(CompareMetric(0.9, 0.8, t), RegressVerdict::kWorse);
  // A consistent gain beyond the tolerance is better.
  EXPECT_EQ(CompareSeeds(baseline, V{0.93, 0.92, 0.93, 0.92, 0.93}, t).verdict,
            RegressVerdict::kBetter);
}

// The seeded mode's mean change of exactly the tolerance is not beyond it
// either: two seeds each 0.9575 -> 0.9375 (a mean change of
// −0.020000000000000018 in doubles, its interval zero wide) against 0.02 is
// ok, and 0.9575 -> 0.9374 is WORSE.
TEST(Regress, CompareSeedsAtExactlyTheTolerance) {
  const RegressTolerance t{"da_accuracy", 0.02, true};
  const std::vector<double> baseline = {0.9575, 0.9575};
  EXPECT_EQ(CompareSeeds(baseline, std::vector<double>{0.9375, 0.9375}, t).verdict,
            RegressVerdict::kSame);
  EXPECT_EQ(CompareSeeds(baseline, std::vector<double>{0.9374, 0.9374}, t).verdict,
            RegressVerdict::kWorse);
}

TEST(Regress, CompareSeedsIdentityAndNaN) {
  const double nan = std::nan("");
  const std::vector<double> v = {0.3, 0.7, 0.1, 0.9};
  for (const RegressTolerance& t :
       {RegressTolerance{"idf1", 0.0, true}, RegressTolerance{"hijack_rate", 0.0, false}}) {
    const RegressRow r = CompareSeeds(v, v, t);
    EXPECT_EQ(r.verdict, RegressVerdict::kSame) << t.metric;
    EXPECT_EQ(r.difference, 0.0);
    EXPECT_EQ(r.lower, 0.0);
    EXPECT_EQ(r.upper, 0.0);
  }
  // A number on one side and NaN on the other (either way) is WORSE.
  RegressRow r = CompareSeeds(V{0.5, 0.5, nan}, V{0.5, 0.5, 0.5}, {"idf1", 0.1, true});
  EXPECT_EQ(r.verdict, RegressVerdict::kWorse);
  EXPECT_EQ(r.nan_mismatches, 1);
  EXPECT_EQ(r.pairs, 2);
  EXPECT_EQ(CompareSeeds(V{0.5, 0.5, 0.5}, V{0.5, nan, 0.5}, {"idf1", 0.1, true}).verdict,
            RegressVerdict::kWorse);
  // NaN on both sides is left out: two equal pairs remain, ok.
  r = CompareSeeds(V{nan, 0.5, 0.6}, V{nan, 0.5, 0.6}, {"idf1", 0.0, true});
  EXPECT_EQ(r.verdict, RegressVerdict::kSame);
  EXPECT_EQ(r.pairs, 2);
  EXPECT_EQ(r.nan_mismatches, 0);
  // One pair left: judged like the exact mode; none: ok.
  EXPECT_EQ(CompareSeeds(V{nan, 0.5}, V{nan, 0.4}, {"idf1", 0.05, true}).verdict,
            RegressVerdict::kWorse);
  EXPECT_EQ(CompareSeeds(V{nan, nan}, V{nan, nan}, {"idf1", 0.05, true}).verdict,
            RegressVerdict::kSame);
}

std::string SuiteError(const fs::path& dir, const std::string& text) {
  std::ofstream(dir / "bad.yaml") << text;
  try {
    LoadRegressSuite((dir / "bad.yaml").string());
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Regress, BadSuitesAreLocated) {
  const auto dir = testing::SweepFolder("regress-bad");
  std::string e = SuiteError(dir,
                             "scenes:\n  - {scenario: base.yaml}\nmetrics:\n  idf: {tolerance: "
                             "0.1, direction: higher_is_better}\n");
  EXPECT_NE(e.find("did you mean \"idf1\""), std::string::npos) << e;
  // ...at the key's line and column (a bad-input audit: none were given).
  EXPECT_NE(e.find("bad.yaml:4:3: metrics.idf:"), std::string::npos) << e;
  // An empty mapping is said to be one (it was "found a mapping").
  e = SuiteError(dir, "scenes:\n  - {scenario: base.yaml}\nmetrics: {}\n");
  EXPECT_NE(e.find("expected a mapping of metric names to {tolerance, direction}, found an empty "
                   "mapping"),
            std::string::npos)
      << e;
  e = SuiteError(dir,
                 "scenes:\n  - {scenario: base.yaml}\nmetrics:\n  idf1: {tolerance: 0.1, "
                 "direction: higher}\n");
  EXPECT_NE(e.find("bad.yaml:4:"), std::string::npos) << e;
  EXPECT_NE(e.find("higher_is_better"), std::string::npos) << e;
  e = SuiteError(dir,
                 "scenes:\n  - {scenario: base.yaml, set: {tracker.particles: 0}}\nmetrics:\n  "
                 "idf1: {tolerance: 0.1, direction: higher_is_better}\n");
  EXPECT_NE(e.find("tracker.particles"), std::string::npos) << e;
  // A bad set: value at that value, naming the scene (none was given); an
  // error in the scenario file a set: value makes at the file's line.
  EXPECT_NE(e.find("bad.yaml:2:52: tracker.particles: expected"), std::string::npos) << e;
  EXPECT_NE(e.find("in the suite's scene \"base\" (" + (dir / "bad.yaml").string() + ":2:5)"),
            std::string::npos)
      << e;
  e = SuiteError(dir,
                 "scenes:\n  - {scenario: base.yaml, set: {frames: 2}}\nmetrics:\n  "
                 "idf1: {tolerance: 0.1, direction: higher_is_better}\n");
  EXPECT_NE(e.find("base.yaml:15:"), std::string::npos) << e;
  EXPECT_NE(e.find("targets[1].path.start_frame"), std::string::npos) << e;
  EXPECT_NE(e.find("in the suite's scene \"base\""), std::string::npos) << e;
  e = SuiteError(dir,
                 "scenes:\n  - {scenario: missing.yaml}\nmetrics:\n  idf1: {tolerance: 0.1, "
                 "direction: higher_is_better}\n");
  EXPECT_NE(e.find("bad.yaml:2:16: scenes[0].scenario"), std::string::npos) << e;
  // The direction is the metric catalogue's: stating the opposite is an error
  // at the direction, and leaving it out takes the catalogue's.
  e = SuiteError(dir,
                 "scenes:\n  - {scenario: base.yaml}\nmetrics:\n  ospa: {tolerance: 1, "
                 "direction: higher_is_better}\n");
  EXPECT_NE(e.find("bad.yaml:4:"), std::string::npos) << e;
  EXPECT_NE(e.find("metrics.ospa.direction"), std::string::npos) << e;
  EXPECT_NE(e.find("lower_is_better"), std::string::npos) << e;
  // seeds: an integer in [2, 1000], located at the value.
  for (const std::string value : {"0", "1", "\"x\"", "1001"}) {
    e = SuiteError(dir, "scenes:\n  - {scenario: base.yaml, seeds: " + value +
                            "}\nmetrics:\n  idf1: {tolerance: 0.1}\n");
    EXPECT_NE(e.find("bad.yaml:2:"), std::string::npos) << value << ": " << e;
    EXPECT_NE(e.find("scenes[0].seeds"), std::string::npos) << value << ": " << e;
    EXPECT_NE(e.find("an integer in [2, 1000]"), std::string::npos) << value << ": " << e;
  }
  // A key and one inside it in one scene's set: the later won (a bad-input
  // audit).
  e = SuiteError(dir,
                 "scenes:\n  - {scenario: base.yaml, set: {tracker.particles: 30, tracker: "
                 "{particles: 40}}}\nmetrics:\n  idf1: {tolerance: 0.1}\n");
  EXPECT_NE(e.find("bad.yaml:2:"), std::string::npos) << e;
  EXPECT_NE(e.find("none inside another (tracker.particles is set too)"), std::string::npos) << e;
  // The name is the scene's folder under --work: "../victim" escaped it and
  // replaced a folder beside it (a bad-input audit).
  for (const std::string name :
       {"\"../victim\"", "\"\"", "a/b", "\"..\"", "\"a\\\\b\"", "\"a\\x85\""}) {
    e = SuiteError(dir, "scenes:\n  - {name: " + name +
                            ", scenario: base.yaml}\nmetrics:\n  idf1: {tolerance: 0.1}\n");
    EXPECT_NE(e.find("bad.yaml:2:"), std::string::npos) << name << ": " << e;
    EXPECT_NE(e.find("scenes[0].name"), std::string::npos) << name << ": " << e;
    EXPECT_NE(e.find("can name one folder"), std::string::npos) << name << ": " << e;
  }
  std::ofstream(dir / "ok.yaml") << "scenes:\n  - {scenario: base.yaml}\nmetrics:\n"
                                    "  ospa: {tolerance: 1}\n  idf1: {tolerance: 0.1}\n";
  const RegressSuite suite = LoadRegressSuite((dir / "ok.yaml").string());
  ASSERT_EQ(suite.metrics.size(), 2u);
  EXPECT_FALSE(suite.metrics[0].higher_is_better);
  EXPECT_TRUE(suite.metrics[1].higher_is_better);
}

// A scene's seeds derive from its seed like a sweep's (sweep.h), written out
// here independently of SweepSeed: Rng(seed).Fork("sweep/seed/i").identity();
// without `seed:` from the scenario's own seed (base.yaml: seed 7).
TEST(Regress, SceneSeedsDeriveLikeSweepSeeds) {
  const auto dir = testing::SweepFolder("regress-seeds");
  std::ofstream(dir / "suite.yaml") << "scenes:\n"
                                       "  - {name: a, scenario: base.yaml, seed: 3, seeds: 3}\n"
                                       "  - {name: b, scenario: base.yaml, seeds: 2}\n"
                                       "  - {name: c, scenario: base.yaml}\n"
                                       "metrics:\n  idf1: {tolerance: 0.1}\n";
  const RegressSuite suite = LoadRegressSuite((dir / "suite.yaml").string());
  ASSERT_EQ(suite.scenes.size(), 3U);
  EXPECT_EQ(suite.scenes[0].seeds, 3);
  ASSERT_EQ(suite.scenes[0].run_seeds.size(), 3U);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(suite.scenes[0].run_seeds[static_cast<size_t>(i)],
              Rng(3).Fork("sweep/seed/" + std::to_string(i)).identity());
  }
  ASSERT_EQ(suite.scenes[1].run_seeds.size(), 2U);
  EXPECT_EQ(suite.scenes[1].run_seeds[1], Rng(7).Fork("sweep/seed/1").identity());
  EXPECT_EQ(suite.scenes[2].seeds, 0);
  EXPECT_TRUE(suite.scenes[2].run_seeds.empty());
}

TEST(Regress, BaselineRoundTripAndPlantedRegression) {
  const auto dir = testing::SweepFolder("regress");
  std::ofstream(dir / "suite.yaml")
      << "scenes:\n"
         "  - {name: a, scenario: base.yaml, set: {tracker.particles: 50}, seed: 3}\n"
         "  - {name: b, scenario: base.yaml, set: {tracker.resampling.method: systematic}}\n"
         "metrics:\n"
         "  idf1: {tolerance: 0.01, direction: higher_is_better}\n"
         "  hijack_rate: {tolerance: 0, direction: lower_is_better}\n";
  RegressOptions o;
  o.suite_path = (dir / "suite.yaml").string();
  o.baseline_path = (dir / "baseline.json").string();
  EXPECT_THROW(RunRegress(o), InputError);  // no baseline yet
  o.update_baseline = true;
  RegressResult r = RunRegress(o);
  EXPECT_TRUE(r.baseline_written);
  o.update_baseline = false;
  o.junit_path = (dir / "junit.xml").string();
  o.markdown_path = (dir / "summary.md").string();
  o.jobs = 2;
  r = RunRegress(o);
  ASSERT_EQ(r.rows.size(), 4U);
  EXPECT_EQ(r.worse, 0);
  EXPECT_EQ(r.better, 0);

  // Plant a regression: a baseline better than reality by more than the tolerance.
  nlohmann::json baseline;
  std::ifstream(o.baseline_path) >> baseline;
  const double idf1 = baseline["scenes"]["a"]["metrics"]["idf1"].get<double>();
  baseline["scenes"]["a"]["metrics"]["idf1"] = idf1 + 0.02;
  std::ofstream(o.baseline_path) << baseline.dump(2);
  r = RunRegress(o);
  EXPECT_EQ(r.worse, 1);
  EXPECT_EQ(r.rows[0].verdict, RegressVerdict::kWorse);
  std::stringstream junit;
  junit << std::ifstream(o.junit_path).rdbuf();
  EXPECT_NE(junit.str().find("failures=\"1\""), std::string::npos) << junit.str();
  EXPECT_NE(junit.str().find("<failure message=\"a idf1"), std::string::npos) << junit.str();
  std::stringstream md;
  md << std::ifstream(o.markdown_path).rdbuf();
  EXPECT_NE(md.str().find("**WORSE**"), std::string::npos) << md.str();

  // A baseline worse than reality: only better, no failure.
  baseline["scenes"]["a"]["metrics"]["idf1"] = idf1 - 0.02;
  std::ofstream(o.baseline_path) << baseline.dump(2);
  r = RunRegress(o);
  EXPECT_EQ(r.worse, 0);
  EXPECT_EQ(r.better, 1);
}

// A suite of one scene, "a" (the sweep fixture's base.yaml), judged by IDF1,
// in a fresh folder; ErrorOf(text) writes `text` as its baseline and returns
// what RunRegress refuses it with, "(accepted)" when it runs.
struct OneSceneSuite {
  explicit OneSceneSuite(const std::string& name) : dir(testing::SweepFolder(name)) {
    std::ofstream(dir / "suite.yaml") << "scenes:\n  - {name: a, scenario: base.yaml}\n"
                                         "metrics:\n  idf1: {tolerance: 0.01}\n";
    options.suite_path = (dir / "suite.yaml").string();
    options.baseline_path = (dir / "baseline.json").string();
  }
  std::string ErrorOf(const std::string& text) const {
    std::ofstream(options.baseline_path) << text;
    try {
      RunRegress(options);
    } catch (const InputError& e) {
      return e.what();
    }
    return "(accepted)";
  }
  fs::path dir;
  RegressOptions options;
};

// A baseline is bad input (InputError, exit 2) unless each of its keys is
// known, its hashes are strings and its values are numbers in the metric's
// range: a bad-input audit found a number for config_hash ending in a JSON
// type error (exit 1), and a misspelt key, an unknown metric and an idf1 of
// 7 accepted. Checked before anything runs.
TEST(Regress, BadBaselinesAreBadInput) {
  const OneSceneSuite suite("regress-bad-baseline");
  const RegressOptions& o = suite.options;
  const auto error_of = [&suite](const std::string& text) { return suite.ErrorOf(text); };
  const std::string scene = R"("a": {"config_hash": "0123", "metrics": {"idf1": 0.9}})";
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
      {R"({"scenes": {"a": {"config_hash": 17, "metrics": {"idf1": 0.9}}}})",
       {"scenes.a.config_hash", "a string", "17"}},
      {R"({"scenes": {"a": {"confighash": "0123", "metrics": {"idf1": 0.9}}}})",
       {"scenes.a.confighash", "did you mean \"config_hash\"?"}},
      {R"({"scenes": {"a": {"metrics": {"idf1": 0.9, "idf": 0.8}}}})",
       {"scenes.a.metrics.idf", "did you mean \"idf1\"?"}},
      {R"({"scenes": {"a": {"metrics": {"idf1": 7}}}})",
       {"scenes.a.metrics.idf1", "a number in [0, 1]", "found 7"}},
      {R"({"scenes": {"a": {"metrics": {"idf1": "0.9"}}}})", {"scenes.a.metrics.idf1", "\"0.9\""}},
      {R"({"scene": {)" + scene + "}}", {"scenes", "found an object without \"scenes\""}},
      {"[]", {"scenes", "found an empty list"}},
      {R"({"scenes": []})", {"scenes", "found \"scenes\" holding an empty list"}},
      {R"({"format": "hcpf-regress-baseline/2", "sweet": "x", "scenes": {)" + scene + "}}",
       {"sweet", "one of the keys format, suite, scenes"}},
      {R"({"format": 2, "scenes": {)" + scene + "}}", {"format", "found 2"}},
      // Format 1 holds exact scenes only (a fourth bad-input audit: a seeded
      // scene was accepted in it).
      {R"({"format": "hcpf-regress-baseline/1", "scenes": {"a": {"seeds": ["1"], )"
       R"("metrics": {"idf1": [0.9]}}}})",
       {"scenes.a.seeds", "one of the keys config_hash, metrics"}},
      {R"({"scenes": {"a": [0.9]}})", {"scenes.a", "an object"}},
      {R"({"scenes": {"b": {"metrics": {"idf1": 0.9}}}})", {"scenes.a.metrics", "none"}},
      {"{\"scenes\": ", {"baseline.json", "a baseline JSON file"}},
      // A key twice in one object (a fourth bad-input audit: the JSON
      // library kept the last, so a baseline compared with 0.2 silently).
      {R"({"scenes": {"a": {"metrics": {"idf1": 1.0, "idf1": 0.2}}}})",
       {"scenes.a.metrics.idf1: expected each key once in its object, found \"idf1\" a second "
        "time"}},
      {R"({"scenes": {"a": {"seeds": [1, 2], "config_hashes": ["x", "y"], "metrics": {}}, )"
       R"("a": {"metrics": {"idf1": 0.9}}}})",
       {"scenes.a: expected each key once in its object, found \"a\" a second time"}},
      // A syntax error at its line and column (it was inside the JSON
      // library's text: a bad-input audit).
      // A number no double holds, a NUL byte (the JSON library stopped
      // there as at the end), nesting deeper than any baseline (a review:
      // dotted names of keys thousands deep took seconds and gigabytes).
      {R"({"scenes": {"a": {"metrics": {"idf1": 1e999}}}})",
       {"baseline.json:1:",
        "expected a baseline JSON file, found a number out of range (number "
        "overflow parsing '1e999')"}},
      {std::string("{\"scenes\": {}}\n\0{\"x\": 1}", 24),
       {"baseline.json:2:1: expected a baseline JSON file, found a NUL byte"}},
      {"{\"scenes\": " + std::string(70, '[') + std::string(70, ']') + "}",
       {"expected a baseline JSON file nested at most 64 levels deep, found a list or object "
        "nested deeper"}},
      {"{\n  \"scenes\": {\n    \"a\": x\n",
       {"baseline.json:3:10: expected a baseline JSON file, found a JSON syntax error (syntax "
        "error while parsing value - invalid literal"}},
  };
  for (const auto& [text, wanted] : cases) {
    const std::string e = error_of(text);
    for (const std::string& piece : wanted)
      EXPECT_NE(e.find(piece), std::string::npos) << text << ": " << e;
  }
  // A folder given as the baseline is bad input too (it was exit 1).
  fs::remove(o.baseline_path);
  fs::create_directories(o.baseline_path);
  try {
    RunRegress(o);
    ADD_FAILURE() << "a folder was accepted as the baseline";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("baseline.json"), std::string::npos) << e.what();
  }
  fs::remove(o.baseline_path);
  // The well-formed baseline runs (NaN written "nan"; a scene the suite does
  // not run is allowed, a baseline may outlive a trimmed suite).
  std::ofstream(o.baseline_path) << R"({"scenes": {"a": {"metrics": {"idf1": "nan"}}, )"
                                    R"("old": {"metrics": {"mota": -3}}}})";
  const RegressResult r = RunRegress(o);
  ASSERT_EQ(r.rows.size(), 1U);
  EXPECT_TRUE(std::isnan(r.rows[0].baseline));
}

// Every baseline error names the line and column where its key begins, or
// where the nearest key above it that the file has begins (a bad-input audit:
// the value errors named the key but no line, the JSON library giving no
// positions after parsing). Worked out by hand from the text below.
TEST(Regress, BaselineErrorsNameTheLineOfTheirKey) {
  const OneSceneSuite suite("regress-baseline-lines");
  const auto error_of = [&suite](const std::string& text) { return suite.ErrorOf(text); };
  // Line 6, column 9: "idf1" after eight spaces.
  EXPECT_NE(error_of("{\n"
                     "  \"scenes\": {\n"
                     "    \"a\": {\n"
                     "      \"config_hash\": \"0123\",\n"
                     "      \"metrics\": {\n"
                     "        \"idf1\": 7\n"
                     "      }\n"
                     "    }\n"
                     "  }\n"
                     "}\n")
                .find("baseline.json:6:9: scenes.a.metrics.idf1: expected a number in [0, 1]"),
            std::string::npos);
  // A key with an escaped quote in it: at its opening quote (line 3,
  // column 3), not at the escaped one.
  EXPECT_NE(error_of("{\"scenes\": {\n"
                     "  \"a\": {\"metrics\": {\"idf1\": 0.5},\n"
                     "  \"x\\\"y\": 1}}}\n")
                .find("baseline.json:3:3: scenes.a.x\"y: expected one of the keys"),
            std::string::npos);
  // A hash of the wrong type: line 3, column 20.
  EXPECT_NE(error_of("{\"scenes\": {\n"
                     "  \"a\": {\"metrics\": {\"idf1\": 0.5},\n"
                     "                   \"config_hash\": 17}}}\n")
                .find("baseline.json:3:20: scenes.a.config_hash: expected a configuration hash"),
            std::string::npos);
  // The suite's scene is absent: at the key above it, "scenes" (line 2,
  // column 3).
  EXPECT_NE(error_of("{\n  \"scenes\": {\n    \"b\": {\"metrics\": {\"idf1\": 0.5}}}}\n")
                .find("baseline.json:2:3: scenes.a.metrics: expected a baseline value for every "
                      "scene and metric of the suite, found none"),
            std::string::npos);
  // A byte-order mark is no column (an editor does not show it): "idf1"
  // opens at column 31 of line 1 with or without one.
  EXPECT_NE(error_of("\xEF\xBB\xBF{\"scenes\": {\"a\": {\"metrics\": {\"idf1\": 7}}}}\n")
                .find("baseline.json:1:31: scenes.a.metrics.idf1: expected a number"),
            std::string::npos);
  // A key twice: at the second.
  EXPECT_NE(error_of("{\"scenes\": {\"a\": {\"metrics\": {\n"
                     "  \"idf1\": 0.5,\n"
                     "  \"idf1\": 0.6}}}}\n")
                .find("baseline.json:3:3: scenes.a.metrics.idf1: expected each key once"),
            std::string::npos);
}

// Outputs are checked before anything runs (a bad-input audit: --junit
// naming the baseline replaced it with XML, exit 0; --update-baseline onto
// the suite replaced the suite; a missing folder failed with exit 1 after
// the whole suite had run, which a CI gate reads as a regression).
std::string ReadText(const fs::path& path) {
  std::stringstream text;
  text << std::ifstream(path).rdbuf();
  return text.str();
}

TEST(Regress, OutputsThatWouldReplaceAnInputOrCannotBeWrittenAreRefused) {
  const auto dir = testing::SweepFolder("regress-outputs");
  std::ofstream(dir / "suite.yaml") << "scenes:\n  - {name: a, scenario: base.yaml}\n"
                                       "metrics:\n  idf1: {tolerance: 0.01}\n";
  std::ofstream(dir / "baseline.json") << R"({"scenes": {"a": {"metrics": {"idf1": 0.5}}}})";
  fs::create_directories(dir / "folder");
  const auto refused = [&](RegressOptions o, const std::string& wanted) {
    o.suite_path = (dir / "suite.yaml").string();
    if (o.baseline_path.empty()) o.baseline_path = (dir / "baseline.json").string();
    const std::string suite_before = ReadText(dir / "suite.yaml");
    const std::string baseline_before = ReadText(dir / "baseline.json");
    const std::string scenario_before = ReadText(dir / "base.yaml");
    try {
      RunRegress(o);
      ADD_FAILURE() << wanted << ": accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(wanted), std::string::npos) << e.what();
    }
    EXPECT_EQ(ReadText(dir / "suite.yaml"), suite_before);
    EXPECT_EQ(ReadText(dir / "baseline.json"), baseline_before);
    EXPECT_EQ(ReadText(dir / "base.yaml"), scenario_before);
    EXPECT_FALSE(fs::exists(dir / "a")) << "nothing ran";
  };
  const std::string at = dir.string() + "/";
  refused({.junit_path = at + "baseline.json"},
          "--junit: expected a file regress does not read, found the baseline it compares with");
  refused({.markdown_path = at + "suite.yaml"},
          "--markdown: expected a file regress does not "
          "read, found the suite");
  refused({.junit_path = at + "base.yaml"}, "found the scenario of scene \"a\"");
  refused({.baseline_path = at + "suite.yaml", .update_baseline = true},
          "--baseline: expected a file regress does not read, found the suite");
  refused({.junit_path = at + "out.xml", .markdown_path = at + "out.xml"},
          "--markdown: expected a file of its own, found the file --junit writes too");
  refused({.junit_path = at + "nodir/j.xml"}, "expected a file in an existing folder");
  refused({.markdown_path = at + "folder"}, "--markdown: expected a file to write, found a folder");
  refused({.work_dir = at + "suite.yaml"}, "--work: expected a folder (new or existing)");
  // A scene's folder in --work holding the user's files: refused before any
  // scene runs, naming --work (it failed the suite midway naming --out).
  fs::create_directories(dir / "work" / "a");
  std::ofstream(dir / "work" / "a" / "notes.txt") << "mine\n";
  refused({.work_dir = at + "work"},
          "work/a: --work: expected a folder for the run of scene \"a\": new, empty, or an "
          "earlier run's, found a folder with other files in it");
  EXPECT_EQ(ReadText(dir / "work" / "a" / "notes.txt"), "mine\n");
}

// A seeded scene beside an exact one: the baseline keeps per-seed values, a
// consistent planted drop fails, the same mean drop on one seed does not, and
// a baseline of other seeds is refused.
TEST(Regress, SeededSceneBaselineAndPairedVerdicts) {
  const auto dir = testing::SweepFolder("regress-seeded");
  std::ofstream(dir / "suite.yaml") << "scenes:\n"
                                       "  - {name: s, scenario: base.yaml, seed: 5, seeds: 3}\n"
                                       "  - {name: e, scenario: base.yaml}\n"
                                       "metrics:\n"
                                       "  idf1: {tolerance: 0.01}\n"
                                       "  mota: {tolerance: 0.01}\n";
  RegressOptions o;
  o.suite_path = (dir / "suite.yaml").string();
  o.baseline_path = (dir / "baseline.json").string();
  o.update_baseline = true;
  o.jobs = 2;
  RunRegress(o);
  nlohmann::json baseline;
  std::ifstream(o.baseline_path) >> baseline;
  EXPECT_EQ(baseline["format"], "hcpf-regress-baseline/2");
  const nlohmann::json& s = baseline["scenes"]["s"];
  ASSERT_EQ(s["seeds"].size(), 3U);
  EXPECT_EQ(s["seeds"][2].get<std::string>(),
            std::to_string(Rng(5).Fork("sweep/seed/2").identity()));
  ASSERT_EQ(s["metrics"]["idf1"].size(), 3U);
  ASSERT_EQ(s["config_hashes"].size(), 3U);
  EXPECT_TRUE(baseline["scenes"]["e"]["metrics"]["idf1"].is_number());

  o.update_baseline = false;
  o.junit_path = (dir / "junit.xml").string();
  RegressResult r = RunRegress(o);
  ASSERT_EQ(r.rows.size(), 4U);
  EXPECT_EQ(r.worse, 0);
  EXPECT_EQ(r.better, 0);
  EXPECT_EQ(r.rows[0].seeds, 3);
  EXPECT_EQ(r.rows[0].pairs, 3);
  EXPECT_EQ(r.rows[0].difference, 0.0);  // the same runs: identical values
  EXPECT_EQ(r.rows[2].seeds, 0);
  std::stringstream junit;
  junit << std::ifstream(o.junit_path).rdbuf();
  EXPECT_NE(junit.str().find("<system-out>s idf1: mean paired difference 0"), std::string::npos)
      << junit.str();

  // Every seed's baseline 0.05 better than reality: a consistent drop, WORSE.
  // (Planted on MOTA, whose values here leave room below its bound of 1: a
  // baseline value out of the metric's range is refused.)
  ASSERT_EQ(r.rows[1].metric, "mota");
  nlohmann::json planted = baseline;
  for (auto& v : planted["scenes"]["s"]["metrics"]["mota"]) v = v.get<double>() + 0.05;
  std::ofstream(o.baseline_path) << planted.dump(2);
  r = RunRegress(o);
  EXPECT_EQ(r.worse, 1);
  EXPECT_EQ(r.rows[1].verdict, RegressVerdict::kWorse);
  EXPECT_NEAR(r.rows[1].difference, -0.05, 1e-12);
  // The same mean drop on one seed only (+0.15, on the seed with the lowest
  // MOTA): the interval holds zero.
  planted = baseline;
  auto& lowest = planted["scenes"]["s"]["metrics"]["mota"][2];
  ASSERT_LE(lowest.get<double>() + 0.15, 1.0);
  lowest = lowest.get<double>() + 0.15;
  std::ofstream(o.baseline_path) << planted.dump(2);
  r = RunRegress(o);
  EXPECT_EQ(r.worse, 0);
  EXPECT_NEAR(r.rows[1].difference, -0.05, 1e-12);
  EXPECT_LT(r.rows[1].lower, 0.0);
  EXPECT_GT(r.rows[1].upper, 0.0);

  // A baseline of other seeds, or a per-seed list for an exact scene: bad input.
  planted = baseline;
  planted["scenes"]["s"]["seeds"][1] = "12";
  std::ofstream(o.baseline_path) << planted.dump(2);
  EXPECT_THROW(RunRegress(o), InputError);
  planted = baseline;
  planted["scenes"]["e"]["metrics"]["idf1"] = {0.5};
  std::ofstream(o.baseline_path) << planted.dump(2);
  EXPECT_THROW(RunRegress(o), InputError);
  planted = baseline;
  planted["scenes"]["s"]["metrics"]["mota"] = 0.5;
  std::ofstream(o.baseline_path) << planted.dump(2);
  EXPECT_THROW(RunRegress(o), InputError);
  // A first-format baseline still reads for the exact scene.
  std::ofstream(dir / "v1.yaml") << "scenes:\n  - {name: e, scenario: base.yaml}\n"
                                    "metrics:\n  idf1: {tolerance: 0.01}\n";
  nlohmann::json v1 = {{"format", "hcpf-regress-baseline/1"},
                       {"scenes", {{"e", {{"metrics", baseline["scenes"]["e"]["metrics"]}}}}}};
  std::ofstream(dir / "v1.json") << v1.dump(2);
  RegressOptions o1;
  o1.suite_path = (dir / "v1.yaml").string();
  o1.baseline_path = (dir / "v1.json").string();
  EXPECT_EQ(RunRegress(o1).worse, 0);
  v1["format"] = "hcpf-regress-baseline/9";
  std::ofstream(dir / "v1.json") << v1.dump(2);
  EXPECT_THROW(RunRegress(o1), InputError);
}

}  // namespace
}  // namespace hcpf::studies
