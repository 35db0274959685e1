// Report statistics (hand-worked t intervals) and the report files of a tiny sweep.

#include "hcpf/studies/report.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "hcpf/core/error.h"
#include "hcpf/studies/results_store.h"
#include "hcpf/studies/sweep.h"
#include "sweep_fixture.h"
#include "text.h"

namespace hcpf::studies {
namespace {

namespace fs = std::filesystem;

std::string Read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

size_t Count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// Runs the sweep into DIR/out with 2 jobs and no progress; returns that folder.
std::string RunQuietly(const SweepSpec& spec, const fs::path& dir) {
  SweepOptions o;
  o.out_dir = (dir / "out").string();
  o.jobs = 2;
  o.progress = false;
  RunSweep(spec, ExpandSweep(spec), o);
  return o.out_dir;
}

TEST(ReportStatistics, StudentQuantilesMatchTables) {
  // Printed two-sided 95 % t tables: 12.706 (1), 2.228 (10), 2.042 (30),
  // 2.021 (40), 2.000 (60), 1.980 (120). Above 30 the expansion must agree to 1e-3.
  EXPECT_DOUBLE_EQ(StudentT975(1), 12.706);
  EXPECT_DOUBLE_EQ(StudentT975(10), 2.228);
  EXPECT_NEAR(StudentT975(40), 2.021, 1e-3);
  EXPECT_NEAR(StudentT975(60), 2.000, 1e-3);
  EXPECT_NEAR(StudentT975(120), 1.980, 1e-3);
}

TEST(ReportStatistics, MeanAndHalfWidthByHand) {
  // {1, 2, 3}: mean 2, s = 1, half-width = t(2) * 1 / sqrt(3) = 4.303 / 1.7320508 = 2.484338.
  MeanCi a = MeanConfidence95({1.0, 2.0, 3.0});
  EXPECT_EQ(a.n, 3);
  EXPECT_DOUBLE_EQ(a.mean, 2.0);
  EXPECT_NEAR(a.half_width, 2.484338, 1e-6);
  // NaN values are left out: {4, 6}: mean 5, s = sqrt(2), half-width = 12.706 * sqrt(2)/sqrt(2).
  MeanCi b = MeanConfidence95({std::nan(""), 4.0, 6.0});
  EXPECT_EQ(b.n, 2);
  EXPECT_DOUBLE_EQ(b.mean, 5.0);
  EXPECT_NEAR(b.half_width, 12.706, 1e-9);
  MeanCi c = MeanConfidence95({0.5});
  EXPECT_EQ(c.n, 1);
  EXPECT_EQ(c.half_width, 0.0);
  EXPECT_TRUE(std::isnan(MeanConfidence95({}).mean));
}

TEST(Report, HtmlHasOnePlotWithDataPerMetricAndCsvHasOneRowPerCell) {
  const auto dir = testing::SweepFolder("report-files");
  const SweepSpec spec = LoadSweepFile(
      testing::WriteSweep(dir,
                          "base: base.yaml\nseeds: 3\ngrid:\n  tracker.particles: [20, 200]\n"
                          "  tracker.resampling.method: [systematic, charged]\n"
                          "report: {x: tracker.particles, series: tracker.resampling.method, y: "
                          "[idf1, hota, ms_per_frame]}\n"));
  SweepOptions o;
  o.out_dir = (dir / "out").string();
  o.jobs = 2;
  o.progress = false;
  const auto runs = ExpandSweep(spec);
  RunSweep(spec, runs, o);
  // A video in the first-seed run of (20, charged) (index 3: ((0*2)+1)*3 + 0) and
  // in a second-seed run (index 4), which must not be linked.
  ASSERT_EQ(runs[3].seed_index, 0);
  std::ofstream(fs::path(o.out_dir) / "runs" / runs[3].key / "overlay.mp4") << "video";
  std::ofstream(fs::path(o.out_dir) / "runs" / runs[4].key / "overlay.mp4") << "video";
  const ReportResult r = WriteReport({.dir = o.out_dir});
  EXPECT_EQ(r.plots, 3);
  EXPECT_EQ(r.cells, 4);
  const std::string html = Read(r.html_path);
  EXPECT_EQ(Count(html, "<svg"), 3U);
  for (const char* id : {"plot-idf1", "plot-hota", "plot-ms_per_frame"}) {
    const size_t at = html.find(id);
    ASSERT_NE(at, std::string::npos) << id;
    const size_t end = html.find("</svg>", at);
    const std::string svg = html.substr(at, end - at);
    // Two lines (systematic, charged), each a <path> through its points, and a legend naming them.
    EXPECT_GE(Count(svg, "<path"), 4U) << id;
    EXPECT_NE(svg.find("systematic"), std::string::npos);
    EXPECT_NE(svg.find("charged"), std::string::npos);
  }
  // Self-contained: nothing loaded from elsewhere.
  EXPECT_EQ(html.find("src=\"http"), std::string::npos);
  EXPECT_EQ(html.find("<script src"), std::string::npos);
  EXPECT_EQ(html.find("<link"), std::string::npos);
  EXPECT_NE(html.find("name: &quot;minimal&quot;"),
            std::string::npos);  // the resolved base scenario, escaped
  EXPECT_NE(html.find("href=\"runs/" + runs[3].key + "/overlay.mp4\""), std::string::npos);
  EXPECT_EQ(html.find("runs/" + runs[4].key + "/overlay.mp4"), std::string::npos);

  // summary.csv: header + 4 cells; the idf1 mean of cell (200, charged) is the
  // mean of its three runs' values in the store, computed here independently.
  const std::string csv = Read(r.csv_path);
  EXPECT_EQ(Count(csv, "\n"), 5U);
  double sum = 0.0;
  int n = 0;
  for (const RunRecord& rec : ResultsStore::Open(o.out_dir + "/results.sqlite")->Runs()) {
    if (rec.values[0] == "200" && rec.values[1] == "charged") {
      sum += rec.metrics.at("idf1");
      ++n;
    }
  }
  ASSERT_EQ(n, 3);
  const size_t row = csv.find("200,charged,3,0,");
  ASSERT_NE(row, std::string::npos) << csv;
  const std::string header = csv.substr(0, csv.find('\n'));
  // Column of idf1_mean in the header.
  int column = 0;
  for (size_t at = 0, next = 0;
       (next = header.find(',', at)) != std::string::npos || at < header.size(); at = next + 1) {
    if (header.substr(at, next == std::string::npos ? std::string::npos : next - at) == "idf1_mean")
      break;
    ++column;
    if (next == std::string::npos) break;
  }
  std::stringstream line(csv.substr(row, csv.find('\n', row) - row));
  std::string cell;
  for (int i = 0; i <= column; ++i) std::getline(line, cell, ',');
  EXPECT_NEAR(std::stod(cell), sum / 3.0, 1e-5);  // csv writes 6 significant digits
}

// report.x_metric: each cell sits at its mean of a metric. With x_metric and
// y both idf1 every plotted point lies on the diagonal, and a line's points
// keep the order of its swept x values. The plot data is read through a
// gnuplot wrapper that keeps a copy.
TEST(Report, XMetricPlacesEachCellAtItsMeanOfThatMetric) {
  const auto dir = testing::SweepFolder("report-x-metric");
  const SweepSpec spec = LoadSweepFile(
      testing::WriteSweep(dir,
                          "base: base.yaml\nseeds: 2\ngrid:\n  tracker.particles: [20, 60, 200]\n"
                          "report: {x: tracker.particles, x_metric: idf1, y: [idf1, hota]}\n"));
  ASSERT_EQ(spec.report.x_metric, "idf1");
  const std::string out = RunQuietly(spec, dir);
  const fs::path kept = dir / "kept";
  fs::create_directories(kept);
  const fs::path wrapper = dir / "gnuplot.sh";
  std::ofstream(wrapper) << "#!/bin/sh\ncp \"$(dirname \"$1\")\"/plot_*.dat " << kept.string()
                         << "/\nexec gnuplot \"$@\"\n";
  fs::permissions(wrapper, fs::perms::owner_all);
  const ReportResult r = WriteReport({.dir = out, .gnuplot = wrapper.string()});
  const std::string html = Read(r.html_path);
  EXPECT_NE(html.find("(idf1; mean per cell, lines follow tracker.particles)"), std::string::npos);
  std::stringstream rows(Read(kept / "plot_0.dat"));
  std::string line;
  int points = 0;
  while (std::getline(rows, line)) {
    if (line.empty() || line[0] == '#') continue;
    double x = 0, mean = 0;
    std::stringstream(line) >> x >> mean;
    EXPECT_NEAR(x, mean, 1e-9) << line;
    ++points;
  }
  EXPECT_EQ(points, 3);
  // The x of the second plot (hota) is still idf1: its rows' x are the first plot's.
  std::stringstream a(Read(kept / "plot_0.dat")), b(Read(kept / "plot_1.dat"));
  std::string la, lb;
  while (std::getline(a, la) && std::getline(b, lb)) {
    EXPECT_EQ(la.substr(0, la.find(' ')), lb.substr(0, lb.find(' ')));
  }
}

// report.pool: the resampler's runs share a cell; each cell then holds
// 2 resamplers x 3 seeds = 6 runs, and there is one line.
TEST(Report, PooledKeysShareACell) {
  const auto dir = testing::SweepFolder("report-pool");
  const SweepSpec spec = LoadSweepFile(testing::WriteSweep(
      dir,
      "base: base.yaml\nseeds: 3\ngrid:\n  tracker.particles: [20, 200]\n"
      "  tracker.resampling.method: [systematic, charged]\n"
      "report: {x: tracker.particles, pool: [tracker.resampling.method], y: [idf1]}\n"));
  ASSERT_EQ(spec.report.pool, std::vector<std::string>{"tracker.resampling.method"});
  const std::string out = RunQuietly(spec, dir);
  const ReportResult r = WriteReport({.dir = out});
  EXPECT_EQ(r.cells, 2);
  const std::string csv = Read(r.csv_path);
  EXPECT_NE(csv.find("\n20,all,6,0,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("\n200,all,6,0,"), std::string::npos) << csv;
  EXPECT_NE(Read(r.html_path).find("every value of <code>tracker.resampling.method</code>"),
            std::string::npos);
  // Bad input: pooling x, or a key not swept.
  for (const char* pool : {"[tracker.particles]", "[tracker.resampling.methd]"}) {
    EXPECT_THROW(LoadSweepFile(testing::WriteSweep(
                     dir, std::string("base: base.yaml\ngrid:\n  tracker.particles: [20, 200]\n"
                                      "  tracker.resampling.method: [systematic, charged]\n"
                                      "report: {x: tracker.particles, pool: ") +
                              pool + "}\n")),
                 InputError)
        << pool;
  }
}

// A key zipped with x moves along the line with it: it does not split lines
// (two lines, systematic and charged, each through both x values).
TEST(Report, KeysZippedWithXDoNotSplitLines) {
  const auto dir = testing::SweepFolder("report-zip-x");
  const SweepSpec spec = LoadSweepFile(testing::WriteSweep(
      dir,
      "base: base.yaml\ngrid:\n  tracker.resampling.method: [systematic, charged]\n"
      "zip:\n  tracker.particles: [20, 200]\n  tracker.dynamics.sigma_pos_px: [1, 2]\n"
      "report: {x: tracker.particles, series: tracker.resampling.method, y: [idf1]}\n"));
  const std::string out = RunQuietly(spec, dir);
  const std::string html = Read(WriteReport({.dir = out}).html_path);
  const size_t at = html.find("plot-idf1");
  ASSERT_NE(at, std::string::npos);
  const std::string svg = html.substr(at, html.find("</svg>", at) - at);
  EXPECT_EQ(svg.find("sigma_pos_px="), std::string::npos) << "a zipped key split the lines";
  EXPECT_NE(svg.find("systematic"), std::string::npos);
  EXPECT_NE(svg.find("charged"), std::string::npos);
}

TEST(Report, MissingStoreIsBadInput) {
  EXPECT_THROW(WriteReport({.dir = "/nonexistent/hcpf"}), InputError);
}

}  // namespace
}  // namespace hcpf::studies

namespace hcpf::studies {
namespace {

// RFC 4648 section 10 test vectors.
TEST(Base64, Rfc4648Vectors) {
  EXPECT_EQ(Base64(""), "");
  EXPECT_EQ(Base64("f"), "Zg==");
  EXPECT_EQ(Base64("fo"), "Zm8=");
  EXPECT_EQ(Base64("foo"), "Zm9v");
  EXPECT_EQ(Base64("foob"), "Zm9vYg==");
  EXPECT_EQ(Base64("fooba"), "Zm9vYmE=");
  EXPECT_EQ(Base64("foobar"), "Zm9vYmFy");
  EXPECT_EQ(Base64(std::string("\xff\x00\x80", 3)), "/wCA");
}

TEST(EscapeMarkup, EscapesTheFourCharacters) {
  EXPECT_EQ(EscapeMarkup("a<b>&\"c'"), "a&lt;b&gt;&amp;&quot;c'");
}

}  // namespace
}  // namespace hcpf::studies
