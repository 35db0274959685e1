// Report statistics (hand-worked t intervals) and the report files of a tiny sweep.

#include "hcpf/studies/report.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sqlite3.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <tuple>
#include <vector>

#include "hcpf/core/error.h"
#include "hcpf/scenarios/output_folder.h"
#include "hcpf/scenarios/run.h"
#include "hcpf/scenarios/scenario.h"
#include "hcpf/scenarios/version.h"
#include "hcpf/studies/results_store.h"
#include "hcpf/studies/sweep.h"
#include "scene_sketch.h"
#include "sweep_fixture.h"
#include "text.h"

namespace hcpf::studies {
namespace {

namespace fs = std::filesystem;

// A finished hand-made run of the store in `dir`, its folder made (the
// report links it); the caller adds its metrics (and may set ok = false).
RunRecord HandRun(const fs::path& dir, std::string key, int64_t index, int seed_index,
                  uint64_t seed, std::vector<std::string> values) {
  RunRecord r;
  r.key = std::move(key);
  r.index = index;
  r.seed_index = seed_index;
  r.seed = seed;
  r.values = std::move(values);
  r.ok = true;
  r.run_dir = "runs/" + r.key;
  fs::create_directories(dir / r.run_dir);
  return r;
}

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

// A gnuplot that keeps a copy of the data files and the script of every
// plot in `kept`, and of the box files gnuplot writes (FitCanvasToBox).
fs::path KeepingGnuplot(const fs::path& dir, const fs::path& kept) {
  fs::create_directories(kept);
  const fs::path wrapper = dir / "gnuplot.sh";
  std::ofstream(wrapper)
      << "#!/bin/sh\nwork=\"$(dirname \"$1\")\"\ncp \"$work\"/*.dat \"$work\"/*.gp "
      << kept.string() << "/\ngnuplot \"$@\" || exit $?\n"
      << "for f in \"$work\"/*-box.txt; do [ -f \"$f\" ] && cp \"$f\" " << kept.string()
      << "/; done\nexit 0\n";
  fs::permissions(wrapper, fs::perms::owner_all);
  return wrapper;
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
  const fs::path kept = dir / "kept";
  const ReportResult r =
      WriteReport({.dir = o.out_dir, .gnuplot = KeepingGnuplot(dir, kept).string()});
  EXPECT_EQ(r.plots, 3);
  EXPECT_EQ(r.cells, 4);
  // charged − systematic at both x: two comparisons, one difference plot per metric.
  EXPECT_EQ(r.comparisons, 2);
  EXPECT_EQ(r.difference_plots, 3);
  const std::string html = Read(r.html_path);
  EXPECT_EQ(Count(html, "<svg"), 7U);  // 3 plots, 3 of differences, the scene from above
  // The two wide tables (paired differences, cells) scroll by themselves
  // rather than widen the page (an audit: the main job's paired table was
  // 1290 px in a 1280 px window).
  EXPECT_EQ(Count(html, "<div class=\"wide\"><table>"), 2U);
  EXPECT_NE(html.find(".wide{overflow-x:auto;max-width:100%}"), std::string::npos);
  // The scene from above, from the first run's gt.json (the minimal
  // scenario's one target).
  EXPECT_NE(html.find("<h2 id=\"scene\">The scene from above</h2>"), std::string::npos);
  EXPECT_NE(html.find("no two targets' boxes overlap in the image"), std::string::npos);
  for (const char* id : {"plot-idf1", "plot-hota", "plot-ms_per_frame"}) {
    const size_t at = html.find(id);
    ASSERT_NE(at, std::string::npos) << id;
    const size_t end = html.find("</svg>", at);
    const std::string svg = html.substr(at, end - at);
    // A legend naming the two lines.
    EXPECT_NE(svg.find("systematic"), std::string::npos);
    EXPECT_NE(svg.find("charged"), std::string::npos);
  }
  // The data behind each plot: two lines (a "# name" block each), each
  // through its two cells, x = 20 and 200 particles, with a finite mean.
  for (int p = 0; p < 3; ++p) {
    std::stringstream data(Read(kept / ("plot_" + std::to_string(p) + ".dat")));
    std::string line;
    std::vector<std::vector<double>> xs;
    while (std::getline(data, line)) {
      if (line.rfind("# ", 0) == 0) {
        xs.emplace_back();
      } else if (!line.empty()) {
        ASSERT_FALSE(xs.empty()) << line;
        double x = 0, mean = 0;
        std::stringstream(line) >> x >> mean;
        EXPECT_TRUE(std::isfinite(mean)) << "plot " << p << ": " << line;
        xs.back().push_back(x);
      }
    }
    EXPECT_EQ(xs, std::vector<std::vector<double>>({{20, 200}, {20, 200}})) << "plot " << p;
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
  const ReportResult r = WriteReport({.dir = out, .gnuplot = KeepingGnuplot(dir, kept).string()});
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
  int compared = 0;
  while (std::getline(a, la) && std::getline(b, lb)) {
    EXPECT_EQ(la.substr(0, la.find(' ')), lb.substr(0, lb.find(' ')));
    if (!la.empty() && la[0] != '#') ++compared;
  }
  EXPECT_EQ(compared, 3) << "three cells in each plot";
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

// The rows of a CSV file after its header, split at commas.
std::vector<std::vector<std::string>> CsvRows(const fs::path& path) {
  std::stringstream text(Read(path));
  std::string line;
  std::getline(text, line);  // header
  std::vector<std::vector<std::string>> rows;
  while (std::getline(text, line)) {
    if (line.empty()) continue;
    std::vector<std::string> fields;
    std::stringstream f(line);
    std::string field;
    while (std::getline(f, field, ',')) fields.push_back(field);
    if (!line.empty() && line.back() == ',') fields.emplace_back();
    rows.push_back(fields);
  }
  return rows;
}

// A run of the minimal scene (20 frames) with a shaking camera (so the
// camera moves between frames) and the given camera-motion mode.
fs::path RunMinimal(const fs::path& dir, const std::string& mode) {
  const fs::path out = dir / ("run-" + mode);
  const scenarios::Scenario scenario =
      scenarios::LoadScenarioText(scenarios::testing::kMinimal, "base.yaml",
                                  {{"camera.shake_px", "1.0"},
                                   {"tracker.camera_motion", mode},
                                   {"tracker.scene_filter.particles", "100"}});
  scenarios::RunScenario(scenario, {.out_dir = out.string()});
  return out;
}

// hcpf report RUN_DIR: report.html in the run folder with the headline
// metrics and the per-frame camera-motion error, its legend naming the mode;
// the scene filter's ESS on a second axis. The plotted points are the rows of
// camera_motion.csv, read here independently.
TEST(RunReport, PlotsPerFrameCameraMotionErrorWithModeAndEss) {
  const auto dir = testing::SweepFolder("run-report");
  const fs::path run = RunMinimal(dir, "scene_filter");
  ASSERT_FALSE(fs::exists(run / "report.html"));
  EXPECT_EQ(ClassifyReportFolder(run.string()), ReportFolder::kRun);
  const fs::path kept = dir / "kept";
  const ReportResult r =
      WriteReport({.dir = run.string(), .gnuplot = KeepingGnuplot(dir, kept).string()});
  EXPECT_EQ(r.html_path, (run / "report.html").string());
  EXPECT_TRUE(r.csv_path.empty());
  EXPECT_EQ(r.plots, 4) << "camera motion, the timeline, the centre error and the scene";
  const std::string html = Read(run / "report.html");
  const size_t at = html.find("id=\"plot-camera_motion\"");
  ASSERT_NE(at, std::string::npos) << "no camera-motion plot";
  const std::string svg = html.substr(at, html.find("</svg>", at) - at);
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  EXPECT_NE(svg.find("camera-motion error (scene_filter)"), std::string::npos) << "mode in legend";
  EXPECT_NE(svg.find("ESS"), std::string::npos) << "the scene filter's ESS";
  EXPECT_NE(svg.find("similarity floor"), std::string::npos) << "the floor's line";
  EXPECT_GE(Count(svg, "<path"), 3U);
  EXPECT_NE(html.find("<tr><td>floor</td>"), std::string::npos) << "the floor in the table";
  // The headline table: a row per measured catalogue metric.
  EXPECT_NE(html.find("<code>da_accuracy</code>"), std::string::npos);
  EXPECT_NE(html.find("<code>camera_motion_error_px</code>"), std::string::npos);
  EXPECT_NE(html.find("Mode <code>scene_filter</code>"), std::string::npos);
  // The header says what the run is (an audit: settings given with --set
  // showed only in the resolved YAML at the page's foot).
  EXPECT_NE(html.find("tracker: particle filter, 100 particles, charged resampling, likelihood "
                      "detections_mixture, camera motion scene_filter, config hash"),
            std::string::npos)
      << html.substr(0, 2000);

  EXPECT_NE(html.find("name: &quot;minimal&quot;"), std::string::npos) << "resolved scenario";
  EXPECT_FALSE(fs::exists(run / ".report-work")) << "work files removed";

  // Every csv row is plotted: frame, error_px, ess and floor_px (columns 1, 6, 7, 8).
  const auto csv = CsvRows(run / "camera_motion.csv");
  ASSERT_EQ(csv.size(), 19U) << "frames 2..20 of a 20-frame run";
  EXPECT_EQ(csv.front()[0], "2") << "frames count from 1, as in filters.csv";
  EXPECT_EQ(csv.back()[0], "20");
  std::stringstream dat(Read(kept / "camera_motion.dat"));
  std::string line;
  size_t row = 0;
  while (std::getline(dat, line)) {
    if (line.empty() || line[0] == '#') continue;
    ASSERT_LT(row, csv.size());
    double frame = 0, error = 0, ess = 0, floor = 0;
    std::stringstream(line) >> frame >> error >> ess >> floor;
    EXPECT_EQ(frame, std::stod(csv[row][0]));
    EXPECT_NEAR(error, std::stod(csv[row][5]), 1e-5 * (1 + std::abs(error)));  // 6 digits
    EXPECT_NEAR(ess, std::stod(csv[row][6]), 1e-5 * (1 + std::abs(ess)));
    EXPECT_NEAR(floor, std::stod(csv[row][7]), 1e-5 * (1 + std::abs(floor)));
    EXPECT_LE(std::stod(csv[row][7]), std::stod(csv[row][5]) + 1e-9) << "no estimate beats it";
    ++row;
  }
  EXPECT_EQ(row, csv.size());

  // A run's folder with its report is still one hcpf run may replace.
  EXPECT_EQ(scenarios::WhyNotOurOutput(run), "");
}

// A rendered run with a detector: the report's detection-quality table, one
// row for all targets and one per non-empty bin, from metrics.json's
// detection block (written here by hand, so every cell is derived below).
TEST(RunReport, DetectionQualityTableHasARowPerNonEmptyBin) {
  const auto dir = testing::SweepFolder("run-report-detection");
  const fs::path run = RunMinimal(dir, "none");
  EXPECT_EQ(Read(run / "metrics.json").find("\"detection\""), std::string::npos)
      << "a simulated run has no detection block";
  EXPECT_EQ(Read(WriteReport({.dir = run.string()}).html_path).find("Detection quality"),
            std::string::npos);
  auto metrics = nlohmann::json::parse(Read(run / "metrics.json"));
  const auto counts = [](int tp, int fp, int fn) {
    return nlohmann::json{{"tp", tp}, {"fp", fp}, {"fn", fn}};
  };
  metrics["detection"] = {
      {"iou", counts(8, 2, 2)},
      {"centre", counts(9, 1, 1)},
      {"by_size_px",
       {{{"lo", 0.0}, {"hi", 8.0}, {"iou", counts(0, 0, 0)}, {"centre", counts(0, 0, 0)}},
        {{"lo", 16.0}, {"hi", 32.0}, {"iou", counts(8, 2, 2)}, {"centre", counts(9, 1, 1)}},
        {{"lo", 64.0}, {"hi", "inf"}, {"iou", counts(0, 0, 0)}, {"centre", counts(0, 0, 0)}}}},
      {"by_visibility",
       {{{"lo", 0.5}, {"hi", 0.75}, {"iou", counts(0, 0, 1)}, {"centre", counts(0, 0, 1)}},
        {{"lo", 0.75}, {"hi", 1.0}, {"iou", counts(8, 0, 1)}, {"centre", counts(9, 0, 0)}}}},
      {"by_truncation",
       {{{"lo", 0.0}, {"hi", 0.15}, {"iou", counts(8, 0, 1)}, {"centre", counts(9, 0, 0)}},
        {{"lo", 0.5}, {"hi", 1.0}, {"iou", counts(0, 0, 1)}, {"centre", counts(0, 0, 1)}}}},
      {"mostly_visible",
       {{"min_visible", 0.75},
        {"iou", counts(8, 1, 1)},
        {"precision_recall", {{"average_precision", 0.625}}}}}};
  std::ofstream(run / "metrics.json") << metrics.dump();
  const std::string html = Read(WriteReport({.dir = run.string()}).html_path);
  // The mostly visible subset with its precision (8 / 9) and recall (8 / 9),
  // no centre rule; its AP sentence.
  EXPECT_NE(html.find("<tr><td class=\"k\">visible ≥ 0.75 (the others not counted)</td>"
                      "<td>8</td><td>1</td><td>1</td><td>0.889</td><td>0.889</td><td>–</td></tr>"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("<h2>Detection quality</h2>"), std::string::npos);
  // All: precision 8 / 10, recall 8 / 10, centre recall 9 / 10.
  EXPECT_NE(html.find("<tr><td class=\"k\">all</td><td>8</td><td>2</td><td>2</td>"
                      "<td>0.800</td><td>0.800</td><td>0.900</td></tr>"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("<tr><td class=\"k\">size 16–32 px</td><td>8</td><td>2</td><td>2</td>"),
            std::string::npos);
  EXPECT_EQ(html.find("size 0–8 px"), std::string::npos) << "an empty bin has no row";
  EXPECT_EQ(html.find("size 64–"), std::string::npos) << "an empty bin has no row";
  // Visibility and truncation rows: recall only (8 / 9; 0 / 1).
  EXPECT_NE(html.find("<tr><td class=\"k\">visible 0.75–1</td><td>8</td><td>1</td><td>–</td>"
                      "<td>–</td><td>0.889</td><td>1.000</td></tr>"),
            std::string::npos);
  EXPECT_NE(html.find("<tr><td class=\"k\">truncated 0.5–1</td><td>0</td><td>1</td><td>–</td>"
                      "<td>–</td><td>0.000</td><td>0.000</td></tr>"),
            std::string::npos);
  // No labels block (an unlabelled detector): no label sentence; with one,
  // its counts and accuracy.
  EXPECT_EQ(html.find("label accuracy"), std::string::npos);
  metrics["detection"]["labels"] = {{"matched", 9}, {"right", 8}, {"accuracy", 8.0 / 9.0}};
  std::ofstream(run / "metrics.json") << metrics.dump();
  const std::string labelled = Read(WriteReport({.dir = run.string()}).html_path);
  EXPECT_NE(labelled.find("8 of its 9 detections on a target name that target: label accuracy "
                          "<b>0.889</b>"),
            std::string::npos)
      << labelled;
}

// The precision-recall block of metrics.json (written by hand): the AP and the
// best-F1 point in the text, and a plot whose data file has one row per
// curve point and whose legend names the best F1's threshold.
TEST(RunReport, DetectionSectionPlotsThePrecisionRecallCurve) {
  const auto dir = testing::SweepFolder("run-report-precision-recall");
  const fs::path run = RunMinimal(dir, "none");
  auto metrics = nlohmann::json::parse(Read(run / "metrics.json"));
  metrics["detection"] = nlohmann::json::parse(R"({
      "iou": {"tp": 2, "fp": 2, "fn": 0}, "centre": {"tp": 2, "fp": 2, "fn": 0},
      "precision_recall": {"average_precision": 0.75,
        "best_f1": {"f1": 0.8, "precision": 0.6667, "recall": 1, "min_score": 0.4},
        "curve": {"recall": [0, 0.5, 1], "precision": [1, 1, 0.6667],
                  "min_score": [0.9, 0.9, 0.4]}},
      "mostly_visible": {"min_visible": 0.75, "iou": {"tp": 1, "fp": 1, "fn": 0},
        "precision_recall": {"average_precision": 0.625}}})");
  std::ofstream(run / "metrics.json") << metrics.dump();
  const fs::path kept = dir / "kept";
  const ReportResult r =
      WriteReport({.dir = run.string(), .gnuplot = KeepingGnuplot(dir, kept).string()});
  const std::string html = Read(r.html_path);
  EXPECT_NE(html.find("average precision <b>0.750</b>"), std::string::npos) << html;
  EXPECT_NE(html.find("The best F1, 0.800, is at score ≥ 0.4 (precision 0.667, recall 1.000)."),
            std::string::npos);
  EXPECT_NE(html.find("<code>det_ap</code>"), std::string::npos) << "a headline metric";
  EXPECT_NE(html.find("targets visible at least 0.75 alone (a detection on a less visible target "
                      "neither true nor false): average precision <b>0.625</b>"),
            std::string::npos)
      << html;
  const size_t at = html.find("id=\"plot-precision_recall\"");
  ASSERT_NE(at, std::string::npos) << "no precision-recall plot";
  const std::string svg = html.substr(at, html.find("</svg>", at) - at);
  EXPECT_NE(svg.find("best F1 0.800 at score >= 0.4"), std::string::npos);
  EXPECT_EQ(Read(kept / "precision_recall.dat"), "# recall precision\n0 1\n0.5 1\n1 0.6667\n");
  EXPECT_EQ(Read(kept / "precision_recall_best.dat"), "1 0.6667\n");

  // Without a counted target the curve is empty and AP undefined: no plot,
  // no AP sentence.
  metrics["detection"]["precision_recall"] = nlohmann::json::parse(
      R"({"average_precision": "nan", "best_f1": {"f1": "nan"},
          "curve": {"recall": [], "precision": [], "min_score": []}})");
  std::ofstream(run / "metrics.json") << metrics.dump();
  const std::string bare = Read(WriteReport({.dir = run.string()}).html_path);
  EXPECT_NE(bare.find("<h2>Detection quality</h2>"), std::string::npos);
  EXPECT_EQ(bare.find("average precision"), std::string::npos);
  EXPECT_EQ(bare.find("plot-precision_recall"), std::string::npos);
}

// The segments of a timeline ("x0 y length colour"), from the kept
// timeline.dat (KeepingGnuplot).
std::vector<std::string> TimelineSegments(const fs::path& kept) {
  std::vector<std::string> segments;
  std::stringstream dat(Read(kept / "timeline.dat"));
  for (std::string line; std::getline(dat, line);) {
    if (!line.empty() && line[0] != '#') segments.push_back(line);
  }
  return segments;
}

// The timeline: rows and segments from gt/gt.txt, metrics.json's
// filters.mapping and per_frame_states and detection.by_target, and the
// manifest's model frames, all written here by hand (metrics.json and the
// manifest count frames from 0, gt.txt and the plot from 1). Rows, top
// (y = 0) to bottom: target 1, its detections, filter 1 (mapped to it),
// target 2, its detections, filter 9 (mapped to it), filter 5 (no target).
// Segments "x0 y length colour", x0 = first frame − 0.5, one per run of a
// colour: target 1 visible 1.0 in frames 1–4, 0.5 in 5, 0.1 in 6; found in
// 1–2, missed in 3–4; filter 1 CORRECT 1–4, HIJACKED 5, CORRECT 6. Target 2
// in frames 3–6, missed in 3, found in 4–6, model cut in frame 3; filter 9
// CORRECT 3–4; filter 5 LOST in 1.
TEST(RunReport, TimelineDrawsTargetsTheirDetectionsAndTheirFilters) {
  const auto dir = testing::SweepFolder("run-report-timeline");
  const fs::path run = RunMinimal(dir, "none");
  std::ofstream(run / "gt" / "gt.txt")
      << "1,1,10,10,20,10,1,1,1\n2,1,11,10,20,10,1,1,1\n3,1,12,10,20,10,1,1,1\n"
         "4,1,13,10,20,10,1,1,1\n5,1,14,10,20,10,1,1,0.5\n6,1,15,10,20,10,1,1,0.1\n"
         "3,2,50,50,20,10,1,1,1\n4,2,50,51,20,10,1,1,1\n5,2,50,52,20,10,1,1,1\n"
         "6,2,50,53,20,10,1,1,1\n";
  auto metrics = nlohmann::json::parse(Read(run / "metrics.json"));
  metrics["filters"]["mapping"] =
      nlohmann::json::parse(R"([{"filter": 1, "target": 1}, {"filter": 9, "target": 2}])");
  nlohmann::json states = nlohmann::json::array();
  const auto state = [&states](int frame, int filter, const char* name) {
    states.push_back({{"frame", frame}, {"filter", filter}, {"state", name}});
  };
  for (int f = 0; f < 6; ++f) state(f, 1, f == 4 ? "HIJACKED" : "CORRECT");
  state(2, 9, "CORRECT");
  state(3, 9, "CORRECT");
  state(0, 5, "LOST");
  metrics["filters"]["per_frame_states"] = states;
  metrics["detection"] = nlohmann::json::parse(R"({"by_target": [
      {"target": 1, "found": 2, "missed": 2, "found_centre": 2, "missed_centre": 2,
       "found_frames": [[0, 1]], "missed_frames": [[2, 3]]},
      {"target": 2, "found": 3, "missed": 1, "found_centre": 4, "missed_centre": 0,
       "found_frames": [[3, 5]], "missed_frames": [[2, 2]]}]})");
  std::ofstream(run / "metrics.json") << metrics.dump();
  auto manifest = nlohmann::json::parse(Read(run / "manifest.json"));
  manifest["target_model_sources"] = nlohmann::json::parse(R"([{"target": 2, "frame": 2}])");
  // Filter 1 re-acquired at the end of frame 5 (from 0: frame 4), and a
  // frame past the run's end that is not drawn.
  manifest["tracker"]["reacquired"] =
      nlohmann::json::parse(R"([{"frame": 4, "filter": 1}, {"frame": 20, "filter": 1}])");
  std::ofstream(run / "manifest.json") << manifest.dump();

  const fs::path kept = dir / "kept";
  const ReportResult r =
      WriteReport({.dir = run.string(), .gnuplot = KeepingGnuplot(dir, kept).string()});
  EXPECT_EQ(r.plots, 4) << "the timeline, the centre error, camera motion and the scene";
  const std::string html = Read(r.html_path);
  ASSERT_NE(html.find("id=\"plot-timeline\""), std::string::npos);
  std::vector<std::string> segments = TimelineSegments(kept);
  const std::string dark = std::to_string(0x404040), half = std::to_string(0x9a9a9a),
                    little = std::to_string(0xd4d4d4), found = std::to_string(0x2ca02c),
                    missed = std::to_string(0xf4a0a0), correct = std::to_string(0x1f77b4),
                    hijacked = std::to_string(0xd62728), lost = std::to_string(0x9467bd);
  EXPECT_EQ(segments,
            std::vector<std::string>(
                {"0.5 0 4 " + dark, "4.5 0 1 " + half, "5.5 0 1 " + little, "0.5 -1 2 " + found,
                 "2.5 -1 2 " + missed, "0.5 -2 4 " + correct, "4.5 -2 1 " + hijacked,
                 "5.5 -2 1 " + correct, "2.5 -3 4 " + dark, "2.5 -4 1 " + missed,
                 "3.5 -4 3 " + found, "2.5 -5 2 " + correct, "0.5 -6 1 " + lost}));
  EXPECT_NE(Read(kept / "timeline_marks.dat").find("\n3 -4\n"), std::string::npos);
  EXPECT_EQ(Read(kept / "timeline_reacquired.dat"), "# frame row\n5 -2\n");
  // Deleted (the first frame a filter's row is absent from, before the
  // run's 20): filter 1 at 7 (its states end at 6), filter 9 at 5, filter 5
  // at 2.
  EXPECT_EQ(Read(kept / "timeline_deleted.dat"), "# frame row\n7 -2\n5 -5\n2 -6\n");
  const std::string gp = Read(kept / "timeline.gp");
  EXPECT_NE(gp.find("set ytics ('target 1' 0, 'detections' -1, 'filter 1' -2, 'target 2' -3, "
                    "'detections' -4, 'filter 9' -5, 'filter 5 (no target)' -6)"),
            std::string::npos)
      << gp;
  EXPECT_NE(gp.find("set xrange [0.5:20.5]"), std::string::npos) << "the run's 20 frames";
  // The legend names the colours drawn and no other.
  EXPECT_NE(gp.find("title 'HIJACKED'"), std::string::npos);
  EXPECT_NE(gp.find("title 'model cut'"), std::string::npos);
  EXPECT_NE(gp.find("title 're-acquired'"), std::string::npos);
  EXPECT_NE(gp.find("title 'deleted'"), std::string::npos);
  EXPECT_EQ(gp.find("title 'SWAPPED'"), std::string::npos);
  // The detection table's per-target rows: recall 2 / 4 and 3 / 4, centre 2 / 4 and 4 / 4.
  EXPECT_NE(html.find("<tr><td class=\"k\">target 1</td><td>2</td><td>2</td><td>–</td>"
                      "<td>–</td><td>0.500</td><td>0.500</td></tr>"),
            std::string::npos);
  EXPECT_NE(html.find("<tr><td class=\"k\">target 2</td><td>3</td><td>1</td><td>–</td>"
                      "<td>–</td><td>0.750</td><td>1.000</td></tr>"),
            std::string::npos);

  // Without filters (an external tracker) or a detector: the targets alone.
  metrics.erase("filters");
  metrics.erase("detection");
  std::ofstream(run / "metrics.json") << metrics.dump();
  WriteReport({.dir = run.string(), .gnuplot = KeepingGnuplot(dir, kept).string()});
  EXPECT_NE(Read(kept / "timeline.gp").find("set ytics ('target 1' 0, 'target 2' -1)"),
            std::string::npos);
  EXPECT_EQ(Read(kept / "timeline.gp").find("re-acquired"), std::string::npos)
      << "no filter row, so no ring";
}

// The centre error per frame of each target's filter (an audit: two runs
// differing in IDF1 0.952 against 0.910 had identical timelines and no
// picture of where). By hand: target 1's box (10, 10, 20, 10), centre (20,
// 15), in frames 1–3 and 5; filter 1's (13, 14, 20, 10), centre (23, 19),
// in frames 1, 2, 5 and 6: 5 px (3-4-5) in frames 1, 2 and 5, a gap at 3-4.
TEST(RunReport, PlotsTheCentreErrorOfEachTargetsFilter) {
  const auto dir = testing::SweepFolder("run-report-centre");
  const fs::path run = RunMinimal(dir, "none");
  std::ofstream(run / "gt" / "gt.txt", std::ios::trunc)
      << "1,1,10,10,20,10,1,1,1\n2,1,10,10,20,10,1,1,1\n3,1,10,10,20,10,1,1,1\n"
         "5,1,10,10,20,10,1,1,1\n";
  std::ofstream(run / "tracks.txt", std::ios::trunc)
      << "1,1,13,14,20,10,1,-1,-1,-1\n2,1,13,14,20,10,1,-1,-1,-1\n5,1,13,14,20,10,1,-1,-1,-1\n"
         "6,1,13,14,20,10,1,-1,-1,-1\n";
  auto metrics = nlohmann::json::parse(Read(run / "metrics.json"));
  metrics["filters"]["mapping"] = nlohmann::json::parse(R"([{"filter": 1, "target": 1}])");
  std::ofstream(run / "metrics.json", std::ios::trunc) << metrics.dump();
  const fs::path kept = dir / "kept";
  const std::string html = Read(
      WriteReport({.dir = run.string(), .gnuplot = KeepingGnuplot(dir, kept).string()}).html_path);
  EXPECT_NE(html.find("id=\"plot-centre_error\""), std::string::npos);
  EXPECT_EQ(Read(kept / "centre_error.dat"), "# target 1: filter 1\n1 5\n2 5\n\n5 5\n\n\n");
  EXPECT_NE(Read(kept / "centre_error.gp").find("title 'target 1: filter 1, mean 5 px'"),
            std::string::npos);
}

// A plot's key takes canvas, not plot (FitCanvasToBox): the timeline's rows
// stay 24 px apart and the centre-error plot 300 px tall whatever their keys
// hold (an audit: 18 targets' centre-error lines left their plot 200 of 440
// px, and the timeline's key of nine entries ran off its canvas). One target
// and its filter, CORRECT throughout, against 40 targets each with a filter
// (80 timeline rows, 40 centre-error lines, every state's colour in the
// key). Past ten lines the centre-error colours come round again, dashed.
// A text gnuplot's SVG terminal placed: its anchor (x, y from the top) and
// what it says.
struct SvgText {
  double x = 0, y = 0;
  std::string text;
};

// The SVG of `html` holding a text that starts with `marker`: its canvas
// height (the viewBox's) and every text placed with translate().
std::pair<double, std::vector<SvgText>> SvgTexts(const std::string& html,
                                                 const std::string& marker) {
  // Found by hand: std::regex recurses per character and overflows the
  // stack on a whole SVG.
  const std::string translate = "<g transform=\"translate(";
  for (size_t at = html.find("<svg"); at != std::string::npos; at = html.find("<svg", at + 1)) {
    const size_t end = std::min(html.find("</svg>", at), html.size());
    const size_t view = html.find("viewBox=\"0 0 ", at);
    if (view == std::string::npos || view > end) continue;
    std::istringstream box(html.substr(view + 13, 40));
    double width = 0, height = 0;
    box >> width >> height;
    std::vector<SvgText> texts;
    bool holds = false;
    for (size_t g = html.find(translate, at); g < end; g = html.find(translate, g + 1)) {
      SvgText t;
      char comma = 0;
      std::istringstream xy(html.substr(g + translate.size(), 40));
      xy >> t.x >> comma >> t.y;
      const size_t open = html.find('>', g);
      const size_t text = html.find_first_not_of(" \t\n", open + 1);
      if (!xy || comma != ',' || text >= end || html.compare(text, 6, "<text>") != 0) continue;
      t.text = html.substr(text + 6, html.find('<', text + 6) - text - 6);
      holds = holds || t.text.starts_with(marker);
      texts.push_back(std::move(t));
    }
    if (holds) return {height, texts};
  }
  ADD_FAILURE() << "no SVG holds a text starting with " << marker;
  return {};
}

// Each key entry (a text starting with one of `entries`, found once) lies on
// the canvas and off the plot's box (xmin xmax ymin ymax, px from the
// bottom), its whole text too, and two entries on one line do not overlap: the right-aligned
// text of the next one (about 5.5 px a character at 11 px sans) starts past
// the end of the one before.
void ExpectKeyEntriesOffThePlot(const std::pair<double, std::vector<SvgText>>& svg,
                                const std::array<double, 5>& box,
                                const std::vector<std::string>& entries) {
  const auto& [height, texts] = svg;
  std::map<double, std::vector<const SvgText*>> lines;
  for (const std::string& entry : entries) {
    std::vector<const SvgText*> found;
    for (const SvgText& t : texts) {
      if (t.text.starts_with(entry)) found.push_back(&t);
    }
    ASSERT_EQ(found.size(), 1u) << entry;
    const SvgText& t = *found.front();
    const double from_bottom = height - t.y;
    EXPECT_GT(t.x, 0.0) << t.text;
    EXPECT_GT(t.y, 0.0) << t.text;
    EXPECT_LT(t.y, height) << t.text;
    // The text runs left from its anchor (gnuplot's key text is right-aligned).
    const double left = t.x - 5.5 * static_cast<double>(t.text.size());
    const bool over = left < box[1] && t.x > box[0] && from_bottom > box[2] && from_bottom < box[3];
    EXPECT_FALSE(over) << t.text << " at (" << t.x << ", " << t.y << ") is over the plot";
    lines[t.y].push_back(&t);
  }
  for (auto& [y, line] : lines) {
    std::sort(line.begin(), line.end(), [](auto* a, auto* b) { return a->x < b->x; });
    for (size_t i = 1; i < line.size(); ++i) {
      EXPECT_GE(line[i]->x - 5.5 * static_cast<double>(line[i]->text.size()), line[i - 1]->x)
          << line[i - 1]->text << " and " << line[i]->text << " overlap at y " << y;
    }
  }
}

TEST(RunReport, APlotsKeyTakesCanvasNotPlot) {
  const auto dir = testing::SweepFolder("run-report-key");
  const fs::path run = RunMinimal(dir, "none");
  const fs::path kept = dir / "kept";
  const char* states[] = {"CORRECT", "SWAPPED", "HIJACKED", "STRAYED", "LOST", "COASTING"};
  // box file: xmin xmax ymin ymax height, px from the bottom.
  const auto box = [&](const char* file) {
    std::istringstream in(Read(kept / file));
    std::array<double, 5> v{};
    for (double& x : v) in >> x;
    EXPECT_TRUE(in) << file;
    return v;
  };
  std::array<double, 5> small{};
  for (const int targets : {1, 40}) {
    SCOPED_TRACE(fmt::format("{} targets", targets));
    std::ofstream gt(run / "gt" / "gt.txt", std::ios::trunc);
    std::ofstream tracks(run / "tracks.txt", std::ios::trunc);
    auto metrics = nlohmann::json::parse(Read(run / "metrics.json"));
    nlohmann::json mapping = nlohmann::json::array(), per_frame = nlohmann::json::array();
    for (int t = 1; t <= targets; ++t) {
      for (int f = 1; f <= 3; ++f) {
        gt << fmt::format("{},{},{},10,20,10,1,1,1\n", f, t, 10 * t);
        tracks << fmt::format("{},{},{},13,20,10,1,-1,-1,-1\n", f, t, 10 * t + f);
        per_frame.push_back({{"frame", f - 1},
                             {"filter", t},
                             {"state", targets == 1 ? "CORRECT" : states[(t + f) % 6]}});
      }
      mapping.push_back({{"filter", t}, {"target", t}});
    }
    gt.close();
    tracks.close();
    metrics["filters"]["mapping"] = mapping;
    metrics["filters"]["per_frame_states"] = per_frame;
    metrics.erase("detection");
    std::ofstream(run / "metrics.json", std::ios::trunc) << metrics.dump();
    const std::string html =
        Read(WriteReport({.dir = run.string(), .gnuplot = KeepingGnuplot(dir, kept).string()})
                 .html_path);
    const std::array<double, 5> timeline = box("timeline-box.txt");
    const std::array<double, 5> centre = box("centre_error-box.txt");
    // gnuplot places the box's edges to within a pixel.
    EXPECT_NEAR(timeline[3] - timeline[2], 24.0 * 2 * targets, 1.0);
    EXPECT_NEAR(centre[3] - centre[2], 300.0, 1.0);
    // Each key entry where it is drawn (a review: only the box and the
    // canvas were checked).
    std::vector<std::string> centre_entries;
    for (int t = 1; t <= targets; ++t) {
      centre_entries.push_back(fmt::format("target {}: filter {}, mean ", t, t));
    }
    ExpectKeyEntriesOffThePlot(SvgTexts(html, "target 1: filter 1, mean "), centre, centre_entries);
    if (targets > 1) {
      ExpectKeyEntriesOffThePlot(SvgTexts(html, "HIJACKED"), timeline,
                                 {std::begin(states), std::end(states)});
    }
    if (targets == 1) {
      small = centre;
      EXPECT_EQ(Read(kept / "centre_error.gp").find(" dt 2 "), std::string::npos);
      continue;
    }
    EXPECT_GT(centre[4], small[4] + 100) << "40 key entries below the plot";
    const std::string gp = Read(kept / "centre_error.gp");
    EXPECT_NE(gp.find("lc rgb '#1f77b4' dt 1 title 'target 1: filter 1, mean "), std::string::npos);
    EXPECT_NE(gp.find("lc rgb '#1f77b4' dt 2 title 'target 11: filter 11, mean "),
              std::string::npos);
    for (const char* state : states) {
      EXPECT_NE(Read(kept / "timeline.gp").find(fmt::format("title '{}'", state)),
                std::string::npos)
          << state;
    }
  }
}

// A tracks.txt the plot cannot read, cut short or missing: the section says
// so in place of its plot (a bad-input audit: it was gone without a word,
// exit 0, as the note was written only beside a plot).
TEST(RunReport, SaysWhyTheCentreErrorHasNoPlot) {
  const auto dir = testing::SweepFolder("run-report-centre-note");
  const fs::path run = RunMinimal(dir, "none");
  for (const std::string damage : {"unreadable", "missing"}) {
    SCOPED_TRACE(damage);
    if (damage == "missing") {
      fs::remove(run / "tracks.txt");
    } else {
      std::ofstream(run / "tracks.txt", std::ios::trunc) << "1,1,abc,2,3,4,1,-1,-1,-1\n";
    }
    const std::string html = Read(WriteReport({.dir = run.string()}).html_path);
    EXPECT_EQ(html.find("id=\"plot-centre_error\""), std::string::npos);
    const size_t section = html.find("<h2>Centre error per frame</h2>");
    ASSERT_NE(section, std::string::npos);
    const std::string paragraph = html.substr(section, html.find("</p>", section) - section);
    EXPECT_NE(paragraph.find((run / "tracks.txt").string() + " is left out of this plot: "),
              std::string::npos)
        << paragraph;
    EXPECT_NE(paragraph.find(damage == "missing" ? "it is missing." : "column"), std::string::npos)
        << paragraph;
    EXPECT_NE(paragraph.find("Nothing is left to plot."), std::string::npos) << paragraph;
  }
}

// An audit: a truck 98 % outside the image was drawn "visible ≥ 0.75" (the
// visible fraction counts only the part in the image) above 40 frames of
// "detector missed it" before its model existed. By hand: target 1 visible
// 1.0 in frames 1–4 with truncation 0, 0.5, 0.8 and 0 (gt.json, frames from
// 0): seen 1.0, 0.5, 0.2, 1.0 → dark, half, little, dark; missed in 1–3,
// found in 4, its model cut at the start of frame 3 (from 1; 2 from 0):
// frames 1–2 are misses before the model, 3 a miss.
TEST(RunReport, TimelineShadesTheShareSeenAndMissesBeforeTheModel) {
  const auto dir = testing::SweepFolder("run-report-timeline-seen");
  const fs::path run = RunMinimal(dir, "none");
  std::ofstream(run / "gt" / "gt.txt") << "1,1,10,10,20,10,1,1,1\n2,1,11,10,20,10,1,1,1\n"
                                          "3,1,12,10,20,10,1,1,1\n4,1,13,10,20,10,1,1,1\n";
  // The run's own gt.json, target 1's truncation set by hand.
  auto gt = nlohmann::json::parse(Read(run / "gt.json"));
  for (const auto& [frame, truncation] :
       {std::pair{0, 0.0}, std::pair{1, 0.5}, std::pair{2, 0.8}, std::pair{3, 0.0}}) {
    int set = 0;
    for (auto& o : gt["frames"][frame]["objects"]) {
      if (o["id"] == 1) o["truncation"] = truncation, ++set;
    }
    ASSERT_EQ(set, 1) << frame;
  }
  std::ofstream(run / "gt.json", std::ios::trunc) << gt.dump();
  auto metrics = nlohmann::json::parse(Read(run / "metrics.json"));
  metrics["detection"] = nlohmann::json::parse(R"({"by_target": [
      {"target": 1, "found": 1, "missed": 3, "found_centre": 1, "missed_centre": 3,
       "found_frames": [[3, 3]], "missed_frames": [[0, 2]]}]})");
  metrics["filters"]["hijack_rate"] = 1.0;
  std::ofstream(run / "metrics.json") << metrics.dump();
  auto manifest = nlohmann::json::parse(Read(run / "manifest.json"));
  manifest["target_model_sources"] = nlohmann::json::parse(R"([{"target": 1, "frame": 2}])");
  std::ofstream(run / "manifest.json") << manifest.dump();
  const fs::path kept = dir / "kept";
  WriteReport({.dir = run.string(), .gnuplot = KeepingGnuplot(dir, kept).string()});
  std::vector<std::string> segments = TimelineSegments(kept);
  const std::string dark = std::to_string(0x404040), half = std::to_string(0x9a9a9a),
                    little = std::to_string(0xd4d4d4), found = std::to_string(0x2ca02c),
                    missed = std::to_string(0xf4a0a0), no_model = std::to_string(0xf3dcb8);
  ASSERT_GE(segments.size(), 7U);
  segments.resize(7);  // the run's own filters' rows follow
  EXPECT_EQ(segments,
            std::vector<std::string>({"0.5 0 1 " + dark, "1.5 0 1 " + half, "2.5 0 1 " + little,
                                      "3.5 0 1 " + dark, "0.5 -1 2 " + no_model,
                                      "2.5 -1 1 " + missed, "3.5 -1 1 " + found}));
  const std::string gp = Read(kept / "timeline.gp");
  EXPECT_NE(gp.find("title 'missed, before its model was cut'"), std::string::npos) << gp;
  EXPECT_NE(gp.find("title 'target seen ≥ 0.75 (unhidden, in the image)'"), std::string::npos);
  // The headline's hijack rate says it counts lost filters (beside a
  // hijacked fraction of 0 a rate of 1 read as a contradiction: an audit).
  EXPECT_NE(Read(run / "report.html")
                .find("hijack rate<br><small>encounters after which a filter of either target is "
                      "HIJACKED, STRAYED or LOST (a target left with no filter counts as LOST "
                      "while in view"),
            std::string::npos);
  // A gt.json that does not parse leaves the shading to the visible
  // fraction and says so; the report stands (a review: it stopped it).
  std::ofstream(run / "gt.json", std::ios::trunc) << "{";
  const std::string broken = Read(
      WriteReport({.dir = run.string(), .gnuplot = KeepingGnuplot(dir, kept).string()}).html_path);
  EXPECT_NE(broken.find("gt.json was not read ("), std::string::npos);
  EXPECT_NE(broken.find("targets are shaded by visible fraction alone."), std::string::npos);
  EXPECT_EQ(TimelineSegments(kept).at(0), "0.5 0 4 " + dark)
      << "visible 1 in every frame: dark throughout";
}

