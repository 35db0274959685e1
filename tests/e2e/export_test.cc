// End-to-end test of `hcpf export DIR --trackeval OUT` read back with
// `hcpf score --trackeval-root OUT` through the real executable: every
// (sequence, tracker) scores to its run's own metrics.json; exit codes.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "support/process.h"

namespace hcpf {
namespace {

namespace fs = std::filesystem;
using testing::FreshDir;
using testing::ReadFile;
using testing::RunCommand;

using testing::kHcpf;

TEST(ExportCli, TrackEvalLayoutScoresToTheRunsOwnMetrics) {
  const fs::path dir = FreshDir("export-cli");
  // crossing-dominant shortened to 40 frames, two seeds x two resamplers.
  std::ofstream(dir / "sweep.yaml") << "base: " << testing::LibraryScenario("crossing-dominant")
                                    << "\nseeds: 2\ngrid:\n  frames: [40]\n"
                                       "  tracker.resampling.method: [systematic, charged]\n";
  auto r = RunCommand(kHcpf + " sweep " + (dir / "sweep.yaml").string() + " --out " +
                      (dir / "sweep").string() + " --jobs 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const fs::path out = dir / "trackeval";
  r = RunCommand(kHcpf + " export " + (dir / "sweep").string() + " --trackeval " + out.string() +
                 " --benchmark SIM --split test");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(ReadFile(out / "gt" / "mot_challenge" / "seqmaps" / "SIM-test.txt"),
            "name\nframes-40_seed0\nframes-40_seed1\n");

  // (sequence, tracker) -> run folder, from export.csv.
  std::map<std::pair<std::string, std::string>, std::string> run_dir;
  std::stringstream csv(ReadFile(out / "export.csv"));
  std::string line;
  std::getline(csv, line);
  while (std::getline(csv, line)) {
    std::vector<std::string> f;
    std::stringstream s(line);
    for (std::string field; std::getline(s, field, ',');) f.push_back(field);
    ASSERT_GE(f.size(), 7U) << line;
    run_dir[{f[0], f[1]}] = f[6];
  }
  ASSERT_EQ(run_dir.size(), 4U);

  r = RunCommand(kHcpf + " score --trackeval-root " + out.string() + " --json " +
                 (dir / "scores.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // Two tables (one per tracker), the percent note once, under the last.
  const size_t note = r.output.find("HOTA to IDR in percent");
  ASSERT_NE(note, std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("HOTA to IDR in percent", note + 1), std::string::npos) << r.output;
  EXPECT_GT(note, r.output.rfind("COMBINED")) << r.output;
  const nlohmann::json scores = nlohmann::json::parse(ReadFile(dir / "scores.json"));
  ASSERT_EQ(scores.size(), 2U);  // two trackers
  int compared = 0;
  for (const auto& t : scores) {
    EXPECT_EQ(t["bench"], "SIM-test");
    for (const auto& [seq, m] : t["metrics"]["sequences"].items()) {
      const std::string tracker = t["tracker"].get<std::string>();
      SCOPED_TRACE(tracker + " " + seq);
      ASSERT_EQ(run_dir.count({seq, tracker}), 1U);
      const nlohmann::json own = nlohmann::json::parse(
          ReadFile(dir / "sweep" / run_dir[{seq, tracker}] / "metrics.json"))["mot"];
      for (const char* name : {"MOTA", "IDF1", "HOTA"}) {
        EXPECT_DOUBLE_EQ(m[name].get<double>(), own[name].get<double>()) << name;
      }
      ++compared;
    }
  }
  EXPECT_EQ(compared, 4);

  // OUT not empty, DIR without a store: bad input, exit 2.
  EXPECT_EQ(
      RunCommand(kHcpf + " export " + (dir / "sweep").string() + " --trackeval " + out.string())
          .exit_code,
      2);
  EXPECT_EQ(
      RunCommand(kHcpf + " export " + dir.string() + " --trackeval " + (dir / "other").string())
          .exit_code,
      2);
}

}  // namespace
}  // namespace hcpf
