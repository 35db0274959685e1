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
#include "sweep_fixture.h"

namespace hcpf::studies {
namespace {

namespace fs = std::filesystem;

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
  e = SuiteError(dir,
                 "scenes:\n  - {scenario: base.yaml}\nmetrics:\n  idf1: {tolerance: 0.1, "
                 "direction: higher}\n");
  EXPECT_NE(e.find("bad.yaml:4:"), std::string::npos) << e;
  EXPECT_NE(e.find("higher_is_better"), std::string::npos) << e;
  e = SuiteError(dir,
                 "scenes:\n  - {scenario: base.yaml, set: {tracker.particles: 0}}\nmetrics:\n  "
                 "idf1: {tolerance: 0.1, direction: higher_is_better}\n");
  EXPECT_NE(e.find("tracker.particles"), std::string::npos) << e;
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
  std::ofstream(dir / "ok.yaml") << "scenes:\n  - {scenario: base.yaml}\nmetrics:\n"
                                    "  ospa: {tolerance: 1}\n  idf1: {tolerance: 0.1}\n";
  const RegressSuite suite = LoadRegressSuite((dir / "ok.yaml").string());
  ASSERT_EQ(suite.metrics.size(), 2u);
  EXPECT_FALSE(suite.metrics[0].higher_is_better);
  EXPECT_TRUE(suite.metrics[1].higher_is_better);
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

}  // namespace
}  // namespace hcpf::studies