// mode none: no scene filter, so no ESS column values and no ESS line.
// A run folder whose metrics.json is not a run's (a bad-input audit: "{}"
// gave a report of NaN with exit 0) is bad input naming the file and block.
TEST(RunReport, MetricsJsonWithoutItsMotBlockIsBadInput) {
  const auto dir = testing::SweepFolder("run-report-empty-metrics");
  const fs::path run = RunMinimal(dir, "none");
  for (const std::string text : {"{}", "[1, 2]", R"({"mot": 3})"}) {
    std::ofstream(run / "metrics.json") << text;
    try {
      WriteReport({.dir = run.string()});
      ADD_FAILURE() << text << " was accepted";
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find((run / "metrics.json").string() + ": mot: expected the metrics.json of "
                                                         "hcpf run"),
                std::string::npos)
          << m;
    }
    EXPECT_FALSE(fs::exists(run / "report.html")) << text;
  }
}

// --out takes a new or empty folder, or an earlier report's: a second
// bad-input audit found a report written into another sweep (replacing its
// report), into a run folder (which hcpf run then refused to reuse) and into
// a TrackEval export. Refused before anything is written.
TEST(RunReport, OutMustBeNewEmptyOrAnEarlierReport) {
  const auto dir = testing::SweepFolder("run-report-out");
  const fs::path run = RunMinimal(dir, "none");
  const fs::path other = RunMinimal(dir / "other", "none");
  fs::create_directories(dir / "notes");
  std::ofstream(dir / "notes" / "todo.txt") << "mine\n";
  for (const fs::path& out : {other, dir / "notes"}) {
    const std::string before = Read(out / (out == other ? "manifest.json" : "todo.txt"));
    try {
      WriteReport({.dir = run.string(), .out_dir = out.string()});
      ADD_FAILURE() << out << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--out: expected a new or empty folder, or one holding "
                                           "only an earlier report"),
                std::string::npos)
          << e.what();
    }
    EXPECT_FALSE(fs::exists(out / "report.html")) << out;
  }
  fs::create_directory_symlink(dir / "notes", dir / "link");
  EXPECT_THROW(WriteReport({.dir = run.string(), .out_dir = (dir / "link").string()}), InputError);
  // An earlier report's folder is written again.
  const fs::path reports = dir / "reports";
  WriteReport({.dir = run.string(), .out_dir = reports.string()});
  EXPECT_NO_THROW(WriteReport({.dir = run.string(), .out_dir = reports.string()}));
  // So is one where an earlier report was killed while writing (reports are
  // written whole, through a temporary file beside the name: WriteTextFile).
  std::ofstream(reports / ".report.html.tmp-999999999-0") << "<html>cut sh";
  EXPECT_NO_THROW(WriteReport({.dir = run.string(), .out_dir = reports.string()}));
  EXPECT_FALSE(fs::exists(reports / ".report.html.tmp-999999999-0")) << "a stale temporary file";
  std::ofstream(reports / ".notes.txt.tmp-999999-0") << "not a report's";
  EXPECT_THROW(WriteReport({.dir = run.string(), .out_dir = reports.string()}), InputError);
}

// --gnuplot is checked before anything is written: a folder, a missing or
// non-executable file, or a bare name not on PATH is bad input naming
// --gnuplot, and --out is not created (a second bad-input audit: a folder as
// gnuplot failed the report with exit 1 and left --out behind, empty).
TEST(RunReport, GnuplotThatCannotRunIsBadInputBeforeAnythingIsWritten) {
  const auto dir = testing::SweepFolder("run-report-gnuplot");
  const fs::path run = RunMinimal(dir, "none");
  std::ofstream(dir / "plain.txt") << "not a program\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {dir.string(), "which is a folder"},
      {(dir / "missing").string(), "which does not exist"},
      {(dir / "plain.txt").string(), "which is not an executable file"},
      {"hcpf-no-such-gnuplot", "not an executable file in any folder of PATH"}};
  for (const auto& [gnuplot, found] : cases) {
    const fs::path out = dir / "out";
    try {
      WriteReport({.dir = run.string(), .out_dir = out.string(), .gnuplot = gnuplot});
      ADD_FAILURE() << gnuplot << " was accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("--gnuplot: expected"), std::string::npos) << what;
      EXPECT_NE(what.find(found), std::string::npos) << what;
    }
    EXPECT_FALSE(fs::exists(out)) << gnuplot;
    EXPECT_FALSE(fs::exists(run / "report.html")) << gnuplot;
  }
}

// A manifest.json whose fields are not of the types hcpf run writes is bad
// input naming the field (a bad-input audit: "frames": "twenty" and "seed":
// -1 were shown in the header, "timings": "x" dropped a row).
TEST(RunReport, AManifestFieldOfAnotherTypeIsBadInput) {
  const auto dir = testing::SweepFolder("run-report-manifest-types");
  const fs::path run = RunMinimal(dir, "none");
  const auto good = nlohmann::json::parse(Read(run / "manifest.json"));
  for (const auto& [key, value, expected] :
       std::vector<std::tuple<std::string, nlohmann::json, std::string>>{
           {"frames", "twenty", "frames: expected a whole number, 1 to 100000, found \"twenty\""},
           // A later audit: 10^8 kept the report busy past a minute; a count
           // other than the scenario's drew the timeline to it.
           {"frames", 100000000, "frames: expected a whole number, 1 to 100000, found 100000000"},
           {"frames", 19,
            "frames: expected 20, the frames of its scenario.resolved.yaml, found 19"},
           {"seed", -1, "seed: expected a seed (a whole number, 0 or more), found -1"},
           {"timings", "x", "timings: expected an object, found \"x\""},
           {"config_hash", 17, "config_hash: expected text, found 17"}}) {
    nlohmann::json edited = good;
    edited[key] = value;
    std::ofstream(run / "manifest.json", std::ios::trunc) << edited.dump();
    try {
      WriteReport({.dir = run.string()});
      ADD_FAILURE() << key << " = " << value.dump() << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("manifest.json: " + expected), std::string::npos)
          << e.what();
    }
  }
  std::ofstream(run / "manifest.json", std::ios::trunc) << good.dump();
  EXPECT_NO_THROW(WriteReport({.dir = run.string()}));
  // The scenario's frames themselves (a second audit: "abc" was blamed on
  // the manifest, and a scenario without frames accepted).
  const std::string resolved = Read(run / "scenario.resolved.yaml");
  ASSERT_NE(resolved.find("\nframes: 20\n"), std::string::npos);
  for (const auto& [replacement, expected] : std::vector<std::pair<std::string, std::string>>{
           {"\nframes: abc\n",
            "scenario.resolved.yaml:8:9: frames: expected the run's frames, 1 to 100000, found "
            "\"abc\""},
           {"\n",
            "scenario.resolved.yaml: frames: expected the run's frames, 1 to 100000, found "
            "no frames"}}) {
    std::string edited = resolved;
    edited.replace(edited.find("\nframes: 20\n"), 12, replacement);
    std::ofstream(run / "scenario.resolved.yaml", std::ios::trunc) << edited;
    try {
      WriteReport({.dir = run.string()});
      ADD_FAILURE() << replacement << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  }
  std::ofstream(run / "scenario.resolved.yaml", std::ios::trunc) << resolved;
  // A manifest and a resolved scenario edited together past seqinfo.ini's
  // seqLength, which hcpf run writes with the same count (they were read,
  // the timeline drawn to their count).
  const std::string seqinfo = Read(run / "seqinfo.ini");
  ASSERT_NE(seqinfo.find("\nseqLength=20\n"), std::string::npos) << seqinfo;
  nlohmann::json longer = good;
  longer["frames"] = 400;
  std::ofstream(run / "manifest.json", std::ios::trunc) << longer.dump();
  std::string edited = resolved;
  edited.replace(edited.find("\nframes: 20\n"), 12, "\nframes: 400\n");
  std::ofstream(run / "scenario.resolved.yaml", std::ios::trunc) << edited;
  const int line = static_cast<int>(
      std::count(seqinfo.begin(), seqinfo.begin() + seqinfo.find("seqLength="), '\n') + 1);
  fs::remove(run / "report.html");
  try {
    WriteReport({.dir = run.string()});
    ADD_FAILURE() << "frames 400 against seqLength 20 was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(
                  fmt::format("seqinfo.ini:{}: Sequence.seqLength: expected 400, the frames of its "
                              "manifest.json and scenario.resolved.yaml, found 20",
                              line)),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(run / "report.html"));
  std::ofstream(run / "manifest.json", std::ios::trunc) << good.dump();
  std::ofstream(run / "scenario.resolved.yaml", std::ios::trunc) << resolved;
  EXPECT_NO_THROW(WriteReport({.dir = run.string()}));
}

// A gnuplot that exits 0 and writes no SVG (a bad-input audit: /bin/true
// gave a report of empty plots, "3 plots", exit 0) fails the report as a
// failing gnuplot does, and no report.html is published.
TEST(RunReport, GnuplotThatWritesNoSvgFailsTheReport) {
  const auto dir = testing::SweepFolder("run-report-gnuplot-no-svg");
  const fs::path run = RunMinimal(dir, "none");
  try {
    WriteReport({.dir = run.string(), .gnuplot = "/bin/true"});
    ADD_FAILURE() << "a report of empty plots was written";
  } catch (const RunError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("gnuplot (\"/bin/true\") exited 0 but wrote no SVG to "), std::string::npos)
        << what;
  }
  EXPECT_FALSE(fs::exists(run / "report.html"));
}

// Two runs' hand-written filter states and detections, over one ground
// truth, for the comparison of run A with run B (--against).
void WriteComparedRuns(const fs::path& a, const fs::path& b) {
  const std::string gt =
      "1,1,10,10,20,10,1,1,1\n2,1,11,10,20,10,1,1,1\n3,1,12,10,20,10,1,1,1\n"
      "4,1,13,10,20,10,1,1,1\n5,1,14,10,20,10,1,1,1\n6,1,15,10,20,10,1,1,1\n"
      "3,2,50,50,20,10,1,1,1\n4,2,50,51,20,10,1,1,1\n";
  std::ofstream(a / "gt" / "gt.txt") << gt;
  std::ofstream(b / "gt" / "gt.txt") << gt;
  const auto states = [](const std::vector<std::tuple<int, int, const char*>>& rows) {
    nlohmann::json j = nlohmann::json::array();
    for (const auto& [frame, filter, state] : rows) {
      j.push_back({{"frame", frame}, {"filter", filter}, {"state", state}});
    }
    return j;
  };
  auto ma = nlohmann::json::parse(Read(a / "metrics.json"));
  ma["filters"]["da_accuracy"] = 0.75;
  ma["filters"]["mapping"] =
      nlohmann::json::parse(R"([{"filter": 1, "target": 1}, {"filter": 9, "target": 2}])");
  // Target 1: CORRECT but frame 5 (from 1); target 2: CORRECT in frames 3 and 4.
  ma["filters"]["per_frame_states"] = states({{0, 1, "CORRECT"},
                                              {1, 1, "CORRECT"},
                                              {2, 1, "CORRECT"},
                                              {3, 1, "CORRECT"},
                                              {4, 1, "HIJACKED"},
                                              {5, 1, "CORRECT"},
                                              {2, 9, "CORRECT"},
                                              {3, 9, "CORRECT"}});
  // The detector's rows of target 1 are alike in both runs, those of target 2 not.
  ma["detection"] = nlohmann::json::parse(R"({"median_size_px": 40, "by_target": [
      {"target": 1, "found_frames": [[0, 1]], "missed_frames": [[2, 3]]},
      {"target": 2, "found_frames": [[2, 3]], "missed_frames": []}]})");
  std::ofstream(a / "metrics.json") << ma.dump();
  auto mb = nlohmann::json::parse(Read(b / "metrics.json"));
  mb["filters"]["da_accuracy"] = 0.5;
  // Two filters of target 1, none of target 2, and filter 5 of no target.
  mb["filters"]["mapping"] =
      nlohmann::json::parse(R"([{"filter": 1, "target": 1}, {"filter": 2, "target": 1}])");
  // Filter 2 listed first: the order of the rows does not choose the state.
  // Target 1, frame by frame from 0: CORRECT, CORRECT, LOST (filter 1's, the
  // lower id, over filter 2's STRAYED), SWAPPED (scored beats COASTING),
  // CORRECT (filter 2's beats filter 1's COASTING), STRAYED.
  mb["filters"]["per_frame_states"] = states({{2, 2, "STRAYED"},
                                              {3, 2, "SWAPPED"},
                                              {4, 2, "CORRECT"},
                                              {5, 2, "STRAYED"},
                                              {0, 1, "CORRECT"},
                                              {1, 1, "CORRECT"},
                                              {2, 1, "LOST"},
                                              {3, 1, "COASTING"},
                                              {4, 1, "COASTING"},
                                              {0, 5, "LOST"}});
  mb["detection"] = nlohmann::json::parse(R"({"median_size_px": 30, "by_target": [
      {"target": 1, "found_frames": [[0, 1]], "missed_frames": [[2, 3]]},
      {"target": 2, "found_frames": [[2, 2]], "missed_frames": [[3, 3]]}]})");
  std::ofstream(b / "metrics.json") << mb.dump();
}

// hcpf report RUN --against OTHER: the keys the two resolved scenarios differ
// in, the files alike, the metrics side by side with A − B, both runs' rows
// on one timeline, and target by target the frames whose filters are CORRECT
// in one run alone (every figure worked out by hand from the states above).
TEST(RunReport, AgainstAnotherRunSaysWhatDiffersAndComparesItsFiltersFrameByFrame) {
  const auto dir = testing::SweepFolder("run-report-against");
  const fs::path a = RunMinimal(dir, "none");
  const fs::path b = RunMinimal(dir, "scene_filter");
  WriteComparedRuns(a, b);
  const fs::path kept = dir / "kept";
  const ReportResult r = WriteReport(
      {.dir = a.string(), .gnuplot = KeepingGnuplot(dir, kept).string(), .against = b.string()});
  EXPECT_EQ(r.differing_keys, 1);
  EXPECT_EQ(r.compared_targets, 2);
  EXPECT_EQ(r.plots, 4) << "camera motion, the timeline, the centre error and the scene";
  const std::string html = Read(r.html_path);
  EXPECT_NE(html.find("<h2>Compared with another run</h2>"), std::string::npos);
  EXPECT_NE(html.find("<b>B</b> is <code>" + b.string() + "</code>"), std::string::npos);
  EXPECT_NE(html.find("differ in 1 key:"), std::string::npos);
  EXPECT_NE(html.find("<tr><td class=\"k\"><code>tracker.camera_motion</code></td>"
                      "<td class=\"k\">none</td><td class=\"k\">scene_filter</td></tr>"),
            std::string::npos);
  const size_t same = html.find("Files with the same bytes in both: ");
  const size_t differ = html.find("Files that differ: ", same);
  ASSERT_NE(differ, std::string::npos);
  const std::string same_files = html.substr(same, differ - same);
  const std::string differing_files = html.substr(differ, html.find("</p>", differ) - differ);
  EXPECT_NE(same_files.find("<code>gt/gt.txt</code>"), std::string::npos) << same_files;
  EXPECT_NE(same_files.find("<code>seqinfo.ini</code>"), std::string::npos) << same_files;
  EXPECT_NE(differing_files.find("<code>metrics.json</code>"), std::string::npos);
  EXPECT_NE(differing_files.find("<code>scenario.resolved.yaml</code>"), std::string::npos);
  EXPECT_EQ(html.find("Both are runs of one resolved scenario"), std::string::npos);

  EXPECT_NE(html.find("in both runs 2, in A alone <b>5</b>, in B alone <b>1</b>"),
            std::string::npos);
  EXPECT_NE(html.find("<tr><td class=\"k\">target 1</td><td>6</td><td>5</td><td>6</td><td>3</td>"
                      "<td>3</td><td>1</td><td class=\"k\">3 (A CORRECT, B LOST)</td></tr>"),
            std::string::npos);
  EXPECT_NE(html.find("<tr><td class=\"k\">target 2</td><td>2</td><td>2</td><td>0</td><td>0</td>"
                      "<td>2</td><td>0</td><td class=\"k\">3 (A CORRECT, B no filter)</td></tr>"),
            std::string::npos);
  // The detectors target by target: target 1 alike (found in frames 1–2 of
  // 1–4), target 2 found by A in frames 3–4 and by B in frame 3 alone.
  EXPECT_NE(html.find("found by A's detector alone <b>1</b>, by B's alone <b>0</b>"),
            std::string::npos);
  EXPECT_NE(html.find("<tr><td class=\"k\">target 1</td><td>4</td><td>2</td><td>4</td><td>2</td>"
                      "<td>0</td><td>0</td><td class=\"k\">–</td></tr>"),
            std::string::npos);
  EXPECT_NE(html.find("<tr><td class=\"k\">target 2</td><td>2</td><td>2</td><td>2</td><td>1</td>"
                      "<td>1</td><td>0</td><td class=\"k\">4 (A found, B missed)</td></tr>"),
            std::string::npos);
  // The headline table: A, B and A − B, a score with 3 decimals, the
  // difference green where A is better (DA accuracy: higher).
  EXPECT_NE(html.find("<th>A</th><th>B</th><th>A − B</th>"), std::string::npos);
  EXPECT_NE(html.find("<code>da_accuracy</code></td><td>0.750</td><td>0.500</td><td "
                      "style=\"background:#dff3df\">+0.250</td>"),
            std::string::npos)
      << html;
  // The target size describes the runs, it does not score them: not
  // coloured (a review: it was green, being "higher is better").
  EXPECT_NE(html.find("<code>det_size_px</code></td><td>40 px</td><td>30 px</td><td>+10 px</td>"),
            std::string::npos)
      << html;
  // One timeline, A's rows before B's under each target.
  const std::string gp = Read(kept / "timeline.gp");
  EXPECT_NE(gp.find("set ytics ('target 1' 0, 'detections (A and B)' -1, 'A filter 1' -2, "
                    "'B filter 1' -3, 'B filter 2' -4, 'target 2' -5, 'A detections' -6, "
                    "'A filter 9' -7, 'B detections' -8, 'B filter 5 (no target)' -9)"),
            std::string::npos)
      << gp;
  EXPECT_NE(gp.find("of runs A and B"), std::string::npos);
  // Both camera-motion summaries.
  EXPECT_NE(html.find("<tr><td>error, B</td>"), std::string::npos);
  // A's folder is still one hcpf run may replace; B's is only read.
  EXPECT_EQ(scenarios::WhyNotOurOutput(a), "");
  EXPECT_FALSE(fs::exists(b / "report.html"));

  // An external tracker's run has no filter states: not "no filter" frames.
  auto mb = nlohmann::json::parse(Read(b / "metrics.json"));
  mb.erase("filters");
  std::ofstream(b / "metrics.json") << mb.dump();
  const ReportResult external = WriteReport({.dir = a.string(), .against = b.string()});
  EXPECT_EQ(external.compared_targets, 0);
  const std::string external_html = Read(external.html_path);
  EXPECT_NE(external_html.find("Run B has no filter states"), std::string::npos);
  EXPECT_EQ(external_html.find("B no filter"), std::string::npos);

  // Without --against, the same folder reports alone.
  const ReportResult alone = WriteReport({.dir = a.string()});
  EXPECT_EQ(alone.differing_keys, 0);
  EXPECT_EQ(Read(alone.html_path).find("Compared with another run"), std::string::npos);
}

// Two runs of one resolved scenario must agree byte for byte: the report says
// so, and says loudly when a file differs all the same. Over different ground
// truths nothing is compared frame by frame.
TEST(RunReport, AgainstARunOfTheSameScenarioChecksDeterminism) {
  const auto dir = testing::SweepFolder("run-report-against-same");
  const fs::path a = RunMinimal(dir / "a", "none");
  const fs::path b = RunMinimal(dir / "b", "none");
  ReportResult r = WriteReport({.dir = a.string(), .against = b.string()});
  std::string html = Read(r.html_path);
  EXPECT_EQ(r.differing_keys, 0);
  EXPECT_NE(html.find("are the same, key by key"), std::string::npos);
  EXPECT_NE(html.find("Files that differ: none."), std::string::npos);
  EXPECT_NE(html.find("their files agree"), std::string::npos);
  EXPECT_EQ(r.compared_targets, 2);
  EXPECT_NE(html.find("in A alone <b>0</b>, in B alone <b>0</b>"), std::string::npos);

  std::ofstream(b / "tracks.txt", std::ios::app) << "21,1,0,0,1,1,1,-1,-1,-1\n";
  html = Read(WriteReport({.dir = a.string(), .against = b.string()}).html_path);
  EXPECT_NE(html.find("<strong>Both are runs of one resolved scenario, yet "
                      "<code>tracks.txt</code> differs</strong>"),
            std::string::npos);

  // Another frame count (B's manifest, scenario and seqinfo.ini, which must
  // agree): not compared frame by frame, and said why.
  auto manifest = nlohmann::json::parse(Read(b / "manifest.json"));
  const std::string resolved = Read(b / "scenario.resolved.yaml");
  std::string longer = resolved;
  ASSERT_NE(longer.find("\nframes: 20\n"), std::string::npos);
  longer.replace(longer.find("\nframes: 20\n"), 12, "\nframes: 21\n");
  std::ofstream(b / "scenario.resolved.yaml") << longer;
  manifest["frames"] = 21;
  std::ofstream(b / "manifest.json") << manifest.dump();
  const std::string seqinfo = Read(b / "seqinfo.ini");
  std::string longer_seqinfo = seqinfo;
  ASSERT_NE(longer_seqinfo.find("\nseqLength=20\n"), std::string::npos);
  longer_seqinfo.replace(longer_seqinfo.find("\nseqLength=20\n"), 14, "\nseqLength=21\n");
  std::ofstream(b / "seqinfo.ini") << longer_seqinfo;
  r = WriteReport({.dir = a.string(), .against = b.string()});
  EXPECT_EQ(r.compared_targets, 0);
  EXPECT_NE(Read(r.html_path).find("Run A has 20 frames and run B 21, so"), std::string::npos);
  manifest["frames"] = 20;
  std::ofstream(b / "manifest.json") << manifest.dump();
  std::ofstream(b / "scenario.resolved.yaml") << resolved;
  std::ofstream(b / "seqinfo.ini") << seqinfo;

  std::ofstream(b / "gt" / "gt.txt", std::ios::app) << "20,3,1,1,5,5,1,1,1\n";
  const fs::path kept = dir / "kept";
  r = WriteReport(
      {.dir = a.string(), .gnuplot = KeepingGnuplot(dir, kept).string(), .against = b.string()});
  html = Read(r.html_path);
  EXPECT_EQ(r.compared_targets, 0);
  EXPECT_NE(html.find("Their ground truths differ"), std::string::npos);
  EXPECT_NE(html.find("Run A's alone"), std::string::npos);
  const std::string gp = Read(kept / "timeline.gp");
  EXPECT_EQ(gp.find("'A filter"), std::string::npos) << gp;
  EXPECT_EQ(gp.find("of runs A and B"), std::string::npos);
}

