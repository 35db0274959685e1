// Sweep files: expansion order against hand-worked cases, seeds, validation errors.

#include "hcpf/studies/sweep.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>
#include <vector>

#include "hcpf/core/rng.h"
#include "hcpf/renderer/renderer.h"
#include "hcpf/scenarios/frames.h"
#include "hcpf/studies/run_queue.h"
#include "sweep_fixture.h"
#include "sweep_plan.h"

namespace hcpf::studies {
namespace {

namespace fs = std::filesystem;
using testing::SweepFolder;
using testing::WriteSweep;

std::string ErrorOf(const std::string& path) {
  try {
    LoadSweepFile(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

std::string ExpandErrorOf(const std::string& path) {
  try {
    ExpandSweep(LoadSweepFile(path));
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(Sweep, GridZipSeedsExpansionOrder) {
  const auto dir = SweepFolder("expand");
  const std::string path =
      WriteSweep(dir,
                 "base: base.yaml\n"
                 "seeds: 2\n"
                 "grid:\n"
                 "  tracker.particles: [10, 20]\n"
                 "  tracker.resampling.method: [systematic, charged, stratified]\n"
                 "zip:\n"
                 "  tracker.likelihood.sigma_px: [2, 4]\n"
                 "  observation.simulated.sigma_px: [1, 3]\n");
  const SweepSpec spec = LoadSweepFile(path);
  ASSERT_EQ(spec.RunCount(), 2 * 3 * 2 * 2);
  const std::vector<SweepRun> runs = ExpandSweep(spec);
  ASSERT_EQ(runs.size(), 24U);
  // Hand-worked: index = ((g0 * 3 + g1) * 2 + zip) * 2 + seed.
  struct Expected {
    int index;
    int particles;
    const char* method;
    double lik_sigma;
    double obs_sigma;
    int seed_index;
  };
  const Expected cases[] = {
      {0, 10, "systematic", 2, 1, 0},  {1, 10, "systematic", 2, 1, 1},
      {2, 10, "systematic", 4, 3, 0},  {4, 10, "charged", 2, 1, 0},
      {11, 10, "stratified", 4, 3, 1}, {12, 20, "systematic", 2, 1, 0},
      {23, 20, "stratified", 4, 3, 1},
  };
  for (const Expected& e : cases) {
    const SweepRun& r = runs[e.index];
    SCOPED_TRACE(e.index);
    EXPECT_EQ(r.index, e.index);
    EXPECT_EQ(r.scenario().tracker.particles, e.particles);
    EXPECT_EQ(r.values[1], e.method);
    EXPECT_DOUBLE_EQ(r.scenario().tracker.likelihood.sigma_px, e.lik_sigma);
    EXPECT_DOUBLE_EQ(r.scenario().observation.simulated.sigma_px, e.obs_sigma);
    EXPECT_EQ(r.seed_index, e.seed_index);
    // The documented derivation, written out independently of SweepSeed.
    EXPECT_EQ(r.scenario().seed,
              Rng(1).Fork("sweep/seed/" + std::to_string(e.seed_index)).identity());
  }
  // Keys: one per run, all different (every run differs in a value or seed).
  std::set<std::string> keys;
  for (const SweepRun& r : runs) keys.insert(r.key);
  EXPECT_EQ(keys.size(), runs.size());
  // Deterministic: expanding again gives the same keys and hash.
  EXPECT_EQ(SweepHash(ExpandSweep(LoadSweepFile(path))), SweepHash(runs));
}

// grid.base sweeps the base scenario: each grid combination's runs start
// from its file (told apart here by the scenario's name, which no override
// touches), the other keys apply to both, and `base` is a swept key.
TEST(Sweep, GridBaseSweepsTheBaseScenarioFile) {
  const auto dir = SweepFolder("grid-base");
  std::string other = scenarios::testing::kMinimal;
  other.replace(other.find("name: minimal"), 13, "name: second");
  std::ofstream(dir / "second.yaml") << other;
  const std::string path = WriteSweep(dir,
                                      "seeds: 2\n"
                                      "grid:\n"
                                      "  base: [base.yaml, second.yaml]\n"
                                      "  tracker.particles: [10, 20]\n"
                                      "report: {x: tracker.particles, panels: base}\n");
  const SweepSpec spec = LoadSweepFile(path);
  EXPECT_EQ(spec.SweptKeys(), (std::vector<std::string>{"base", "tracker.particles"}));
  ASSERT_EQ(spec.base_paths.size(), 2U);
  EXPECT_EQ(spec.base_path, spec.base_paths[0]);
  EXPECT_EQ(spec.report.panels, "base");
  const std::vector<SweepRun> runs = ExpandSweep(spec);
  ASSERT_EQ(runs.size(), 8U);
  // index = (base * 2 + particles) * 2 + seed.
  const struct {
    int index;
    const char* name;
    int particles;
  } cases[] = {{0, "minimal", 10}, {3, "minimal", 20}, {4, "second", 10}, {7, "second", 20}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.index);
    EXPECT_EQ(runs[c.index].scenario().name, c.name);
    EXPECT_EQ(runs[c.index].scenario().tracker.particles, c.particles);
    EXPECT_EQ(runs[c.index].values[0], c.index < 4 ? "base.yaml" : "second.yaml");
    // The base is not an override: only the swept key and the seed are.
    ASSERT_EQ(runs[c.index].overrides.size(), 2U);
    EXPECT_EQ(runs[c.index].overrides[0].key, "tracker.particles");
  }
  // Seeds are derived alike for both bases.
  EXPECT_EQ(runs[0].scenario().seed, runs[4].scenario().seed);
}

TEST(Sweep, GridBaseErrorsNameTheLine) {
  const auto dir = SweepFolder("grid-base-errors");
  // Both a top-level base and grid.base.
  std::string e = ErrorOf(WriteSweep(dir, "base: base.yaml\ngrid:\n  base: [base.yaml]\n"));
  EXPECT_NE(e.find("sweep.yaml:1:"), std::string::npos) << e;
  EXPECT_NE(e.find("no top-level base"), std::string::npos) << e;
  // A missing file, at its line and column.
  e = ErrorOf(WriteSweep(dir, "grid:\n  base: [base.yaml, nope.yaml]\n"));
  EXPECT_NE(e.find("sweep.yaml:2:21:"), std::string::npos) << e;
  EXPECT_NE(e.find("a scenario file"), std::string::npos) << e;
  // In zip.
  e = ErrorOf(WriteSweep(dir, "base: base.yaml\nzip:\n  base: [base.yaml]\n"));
  EXPECT_NE(e.find("grid: {base:"), std::string::npos) << e;
  // Not a path.
  e = ErrorOf(WriteSweep(dir, "grid:\n  base: [[1, 2]]\n"));
  EXPECT_NE(e.find("expected a scenario file"), std::string::npos) << e;
  // Neither base nor grid.base: base is required.
  e = ErrorOf(WriteSweep(dir, "grid:\n  tracker.particles: [10]\n"));
  EXPECT_NE(e.find("base"), std::string::npos) << e;
  // report.panels: a swept key other than x.
  e = ErrorOf(WriteSweep(dir,
                         "base: base.yaml\ngrid:\n  tracker.particles: [10, 20]\n"
                         "report: {x: tracker.particles, panels: tracker.particles}\n"));
  EXPECT_NE(e.find("report.panels"), std::string::npos) << e;
  e = ErrorOf(WriteSweep(dir,
                         "base: base.yaml\ngrid:\n  tracker.particles: [10, 20]\n"
                         "report: {x: tracker.particles, panels: bse}\n"));
  EXPECT_NE(e.find("a swept key"), std::string::npos) << e;
}

// report.reference: a value of report.series as the sweep file writes it,
// stored with the report spec; errors name the file, line, key, what was
// expected and what was found.
TEST(Sweep, ReportReferenceIsAValueOfTheSeries) {
  const auto dir = SweepFolder("report-reference");
  const std::string grid =
      "base: base.yaml\ngrid:\n  tracker.particles: [10, 20]\n"
      "  tracker.resampling.method: [systematic, charged]\n";
  const SweepSpec spec = LoadSweepFile(
      WriteSweep(dir, grid + "report: {series: tracker.resampling.method, reference: charged}\n"));
  EXPECT_EQ(spec.report.reference, "charged");
  EXPECT_EQ(LoadSweepFile(WriteSweep(dir, grid + "report: {series: tracker.resampling.method}\n"))
                .report.reference,
            "");
  // Not a value of the series: the values, and the closest one.
  std::string e = ErrorOf(WriteSweep(
      dir, grid + "report:\n  series: tracker.resampling.method\n  reference: systematc\n"));
  EXPECT_NE(e.find("sweep.yaml:7:14: report.reference"), std::string::npos) << e;
  EXPECT_NE(e.find("report.reference"), std::string::npos) << e;
  EXPECT_NE(e.find("a value of report.series tracker.resampling.method (systematic, charged)"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("\"systematc\""), std::string::npos) << e;
  EXPECT_NE(e.find("did you mean \"systematic\"?"), std::string::npos) << e;
  // Without a series there is nothing to refer to.
  e = ErrorOf(WriteSweep(dir, grid + "report: {reference: charged}\n"));
  EXPECT_NE(e.find("no report.reference without report.series"), std::string::npos) << e;
  // A misspelt key is refused like any unknown key.
  e = ErrorOf(WriteSweep(dir, grid + "report: {series: tracker.resampling.method, referense: "
                                     "charged}\n"));
  EXPECT_NE(e.find("referense"), std::string::npos) << e;
  // An empty reference, or an x_metric that is a list, is refused, not read
  // as absent (CheckReportRules reads "" as absent).
  e = ErrorOf(
      WriteSweep(dir, grid + "report: {series: tracker.resampling.method, reference: \"\"}\n"));
  EXPECT_NE(e.find("report.reference: expected a value of report.series"), std::string::npos) << e;
  e = ErrorOf(WriteSweep(dir, grid + "report: {x: tracker.particles, x_metric: [idf1]}\n"));
  EXPECT_NE(e.find("report.x_metric"), std::string::npos) << e;
}

// A scenario file given to hcpf sweep (none of base, grid, zip) is said to
// be one, at its first line, with the command that runs it; until
// 2026-12-06 the error was a missing `base:` at the file's first key (an
// audit).
TEST(Sweep, AScenarioFileIsNoSweepAndTheErrorSaysHowToRunIt) {
  const auto dir = SweepFolder("scenario-as-sweep");
  try {
    LoadSweepFile(WriteSweep(dir, "\nname: a scenario\ntracker:\n  particles: 50\n"));
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, 1);
    EXPECT_EQ(e.found(), "none of base, grid or zip");
    EXPECT_NE(e.hint().find("a scenario file is run by hcpf run FILE --out DIR"), std::string::npos)
        << e.hint();
  }
}

// The warning before a sweep runs, by hand. particles {10, 20} x method
// {systematic, charged}, series method, the 6 default report metrics, of
// which 5 are tested (ms_per_frame, a timing, is not): 2 compared cells x 5
// = 10 comparisons, Holm's first step p < 0.05 / 10 = 0.005. 10 seeds: p
// can reach 2/1024 = 0.00195, no warning; 8 seeds: 2/256 = 0.0078, a
// warning, and 9 pairs (2/512 = 0.0039) are needed. With Tarone's rule the
// first step's K for ten floors of 0.0078 is 7: below 0.05 / k all ten up to
// k = 6 (0.0083), none at 7 (0.00714); 0.0078 could be kept among 6 (6 ×
// 0.0078 = 0.047).
TEST(Sweep, SeedsTooFewForHolmAreSaidBeforeTheSweepRuns) {
  const auto dir = SweepFolder("holm-note");
  const std::string grid =
      "base: base.yaml\ngrid:\n  tracker.particles: [10, 20]\n"
      "  tracker.resampling.method: [systematic, charged]\n"
      "report: {series: tracker.resampling.method}\n";
  EXPECT_EQ(SeedsForHolmNote(LoadSweepFile(WriteSweep(dir, grid + "seeds: 10\n"))), "");
  std::string note = SeedsForHolmNote(LoadSweepFile(WriteSweep(dir, grid + "seeds: 8\n")));
  EXPECT_NE(
      note.find("with 8 seeds each paired comparison of the report "
                "(tracker.resampling.method against systematic) has 8 pairs: the "
                "signed-rank test cannot give p below 0.00781, and Holm's correction over "
                "the report's 10 paired comparisons needs p < 0.00714 for its first "
                "(Tarone's rule: K = 7), so none can survive it unless ties (seeds where both "
                "runs have the same value) leave 6 or fewer comparisons at this floor, "
                "whatever the data. 9 seeds at least are needed "
                "(more where some seeds tie"),
      std::string::npos)
      << note;
  EXPECT_NE(note.find("sweep.yaml: "), std::string::npos) << note;
  // 2 seeds: p cannot reach 0.05 at all (2/4 = 0.5).
  note = SeedsForHolmNote(LoadSweepFile(WriteSweep(dir, grid + "seeds: 2\n")));
  EXPECT_NE(note.find("cannot give p below 0.5, so no comparison can be a finding"),
            std::string::npos)
      << note;
  // No series: nothing is paired, nothing is said.
  EXPECT_EQ(SeedsForHolmNote(LoadSweepFile(WriteSweep(
                dir, "base: base.yaml\nseeds: 2\ngrid:\n  tracker.particles: [10, 20]\n"))),
            "");
  // One seed, or no `seeds:` (one run per cell on the base file's seed): one
  // pair per comparison, no interval; said, with the 9 seeds needed (until
  // 2026-12-06 nothing was said: the report just had no findings).
  note = SeedsForHolmNote(LoadSweepFile(WriteSweep(dir, grid + "seeds: 1\n")));
  EXPECT_TRUE(note.ends_with(
      "/sweep.yaml: with 1 seed each cell of the report runs once, so it has no interval "
      "and its paired comparisons (tracker.resampling.method against systematic) one pair "
      "each: none can be a finding, whatever the data. 9 seeds at least are needed (more "
      "where some seeds tie or differ the other way); docs/sweeps.md, \"Seeds enough for "
      "Holm\""))
      << note;
  note = SeedsForHolmNote(LoadSweepFile(WriteSweep(dir, grid)));
  EXPECT_NE(note.find("sweep.yaml: without `seeds:` (the base file's seed alone) each cell of "
                      "the report runs once"),
            std::string::npos)
      << note;
  // Pooled values add no pairs: a seed's pooled runs share its random
  // streams and are averaged into one pair of means. Sigma (x) {2, 4} x
  // particles {10, 20, 40} pooled x method, y [mota]: 2 comparisons (p <
  // 0.025). 6 seeds x 3 pooled values: 6 pairs (not 18, whose floor 2/2^18
  // would say nothing), 2/64 = 0.03125: a warning, 7 seeds needed; with 7
  // seeds (2/128) none.
  const std::string pooled =
      "base: base.yaml\ngrid:\n  tracker.likelihood.sigma_px: [2, 4]\n"
      "  tracker.particles: [10, 20, 40]\n  tracker.resampling.method: [systematic, charged]\n"
      "report: {x: tracker.likelihood.sigma_px, series: tracker.resampling.method, pool: "
      "[tracker.particles], y: [mota]}\n";
  note = SeedsForHolmNote(LoadSweepFile(WriteSweep(dir, pooled + "seeds: 6\n")));
  // One pooled key written alone is read as a list of one, as report.y's
  // one metric is (until 2026-12-06 refused: an audit).
  {
    std::string alone = pooled;
    const std::string list = "pool: [tracker.particles]";
    alone.replace(alone.find(list), list.size(), "pool: tracker.particles");
    const SweepSpec spec = LoadSweepFile(WriteSweep(dir, alone + "seeds: 6\n", "alone.yaml"));
    EXPECT_EQ(spec.report.pool, std::vector<std::string>{"tracker.particles"});
    EXPECT_EQ(SeedsForHolmNote(spec).substr(SeedsForHolmNote(spec).find("with 6 seeds")),
              note.substr(note.find("with 6 seeds")));
  }
  EXPECT_NE(note.find("with 6 seeds each paired comparison of the report "
                      "(tracker.resampling.method against systematic) has 6 pairs (the runs of "
                      "its 3 pooled values are averaged in each seed): the "
                      "signed-rank test cannot give p below 0.0312, and Holm's correction over "
                      "the report's 2 paired comparisons needs p < 0.025 for its first (Tarone's "
                      "rule: K = 2), so none can survive it unless ties (seeds where both runs "
                      "have the same value) leave 1 or fewer comparisons at this floor"),
            std::string::npos)
      << note;
  EXPECT_NE(note.find("7 seeds at least are needed (more where"), std::string::npos) << note;
  EXPECT_EQ(SeedsForHolmNote(LoadSweepFile(WriteSweep(dir, pooled + "seeds: 7\n"))), "");
  // A pooled key zipped with one that is not pools nothing: method x 3 zip
  // positions of (azimuth, particles), azimuth pooled, y [mota]: each
  // position is its own cell, 3 comparisons (p < 0.0167), and 6 seeds'
  // floor 2/64 = 0.03125 cannot reach it. The note counted the 3 azimuths
  // as pooled (1 comparison, p < 0.05) and said nothing.
  {
    const std::string half_pooled =
        "base: base.yaml\ngrid:\n  tracker.resampling.method: [systematic, charged]\nzip:\n"
        "  world.sun.azimuth_deg: [0, 90, 180]\n  tracker.particles: [10, 20, 40]\n"
        "report: {x: tracker.particles, series: tracker.resampling.method, pool: "
        "[world.sun.azimuth_deg], y: [mota]}\n";
    note = SeedsForHolmNote(LoadSweepFile(WriteSweep(dir, half_pooled + "seeds: 6\n")));
    EXPECT_NE(note.find("with 6 seeds each paired comparison of the report "
                        "(tracker.resampling.method against systematic) has 6 pairs: the "
                        "signed-rank test cannot give p below 0.0312, and Holm's correction "
                        "over the report's 3 paired comparisons"),
              std::string::npos)
        << note;
    // And said so before anything runs.
    const std::string zipped_pool =
        ZippedPoolNote(LoadSweepFile(WriteSweep(dir, half_pooled + "seeds: 6\n")));
    EXPECT_TRUE(zipped_pool.ends_with(
        "sweep.yaml: report.pool lists world.sun.azimuth_deg but not tracker.particles, zipped "
        "with it: each zip position is still its own cell, holding the one value of it that "
        "its position gives, so the report pools nothing of it. Sweep world.sun.azimuth_deg as "
        "a key of grid: to pool its values within each cell (each cell then holds every value "
        "of it, with every combination of the other keys)"))
        << zipped_pool;
    // Positions sharing the unpooled key's value share a cell: pooled there
    // (a review: "pools nothing" was said of 4 cells of 2 values each), and
    // pooling the other key too is advice where it is neither x nor series.
    const std::string shared =
        "base: base.yaml\ngrid:\n  tracker.particles: [10, 20]\n"
        "  tracker.resampling.method: [systematic, charged]\nzip:\n"
        "  world.sun.azimuth_deg: [0, 90, 180, 270]\n  tracker.likelihood.sigma_px: [2, 2, 3, 3]\n"
        "report: {x: tracker.particles, series: tracker.resampling.method, pool: "
        "[world.sun.azimuth_deg], y: [mota]}\nseeds: 10\n";
    EXPECT_TRUE(ZippedPoolNote(LoadSweepFile(WriteSweep(dir, shared)))
                    .ends_with("only zip positions with the same values of "
                               "tracker.likelihood.sigma_px share a cell (2 cells of 4 "
                               "positions), so the report pools it only there. Pool "
                               "tracker.likelihood.sigma_px too, or sweep world.sun.azimuth_deg as "
                               "a key of grid: to pool its values within each cell (each cell "
                               "then holds every value of it, with every combination of the other "
                               "keys)"))
        << ZippedPoolNote(LoadSweepFile(WriteSweep(dir, shared)));
    EXPECT_EQ(ZippedPoolNote(LoadSweepFile(WriteSweep(dir, pooled + "seeds: 6\n"))), "");
  }
  // A series zipped with another key: 2 particle counts x 3 zip positions,
  // the 2 positions but the reference's compared, y [mota, idf1]: 8
  // comparisons (p < 0.00625 without Tarone's rule; with it K = 7, as above:
  // p < 0.00714). 8 seeds: 2/256 = 0.0078, a warning, 9 pairs needed (2/512
  // = 0.0039); 9 seeds: none.
  const std::string zipped =
      "base: base.yaml\ngrid:\n  tracker.particles: [10, 20]\nzip:\n"
      "  tracker.resampling.method: [systematic, charged, stratified]\n"
      "  tracker.likelihood.sigma_px: [2, 3, 4]\n"
      "report: {x: tracker.particles, series: tracker.resampling.method, y: [mota, idf1]}\n";
  note = SeedsForHolmNote(LoadSweepFile(WriteSweep(dir, zipped + "seeds: 8\n")));
  EXPECT_NE(note.find("with 8 seeds each paired comparison of the report "
                      "(tracker.resampling.method against systematic) has 8 pairs: the "
                      "signed-rank test cannot give p below 0.00781, and Holm's correction over "
                      "the report's 8 paired comparisons needs p < 0.00714 for its first "
                      "(Tarone's rule: K = 7)"),
            std::string::npos)
      << note;
  EXPECT_NE(note.find("9 seeds at least are needed (more where"), std::string::npos) << note;
  EXPECT_EQ(SeedsForHolmNote(LoadSweepFile(WriteSweep(dir, zipped + "seeds: 9\n"))), "");
  // The key zipped with the series pooled: each position is still its own
  // cell (the series differs at each), the same 8 comparisons; the note said
  // nothing (a review).
  std::string zipped_pooled = zipped;
  zipped_pooled.replace(zipped_pooled.find("y: [mota"), 1,
                        "pool: [tracker.likelihood.sigma_px], y");
  EXPECT_EQ(SeedsForHolmNote(LoadSweepFile(WriteSweep(dir, zipped_pooled + "seeds: 8\n"))), note);
}

TEST(Sweep, NoSeedsKeepsTheBaseSeedAndSweepSeedChangesDerivedSeeds) {
  const auto dir = SweepFolder("seeds");
  const auto runs = ExpandSweep(
      LoadSweepFile(WriteSweep(dir, "base: base.yaml\ngrid: {tracker.particles: [10, 20]}\n")));
  ASSERT_EQ(runs.size(), 2U);
  EXPECT_EQ(runs[0].scenario().seed, 7U);  // kMinimal's seed: 7
  EXPECT_EQ(runs[1].scenario().seed, 7U);
  const auto a =
      ExpandSweep(LoadSweepFile(WriteSweep(dir, "base: base.yaml\nseeds: 1\nseed: 5\n", "a.yaml")));
  const auto b =
      ExpandSweep(LoadSweepFile(WriteSweep(dir, "base: base.yaml\nseeds: 1\nseed: 6\n", "b.yaml")));
  ASSERT_EQ(a.size(), 1U);
  EXPECT_NE(a[0].scenario().seed, b[0].scenario().seed);
  EXPECT_EQ(a[0].scenario().seed, Rng(5).Fork("sweep/seed/0").identity());
}

// hcpf sweep --seed S: the runs derive their seeds from S as if the file
// said `seed: S` (same runs, same hash), the file's own seed is kept beside
// it, and bad text or a sweep without `seeds:` is refused naming the option.
TEST(Sweep, RootSeedFromAnOptionEqualsTheFilesSeed) {
  const auto dir = SweepFolder("root-seed");
  const std::string body = "base: base.yaml\nseeds: 3\ngrid: {tracker.particles: [10, 20]}\n";
  SweepSpec overridden = LoadSweepFile(WriteSweep(dir, body, "plain.yaml"));
  const std::string plain_hash = SweepHash(ExpandSweep(overridden));
  SetRootSeed(overridden, "9", "--seed");
  EXPECT_EQ(overridden.seed, 9U);
  EXPECT_EQ(overridden.file_seed, 1U);
  EXPECT_EQ(overridden.seed_from, "--seed");
  const auto runs = ExpandSweep(overridden);
  const auto written = ExpandSweep(LoadSweepFile(WriteSweep(dir, body + "seed: 9\n", "nine.yaml")));
  ASSERT_EQ(runs.size(), 6U);
  ASSERT_EQ(written.size(), 6U);
  for (size_t i = 0; i < runs.size(); ++i) {
    EXPECT_EQ(runs[i].key, written[i].key) << i;
    // The documented derivation, written out independently of SweepSeed.
    EXPECT_EQ(runs[i].scenario().seed,
              Rng(9).Fork("sweep/seed/" + std::to_string(runs[i].seed_index)).identity());
  }
  EXPECT_NE(SweepHash(runs), plain_hash);  // another root seed is another sweep
  // The largest seed is taken; past it, signs, spaces and words are not.
  SweepSpec largest = LoadSweepFile(WriteSweep(dir, body, "plain.yaml"));
  SetRootSeed(largest, "18446744073709551615", "--seed");
  EXPECT_EQ(largest.seed, 18446744073709551615ULL);
  for (const std::string bad : {"18446744073709551616", "-1", " 3", "3x", "three", ""}) {
    SweepSpec spec = LoadSweepFile(WriteSweep(dir, body, "plain.yaml"));
    try {
      SetRootSeed(spec, bad, "--seed");
      ADD_FAILURE() << "accepted \"" << bad << "\"";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("--seed: expected a non-negative integer seed below "
                                           "2^64, found \"" +
                                           bad + "\""),
                std::string::npos)
          << e.what();
    }
    EXPECT_EQ(spec.seed, 1U);
  }
  SweepSpec seedless = LoadSweepFile(
      WriteSweep(dir, "base: base.yaml\ngrid: {tracker.particles: [10]}\n", "n.yaml"));
  try {
    SetRootSeed(seedless, "9", "--seed");
    ADD_FAILURE() << "a sweep without seeds: took --seed";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("--seed: expected a sweep with `seeds: N`"), std::string::npos) << what;
    EXPECT_NE(what.find("n.yaml without `seeds:`"), std::string::npos) << what;
  }
}

// A det.txt (observation.detector: file) describes the frames of one
// rendering: `seeds: N` must keep the world and renderer seeds it was
// rendered with, and the error says so at the `seeds` line.
TEST(Sweep, ADetectionFileNeedsTheSeedsItsFramesWereRenderedWith) {
  const auto dir = SweepFolder("detection-file");
  std::ofstream(dir / "det.txt") << "1,-1,11,21,30,15,0.9\n";
  const std::string grid =
      "base: base.yaml\n"
      "grid:\n"
      "  observation.source: [rendered]\n"
      "  observation.detector: [diff, file]\n"
      "  observation.file.path: [det.txt]\n";
  const std::string error = ExpandErrorOf(WriteSweep(dir, "seeds: 3\n" + grid));
  EXPECT_NE(error.find("sweep.yaml:1:8: seeds: expected seeds.world and seeds.renderer pinned"),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("(rendered, file, det.txt)"), std::string::npos) << error;
  // One seed, or the two seeds pinned: the file's frames are the ones run.
  EXPECT_EQ(ExpandSweep(LoadSweepFile(WriteSweep(dir, "seeds: 1\n" + grid, "one.yaml"))).size(),
            2U);
  const auto pinned = ExpandSweep(LoadSweepFile(WriteSweep(
      dir, "seeds: 3\n" + grid + "  seeds.world: [11]\n  seeds.renderer: [12]\n", "pinned.yaml")));
  ASSERT_EQ(pinned.size(), 6U);
  EXPECT_EQ(pinned[5].scenario().seeds.renderer, 12U);
  EXPECT_NE(pinned[5].scenario().seeds.tracker, pinned[4].scenario().seeds.tracker);
}

// observation.file.rendering in a sweep over a key that shapes pixels: the
// cell that renders the det.txt's frames runs, the others are refused when the
// sweep loads them, naming the key. The rendering is a stand-in for the
// folder `hcpf render` writes (its manifest's pixel hash and resolved
// scenario); RenderedRun.ADetectionFileIsCheckedAgainstTheRenderingItWasMadeOn
// renders a real one.
TEST(Sweep, ADetectionFileOfOneRenderingRefusesTheCellsThatRenderOthers) {
  const auto dir = SweepFolder("detection-file-rendering");
  std::ofstream(dir / "det.txt") << "1,-1,11,21,30,15,0.9\n";
  const scenarios::Scenario made_on = scenarios::LoadScenarioFile(
      (dir / "base.yaml").string(), {{"observation.source", "rendered"},
                                     {"seeds.world", "11"},
                                     {"seeds.renderer", "12"},
                                     {"world.sun.elevation_deg", "35"}});
  std::filesystem::create_directories(dir / "render");
  std::ofstream(dir / "render" / "manifest.json")
      << "{\"pixel_hash\": \""
      << renderer::PixelHash(made_on.world, scenarios::RendererOptionsOf(made_on),
                             made_on.seeds.renderer)
      << "\"}\n";
  std::ofstream(dir / "render" / "scenario.resolved.yaml") << scenarios::ToResolvedYaml(made_on);
  const std::string sweep =
      "base: base.yaml\n"
      "grid:\n"
      "  observation.source: [rendered]\n"
      "  observation.detector: [file]\n"
      "  observation.file.path: [det.txt]\n"
      "  observation.file.rendering: [render]\n"
      "  seeds.world: [11]\n"
      "  seeds.renderer: [12]\n"
      "  world.sun.elevation_deg: [35";
  EXPECT_EQ(ExpandSweep(LoadSweepFile(WriteSweep(dir, sweep + "]\n", "one.yaml"))).size(), 1U);
  const std::string error = ExpandErrorOf(WriteSweep(dir, sweep + ", 60]\n"));
  EXPECT_NE(error.find("observation.file.rendering: expected this scenario's frames"),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("the scenarios differ at world.sun.elevation_deg (there 35, here 60)"),
            std::string::npos)
      << error;
}

// Issue 15 item 20: seeds beyond the second are reseeded from the first
// instead of loading the base file again. Every run must be exactly what the
// full loader gives for its overrides: resolved YAML, key, and the seeds a
// base that pins some of them keeps.
TEST(Sweep, ReseededRunsEqualFullyLoadedOnes) {
  const auto dir = SweepFolder("reseed");
  std::string base = scenarios::testing::kMinimal;
  base += "seeds: {tracker: 99}\n";  // pinned: kept by every seed
  std::ofstream(dir / "pinned.yaml") << base;
  for (const std::string file : {"base.yaml", "pinned.yaml"}) {
    const std::string path =
        WriteSweep(dir, "base: " + file + "\nseeds: 6\ngrid:\n  tracker.particles: [10, 20]\n",
                   file + ".sweep");
    const std::vector<SweepRun> runs = ExpandSweep(LoadSweepFile(path));
    ASSERT_EQ(runs.size(), 12U);
    std::set<uint64_t> tracker_seeds;
    for (const SweepRun& run : runs) {
      const scenarios::Scenario full =
          scenarios::LoadScenarioFile((dir / file).string(), run.overrides);
      EXPECT_EQ(scenarios::ToResolvedYaml(run.scenario()), scenarios::ToResolvedYaml(full));
      EXPECT_EQ(run.key, scenarios::ConfigHash(full));
      EXPECT_EQ(run.scenario().world.terrain.seed, full.world.terrain.seed);
      EXPECT_EQ(run.scenario().world.camera.shake_seed, full.world.camera.shake_seed);
      tracker_seeds.insert(run.scenario().seeds.tracker);
    }
    EXPECT_EQ(tracker_seeds.size(), file == "pinned.yaml" ? 1U : 6U) << file;
  }
}

// Issue 15 item 15: a grid whose run count overflows ended in
// std::length_error (exit 1); it is bad input at the sweep file.
TEST(Sweep, RunCountBeyondTheLimitIsBadInput) {
  const auto dir = SweepFolder("huge");
  std::string values = "[";
  for (int i = 0; i < 1000; ++i) values += (i ? ", " : "") + std::to_string(10 + i);
  values += "]";
  std::string text = "base: base.yaml\nseeds: 100000\ngrid:\n";
  for (const char* key : {"tracker.particles", "tracker.resampling.beta",
                          "tracker.resampling.charge", "tracker.likelihood.sigma_px",
                          "tracker.dynamics.sigma_pos_px", "observation.simulated.sigma_px"}) {
    text += std::string("  ") + key + ": " + values + "\n";
  }
  const std::string message = ErrorOf(WriteSweep(dir, text));
  EXPECT_NE(message.find("sweep.yaml:4:"), std::string::npos) << message;
  EXPECT_NE(message.find("expected a sweep of at most 10000000 runs"), std::string::npos)
      << message;
  EXPECT_NE(message.find("more than 2^63"), std::string::npos) << message;
  const std::string big = ErrorOf(
      WriteSweep(dir, "base: base.yaml\nseeds: 20000\ngrid:\n  tracker.particles: " + values + "\n",
                 "big.yaml"));
  EXPECT_NE(big.find("1000 tracker.particles × 20000 seeds = 20000000 runs"), std::string::npos)
      << big;
}

TEST(Sweep, ReportDefaultsAndValidation) {
  const auto dir = SweepFolder("report");
  const SweepSpec spec =
      LoadSweepFile(WriteSweep(dir,
                               "base: base.yaml\ngrid:\n  tracker.particles: [10]\n  "
                               "tracker.resampling.method: [charged]\n"));
  EXPECT_EQ(spec.report.x, "tracker.particles");
  EXPECT_EQ(spec.report.series, "");
  EXPECT_EQ(spec.report.y, std::vector<std::string>({"da_accuracy", "hijack_rate", "idf1", "hota",
                                                     "mota", "ms_per_frame"}));
  const std::string grid = "base: base.yaml\ngrid:\n  tracker.particles: [10]\n";
  EXPECT_EQ(
      LoadSweepFile(WriteSweep(dir, grid + "report: {y: [hota, det_ap]}\n", "y.yaml")).report.y,
      std::vector<std::string>({"hota", "det_ap"}));
  // A misspelt metric and an empty list are refused, naming file, line and key.
  std::string e = ErrorOf(WriteSweep(dir, grid + "report: {y: [hota, idf2]}\n", "typo.yaml"));
  EXPECT_NE(e.find("typo.yaml:4:"), std::string::npos) << e;
  EXPECT_NE(e.find("report.y"), std::string::npos) << e;
  EXPECT_NE(e.find("idf2"), std::string::npos) << e;
  e = ErrorOf(WriteSweep(dir, grid + "report: {y: []}\n", "empty.yaml"));
  EXPECT_NE(e.find("a non-empty list of metric names"), std::string::npos) << e;
  // A metric listed twice (it was plotted twice), at its second item.
  e = ErrorOf(WriteSweep(dir, grid + "report: {y: [hota, idf1, hota]}\n", "twice.yaml"));
  EXPECT_NE(e.find("twice.yaml:4:26: report.y[2]: expected a metric listed once in report.y"),
            std::string::npos)
      << e;
}

TEST(Sweep, BadFilesNameLineKeyExpectedFoundAndHint) {
  const auto dir = SweepFolder("bad");
  // Misspelt top-level key.
  std::string e = ErrorOf(WriteSweep(dir, "base: base.yaml\nseds: 3\n", "a.yaml"));
  EXPECT_NE(e.find("a.yaml:2:1"), std::string::npos) << e;
  EXPECT_NE(e.find("did you mean \"seeds\""), std::string::npos) << e;
  // Zip lists of different lengths: names the second list's first value.
  e = ErrorOf(WriteSweep(dir,
                         "base: base.yaml\nzip:\n  tracker.particles: [10, 20]\n"
                         "  tracker.resampling.method: [charged]\n",
                         "b.yaml"));
  EXPECT_NE(e.find("b.yaml:4:"), std::string::npos) << e;
  EXPECT_NE(e.find("2 values"), std::string::npos) << e;
  EXPECT_NE(e.find("found 1 values"), std::string::npos) << e;
  // A swept value the scenario schema rejects: the line and column of that value.
  e = ExpandErrorOf(
      WriteSweep(dir, "base: base.yaml\ngrid:\n  tracker.particles: [10, -5]\n", "c.yaml"));
  EXPECT_NE(e.find("c.yaml:3:27"), std::string::npos) << e;
  EXPECT_NE(e.find("tracker.particles"), std::string::npos) << e;
  EXPECT_NE(e.find("-5"), std::string::npos) << e;
  // An error in the base file that only some cells make (frames: 2 leaves
  // target 2's start_frame: 2 out of range): at the base file's line, with
  // the cell's swept values and where each is written (a bad-input audit: the
  // swept value that made a valid line invalid was not named).
  e = ExpandErrorOf(WriteSweep(
      dir, "base: base.yaml\ngrid:\n  frames: [20, 2]\n  tracker.particles: [10]\n", "h.yaml"));
  EXPECT_NE(e.find("base.yaml:15:"), std::string::npos) << e;
  EXPECT_NE(e.find("targets[1].path.start_frame"), std::string::npos) << e;
  EXPECT_NE(e.find("in the sweep's runs with frames = 2 ("), std::string::npos) << e;
  EXPECT_NE(e.find("h.yaml:3:16), tracker.particles = 10 ("), std::string::npos) << e;
  // An error of the base file itself, which every cell makes, names no cell.
  {
    std::string base = scenarios::testing::kMinimal;
    base.replace(base.find("particles: 100"), 14, "particles: 0");
    std::ofstream(dir / "bad-base.yaml") << base;
  }
  e = ExpandErrorOf(WriteSweep(
      dir, "base: bad-base.yaml\ngrid:\n  tracker.resampling.method: [systematic]\n", "i.yaml"));
  EXPECT_NE(e.find("bad-base.yaml:17:"), std::string::npos) << e;
  EXPECT_EQ(e.find("in the sweep's runs"), std::string::npos) << e;
  // A misspelt enum value: did-you-mean from the scenario schema, at the sweep line.
  e = ExpandErrorOf(
      WriteSweep(dir, "base: base.yaml\ngrid:\n  tracker.resampling.method: [systematic, chargd]\n",
                 "d.yaml"));
  EXPECT_NE(e.find("d.yaml:3:43"), std::string::npos) << e;
  EXPECT_NE(e.find("charged"), std::string::npos) << e;
  // Unknown metric in report.y.
  e = ErrorOf(WriteSweep(
      dir, "base: base.yaml\ngrid: {tracker.particles: [10]}\nreport: {y: [hotaa]}\n", "e.yaml"));
  EXPECT_NE(e.find("e.yaml:3:14"), std::string::npos) << e;
  EXPECT_NE(e.find("did you mean \"hota\""), std::string::npos) << e;
  // report.x that is not swept.
  e = ErrorOf(WriteSweep(
      dir, "base: base.yaml\ngrid: {tracker.particles: [10]}\nreport: {x: tracker.particle}\n",
      "f.yaml"));
  EXPECT_NE(e.find("f.yaml:3"), std::string::npos) << e;
  EXPECT_NE(e.find("did you mean \"tracker.particles\""), std::string::npos) << e;
  // Missing base file; empty list; seed swept with seeds.
  e = ErrorOf(WriteSweep(dir, "base: nope.yaml\n", "g.yaml"));
  EXPECT_NE(e.find("g.yaml:1:7: base"), std::string::npos) << e;
  e = ErrorOf(WriteSweep(dir, "base: base.yaml\ngrid: {tracker.particles: []}\n", "h.yaml"));
  EXPECT_NE(e.find("non-empty list"), std::string::npos) << e;
  e = ErrorOf(WriteSweep(dir, "base: base.yaml\nseeds: 3\ngrid: {seed: [1, 2]}\n", "i.yaml"));
  EXPECT_NE(e.find("i.yaml:3"), std::string::npos) << e;
  // A value listed twice: two runs of one scenario.
  e = ExpandErrorOf(
      WriteSweep(dir, "base: base.yaml\ngrid:\n  tracker.particles: [10, 20, 10]\n", "k.yaml"));
  EXPECT_NE(e.find("k.yaml:3"), std::string::npos) << e;
  EXPECT_NE(e.find("runs 0 and 2 resolve to the same scenario"), std::string::npos) << e;
  // At the value that repeats: the third particle count (line 3, column
  // 31), and a base file listed twice in grid.base, which is no override
  // (until 2026-12-06 that error had no line: an audit).
  EXPECT_NE(e.find("k.yaml:3:31: grid/zip"), std::string::npos) << e;
  e = ExpandErrorOf(WriteSweep(
      dir, "seeds: 2\ngrid:\n  base: [base.yaml, base.yaml]\n  tracker.particles: [10]\n",
      "l.yaml"));
  EXPECT_NE(e.find("l.yaml:3:21: grid/zip"), std::string::npos) << e;
  EXPECT_NE(e.find("runs 0 and 2 resolve to the same scenario"), std::string::npos) << e;
  e = ErrorOf(WriteSweep(dir, "base: base.yaml\nseeds: 0\n", "j.yaml"));
  EXPECT_NE(e.find("j.yaml:2:8: seeds"), std::string::npos) << e;
  // A key and one inside it, in either order and across grid and zip: the
  // runs used the last override while the store labelled them with both (a
  // bad-input audit). `tracker.particles_x` is not inside `tracker.particles`.
  e = ErrorOf(WriteSweep(dir,
                         "base: base.yaml\nzip:\n  tracker.particles: [30, 40]\n"
                         "  tracker: [{particles: 20}, {particles: 25}]\n",
                         "l.yaml"));
  EXPECT_NE(e.find("l.yaml:4:13: tracker: expected each key swept once"), std::string::npos) << e;
  EXPECT_NE(e.find("found tracker with tracker.particles also swept"), std::string::npos) << e;
  e = ErrorOf(WriteSweep(dir,
                         "base: base.yaml\ngrid:\n  targets.0: [{id: 1}]\n"
                         "zip:\n  targets.0.path.speed_mps: [2, 3]\n",
                         "m.yaml"));
  EXPECT_NE(e.find("m.yaml:5:"), std::string::npos) << e;
  EXPECT_NE(e.find("targets.0.path.speed_mps with targets.0 also swept"), std::string::npos) << e;
}

TEST(SweepOptions, ValidateNamesTheField) {
  SweepOptions o;
  o.out_dir = "x";
  o.shard_index = 2;
  o.shard_count = 2;
  try {
    o.Validate();
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--shard"), std::string::npos);
  }
}

// `hcpf sweep --threads N` reaches every run: the in-process executor gets
// RunOptions::threads = N, an --isolate child `--threads N` on its command
// line (a stand-in program writes its arguments down); 0 is refused.
TEST(SweepOptions, EachRunGetsTheSweepsRunThreads) {
  const auto dir = SweepFolder("run-threads");
  const std::vector<SweepRun> runs = ExpandSweep(
      LoadSweepFile(WriteSweep(dir, "base: base.yaml\ngrid:\n  tracker.particles: [10]\n")));
  ASSERT_EQ(runs.size(), 1U);
  class Recording final : public RunExecutor {
   public:
    void Execute(const SweepRun&, const scenarios::RunOptions& options) const override {
      threads = options.threads;
    }
    std::string_view name() const override { return "recording"; }
    mutable int threads = -1;
  };
  SweepOptions o;
  o.out_dir = (dir / "out").string();
  Recording recording;
  internal::ExecuteRun(runs[0], o,
                       recording);  // no metrics written: a failed record, which is fine here
  EXPECT_EQ(recording.threads, 1);
  o.run_threads = 3;
  internal::ExecuteRun(runs[0], o, recording);
  EXPECT_EQ(recording.threads, 3);

  const fs::path program = dir / "fake-hcpf";
  const fs::path args = dir / "args.txt";
  { std::ofstream(program) << "#!/bin/sh\necho \"$@\" > " << args.string() << "\n"; }
  fs::permissions(program, fs::perms::owner_all);
  fs::create_directories(dir / "runs");
  const ChildProcessExecutor child(program.string(), (dir / "runs").string());
  scenarios::RunOptions run_options;
  run_options.out_dir = (dir / "child").string();
  run_options.threads = 3;
  child.Execute(runs[0], run_options);
  std::ifstream in(args);
  const std::string line((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(line.find(" --threads 3"), std::string::npos) << line;

  o.run_threads = 0;
  try {
    o.Validate();
    FAIL() << "run_threads 0 accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--threads"), std::string::npos) << e.what();
  }
}

// A process's GL contexts share llvmpipe's one rasteriser (docs/sweeps.md):
// with render_exe and several runs at once, a rendered run goes to a child process, the
// others stay in worker threads; under isolate_exe every run.
TEST(SweepOptions, RenderedRunsGoToChildProcessesWhenSeveralRunAtOnce) {
  const auto dir = testing::SweepFolder("render-children");
  const std::vector<SweepRun> runs = ExpandSweep(LoadSweepFile(testing::WriteSweep(
      dir, "base: base.yaml\ngrid:\n  observation.source: [rendered, simulated]\n")));
  ASSERT_EQ(runs.size(), 2u);
  ASSERT_TRUE(runs[0].rendered());
  ASSERT_FALSE(runs[1].rendered());
  SweepOptions o;
  o.out_dir = "x";
  o.jobs = 2;
  EXPECT_FALSE(o.InChildProcess(runs[0]));  // no executable: worker threads
  EXPECT_EQ(o.ChildExe(), "");
  o.render_exe = "/usr/bin/hcpf";
  EXPECT_TRUE(o.InChildProcess(runs[0]));
  EXPECT_FALSE(o.InChildProcess(runs[1]));
  EXPECT_EQ(o.ChildExe(), "/usr/bin/hcpf");
  o.jobs = 1;  // one run at a time: one context in the process
  EXPECT_FALSE(o.InChildProcess(runs[0]));
  o.isolate_exe = "/opt/hcpf";
  EXPECT_TRUE(o.InChildProcess(runs[0]));
  EXPECT_TRUE(o.InChildProcess(runs[1]));
  EXPECT_EQ(o.ChildExe(), "/opt/hcpf");
}

// A rendered run whose frames are all in the frame cache when it starts
// renders nothing, so it stays in a worker thread under render_exe (a warm
// crossing-rendered.yaml: 34.7-46.5 s in threads against 53.0-56.9 s in
// children, docs/sweeps.md); one missing frame sends it to a child, and
// --isolate sends every run.
TEST(SweepOptions, ARenderedRunWhoseFramesAreAllCachedStaysInAWorkerThread) {
  const auto dir = testing::SweepFolder("render-cached");
  const std::vector<SweepRun> runs = ExpandSweep(LoadSweepFile(
      testing::WriteSweep(dir, "base: base.yaml\ngrid:\n  observation.source: [rendered]\n")));
  ASSERT_EQ(runs.size(), 1u);
  SweepOptions o;
  o.out_dir = "x";
  o.jobs = 2;
  o.render_exe = "/usr/bin/hcpf";
  EXPECT_TRUE(o.InChildProcess(runs[0]));  // no frame cache
  o.frame_cache_dir = (dir / "cache").string();
  EXPECT_TRUE(o.InChildProcess(runs[0]));  // an empty one
  const scenarios::Scenario scenario = runs[0].scenario();
  const renderer::FrameCache cache(
      o.frame_cache_dir, renderer::PixelHash(scenario.world, scenarios::RendererOptionsOf(scenario),
                                             scenario.seeds.renderer));
  fs::create_directories(cache.dir());
  const int frames = scenario.world.frames;
  ASSERT_GT(frames, 2);
  const auto store = [&](int f) {
    renderer::RenderedFrame frame;
    frame.frame = f;
    frame.rgb.width = 2;
    frame.rgb.height = 1;
    frame.rgb.pixels.assign(6, static_cast<uint8_t>(f));
    cache.Store(frame);
  };
  for (int f = 1; f < frames; ++f) store(f);  // all but the first
  EXPECT_FALSE(o.FramesAllCached(runs[0]));
  EXPECT_TRUE(o.InChildProcess(runs[0]));
  store(0);
  EXPECT_TRUE(o.FramesAllCached(runs[0]));
  EXPECT_FALSE(o.InChildProcess(runs[0]));
  o.isolate_exe = "/opt/hcpf";
  EXPECT_TRUE(o.InChildProcess(runs[0]));
  // The executors count what they sent where.
  o.isolate_exe.clear();
  const internal::RunExecutors executors(o);
  EXPECT_EQ(executors.For(runs[0]).name(), "threads");
  EXPECT_EQ(executors.cached_in_threads(), 1);
  EXPECT_EQ(executors.rendered_in_children(), 0);
  fs::remove(cache.dir() / "000000.frame");
  EXPECT_EQ(executors.For(runs[0]).name(), "child processes");
  EXPECT_EQ(executors.rendered_in_children(), 1);
}

}  // namespace
}  // namespace hcpf::studies

namespace hcpf::studies {
namespace {

// The run queue: with a frame cache, the first run of each rendered scene goes
// first and the runs that reuse its frames after it; everything else goes
// first, in order.
TEST(RunWaves, RunsThatReuseARenderedSceneGoSecond) {
  const auto dir = testing::SweepFolder("waves");
  const std::vector<SweepRun> runs =
      ExpandSweep(LoadSweepFile(testing::WriteSweep(dir,
                                                    "base: base.yaml\n"
                                                    "grid:\n"
                                                    "  observation.source: [rendered, simulated]\n"
                                                    "  seed: [1, 2]\n"
                                                    "  tracker.particles: [100, 200]\n")));
  ASSERT_EQ(runs.size(), 8u);  // source x seed x particles, the last key fastest
  std::vector<const SweepRun*> all;
  for (const SweepRun& r : runs) all.push_back(&r);
  // Runs 0..3 are rendered: (seed 1: 100, 200), (seed 2: 100, 200). The seed
  // changes the scene, the particle count does not.
  const auto waves = RunWaves(all, "/some/cache");
  ASSERT_EQ(waves.size(), 2u);
  const std::vector<const SweepRun*> first = {&runs[0], &runs[2], &runs[4],
                                              &runs[5], &runs[6], &runs[7]};
  const std::vector<const SweepRun*> second = {&runs[1], &runs[3]};
  EXPECT_EQ(waves[0], first);
  EXPECT_EQ(waves[1], second);
  // Without a cache no run can reuse another's frames.
  const auto uncached = RunWaves(all, "");
  EXPECT_EQ(uncached[0], all);
  EXPECT_TRUE(uncached[1].empty());
}

}  // namespace
}  // namespace hcpf::studies
