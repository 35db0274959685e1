// A sweep with external trackers (docs/external-trackers.md): a program that
// fails is recorded as a failed run and the sweep goes on; an external run's
// particle-filter metrics are missing (NaN in the store, empty in the
// report's summary.csv), never 0.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "hcpf/studies/report.h"
#include "hcpf/studies/results_store.h"
#include "hcpf/studies/sweep.h"
#include "sweep_fixture.h"

namespace hcpf::studies {
namespace {

namespace fs = std::filesystem;
using testing::SweepFolder;
using testing::WriteSweep;

TEST(ExternalSweep, FailedProgramIsAFailedRunAndTheSweepGoesOn) {
  const fs::path dir = SweepFolder("external");
  const std::string src = HCPF_SOURCE_DIR;
  const std::string sweep = WriteSweep(
      dir,
      "base: base.yaml\n"
      "grid: {observation.simulated.clutter_per_frame: [0, 1]}\n"
      "zip:\n"
      "  name: [pf, broken, sort]\n"
      "  tracker.type: [particle_filter, external, external]\n"
      "  tracker.command: [[], [" +
          src + "/scenarios/tests/data/external/bad_tracker.py, exit], [" + src +
          "/examples/trackers/sort_tracker.py]]\n"
          "report: {x: observation.simulated.clutter_per_frame, series: name, reference: pf,\n"
          "         y: [idf1, da_accuracy]}\n");
  const SweepSpec spec = LoadSweepFile(sweep);
  const std::vector<SweepRun> runs = ExpandSweep(spec);
  ASSERT_EQ(runs.size(), 6u);
  SweepOptions options;
  options.out_dir = (dir / "out").string();
  options.jobs = 2;
  options.progress = false;
  const SweepResult result = RunSweep(spec, runs, options);
  EXPECT_EQ(result.computed, 4);
  EXPECT_EQ(result.failed, 2);

  const auto store = ResultsStore::Open((dir / "out" / "results.sqlite").string());
  std::map<std::string, RunRecord> by_name;
  for (const RunRecord& r : store->Runs()) {
    if (r.values.at(0) == "0") by_name[r.values.at(1)] = r;  // clutter 0
  }
  ASSERT_EQ(by_name.size(), 3u);
  EXPECT_FALSE(by_name["broken"].ok);
  EXPECT_NE(by_name["broken"].error.find("exited with status 3"), std::string::npos)
      << by_name["broken"].error;
  EXPECT_NE(by_name["broken"].error.find("bad_tracker: giving up at once"), std::string::npos)
      << by_name["broken"].error;
  ASSERT_TRUE(by_name["sort"].ok) << by_name["sort"].error;
  EXPECT_TRUE(std::isnan(by_name["sort"].metrics.at("da_accuracy")));
  EXPECT_TRUE(std::isfinite(by_name["sort"].metrics.at("idf1")));
  EXPECT_GT(by_name["sort"].metrics.at("idf1"), 0.0);
  ASSERT_TRUE(by_name["pf"].ok) << by_name["pf"].error;
  EXPECT_TRUE(std::isfinite(by_name["pf"].metrics.at("da_accuracy")));

  // The report: SORT's cell has IDF1 and no DA accuracy (empty, n = 0).
  const ReportResult report = WriteReport({.dir = (dir / "out").string()});
  std::ifstream csv(report.csv_path);
  std::stringstream text;
  text << csv.rdbuf();
  std::string header, line, sort_row;
  std::getline(text, header);
  while (std::getline(text, line)) {
    if (line.rfind("0,sort,", 0) == 0) sort_row = line;
  }
  ASSERT_FALSE(sort_row.empty()) << text.str();
  const auto column = [](const std::string& row, const std::string& head, const std::string& name) {
    std::vector<std::string> names, cells;
    std::stringstream h(head), r(row);
    for (std::string c; std::getline(h, c, ',');) names.push_back(c);
    for (std::string c; std::getline(r, c, ',');) cells.push_back(c);
    cells.resize(names.size());
    for (size_t i = 0; i < names.size(); ++i) {
      if (names[i] == name) return cells[i];
    }
    return std::string("(no column)");
  };
  EXPECT_EQ(column(sort_row, header, "da_accuracy_mean"), "");
  EXPECT_EQ(column(sort_row, header, "da_accuracy_n"), "0");
  EXPECT_EQ(column(sort_row, header, "idf1_n"), "1");
  EXPECT_NE(column(sort_row, header, "idf1_mean"), "");
  // One line per name: tracker.type and tracker.command follow the name
  // (zipped with it), so they neither split nor label the lines; SORT's
  // runs pair with the reference particle filter's on the same seed and x.
  std::ifstream html_file(report.html_path);
  std::stringstream html;
  html << html_file.rdbuf();
  EXPECT_NE(html.str().find("<title>sort</title>"), std::string::npos);
  EXPECT_EQ(html.str().find("tracker.type=external"), std::string::npos);
  EXPECT_NE(html.str().find("sort \u2212 pf"), std::string::npos);
  // A row per non-reference cell: sort and broken (no successful runs: no
  // pairs) at clutter 0 and 1.
  EXPECT_EQ(report.comparisons, 4);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hcpf::studies