// Several --against: runs C, D, ... beside A in the headline table (each
// value and A − it, coloured), and who each is with the keys it differs from
// A in; each must be another run folder, named once, and a sweep takes one.
TEST(RunReport, MoreRunsAreSetBesideAInTheHeadlineMetrics) {
  const auto dir = testing::SweepFolder("run-report-more-runs");
  const fs::path a = RunMinimal(dir / "a", "none");
  const fs::path b = RunMinimal(dir / "b", "none");
  const fs::path c = RunMinimal(dir / "c", "none");
  const fs::path d = RunMinimal(dir / "d", "none");
  const auto set_da = [](const fs::path& run, double value) {
    auto metrics = nlohmann::json::parse(Read(run / "metrics.json"));
    metrics["filters"]["da_accuracy"] = value;
    std::ofstream(run / "metrics.json", std::ios::trunc) << metrics.dump();
  };
  set_da(a, 0.75);
  set_da(b, 0.5);
  set_da(c, 0.875);
  set_da(d, 0.75);
  // A's CORRECT target-frames, counted here: its filters map one to one on
  // its targets. D's first of them made LOST: CORRECT in A alone there.
  const auto a_metrics = nlohmann::json::parse(Read(a / "metrics.json"));
  std::set<int64_t> mapped;
  for (const auto& m : a_metrics["filters"]["mapping"]) mapped.insert(m["filter"].get<int64_t>());
  ASSERT_EQ(mapped.size(), 2u);
  int correct = 0;
  for (const auto& s : a_metrics["filters"]["per_frame_states"]) {
    correct += s["state"] == "CORRECT" && mapped.contains(s["filter"].get<int64_t>()) ? 1 : 0;
  }
  ASSERT_GT(correct, 10);
  {
    auto metrics = nlohmann::json::parse(Read(d / "metrics.json"));
    for (auto& s : metrics["filters"]["per_frame_states"]) {
      if (s["state"] == "CORRECT") {
        s["state"] = "LOST";
        break;
      }
    }
    std::ofstream(d / "metrics.json", std::ios::trunc) << metrics.dump();
  }
  // C's scenario differs from A's in one key.
  std::string resolved = Read(c / "scenario.resolved.yaml");
  ASSERT_TRUE(resolved.starts_with("name: \"minimal\"\n")) << resolved;
  resolved.replace(0, 7, "name: \"other-");
  std::ofstream(c / "scenario.resolved.yaml", std::ios::trunc) << resolved;
  const ReportResult r = WriteReport(
      {.dir = a.string(), .against = b.string(), .more_against = {c.string(), d.string()}});
  EXPECT_EQ(r.more_runs, 2);
  const std::string html = Read(r.html_path);
  EXPECT_NE(html.find("<th>A</th><th>B</th><th>A − B</th><th>C</th><th>A − C</th><th>D</th>"
                      "<th>A − D</th>"),
            std::string::npos);
  EXPECT_NE(html.find("<code>da_accuracy</code></td><td>0.750</td><td>0.500</td><td "
                      "style=\"background:#dff3df\">+0.250</td><td>0.875</td><td "
                      "style=\"background:#f8dede\">-0.125</td><td>0.750</td><td>0</td>"),
            std::string::npos)
      << html;
  const size_t more = html.find("<h2>More runs beside A</h2>");
  ASSERT_NE(more, std::string::npos);
  const std::string section = html.substr(more, html.find("</table>", more) - more);
  EXPECT_NE(section.find("<b>C</b></td><td class=\"k\"><code>" + c.string() + "</code>"),
            std::string::npos)
      << section;
  EXPECT_NE(section.find("<code>name</code>: minimal → other-minimal"), std::string::npos)
      << section;
  EXPECT_NE(section.find("none: the same resolved scenario"), std::string::npos) << section;
  // Target-frames CORRECT in both, in A alone, in it alone.
  EXPECT_NE(section.find(fmt::format("<td class=\"k\">{}, <b>0</b>, <b>0</b></td></tr>", correct)),
            std::string::npos)
      << section;
  EXPECT_NE(
      section.find(fmt::format("<td class=\"k\">{}, <b>1</b>, <b>0</b></td></tr>", correct - 1)),
      std::string::npos)
      << section;
  // Another ground truth: not counted, said why, with the run's letter.
  std::ofstream(c / "gt" / "gt.txt", std::ios::app) << "20,3,1,1,5,5,1,1,1\n";
  const std::string other_truth =
      Read(WriteReport({.dir = a.string(), .against = b.string(), .more_against = {c.string()}})
               .html_path);
  EXPECT_NE(other_truth.find("not counted: Their ground truths differ"), std::string::npos);
  // Without more runs, neither the section nor their columns.
  const std::string two = Read(WriteReport({.dir = a.string(), .against = b.string()}).html_path);
  EXPECT_EQ(two.find("More runs beside A"), std::string::npos);
  EXPECT_NE(two.find("<th>A − B</th></tr>"), std::string::npos);

  // Bad input, before anything is written: a run named twice, DIR itself, a
  // sweep folder, more runs without a first, several with a sweep.
  fs::create_directories(dir / "sweep");
  std::ofstream(dir / "sweep" / "results.sqlite") << "";
  const fs::path out = dir / "out";
  for (const auto& [options, found] : std::vector<std::pair<ReportOptions, std::string>>{
           {{.dir = a.string(),
             .out_dir = out.string(),
             .against = b.string(),
             .more_against = {c.string(), b.string()}},
            "expected each run folder once, found " + b.string() + " again"},
           {{.dir = a.string(),
           .out_dir = out.string(),
           .against = b.string(),
           .more_against = {a.string()}},
            "DIR itself"},
           {{.dir = a.string(),
           .out_dir = out.string(),
           .against = b.string(),
           .more_against = {(dir / "sweep").string()}},
            "a sweep folder"},
           {{.dir = a.string(), .out_dir = out.string(), .more_against = {c.string()}},
            "expected the run B to compare A with before more runs"},
           {{.dir = (dir / "sweep").string(),
           .out_dir = out.string(),
           .against = b.string(),
           .more_against = {c.string()}},
            "expected one --against with the sweep folder " + (dir / "sweep").string()}}) {
    try {
      WriteReport(options);
      ADD_FAILURE() << found << ": accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(found), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(out)) << found;
  }
}

// --against with a run is another run folder: anything else is bad input
// naming --against, found before anything is written.
TEST(RunReport, AgainstWhatIsNoOtherRunIsBadInput) {
  const auto dir = testing::SweepFolder("run-report-against-bad");
  const fs::path run = RunMinimal(dir, "none");
  fs::create_directories(dir / "sweep");
  std::ofstream(dir / "sweep" / "results.sqlite") << "";
  std::ofstream(dir / "file.txt") << "x\n";
  const std::vector<std::pair<fs::path, std::string>> cases = {
      {dir / "missing", "no such folder"},
      {dir / "file.txt", "a file, not a folder"},
      {run, "DIR itself"},
      {dir, "a folder with neither results.sqlite nor manifest.json"}};
  for (const auto& [against, found] : cases) {
    const fs::path out = dir / "out";
    try {
      WriteReport({.dir = run.string(), .out_dir = out.string(), .against = against.string()});
      ADD_FAILURE() << against << " was accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("--against: expected another run folder"), std::string::npos) << what;
      EXPECT_NE(what.find(found), std::string::npos) << what;
    }
    EXPECT_FALSE(fs::exists(out)) << against;
    EXPECT_FALSE(fs::exists(run / "report.html")) << against;
  }
  // Another run whose resolved scenario is not YAML: named, before anything
  // is written.
  const fs::path other = RunMinimal(dir / "other", "none");
  std::ofstream(other / "scenario.resolved.yaml") << "name: [unclosed\n";
  try {
    WriteReport(
        {.dir = run.string(), .out_dir = (dir / "out").string(), .against = other.string()});
    ADD_FAILURE() << "a damaged resolved scenario was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find((other / "scenario.resolved.yaml").string()),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(dir / "out"));
}

// A sweep folder as --against: run A beside its cell's seeds. The cell is
// the one whose runs' resolved scenario is A's, seeds aside, else the nearest
// (said, with the keys it differs in); the cell's run of A's seed must give
// A's metrics; each metric's row has the cell's mean, range and A's place,
// counted here from the store's rows.
TEST(RunReport, AgainstASweepSetsTheRunBesideItsCell) {
  const auto dir = testing::SweepFolder("run-report-against-sweep");
  const fs::path sweep =
      RunQuietly(LoadSweepFile(testing::WriteSweep(
                     dir,
                     "base: base.yaml\nseeds: 3\ngrid:\n  tracker.particles: [20, 50]\n"
                     "  tracker.resampling.method: [systematic, charged]\n")),
                 dir);
  std::vector<RunRecord> cell;
  for (RunRecord& r : ResultsStore::Open((sweep / "results.sqlite").string())->Runs()) {
    if (r.values == std::vector<std::string>{"50", "charged"}) cell.push_back(r);
  }
  ASSERT_EQ(cell.size(), 3u);
  const RunRecord& twin = cell[1];
  // Run A: the cell's scenario with its second seed.
  const auto run = [&](const fs::path& out, const std::string& particles, uint64_t seed) {
    scenarios::RunScenario(scenarios::LoadScenarioText(scenarios::testing::kMinimal, "base.yaml",
                                                       {{"tracker.particles", particles},
                                                        {"tracker.resampling.method", "charged"},
                                                        {"seed", std::to_string(seed)}}),
                           {.out_dir = out.string()});
    return out;
  };
  const fs::path a = run(dir / "a", "50", twin.seed);
  ReportResult r = WriteReport({.dir = a.string(), .against = sweep.string()});
  EXPECT_EQ(r.cell_runs, 3);
  EXPECT_EQ(r.cell_differing_keys, 0);
  std::string html = Read(r.html_path);
  const size_t at = html.find("<h2>Beside a sweep's cell</h2>");
  ASSERT_NE(at, std::string::npos);
  std::string section = html.substr(at, html.find("</table>", at) - at);
  EXPECT_NE(section.find("the cell <code>tracker.particles = 50</code>, "
                         "<code>tracker.resampling.method = charged</code> of the sweep"),
            std::string::npos)
      << section;
  // The drawn leaves: `seed` and the seeds.X two runs of the cell differ in.
  EXPECT_NE(section.find("Its seeds are drawn over <code>seed, seeds.observation, "
                         "seeds.renderer, seeds.tracker, seeds.world</code>. Its resolved "
                         "scenario is A's but for those"),
            std::string::npos)
      << section;
  EXPECT_NE(section.find(fmt::format("<code>{}</code> has A's seed {} and A's whole resolved "
                                     "scenario",
                                     twin.run_dir, twin.seed)),
            std::string::npos)
      << section;
  EXPECT_NE(section.find("It gives A's values in all"), std::string::npos) << section;
  // The da_accuracy row: A, the seeds' mean, lowest and highest, A's place.
  std::vector<double> da;
  for (const RunRecord& x : cell) da.push_back(x.metrics.at("da_accuracy"));
  const double a_da = twin.metrics.at("da_accuracy");
  const auto row = [&](const std::string& text) {
    const size_t start = text.find("<code>da_accuracy</code>");
    return start == std::string::npos ? std::string()
                                      : text.substr(start, text.find("</tr>", start) - start);
  };
  const auto count = [&](auto pred) { return std::count_if(da.begin(), da.end(), pred); };
  std::vector<std::string> place;
  if (const auto n = count([&](double v) { return v < a_da; })) {
    place.push_back(fmt::format("higher than {}", n));
  }
  place.push_back(fmt::format("equal to {}", count([&](double v) { return v == a_da; })));
  if (const auto n = count([&](double v) { return v > a_da; })) {
    place.push_back(fmt::format("lower than {}", n));
  }
  EXPECT_NE(row(section).find(fmt::format("<td>{:.3f}</td><td>3</td><td>{:.3f}</td>", a_da,
                                          (da[0] + da[1] + da[2]) / 3.0)),
            std::string::npos)
      << row(section);
  EXPECT_NE(row(section).find(fmt::format("<td>{:.3f}</td><td>{:.3f}</td><td class=\"k\">{} of 3",
                                          *std::min_element(da.begin(), da.end()),
                                          *std::max_element(da.begin(), da.end()),
                                          fmt::join(place, ", "))),
            std::string::npos)
      << row(section);

  // A's DA accuracy above every seed's: marked, and its twin no longer gives
  // it.
  auto metrics = nlohmann::json::parse(Read(a / "metrics.json"));
  metrics["filters"]["da_accuracy"] = 2.0;
  // A camera-motion error of rounding is 0 px, as in the headline table.
  metrics["camera_motion"]["mean_px"] = 7e-14;
  std::ofstream(a / "metrics.json", std::ios::trunc) << metrics.dump();
  html = Read(WriteReport({.dir = a.string(), .against = sweep.string()}).html_path);
  EXPECT_NE(html.find("<code>camera_motion_error_px</code></td><td>0 px</td><td>3</td>"),
            std::string::npos);
  EXPECT_NE(html.find("<td class=\"k\" style=\"background:#fff3cd\">higher than every seed</td>"),
            std::string::npos);
  // (Its camera-motion error is compared as written: 7e-14 is not its twin's.)
  EXPECT_NE(html.find("<b>It gives other values in 2 of"), std::string::npos);
  EXPECT_NE(html.find(fmt::format("<code>da_accuracy</code> (A 2.000, that run {:.3f})", a_da)),
            std::string::npos);

  // A scenario no cell has: the nearest, with the key it differs in; A's
  // seed (the base's 7) is none of its seeds.
  const fs::path b = run(dir / "b", "30", 7);
  r = WriteReport({.dir = b.string(), .against = sweep.string()});
  EXPECT_EQ(r.cell_runs, 3);
  EXPECT_EQ(r.cell_differing_keys, 1);
  html = Read(r.html_path);
  EXPECT_NE(html.find("<b>No cell of the sweep has A's resolved scenario</b> but for the drawn "
                      "keys (4 cells compared)."),
            std::string::npos);
  EXPECT_NE(html.find("<code>tracker.particles</code>: 30 → 20"), std::string::npos);
  // The cell at 50 is as near: said.
  EXPECT_NE(html.find("1 other cell is as near, left out: tracker.particles = 50, "
                      "tracker.resampling.method = charged."),
            std::string::npos);
  EXPECT_NE(html.find("<code>tracker.resampling.method = charged</code>"), std::string::npos);
  EXPECT_NE(html.find("A's seed is none of the cell's"), std::string::npos);

  // Bad input, before anything is written: more runs after a sweep, a store
  // that is none, a sweep without its run folders, A without its resolved
  // scenario.
  const fs::path out = dir / "out-report";
  fs::create_directories(dir / "empty");
  std::ofstream(dir / "empty" / "results.sqlite") << "";
  const fs::path moved = dir / "moved";
  fs::rename(sweep / "runs", moved);
  const fs::path bare = dir / "bare";
  fs::copy(b, bare, fs::copy_options::recursive);
  fs::remove(bare / "scenario.resolved.yaml");
  for (const auto& [options, found] : std::vector<std::pair<ReportOptions, std::string>>{
           {{.dir = a.string(),
             .out_dir = out.string(),
             .against = sweep.string(),
             .more_against = {b.string()}},
            "expected one sweep folder alone (run A beside its cell), or run folders, found the "
            "sweep folder " +
                sweep.string() + ", then " + b.string()},
           {{.dir = a.string(),
           .out_dir = out.string(),
           .against = b.string(),
           .more_against = {sweep.string()}},
            "a sweep folder after the first --against"},
           {{.dir = a.string(), .out_dir = out.string(), .against = (dir / "empty").string()},
            (dir / "empty" / "results.sqlite").string()},
           {{.dir = a.string(), .out_dir = out.string(), .against = sweep.string()},
            "none of its 12 runs' folders holds one"},
           {{.dir = bare.string(), .out_dir = out.string(), .against = (dir / "empty").string()},
            "no scenario.resolved.yaml"}}) {
    try {
      WriteReport(options);
      ADD_FAILURE() << found << ": accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(found), std::string::npos) << e.what();
    }
    EXPECT_FALSE(fs::exists(out)) << found;
  }
  fs::rename(moved, sweep / "runs");

  // A cell whose first run's file is empty (cut short) is read from its
  // next run; a cell with no readable file is not compared, which is said.
  const fs::path first_file = sweep / cell[0].run_dir / "scenario.resolved.yaml";
  const std::string first_text = Read(first_file);
  std::ofstream(first_file, std::ios::trunc) << "";
  r = WriteReport({.dir = a.string(), .against = sweep.string()});
  EXPECT_EQ(r.cell_differing_keys, 0);
  // Cut after its tenth line, still YAML: the cell's second file decides.
  size_t cut = 0;
  for (int line = 0; line < 10; ++line) cut = first_text.find('\n', cut) + 1;
  std::ofstream(first_file, std::ios::trunc) << first_text.substr(0, cut);
  r = WriteReport({.dir = a.string(), .against = sweep.string()});
  EXPECT_EQ(r.cell_differing_keys, 0);
  EXPECT_NE(Read(r.html_path).find("<code>tracker.resampling.method = charged</code> of the sweep"),
            std::string::npos);
  for (const RunRecord& x : cell) fs::rename(sweep / x.run_dir, dir / x.key);
  r = WriteReport({.dir = a.string(), .against = sweep.string()});
  EXPECT_EQ(r.cell_differing_keys, 1);
  EXPECT_NE(Read(r.html_path)
                .find("(3 cells compared). 1 cell could not be compared (no run folder with a "
                      "readable <code>scenario.resolved.yaml</code>): tracker.particles = 50, "
                      "tracker.resampling.method = charged."),
            std::string::npos);
  for (const RunRecord& x : cell) fs::rename(dir / x.key, sweep / x.run_dir);

  // A run of the sweep reported against it: left out of its own seeds.
  r = WriteReport({.dir = (sweep / twin.run_dir).string(),
                   .out_dir = (dir / "itself").string(),
                   .against = sweep.string()});
  html = Read(r.html_path);
  EXPECT_NE(html.find(fmt::format("<p>A is the cell's run <code>{}</code> itself: it is left out "
                                  "of the seeds below.</p>",
                                  twin.run_dir)),
            std::string::npos);
  EXPECT_NE(row(html).find("</td><td>2</td>"), std::string::npos) << row(html);
}

// The leaves a cell's seeds are drawn over are `seed` and the seeds.X two
// of its runs differ in (with one run, those it and A derive from their
// seed): a seed the grid sweeps, or the base pins, counts like any other key
// (a review: `seed` and `seeds.*` were always set aside, so a swept
// seeds.world matched the first cell and a pinned one called another terrain
// a draw; later ones: a rule read from the first cell alone, or from one
// file, was fooled by a base pinning seeds.world in one base only, a file
// cut short, and a pin equal to what a seed derives).
TEST(RunReport, AgainstASweepCountsTheSeedsItSweepsOrPins) {
  const auto dir = testing::SweepFolder("run-report-against-seeds");
  std::ofstream(dir / "pinned.yaml") << scenarios::testing::kMinimal << "seeds:\n  world: 5\n";
  const fs::path swept = RunQuietly(
      LoadSweepFile(testing::WriteSweep(
          dir, "base: base.yaml\nseeds: 2\ngrid:\n  seeds.world: [11, 12]\n", "swept.yaml")),
      dir / "swept");
  const fs::path pinned = RunQuietly(
      LoadSweepFile(testing::WriteSweep(dir, "base: pinned.yaml\nseeds: 2\n", "pinned-sweep.yaml")),
      dir / "pinned");
  const auto second_seed = [](const fs::path& sweep, const std::string& value) {
    for (const RunRecord& x : ResultsStore::Open((sweep / "results.sqlite").string())->Runs()) {
      if (x.seed_index == 1 && (value.empty() || x.values.front() == value)) return x;
    }
    return RunRecord{};
  };
  const auto run = [&](const fs::path& out, const std::vector<config::Override>& set) {
    scenarios::RunScenario(
        scenarios::LoadScenarioText(scenarios::testing::kMinimal, "base.yaml", set),
        {.out_dir = out.string()});
    return out;
  };
  // seeds.world 12 with the second seed: the cell at 12, its run of that seed A's twin.
  const RunRecord twin = second_seed(swept, "12");
  ASSERT_FALSE(twin.key.empty());
  const fs::path a = run(dir / "a", {{"seed", std::to_string(twin.seed)}, {"seeds.world", "12"}});
  ReportResult r = WriteReport({.dir = a.string(), .against = swept.string()});
  EXPECT_EQ(r.cell_differing_keys, 0);
  std::string html = Read(r.html_path);
  EXPECT_NE(html.find("the cell <code>seeds.world = 12</code>"), std::string::npos);
  EXPECT_NE(html.find("drawn over <code>seed, seeds.observation, seeds.renderer, "
                      "seeds.tracker</code>."),
            std::string::npos);
  EXPECT_NE(html.find("It gives A's values in all"), std::string::npos);

  // The base pins seeds.world 5: A's own terrain is another key, and its
  // seed's run is of another scenario, not a failed replay.
  const RunRecord pinned_twin = second_seed(pinned, "");
  ASSERT_FALSE(pinned_twin.key.empty());
  const fs::path b = run(dir / "b", {{"seed", std::to_string(pinned_twin.seed)}});
  r = WriteReport({.dir = b.string(), .against = pinned.string()});
  EXPECT_EQ(r.cell_differing_keys, 1);
  html = Read(r.html_path);
  EXPECT_NE(html.find("<code>seeds.world</code>: "), std::string::npos);
  EXPECT_NE(html.find("but its resolved scenario differs from A's in 1 key, so its values are not "
                      "expected to be A's"),
            std::string::npos);
  EXPECT_EQ(html.find("It gives other values"), std::string::npos);

  // Two bases, the pinned one first (a second review: the drawn leaves
  // were read once, from the first cell, and applied to every cell): each
  // run is set beside its own base's cell.
  const fs::path bases =
      RunQuietly(LoadSweepFile(testing::WriteSweep(
                     dir, "seeds: 2\ngrid:\n  base: [pinned.yaml, base.yaml]\n", "bases.yaml")),
                 dir / "bases");
  std::vector<RunRecord> rows = ResultsStore::Open((bases / "results.sqlite").string())->Runs();
  ASSERT_EQ(rows.size(), 4u);
  for (const RunRecord& x : rows) {
    SCOPED_TRACE(x.run_dir);
    r = WriteReport({.dir = (bases / x.run_dir).string(),
                     .out_dir = (dir / ("of-" + x.key)).string(),
                     .against = bases.string()});
    EXPECT_EQ(r.cell_differing_keys, 0);
    EXPECT_EQ(r.cell_runs, 1);  // the cell's other seed
    html = Read(r.html_path);
    EXPECT_NE(html.find("<code>base = " + x.values.front() + "</code>"), std::string::npos);
    EXPECT_NE(html.find("A is one of this cell's runs."), std::string::npos);
    EXPECT_EQ(html.find("as near"), std::string::npos);
  }
  // A run of the unpinned base with the seed of its cell's second run: that
  // cell, and it replays that run.
  const RunRecord unpinned = rows[3];
  ASSERT_EQ(unpinned.values.front(), "base.yaml");
  const fs::path c = run(dir / "c", {{"seed", std::to_string(unpinned.seed)}});
  r = WriteReport({.dir = c.string(), .against = bases.string()});
  EXPECT_EQ(r.cell_differing_keys, 0);
  html = Read(r.html_path);
  EXPECT_NE(html.find("<code>base = base.yaml</code>"), std::string::npos);
  EXPECT_NE(html.find("A replays one of this cell's runs (below)."), std::string::npos);
  EXPECT_NE(html.find("It gives A's values in all"), std::string::npos);

  // A swept `seed` replicates: its runs share one cell, and A with one of
  // those seeds replays its run.
  const fs::path seeds = RunQuietly(
      LoadSweepFile(testing::WriteSweep(
          dir, "base: base.yaml\ngrid:\n  seed: [5, 6, 7]\n  tracker.particles: [50, 100]\n",
          "seeds.yaml")),
      dir / "seeds");
  const fs::path d = run(dir / "d", {{"seed", "6"}, {"tracker.particles", "100"}});
  r = WriteReport({.dir = d.string(), .against = seeds.string()});
  EXPECT_EQ(r.cell_differing_keys, 0);
  EXPECT_EQ(r.cell_runs, 3);
  html = Read(r.html_path);
  EXPECT_NE(html.find("the cell <code>tracker.particles = 100</code> of the sweep"),
            std::string::npos);
  EXPECT_NE(html.find("has A's seed 6 and A's whole resolved scenario"), std::string::npos);
  EXPECT_NE(html.find("drawn over <code>seed, seeds.observation, seeds.renderer, seeds.tracker, "
                      "seeds.world</code>"),
            std::string::npos);

  // A base that pins seeds.world to what seed 5 derives, swept over seeds 5,
  // 6 and 7 (a third review: read from seed 5's file alone, the pin looked
  // derived): A of seed 6 with its own terrain differs in seeds.world.
  std::ofstream(dir / "pinned-5.yaml")
      << scenarios::testing::kMinimal << "seeds:\n  world: " << scenarios::DeriveSeed(5, "world")
      << "\n";
  const fs::path pinned_5 = RunQuietly(
      LoadSweepFile(testing::WriteSweep(dir, "base: pinned-5.yaml\ngrid:\n  seed: [5, 6, 7]\n",
                                        "pinned-5-sweep.yaml")),
      dir / "pinned-5");
  const fs::path e = run(dir / "e", {{"seed", "6"}});
  r = WriteReport({.dir = e.string(), .against = pinned_5.string()});
  EXPECT_EQ(r.cell_differing_keys, 1);
  html = Read(r.html_path);
  EXPECT_NE(html.find("<code>seeds.world</code>: "), std::string::npos);
  EXPECT_NE(html.find("Run A is set beside the one cell of the sweep"), std::string::npos);
}

TEST(RunReport, ModeNoneHasNoEssLine) {
  const auto dir = testing::SweepFolder("run-report-none");
  const fs::path run = RunMinimal(dir, "none");
  const fs::path out = dir / "elsewhere";
  const ReportResult r = WriteReport({.dir = run.string(), .out_dir = out.string()});
  EXPECT_EQ(r.html_path, (out / "report.html").string());
  EXPECT_FALSE(fs::exists(run / "report.html")) << "--out leaves the run folder alone";
  const std::string html = Read(out / "report.html");
  const size_t at = html.find("id=\"plot-camera_motion\"");
  ASSERT_NE(at, std::string::npos);
  const std::string svg = html.substr(at, html.find("</svg>", at) - at);
  EXPECT_NE(svg.find("camera-motion error (none)"), std::string::npos);
  EXPECT_EQ(svg.find("ESS"), std::string::npos);
}

// A run written with --video: the report links overlay.mp4, from the report's
// own folder (the run folder, or --out elsewhere).
TEST(RunReport, LinksTheOverlayVideoWhenTheRunHasOne) {
  const auto dir = testing::SweepFolder("run-report-video");
  const fs::path run = RunMinimal(dir, "none");
  EXPECT_EQ(Read(WriteReport({.dir = run.string()}).html_path).find("overlay.mp4"),
            std::string::npos)
      << "no video, no link";
  std::ofstream(run / "overlay.mp4") << "stand-in bytes: the report only links the file";
  EXPECT_NE(Read(WriteReport({.dir = run.string()}).html_path)
                .find("<a href=\"overlay.mp4\">overlay.mp4</a>"),
            std::string::npos);
  const fs::path out = dir / "elsewhere";
  EXPECT_NE(Read(WriteReport({.dir = run.string(), .out_dir = out.string()}).html_path)
                .find("<a href=\"../run-none/overlay.mp4\">"),
            std::string::npos);
  // H.264 that no browser is said to play: frames past every H.264 level
  // (scenarios::FitsAnH264Level).
  auto manifest = nlohmann::json::parse(Read(run / "manifest.json"));
  manifest["video"] = {
      {"file", "overlay.mp4"}, {"fourcc", "avc1"}, {"codec", "H.264"}, {"plays_in_browsers", false},
      {"frames", 20},          {"fps", 30.0},      {"width", 8190},    {"height", 8190}};
  std::ofstream(run / "manifest.json", std::ios::trunc) << manifest.dump();
  EXPECT_NE(Read(WriteReport({.dir = run.string()}).html_path)
                .find("<a href=\"overlay.mp4\">overlay.mp4</a>, H.264, which VLC and mpv play "
                      "and most browsers do not (its frames are larger, or come faster, than "
                      "any H.264 level codes: 8176 x 4352, or 1920 x 1080 at 2048 fps, say)"),
            std::string::npos);
}

// hcpf run --video writes H.264, which browsers play: the report shows the
// video, moved to a frame by its buttons and by every frame number that links
// to it (#frame=K), and lists the frames to look at (each filter's episodes
// in a state other than CORRECT, the frames models were cut); compared with
// another run, both videos side by side and the comparison's first differing
// frames as links. A video no browser plays (an older run's) is a link with
// the reason and the command that makes one; a run without one says how to
// get it. Episodes worked out by hand from the states written below.
TEST(RunReport, ShowsTheOverlayVideoAndLinksItsFrames) {
  const auto dir = testing::SweepFolder("run-report-video-plays");
  const auto run_with_video = [&dir](const std::string& name, const std::string& mode) {
    const fs::path out = dir / name;
    const scenarios::Scenario scenario =
        scenarios::LoadScenarioText(scenarios::testing::kMinimal, "base.yaml",
                                    {{"camera.shake_px", "1.0"},
                                     {"tracker.camera_motion", mode},
                                     {"tracker.scene_filter.particles", "100"}});
    scenarios::RunScenario(scenario, {.out_dir = out.string(), .video = true});
    return out;
  };
  const fs::path a = run_with_video("a", "none");
  const fs::path b = run_with_video("b", "scene_filter");
  const auto manifest = nlohmann::json::parse(Read(a / "manifest.json"));
  ASSERT_TRUE(manifest.contains("video")) << manifest.dump();
  EXPECT_EQ(manifest["video"]["file"], "overlay.mp4");
  EXPECT_EQ(manifest["video"]["fourcc"], "avc1");
  EXPECT_EQ(manifest["video"]["codec"], "H.264");
  EXPECT_EQ(manifest["video"]["plays_in_browsers"], true);
  EXPECT_EQ(manifest["video"]["frames"], 20);
  const double fps = manifest["video"]["fps"].get<double>();
  EXPECT_GT(fps, 0.0);
  WriteComparedRuns(a, b);
  // A's filter 1, frame by frame from 0: CORRECT, LOST, LOST, COASTING (ends
  // the episode), LOST, HIJACKED: "LOST 2–3, LOST 5, HIJACKED 6" from 1.
  auto ma = nlohmann::json::parse(Read(a / "metrics.json"));
  ma["filters"]["per_frame_states"] = nlohmann::json::parse(R"([
      {"frame": 0, "filter": 1, "state": "CORRECT"}, {"frame": 1, "filter": 1, "state": "LOST"},
      {"frame": 2, "filter": 1, "state": "LOST"}, {"frame": 3, "filter": 1, "state": "COASTING"},
      {"frame": 4, "filter": 1, "state": "LOST"}, {"frame": 5, "filter": 1, "state": "HIJACKED"},
      {"frame": 2, "filter": 9, "state": "CORRECT"}, {"frame": 3, "filter": 9, "state": "CORRECT"}])");
  std::ofstream(a / "metrics.json") << ma.dump();
  // Both runs cut target 1's model at frame 0 and target 2's at frame 2.
  for (const fs::path& run : {a, b}) {
    auto m = nlohmann::json::parse(Read(run / "manifest.json"));
    m["target_model_sources"] =
        nlohmann::json::parse(R"([{"target": 1, "frame": 0}, {"target": 2, "frame": 2}])");
    std::ofstream(run / "manifest.json") << m.dump();
  }
  const auto link = [](int frame) { return fmt::format("<a href=\"#frame={0}\">{0}</a>", frame); };
  const auto row = [](const std::string& what, const std::string& frames) {
    return fmt::format("<tr><td class=\"k\">{}</td><td class=\"k\">{}</td></tr>", what, frames);
  };

  // A alone.
  std::string html = Read(WriteReport({.dir = a.string()}).html_path);
  EXPECT_NE(html.find(fmt::format("<video id=\"video\" class=\"overlay\" data-fps=\"{}\" "
                                  "data-frames=\"20\" src=\"overlay.mp4\" muted",
                                  fps)),
            std::string::npos);
  EXPECT_NE(html.find("function hcpfShow(frame)"), std::string::npos);
  EXPECT_NE(html.find("move the video to that frame"), std::string::npos);
  // The timeline carries its plot box (gnuplot's, in the SVG's units), so a
  // click there shows that frame and a cursor marks the video's frame.
  const size_t timeline = html.find("<div class=\"plot\" id=\"plot-timeline\" data-frames=\"20\"");
  ASSERT_NE(timeline, std::string::npos);
  double left = 0, right = 0, top = 0, bottom = 0;
  ASSERT_EQ(std::sscanf(html.c_str() + timeline,
                        "<div class=\"plot\" id=\"plot-timeline\" data-frames=\"20\" "
                        "data-left=\"%lf\" data-right=\"%lf\" data-top=\"%lf\" "
                        "data-bottom=\"%lf\"",
                        &left, &right, &top, &bottom),
            4);
  // The SVG is 820 wide; the plot sits right of the row labels, below the title.
  EXPECT_GT(left, 50.0);
  EXPECT_LT(left, right);
  EXPECT_LE(right, 820.0);
  EXPECT_GT(top, 10.0);
  EXPECT_LT(top, bottom);
  // gnuplot's border of that plot, in the same units (y from the top).
  EXPECT_NE(html.find(fmt::format("d='M{0:.2f},{1:.2f} L{0:.2f},{2:.2f} L{3:.2f},{2:.2f} "
                                  "L{3:.2f},{1:.2f} L{0:.2f},{1:.2f} Z",
                                  left, top, bottom, right),
                      timeline),
            std::string::npos);
  EXPECT_NE(html.find("A click on the timeline shows that frame"), std::string::npos);
  EXPECT_NE(html.find(row("filter 1 (target 1)",
                          "LOST " + link(2) + "–3, LOST " + link(5) + ", HIJACKED " + link(6))),
            std::string::npos);
  EXPECT_EQ(html.find("<td class=\"k\">filter 9 (target 2)</td>"), std::string::npos)
      << "always CORRECT: nothing to look at";
  EXPECT_NE(html.find(row("target models cut", "target 1: " + link(1) + ", target 2: " + link(3))),
            std::string::npos);

  // A against B: both videos, the comparison's frames link to them, and a
  // row B has as A has it is one row.
  html = Read(WriteReport({.dir = a.string(), .against = b.string()}).html_path);
  EXPECT_NE(html.find("<video id=\"video-a\" class=\"overlay\""), std::string::npos);
  EXPECT_NE(html.find("<video id=\"video-b\" class=\"overlay\""), std::string::npos);
  EXPECT_NE(html.find("src=\"../b/overlay.mp4\""), std::string::npos);
  EXPECT_NE(html.find("move both videos to that frame"), std::string::npos);
  EXPECT_NE(html.find("<td class=\"k\">" + link(2) + " (A LOST, B CORRECT)</td>"),
            std::string::npos);
  EXPECT_NE(html.find("<td class=\"k\">" + link(4) + " (A found, B missed)</td>"),
            std::string::npos);
  EXPECT_NE(html.find(row("B filter 2 (target 1)",
                          "STRAYED " + link(3) + ", SWAPPED " + link(4) + ", STRAYED " + link(6))),
            std::string::npos);
  EXPECT_NE(html.find(row("B filter 5 (no target)", "LOST " + link(1))), std::string::npos);
  EXPECT_NE(html.find(row("B filter 1 (target 1)", "LOST " + link(3))), std::string::npos);
  EXPECT_NE(html.find(row("A and B: target models cut",
                          "target 1: " + link(1) + ", target 2: " + link(3))),
            std::string::npos);
  EXPECT_EQ(html.find("B target models cut"), std::string::npos);
  EXPECT_NE(html.find(row("A filter 1 (target 1)",
                          "LOST " + link(2) + "–3, LOST " + link(5) + ", HIJACKED " + link(6))),
            std::string::npos);

  // B's video made by an hcpf that wrote MPEG-4 Part 2 (no "video" entry).
  auto mb = nlohmann::json::parse(Read(b / "manifest.json"));
  mb.erase("video");
  std::ofstream(b / "manifest.json") << mb.dump();
  html = Read(WriteReport({.dir = a.string(), .against = b.string()}).html_path);
  EXPECT_NE(html.find("<video id=\"video-a\""), std::string::npos);
  EXPECT_EQ(html.find("<video id=\"video-b\""), std::string::npos);
  EXPECT_NE(html.find("Run B's video: <a href=\"../b/overlay.mp4\">overlay.mp4</a>, MPEG-4 Part "
                      "2, which VLC and mpv play and most browsers do not (made by an hcpf that "
                      "wrote no H.264"),
            std::string::npos);
  EXPECT_NE(html.find("<code>hcpf run " + (b / "scenario.resolved.yaml").string() + " --out " +
                      b.string() + "-video --video</code>"),
            std::string::npos);
  // Neither plays: no player, no script, frame numbers are plain.
  ma = nlohmann::json::parse(Read(a / "manifest.json"));
  ma["video"]["plays_in_browsers"] = false;
  ma["video"]["codec"] = "MPEG-4 Part 2";
  std::ofstream(a / "manifest.json") << ma.dump();
  fs::remove(b / "overlay.mp4");
  html = Read(WriteReport({.dir = a.string(), .against = b.string()}).html_path);
  EXPECT_EQ(html.find("<video"), std::string::npos);
  EXPECT_EQ(html.find("<script>"), std::string::npos);
  EXPECT_NE(html.find("<div class=\"plot\" id=\"plot-timeline\">"), std::string::npos)
      << "no video: the timeline is only a picture";
  EXPECT_EQ(html.find("#frame="), std::string::npos);
  EXPECT_NE(html.find("<td class=\"k\">2 (A LOST, B CORRECT)</td>"), std::string::npos);
  EXPECT_NE(html.find(row("A filter 1 (target 1)", "LOST 2–3, LOST 5, HIJACKED 6")),
            std::string::npos)
      << "the frames to look at, without a video to show them: plain numbers";
  EXPECT_NE(html.find("Run A's video: <a href=\"overlay.mp4\">overlay.mp4</a>, MPEG-4 Part 2, "
                      "which VLC and mpv play and most browsers do not (the FFmpeg that wrote it "
                      "had no H.264 encoder)"),
            std::string::npos);
  EXPECT_NE(html.find("Run B has no <code>overlay.mp4</code>: <code>hcpf run "), std::string::npos);
}

// A rendered run's report says where its frames came from: how many were
// rendered and by which GL renderer, how many read from the frame cache and
// which renderers stored frames there, two of them in bold (they may mix).
// A detection-level run (no frames) says nothing of frames.
// What hcpf validate, run and render warn of the scene goes into the run's
// manifest.json (scene_notes) and the report says it under the header: here
// kMinimal's two vehicles, run long enough to meet at the crossing.
TEST(RunReport, SaysWhatWasWarnedOfTheScene) {
  const auto dir = testing::SweepFolder("run-report-scene-notes");
  const fs::path quiet = RunMinimal(dir, "none");
  EXPECT_EQ(nlohmann::json::parse(Read(quiet / "manifest.json"))["scene_notes"],
            nlohmann::json::array());
  EXPECT_EQ(Read(WriteReport({.dir = quiet.string()}).html_path).find("The scene:"),
            std::string::npos);
  const fs::path meeting = dir / "meeting";
  const scenarios::Scenario scenario = scenarios::LoadScenarioText(
      scenarios::testing::kMinimal, "base.yaml", {{"frames", "200"}, {"tracker.particles", "50"}});
  scenarios::RunScenario(scenario, {.out_dir = meeting.string()});
  const nlohmann::json notes =
      nlohmann::json::parse(Read(meeting / "manifest.json"))["scene_notes"];
  ASSERT_EQ(notes.size(), 1u) << notes.dump();
  const std::string note = notes[0].get<std::string>();
  EXPECT_EQ(note.rfind("targets 1 and 2 drive through each other at frames ", 0), 0u) << note;
  const std::string html = Read(WriteReport({.dir = meeting.string()}).html_path);
  EXPECT_NE(html.find("<p><strong>The scene:</strong></p>\n<ul>\n<li>" + note.substr(0, 60)),
            std::string::npos)
      << html.substr(0, 3000);
  // A manifest whose notes are not texts is refused, naming the key.
  nlohmann::json manifest = nlohmann::json::parse(Read(meeting / "manifest.json"));
  manifest["scene_notes"] = {1, 2};
  std::ofstream(meeting / "manifest.json") << manifest.dump(2);
  try {
    WriteReport({.dir = meeting.string()});
    FAIL() << "scene_notes [1, 2] accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("scene_notes"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("a list of texts"), std::string::npos) << e.what();
  }
}

TEST(RunReport, SaysWhichRendererMadeTheFrames) {
  const auto dir = testing::SweepFolder("run-report-frames");
  const fs::path run = RunMinimal(dir, "none");
  EXPECT_EQ(Read(WriteReport({.dir = run.string()}).html_path).find("<p>Frames:"),
            std::string::npos);
  nlohmann::json manifest = nlohmann::json::parse(Read(run / "manifest.json"));
  manifest["frames_rendered"] = 3;
  manifest["frames_from_cache"] = 2;
  manifest["gl_renderer"] = {{"backend", "osmesa"},
                             {"platform", "osmesa"},
                             {"vendor", "Mesa"},
                             {"renderer", "llvmpipe <x>"},
                             {"version", "4.5 Mesa 22.3.6"}};
  manifest["frame_cache_renderers"] = {"osmesa; Mesa; llvmpipe <x>; 4.5 Mesa 22.3.6"};
  std::ofstream(run / "manifest.json") << manifest.dump(2);
  EXPECT_NE(Read(WriteReport({.dir = run.string()}).html_path)
                .find("<p>Frames: 3 rendered by <code>osmesa; Mesa; llvmpipe &lt;x&gt;; 4.5 Mesa "
                      "22.3.6</code>; 2 read from the frame cache, rendered there by <code>osmesa; "
                      "Mesa; llvmpipe &lt;x&gt;; 4.5 Mesa 22.3.6</code>.</p>"),
            std::string::npos);
  manifest["frames_rendered"] = 0;
  manifest["gl_renderer"] = nullptr;
  manifest["frame_cache_renderers"].push_back("egl device 0 (hardware); NVIDIA; H200; 4.6");
  std::ofstream(run / "manifest.json") << manifest.dump(2);
  EXPECT_NE(Read(WriteReport({.dir = run.string()}).html_path)
                .find("<p>Frames: 2 read from the frame cache, whose folder holds frames of 2 GL "
                      "renderers, so they may mix: <strong><code>osmesa; Mesa; llvmpipe &lt;x&gt;; "
                      "4.5 Mesa 22.3.6</code> and <code>egl device 0 (hardware); NVIDIA; H200; "
                      "4.6</code></strong>.</p>"),
            std::string::npos);
}

// Bad input: a folder that is neither a sweep's nor a run's names the folder,
// both kinds expected, and what it is.
TEST(RunReport, FolderThatIsNeitherSweepNorRunIsBadInput) {
  const auto dir = testing::SweepFolder("report-neither");
  const fs::path plain = dir / "plain";
  fs::create_directories(plain);
  std::ofstream(plain / "notes.txt") << "hello";
  try {
    WriteReport({.dir = plain.string()});
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(plain.string()), std::string::npos) << m;
    EXPECT_NE(m.find("results.sqlite"), std::string::npos) << m;
    EXPECT_NE(m.find("hcpf-run/1"), std::string::npos) << m;
    EXPECT_NE(m.find("found a folder with neither results.sqlite nor manifest.json"),
              std::string::npos)
        << m;
  }
  // A render folder (hcpf render) has a manifest but no metrics.
  std::ofstream(plain / "manifest.json") << R"({"format": "hcpf-render/1"})";
  try {
    WriteReport({.dir = plain.string()});
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("found a render folder"), std::string::npos) << e.what();
  }
  std::ofstream(plain / "manifest.json") << "{not json";
  EXPECT_THROW(WriteReport({.dir = plain.string()}), InputError);
  EXPECT_THROW(WriteReport({.dir = (plain / "notes.txt").string()}), InputError);
}

