// Parity with TrackEval on every case and group of the conformance kit in
// ../shared/conformance/mot/ (never copied into the repository). The kit's
// README gives the rules; its expected.json holds TrackEval's numbers.
// Tolerances (from the kit's README): integer counts exact, ratios within 1e-6
// absolute. Prints a per-metric pass/fail table.
// Set HCPF_CONFORMANCE_DIR to use another copy of the kit.

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "hcpf/metrics/mot_io.h"
#include "hcpf/metrics/mot_metrics.h"

namespace hcpf::metrics {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

constexpr double kRatioTolerance = 1e-6;  // the kit's stated tolerance

fs::path ConformanceDir() {
  if (const char* env = std::getenv("HCPF_CONFORMANCE_DIR"); env != nullptr && *env != '\0') {
    return env;
  }
  return HCPF_CONFORMANCE_DEFAULT_DIR;
}

json LoadJson(const fs::path& path) {
  std::ifstream in(path);
  return json::parse(in);
}

double ExpectedNumber(const json& v) {
  if (v.is_string()) {
    const std::string s = v.get<std::string>();
    if (s == "nan") return std::nan("");
    if (s == "inf") return INFINITY;
    if (s == "-inf") return -INFINITY;
  }
  return v.get<double>();
}

struct Tally {
  int passed = 0;
  int failed = 0;
};

// Compares every metric listed under `expected`; returns false on any mismatch
// and records one row per metric in `table`.
bool Compare(const std::string& label, const MotSummary& got, const json& expected,
             std::map<std::string, Tally>* table) {
  const NamedMetrics named = ToNamedMetrics(got);
  bool all_ok = true;
  for (const auto& [name, value] : expected.items()) {
    const bool count = IsCountMetric(name);
    if (value.is_array()) {
      const std::vector<double>* mine = named.Array(name);
      bool ok = mine != nullptr && mine->size() == value.size();
      double worst = 0.0;
      for (size_t k = 0; ok && k < value.size(); ++k) {
        const double e = ExpectedNumber(value[k]);
        const double diff = std::fabs((*mine)[k] - e);
        worst = std::max(worst, diff);
        ok = count ? (*mine)[k] == e : diff <= kRatioTolerance;
      }
      (*table)[name].passed += ok;
      (*table)[name].failed += !ok;
      EXPECT_TRUE(ok) << label << ": " << name << " differs (worst |diff| " << worst << ")"
                      << (mine == nullptr ? " (not computed)" : "");
      all_ok = all_ok && ok;
      continue;
    }
    const double* mine = named.Scalar(name);
    const double e = ExpectedNumber(value);
    bool ok = false;
    if (mine != nullptr) {
      ok = count ? *mine == e : std::fabs(*mine - e) <= kRatioTolerance;
    }
    (*table)[name].passed += ok;
    (*table)[name].failed += !ok;
    EXPECT_TRUE(ok) << label << ": " << name << " expected " << fmt::format("{}", e) << " got "
                    << (mine ? fmt::format("{}", *mine) : std::string("(not computed)"));
    all_ok = all_ok && ok;
  }
  return all_ok;
}

TEST(Conformance, EveryCaseAndGroupMatchesTrackEval) {
  const fs::path dir = ConformanceDir();
  if (!fs::exists(dir / "manifest.json") || !fs::exists(dir / "expected.json")) {
    GTEST_SKIP() << "MOT conformance kit not found at " << dir
                 << " (manifest.json + expected.json); set HCPF_CONFORMANCE_DIR to its folder";
  }
  const json manifest = LoadJson(dir / "manifest.json");
  const json expected = LoadJson(dir / "expected.json");
  // The kit's alphas must be ours, bit for bit.
  const auto& alphas = HotaAlphas();
  ASSERT_EQ(expected.at("hota_alphas").size(), alphas.size());
  for (size_t a = 0; a < alphas.size(); ++a) {
    EXPECT_EQ(expected.at("hota_alphas")[a].get<double>(), alphas[a]) << "alpha " << a;
  }
  std::map<std::string, Tally> table;
  std::map<std::string, MotSummary> by_case;
  int cases = 0;
  for (const json& c : manifest.at("cases")) {
    const std::string name = c.at("name");
    SCOPED_TRACE(name);
    int seq_length = c.at("seq_length");
    if (c.contains("seqinfo")) {
      const SeqInfo info = ReadSeqInfo((dir / c.at("seqinfo").get<std::string>()).string());
      EXPECT_EQ(info.seq_length, seq_length);
      seq_length = info.seq_length;
    }
    const MotFile gt = ReadMotFile((dir / c.at("gt").get<std::string>()).string(),
                                   MotFileKind::kGroundTruth, seq_length);
    const MotFile hyp = ReadMotFile((dir / c.at("hyp").get<std::string>()).string(),
                                    MotFileKind::kTracks, seq_length);
    const auto benchmark = ParseBenchmark(c.at("benchmark").get<std::string>());
    ASSERT_TRUE(benchmark.has_value());
    // The kit's benchmark must also be what auto-detection picks.
    EXPECT_EQ(ResolveBenchmark(Benchmark::kAuto, gt), *benchmark);
    const Sequence seq = BuildSequence(gt, hyp, seq_length, *benchmark, {}, name);
    const MotSummary summary = ComputeAll(seq);
    Compare(name, summary, expected.at("cases").at(name).at("expected"), &table);
    by_case[name] = summary;
    ++cases;
  }
  EXPECT_GT(cases, 0);
  int groups = 0;
  for (const auto& [group, body] : expected.at("groups").items()) {
    std::vector<MotSummary> members;
    for (const json& m : body.at("members")) members.push_back(by_case.at(m.get<std::string>()));
    Compare(group, Pool(members, group), body.at("expected"), &table);
    ++groups;
  }
  EXPECT_GT(groups, 0);
  std::string report =
      fmt::format("\nMOT conformance: {} cases, {} groups ({})\n", cases, groups, dir.string());
  report += fmt::format("{:<16} {:>6} {:>6}  {}\n", "metric", "pass", "fail", "result");
  for (const auto& [name, t] : table) {
    report += fmt::format("{:<16} {:>6} {:>6}  {}\n", name, t.passed, t.failed,
                          t.failed == 0 ? "PASS" : "FAIL");
  }
  std::printf("%s", report.c_str());
}

}  // namespace
}  // namespace hcpf::metrics