// A damaged camera_motion.csv: the error names the file, line and column.
TEST(RunReport, MalformedCameraMotionCsvNamesFileLineAndColumn) {
  const auto dir = testing::SweepFolder("run-report-bad-csv");
  const fs::path run = RunMinimal(dir, "oracle");
  const fs::path csv = run / "camera_motion.csv";
  std::string text = Read(csv);
  // Line 3 (frame 2): replace its error_px (the 6th field) with "abc".
  size_t line3 = text.find('\n', text.find('\n') + 1) + 1;
  size_t field = line3;
  for (int i = 0; i < 5; ++i) field = text.find(',', field) + 1;
  const size_t end = text.find(',', field);
  text.replace(field, end - field, "abc");
  std::ofstream(csv, std::ios::trunc) << text;
  try {
    WriteReport({.dir = run.string()});
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find(csv.string() + ":3:" + std::to_string(field - line3 + 1)), std::string::npos)
        << m;
    EXPECT_NE(m.find("error_px"), std::string::npos) << m;
    EXPECT_NE(m.find("found \"abc\""), std::string::npos) << m;
  }
}

// A static camera under mode none, or motion applied exactly, leaves
// errors of ~1e-14 px: rounding, which was drawn as a plot of noise on a 0
// to 7e-14 axis with "mean 6.86149e-14 px" (an audit). Shown as 0, and not
// plotted; an error of 1e-6 px is still one.
// A run of one frame measured no camera motion (metrics.json's summaries
// are null): the table says "–", and nothing on the page reads "nan" (an
// audit of valid input: eight cells did).
TEST(RunReport, ARunOfOneFrameShowsNoCameraMotionAsADash) {
  const auto dir = testing::SweepFolder("run-report-one-frame");
  const fs::path run = dir / "one";
  std::string text = scenarios::testing::kMinimal;
  text.replace(text.find("start_frame: 2"), 14, "start_frame: 0");
  scenarios::RunScenario(scenarios::LoadScenarioText(text, "base.yaml", {{"frames", "1"}}),
                         {.out_dir = run.string()});
  const auto metrics = nlohmann::json::parse(Read(run / "metrics.json"));
  ASSERT_TRUE(metrics["camera_motion"]["mean_px"].is_null()) << metrics["camera_motion"];
  const std::string html = Read(WriteReport({.dir = run.string()}).html_path);
  EXPECT_NE(html.find("<tr><td>error</td><td>–</td><td>–</td><td>–</td><td>–</td></tr>"),
            std::string::npos);
  EXPECT_EQ(html.find("nan"), std::string::npos);
}

TEST(RunReport, CameraMotionErrorsOfRoundingAreShownAsZeroAndNotPlotted) {
  const auto dir = testing::SweepFolder("run-report-rounding");
  const fs::path run = RunMinimal(dir, "none");
  const auto rewrite = [&run](const std::string& error) {
    std::stringstream in(Read(run / "camera_motion.csv"));
    std::string text, line;
    std::getline(in, line);
    text = line + "\n";
    while (std::getline(in, line)) {
      std::vector<std::string> f;
      std::stringstream fields(line);
      for (std::string x; std::getline(fields, x, ',');) f.push_back(x);
      if (line.back() == ',') f.emplace_back();
      f[5] = error;
      f[7] = "2.8e-14";
      text += fmt::format("{}\n", fmt::join(f, ","));
    }
    std::ofstream(run / "camera_motion.csv", std::ios::trunc) << text;
    auto metrics = nlohmann::json::parse(Read(run / "metrics.json"));
    for (const char* k : {"mean_px", "median_px", "p95_px", "max_px"}) {
      metrics["camera_motion"][k] = std::stod(error);
      metrics["camera_motion"]["floor"][k] = 2.8e-14;
    }
    std::ofstream(run / "metrics.json", std::ios::trunc) << metrics.dump();
  };
  rewrite("6.86e-14");
  std::string html = Read(WriteReport({.dir = run.string()}).html_path);
  EXPECT_EQ(html.find("id=\"plot-camera_motion\""), std::string::npos);
  EXPECT_NE(html.find("<tr><td>error</td><td>0</td><td>0</td><td>0</td><td>0</td></tr>"),
            std::string::npos);
  EXPECT_NE(html.find("<tr><td>floor</td><td>0</td><td>0</td><td>0</td><td>0</td></tr>"),
            std::string::npos);
  EXPECT_NE(html.find("is below 10<sup>&minus;9</sup>&nbsp;px, floating-point rounding"),
            std::string::npos);
  rewrite("1e-06");
  html = Read(WriteReport({.dir = run.string()}).html_path);
  EXPECT_NE(html.find("id=\"plot-camera_motion\""), std::string::npos);
  EXPECT_NE(html.find("<tr><td>error</td><td>1e-06</td>"), std::string::npos);
  EXPECT_NE(html.find("mean 0 px"), std::string::npos) << "the floor's legend";
}

// report.panels: one plot per metric and panel value, each with the lines
// of its own cells (its series values) and the panel named in the title;
// with grid.base every base scenario is shown, resolved.
TEST(Report, PanelsDrawOnePlotPerMetricAndValue) {
  const auto dir = testing::SweepFolder("report-panels");
  std::string other = scenarios::testing::kMinimal;
  other.replace(other.find("name: minimal"), 13, "name: second");
  std::ofstream(dir / "second.yaml") << other;
  const SweepSpec spec = LoadSweepFile(testing::WriteSweep(
      dir,
      "seeds: 2\ngrid:\n  base: [base.yaml, second.yaml]\n  tracker.particles: [20, 60]\n"
      "  tracker.resampling.method: [systematic, charged]\n"
      "report: {x: tracker.particles, series: tracker.resampling.method, panels: base, "
      "y: [idf1, hota]}\n"));
  const std::string out = RunQuietly(spec, dir);
  // The panels of a metric share one y range, which reaches past every
  // value drawn in either (an audit: hijack rate 0-1 in one panel, 0-0.3 in
  // the other, so a bump of 0.05 looked like a gap of 0.6).
  const fs::path kept = dir / "kept";
  WriteReport({.dir = out, .gnuplot = KeepingGnuplot(dir, kept).string()});
  const auto y_range = [&kept](int plot) {
    const std::string gp = Read(kept / fmt::format("plot_{}.gp", plot));
    const size_t at = gp.find("set yrange [");
    return at == std::string::npos ? std::string("(none)") : gp.substr(at, gp.find('\n', at) - at);
  };
  EXPECT_NE(y_range(0), "(none)");
  EXPECT_EQ(y_range(0), y_range(1)) << "idf1's two panels";
  EXPECT_EQ(y_range(2), y_range(3)) << "hota's two panels";
  for (int plot = 0; plot < 2; ++plot) {
    double lo = 0, hi = 0;
    ASSERT_EQ(std::sscanf(y_range(plot).c_str(), "set yrange [%lf:%lf]", &lo, &hi), 2);
    std::stringstream dat(Read(kept / fmt::format("plot_{}.dat", plot)));
    for (std::string line; std::getline(dat, line);) {
      double x, mean, lower, upper;
      if (std::sscanf(line.c_str(), "%lf %lf %lf %lf", &x, &mean, &lower, &upper) != 4) continue;
      for (const double v : {mean, lower, upper}) {
        if (std::isfinite(v)) {
          EXPECT_LT(lo, v);
          EXPECT_GT(hi, v);
        }
      }
    }
  }
  const ReportResult r = WriteReport({.dir = out});
  EXPECT_EQ(r.plots, 4);
  EXPECT_EQ(r.cells, 8);
  EXPECT_EQ(r.difference_plots, 4);  // one per metric and panel
  // The at-a-glance table has a row per metric and panel (pooled over the
  // main job's two likelihood models, "5 better, 3 worse" hid that they
  // were under different models: an audit). 2 particle counts per panel.
  const std::string md = Read(fs::path(out) / "findings.md");
  EXPECT_NE(md.find("| metric | base | compared | better |"), std::string::npos) << md;
  for (const char* row : {"| idf1 | base.yaml | charged − systematic |",
                          "| idf1 | second.yaml | charged − systematic |",
                          "| hota | base.yaml | charged − systematic |",
                          "| hota | second.yaml | charged − systematic |"}) {
    EXPECT_NE(md.find(row), std::string::npos) << row << "\n" << md;
  }
  EXPECT_NE(md.find("At a glance: for each metric, base value and"), std::string::npos);
  const std::string html = Read(r.html_path);
  EXPECT_EQ(Count(html, "<svg"), 10U);  // 8 plots, a scene sketch per base
  for (const char* id : {"plot-idf1-0", "plot-idf1-1", "plot-hota-0", "plot-hota-1"}) {
    const size_t at = html.find(std::string("id=\"") + id + "\"");
    ASSERT_NE(at, std::string::npos) << id;
    const std::string svg = html.substr(at, html.find("</svg>", at) - at);
    EXPECT_NE(
        svg.find(id[std::string(id).size() - 1] == '0' ? "base = base.yaml" : "base = second.yaml"),
        std::string::npos)
        << id;
    // Lines are the series alone: the panel key does not split them.
    EXPECT_NE(svg.find("systematic"), std::string::npos) << id;
    EXPECT_NE(svg.find("charged"), std::string::npos) << id;
    EXPECT_EQ(svg.find("base="), std::string::npos) << id;
  }
  EXPECT_NE(html.find("Base scenarios (resolved)"), std::string::npos);
  // What the runs did not take from the bases (an audit: a rendered sweep's
  // base read "source: simulated" with nothing to say no run used it).
  EXPECT_NE(html.find("Every run replaces 3 keys: <code>base</code> = base.yaml, second.yaml; "
                      "<code>tracker.particles</code> = "),
            std::string::npos)
      << html.substr(html.find("Base scenarios (resolved)"), 1500);
  EXPECT_NE(html.find("Its <code>seed</code> and <code>seeds</code> are the base's own"),
            std::string::npos);
  EXPECT_NE(html.find("# base: base.yaml"), std::string::npos);
  EXPECT_NE(html.find("# base: second.yaml"), std::string::npos);
  EXPECT_NE(html.find("name: &quot;second&quot;"), std::string::npos);
  // summary.csv: a base column.
  EXPECT_EQ(Read(r.csv_path).rfind("base,tracker.particles,", 0), 0U);
}

// A sweep whose series is tracker.camera_motion plots camera_motion_error_px:
// one line per mode, and each cell's mean is the mean of its runs'
// metrics.json camera_motion.mean_px, read here from the files.
TEST(Report, CameraMotionSeriesPlotsCameraMotionError) {
  const auto dir = testing::SweepFolder("report-camera-motion");
  const SweepSpec spec = LoadSweepFile(
      testing::WriteSweep(dir,
                          "base: base.yaml\nseeds: 2\ngrid:\n  camera.shake_px: [1.0]\n"
                          "  tracker.scene_filter.particles: [100]\n  tracker.particles: [20, 60]\n"
                          "  tracker.camera_motion: [none, scene_filter]\n"
                          "report: {x: tracker.particles, series: tracker.camera_motion, "
                          "y: [camera_motion_error_px]}\n"));
  const std::string out = RunQuietly(spec, dir);
  const ReportResult r = WriteReport({.dir = out});
  EXPECT_EQ(r.cells, 4);
  const std::string html = Read(r.html_path);
  const size_t at = html.find("plot-camera_motion_error_px");
  ASSERT_NE(at, std::string::npos);
  const std::string svg = html.substr(at, html.find("</svg>", at) - at);
  EXPECT_NE(svg.find("camera-motion error"), std::string::npos);
  EXPECT_NE(svg.find("none"), std::string::npos);
  EXPECT_NE(svg.find("scene_filter"), std::string::npos);

  const auto mean_px = [](const fs::path& run_dir) {
    const auto metrics = nlohmann::json::parse(Read(run_dir / "metrics.json"));
    return metrics.at("camera_motion").at("mean_px").get<double>();
  };
  for (const char* mode : {"none", "scene_filter"}) {
    double sum = 0.0;
    int n = 0;
    for (const SweepRun& run : ExpandSweep(spec)) {
      if (run.values[2] != "60" || run.values[3] != mode) continue;
      sum += mean_px(fs::path(out) / "runs" / run.key);
      ++n;
    }
    ASSERT_EQ(n, 2);
    // summary.csv row of the cell: 1.0,100,60,<mode>,2,0,... ; find the column by the header.
    const std::string csv = Read(r.csv_path);
    const std::string header = csv.substr(0, csv.find('\n'));
    std::vector<std::string> names;
    std::stringstream hs(header);
    for (std::string name; std::getline(hs, name, ',');) names.push_back(name);
    const size_t column =
        std::find(names.begin(), names.end(), "camera_motion_error_px_mean") - names.begin();
    ASSERT_LT(column, names.size());
    const size_t row = csv.find(std::string("\n1.0,100,60,") + mode + ",2,0,");
    ASSERT_NE(row, std::string::npos) << csv;
    std::stringstream line(csv.substr(row + 1, csv.find('\n', row + 1) - row - 1));
    std::string cell;
    for (size_t i = 0; i <= column; ++i) std::getline(line, cell, ',');
    EXPECT_NEAR(std::stod(cell), sum / n, 1e-5 * (1 + sum / n)) << mode;
  }
}

// The rows of a kept gnuplot data file, by line label: x, mean, lower, upper.
std::map<std::string, std::vector<std::array<double, 4>>> PlotRows(const fs::path& dat) {
  std::map<std::string, std::vector<std::array<double, 4>>> rows;
  std::stringstream text(Read(dat));
  std::string line, label;
  while (std::getline(text, line)) {
    if (line.empty()) continue;
    if (line[0] == '#') {
      label = line.substr(2);
      continue;
    }
    std::array<double, 4> r{};
    std::stringstream(line) >> r[0] >> r[1] >> r[2] >> r[3];
    rows[label].push_back(r);
  }
  return rows;
}

// The y axis is logarithmic exactly when every value a plot draws (means and
// band edges) is positive and they span more than 20x: checked on every plot
// of a sweep whose camera-motion errors span ~30x over 6 seeds (none ~1.7 px,
// the scene filter on the simulated evidence ~0.06 px at the bands' lower
// edge), against the plots' own data files. With 2 seeds the t bands reach 0
// and the axis stays linear (0 has no place on a log axis).
TEST(Report, WideRangesGetALogarithmicYAxis) {
  const auto dir = testing::SweepFolder("report-log-y");
  const SweepSpec spec = LoadSweepFile(
      testing::WriteSweep(dir,
                          "base: base.yaml\nseeds: 6\ngrid:\n  camera.shake_px: [1.0]\n"
                          "  tracker.scene_filter.particles: [100]\n  tracker.particles: [20, 60]\n"
                          "  tracker.camera_motion: [none, scene_filter]\n"
                          "report: {x: tracker.particles, series: tracker.camera_motion, "
                          "y: [camera_motion_error_px, da_accuracy, mota]}\n"));
  const std::string out = RunQuietly(spec, dir);
  const fs::path kept = dir / "kept";
  WriteReport({.dir = out, .gnuplot = KeepingGnuplot(dir, kept).string()});
  int log_plots = 0, linear_plots = 0;
  for (const auto& entry : fs::directory_iterator(kept)) {
    if (entry.path().extension() != ".gp") continue;
    const std::string script = Read(entry.path());
    const bool difference = script.find("paired difference") != std::string::npos;
    double lo = std::numeric_limits<double>::infinity(), hi = 0.0;
    fs::path dat = entry.path();
    dat.replace_extension(".dat");
    for (const auto& [label, rows] : PlotRows(dat)) {
      for (const auto& row : rows) {
        for (int k = 1; k < 4; ++k) {
          if (!std::isfinite(row[k])) continue;
          lo = std::min(lo, row[k]);
          hi = std::max(hi, row[k]);
        }
      }
    }
    const bool expected = !difference && lo > 0.0 && hi / lo > 20.0;
    const bool log_y = script.find("set logscale y") != std::string::npos;
    EXPECT_EQ(log_y, expected) << entry.path() << ": values " << lo << " .. " << hi;
    (log_y ? log_plots : linear_plots) += 1;
  }
  EXPECT_GE(log_plots, 1) << "the camera-motion error spans more than 20x";
  EXPECT_GE(linear_plots, 1);
}

// The meta of a store written by hand: its swept keys (the first is x),
// the series ("" for none), the reported metrics and the run count.
StoreMeta HandMeta(std::vector<std::string> keys, const std::string& series,
                   std::vector<std::string> y, int64_t runs) {
  StoreMeta meta;
  meta.sweep_hash = "hand";
  meta.sweep_file = "hand.yaml";
  meta.report.x = keys.front();
  meta.swept_keys = std::move(keys);
  meta.report.series = series;
  meta.report.y = std::move(y);
  meta.run_count = runs;
  return meta;
}

// A store written directly, with hand-picked values: particles {100, 1000} ×
// {systematic, charged} × 10 seeds. hijack_rate per run is 0 or 1:
// systematic 1 on every seed at 100 and on seeds 0–4 at 1000, charged 0
// everywhere. mota: systematic 0.9 everywhere; charged at 1000 is 1.0 on
// seeds 0–8 and 0.5 on seed 9 (its t interval reaches past 1).
fs::path HandStore(const std::string& name, const std::string& reference = "systematic",
                   int seeds = 10, int failed_charged_at_1000 = 0) {
  const auto dir = testing::SweepFolder(name);
  StoreMeta meta = HandMeta({"tracker.particles", "tracker.resampling.method"},
                            "tracker.resampling.method", {"hijack_rate", "mota"}, 4 * seeds);
  meta.report.reference = reference;
  auto store = ResultsStore::OpenOrCreate((dir / "results.sqlite").string(), meta);
  int64_t index = 0;
  for (const char* particles : {"100", "1000"}) {
    for (const char* method : {"systematic", "charged"}) {
      for (int seed = 0; seed < seeds; ++seed) {
        RunRecord r =
            HandRun(dir, std::string(particles) + "-" + method + "-" + std::to_string(seed),
                    index++, seed, 1000 + seed, {particles, method});
        const bool systematic = std::string(method) == "systematic";
        const bool many = std::string(particles) == "1000";
        r.ok = systematic || !many || seed >= failed_charged_at_1000;
        r.metrics["hijack_rate"] = systematic && (!many || seed < 5) ? 1.0 : 0.0;
        r.metrics["mota"] = systematic ? 0.9 : (many ? (seed < 9 ? 1.0 : 0.5) : 0.9);
        store->Put(r);
      }
    }
  }
  return dir;
}

// A pooled store written directly: particles {100} × {systematic, charged}
// × sun azimuth {0, 90, 180} (pooled) × 5 seeds, report.y [mota].
// systematic: 0.47, 0.5, 0.53 at the three azimuths on every seed; charged
// on seeds s = 0–3: 0.5 + m_s − 0.05, + m_s, + m_s + 0.05 with m_s = 0.1 (s
// + 1); on seed 4, 0 at 0 and 180 and its run at 90 failed. The runs of a
// seed share its random streams: one value per seed, and only from a seed
// with every pooled value (charged's seed 4 is left out, not averaged over
// its two zeros).
//   charged's cell: seed means 0.6, 0.7, 0.8, 0.9; mean 0.75, s =
//   √(0.05 / 3) = 0.129099, t(0.975, 3) = 3.182 (StudentT975's table),
//   half-width 3.182 · 0.129099 / 2 = 0.205397: [0.544603, 0.955397], n =
//   4 (12 runs). The 12
//   runs taken as independent would give n = 12 and a half-width of
//   2.201 · 0.124316 / √12 = 0.078988.
//   charged − systematic: 4 pairs of seed means, differences 0.1 … 0.4,
//   mean 0.25, [0.044603, 0.455397]; all positive: W+ = 10, exact p = 2/16
//   = 0.125, not a finding. The 12 run pairs, all positive, would give p =
//   2/4096 = 0.000488 and call it one. Each run pairs with the reference's
//   run of its own azimuth: paired with the first (0.47) the differences
//   would be 0.03 larger. The largest run pair: seed 3 at 180, 0.95 − 0.53.
// With `complete` and `step` (PooledRunsNameTheirPooledValues): seeds 0 …
// complete − 1 as seeds 0–3 above with m_s = step (s + 1), and seed
// `complete` as seed 4.
fs::path PooledHandStore(const std::string& name, int complete = 4, double step = 0.1) {
  const auto dir = testing::SweepFolder(name);
  StoreMeta meta =
      HandMeta({"tracker.particles", "tracker.resampling.method", "world.sun.azimuth_deg"},
               "tracker.resampling.method", {"mota"}, 2 * 3 * (complete + 1));
  meta.report.pool = {"world.sun.azimuth_deg"};
  auto store = ResultsStore::OpenOrCreate((dir / "results.sqlite").string(), meta);
  int64_t index = 0;
  for (const char* method : {"systematic", "charged"}) {
    for (int a = 0; a < 3; ++a) {
      for (int seed = 0; seed <= complete; ++seed) {
        RunRecord r = HandRun(dir, fmt::format("100-{}-{}-{}", method, a * 90, seed), index++, seed,
                              1000 + seed, {"100", method, std::to_string(a * 90)});
        const bool systematic = std::string(method) == "systematic";
        r.ok = systematic || seed < complete || a != 1;
        const double m = step * (seed + 1);
        r.metrics["mota"] = systematic        ? 0.5 + 0.03 * (a - 1)
                            : seed < complete ? 0.5 + m + 0.05 * (a - 1)
                                              : 0.0;
        store->Put(r);
      }
    }
  }
  return dir;
}

// The column of `name` in a CSV file's header.
size_t CsvColumn(const fs::path& path, const std::string& name) {
  std::stringstream text(Read(path));
  std::string header, field;
  std::getline(text, header);
  std::stringstream f(header);
  for (size_t i = 0; std::getline(f, field, ','); ++i) {
    if (field == name) return i;
  }
  ADD_FAILURE() << name << " not in " << path;
  return 0;
}

// `meta` recording `expansion` (none when nullopt) with root seed 1 (the
// seeds SweepSeed(1, seed index) of the hand stores' runs), as a sweep file's
// `seed: 1` writes it.
void RecordExpansion(StoreMeta* meta, const std::optional<StoredExpansion>& expansion) {
  meta->expansion = expansion;
  meta->root_seed = "1";
  meta->root_seed_from = "sweep file";
}

// A store of the runs `cells` × seeds 0–4 of a sweep over particles (x),
// method (series) and the sun's azimuth (pooled), recording `expansion`
// when given; each run's index is its cell's position in the expansion
// (`cell_index`) times 5 plus its seed. mota: 0.5 for systematic, 0.5 + 0.1 ×
// (seed + 1) for charged.
fs::path PooledSunStore(const std::string& name,
                        const std::vector<std::pair<int64_t, std::vector<std::string>>>& cells,
                        const std::optional<StoredExpansion>& expansion) {
  const auto dir = testing::SweepFolder(name);
  StoreMeta meta =
      HandMeta({"tracker.particles", "tracker.resampling.method", "world.sun.azimuth_deg"},
               "tracker.resampling.method", {"mota"}, 20);
  meta.report.pool = {"world.sun.azimuth_deg"};
  RecordExpansion(&meta, expansion);
  auto store = ResultsStore::OpenOrCreate((dir / "results.sqlite").string(), meta);
  for (const auto& [cell_index, values] : cells) {
    for (int seed = 0; seed < 5; ++seed) {
      RunRecord r = HandRun(dir, fmt::format("{}-{}-{}-{}", values[0], values[1], values[2], seed),
                            cell_index * 5 + seed, seed, SweepSeed(1, seed), values);
      r.metrics["mota"] = values[1] == "systematic" ? 0.5 : 0.5 + 0.1 * (seed + 1);
      store->Put(r);
    }
  }
  return dir;
}

// A pooled key is cleared from a run's partner key only where it follows the
// series in the comparison made (a review of the pooled pairing):
// - a store that stopped with each series value at one pooled value of a
//   grid key: the runs look as if the azimuth followed the method, but the
//   recorded expansion says it is swept across every method, so no run pairs
//   with a run of another azimuth (a store without the expansion, written
//   before it was recorded, still pairs them);
// - an azimuth zipped with x and the series follows the series at each x,
//   not over the store: until 2026-12-06 that was decided once over every
//   run, and no run paired.
TEST(Report, APooledKeyIsClearedOnlyWhereItFollowsTheSeriesInTheComparison) {
  StoredExpansion grid;
  grid.grid = {{"tracker.particles", {"100"}},
               {"tracker.resampling.method", {"systematic", "charged"}},
               {"world.sun.azimuth_deg", {"0", "180"}}};
  grid.seeds = 5;
  // Cells in expansion order: (systematic, 0) 0, (systematic, 180) 1,
  // (charged, 0) 2, (charged, 180) 3; the store holds cells 0 and 3.
  const std::vector<std::pair<int64_t, std::vector<std::string>>> partial = {
      {0, {"100", "systematic", "0"}}, {3, {"100", "charged", "180"}}};
  const auto pairs_of = [](const fs::path& dir) {
    WriteReport({.dir = dir.string()});
    const auto rows = CsvRows(dir / "paired.csv");
    std::vector<std::string> pairs;
    for (const auto& row : rows) pairs.push_back(row[CsvColumn(dir / "paired.csv", "pairs")]);
    return pairs;
  };
  EXPECT_EQ(pairs_of(PooledSunStore("report-pool-partial", partial, grid)),
            std::vector<std::string>{"0"});
  EXPECT_EQ(pairs_of(PooledSunStore("report-pool-partial-old", partial, std::nullopt)),
            std::vector<std::string>{"5"});

  StoredExpansion zip;
  zip.zip = {{"tracker.particles", {"100", "100", "1000", "1000"}},
             {"tracker.resampling.method", {"systematic", "charged", "systematic", "charged"}},
             {"world.sun.azimuth_deg", {"0", "90", "180", "270"}}};
  zip.seeds = 5;
  const std::vector<std::pair<int64_t, std::vector<std::string>>> zipped = {
      {0, {"100", "systematic", "0"}},
      {1, {"100", "charged", "90"}},
      {2, {"1000", "systematic", "180"}},
      {3, {"1000", "charged", "270"}}};
  const fs::path dir = PooledSunStore("report-pool-zipped", zipped, zip);
  EXPECT_EQ(pairs_of(dir), (std::vector<std::string>{"5", "5"}));
  // Each seed's charged run at 90° pairs with its systematic run at 0°.
  const auto rows = CsvRows(dir / "paired.csv");
  EXPECT_EQ(rows[0][CsvColumn(dir / "paired.csv", "max_run")], "100-charged-90-4");
  EXPECT_EQ(rows[0][CsvColumn(dir / "paired.csv", "max_reference_run")], "100-systematic-0-4");
}

// A pooled cell's runs of one seed are averaged before its band and its
// paired test (PooledHandStore's comment works the values out).
TEST(Report, PooledRunsOfASeedCountAsOneUnit) {
  const fs::path dir = PooledHandStore("report-pool-seeds");
  const fs::path kept = dir / "kept";
  const ReportResult r =
      WriteReport({.dir = dir.string(), .gnuplot = KeepingGnuplot(dir, kept).string()});
  EXPECT_EQ(r.cells, 2);
  const auto cells = CsvRows(r.csv_path);
  ASSERT_EQ(cells.size(), 2U);
  const size_t runs = CsvColumn(r.csv_path, "runs"), mean = CsvColumn(r.csv_path, "mota_mean"),
               lo = CsvColumn(r.csv_path, "mota_lo95"), hi = CsvColumn(r.csv_path, "mota_hi95"),
               n = CsvColumn(r.csv_path, "mota_n");
  const auto& charged = cells[1];
  ASSERT_EQ(charged[1], "charged");
  EXPECT_EQ(charged[2], "all");
  EXPECT_EQ(charged[runs], "15");
  EXPECT_EQ(charged[n], "4");
  EXPECT_NEAR(std::stod(charged[mean]), 0.75, 1e-9);
  EXPECT_NEAR(std::stod(charged[lo]), 0.544603, 1e-6);
  EXPECT_NEAR(std::stod(charged[hi]), 0.955397, 1e-6);
  EXPECT_EQ(cells[0][n], "5");
  EXPECT_NEAR(std::stod(cells[0][mean]), 0.5, 1e-12);
  const auto paired = CsvRows(dir / "paired.csv");
  ASSERT_EQ(paired.size(), 1U);
  const size_t pairs = CsvColumn(dir / "paired.csv", "pairs"),
               difference = CsvColumn(dir / "paired.csv", "mean_difference"),
               dlo = CsvColumn(dir / "paired.csv", "lo95"),
               dhi = CsvColumn(dir / "paired.csv", "hi95"),
               positive = CsvColumn(dir / "paired.csv", "positive"),
               p = CsvColumn(dir / "paired.csv", "p_value");
  EXPECT_EQ(paired[0][pairs], "4");
  EXPECT_EQ(paired[0][positive], "4");
  EXPECT_NEAR(std::stod(paired[0][difference]), 0.25, 1e-9);
  EXPECT_NEAR(std::stod(paired[0][dlo]), 0.044603, 1e-6);
  EXPECT_NEAR(std::stod(paired[0][dhi]), 0.455397, 1e-6);
  EXPECT_NEAR(std::stod(paired[0][p]), 0.125, 1e-12);
  const size_t max_difference = CsvColumn(dir / "paired.csv", "max_difference"),
               max_run = CsvColumn(dir / "paired.csv", "max_run"),
               max_reference = CsvColumn(dir / "paired.csv", "max_reference_run");
  EXPECT_NEAR(std::stod(paired[0][max_difference]), 0.42, 1e-9);
  EXPECT_EQ(paired[0][max_run], "100-charged-180-3");
  EXPECT_EQ(paired[0][max_reference], "100-systematic-180-3");
  const std::string md = Read(dir / "findings.md");
  EXPECT_EQ(md.find("significantly better"), std::string::npos) << md;
  EXPECT_NE(md.find("4 seed pairs"), std::string::npos) << md;
  EXPECT_NE(Read(r.html_path).find("n, the bands and the paired tests count seeds"),
            std::string::npos);
  // The plot's faint points are the seeds' means the band is over: charged's
  // block (the second) has 4 of them, 0.6 … 0.9, not the 12 runs.
  std::stringstream points(Read(kept / "plot_0_seeds.dat"));
  std::vector<std::vector<double>> blocks(1);
  std::string line;
  while (std::getline(points, line)) {
    if (line.empty()) {
      if (!blocks.back().empty()) blocks.emplace_back();
      continue;
    }
    double x = 0.0, y = 0.0;
    std::stringstream(line) >> x >> y;
    blocks.back().push_back(y);
  }
  if (blocks.back().empty()) blocks.pop_back();
  ASSERT_EQ(blocks.size(), 2U);
  ASSERT_EQ(blocks[1].size(), 4U);
  for (size_t k = 0; k < 4; ++k) EXPECT_NEAR(blocks[1][k], 0.6 + 0.1 * k, 1e-12) << k;
  EXPECT_NE(Read(kept / "plot_0.gp").find("title 'one seed (its pooled runs averaged)'"),
            std::string::npos);
  // The cells table: n counts the seeds with a run at every pooled value
  // (charged: 4; systematic: 5), then the finished runs and the failures.
  const std::string html = Read(r.html_path);
  EXPECT_NE(html.find("<th>n</th><th>runs</th><th>failures</th>"), std::string::npos);
  EXPECT_NE(html.find("<td class=\"k\">charged</td><td class=\"k\">all</td><td>4</td><td>14</td>"
                      "<td class=\"failed\">1</td>"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("<td class=\"k\">systematic</td><td class=\"k\">all</td><td>5</td>"
                      "<td>15</td><td>0</td>"),
            std::string::npos);
}

// A pooled report's seeds to look at are run pairs, named by their pooled
// value. PooledHandStore with 6 complete seeds, m_s = 0.05 (s + 1): every
// seed's mean difference is m_s > 0, p = 2/64 = 0.031, a finding. Its run
// pairs differ by m_s + 0.02 (a − 1): the furthest is seed 5 at 180 (0.3 +
// 0.02 = 0.32), the least far seed 0 at 0 (0.05 − 0.02 = 0.03).
TEST(Report, PooledRunsNameTheirPooledValues) {
  const fs::path dir = PooledHandStore("report-pool-look", 6, 0.05);
  const std::string html = Read(WriteReport({.dir = dir.string()}).html_path);
  EXPECT_NE(html.find("the run pair (one seed at one pooled value) whose difference goes furthest"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("so a run pair against it need not be a seed against it"), std::string::npos);
  EXPECT_NE(html.find(">seed index 5, world.sun.azimuth_deg = 180</a>: &Delta;&nbsp;0.32<br>"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find(">seed index 0, world.sun.azimuth_deg = 0</a>: &Delta;&nbsp;0.03<br>"),
            std::string::npos)
      << html.substr(html.find("seeds-to-look-at"), 3000);
}

// Bands of a 0/1 metric stay inside [0, 1]: Wilson, by hand
// (statistics_test.cc): 0 of 10 and 10 of 10 have no spread, n* = 10:
// [0, 0.277533] and [0.722467, 1]; 5 of 10 has n* = 6.756993:
// [0.198979, 0.801021]. MOTA's t band at
// (1000, charged), mean 0.95, s = 0.5/√10 = 0.158114, half-width 2.262 ·
// 0.158114 / √10 = 0.113100, is cut at 1.
TEST(Report, BandsOfAZeroOneMetricAreWilsonInsideTheUnitInterval) {
  const fs::path dir = HandStore("report-wilson");
  const fs::path kept = dir / "kept";
  const ReportResult r =
      WriteReport({.dir = dir.string(), .gnuplot = KeepingGnuplot(dir, kept).string()});
  const auto hijack = PlotRows(kept / "plot_0.dat");
  ASSERT_EQ(hijack.at("systematic").size(), 2U);
  ASSERT_EQ(hijack.at("charged").size(), 2U);
  for (const auto& [label, rows] : hijack) {
    for (const auto& row : rows) {
      EXPECT_GE(row[2], 0.0) << label;
      EXPECT_LE(row[3], 1.0) << label;
      EXPECT_LE(row[2], row[1]) << label;
      EXPECT_GE(row[3], row[1]) << label;
    }
  }
  // Rows go left to right: x = 100, then 1000. Six significant digits.
  const auto& sys = hijack.at("systematic");
  EXPECT_NEAR(sys[0][2], 0.722467, 1e-6);
  EXPECT_NEAR(sys[0][3], 1.0, 1e-6);
  EXPECT_NEAR(sys[1][1], 0.5, 1e-9);
  EXPECT_NEAR(sys[1][2], 0.198979, 1e-6);
  EXPECT_NEAR(sys[1][3], 0.801021, 1e-6);
  for (const auto& row : hijack.at("charged")) {
    EXPECT_EQ(row[1], 0.0);
    EXPECT_EQ(row[2], 0.0);
    EXPECT_NEAR(row[3], 0.277533, 1e-6);  // a band at 0, where t would have none
  }
  const auto mota = PlotRows(kept / "plot_1.dat");
  EXPECT_NEAR(mota.at("charged")[1][1], 0.95, 1e-9);
  EXPECT_NEAR(mota.at("charged")[1][2], 0.95 - 0.113100, 1e-6);
  EXPECT_EQ(mota.at("charged")[1][3], 1.0);
  const std::string html = Read(r.html_path);
  EXPECT_NE(html.find("0.95 [0.8369, 1]&dagger;"), std::string::npos) << "cut, and marked";
  EXPECT_NE(html.find("0.5 [0.199, 0.801]&nbsp;W"), std::string::npos) << "Wilson, marked";
  EXPECT_NE(html.find("95% Wilson CI"), std::string::npos) << "the hijack plot's axis says so";
  // summary.csv: mean, lo95, hi95, n.
  const std::string csv = Read(r.csv_path);
  EXPECT_NE(csv.find("hijack_rate_mean,hijack_rate_lo95,hijack_rate_hi95,hijack_rate_n"),
            std::string::npos);
  EXPECT_NE(csv.find(",0.5,0.198979,0.801021,10,"), std::string::npos) << csv;
}

// Puts `runs` hand-made runs into a store of `meta` at `dir`: run i has
// the swept values `values(i)`, seed index i % `seeds` (its seed derived from
// root seed 1) and mota `mota(i)`, and a folder.
void PutHandRuns(const fs::path& dir, const StoreMeta& meta, int64_t runs, int seeds,
                 const std::function<std::vector<std::string>(int64_t)>& values,
                 const std::function<double(int64_t)>& mota) {
  auto store = ResultsStore::OpenOrCreate((dir / "results.sqlite").string(), meta);
  for (int64_t i = 0; i < runs; ++i) {
    const int seed_index = static_cast<int>(i % seeds);
    RunRecord r =
        HandRun(dir, fmt::format("run-{}", i), i, seed_index, SweepSeed(1, seed_index), values(i));
    r.metrics["mota"] = mota(i);
    store->Put(r);
  }
}

// A series zipped one to one with x has no two series at one x: nothing is
// compared. The report compared charged at 100 particles with systematic at
// 50 and filed it under 100 (an audit of valid input: "no significant
// difference at tracker.particles = 100", where no systematic run was).
TEST(Report, ASeriesZippedWithXComparesNothingAcrossX) {
  const auto dir = testing::SweepFolder("report-series-zipped-with-x");
  StoreMeta meta = HandMeta({"tracker.particles", "tracker.resampling.method"},
                            "tracker.resampling.method", {"mota"}, 6);
  StoredExpansion zip;
  zip.zip = {{"tracker.particles", {"50", "100"}},
             {"tracker.resampling.method", {"systematic", "charged"}}};
  zip.seeds = 3;
  RecordExpansion(&meta, zip);
  PutHandRuns(
      dir, meta, 6, 3, [&zip](int64_t i) { return zip.Values(i); },
      [](int64_t i) { return i < 3 ? 0.5 : 0.9; });
  const ReportResult r = WriteReport({.dir = dir.string()});
  EXPECT_EQ(r.cells, 2);
  EXPECT_EQ(r.comparisons, 0);
  const std::string findings = Read(dir / "findings.md");
  EXPECT_EQ(findings.find("charged − systematic"), std::string::npos) << findings;
  EXPECT_NE(findings.find("This report tests no comparison: no cell has a partner, a cell of "
                          "tracker.resampling.method = systematic at its tracker.particles (each "
                          "tracker.resampling.method value is swept at other values of them: "
                          "zipped with them one to one)."),
            std::string::npos)
      << findings;
}

// --against a store of the same swept keys listed in another order (its
// sweep file's grid written the other way round): its runs are read in
// this store's order, and the comparisons are made again (an audit of valid
// input: refused, exit 2). Here HandStore's mota values, keys swapped.
TEST(Report, AgainstTheSameKeysInAnotherOrderReplicates) {
  const fs::path here = HandStore("report-against-order");
  const auto dir = testing::SweepFolder("report-against-order-there");
  StoreMeta meta = HandMeta({"tracker.resampling.method", "tracker.particles"},
                            "tracker.resampling.method", {"mota"}, 40);
  meta.report.x = "tracker.particles";
  PutHandRuns(
      dir, meta, 40, 10,
      [](int64_t i) {
        return std::vector<std::string>{(i / 10) % 2 == 0 ? "systematic" : "charged",
                                        i < 20 ? "100" : "1000"};
      },
      [](int64_t i) {
        const bool charged = (i / 10) % 2 == 1, many = i >= 20;
        return !charged ? 0.9 : (many ? (i % 10 < 9 ? 1.0 : 0.5) : 0.9);
      });
  const ReportResult r = WriteReport({.dir = here.string(), .against = dir.string()});
  // mota, charged − systematic at 1000 (at 100 every pair ties in both: no
  // outcome to compare).
  EXPECT_EQ(r.replication_comparisons, 1);
  EXPECT_EQ(r.replication_cells, 4);  // mota's four cell means (hijack_rate: none there)
}

// A store whose sweep file writes the same values otherwise (2.0 and 3e0
// for 2 and 3) is read in this store's spelling, so its cells meet these
// (an audit of valid input: no comparison and no cell matched). Whole
// numbers compare exactly: two seeds past 2^53 that round to one double are
// two values (a review: they were merged).
TEST(Report, AgainstAStoreSpellingItsValuesOtherwiseReplicates) {
  // key {a, b} x method {systematic, charged} x 10 seeds; mota: charged at b
  // 1.0 on nine seeds and 0.5 on the tenth, 0.9 elsewhere (a finding at b
  // only).
  const auto store = [](const std::string& name, const std::string& key, const std::string& a,
                        const std::string& b, const std::string& resolved = "") {
    const auto dir = testing::SweepFolder(name);
    StoreMeta meta =
        HandMeta({key, "tracker.resampling.method"}, "tracker.resampling.method", {"mota"}, 40);
    if (!resolved.empty()) meta.base_resolved = resolved;
    PutHandRuns(
        dir, meta, 40, 10,
        [a, b](int64_t i) {
          return std::vector<std::string>{i < 20 ? a : b,
                                          (i / 10) % 2 == 0 ? "systematic" : "charged"};
        },
        [](int64_t i) {
          const bool charged = (i / 10) % 2 == 1, second = i >= 20;
          return !charged ? 0.9 : (second ? (i % 10 < 9 ? 1.0 : 0.5) : 0.9);
        });
    return dir;
  };
  const std::string sigma = "tracker.likelihood.sigma_px";
  const fs::path here = store("report-against-spelling", sigma, "2", "3");
  const fs::path there = store("report-against-spelling-there", sigma, "2.0", "+3e0");
  const ReportResult r = WriteReport({.dir = here.string(), .against = there.string()});
  EXPECT_EQ(r.replication_comparisons, 1);  // mota, charged − systematic at 3
  EXPECT_EQ(r.replication_cells, 4);
  // The values read in this store's spelling are listed in the Replication
  // section. No resolved scenario here holds the key (a hand-made base, no
  // run folder's file): read as numbers, which the line says.
  EXPECT_NE(Read(r.html_path)
                .find("<li>" + there.string() + "'s " + sigma +
                      " = +3e0 read as 3 (the same value as numbers: neither this store's base "
                      "nor the 0 run files read here holds " +
                      sigma + ", so whether it takes text is not known)</li>"),
            std::string::npos);
  // A base that holds it as a number.
  const std::string numeric = "seed: 5\nframes: 10\ntracker:\n  likelihood:\n    sigma_px: 2\n";
  const ReportResult n = WriteReport(
      {.dir = store("report-against-numbers", sigma, "2", "3", numeric).string(),
       .against = store("report-against-numbers-there", sigma, "2.0", "+3e0", numeric).string()});
  EXPECT_EQ(n.replication_comparisons, 1);
  EXPECT_NE(Read(n.html_path).find("= +3e0 read as 3 (the same value)</li>"), std::string::npos);

  // A key that takes text (quoted in the resolved base scenario): 1.10 and
  // 1.1 are two names, so only the cells at 2 meet (a review).
  const std::string resolved = "name: \"x\"\nseed: 5\nframes: 10\n";
  const ReportResult t = WriteReport(
      {.dir = store("report-against-text", "name", "1.1", "2", resolved).string(),
       .against = store("report-against-text-there", "name", "1.10", "2", resolved).string()});
  EXPECT_EQ(t.replication_comparisons, 1);  // mota, charged − systematic at 2
  EXPECT_EQ(t.replication_cells, 2);
  // An optional path, which the resolved base leaves out where it is not
  // set: read from the runs' resolved scenarios, which quote it (a review:
  // its values were compared as numbers, 1.1 and 1.10 one model).
  const std::string model = "targets.0.model";
  const std::string no_model = "seed: 5\nframes: 10\ntargets:\n  - id: 1\n";
  const auto with_models = [&](const std::string& name, const std::string& a) {
    const fs::path dir = store(name, model, a, "2", no_model);
    // Every run's file quotes a model (which one is not read here).
    for (const auto& run : fs::directory_iterator(dir / "runs")) {
      std::ofstream(run.path() / "scenario.resolved.yaml")
          << "seed: 5\nframes: 10\ntargets:\n  - id: 1\n    model: \"" << a << "\"\n";
    }
    return dir;
  };
  const ReportResult m =
      WriteReport({.dir = with_models("report-against-model", "1.1").string(),
                   .against = with_models("report-against-model-there", "1.10").string()});
  EXPECT_EQ(m.replication_comparisons, 1);  // mota, charged − systematic at 2
  EXPECT_EQ(m.replication_cells, 2);
  // Only the runs at 1.1 name a model, and the first of them is damaged:
  // the next is read (a review: a damaged file counted as read, so 1.1's
  // other runs were not, and 1.1 and 1.10 were compared as numbers).
  const auto first_damaged = [&](const std::string& name, const std::string& a) {
    const fs::path dir = store(name, model, a, "2", no_model);
    for (int i = 0; i < 40; ++i) {
      std::ofstream file(dir / "runs" / fmt::format("run-{}", i) / "scenario.resolved.yaml");
      file << "seed: 5\nframes: 10\ntargets:\n  - id: 1\n";
      if (i == 0) file << "    model: [\"" << a << "\"\n";  // not YAML
      if (i > 0 && i < 20) file << "    model: \"" << a << "\"\n";
    }
    return dir;
  };
  const ReportResult f =
      WriteReport({.dir = first_damaged("report-against-damaged", "1.1").string(),
                   .against = first_damaged("report-against-damaged-there", "1.10").string()});
  EXPECT_EQ(f.replication_cells, 2);

  const std::string seed = "seeds.world";
  const fs::path big = store("report-against-big-seeds", seed, "1000", "18446744073709551614");
  const fs::path other =
      store("report-against-big-seeds-there", seed, "1000", "18446744073709551615");
  const ReportResult o = WriteReport({.dir = big.string(), .against = other.string()});
  EXPECT_EQ(o.replication_comparisons, 0);  // only the cells at 1000 meet, every pair tied
  EXPECT_EQ(o.replication_cells, 2);
}

// grid.base paths written otherwise in the other sweep file (absolute for
// relative) whose resolved scenarios are the same are the same cells; a
// base whose resolved scenario differs is not.
TEST(Report, AgainstAStoreNamingTheSameBasesOtherwiseReplicates) {
  // `reversed`: the other sweep file lists its keys the other way round
  // (its expansion is then dropped; the bases' texts were read from it:
  // a review found them lost).
  const auto store = [](const std::string& name, const std::string& a, const std::string& b,
                        const std::string& b_text, bool reversed = false) {
    const auto dir = testing::SweepFolder(name);
    const std::string method = "tracker.resampling.method";
    StoreMeta meta = HandMeta(reversed ? std::vector<std::string>{method, "base"}
                                       : std::vector<std::string>{"base", method},
                              method, {"mota"}, 40);
    meta.report.x = "base";
    StoredExpansion grid;
    grid.grid = {{"base", {a, b}}, {method, {"systematic", "charged"}}};
    if (reversed) std::swap(grid.grid[0], grid.grid[1]);
    grid.seeds = 10;
    RecordExpansion(&meta, grid);
    meta.base_resolved = "# base: " + a + "\nseed: 5\nframes: 10\n# base: " + b + "\n" + b_text;
    // Run i: base i / 20, method (i / 10) % 2, seed i % 10 (reversed: method
    // i / 20, base (i / 10) % 2); mota: charged on b 1.0 on nine seeds and
    // 0.5 on the tenth, 0.9 elsewhere.
    PutHandRuns(
        dir, meta, 40, 10,
        [a, b, reversed](int64_t i) {
          const bool second = reversed ? (i / 10) % 2 == 1 : i >= 20;
          const bool charged = reversed ? i >= 20 : (i / 10) % 2 == 1;
          const std::string base = second ? b : a, m = charged ? "charged" : "systematic";
          return reversed ? std::vector<std::string>{m, base} : std::vector<std::string>{base, m};
        },
        [reversed](int64_t i) {
          const bool second = reversed ? (i / 10) % 2 == 1 : i >= 20;
          const bool charged = reversed ? i >= 20 : (i / 10) % 2 == 1;
          return !charged ? 0.9 : (second ? (i % 10 < 9 ? 1.0 : 0.5) : 0.9);
        });
    return dir;
  };
  const std::string b_text = "seed: 6\nframes: 20\n";
  const fs::path here = store("report-against-bases", "a.yaml", "b.yaml", b_text);
  const fs::path there =
      store("report-against-bases-there", "/elsewhere/a.yaml", "/elsewhere/b.yaml", b_text);
  const ReportResult r = WriteReport({.dir = here.string(), .against = there.string()});
  EXPECT_EQ(r.replication_comparisons, 1);  // mota, charged − systematic on b
  EXPECT_EQ(r.replication_cells, 4);
  const fs::path reversed = store("report-against-bases-reversed", "/elsewhere/a.yaml",
                                  "/elsewhere/b.yaml", b_text, true);
  const ReportResult v = WriteReport({.dir = here.string(), .against = reversed.string()});
  EXPECT_EQ(v.replication_comparisons, 1);
  EXPECT_EQ(v.replication_cells, 4);
  // b's scenario differs there (frames 30): only a's two cells meet.
  const fs::path other = store("report-against-bases-other", "/elsewhere/a.yaml",
                               "/elsewhere/b.yaml", "seed: 6\nframes: 30\n");
  const ReportResult o = WriteReport({.dir = here.string(), .against = other.string()});
  EXPECT_EQ(o.replication_comparisons, 0);
  EXPECT_EQ(o.replication_cells, 2);
}

// A store that holds no run yet (an empty shard) names the sweep's swept
// values from its expansion, and set against another store says why nothing
// is compared again (an audit of valid input: "frames = ; tracker.particles
// = " and "without report.series", though the store's report names one).
TEST(Report, AStoreWithoutRunsNamesItsSweepsValues) {
  const auto dir = testing::SweepFolder("report-no-runs");
  StoreMeta meta = HandMeta({"tracker.particles", "tracker.resampling.method"},
                            "tracker.resampling.method", {"mota"}, 40);
  StoredExpansion grid;
  grid.grid = {{"tracker.particles", {"100", "1000"}},
               {"tracker.resampling.method", {"systematic", "charged"}}};
  grid.seeds = 10;
  RecordExpansion(&meta, grid);
  ResultsStore::OpenOrCreate((dir / "results.sqlite").string(), meta);
  const fs::path there = HandStore("report-no-runs-there");
  const ReportResult r = WriteReport({.dir = dir.string(), .against = there.string()});
  const std::string html = Read(r.html_path);
  EXPECT_NE(html.find("Every run replaces 2 keys: <code>tracker.particles</code> = 100, 1000; "
                      "<code>tracker.resampling.method</code> = systematic, charged."),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("this store holds no finished run, so there are no paired comparisons to "
                      "make again"),
            std::string::npos);
  EXPECT_EQ(html.find("without <code>report.series</code>"), std::string::npos);
}

// Values that differ only past the six significant digits the y range is
// written with (a similarity floor of 0.0656259... px over seeds) get a
// range of two numbers: it was [0.065626:0.065626], which gnuplot refuses
// ("empty y range"), and the report failed (an audit of valid input).
TEST(Report, NearlyEqualValuesStillGetAYRange) {
  const auto dir = testing::SweepFolder("report-near-equal");
  const StoreMeta meta = HandMeta({"tracker.particles"}, "", {"mota"}, 6);
  PutHandRuns(
      dir, meta, 6, 3, [](int64_t i) { return std::vector<std::string>{i < 3 ? "20" : "40"}; },
      [](int64_t i) { return 0.0656259790 + 1e-9 * static_cast<double>(i); });
  const fs::path kept = dir / "kept";
  WriteReport({.dir = dir.string(), .gnuplot = KeepingGnuplot(dir, kept).string()});
  const std::string gp = Read(kept / "plot_0.gp");
  double lo = 0.0, hi = 0.0;
  const size_t at = gp.find("set yrange [");
  ASSERT_NE(at, std::string::npos) << gp;
  ASSERT_EQ(std::sscanf(gp.c_str() + at, "set yrange [%lf:%lf]", &lo, &hi), 2) << gp;
  // 0.05 % of 0.065626 (3.28e-5) on each side, to six digits: [0.0655932,
  // 0.0656588].
  EXPECT_NEAR(lo, 0.0655932, 1e-9);
  EXPECT_NEAR(hi, 0.0656588, 1e-9);
}

// Swept values on a category x axis are drawn as written: gnuplot's
// enhanced text took the underscore of detections_mixture, a shipped
// likelihood model, for a subscript (an audit of valid input).
TEST(Report, CategoryTicsAreDrawnAsWritten) {
  const auto dir = testing::SweepFolder("report-category-tics");
  const StoreMeta meta = HandMeta({"tracker.likelihood.model"}, "", {"mota"}, 4);
  PutHandRuns(
      dir, meta, 4, 2,
      [](int64_t i) { return std::vector<std::string>{i < 2 ? "detections_mixture" : "x&y^2"}; },
      [](int64_t i) { return 0.5 + 0.1 * static_cast<double>(i); });
  const std::string html = Read(WriteReport({.dir = dir.string()}).html_path);
  const size_t plot = html.find("<svg");
  ASSERT_NE(plot, std::string::npos);
  const std::string svg = html.substr(plot, html.find("</svg>", plot) - plot);
  EXPECT_NE(svg.find(">detections_mixture<"), std::string::npos) << svg;
  EXPECT_NE(svg.find(">x&amp;y^2<"), std::string::npos) << svg;
}

// Every run's value is drawn behind a plot's means (an audit: a cell of
// IDF1 0.953 [0.91, 1.0] was most seeds at 1 and a few far below, which a
// mean and its interval cannot show), spread sideways so the two lines'
// seeds do not fall on each other; the x axis has tics at the swept values
// and ends just past them (it ran from 10 to 10000 for 50 to 5000). On the
// hand store, log x at 100 and 1000: gap ln 10 = 2.302585, strip half of it
// but at most 2 ln 1.3 = 0.524729 on a log axis, two lines: line 0's slot
// centred at −0.131182, line 1's at +0.131182, each 0.8 · 0.524729 / 2 =
// 0.209891 wide; seed k of 10 at centre + ((k + 0.5)/10 − 0.5) · 0.209891:
// line 0, seed 0 at 100 · e^−0.225633 = 79.8011 and seed 9 at 100 ·
// e^−0.036731 = 96.3935; line 1, seed 0 at 100 · e^0.036731 = 103.741, seed 9
// at 1000 · e^0.225633 = 1253.12: inside the x range [100/1.4, 1000 · 1.4].
// (A review found the uncapped strip put points at 60.95 and 1640, outside.)
TEST(Report, APlotOfMeansDrawsEveryRunsValueBesideItsCell) {
  const fs::path dir = HandStore("report-seed-points");
  const fs::path kept = dir / "kept";
  WriteReport({.dir = dir.string(), .gnuplot = KeepingGnuplot(dir, kept).string()});
  // plot_1: mota. Blocks: systematic, then charged; 20 rows each (2 x × 10 seeds).
  const std::string text = Read(kept / "plot_1_seeds.dat");
  std::vector<std::vector<std::array<double, 2>>> blocks(1);
  std::stringstream lines(text);
  std::string line;
  int blank = 0;
  while (std::getline(lines, line)) {
    if (line.empty()) {
      if (++blank == 2 && !blocks.back().empty()) blocks.emplace_back();
      continue;
    }
    blank = 0;
    std::array<double, 2> r{};
    std::stringstream(line) >> r[0] >> r[1];
    blocks.back().push_back(r);
  }
  if (blocks.back().empty()) blocks.pop_back();
  ASSERT_EQ(blocks.size(), 2U) << text;
  ASSERT_EQ(blocks[0].size(), 20U) << text;
  ASSERT_EQ(blocks[1].size(), 20U) << text;
  EXPECT_NEAR(blocks[0][0][0], 79.8011, 1e-3);
  EXPECT_NEAR(blocks[0][9][0], 96.3935, 1e-3);
  EXPECT_NEAR(blocks[1][0][0], 103.741, 1e-3);
  EXPECT_NEAR(blocks[1][19][0], 1253.12, 1e-2);
  for (const auto& block : blocks) {
    for (const auto& r : block) {
      EXPECT_GT(r[0], 100.0 / 1.4);
      EXPECT_LT(r[0], 1000.0 * 1.4);
    }
  }
  // The values: systematic 0.9 everywhere; charged 0.9 at 100, then at
  // 1000 1.0 on seeds 0–8 and 0.5 on seed 9 (outside its cell's band
  // [0.837, 1]).
  for (const auto& r : blocks[0]) EXPECT_EQ(r[1], 0.9);
  EXPECT_EQ(blocks[1][9][1], 0.9);
  EXPECT_EQ(blocks[1][10][1], 1.0);
  EXPECT_EQ(blocks[1][19][1], 0.5);
  EXPECT_GT(blocks[1][19][0], 1000.0);  // line 1 right of its x
  const std::string gp = Read(kept / "plot_1.gp");
  // The y axis reaches the seed at 0.5 (0.5 − 0.04 · 0.5 = 0.48), the
  // points are drawn first and have one key entry.
  EXPECT_NE(gp.find("set yrange [0.48:1.02]"), std::string::npos) << gp;
  EXPECT_LT(gp.find("plot_1_seeds.dat"), gp.find("filledcurves")) << gp;
  EXPECT_NE(gp.find("title 'one run (seed)'"), std::string::npos) << gp;
  EXPECT_NE(gp.find("set xrange [71.4286:1400]"), std::string::npos) << gp;
  EXPECT_NE(gp.find("set xtics ('100' 100, '1000' 1000) noenhanced"), std::string::npos) << gp;
}

// Paired differences, charged − systematic (the sweep's report.reference),
// by hand. hijack_rate at 100: d = −1 on all 10 seeds: mean −1, s = 0, the
// interval [−1, −1]; signed-rank: 10 nonzero, all negative, one tie group
// (ranks 5.5), W+ = 0, exact P(W+ <= 0) = 1/1024, p = 2/1024 = 0.001953.
// At 1000: d = −1 on seeds 0–4, 0 on 5–9: mean −0.5, s = √(2.5/9), s/√10 =
// √(2.5/90) = 1/6, half-width 2.262 / 6 = 0.377; 5 nonzero, W+ = 0,
// p = 2/32 = 0.0625. mota at 1000: d = 0.1 on seeds 0–8, −0.4 on seed 9:
// mean 0.05; 9 positive, 1 negative; ranks: the nine 0.1s share 5, the −0.4
// has 10: W+ = 45. Under the sign flips W+ = 5k + 10b (k of the nine 5s and
// b of the 10 positive): W+ >= 45 for b = 1, k >= 7 (36 + 9 + 1) and for
// b = 0, k = 9 (1): 47 of 1024, p = 94/1024 = 0.091797.
TEST(Report, PairedDifferencesByHand) {
  const fs::path dir = HandStore("report-paired");
  const fs::path kept = dir / "kept";
  const ReportResult r =
      WriteReport({.dir = dir.string(), .gnuplot = KeepingGnuplot(dir, kept).string()});
  EXPECT_EQ(r.comparisons, 2);
  EXPECT_EQ(r.difference_plots, 2);
  const auto rows = CsvRows(dir / "paired.csv");
  ASSERT_EQ(rows.size(), 4U);  // 2 x values × 2 metrics
  // Columns: particles, method, reference, metric, pairs, mean_difference,
  // lo95, hi95, clipped, positive, negative, ties, nonzero, w_plus, p_value, exact,
  // p_holm.
  const auto row_of = [&](const std::string& x, const std::string& metric) {
    for (const auto& row : rows) {
      if (row[0] == x && row[3] == metric) return row;
    }
    ADD_FAILURE() << x << " " << metric;
    return std::vector<std::string>(17);
  };
  auto row = row_of("100", "hijack_rate");
  EXPECT_EQ(row[1], "charged");
  EXPECT_EQ(row[2], "systematic");
  EXPECT_EQ(row[4], "10");
  EXPECT_EQ(std::stod(row[5]), -1.0);
  EXPECT_EQ(std::stod(row[6]), -1.0);
  EXPECT_EQ(std::stod(row[7]), -1.0);
  EXPECT_EQ(row[10], "10");            // negative
  EXPECT_EQ(row[12], "10");            // nonzero
  EXPECT_EQ(std::stod(row[13]), 0.0);  // W+
  EXPECT_NEAR(std::stod(row[14]), 2.0 / 1024.0, 1e-6);
  row = row_of("1000", "hijack_rate");
  EXPECT_NEAR(std::stod(row[5]), -0.5, 1e-9);
  EXPECT_NEAR(std::stod(row[6]), -0.5 - 0.377, 1e-6);
  EXPECT_NEAR(std::stod(row[7]), -0.5 + 0.377, 1e-6);
  EXPECT_EQ(row[11], "5");  // ties (zero differences)
  EXPECT_EQ(row[12], "5");  // nonzero
  row = row_of("1000", "mota");
  EXPECT_NEAR(std::stod(row[5]), 0.05, 1e-9);
  EXPECT_EQ(row[9], "9");
  EXPECT_EQ(row[10], "1");
  EXPECT_EQ(std::stod(row[13]), 45.0);
  EXPECT_NEAR(std::stod(row[14]), 94.0 / 1024.0, 1e-6);
  EXPECT_EQ(row[15], "1");
  EXPECT_NEAR(std::stod(row_of("1000", "hijack_rate")[14]), 0.0625, 1e-9);
  // mota at 100: d = 0 on every seed (0.9 both), not tested: no p, no Holm
  // p, outside the family. The other 3 are tested, sorted p 2/1024,
  // 0.0625, 94/1024, whose p cannot fall below 2/1024, 2/32 (hijack_rate at
  // 1000: 5 nonzero) and 2/1024. Holm with Tarone's rule: step 1, below
  // 0.05 / 1 two floors, below 0.05 / 2 two: K = 2, 4/1024 = 0.003906; step
  // 2 (2/32, 2/1024 left): below 0.05 one: K = 1, 0.0625; step 3: K = 1,
  // 0.091797. (Holm alone: 6/1024, 0.125, 0.125.)
  EXPECT_EQ(row_of("100", "mota")[12], "0");
  EXPECT_EQ(row_of("100", "mota")[14], "");
  EXPECT_EQ(row_of("100", "mota")[16], "");
  EXPECT_NEAR(std::stod(row_of("100", "hijack_rate")[16]), 4.0 / 1024.0, 1e-6);
  EXPECT_NEAR(std::stod(row_of("1000", "hijack_rate")[16]), 0.0625, 1e-6);
  EXPECT_NEAR(std::stod(row_of("1000", "mota")[16]), 94.0 / 1024.0, 1e-6);

  const std::string html = Read(r.html_path);
  EXPECT_NE(html.find("<h2 id=\"paired\">Paired differences</h2>"), std::string::npos);
  EXPECT_NE(html.find("charged &minus; systematic</td><td>10</td>"), std::string::npos);
  EXPECT_NE(html.find("p&nbsp;=&nbsp;0.002, <b>Holm&nbsp;0.004</b>"), std::string::npos);
  EXPECT_NE(html.find("over the 3 comparisons of this table"), std::string::npos);
  // The first step's level with K = 2 is p < 0.025: 7 nonzero differences
  // (2/128 = 0.0156; 6 give 0.03125).
  EXPECT_NE(html.find("Of the 3 comparisons, 2 can reach p &lt; 0.025, the first step's level "
                      "(Tarone's rule: K = 2, the smallest k with at most k comparisons whose p "
                      "can fall below 0.05 / k; docs/sweeps.md, &quot;Holm's correction&quot;). "
                      "The other one cannot, whatever the data: 1 with enough seed pairs but "
                      "fewer than 7 where the two differ (a tied seed leaves the signed-rank "
                      "test). It cannot be kept at any step."),
            std::string::npos)
      << html;
  EXPECT_NE(html.find(" 1 comparison (mota) has the same value in every seed pair"),
            std::string::npos);
  // Lower hijack rate is better: significant and negative → green.
  EXPECT_NE(html.find("style=\"background:#dff3df\">&Delta;&nbsp;-1<br><span class=\"i\">[-1, "
                      "-1]</span>"),
            std::string::npos);
  // The difference plots ring the findings: hijack_rate's at 100 is one
  // and Holm keeps it (0.0059): an open square there, no open circle; mota
  // has none, so its plot has neither. No per-run points on a difference plot.
  EXPECT_EQ(Read(kept / "plot_d0_findings.dat"), "nan nan\n\n\n100 -1\n\n\n");
  EXPECT_NE(Read(kept / "plot_d0.gp").find("index 1 using 1:2 with points pt 4"),
            std::string::npos);
  EXPECT_EQ(Read(kept / "plot_d0.gp").find("title 'finding'"), std::string::npos);
  EXPECT_EQ(Read(kept / "plot_d1.gp").find("_findings.dat"), std::string::npos);
  EXPECT_FALSE(fs::exists(kept / "plot_d0_seeds.dat"));
  // The difference plots: a line "charged − systematic" and a zero line.
  const auto diff = PlotRows(kept / "plot_d0.dat");
  ASSERT_EQ(diff.size(), 1U);
  EXPECT_EQ(diff.begin()->first, "charged \u2212 systematic");
  EXPECT_NEAR(diff.begin()->second[1][1], -0.5, 1e-9);
  const size_t at = html.find("id=\"difference-hijack_rate\"");
  ASSERT_NE(at, std::string::npos);
  EXPECT_NE(html.substr(at, html.find("</svg>", at) - at).find("paired difference against"),
            std::string::npos);

  // Determinism: the same store gives the same bytes.
  const std::string csv = Read(r.csv_path), paired = Read(dir / "paired.csv");
  const ReportResult again = WriteReport({.dir = dir.string()});
  EXPECT_EQ(Read(again.html_path), html);
  EXPECT_EQ(Read(again.csv_path), csv);
  EXPECT_EQ(Read(dir / "paired.csv"), paired);
}

// The scene from above, by hand: a camera whose image is the ground at 10
// px per metre, north up, centred on (0, 0) at frames 0 and 1 and on (5, 0)
// at frame 2 (u = 10 (x − cx) + 320, v = −10 y + 240). Its 640 × 480 image
// sees x ∈ [−32, 32], y ∈ [−24, 24]: the first footprint; the middle (frame
// 1) is the same and left out; the last is 5 m east. Targets 1 and 2: their
// boxes apart at frame 0, overlapping at frames 1 and 2; target 2 half
// visible at frame 1.
TEST(SceneSketch, FootprintsPathsAndEncountersByHand) {
  metrics::GroundTruthFile gt;
  for (int f = 0; f < 3; ++f) {
    FrameGroundTruth frame;
    frame.frame = f;
    frame.camera.intrinsics.width_px = 640;
    frame.camera.intrinsics.height_px = 480;
    const double cx = f == 2 ? 5.0 : 0.0;
    frame.image_from_ground << 10, 0, 320 - 10 * cx, 0, -10, 240, 0, 0, 1;
    GroundTruthObject a, b;
    a.id = ObjectId{1};
    b.id = ObjectId{2};
    a.in_frame = b.in_frame = true;
    a.position_m = Eigen::Vector3d(-10.0 + f, 0.0, 0.0);
    b.position_m = Eigen::Vector3d(0.0, -5.0 + f, 0.0);
    a.amodal_box = {110.0 + 30.0 * f, 100.0, 40.0, 20.0};  // x from 110, 140, 170
    b.amodal_box = {160.0, 100.0, 20.0, 40.0};             // x from 160 to 180
    a.visible_fraction = 1.0;
    b.visible_fraction = f == 1 ? 0.5 : 1.0;
    frame.objects = {a, b};
    gt.frames.push_back(frame);
  }
  const SceneSketch sketch = SketchOf(gt);
  EXPECT_EQ(sketch.frames, 3);
  ASSERT_EQ(sketch.paths.size(), 2U);
  EXPECT_EQ(sketch.paths[0].id, 1);
  ASSERT_EQ(sketch.paths[1].points.size(), 3U);
  EXPECT_EQ(sketch.paths[1].points[2].y_m, -3.0);
  EXPECT_EQ(sketch.paths[1].points[1].visible_fraction, 0.5);
  ASSERT_EQ(sketch.footprints.size(), 2U);
  EXPECT_EQ(sketch.footprints[0].frame, 0);
  EXPECT_EQ(sketch.footprints[1].frame, 2);
  const std::vector<std::pair<double, double>> first = {{-32, 24}, {32, 24}, {32, -24}, {-32, -24}};
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_NEAR(sketch.footprints[0].corners[i].first, first[i].first, 1e-9) << i;
    EXPECT_NEAR(sketch.footprints[0].corners[i].second, first[i].second, 1e-9) << i;
    EXPECT_NEAR(sketch.footprints[1].corners[i].first, first[i].first + 5.0, 1e-9) << i;
  }
  ASSERT_EQ(sketch.encounters.size(), 1U);
  EXPECT_EQ(sketch.encounters[0].frames, (std::vector<int>{1, 2}));
  EXPECT_EQ(EncounterText(sketch),
            "targets 1 and 2: boxes overlap in the image in frames 2\u20133");
  // The drawing: target 2's frame below 0.75 visible is ringed.
  const fs::path work = testing::SweepFolder("scene-sketch");
  const std::string svg = SceneSketchSvg(sketch, "hand", work, "gnuplot", "t");
  EXPECT_NE(svg.find("<svg"), std::string::npos);
  const std::string dat = Read(work / "sketch_t.dat");
  // Blocks: target 1's path, dots, rings; target 2's; two footprints.
  EXPECT_NE(dat.find("\n\n\n0 -4\n\n\n"), std::string::npos) << dat;  // target 2, frame 1
  EXPECT_NE(Read(work / "sketch_t.gp").find("title 'camera view, frame 3'"), std::string::npos);
}

// A store of 10 seeds of {systematic, charged} at one particle count, with
// report.y `y` and each run's metrics `values(method, seed)`.
fs::path TwoMethodStore(
    const std::string& name, const std::vector<std::string>& y,
    const std::function<std::map<std::string, double>(const std::string&, int)>& values) {
  const auto dir = testing::SweepFolder(name);
  StoreMeta meta;
  meta.sweep_hash = name;
  meta.sweep_file = name + ".yaml";
  meta.swept_keys = {"tracker.particles", "tracker.resampling.method"};
  meta.report.x = "tracker.particles";
  meta.report.series = "tracker.resampling.method";
  meta.report.y = y;
  meta.report.reference = "systematic";
  meta.run_count = 20;
  auto store = ResultsStore::OpenOrCreate((dir / "results.sqlite").string(), meta);
  int64_t index = 0;
  for (const char* method : {"systematic", "charged"}) {
    for (int seed = 0; seed < 10; ++seed) {
      RunRecord r = HandRun(dir, std::string("1-") + method + "-" + std::to_string(seed), index++,
                            seed, 2000 + seed, {"1", method});
      for (const auto& [metric, value] : values(method, seed)) r.metrics[metric] = value;
      store->Put(r);
    }
  }
  return dir;
}

// The seed pairs behind each finding (paired.csv's extreme columns and the
// report's "Seeds to look at"), on the hand store and on a store of one
// cell pair, 10 seeds, whose MOTA is charged 0.8 against systematic 0.5 on
// seeds 0–8 and 0.4 against 0.5 on seed 9: differences 0.3 nine times and
// −0.1 once (W− = 1, p = 4/1024; mean 0.26, t interval [0.17, 0.35]), a
// finding with one seed against it. Its folder has a space, so the commands
// quote their paths.
TEST(Report, SeedsToLookAtNameTheFurthestAndTheLeastFarPairOfEachFinding) {
  const fs::path hand = HandStore("report-seeds-hand");
  WriteReport({.dir = hand.string()});
  const auto rows = CsvRows(hand / "paired.csv");
  ASSERT_EQ(rows.size(), 4U);
  const auto row_of = [&](const std::string& x, const std::string& metric) {
    for (const auto& row : rows) {
      if (row[0] == x && row[3] == metric) return row;
    }
    ADD_FAILURE() << x << " " << metric;
    return std::vector<std::string>(23);
  };
  // Columns 17–22: max_difference, max_run, max_reference_run, min_difference,
  // min_run, min_reference_run; the first seed that reaches each.
  auto row = row_of("1000", "mota");
  ASSERT_EQ(row.size(), 23U);
  EXPECT_NEAR(std::stod(row[17]), 0.1, 1e-12);
  EXPECT_EQ(row[18], "1000-charged-0");
  EXPECT_EQ(row[19], "1000-systematic-0");
  EXPECT_NEAR(std::stod(row[20]), -0.4, 1e-12);
  EXPECT_EQ(row[21], "1000-charged-9");
  EXPECT_EQ(row[22], "1000-systematic-9");
  row = row_of("1000", "hijack_rate");
  EXPECT_EQ(std::stod(row[17]), 0.0);
  EXPECT_EQ(row[18], "1000-charged-5");
  EXPECT_EQ(std::stod(row[20]), -1.0);
  EXPECT_EQ(row[21], "1000-charged-0");
  // The one finding of the hand store: hijack rate at 100, −1 on every seed.
  std::string html = Read(hand / "report.html");
  EXPECT_NE(html.find("for the one coloured cell, the seed"), std::string::npos);
  EXPECT_NE(html.find("(0 of them against it"), std::string::npos);
  // How to see the two runs' videos when they have none.
  EXPECT_NE(html.find("<code>hcpf run RUN/scenario.resolved.yaml --out NEW --video</code> makes "
                      "the same run with one"),
            std::string::npos);
  EXPECT_NE(
      html.find("<a href=\"runs/100-charged-0\">seed index 0</a>: &Delta;&nbsp;-1<br><code>hcpf "
                "report " +
                (hand / "runs" / "100-charged-0").string() + " --against " +
                (hand / "runs" / "100-systematic-0").string() + "</code>"),
      std::string::npos);

  const auto dir = TwoMethodStore(
      "report seeds", {"mota", "ms_per_frame"}, [](const std::string& method, int seed) {
        const bool systematic = method == "systematic";
        // A timing finding (charged slower on every
        // seed): no seed to look at.
        return std::map<std::string, double>{{"mota", systematic ? 0.5 : (seed < 9 ? 0.8 : 0.4)},
                                             {"ms_per_frame", systematic ? 1.0 : 2.0 + 0.1 * seed}};
      });
  WriteReport({.dir = dir.string()});
  html = Read(dir / "report.html");
  // The timing (charged slower on every seed, p = 0.002; differences 1.0 to
  // 1.9, mean 1.45, s = 0.303, t = 2.262: [1.233, 1.667]) is tabled, not
  // tested: not coloured, outside the family (1 comparison, not 2), no
  // finding (an audit found a rendered sweep's run order made one).
  EXPECT_NE(html.find("<td>&Delta;&nbsp;1.45<br><span class=\"i\">[1.23, 1.67]</span><br>10/0/0, "
                      "not tested</td>"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("This report makes 1 comparisons"), std::string::npos);
  EXPECT_NE(html.find("ms_per_frame is plotted and tabled but not tested"), std::string::npos);
  EXPECT_NE(html.find("best mean (lower is better): systematic at every tracker.particles. Not "
                      "tested (a time depends on the machine's load"),
            std::string::npos);
  EXPECT_NE(html.find("for the one coloured cell"), std::string::npos);
  EXPECT_NE(html.find("(1 of them against it"), std::string::npos);
  const std::string quoted = "'" + (dir / "runs").string();
  EXPECT_NE(html.find("seed index 0</a>: &Delta;&nbsp;0.3<br><code>hcpf report " + quoted +
                      "/1-charged-0' --against " + quoted + "/1-systematic-0'</code>"),
            std::string::npos);
  EXPECT_NE(html.find("seed index 9</a>: &Delta;&nbsp;-0.1 <b>(against it)</b>"), std::string::npos)
      << html;
}

// A sweep report whose run folders are gone (runs/ deleted, or results.sqlite
// copied alone) says so on the page, in findings.md and in the log, and
// links to none of them (a bad-input audit: it linked every seed to look at
// and the first run's scenario to folders that were not there).
TEST(Report, RunsWhoseFoldersAreGoneAreNamedNotLinked) {
  const auto dir =
      TwoMethodStore("report-folders-gone", {"mota"}, [](const std::string& method, int seed) {
        return std::map<std::string, double>{
            {"mota", method == "systematic" ? 0.5 : 0.8 - 0.01 * seed}};
      });
  ReportResult r = WriteReport({.dir = dir.string()});
  EXPECT_EQ(r.absent_run_folders, 0);
  std::string html = Read(r.html_path);
  EXPECT_NE(html.find("<a href=\"runs/1-charged-0\">seed index 0</a>"), std::string::npos);
  EXPECT_NE(html.find("/scenario.resolved.yaml</a>"), std::string::npos);
  fs::remove_all(dir / "runs" / "1-systematic-0");
  r = WriteReport({.dir = dir.string()});
  EXPECT_EQ(r.absent_run_folders, 1);
  html = Read(r.html_path);
  const std::string sentence =
      "1 of the 20 finished runs have no folder in <code>" + (dir / "runs").string() +
      "</code> (deleted or moved): their numbers here are the store's, and nothing links to them.";
  EXPECT_NE(html.find(sentence), std::string::npos) << html;
  // The pair of seed 0 (its reference run's folder gone) is named, not linked.
  EXPECT_EQ(html.find("href=\"runs/1-charged-0\""), std::string::npos);
  EXPECT_NE(html.find("seed index 0: &Delta;&nbsp;0.3 (a folder of the pair is gone)"),
            std::string::npos);
  fs::remove_all(dir / "runs");
  r = WriteReport({.dir = dir.string()});
  EXPECT_EQ(r.absent_run_folders, 20);
  html = Read(r.html_path);
  EXPECT_EQ(html.find("href=\"runs/"), std::string::npos);
  EXPECT_EQ(html.find("scenario.resolved.yaml</a>"), std::string::npos);
  EXPECT_NE(Read(dir / "findings.md").find("20 of the 20 finished runs have no folder in `"),
            std::string::npos);
}

// A report of timings alone tests nothing, and says so (a review: it said
// "This report makes 0 comparisons; ... about 0.0 of them findings");
// paired.csv gives a timing no p-value, as the page gives none.
TEST(Report, ATimingsOnlyReportSaysItTestsNothing) {
  const auto dir = TwoMethodStore(
      "report-timings-only", {"ms_per_frame"}, [](const std::string& method, int seed) {
        return std::map<std::string, double>{
            {"ms_per_frame", method == "systematic" ? 1.0 : 2.0 + 0.1 * seed}};
      });
  WriteReport({.dir = dir.string()});
  const std::string md = Read(dir / "findings.md");
  EXPECT_NE(md.find("This report tests no comparison: ms_per_frame is plotted and tabled but not "
                    "tested"),
            std::string::npos)
      << md;
  EXPECT_EQ(md.find("makes 0 comparisons"), std::string::npos) << md;
  // paired.csv: ...,nonzero,w_plus,p_value,exact,p_holm,...: no p-value, no Holm p.
  EXPECT_NE(Read(dir / "paired.csv").find(",10,55,,1,,"), std::string::npos)
      << Read(dir / "paired.csv");
}

// A metric with the same value in every seed pair (a detector's recall
// across resamplers that read the same cached detections) is not tested: an
// audit found det_recall's "Δ 0 [0, 0] 0/0/10, p = 1.000" counted in Holm's
// family. Here mota differs on every seed (charged 0.8 against 0.5: p =
// 2/1024), det_recall is 0.5 + 0.01·seed for both methods. The family is the
// one mota comparison, so its Holm p is its own p (0.002), not 2 × 0.002.
TEST(Report, AComparisonWhoseEveryPairTiesIsNotTested) {
  const auto dir = TwoMethodStore(
      "report-every-pair-ties", {"mota", "det_recall"}, [](const std::string& method, int seed) {
        return std::map<std::string, double>{{"mota", method == "systematic" ? 0.5 : 0.8},
                                             {"det_recall", 0.5 + 0.01 * seed}};
      });
  const ReportResult r = WriteReport({.dir = dir.string()});
  EXPECT_EQ(r.findings, 2);  // one sentence per metric
  const std::string html = Read(dir / "report.html");
  EXPECT_NE(html.find("<td>&Delta;&nbsp;0<br><span class=\"i\">[0, 0]</span><br>0/0/10, the same "
                      "in every pair: not tested</td>"),
            std::string::npos)
      << html;
  EXPECT_NE(html.find("p&nbsp;=&nbsp;0.002, <b>Holm&nbsp;0.002</b>"), std::string::npos) << html;
  const std::string md = Read(dir / "findings.md");
  EXPECT_NE(md.find("This report makes 1 comparisons;"), std::string::npos) << md;
  EXPECT_NE(md.find(" 1 comparison (det_recall) has the same value in every seed pair"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("- **det_recall**: best mean (higher is better): equal means at every "
                    "tracker.particles. charged \u2212 systematic: the same value in every seed "
                    "pair at every tracker.particles, not tested (10 seed pairs per "
                    "tracker.particles).\n"),
            std::string::npos)
      << md;
  // The glance table: a "tied" column, det_recall's cell counted there.
  EXPECT_NE(md.find("| not significant | tied | cells |"), std::string::npos) << md;
  EXPECT_NE(md.find("| det_recall | charged \u2212 systematic | 0 | 0 | 0 | 0 | 1 | 1 |"),
            std::string::npos)
      << md;
  // paired.csv (...,nonzero,w_plus,p_value,exact,p_holm,...): no p-value, no Holm p.
  const std::string csv = Read(dir / "paired.csv");
  EXPECT_NE(csv.find("det_recall,10,0,0,0,0,0,0,10,0,0,,0,,"), std::string::npos) << csv;
  // Every comparison tied: the report tests none and says so (a review: it
  // said "makes 0 comparisons; ... about 0.0 of them findings").
  const auto only = TwoMethodStore(
      "report-every-pair-ties-only", {"det_recall"}, [](const std::string&, int seed) {
        return std::map<std::string, double>{{"det_recall", 0.5 + 0.01 * seed}};
      });
  WriteReport({.dir = only.string()});
  const std::string only_md = Read(only / "findings.md");
  EXPECT_NE(only_md.find("This report tests no comparison: 1 comparison (det_recall) has the same "
                         "value in every seed pair"),
            std::string::npos)
      << only_md;
  EXPECT_EQ(only_md.find("makes 0 comparisons"), std::string::npos) << only_md;
  EXPECT_NE(
      Read(only / "report.html").find("This table tests no comparison, so no cell is coloured."),
      std::string::npos);
}

// The summary above the findings (an audit: "12 bullets of about 60 words
// each ... a researcher wants a 2–3 line conclusion"): one sentence per panel
// of what survives Holm's correction, the metrics kept at the same x values
// together. A hand store of 4 particle counts × 2 methods × 2 panels × 10
// seeds. Panel a: mota and idf1 0.6 for charged against 0.5 at 100, 200 and
// 500 (equal at 50); hijack_rate 0 against 1 at 50 and 500 (0.5 both
// elsewhere); hota 0.4 against 0.5 at every count. Panel b: every metric
// equal. Every difference has one sign on all 10 seeds (p = 2/1024), the
// equal ones tie (not tested): a family of 3 + 3 + 2 + 4 = 12, Holm's
// p 12 × 2/1024 = 0.023 for each, all kept.
TEST(Report, TheSummarySaysPerPanelWhatSurvivesHolmsCorrection) {
  // The same store with the model as panels, then without panels and with
  // the particle counts stored out of order: the summary groups the cells as
  // the findings do (every swept value but x and the series), so the model
  // still tells the sentences apart (a review: without panels it pooled
  // them), and the counts come in the axis's order.
  for (const bool panels : {true, false}) {
    SCOPED_TRACE(panels ? "panels" : "no panels");
    const auto dir = testing::SweepFolder(panels ? "report-summary" : "report-summary-no-panels");
    StoreMeta meta;
    meta.sweep_hash = "summary";
    meta.sweep_file = "summary.yaml";
    meta.swept_keys = {"tracker.likelihood.model", "tracker.particles",
                       "tracker.resampling.method"};
    meta.report.x = "tracker.particles";
    meta.report.series = "tracker.resampling.method";
    if (panels) meta.report.panels = "tracker.likelihood.model";
    meta.report.y = {"mota", "idf1", "hijack_rate", "hota"};
    meta.report.reference = "systematic";
    meta.run_count = 2 * 4 * 2 * 10;
    const std::vector<std::string> counts =
        panels ? std::vector<std::string>{"50", "100", "200", "500"}
               : std::vector<std::string>{"500", "50", "200", "100"};
    {
      auto store = ResultsStore::OpenOrCreate((dir / "results.sqlite").string(), meta);
      int64_t index = 0;
      for (const std::string panel : {"a", "b"}) {
        for (const std::string& particles : counts) {
          for (const std::string method : {"systematic", "charged"}) {
            for (int seed = 0; seed < 10; ++seed) {
              RunRecord r =
                  HandRun(dir, panel + "-" + particles + "-" + method + "-" + std::to_string(seed),
                          index++, seed, 3000 + seed, {panel, particles, method});
              const bool charged = method == "charged" && panel == "a";
              const double spread = 0.01 * seed;  // the same in both methods
              r.metrics["mota"] = (charged && particles != "50" ? 0.6 : 0.5) + spread;
              r.metrics["idf1"] = r.metrics["mota"];
              const bool hijack_differs = panel == "a" && (particles == "50" || particles == "500");
              r.metrics["hijack_rate"] = hijack_differs ? (method == "charged" ? 0.0 : 1.0) : 0.5;
              r.metrics["hota"] = (charged ? 0.4 : 0.5) + spread;
              store->Put(r);
            }
          }
        }
      }
    }
    WriteReport({.dir = dir.string()});
    const std::string md = Read(dir / "findings.md");
    EXPECT_NE(md.find("**Summary.** Under tracker.likelihood.model = a, charged \u2212 "
                      "systematic, after Holm's correction: better in mota and idf1 at "
                      "tracker.particles = 100 to 500, and in hijack_rate at 50 and 500; worse "
                      "in hota at every tracker.particles. Under tracker.likelihood.model = b, "
                      "charged \u2212 systematic: no finding.\n"),
              std::string::npos)
        << md;
    EXPECT_NE(md.find("This report makes 12 comparisons;"), std::string::npos) << md;
    if (panels) {
      const std::string html = Read(dir / "report.html");
      EXPECT_NE(html.find("<h2 id=\"findings\">Findings</h2>\n<p id=\"summary\"><b>Summary.</b> "
                          "Under tracker.likelihood.model = a,"),
                std::string::npos)
          << html;
      // The bands' rule as MeanInterval95 has it (it said the binomial band
      // "when they all agree", which since 2026-12-07 holds at 0 and 1 only).
      EXPECT_NE(html.find("the binomial over the n seeds when every seed is 0 or every seed is "
                          "1, so a band even there; width 0 when every seed has one value "
                          "between"),
                std::string::npos)
          << html;
    }
  }
}

// A finding needs the signed-rank test and the t interval to say the same
// way. 40 seed pairs: charged 0.01 above systematic on 34 seeds and 0.5
// below on 6. The mean difference is -0.0665 and its t interval [-0.125,
// -0.0075] excludes 0, but the ranks say "higher": the 34 ties at rank 17.5
// give W+ = 595 against 410 expected, p = 0.0072 two-sided (a review). The
// report called charged significantly worse; now it is no finding.
TEST(Report, AFindingNeedsTheTestAndTheIntervalToSayTheSameWay) {
  const auto dir = testing::SweepFolder("report-test-and-interval-disagree");
  StoreMeta meta;
  meta.sweep_hash = "disagree";
  meta.sweep_file = "disagree.yaml";
  meta.swept_keys = {"tracker.particles", "tracker.resampling.method"};
  meta.report.x = "tracker.particles";
  meta.report.series = "tracker.resampling.method";
  meta.report.y = {"da_accuracy"};
  meta.report.reference = "systematic";
  meta.run_count = 2 * 40;
  {
    auto store = ResultsStore::OpenOrCreate((dir / "results.sqlite").string(), meta);
    int64_t index = 0;
    for (const std::string method : {"systematic", "charged"}) {
      for (int seed = 0; seed < 40; ++seed) {
        RunRecord r = HandRun(dir, method + "-" + std::to_string(seed), index++, seed, 5000 + seed,
                              {"100", method});
        const bool outlier = seed >= 34;
        r.metrics["da_accuracy"] =
            method == "systematic" ? (outlier ? 0.95 : 0.90) : (outlier ? 0.45 : 0.91);
        store->Put(r);
      }
    }
  }
  WriteReport({.dir = dir.string()});
  const std::string md = Read(dir / "findings.md");
  EXPECT_NE(md.find("None of them is a finding."), std::string::npos) << md;
  EXPECT_EQ(md.find("worse in da_accuracy"), std::string::npos) << md;
  EXPECT_EQ(md.find("significantly worse"), std::string::npos) << md;
  const std::string paired = Read(dir / "paired.csv");
  EXPECT_NE(paired.find(",595,"), std::string::npos) << paired;  // W+ as the review computed
}

// The findings of the hand store (values above): hijack_rate, lower is
// better: charged's means are 0 and 0 against systematic's 1 and 0.5, so
// charged is best at both x; the paired differences are a finding at 100
// (p = 0.002, interval [−1, −1]) and not at 1000 (p = 0.0625). mota: equal
// means (0.9) at 100, charged best at 1000 (0.95 > 0.9); no difference is a
// finding (p = 0.092 at 1000), and at 100 every pair ties (0.9 both), so it
// is not tested: the family is 3, and Tarone's rule makes Holm's first
// step K = 2 (PairedDifferencesByHand). With charged as the reference the
// sign turns: systematic − charged is worse at 100.
TEST(Report, FindingsSayWhichSeriesIsBestAndWhereTheDifferenceIsSignificant) {
  const fs::path dir = HandStore("report-findings");
  const ReportResult r = WriteReport({.dir = dir.string()});
  EXPECT_EQ(r.findings, 2);
  const std::string md = Read(dir / "findings.md");
  // The summary first: the one finding, kept by Holm (2/1024 × 2 = 0.0039).
  EXPECT_NE(md.find("# Findings\n\n**Summary.** charged \u2212 systematic, after Holm's "
                    "correction: better in hijack_rate at tracker.particles = 100; worse in no "
                    "metric.\n"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("- **hijack_rate**: best mean (lower is better): charged at every "
                    "tracker.particles. charged \u2212 systematic: significantly better at "
                    "tracker.particles = 100; not significantly different at "
                    "tracker.particles = 1000 (10 seed pairs per tracker.particles). After "
                    "Holm's correction for the report's 3 comparisons: still significant at "
                    "tracker.particles = 100.\n"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("- **mota**: best mean (higher is better): equal means at "
                    "tracker.particles = 100; charged at tracker.particles = 1000. charged "
                    "\u2212 systematic: no significant difference at tracker.particles = 1000; "
                    "the same value in every seed pair at tracker.particles = 100, not tested "
                    "(10 seed pairs per tracker.particles).\n"),
            std::string::npos)
      << md;
  // At a glance: hijack_rate a finding for better at one x of two, mota at
  // none, and tied at one.
  EXPECT_NE(md.find("| metric | compared | better | worse | of them after Holm | not significant "
                    "| tied | cells |\n"
                    "|---|---|---|---|---|---|---|---|\n"
                    "| hijack_rate | charged \u2212 systematic | 1 | 0 | 1 | 1 | 0 | 2 |\n"
                    "| mota | charged \u2212 systematic | 0 | 0 | 0 | 1 | 1 | 2 |\n"),
            std::string::npos)
      << md;
  const std::string html = Read(r.html_path);
  EXPECT_NE(html.find("<h2 id=\"findings\">Findings</h2>"), std::string::npos);
  EXPECT_NE(html.find("<tr><td class=\"k\">hijack_rate</td><td class=\"k\">charged &minus; "
                      "systematic</td><td style=\"background:#dff3df\">1</td><td>0</td><td>1</td>"
                      "<td>1</td><td>0</td><td>2</td></tr>"),
            std::string::npos);
  EXPECT_LT(html.find("id=\"findings\""), html.find("<h2>Plots</h2>"));
  EXPECT_NE(html.find("<li><b>hijack_rate</b>: best mean (lower is better): charged"),
            std::string::npos);

  const fs::path flipped = HandStore("report-findings-flipped", "charged");
  WriteReport({.dir = flipped.string()});
  EXPECT_NE(Read(flipped / "findings.md")
                .find("systematic \u2212 charged: significantly worse at tracker.particles = 100; "
                      "not significantly different at tracker.particles = 1000"),
            std::string::npos)
      << Read(flipped / "findings.md");
  EXPECT_NE(Read(flipped / "findings.md")
                .find("| hijack_rate | systematic \u2212 charged | 0 | 1 | 1 | 1 | 0 | 2 |\n"),
            std::string::npos);
}

// The hand store with 6 seeds: hijack_rate at 100 is −1 on all 6 pairs
// (p = 2/64 = 0.03125, interval [−1, −1]) and mota at 1000 +0.1 on all 6
// (p = 0.03125, [0.1, 0.1]): two findings. Holm over the 3 comparisons
// (0.03125, 0.03125, hijack_rate at 1000: 5 nonzero, p = 2/32 = 0.0625;
// mota at 100 ties on every pair, not tested) with Tarone's rule (below)
// gives 0.0625 each: its first step needs p < 0.05/2 = 0.025, which 2/64
// misses. Neither finding survives, and the report says so rather than
// calling them two results; 7 pairs, each differing (2/128 = 0.0156 <
// 0.05/3), would let all three count.
TEST(Report, FindingsSayWhenNoneSurvivesHolmsCorrection) {
  const fs::path dir = HandStore("report-holm", "systematic", 6);
  const ReportResult r = WriteReport({.dir = dir.string()});
  const std::string md = Read(dir / "findings.md");
  EXPECT_NE(md.find("**Summary.** charged \u2212 systematic: 2 findings, none of which survives "
                    "Holm's correction.\n"),
            std::string::npos)
      << md;
  EXPECT_NE(
      md.find("This report makes 3 comparisons; where nothing differs, chance alone makes "
              "at most about 0.1 of them findings (0.05 for each of the 2 whose seed pairs can "
              "reach p < 0.05). Of them 2 are findings, and 0 of those stay "
              "significant after Holm's correction for all 3 (Holm p < 0.05). With 6 seed "
              "pairs the signed-rank test cannot give p below 0.0312, and Holm's correction "
              "for 3 comparisons needs p < 0.025 for its first (Tarone's rule: K = 2): no "
              "comparison of this report can stay significant after it, whatever the data. At "
              "least 7 seed pairs per comparison are needed for Holm's "
              "correction to keep one, more for a difference that does not have the same "
              "sign in every seed. 1 comparison (mota) has the same value in every seed pair"),
      std::string::npos)
      << md;
  EXPECT_NE(md.find("charged \u2212 systematic: significantly better at tracker.particles = 100; "
                    "not significantly different at tracker.particles = 1000 (6 seed pairs per "
                    "tracker.particles). None stays significant after Holm's correction for the "
                    "report's 3 comparisons.\n"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| hijack_rate | charged \u2212 systematic | 1 | 0 | 0 | 1 | 0 | 2 |\n"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| mota | charged \u2212 systematic | 1 | 0 | 0 | 0 | 1 | 2 |\n"),
            std::string::npos)
      << md;
  // Holm with Tarone's rule: sorted p 2/64, 2/64, 2/32 with the same floors.
  // Step 1: below 0.05 two, below 0.025 none: K = 2, 0.0625; step 2 (2/64,
  // 2/32): below 0.05 one, K = 1, 0.03125 raised to 0.0625; step 3: 0.0625.
  // No comparison reaches the first step's 0.025 (Holm alone: 0.09375 each).
  const auto rows = CsvRows(dir / "paired.csv");
  ASSERT_EQ(rows.size(), 4U);
  for (const auto& row : rows) {
    if (row[0] == "100" && row[3] == "mota") {
      EXPECT_EQ(row[16], "");  // not tested
    } else {
      EXPECT_NEAR(std::stod(row[16]), 0.0625, 1e-9) << row[0] << " " << row[3];
    }
  }
  // The coloured cells give Holm's p, not in bold (not below 0.05); the
  // table says none can be kept.
  const std::string html = Read(r.html_path);
  EXPECT_NE(html.find("p&nbsp;=&nbsp;0.031, Holm&nbsp;0.062</td>"), std::string::npos);
  EXPECT_EQ(html.find("<b>Holm&nbsp;"), std::string::npos);
  EXPECT_NE(html.find("<b>Holm</b>: no comparison of this table can reach the p Holm's "
                      "correction needs (below)"),
            std::string::npos);
  // The paired table's note says it too, in bold.
  EXPECT_NE(html.find("<b>With 6 seed pairs the signed-rank test cannot give p below 0.0312"),
            std::string::npos);

  // 10 seeds: 2 / 1024 = 0.00195 < 0.0167, no comparison has too few pairs,
  // and that is not said. With the charged runs at 1000 failed on seeds 0–3,
  // the two comparisons at 1000 have 6 pairs and cannot be kept: the note
  // counts them.
  const fs::path ten = HandStore("report-holm-ten");
  WriteReport({.dir = ten.string()});
  EXPECT_EQ(Read(ten / "findings.md").find("seed pairs the signed-rank test cannot"),
            std::string::npos)
      << Read(ten / "findings.md");
  // But hijack_rate at 1000 differs on 5 of its 10 seeds only (systematic
  // hijacked on seeds 0–4, charged never): 5 nonzero differences give p >=
  // 2/32, so Holm cannot keep it whatever they are; Tarone's rule does not
  // count it at the first step (PairedDifferencesByHand), and the report
  // says so.
  EXPECT_NE(Read(ten / "findings.md")
                .find("significant after Holm's correction for all 3 (Holm p < 0.05). Of the 3 "
                      "comparisons, 2 can reach p < 0.025, the first step's level (Tarone's "
                      "rule: K = 2, the smallest k with at most k comparisons whose p can fall "
                      "below 0.05 / k; docs/sweeps.md, \"Holm's correction\"). The other one "
                      "cannot, whatever the data: 1 with enough seed pairs but fewer than 7 "
                      "where the two differ (a tied seed leaves the signed-rank test). It cannot "
                      "be kept at any step. 1 comparison (mota) has the same value in every seed "
                      "pair"),
            std::string::npos)
      << Read(ten / "findings.md");
  // The two at 1000: hijack_rate differs on seed 4 alone of 4–9 (floor 1),
  // mota on all six (floor 2/64); hijack_rate at 100 has 10 (2/1024). Below
  // 0.05 two, below 0.025 one: K = 2, and only hijack_rate at 100 can reach
  // the first step's 0.025. Both at 1000 have 6 pairs, whose floor (2/64)
  // is above 0.025 whatever the ties. With every p at its floor, hijack_rate
  // at 100 is kept first (2 × 2/1024), then K over the two left (floors 1
  // and 2/64) is 1 and mota's 2/64 is kept: it can be kept at a later step;
  // hijack_rate's floor (1) never. 7 pairs, each differing, reach 2/128 <
  // 0.05 / 3.
  const fs::path some = HandStore("report-holm-some", "systematic", 10, 4);
  WriteReport({.dir = some.string()});
  EXPECT_NE(Read(some / "findings.md")
                .find("Of the 3 comparisons, 1 can reach p < 0.025, the first step's level "
                      "(Tarone's rule: K = 2, the smallest k with at most k comparisons whose p "
                      "can fall below 0.05 / k; docs/sweeps.md, \"Holm's correction\"). The "
                      "other 2 cannot, whatever the data: 2 with 6 seed pairs or fewer, where "
                      "the signed-rank test cannot give p below 0.0312. 1 of them can be kept at "
                      "a later step, after enough others are kept; 1 cannot be kept at any step. "
                      "7 seed pairs per comparison, each differing, would let every comparison "
                      "count from the first "
                      "step."),
            std::string::npos)
      << Read(some / "findings.md");
}

// A store written by hand: tracker.particles swept over 100 and 1000, one ok
// run each with MOTA 0.5 (and no other metric), report.y = `y`.
void WriteTwoRunStore(const fs::path& dir, const std::vector<std::string>& y,
                      const std::string& x_metric = "") {
  StoreMeta meta = HandMeta({"tracker.particles"}, "", y, 2);
  meta.report.x_metric = x_metric;
  auto store = ResultsStore::OpenOrCreate((dir / "results.sqlite").string(), meta);
  for (int i = 0; i < 2; ++i) {
    RunRecord r = HandRun(dir, "k" + std::to_string(i), i, 0, 0, {i == 0 ? "100" : "1000"});
    r.metrics["mota"] = 0.5;
    store->Put(r);
  }
}

// Cells placed at a measured metric (report.x_metric) that no run measured
// (detection-level runs have no det_size_px): the page says every plot is
// empty because of the x axis, not the metrics drawn, which were measured
// (an audit: every plot said "no values of this metric", mota's too).
TEST(Report, AnXMetricNoRunMeasuredIsNamed) {
  const auto dir = testing::SweepFolder("report-x-unmeasured");
  // Two runs measuring mota alone, cells placed at `x_metric`.
  const auto report_at = [](const fs::path& folder, const std::string& x_metric) {
    WriteTwoRunStore(folder, {"mota"}, x_metric);
    return Read(WriteReport({.dir = folder.string()}).html_path);
  };
  const std::string html = report_at(dir, "det_size_px");
  EXPECT_NE(html.find("No finished run of this sweep measured the x axis's metric, det_size_px"),
            std::string::npos)
      << html.substr(0, 4000);
  EXPECT_EQ(html.find("No finished run of this sweep measured mota"), std::string::npos);
  // Measured, it is not said.
  EXPECT_EQ(report_at(testing::SweepFolder("report-x-measured"), "mota").find("x axis's metric"),
            std::string::npos);
}

// A panel whose runs measure the metric drawn but not report.x_metric (the
// simulated runs of a sweep over the observation source have no detection
// size) names the x axis's metric in its empty plot; it said "no values of
// this metric" of a metric each of its runs measured (an audit of valid
// input). The other panel is drawn.
TEST(Report, APanelWithoutTheXMetricNamesIt) {
  const auto dir = testing::SweepFolder("report-panel-x-unmeasured");
  // A third panel ("file"): one cell with mota but no det_size_px, the other
  // with det_size_px but no mota: both are named (a review).
  StoreMeta meta = HandMeta({"observation.source", "tracker.particles"}, "", {"mota"}, 6);
  meta.report.x = "tracker.particles";
  meta.report.x_metric = "det_size_px";
  meta.report.panels = "observation.source";
  auto store = ResultsStore::OpenOrCreate((dir / "results.sqlite").string(), meta);
  for (int i = 0; i < 6; ++i) {
    const char* source = i < 2 ? "simulated" : i < 4 ? "rendered" : "file";
    RunRecord r =
        HandRun(dir, "k" + std::to_string(i), i, 0, 0, {source, i % 2 == 0 ? "100" : "1000"});
    if (i != 5) r.metrics["mota"] = 0.5;
    if (i >= 2 && i != 4) r.metrics["det_size_px"] = 20.0 + i;
    store->Put(r);
  }
  const fs::path kept = dir / "kept";
  WriteReport({.dir = dir.string(), .gnuplot = KeepingGnuplot(dir, kept).string()});
  int named = 0, both = 0, drawn = 0;
  for (const auto& entry : fs::directory_iterator(kept)) {
    if (entry.path().extension() != ".gp") continue;
    const std::string gp = Read(entry.path());
    EXPECT_EQ(gp.find("no values of this metric"), std::string::npos) << gp;
    named += gp.find("'no values of det_size_px, the x axis, in this panel'") != std::string::npos;
    both += gp.find(
                "'no cell with values of both this metric and det_size_px, the x axis, in "
                "this panel'") != std::string::npos;
    drawn += gp.find("with linespoints") != std::string::npos;
  }
  EXPECT_EQ(named, 1);  // mota's simulated panel
  EXPECT_EQ(both, 1);   // its file panel
  EXPECT_GE(drawn, 1);  // its rendered panel
}

// Without a series there is nothing to compare: no findings, no file.
// A report that fails part-way (here a full disk: RLIMIT_FSIZE one byte
// under report.html's size, in a forked child) leaves the earlier report's
// four files as they were, not a mix of two reports. Before the files were
// published as a set, paired.csv, findings.md and summary.csv were replaced
// and the old report.html stayed beside them.
TEST(Report, AReportThatFailsPartWayLeavesTheEarlierReportWhole) {
  const fs::path dir = HandStore("report-whole");
  const ReportResult first = WriteReport({.dir = dir.string()});
  ASSERT_EQ(first.findings, 2);
  const std::vector<std::string> names = {"paired.csv", "findings.md", "summary.csv",
                                          "report.html"};
  const std::map<std::string, std::string> made = [&] {
    std::map<std::string, std::string> m;
    for (const std::string& name : names) m[name] = Read(dir / name);
    return m;
  }();
  const uint64_t html_bytes = made.at("report.html").size();
  for (const std::string& name : names) {
    ASSERT_LT(made.at(name).size(), made.at("report.html").size() + (name == "report.html"));
    std::ofstream(dir / name) << "earlier " << name << "\n";
  }

  // gnuplot inherits the limit and the ignored SIGXFSZ.
  const int code = hcpf::testing::InChildWithFileSizeLimit(html_bytes - 1, [&] {
    try {
      WriteReport({.dir = dir.string()});
    } catch (const RunError& e) {
      return std::string(e.what()).find("report.html") != std::string::npos ? 0 : 3;
    }
    return 4;  // no error
  });
  EXPECT_EQ(code, 0) << "3: another error, 4: no error, 5: not a RunError";
  for (const std::string& name : names) {
    EXPECT_EQ(Read(dir / name), "earlier " + name + "\n") << name;
  }
  // The next report replaces the set and clears what the failed one left.
  WriteReport({.dir = dir.string()});
  for (const std::string& name : names) EXPECT_EQ(Read(dir / name), made.at(name)) << name;
  EXPECT_FALSE(fs::exists(dir / ".report-work"));
}

TEST(Report, NoSeriesNoFindings) {
  const auto dir = testing::SweepFolder("report-no-findings");
  WriteTwoRunStore(dir, {"mota"});
  const ReportResult r = WriteReport({.dir = dir.string()});
  EXPECT_EQ(r.findings, 0);
  EXPECT_FALSE(fs::exists(dir / "findings.md"));
  EXPECT_EQ(Read(r.html_path).find("id=\"findings\""), std::string::npos);
}

// A metric of report.y that no finished run measured (det_ap of
// detection-level runs) gets its empty plot and a sentence saying so, naming
// where the value is read from; a measured one gets neither.
TEST(Report, MetricsNoRunMeasuredAreNamed) {
  const auto dir = testing::SweepFolder("report-unmeasured");
  WriteTwoRunStore(dir, {"mota", "det_ap"});
  const ReportResult r = WriteReport({.dir = dir.string()});
  EXPECT_EQ(r.plots, 2);
  const std::string html = Read(r.html_path);
  EXPECT_NE(html.find("No finished run of this sweep measured det_ap (metrics.json "
                      "/detection/precision_recall/average_precision): its plot is empty"),
            std::string::npos)
      << html.substr(0, 4000);
  EXPECT_EQ(html.find("measured mota"), std::string::npos);
  const size_t plot = html.find("id=\"plot-det_ap\"");
  ASSERT_NE(plot, std::string::npos);
  EXPECT_NE(html.find("no values of this metric", plot), std::string::npos);
}

// Keys zipped with the series (an external tracker's type beside the name
// that labels it) do not split the findings into one group per value: one
// sentence per metric, comparing sort with pf on the seeds they share (none
// for a metric sort does not have).
TEST(Report, FindingsIgnoreKeysThatFollowTheSeries) {
  const auto dir = testing::SweepFolder("report-findings-follow");
  StoreMeta meta =
      HandMeta({"tracker.particles", "name", "tracker.type"}, "name", {"mota", "da_accuracy"}, 12);
  meta.report.reference = "pf";
  {
    auto store = ResultsStore::OpenOrCreate((dir / "results.sqlite").string(), meta);
    int64_t index = 0;
    for (const char* x : {"100", "1000"}) {
      for (const char* name : {"pf", "sort"}) {
        for (int seed = 0; seed < 3; ++seed) {
          const bool sort = std::string(name) == "sort";
          RunRecord r = HandRun(dir, std::string(x) + name + std::to_string(seed), index++, seed,
                                7 + seed, {x, name, sort ? "external" : "particle_filter"});
          r.metrics["mota"] = sort ? 0.8 : 0.9;
          // An external tracker has no particle filters to score.
          r.metrics["da_accuracy"] = sort ? std::nan("") : 0.95;
          store->Put(r);
        }
      }
    }
  }
  const ReportResult r = WriteReport({.dir = dir.string()});
  EXPECT_EQ(r.findings, 2);
  const std::string md = Read(dir / "findings.md");
  EXPECT_NE(md.find("- **da_accuracy**: best mean (higher is better): pf at every "
                    "tracker.particles. sort \u2212 pf: no seed pairs (no seed has a value of the "
                    "metric in both: its runs are not in this store, failed, or lack the "
                    "metric).\n"),
            std::string::npos)
      << md;
  // The family Holm is over counts the comparisons with pairs only: mota's
  // two (3 pairs each, all lower: p = 0.25, no finding).
  // Neither can reach p < 0.05, so chance makes none of them findings (it
  // said "about 0.1" beside "no comparison ... can be a finding": a review).
  EXPECT_NE(md.find("This report makes 2 comparisons; where nothing differs, chance alone makes "
                    "none of them findings (no comparison's seed pairs can reach p < 0.05). None "
                    "of them is a finding. With 3 seed pairs "
                    "the signed-rank test cannot give p below 0.25: no comparison of this report "
                    "can be a finding, whatever the data. At least 7 seed pairs per comparison"),
            std::string::npos)
      << md;
  // At a glance, da_accuracy has no pairs in either cell.
  EXPECT_NE(md.find("| da_accuracy | sort \u2212 pf | 0 | 0 | 0 | 0 | 2 | 2 |\n"),
            std::string::npos)
      << md;
  // Three pairs: the rank test cannot reach p < 0.05 (2/8 = 0.25).
  EXPECT_NE(md.find("- **mota**: best mean (higher is better): pf at every tracker.particles. "
                    "sort \u2212 pf: no significant difference at any tracker.particles (3 seed "
                    "pairs per tracker.particles).\n"),
            std::string::npos)
      << md;
}

// With report.x_metric the difference of a pair sits where its compared
// cell does: the x of every difference point is the x of the charged line's
// point in the metric's own plot, even for the plot of x_metric itself
// (whose y is then the difference, not the cell's mean).
TEST(Report, DifferencePointsSitAtTheComparedCellsMeasuredX) {
  const auto dir = testing::SweepFolder("report-paired-x-metric");
  const SweepSpec spec = LoadSweepFile(testing::WriteSweep(
      dir,
      "base: base.yaml\nseeds: 2\ngrid:\n  tracker.particles: [20, 200]\n"
      "  tracker.resampling.method: [systematic, charged]\n"
      "report: {x: tracker.particles, x_metric: idf1, series: tracker.resampling.method, "
      "y: [idf1, hota]}\n"));
  const std::string out = RunQuietly(spec, dir);
  const fs::path kept = dir / "kept";
  WriteReport({.dir = out, .gnuplot = KeepingGnuplot(dir, kept).string()});
  const auto cells = PlotRows(kept / "plot_0.dat").at("charged");
  const auto sys = PlotRows(kept / "plot_0.dat").at("systematic");
  const auto diff = PlotRows(kept / "plot_d0.dat").at("charged \u2212 systematic");
  ASSERT_EQ(cells.size(), 2U);
  ASSERT_EQ(diff.size(), 2U);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(diff[i][0], cells[i][0]) << i;
    // y: the mean difference of the pairs = the difference of the two means
    // (both cells have both seeds); 6 significant digits in the files.
    EXPECT_NEAR(diff[i][1], cells[i][1] - sys[i][1], 2e-6) << i;
  }
}

// A tiny real sweep: each comparison's mean difference and pair count are
// the store's own per-seed differences, paired here by seed; its p-value is
// the exact signed-rank p computed here by enumerating the 2^n sign flips.
TEST(Report, PairedDifferencesOfATinySweepMatchTheStore) {
  const auto dir = testing::SweepFolder("report-paired-sweep");
  const SweepSpec spec = LoadSweepFile(testing::WriteSweep(
      dir,
      "base: base.yaml\nseeds: 4\ngrid:\n  tracker.particles: [20, 200]\n"
      "  tracker.resampling.method: [systematic, charged]\n"
      "report: {x: tracker.particles, series: tracker.resampling.method, reference: charged, "
      "y: [idf1, da_accuracy]}\n"));
  const std::string out = RunQuietly(spec, dir);
  const ReportResult r = WriteReport({.dir = out});
  EXPECT_EQ(r.comparisons, 2);                             // systematic − charged at 20 and 200
  std::map<std::string, std::map<uint64_t, double>> idf1;  // "x/method" → seed → value
  for (const RunRecord& rec : ResultsStore::Open(out + "/results.sqlite")->Runs()) {
    idf1[rec.values[0] + "/" + rec.values[1]][rec.seed] = rec.metrics.at("idf1");
  }
  for (const char* x : {"20", "200"}) {
    std::vector<double> d;
    for (const auto& [seed, v] : idf1[std::string(x) + "/systematic"]) {
      d.push_back(v - idf1[std::string(x) + "/charged"].at(seed));
    }
    ASSERT_EQ(d.size(), 4U);
    double mean = 0.0;
    for (double v : d) mean += v / 4.0;
    // Exact two-sided signed-rank p by enumeration (no ties assumed away:
    // ranks averaged over equal |d|; zeros dropped).
    std::vector<double> nz;
    for (double v : d) {
      if (v != 0.0) nz.push_back(v);
    }
    std::vector<double> rank(nz.size());
    for (size_t i = 0; i < nz.size(); ++i) {
      double below = 0, equal = 0;
      for (double w : nz) {
        below += std::abs(w) < std::abs(nz[i]);
        equal += std::abs(w) == std::abs(nz[i]);
      }
      rank[i] = below + (equal + 1) / 2;
    }
    double w_plus = 0;
    for (size_t i = 0; i < nz.size(); ++i) w_plus += nz[i] > 0 ? rank[i] : 0;
    double at_most = 0, at_least = 0;
    const size_t flips = size_t{1} << nz.size();
    for (size_t mask = 0; mask < flips; ++mask) {
      double w = 0;
      for (size_t i = 0; i < nz.size(); ++i) w += (mask >> i & 1) ? rank[i] : 0;
      at_most += w <= w_plus + 1e-9;
      at_least += w >= w_plus - 1e-9;
    }
    const double p = nz.empty() ? 1.0 : std::min(1.0, 2 * std::min(at_most, at_least) / flips);
    bool found = false;
    for (const auto& row : CsvRows(fs::path(out) / "paired.csv")) {
      if (row[0] != x || row[3] != "idf1") continue;
      found = true;
      EXPECT_EQ(row[1], "systematic");
      EXPECT_EQ(row[2], "charged");
      EXPECT_EQ(row[4], "4");
      EXPECT_NEAR(std::stod(row[5]), mean, 1e-5 * (1 + std::abs(mean))) << x;
      EXPECT_NEAR(std::stod(row[14]), p, 1e-5) << x;
    }
    EXPECT_TRUE(found) << x;
  }
  const std::string html = Read(r.html_path);
  EXPECT_NE(html.find("systematic &minus; charged</td><td>4</td>"), std::string::npos);
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

TEST(CodeSpansToHtml, BackticksPairIntoCodeAndTheRestIsEscaped) {
  EXPECT_EQ(CodeSpansToHtml("run `hcpf sweep --seed 3` & <see> `seed:`"),
            "run <code>hcpf sweep --seed 3</code> &amp; &lt;see&gt; <code>seed:</code>");
  EXPECT_EQ(CodeSpansToHtml("one ` left"), "one ` left");
  EXPECT_EQ(CodeSpansToHtml("``"), "<code></code>");
  EXPECT_EQ(CodeSpansToHtml(""), "");
}

// Runs `sql` on the store in `dir` (hand edits of a hand store).
void EditStore(const fs::path& dir, const std::string& sql) {
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open((dir / "results.sqlite").c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db, sql.c_str(), nullptr, nullptr, nullptr), SQLITE_OK)
      << sqlite3_errmsg(db);
  sqlite3_close(db);
}

// hcpf report DIR --against OTHER, on hand stores whose verdicts are worked
// out above (HandStore, FindingsSayWhenNoneSurvivesHolmsCorrection): with 10
// seeds hijack_rate at 100 is a finding for charged (p = 2/1024, kept by
// Holm), at 1000 not (5 nonzero, p = 0.0625); mota is a finding nowhere (at
// 1000 nine +0.1 and one −0.4: the interval reaches 0). With 6 seeds
// hijack_rate at 100 (p = 2/64) and mota at 1000 (six +0.1, p = 2/64) are
// findings, neither kept by Holm (Holm p 0.0625 each:
// FindingsSayWhenNoneSurvivesHolmsCorrection; in the 10-seed store
// hijack_rate at 100 has Holm p 4/1024 = 0.00390625: PairedDifferencesByHand).
// mota at 100 ties on every pair in both stores: tested in neither, no
// replication outcome.
TEST(Report, AgainstAnotherStoreSaysWhichFindingsReplicate) {
  const fs::path ten = HandStore("replicate-ten", "systematic", 10);
  const fs::path six = HandStore("replicate-six", "systematic", 6);
  EditStore(ten,
            "INSERT OR REPLACE INTO meta(name, value) VALUES ('root_seed', '1'), "
            "('root_seed_from', 'sweep "
            "file'), ('root_file_seed', '1')");
  EditStore(
      six,
      "INSERT OR REPLACE INTO meta(name, value) VALUES ('root_seed', '3'), ('root_seed_from', "
      "'--seed'), ('root_file_seed', '1')");
  ReportResult r = WriteReport({.dir = six.string(), .against = ten.string()});
  EXPECT_EQ(r.replication_comparisons, 3);
  std::string csv = Read(six / "replication.csv");
  EXPECT_NE(csv.find("100,charged,systematic,hijack_rate,10,-1,0.00195312,"), std::string::npos)
      << csv;
  EXPECT_NE(csv.find("100,charged,systematic,hijack_rate,10,-1,0.00195312,0.00390625,better,1,"),
            std::string::npos)
      << csv;
  EXPECT_NE(csv.find(",better,1,6,-1,0.03125,0.0625,better,0,replicated\n"), std::string::npos)
      << csv;
  EXPECT_EQ(csv.find("100,charged,systematic,mota,"), std::string::npos) << csv;
  EXPECT_NE(csv.find("1000,charged,systematic,hijack_rate,10,-0.5,0.0625,"), std::string::npos)
      << csv;
  EXPECT_NE(csv.find("1000,charged,systematic,mota,10,0.05,"), std::string::npos) << csv;
  EXPECT_NE(csv.find(",none,0,6,0.1,0.03125,0.0625,better,0,new here\n"), std::string::npos) << csv;
  EXPECT_EQ(Count(csv, "\n"), 4U) << csv;  // the header and 3 comparisons
  const std::string sentence =
      "Against `" + ten.string() +
      "` (runs of root seed 1; these runs: root seed 3), 3 comparisons are made in both stores. "
      "Of the 1 that is a finding there, 1 is a finding here in the same direction (0 of them "
      "kept by Holm's correction in both stores), 0 are weaker here (the same direction with p < "
      "0.05 or an interval that excludes 0, not both), 0 are not findings here and 0 are "
      "findings the other way. 1 comparison is a finding here and not there.";
  EXPECT_NE(Read(six / "findings.md").find("\n## Replication\n\n" + sentence + "\n"),
            std::string::npos)
      << Read(six / "findings.md");
  const std::string html = Read(r.html_path);
  EXPECT_NE(html.find("<h2 id=\"replication\">Replication</h2>\n<p>Against <code>" + ten.string() +
                      "</code> (runs of root seed 1;"),
            std::string::npos);
  EXPECT_LT(html.find("id=\"replication\""), html.find("<h2>Plots</h2>"));
  // At a glance, per metric: hijack_rate replicated at 100, mota new at 1000.
  EXPECT_NE(html.find("<tr><td class=\"k\">hijack_rate</td><td>1</td><td "
                      "style=\"background:#dff3df\">1</td><td>0</td><td>0</td><td>0</td><td>0</"
                      "td><td>1</td></tr>\n<tr><td class=\"k\">mota</td><td>0</td><td>0</td><td>0</"
                      "td><td>0</td><td>0</td><td>1</td><td>0</td></tr>"),
            std::string::npos)
      << html;
  // The table lists the two comparisons that are a finding in either store.
  EXPECT_EQ(Count(html, "replicated</td></tr>"), 1U);
  EXPECT_EQ(Count(html, "new here</td></tr>"), 1U);

  // The other way round: the 6-seed finding at 1000 is not one with 10 seeds.
  r = WriteReport({.dir = ten.string(), .against = six.string()});
  csv = Read(ten / "replication.csv");
  EXPECT_NE(csv.find("1000,charged,systematic,mota,6,0.1,0.03125,0.0625,better,0,10,0.05,"),
            std::string::npos)
      << csv;
  EXPECT_NE(csv.find(",none,0,not replicated\n"), std::string::npos) << csv;

  // Weaker here: with 5 seeds hijack_rate at 100 is −1 on every seed, its
  // interval [−1, −1], but the signed-rank test cannot go below 2/32 =
  // 0.0625: the same direction, one criterion of two. Not "not replicated"
  // (an audit found same-direction differences at p = 6e-5 called so).
  const fs::path five = HandStore("replicate-five", "systematic", 5);
  WriteReport({.dir = five.string(), .against = ten.string()});
  csv = Read(five / "replication.csv");
  EXPECT_NE(csv.find("100,charged,systematic,hijack_rate,10,-1,0.00195312,0.00390625,better,1,5,"
                     "-1,0.0625,"),
            std::string::npos)
      << csv;
  EXPECT_NE(csv.find(",none,0,weaker here\n"), std::string::npos) << csv;
  EXPECT_NE(Read(five / "findings.md").find("1 is weaker here (the same direction"),
            std::string::npos)
      << Read(five / "findings.md");

  // Reversed: with the values at 100 swapped, charged is worse in hijack_rate there.
  const fs::path swapped = HandStore("replicate-swapped", "systematic", 10);
  EditStore(swapped,
            "UPDATE runs SET hijack_rate = 1 - hijack_rate WHERE \"tracker.particles\" = "
            "'100'");
  WriteReport({.dir = swapped.string(), .against = ten.string()});
  csv = Read(swapped / "replication.csv");
  EXPECT_NE(csv.find("100,charged,systematic,hijack_rate,10,-1,0.00195312,0.00390625,better,1,10,"
                     "1,0.00195312,0.00390625,worse,1,reversed\n"),
            std::string::npos)
      << csv;
  // Tied in one store only: mota at 100 differs here (charged 0.95 against
  // 0.9 on every seed: p = 2/1024; 4 tested, floors 2/1024 three times and
  // 2/32: below 0.05 / 3 three, so Holm's first step has K = 3: 3 × 2/1024
  // = 0.00585938, and the second (K = 2, 4/1024) keeps it), ties there;
  // there's side has no p, no Holm p.
  const fs::path untied = HandStore("replicate-untied", "systematic", 10);
  EditStore(untied,
            "UPDATE runs SET mota = 0.95 WHERE \"tracker.particles\" = '100' AND "
            "\"tracker.resampling.method\" = 'charged'");
  WriteReport({.dir = untied.string(), .against = ten.string()});
  csv = Read(untied / "replication.csv");
  EXPECT_NE(
      csv.find("100,charged,systematic,mota,10,0,,,none,0,10,0.05,0.00195312,0.00585938,better,"
               "1,new here\n"),
      std::string::npos)
      << csv;
  EXPECT_NE(Read(untied / "findings.md")
                .find("4 comparisons are made in both stores (1 of them with every seed pair tied "
                      "in one store, tested in the other only;"),
            std::string::npos)
      << Read(untied / "findings.md");
  // A store without the cells at 1000: their 2 comparisons have no partner.
  const fs::path fewer = HandStore("replicate-fewer", "systematic", 10);
  EditStore(fewer, "DELETE FROM runs WHERE \"tracker.particles\" = '1000'");
  r = WriteReport({.dir = six.string(), .against = fewer.string()});
  EXPECT_EQ(r.replication_comparisons, 1);  // hijack_rate at 100 (mota there ties in both)
  // Its 2 cells at 1000 have no interval there (4 cell means: 2 cells x 2 metrics).
  EXPECT_NE(Read(six / "findings.md").find("overlap; 4 cell means here have no interval there."),
            std::string::npos)
      << Read(six / "findings.md");
  EXPECT_NE(Read(six / "findings.md")
                .find("2 comparisons of this report have no partner there and 0 there none here"),
            std::string::npos)
      << Read(six / "findings.md");
  WriteReport({.dir = fewer.string(), .against = six.string()});
  EXPECT_NE(Read(fewer / "findings.md")
                .find("0 comparisons of this report have no partner there and 2 there none here"),
            std::string::npos)
      << Read(fewer / "findings.md");
  // A copy of the store (the same root seed): the same runs, said to be no
  // replication. The store itself is refused, as a run's --against refuses
  // its DIR (a fourth bad-input audit: accepted).
  const fs::path copy = testing::SweepFolder("replicate-ten-copy");  // removed when it passes
  fs::copy(ten, copy, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  EXPECT_NE(Read(WriteReport({.dir = ten.string(), .against = copy.string()}).html_path)
                .find("so matching runs are the same runs: this is no replication."),
            std::string::npos);
  try {
    WriteReport({.dir = ten.string(), .against = ten.string()});
    ADD_FAILURE() << "a store against itself was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--against: expected a sweep folder (results.sqlite) over "
                                         "the same swept keys, other than DIR, found "),
              std::string::npos)
        << e.what();
  }
  // Without --against, an earlier replication.csv goes.
  WriteReport({.dir = ten.string()});
  EXPECT_FALSE(fs::exists(ten / "replication.csv"));
  // A report folder (--out) holding an earlier replication.csv is an earlier report's.
  const fs::path elsewhere = testing::SweepFolder("replicate-out") / "report";
  WriteReport({.dir = six.string(), .out_dir = elsewhere.string(), .against = ten.string()});
  EXPECT_TRUE(fs::exists(elsewhere / "replication.csv"));
  EXPECT_NO_THROW(WriteReport({.dir = six.string(), .out_dir = elsewhere.string()}));
  EXPECT_FALSE(fs::exists(elsewhere / "replication.csv"));

  // Bad input: no such folder, a store over other keys.
  const auto error_of = [&](const std::string& against) {
    try {
      WriteReport({.dir = six.string(), .against = against});
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("(no error)");
  };
  EXPECT_NE(error_of((six / "nosuch").string())
                .find("--against: expected a sweep folder (results.sqlite) over the same swept "
                      "keys, found " +
                      (six / "nosuch").string() + ": no such folder"),
            std::string::npos);
  // Checked before anything is written: --out is not made.
  EXPECT_THROW(WriteReport({.dir = six.string(),
                            .out_dir = (six / "report-out").string(),
                            .against = (six / "nosuch").string()}),
               InputError);
  EXPECT_FALSE(fs::exists(six / "report-out"));
  const fs::path other = testing::SweepFolder("replicate-other-keys");
  {
    StoreMeta meta;
    meta.sweep_hash = "other";
    meta.sweep_file = "other.yaml";
    meta.swept_keys = {"tracker.particles"};
    meta.report.y = {"mota"};
    ResultsStore::OpenOrCreate((other / "results.sqlite").string(), meta);
  }
  EXPECT_NE(error_of(other.string())
                .find("over the same swept keys (tracker.particles, tracker.resampling.method), "
                      "found " +
                      other.string() + " sweeping tracker.particles"),
            std::string::npos)
      << error_of(other.string());
  // Cell by cell (six against ten, every cell and metric with an interval
  // in both: 8): each mean here against the interval there. By hand: 7 of 8
  // inside (systematic's hijack rate at 100 is 1 in both, at the upper bound
  // of 10 of 10's Wilson interval [0.7225, 1]); systematic's hijack rate at
  // 1000 is 5 of 6 = 0.833 here, outside 5 of 10's interval [0.199, 0.801]
  // there (Korn & Graubard: n* = p(1 − p) / (s² / n) = 9, t with 9 degrees
  // of freedom), and its own interval (n* = 5, t with 5: [0.304, 0.983])
  // overlaps it, as all 8 do.
  r = WriteReport({.dir = six.string(), .against = ten.string()});
  EXPECT_EQ(r.replication_cells, 8);
  const std::string cells_sentence =
      "Cell by cell: of the 8 cell means measured with an interval in both stores (cells \u00d7 "
      "metrics), 7 lie inside the other store's 95 % interval of the same cell and 8 of the two "
      "intervals overlap.";
  EXPECT_NE(Read(six / "findings.md").find(sentence + "\n\n" + cells_sentence), std::string::npos)
      << Read(six / "findings.md");
  const std::string cells_csv = Read(six / "replication_cells.csv");
  EXPECT_EQ(Count(cells_csv, "\n"), 9U) << cells_csv;
  EXPECT_NE(cells_csv.find("1000,systematic,hijack_rate,10,0.5,0.198"), std::string::npos)
      << cells_csv;
  EXPECT_NE(cells_csv.find("1000,systematic,hijack_rate,10,0.5,0.198979,0.801021,6,0.833333,"
                           "0.304303,0.982805,0,1\n"),
            std::string::npos)
      << cells_csv;
  EXPECT_EQ(Count(cells_csv, ",0,1\n"), 1U) << cells_csv;  // the one outside, overlapping
  EXPECT_EQ(Count(Read(r.html_path), "<td class=\"k\">yes</td></tr>"), 1U);

  // Without report.series: no paired comparisons, the cells all the same.
  EditStore(six,
            "UPDATE meta SET value = '{\"x\":\"tracker.particles\",\"y\":[\"hijack_rate\","
            "\"mota\"]}' WHERE name = 'report'");
  r = WriteReport({.dir = six.string(), .against = ten.string()});
  EXPECT_EQ(r.replication_comparisons, 0);
  EXPECT_EQ(r.replication_cells, 8);
  EXPECT_FALSE(fs::exists(six / "replication.csv"));
  EXPECT_TRUE(fs::exists(six / "replication_cells.csv"));
  EXPECT_NE(Read(r.html_path)
                .find("(runs of root seed 1; these runs: root seed 3): without "
                      "<code>report.series</code> there are no paired comparisons to make "
                      "again.</p>"),
            std::string::npos);
}

// A sweep of four runs: systematic against charged resampling, two seeds.
constexpr const char* kFourRuns =
    "base: base.yaml\nseeds: 2\ngrid:\n  tracker.particles: [20]\n"
    "  tracker.resampling.method: [systematic, charged]\n"
    "report: {x: tracker.particles, series: tracker.resampling.method, y: [idf1]}\n";

// The scene sketch is of the first run of a cell whose folder is there (a
// bad-input audit: with the first run's folder deleted it said "its folder
// has no gt.json").
TEST(Report, TheSceneSketchTakesARunWhoseFolderIsThere) {
  const auto dir = testing::SweepFolder("report-sketch-folder");
  const SweepSpec spec = LoadSweepFile(testing::WriteSweep(dir, kFourRuns, "s.yaml"));
  const std::vector<SweepRun> runs = ExpandSweep(spec);
  const fs::path out = RunQuietly(spec, dir);
  fs::remove_all(out / "runs" / runs[0].key);
  const std::string html = Read(WriteReport({.dir = out.string()}).html_path);
  EXPECT_EQ(html.find("No sketch of"), std::string::npos);
  EXPECT_NE(html.find("<p>run " + runs[1].key + " (seed index 1; "), std::string::npos);
}

// Two compared cells with no seed in common (a shard, a sweep stopped early)
// have no seed pairs, and the findings say why without blaming the metric (a
// fourth bad-input audit: "the metric is absent from one of them").
TEST(Report, CellsWithoutACommonSeedHaveNoPairsAndSayWhy) {
  const auto dir = testing::SweepFolder("report-no-common-seed");
  const SweepSpec spec = LoadSweepFile(testing::WriteSweep(dir, kFourRuns, "s.yaml"));
  const fs::path out = RunQuietly(spec, dir);
  EditStore(out,
            "DELETE FROM runs WHERE (\"tracker.resampling.method\" = 'charged' AND seed_index = 0) "
            "OR (\"tracker.resampling.method\" = 'systematic' AND seed_index = 1)");
  WriteReport({.dir = out.string()});
  EXPECT_NE(Read(out / "findings.md")
                .find("charged \u2212 systematic: no seed pairs (no seed has a value of the metric "
                      "in both: its runs are not in this store, failed, or lack the metric)."),
            std::string::npos)
      << Read(out / "findings.md");
}

// A store's report.reference that no run has (a bad-input audit: edited to
// "nope", the report said "0 compared cells" and nothing else, exit 0): the
// findings say why nothing is compared.
TEST(Report, SaysWhenNoRunHasTheReferenceValue) {
  const auto dir = testing::SweepFolder("report-reference-absent");
  const SweepSpec spec = LoadSweepFile(testing::WriteSweep(dir, kFourRuns, "s.yaml"));
  const fs::path out = RunQuietly(spec, dir);
  EditStore(out,
            "UPDATE meta SET value = '{\"x\":\"tracker.particles\",\"y\":[\"idf1\"],"
            "\"series\":\"tracker.resampling.method\",\"reference\":\"nope\"}' "
            "WHERE name = 'report'");
  const ReportResult r = WriteReport({.dir = out.string()});
  EXPECT_EQ(r.comparisons, 0);
  EXPECT_NE(Read(r.html_path)
                .find("This report tests no comparison: no run has the reference value "
                      "tracker.resampling.method = nope (report.reference), so no cell has a "
                      "partner."),
            std::string::npos);
}

// The report names the build of hcpf that made the runs (the store keeps each
// run's, from its manifest, when the run is put), and says in bold when they
// are several: here one row says another revision, as after a rebuild and a
// resume. The manifests are not read again: they are deleted first.
TEST(Report, SaysWhichBuildsMadeTheRuns) {
  const auto dir = testing::SweepFolder("report-builds");
  const SweepSpec spec = LoadSweepFile(testing::WriteSweep(dir, kFourRuns, "s.yaml"));
  const std::string out = RunQuietly(spec, dir);
  const std::string here = scenarios::ProjectVersion() + " at " + scenarios::GitRevision();
  const std::vector<RunRecord> runs =
      ResultsStore::Open((fs::path(out) / "results.sqlite").string())->Runs();
  ASSERT_EQ(runs.size(), 4U);
  for (const RunRecord& run : runs) {
    EXPECT_EQ(run.build, here);
    fs::remove(fs::path(out) / run.run_dir / "manifest.json");
  }
  ReportResult r = WriteReport({.dir = out});
  EXPECT_EQ(r.builds, 1);
  EXPECT_NE(Read(r.html_path)
                .find("<p>Every finished run that names its build was made by one: hcpf <code>" +
                      here + "</code>.</p>"),
            std::string::npos);
  EditStore(out, "UPDATE runs SET build = '" + scenarios::ProjectVersion() +
                     " at 0123456789ab' WHERE key = '" + runs[2].key + "'");
  r = WriteReport({.dir = out});
  EXPECT_EQ(r.builds, 2);
  EXPECT_NE(
      Read(r.html_path)
          .find("<p><strong>The finished runs were made by 2 builds of hcpf</strong>: <code>" +
                here + "</code> (3 runs), <code>" + scenarios::ProjectVersion() +
                " at 0123456789ab</code> (1 run)."),
      std::string::npos);
  // A run whose manifest named no build: counted apart, not a build.
  EditStore(out, "UPDATE runs SET build = '' WHERE key = '" + runs[2].key + "'");
  r = WriteReport({.dir = out});
  EXPECT_EQ(r.builds, 1);
  EXPECT_NE(
      Read(r.html_path)
          .find("<p>Every finished run that names its build was made by one: hcpf <code>" + here +
                "</code>. 1 finished run names no build (a <code>manifest.json</code> "
                "missing, unreadable or without <code>git_revision</code>).</p>"),
      std::string::npos);
}

// A report of one shard of two says, in bold and in findings.md, how many of
// the sweep's runs are missing and how to get them; resumed whole, it says
// nothing of it (a bad-input audit: a report of a sweep stopped early named
// a best series among runs of one series only, exit 0 and no word).
TEST(Report, OfAShardSaysHowManyRunsAreMissing) {
  const auto dir = testing::SweepFolder("report-shard");
  const SweepSpec spec = LoadSweepFile(testing::WriteSweep(dir, kFourRuns, "s.yaml"));
  SweepOptions o;
  o.out_dir = (dir / "out").string();
  o.progress = false;
  o.shard_index = 0;
  o.shard_count = 2;
  RunSweep(spec, ExpandSweep(spec), o);
  const std::string sentence =
      "The store holds 2 of the sweep's 4 runs: 2 are missing (a sweep stopped before its end, "
      "or one shard of several: resume it with the same ";
  ReportResult r = WriteReport({.dir = o.out_dir});
  EXPECT_EQ(r.missing_runs, 2);
  EXPECT_NE(
      Read(r.html_path).find("<p class=\"failed\"><strong>" + sentence + "<code>hcpf sweep</code>"),
      std::string::npos);
  EXPECT_NE(Read(fs::path(o.out_dir) / "findings.md").find("**" + sentence + "`hcpf sweep`"),
            std::string::npos);
  o.shard_count = 1;
  RunSweep(spec, ExpandSweep(spec), o);
  r = WriteReport({.dir = o.out_dir});
  EXPECT_EQ(r.missing_runs, 0);
  EXPECT_EQ(Read(r.html_path).find("The store holds"), std::string::npos);
  EXPECT_EQ(Read(fs::path(o.out_dir) / "findings.md").find("The store holds"), std::string::npos);
}

// A store stopped before its first run (or a shard given none) over
// particle counts, whose axis is logarithmic when it has values: the report
// is written, says every run is missing, and leaves no work folder. Until
// 2026-12-06 its x range was [nan:nan] on a log axis and gnuplot failed the
// report (exit 1, .report-work left behind: an audit).
TEST(Report, OfAStoreWithoutRunsIsWritten) {
  const auto dir = testing::SweepFolder("report-no-runs");
  {
    auto store = ResultsStore::OpenOrCreate((dir / "results.sqlite").string(),
                                            HandMeta({"tracker.particles"}, "", {"mota"}, 2));
  }
  ReportResult r;
  ASSERT_NO_THROW(r = WriteReport({.dir = dir.string()}));
  EXPECT_EQ(r.missing_runs, 2);
  EXPECT_NE(Read(r.html_path).find("The store holds 0 of the sweep's 2 runs"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / ".report-work"));
}

// A store written before the build column: the report (which opens it
// read-only, and leaves it so) reads each finished run's manifest instead;
// a missing manifest names no build.
TEST(Report, ReadsTheBuildsOfAnOlderStoreFromTheManifests) {
  const auto dir = testing::SweepFolder("report-builds-old");
  const SweepSpec spec = LoadSweepFile(testing::WriteSweep(dir, kFourRuns, "s.yaml"));
  const std::string out = RunQuietly(spec, dir);
  EditStore(out, "ALTER TABLE runs DROP COLUMN build");
  const std::string here = scenarios::ProjectVersion() + " at " + scenarios::GitRevision();
  const std::vector<RunRecord> runs =
      ResultsStore::Open((fs::path(out) / "results.sqlite").string())->Runs();
  ASSERT_EQ(runs.size(), 4U);
  EXPECT_FALSE(runs[2].build.has_value());
  const fs::path manifest = fs::path(out) / runs[2].run_dir / "manifest.json";
  auto m = nlohmann::json::parse(Read(manifest));
  EXPECT_EQ(m["hcpf_version"], scenarios::ProjectVersion());
  m["git_revision"] = "0123456789ab";
  std::ofstream(manifest) << m.dump();
  ReportResult r = WriteReport({.dir = out});
  EXPECT_EQ(r.builds, 2);
  EXPECT_NE(
      Read(r.html_path)
          .find("<p><strong>The finished runs were made by 2 builds of hcpf</strong>: <code>" +
                here + "</code> (3 runs), <code>" + scenarios::ProjectVersion() +
                " at 0123456789ab</code> (1 run)."),
      std::string::npos);
  fs::remove(manifest);
  r = WriteReport({.dir = out});
  EXPECT_EQ(r.builds, 1);
  EXPECT_NE(
      Read(r.html_path)
          .find("<p>Every finished run that names its build was made by one: hcpf <code>" + here +
                "</code>. 1 finished run names no build (a <code>manifest.json</code> "
                "missing, unreadable or without <code>git_revision</code>).</p>"),
      std::string::npos);
  EXPECT_FALSE(
      ResultsStore::Open((fs::path(out) / "results.sqlite").string())->Runs()[0].build.has_value());
}

// Where the runs' seeds come from is stored with the sweep and said by its
// report: the file's seed:, hcpf sweep --seed (with the file's own seed), or
// the base scenario's seed when the sweep has no seeds:. Resuming with the
// same runs from a file that writes the seed takes the new source; a store
// written before the root seed was recorded says so, and is filled in when
// a sweep resumes into it.
TEST(Report, SaysWhereTheRunsSeedsComeFrom) {
  const auto dir = testing::SweepFolder("report-root-seed");
  const std::string body = kFourRuns;
  SweepSpec spec = LoadSweepFile(testing::WriteSweep(dir, body, "s.yaml"));
  SetRootSeed(spec, "41", "--seed");
  const std::string out = RunQuietly(spec, dir);
  const std::string store_path = (fs::path(out) / "results.sqlite").string();
  StoreMeta meta = ResultsStore::Open(store_path)->meta();
  EXPECT_EQ(meta.root_seed, "41");
  EXPECT_EQ(meta.root_seed_from, "--seed");
  EXPECT_EQ(meta.root_file_seed, "1");
  ReportResult r = WriteReport({.dir = out});
  EXPECT_NE(Read(r.html_path)
                .find("<p>The runs' seeds are derived from root seed 41, given by <code>hcpf sweep "
                      "--seed 41</code> (the sweep file's <code>seed:</code> is 1).</p>"),
            std::string::npos);

  // The same runs from a file that says seed: 41: resumed, nothing computed,
  // and the report now names the file as the source.
  const SweepSpec written =
      LoadSweepFile(testing::WriteSweep(dir, body + "seed: 41\n", "s41.yaml"));
  SweepOptions o;
  o.out_dir = out;
  o.jobs = 2;
  o.progress = false;
  EXPECT_EQ(RunSweep(written, ExpandSweep(written), o).computed, 0);
  meta = ResultsStore::Open(store_path)->meta();
  EXPECT_EQ(meta.root_seed, "41");
  EXPECT_EQ(meta.root_seed_from, "sweep file");
  r = WriteReport({.dir = out});
  EXPECT_NE(Read(r.html_path)
                .find("<p>The runs' seeds are derived from root seed 41, the sweep file's "
                      "<code>seed:</code>.</p>"),
            std::string::npos);

  // A store of before: no root seed rows (nor the expansion, recorded
  // later). Read as not recorded, said so.
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open(store_path.c_str(), &db), SQLITE_OK);
    ASSERT_EQ(sqlite3_exec(db, "DELETE FROM meta WHERE name LIKE 'root%' OR name = 'expansion'",
                           nullptr, nullptr, nullptr),
              SQLITE_OK);
    sqlite3_close(db);
  }
  meta = ResultsStore::Open(store_path)->meta();
  EXPECT_EQ(meta.root_seed_from, "");
  EXPECT_EQ(RootSeedSentence(meta),
            "The store does not record the sweep's root seed (it was written before hcpf "
            "recorded one).");
  EXPECT_NE(Read(WriteReport({.dir = out}).html_path).find("does not record the sweep's root seed"),
            std::string::npos);
  // Resumed into: filled in.
  EXPECT_EQ(RunSweep(written, ExpandSweep(written), o).computed, 0);
  EXPECT_EQ(ResultsStore::Open(store_path)->meta().root_seed_from, "sweep file");

  // No seeds: every run keeps its base scenario's seed.
  StoreMeta seedless;
  SetRootSeedMeta(LoadSweepFile(testing::WriteSweep(
                      dir, "base: base.yaml\ngrid: {tracker.particles: [20]}\n", "n.yaml")),
                  seedless);
  EXPECT_EQ(seedless.root_seed, "");
  EXPECT_EQ(RootSeedSentence(seedless),
            "Every run keeps its base scenario's seed (the sweep has no `seeds:`).");
}

}  // namespace
}  // namespace hcpf::studies
