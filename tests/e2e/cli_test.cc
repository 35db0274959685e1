// End-to-end tests of the `hcpf` command: exit codes, outputs, determinism,
// and every shipped scenario.

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "support/process.h"

namespace hcpf {
namespace {

namespace fs = std::filesystem;
using testing::FreshDir;
using testing::LibraryScenario;
using testing::ReadFile;
using testing::RunCommand;

using testing::kHcpf;

TEST(Cli, VersionAndHelp) {
  auto r = RunCommand(kHcpf + " --version");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.output.find("hcpf 0."), std::string::npos) << r.output;
  // The GL context `backend: auto` gets here, with its GL_RENDERER (issue 13
  // item 3), or why there is none.
  EXPECT_NE(r.output.find("GL (backend auto): "), std::string::npos) << r.output;
  EXPECT_TRUE(r.output.find("renderer \"") != std::string::npos ||
              r.output.find("none (") != std::string::npos)
      << r.output;
  r = RunCommand(kHcpf + " run --help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.output.find("--set"), std::string::npos);
  EXPECT_NE(r.output.find("--out"), std::string::npos);
}

// What a command prints on standard output is what it was asked for: when it
// cannot be written (a full disk; /dev/full answers every write with ENOSPC)
// the command fails, exit 1, saying so. They all exited 0 with the text lost.
TEST(Cli, OutputThatCannotBeWrittenFailsTheCommand) {
  if (!fs::exists("/dev/full")) GTEST_SKIP() << "no /dev/full on this machine";
  const std::string scenario = LibraryScenario("crossing");
  const std::string cache = FreshDir("stdout-cache").string();
  for (const std::string& args :
       std::vector<std::string>{"schema", "validate --print " + scenario, "--version", "run --help",
                                "cache --cache " + cache}) {
    // Standard error to the captured pipe, standard output to /dev/full.
    const auto r = RunCommand("{ " + kHcpf + " " + args + " 2>&1 >/dev/full; }");
    EXPECT_EQ(r.exit_code, 1) << args << "\n" << r.output;
    EXPECT_NE(r.output.find("writing standard output failed: "), std::string::npos) << args << "\n"
                                                                                    << r.output;
  }
  // Written to where it fits, the same commands succeed.
  EXPECT_EQ(RunCommand(kHcpf + " validate --print " + scenario + " >/dev/null").exit_code, 0);
  // Bad input keeps its exit code 2.
  EXPECT_EQ(RunCommand(kHcpf + " validate --print /nonexistent.yaml >/dev/full").exit_code, 2);
}

// An external tracker the user may execute but not read (mode 711: the
// kernel starts a native binary without read permission) is a valid
// tracker.command; validate refused it for everyone but root ("cannot read",
// exit 1). As root, the command runs as nobody (setpriv) to lose the read.
TEST(Cli, AnExecuteOnlyTrackerProgramIsAccepted) {
  const fs::path dir = FreshDir("execute-only");
  fs::permissions(dir, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                           fs::perms::others_read | fs::perms::others_exec);
  const fs::path program = dir / "tracker";
  fs::copy_file("/bin/true", program);
  fs::permissions(program, fs::perms::owner_exec | fs::perms::owner_write | fs::perms::group_exec |
                               fs::perms::others_exec);
  std::string as_user;
  if (::geteuid() == 0) {
    if (RunCommand("command -v setpriv").exit_code != 0) GTEST_SKIP() << "no setpriv";
    as_user = "setpriv --reuid=65534 --regid=65534 --clear-groups ";
  }
  const std::string validate = as_user + kHcpf + " validate " + LibraryScenario("crossing");
  const auto plain = RunCommand(validate);
  if (plain.exit_code != 0) {
    GTEST_SKIP() << "user nobody cannot validate a shipped scenario here (the build or source "
                    "folder is not readable by others):\n"
                 << plain.output;
  }
  ASSERT_NE(RunCommand(as_user + "head -c 4 " + program.string() + " >/dev/null").exit_code, 0)
      << "the program is readable, so this test would check nothing";
  const auto r = RunCommand(validate + " --set tracker.type=external --set 'tracker.command=[" +
                            program.string() + "]'");
  EXPECT_EQ(r.exit_code, 0) << r.output;
}

TEST(Cli, NoOrUnknownSubcommandIsBadInput) {
  EXPECT_EQ(RunCommand(kHcpf).exit_code, 2);
  const auto unknown = RunCommand(kHcpf + " frobnicate");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.output.find("found \"frobnicate\""), std::string::npos) << unknown.output;
  const auto typo = RunCommand(kHcpf + " valdate x.yaml");
  EXPECT_EQ(typo.exit_code, 2);
  EXPECT_NE(typo.output.find("did you mean \"validate\"?"), std::string::npos) << typo.output;
  EXPECT_EQ(RunCommand(kHcpf + " run").exit_code, 2);  // missing scenario and --out
  // An unknown schema section prints no table before its error (a bad-input
  // audit found the header of the unknown section printed), and sweep-file
  // sections are among those offered.
  const auto schema = RunCommand(kHcpf + " schema tracker swep");
  EXPECT_EQ(schema.exit_code, 2) << schema.output;
  EXPECT_EQ(schema.output.find("## `"), std::string::npos) << schema.output;
  EXPECT_NE(schema.output.find("did you mean \"sweep\"?"), std::string::npos) << schema.output;
}

// Number options take a finite decimal number (a third bad-input audit:
// --min-visible nan passed CLI11's range check, NaN failing both of its
// comparisons, and scored every target "don't care" with exit 0; a
// hexadecimal float was read). Their ranges are written as numbers, not
// CLI11's "0.000000".
TEST(Cli, NumberOptionsAreFiniteDecimals) {
  for (const std::string value : {"nan", "-nan", "inf", "1e400", "0x0.8p0", "1,5", "."}) {
    const auto r = RunCommand(kHcpf + " score --detections a b --min-visible '" + value + "'");
    EXPECT_EQ(r.exit_code, 2) << value << "\n" << r.output;
    EXPECT_NE(
        r.output.find("--min-visible: expected a finite decimal number, found \"" + value + "\""),
        std::string::npos)
        << r.output;
  }
  const auto score = RunCommand(kHcpf + " score --detections a b --min-score nan");
  EXPECT_EQ(score.exit_code, 2) << score.output;
  EXPECT_NE(score.output.find("--min-score: expected a finite decimal number, found \"nan\""),
            std::string::npos)
      << score.output;
  const auto range = RunCommand(kHcpf + " score --detections a b --min-visible 1.5");
  EXPECT_EQ(range.exit_code, 2) << range.output;
  EXPECT_NE(range.output.find("--min-visible: expected a value in [0, 1], found \"1.5\""),
            std::string::npos)
      << range.output;
  // Decimal forms are read: the files are then looked for.
  for (const std::string value : {"0.5", ".5", "5e-1", "+1", "0"}) {
    const auto r = RunCommand(kHcpf + " score --detections a b --min-visible " + value);
    EXPECT_NE(r.output.find("a: expected a gt.json"), std::string::npos) << value << r.output;
  }
}

// An error that a --set makes at a line of the file valid on its own names
// the overrides (a bad-input audit: the line was blamed, the --set unnamed);
// one at the override's own value names it as before; the file's own errors
// stay as they are.
TEST(Cli, ErrorsMadeByASetNameIt) {
  const std::string scenario = LibraryScenario("crossing");
  const auto id = RunCommand(kHcpf + " validate " + scenario + " --set targets.0.id=2");
  EXPECT_EQ(id.exit_code, 2) << id.output;
  EXPECT_NE(id.output.find("targets[1].id: expected an id used by no other target, found \"2\" "
                           "(with --set targets.0.id=2)"),
            std::string::npos)
      << id.output;
  const auto frames =
      RunCommand(kHcpf + " run " + scenario + " --set frames=10 --set seed=3 --out " +
                 (FreshDir("set-named") / "out").string());
  EXPECT_EQ(frames.exit_code, 2) << frames.output;
  EXPECT_NE(frames.output.find("expected an integer in [0, 9], found \"12\" (with --set frames=10, "
                               "--set seed=3)"),
            std::string::npos)
      << frames.output;
  const auto own = RunCommand(kHcpf + " validate " + scenario + " --set frames=x");
  EXPECT_NE(own.output.find("--set frames=x: frames: expected an integer"), std::string::npos)
      << own.output;
  EXPECT_EQ(own.output.find("(with --set"), std::string::npos) << own.output;
}

// A file or a run folder given where a sweep folder goes is said to be one
// (a fourth bad-input audit: both were "results.sqlite: no such file"), and
// a --cache below a file is "a path below the file", not "no such folder".
TEST(Cli, AFileOrARunFolderWhereASweepGoesIsNamed) {
  const fs::path dir = FreshDir("not-a-sweep");
  std::ofstream(dir / "afile") << "x\n";
  const auto merged = RunCommand(kHcpf + " merge " + (dir / "out").string() + " " +
                                 (dir / "afile").string() + " " + (dir / "afile").string());
  EXPECT_EQ(merged.exit_code, 2) << merged.output;
  EXPECT_NE(merged.output.find("found no such file: " + (dir / "afile").string() +
                               " is a file, not a sweep folder"),
            std::string::npos)
      << merged.output;
  const auto run = RunCommand(kHcpf + " run " + LibraryScenario("crossing") +
                              " --set frames=20 --set targets.1.path.start_frame=0 --out " +
                              (dir / "run").string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto exported = RunCommand(kHcpf + " export " + (dir / "run").string() + " --trackeval " +
                                   (dir / "te").string());
  EXPECT_EQ(exported.exit_code, 2) << exported.output;
  EXPECT_NE(exported.output.find("is a run or render folder (manifest.json), not a sweep folder"),
            std::string::npos)
      << exported.output;
  const auto cache = RunCommand(kHcpf + " cache --cache " + (dir / "afile" / "x").string());
  EXPECT_EQ(cache.exit_code, 2) << cache.output;
  EXPECT_NE(cache.output.find("--cache: expected a folder (new or existing), found a path below "
                              "the file " +
                              (dir / "afile").string()),
            std::string::npos)
      << cache.output;
}

// A default cache folder that cannot be one is named by where it came from
// (a bad-input audit: HCPF_CACHE_DIR naming a file was reported as
// "--cache", an option not given; one below a file was "not created yet:
// nothing cached", exit 0).
TEST(Cli, ABadCacheFromTheEnvironmentIsNamedSo) {
  const fs::path dir = FreshDir("cache-env");
  std::ofstream(dir / "file") << "not a folder\n";
  const std::string env = "HCPF_CACHE_DIR=" + (dir / "file").string() + " ";
  const auto cache = RunCommand(env + kHcpf + " cache");
  EXPECT_EQ(cache.exit_code, 2) << cache.output;
  EXPECT_NE(cache.output.find((dir / "file").string() +
                              ": HCPF_CACHE_DIR (environment): expected a cache folder, found an "
                              "existing file"),
            std::string::npos)
      << cache.output;
  const auto below =
      RunCommand("HCPF_CACHE_DIR=" + (dir / "file" / "sub").string() + " " + kHcpf + " cache");
  EXPECT_EQ(below.exit_code, 2) << below.output;
  EXPECT_NE(below.output.find("HCPF_CACHE_DIR (environment): expected a folder (new or "
                              "existing), found a path below the file " +
                              (dir / "file").string()),
            std::string::npos)
      << below.output;
  const auto run = RunCommand(env + kHcpf + " run " + LibraryScenario("crossing") + " --out " +
                              (dir / "run").string());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("HCPF_CACHE_DIR (environment): expected a folder"), std::string::npos)
      << run.output;
  EXPECT_EQ(run.output.find("--cache"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(dir / "run"));
}

// Integer options take decimal digits only, checked before their range (a
// second bad-input audit: CLI11 read --jobs 0x2 as 2, and --jobs 1.5 was
// "not in range"). Exit 2 with the option named, nothing written; every
// refusal of the option parser in the house form.
TEST(Cli, IntegerOptionsAreDecimal) {
  const fs::path dir = FreshDir("decimal");
  const std::string scenario = LibraryScenario("crossing");
  for (const auto& [command, option] : std::vector<std::pair<std::string, std::string>>{
           {" run " + scenario + " --threads 0x2", "--threads"},
           {" run " + scenario + " --threads 1.5", "--threads"},
           {" render " + scenario + " --sheet-frames 0b11", "--sheet-frames"},
           {" regress suite.yaml --baseline b.json --jobs 1e1", "--jobs"}}) {
    const auto r = RunCommand(kHcpf + command + " --out " + (dir / "out").string());
    EXPECT_EQ(r.exit_code, 2) << command << "\n" << r.output;
    EXPECT_NE(r.output.find(option + ": expected a decimal integer, found"), std::string::npos)
        << command << "\n"
        << r.output;
  }
  // Out of range, and the parser's other refusals, in the house form (a
  // bad-input audit: CLI11's "Value 0 not in range 1 to 256" and "Run with
  // --help for more information.").
  for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
           {" run " + scenario + " --threads 0 --out " + (dir / "out").string(),
            "command line: --threads: expected a value in [1, 256], found \"0\" (hcpf run --help "
            "lists the options)"},
           {" run " + scenario + " --out " + (dir / "out").string() + " --no-cahce",
            "command line: expected no more arguments, found \"--no-cahce\" (did you mean "
            "\"--no-cache\"?)"},
           {" score --benchmark MOT71 a b",
            "command line: --benchmark: expected one of MOT15, MOT16, MOT17, MOT20, auto, found "
            "\"MOT71\" (did you mean \"MOT17\"?)"},
           {" sweep s.yaml --out", "command line: --out: expected a value after it, found none"},
           {" run " + scenario + " --out " + (dir / "out").string() + " --threads",
            "command line: --threads: expected a value after it, found none"},
           {" validate " + scenario + " --log-level warn",
            "command line: --log-level: expected it before the command (hcpf --log-level LEVEL "
            "validate ...), found it after"},
           // A review: std::regex overflowed the stack on a message of
           // thousands of characters (exit 139).
           {" score a b " + std::string(40000, 'x'), "command line: The following argument"},
           {" run " + scenario, "command line: --out: expected the option --out (it is required)"},
           // A fourth bad-input audit: CLI11's "At Most 1 required but
           // received 2", and an unknown option before the command blamed on
           // the command's arguments.
           {" cache --max-size 10M --max-size 20M",
            "command line: --max-size: expected it once, found it 2 times"},
           {" --verison validate " + scenario,
            "command line: expected an option of hcpf before the command (--log-level "
            "LEVEL, --version, --help), found \"--verison\" (did you mean \"--version\"?)"}}) {
    const auto r = RunCommand(kHcpf + args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << args << "\n" << r.output;
    EXPECT_EQ(r.output.find("Run with --help"), std::string::npos) << r.output;
  }
  EXPECT_FALSE(fs::exists(dir / "out"));
}

// $HCPF_CACHE_MAX_SIZE: after a rendered run, the cache's entries used
// before the run started go, least recently used first (a hand-made scene
// folder of two days ago); what the run used stays, though over the limit,
// and the log says so. A sweep prunes once after its runs: with --isolate
// its children (hcpf run) do not, or the second would remove the first's
// scene. A bad value is bad input before anything runs.
TEST(Cli, TheCacheLimitPrunesWhatWasUsedBeforeTheCommand) {
  const fs::path dir = FreshDir("cache-limit");
  const fs::path cache = dir / "cache";
  const fs::path old_scene = cache / "00000000000000000000000000000001";
  const auto plant_old_scene = [&] {
    fs::create_directories(old_scene);
    std::ofstream(old_scene / "000000.frame", std::ios::binary) << std::string(3000, 'x');
    fs::last_write_time(old_scene, fs::file_time_type::clock::now() - std::chrono::hours(48));
  };
  const auto scenes = [&] {
    int n = 0;
    for (const auto& e : fs::directory_iterator(cache))
      n += e.is_directory() && e.path().filename().string().size() == 32;
    return n;
  };
  plant_old_scene();
  const std::string scenario = LibraryScenario("crossing");
  const std::string rendered =
      " --set frames=20 --set observation.source=rendered --cache " + cache.string();
  auto r = RunCommand("HCPF_CACHE_MAX_SIZE=1K " + kHcpf + " run " + scenario + rendered +
                      " --out " + (dir / "run").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(old_scene)) << r.output;
  EXPECT_EQ(scenes(), 1) << r.output;
  EXPECT_NE(r.output.find("removed 1 scene(s) and 0 detector output(s) used least recently, 2.9 "
                          "KiB;"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("over HCPF_CACHE_MAX_SIZE 1K: the rest was used since this command "
                          "started"),
            std::string::npos)
      << r.output;

  // A sweep of two seeds, each run in a child process one after the other;
  // the run's scene above marked as used an hour ago (the prune spares what
  // was used in the two seconds before a command started).
  plant_old_scene();
  for (const auto& e : fs::directory_iterator(cache)) {
    fs::last_write_time(e.path(), fs::file_time_type::clock::now() - std::chrono::hours(1));
  }
  fs::last_write_time(old_scene, fs::file_time_type::clock::now() - std::chrono::hours(48));
  std::ofstream(dir / "sweep.yaml") << "base: " << scenario
                                    << "\nseeds: 2\ngrid: {frames: [20], observation.source: "
                                       "[rendered]}\n";
  r = RunCommand("HCPF_CACHE_MAX_SIZE=1K " + kHcpf + " sweep " + (dir / "sweep.yaml").string() +
                 " --isolate --jobs 1 --cache " + cache.string() + " --out " +
                 (dir / "sweep").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_FALSE(fs::exists(old_scene)) << r.output;
  // The two scenes of the sweep stay; the old one and the run's above (used
  // before the sweep started) went. Had the second child pruned as it
  // ended, the first child's scene would have gone with them (1 left).
  EXPECT_EQ(scenes(), 2) << r.output;
  EXPECT_NE(r.output.find("removed 2 scene(s) and 0 detector output(s) used least recently"),
            std::string::npos)
      << r.output;

  // hcpf cache says the limit.
  r = RunCommand("HCPF_CACHE_MAX_SIZE=1K " + kHcpf + " cache --cache " + cache.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("  limit: 1.0 KiB after each hcpf run, render and sweep "
                          "(HCPF_CACHE_MAX_SIZE=1K), what they used kept\n"),
            std::string::npos)
      << r.output;
  // Unset, the default 20 GiB; off, none.
  r = RunCommand("env -u HCPF_CACHE_MAX_SIZE " + kHcpf + " cache --cache " + cache.string());
  EXPECT_NE(r.output.find("  limit: 20.0 GiB after each hcpf run, render and sweep "
                          "(HCPF_CACHE_MAX_SIZE unset: the default), what they used kept\n"),
            std::string::npos)
      << r.output;
  r = RunCommand("HCPF_CACHE_MAX_SIZE=off " + kHcpf + " cache --cache " + cache.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("limit:"), std::string::npos) << r.output;
  EXPECT_EQ(RunCommand("HCPF_CACHE_MAX_SIZE=lots " + kHcpf + " cache --cache " + cache.string())
                .exit_code,
            2);
  r = RunCommand("HCPF_CACHE_MAX_SIZE=lots " + kHcpf + " run " + scenario + rendered + " --out " +
                 (dir / "bad").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("environment: HCPF_CACHE_MAX_SIZE: expected a size"), std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir / "bad"));
  // hcpf validate accepts what hcpf run accepts: the same refusal, for a
  // scenario and for a sweep (until 2026-12-06 validate said "valid", exit 0:
  // an audit).
  for (const std::string& file : {scenario, (dir / "sweep.yaml").string()}) {
    r = RunCommand("HCPF_CACHE_MAX_SIZE=lots " + kHcpf + " validate " + file);
    EXPECT_EQ(r.exit_code, 2) << file << r.output;
    EXPECT_NE(r.output.find("environment: HCPF_CACHE_MAX_SIZE: expected a size"), std::string::npos)
        << r.output;
  }
}

// hcpf sweep --seed: bad text, an empty value and a sweep without seeds:
// (whose runs keep the base scenario's seed) are refused before anything is
// written, exit 2, naming the option.
TEST(Cli, SweepSeedIsCheckedBeforeAnythingRuns) {
  const fs::path dir = FreshDir("sweep-seed");
  const std::string scenario = LibraryScenario("crossing-dominant");
  std::ofstream(dir / "seeds.yaml") << "base: " << scenario << "\nseeds: 2\ngrid: {frames: [20]}\n";
  std::ofstream(dir / "seedless.yaml") << "base: " << scenario << "\ngrid: {frames: [20]}\n";
  const std::string out = " --out " + (dir / "out").string();
  for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
           {(dir / "seeds.yaml").string() + " --seed 0x3",
            "--seed: expected a non-negative integer seed below 2^64, found \"0x3\""},
           {(dir / "seeds.yaml").string() + " --seed -3",
            "--seed: expected a non-negative integer seed below 2^64, found \"-3\""},
           {(dir / "seeds.yaml").string() + " --seed ''",
            "--seed: expected a value, found an empty value"},
           {(dir / "seedless.yaml").string() + " --seed 3",
            "--seed: expected a sweep with `seeds: N`"}}) {
    const auto r = RunCommand(kHcpf + " sweep " + args + out);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << args << "\n" << r.output;
    EXPECT_FALSE(fs::exists(dir / "out")) << args;
  }
  // Taken: the store says where its seeds came from.
  const auto r = RunCommand(kHcpf + " sweep " + (dir / "seeds.yaml").string() + " --seed 3" + out);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir / "out" / "results.sqlite")) << r.output;
  EXPECT_NE(r.output.find("sweep: runs seeded from root seed 3 (--seed; the sweep file's seed: 1)"),
            std::string::npos)
      << r.output;
}

// hcpf cache on a hand-built cache folder: a scene of 3000 bytes (and its
// scene.json, written here: crossing, seed 7) last used on 2026-01-02 at
// 03:04 UTC, one of 1000 used now, a detector output of 500 used a day ago.
// It reports what is there, a scene a line, most recently used last, by
// what it is and when it was used to the minute; --max-size 2K (2048)
// removes the least recently used until the rest fits: the old scene
// (leaving 1500); --dry-run removes nothing and says the total first, the
// detector outputs in one line (--verbose: a line each too); a size it
// cannot read is bad input (exit 2, naming the option).
TEST(Cli, CacheReportsAndPrunesTheLeastRecentlyUsed) {
  const fs::path cache = FreshDir("cache-command");
  const auto write = [](const fs::path& p, size_t n) {
    fs::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << std::string(n, 'x');
  };
  const fs::path old_scene = cache / "00000000000000000000000000000001";
  const fs::path new_scene = cache / "00000000000000000000000000000002";
  const fs::path det = cache / "detections" / "k.det";
  write(old_scene / "000000.frame", 2900);
  // 100 bytes, padded with spaces (JSON reads past them).
  const std::string note =
      R"({"scenario": "crossing", "seed": 7, "frames": 1, "width_px": 640, "height_px": 480})";
  std::ofstream(old_scene / "scene.json") << note << std::string(100 - note.size(), ' ');
  write(new_scene / "000000.frame", 1000);
  write(det, 500);
  {
    std::fstream header(det, std::ios::in | std::ios::out | std::ios::binary);
    header << "HCPFDET2";  // a detector output of ours starts so
  }
  const auto now = fs::file_time_type::clock::now();
  using std::chrono::sys_days;
  fs::last_write_time(
      old_scene, std::chrono::file_clock::from_sys(sys_days{std::chrono::year{2026} / 1 / 2} +
                                                   std::chrono::hours(3) + std::chrono::minutes(4) +
                                                   std::chrono::seconds(59)));
  fs::last_write_time(det, now - std::chrono::hours(24));
  const std::string base = kHcpf + " cache --cache " + cache.string();

  auto r = RunCommand(base);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("2 scene(s) of rendered frames: 3.9 KiB"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("1 detector output(s): 500 B"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("used from 2026-01-02 03:04 to "), std::string::npos) << r.output;
  const size_t old_line = r.output.find(
      "    2026-01-02 03:04     2.9 KiB  crossing, seed 7, 1 frame(s), 640 x 480  "
      "00000000000000000000000000000001\n");
  const size_t new_line = r.output.find(
      "1000 B  scene unknown: no scene.json (cached before hcpf noted its scenes); 1 frame(s) "
      "cached  00000000000000000000000000000002\n");
  EXPECT_NE(old_line, std::string::npos) << r.output;
  EXPECT_NE(new_line, std::string::npos) << r.output;
  EXPECT_LT(old_line, new_line) << "most recently used last\n" << r.output;
  EXPECT_NE(r.output.find("    1 detector output(s), 500 B, used from "), std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("k.det"), std::string::npos) << r.output;
  r = RunCommand(base + " --verbose");
  EXPECT_NE(r.output.find(" 500 B  detections/k.det\n"), std::string::npos) << r.output;

  // At most 1K: the old scene and the detector output would go; the total
  // first, then a line for the scene and one for the detector outputs, no
  // file's line (an audit: 1,440 lines, one per detector output, came
  // before the total).
  r = RunCommand(base + " --max-size 1K --dry-run");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const size_t total = r.output.find(
      "  would remove 1 scene(s) and 1 detector output(s), 3.4 KiB, least recently used first: "
      "1000 B left (--max-size 1K)\n");
  const size_t scene_line = r.output.find(
      "\n    2026-01-02 03:04     2.9 KiB  crossing, seed 7, 1 frame(s), 640 x 480  "
      "00000000000000000000000000000001\n    1 detector output(s), 500 B, used from ");
  EXPECT_NE(total, std::string::npos) << r.output;
  EXPECT_NE(scene_line, std::string::npos) << r.output;
  EXPECT_LT(total, scene_line) << r.output;
  EXPECT_EQ(r.output.find("k.det"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("00000000000000000000000000000002"), std::string::npos) << r.output;
  r = RunCommand(base + " --max-size 1K --dry-run --verbose");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find(" 500 B  detections/k.det\n"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(old_scene));
  EXPECT_TRUE(fs::exists(det));

  r = RunCommand(base + " --max-size 2K");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("removed 1 scene(s) and 0 detector output(s), 2.9 KiB"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(old_scene));
  EXPECT_TRUE(fs::exists(new_scene / "000000.frame"));
  EXPECT_TRUE(fs::exists(det));

  // A folder with a scene's name that is not one (a third bad-input audit:
  // pruned as a scene): pruning is refused, nothing is removed; listing
  // leaves it out.
  write(cache / "00000000000000000000000000000009" / "important.txt", 10);
  r = RunCommand(base + " --max-size 0");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("00000000000000000000000000000009/important.txt, which is not a cache "
                          "entry"),
            std::string::npos)
      << r.output;
  EXPECT_TRUE(fs::exists(new_scene / "000000.frame"));
  EXPECT_TRUE(fs::exists(det));
  EXPECT_EQ(RunCommand(base).exit_code, 0);
  fs::remove_all(cache / "00000000000000000000000000000009");

  r = RunCommand(base + " --max-size 2KB");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--max-size: expected a size"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("found \"2KB\""), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(new_scene / "000000.frame"));

  // A bad-input audit: --max-size "" (a size left out of a script's
  // variable) listed the cache and exited 0; --cache naming a missing folder
  // or a file read as an empty cache; --dry-run alone did nothing.
  r = RunCommand(base + " --max-size ''");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--max-size: expected a value, found an empty value"), std::string::npos)
      << r.output;
  // So is any option given an empty value (a second bad-input audit:
  // --shard '' ran the whole sweep, report --out '' wrote into DIR,
  // regress --junit '' wrote nothing, --cache '' turned the cache off, all
  // with exit 0), and an empty --set value, which replaced a whole section
  // with its defaults.
  const std::string scenario = LibraryScenario("crossing");
  const fs::path source(HCPF_SOURCE_DIR);
  for (const std::string& args :
       {" sweep " + (source / "scenarios/sweeps/default.yaml").string() + " --out " +
            (cache / "sw").string() + " --shard ''",
        " report " + cache.string() + " --out ''",
        " regress " + (source / "scenarios/regress/suite.yaml").string() +
            " --baseline x.json --update-baseline --junit ''",
        " run " + scenario + " --out " + (cache / "r").string() + " --cache ''"}) {
    r = RunCommand(kHcpf + args);
    EXPECT_EQ(r.exit_code, 2) << args << ": " << r.output;
    EXPECT_NE(r.output.find("expected a value, found an empty value"), std::string::npos)
        << args << ": " << r.output;
  }
  EXPECT_FALSE(fs::exists(cache / "sw"));
  EXPECT_FALSE(fs::exists(cache / "r"));
  r = RunCommand(kHcpf + " validate " + scenario + " --set tracker=");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--set tracker=: tracker: expected a value, found nothing"),
            std::string::npos)
      << r.output;
  r = RunCommand(kHcpf + " cache --cache " + (cache / "nosuch").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("nosuch: --cache: expected an existing cache folder, found no such "
                          "folder"),
            std::string::npos)
      << r.output;
  r = RunCommand(kHcpf + " cache --cache " + det.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("found an existing file"), std::string::npos) << r.output;
  r = RunCommand(base + " --dry-run");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--max-size"), std::string::npos) << r.output;
  EXPECT_TRUE(fs::exists(new_scene / "000000.frame"));
}

// A scenario saved as Latin-1: hcpf validate had accepted it and hcpf run
// failed (exit 1) writing its JSON. Both now refuse it at the byte, exit 2,
// and the run leaves no output folder.
TEST(Cli, ValidateAndRunRefuseTextThatIsNotUtf8) {
  const fs::path dir = FreshDir("not-utf8");
  std::ifstream library(LibraryScenario("crossing"));
  std::ofstream scenario(dir / "latin1.yaml");
  scenario << "name: caf\xE9\n";
  std::string line;
  while (std::getline(library, line)) {
    if (line.rfind("name:", 0) != 0) scenario << line << "\n";
  }
  scenario.close();
  const std::string file = (dir / "latin1.yaml").string();
  for (const std::string& command :
       {kHcpf + " validate " + file, kHcpf + " run " + file + " --out " + (dir / "out").string()}) {
    const auto r = RunCommand(command);
    EXPECT_EQ(r.exit_code, 2) << command << "\n" << r.output;
    EXPECT_NE(r.output.find("latin1.yaml:1:10: expected UTF-8 text, found the byte 0xE9"),
              std::string::npos)
        << r.output;
  }
  EXPECT_FALSE(fs::exists(dir / "out"));
}

// hcpf validate takes a sweep file too (a mapping with base, grid or zip at
// the top), with the checks hcpf sweep makes before running: 3 particle
// counts x 2 resamplers = 6 cells x 2 seeds = 12 runs, every scenario valid.
// A swept value a scenario cannot take is bad input naming its line (line 3:
// "lots"); --set and --print, which apply to one scenario, are bad input.
// (Read as a scenario, as before, the sweep's `seeds: 2` was "expected a
// mapping of keys".)
TEST(Cli, ValidateChecksSweepFilesToo) {
  const fs::path dir = FreshDir("validate-sweep");
  const auto write = [&](const std::string& name, const std::string& particles) {
    std::ofstream(dir / name) << "base: " << LibraryScenario("crossing") << "\n"
                              << "grid:\n"
                              << "  tracker.particles: [100, 200, " << particles << "]\n"
                              << "  tracker.resampling.method: [systematic, charged]\n"
                              << "seeds: 2\n";
    return (dir / name).string();
  };
  const std::string good = write("good.yaml", "400");
  auto r = RunCommand(kHcpf + " validate " + good);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("valid sweep: 12 runs (6 cells x 2 seed(s)), every scenario valid"),
            std::string::npos)
      << r.output;
  // With a series to compare and 2 seeds no paired comparison can be a
  // finding: validate (as sweep) says so before anything runs, and the
  // sweep is still valid.
  std::ofstream(dir / "few.yaml") << "base: " << LibraryScenario("crossing") << "\n"
                                  << "grid:\n  tracker.particles: [100, 200]\n"
                                  << "  tracker.resampling.method: [systematic, charged]\n"
                                  << "seeds: 2\nreport: {series: tracker.resampling.method}\n";
  r = RunCommand(kHcpf + " validate " + (dir / "few.yaml").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("has 2 pairs: the signed-rank test cannot give p below 0.5, so no "
                          "comparison can be a finding"),
            std::string::npos)
      << r.output;
  const std::string bad = write("bad.yaml", "lots");
  r = RunCommand(kHcpf + " validate " + bad);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("bad.yaml:3"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\"lots\""), std::string::npos) << r.output;
  r = RunCommand(kHcpf + " validate " + good + " --print");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--print: expected a scenario file"), std::string::npos) << r.output;
  // A scenario is validated as one, as before.
  r = RunCommand(kHcpf + " validate " + LibraryScenario("crossing"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("valid scenario \"crossing\""), std::string::npos) << r.output;
}

// hcpf validate takes a regression suite too (its scenes: a list), with the checks hcpf regress
// makes before running: every scene's scenario with its set: and seed, the seeded scene's runs
// counted (1 + 3), and what validate warns of each scene (crossing's vehicles drive through each
// other), named by the scene. A bad `set:` value is bad input at its line; --print is bad input; a
// baseline is still refused as a scenario (until 2026-12-07 a suite was refused as "a regression
// suite or baseline").
TEST(Cli, ValidateChecksRegressionSuitesToo) {
  const fs::path dir = FreshDir("validate-suite");
  const auto write = [&](const std::string& name, const std::string& particles) {
    std::ofstream(dir / name) << "scenes:\n"
                              << "  - {name: a, scenario: " << LibraryScenario("crossing") << "}\n"
                              << "  - {name: b, scenario: " << LibraryScenario("parallel")
                              << ", seeds: 3,\n"
                              << "     set: {tracker.particles: " << particles << "}}\n"
                              << "metrics:\n  idf1: {tolerance: 0.02}\n";
    return (dir / name).string();
  };
  const std::string good = write("good.yaml", "400");
  auto r = RunCommand(kHcpf + " validate " + good);
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("valid regression suite: 2 scenes (4 runs), 1 metric, every scenario "
                          "valid"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("scene \"a\": targets 1 and 2 drive through each other at frames "
                          "184-222"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(r.output.find("scene \"b\""), std::string::npos) << r.output;
  const std::string bad = write("bad.yaml", "lots");
  r = RunCommand(kHcpf + " validate " + bad);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("bad.yaml:4"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("\"lots\""), std::string::npos) << r.output;
  r = RunCommand(kHcpf + " validate " + good + " --print");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--print: expected a scenario file"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("found the regression suite"), std::string::npos) << r.output;
  std::ofstream(dir / "baseline.json") << R"({"format": "hcpf-regress-baseline/2", "scenes": {}})";
  r = RunCommand(kHcpf + " validate " + (dir / "baseline.json").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("found a regression suite or baseline"), std::string::npos) << r.output;
  // A scenario's own `metrics:` (its metric options) does not make it a suite.
  std::ofstream(dir / "scenario.yaml")
      << ReadFile(LibraryScenario("crossing")) << "metrics: {gospa_switching_penalty: 2}\n";
  r = RunCommand(kHcpf + " validate " + (dir / "scenario.yaml").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("valid scenario \"crossing\""), std::string::npos) << r.output;
}

TEST(Cli, RunWritesEveryOutputAndSucceeds) {
  const fs::path out = FreshDir("run") / "crossing";
  const auto r =
      RunCommand(kHcpf + " run " + LibraryScenario("crossing") + " --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* f : {"scenario.resolved.yaml", "gt/gt.txt", "seqinfo.ini", "gt.json",
                        "detections.txt", "manifest.json"}) {
    EXPECT_TRUE(fs::exists(out / f)) << f;
  }
  EXPECT_NE(r.output.find(out.string()), std::string::npos) << "the output folder is named";
  // MOT17 ground truth: 9 comma-separated columns, 1-based frames.
  const std::string gt = ReadFile(out / "gt" / "gt.txt");
  const std::string first = gt.substr(0, gt.find('\n'));
  EXPECT_EQ(std::count(first.begin(), first.end(), ','), 8) << first;
  EXPECT_EQ(first.rfind("1,", 0), 0u) << first;
  const std::string seqinfo = ReadFile(out / "seqinfo.ini");
  EXPECT_NE(seqinfo.find("seqLength=240"), std::string::npos);
  EXPECT_NE(seqinfo.find("imWidth=640"), std::string::npos);
  // The staging folder (DIR.partial-<pid>) was renamed into place: nothing
  // but the output is left beside it.
  for (const auto& entry : fs::directory_iterator(out.parent_path())) {
    EXPECT_EQ(entry.path(), out) << "left behind: " << entry.path();
  }
}

// `hcpf score` runs in the thin executable: neither the command library nor
// OpenCV (nor anything else only the other commands need) is loaded, which is
// what keeps the whole-process time low (cli/src/main.cc). LD_DEBUG=libs makes
// the dynamic loader list every library it loads.
TEST(Cli, ScoreRunsWithoutLoadingTheFullProgram) {
  const fs::path out = FreshDir("score_thin") / "crossing";
  ASSERT_EQ(RunCommand(kHcpf + " run " + LibraryScenario("crossing") + " --out " + out.string())
                .exit_code,
            0);
  for (const std::string args : {" score ", " --log-level warn score "}) {
    const auto r = RunCommand("LD_DEBUG=libs " + kHcpf + args + (out / "gt" / "gt.txt").string() +
                              " " + (out / "tracks.txt").string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("HOTA"), std::string::npos) << r.output;
    EXPECT_NE(r.output.find("libstdc++"), std::string::npos) << "LD_DEBUG had no effect:\n"
                                                             << r.output;
    EXPECT_EQ(r.output.find("libhcpf_cli"), std::string::npos) << r.output;
    EXPECT_EQ(r.output.find("libopencv"), std::string::npos) << r.output;
  }
  // Every other command goes through the library.
  const auto r = RunCommand("LD_DEBUG=libs " + kHcpf + " validate " + LibraryScenario("crossing"));
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("libhcpf_cli"), std::string::npos) << r.output;
}

// A third bad-input audit: --json or --events naming an input replaced it
// (exit 0), both naming one file lost the JSON, and a folder or a missing
// parent failed after the table was printed (exit 1); --events and
// --seqinfo were ignored with --trackeval-root. Each is bad input before
// anything is read or written.
TEST(Cli, ScoreOutputsThatWouldReplaceAnInputOrCannotBeWrittenAreRefused) {
  const fs::path dir = FreshDir("score-outputs");
  fs::create_directories(dir / "s" / "gt");
  std::ofstream(dir / "s" / "seqinfo.ini") << "[Sequence]\nname=s\nseqLength=3\n";
  const std::string gt_text = "1,1,10,10,20,20,1,1,1\n2,1,11,10,20,20,1,1,1\n";
  const std::string hyp_text = "1,1,10,10,20,20,1,-1,-1,-1\n2,1,11,10,20,20,1,-1,-1,-1\n";
  std::ofstream(dir / "s" / "gt" / "gt.txt") << gt_text;
  std::ofstream(dir / "hyp.txt") << hyp_text;
  const std::string gt = (dir / "s" / "gt" / "gt.txt").string();
  const std::string hyp = (dir / "hyp.txt").string();
  const std::string base = kHcpf + " score " + gt + " " + hyp;
  for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
           {" --json " + hyp,
            "--json: expected a file score does not read, found the tracker "
            "output (HYP)"},
           {" --events " + gt,
            "--events: expected a file score does not read, found the ground "
            "truth (GT)"},
           {" --json " + (dir / "x").string() + " --events " + (dir / "x").string(),
            "--events: expected a file of its own, found the file --json writes too"},
           {" --json " + dir.string(), "--json: expected a file to write, found a folder"},
           {" --json " + (dir / "no" / "x.json").string(),
            "--json: expected a file in an existing folder"}}) {
    const auto r = RunCommand(base + args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.output;
    EXPECT_NE(r.output.find(message), std::string::npos) << args << "\n" << r.output;
    EXPECT_EQ(r.output.find("HOTA"), std::string::npos) << "a table was printed: " << r.output;
  }
  EXPECT_EQ(ReadFile(dir / "s" / "gt" / "gt.txt"), gt_text);
  EXPECT_EQ(ReadFile(dir / "hyp.txt"), hyp_text);
  EXPECT_FALSE(fs::exists(dir / "x"));
  for (const std::string option : {"--events", "--seqinfo"}) {
    const auto r = RunCommand(kHcpf + " score --trackeval-root " + dir.string() + " " + option +
                              " " + (dir / "e").string());
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find(option + ": expected no " + option + " with --trackeval-root"),
              std::string::npos)
        << r.output;
  }
  // Both outputs beside the inputs are written.
  const auto r = RunCommand(base + " --json " + (dir / "m.json").string() + " --events " +
                            (dir / "e.jsonl").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::is_regular_file(dir / "m.json"));
  EXPECT_TRUE(fs::is_regular_file(dir / "e.jsonl"));
}

// --json /dev/stdout (docs/outputs.md's example) or --events /dev/stdout
// with standard output redirected to a file: the file holds that output alone
// and the table goes to standard error. Before, the table was printed
// through stdout over the first bytes of the JSON (exit 0, a file that did
// not parse; docs audit, 2026-12-05).
TEST(Cli, ScoreWritesItsJsonAloneToStandardOutputAndTheTableToStandardError) {
  const fs::path dir = FreshDir("score-stdout");
  fs::create_directories(dir / "s" / "gt");
  std::ofstream(dir / "s" / "seqinfo.ini") << "[Sequence]\nname=s\nseqLength=3\n";
  std::ofstream(dir / "s" / "gt" / "gt.txt") << "1,1,10,10,20,20,1,1,1\n2,1,11,10,20,20,1,1,1\n";
  std::ofstream(dir / "hyp.txt") << "1,1,10,10,20,20,1,-1,-1,-1\n2,1,11,10,20,20,1,-1,-1,-1\n";
  const std::string base =
      kHcpf + " score " + (dir / "s" / "gt" / "gt.txt").string() + " " + (dir / "hyp.txt").string();
  auto r = RunCommand(base + " --json " + (dir / "m.json").string() + " --events " +
                      (dir / "e.jsonl").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // "-" is standard output too, run in `dir`: it wrote a file named "-" there
  // (an audit of valid input).
  for (const std::string to : {"/dev/stdout", "-"}) {
    for (const auto& [option, file] : std::vector<std::pair<std::string, std::string>>{
             {"--json", "m.json"}, {"--events", "e.jsonl"}}) {
      r = RunCommand("(cd " + dir.string() + " && " + base + " " + option + " " + to + " > " +
                     (dir / "out").string() + " 2> " + (dir / "err").string() + ")");
      EXPECT_EQ(r.exit_code, 0) << option << " " << to << "\n" << r.output;
      EXPECT_EQ(ReadFile(dir / "out"), ReadFile(dir / file)) << option << " " << to;
      EXPECT_NE(ReadFile(dir / "err").find("HOTA"), std::string::npos) << option << " " << to;
      EXPECT_FALSE(fs::exists(dir / "-")) << option << " " << to;
    }
  }
  // Without it, the table is standard output.
  r = RunCommand("(" + base + " > " + (dir / "out").string() + " 2> " + (dir / "err").string() +
                 ")");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(ReadFile(dir / "out").find("HOTA"), std::string::npos);
  EXPECT_EQ(ReadFile(dir / "err").find("HOTA"), std::string::npos);
}

// A gt.json frame as hcpf writes it (core/ground_truth_json.h), 100 x 80 px,
// with targets given as {id, [left, top, width, height], visible fraction,
// truncation}.
struct GtTarget {
  int id;
  std::vector<double> box;
  double visible;
  double truncation;
};
nlohmann::json GtFrame(int frame, const std::vector<GtTarget>& targets) {
  nlohmann::json objects = nlohmann::json::array();
  for (const GtTarget& t : targets) {
    objects.push_back({{"id", t.id},
                       {"in_frame", true},
                       {"amodal_box", t.box},
                       {"visible_box", t.box},
                       {"visible_fraction", t.visible},
                       {"truncation", t.truncation},
                       {"pixels_visible", 100},
                       {"pixels_total", 100},
                       {"position_m", {0.0, 0.0, 0.0}},
                       {"heading_deg", 0.0},
                       {"dimensions_m", {4.0, 2.0, 1.5}}});
  }
  const nlohmann::json identity = {{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}};
  return {{"frame", frame},
          {"camera",
           {{"K", {{100.0, 0.0, 50.0}, {0.0, 100.0, 40.0}, {0.0, 0.0, 1.0}}},
            {"width_px", 100},
            {"height_px", 80},
            {"position_m", {0.0, 0.0, 100.0}},
            {"world_from_camera", identity}}},
          {"image_from_ground", identity},
          {"objects", objects}};
}

// hcpf score --detections: a detector's own det.txt against a gt.json,
// counted by hand. Frame 1: target 1 found exactly; target 2 half outside
// the image (its box clipped to x < 100) found; target 3 visible 0.05, so
// the detection on it is neither true nor false; target 4 a 2 x 2 px box
// found only if the file's 1-based pixels are read as such; one detection on
// nothing. Frame 2: target 1 (visible 0.6) missed. Ids are -1 throughout (not
// identities: no duplicate-id error).
TEST(Cli, ScoreDetectionsScoresADetectorsOwnOutputAgainstAGtJson) {
  const fs::path dir = FreshDir("score-detections");
  const nlohmann::json gt = {{"format", "hcpf-gt/1"},
                             {"source", "rendered"},
                             {"frames",
                              {GtFrame(0, {{1, {10, 10, 20, 20}, 1.0, 0.0},
                                           {2, {90, 40, 20, 20}, 1.0, 0.5},
                                           {3, {50, 50, 10, 10}, 0.05, 0.0},
                                           {4, {30, 60, 2, 2}, 1.0, 0.0}}),
                               GtFrame(1, {{1, {12, 10, 20, 20}, 0.6, 0.0}})}}};
  std::ofstream(dir / "gt.json") << gt.dump(1);
  // Frame 1's five detections (left, top, width, height, score), written
  // with the ids given.
  const auto det_rows = [](const std::vector<int>& ids) {
    const char* boxes[] = {"11,11,20,20,0.9", "91,41,10,20,0.8", "51,51,10,10,0.7", "71,61,8,8,0.6",
                           "31,61,2,2,0.5"};
    std::string text;
    for (size_t i = 0; i < ids.size(); ++i) {
      text += "1," + std::to_string(ids[i]) + "," + boxes[i] + ",-1,-1,-1\n";
    }
    return text;
  };
  std::ofstream(dir / "det.txt") << det_rows({-1, -1, -1, -1, -1});
  const std::string base = kHcpf + " score --detections " + (dir / "gt.json").string() + " " +
                           (dir / "det.txt").string();
  const auto r = RunCommand(base + " --json " + (dir / "d.json").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("(5 detections)"), std::string::npos) << r.output;
  const auto d = nlohmann::json::parse(ReadFile(dir / "d.json"));
  EXPECT_EQ(d["iou"]["tp"], 3) << d["iou"];
  EXPECT_EQ(d["iou"]["fp"], 1) << d["iou"];
  EXPECT_EQ(d["iou"]["fn"], 1) << d["iou"];
  EXPECT_DOUBLE_EQ(d["iou"]["precision"].get<double>(), 0.75);
  // Visible at least 0.75 alone: frame 2's target 1 is don't care too.
  EXPECT_EQ(d["mostly_visible"]["iou"]["tp"], 3);
  EXPECT_EQ(d["mostly_visible"]["iou"]["fn"], 0);
  EXPECT_EQ(d["mostly_visible"]["iou"]["fp"], 1);
  // Truncation [0.5, 1]: target 2, found; size [0, 8): target 4 and the false
  // detection (8 x 8 is the next bin), so one found, none false.
  EXPECT_EQ(d["by_truncation"][3]["iou"]["tp"], 1);
  EXPECT_EQ(d["by_size_px"][0]["iou"]["tp"], 1);
  EXPECT_EQ(d["by_size_px"][0]["iou"]["fp"], 0);
  // Ranked by score: 0.9 and 0.8 found (precision 1 up to recall 0.5), 0.7
  // ignored, 0.6 false, 0.5 found (precision 0.75 at recall 0.75): 51 of the
  // 101 recalls at 1, 25 at 0.75, the rest 0.
  EXPECT_NEAR(d["precision_recall"]["average_precision"].get<double>(), (51 + 25 * 0.75) / 101,
              1e-12);
  // The folder holding the gt.json stands for it.
  const auto folder =
      RunCommand(kHcpf + " score --detections " + dir.string() + " " + (dir / "det.txt").string());
  EXPECT_EQ(folder.exit_code, 0) << folder.output;
  EXPECT_EQ(folder.output, r.output) << folder.output;
  // --min-visible 0.7: frame 2's target 1 no longer counts (recall 1).
  const auto r2 = RunCommand(base + " --min-visible 0.7 --json " + (dir / "e.json").string());
  ASSERT_EQ(r2.exit_code, 0) << r2.output;
  EXPECT_EQ(nlohmann::json::parse(ReadFile(dir / "e.json"))["iou"]["fn"], 0);

  // --labels: column 2 names each detection's target, and a detection may
  // only match its own. Target 1's box labelled 2 is then a false detection
  // and target 1 a miss; target 2's and 4's boxes carry their right labels.
  std::ofstream(dir / "labelled.txt") << det_rows({2, 2, -1, -1, 4});
  const std::string labelled = kHcpf + " score --detections " + (dir / "gt.json").string() + " " +
                               (dir / "labelled.txt").string() + " --json ";
  const auto l = RunCommand(labelled + (dir / "l.json").string() + " --labels");
  ASSERT_EQ(l.exit_code, 0) << l.output;
  const auto ld = nlohmann::json::parse(ReadFile(dir / "l.json"));
  EXPECT_EQ(ld["iou"]["tp"], 2) << ld["iou"];
  EXPECT_EQ(ld["iou"]["fp"], 2) << ld["iou"];
  EXPECT_EQ(ld["iou"]["fn"], 2) << ld["iou"];
  // Their label accuracy, matched with the labels ignored: the boxes on
  // targets 1, 2 and 4 (3 is "don't care", its row unlabelled anyway), two
  // of them labelled right.
  EXPECT_EQ(ld["labels"]["matched"], 3) << ld;
  EXPECT_EQ(ld["labels"]["right"], 2) << ld;
  EXPECT_NE(l.output.find("labels: 2 of the 3 labelled detections on a target (IoU >= 0.5, labels "
                          "ignored) name it: label accuracy 0.667"),
            std::string::npos)
      << l.output;
  // Without --labels the ids are not read: the counts of det.txt, no labels.
  const auto u = RunCommand(labelled + (dir / "u.json").string());
  ASSERT_EQ(u.exit_code, 0) << u.output;
  EXPECT_EQ(nlohmann::json::parse(ReadFile(dir / "u.json"))["iou"], d["iou"]);
  EXPECT_FALSE(nlohmann::json::parse(ReadFile(dir / "u.json")).contains("labels"));
  EXPECT_EQ(u.output.find("label accuracy"), std::string::npos) << u.output;

  // Bad input: exit 2, the file, line and column named, nothing written.
  std::ofstream(dir / "zero.txt") << "1,-1,11,11,20,20,0.9\n2,-1,11,11,0,20,0.9\n";
  std::ofstream(dir / "stranger.txt") << "1,4,11,11,20,20,0.9\n2,9,11,11,20,20,0.9\n";
  // A fourth bad-input audit: a fractional label read as "no label".
  std::ofstream(dir / "fraction.txt") << "1,1.5,11,11,20,20,0.9\n";
  std::ofstream(dir / "late.txt") << "3,-1,11,11,20,20,0.9\n";
  std::ofstream(dir / "far.txt") << "1,-1,1e300,11,20,20,0.9\n";
  for (const auto& [args, message] : std::vector<std::pair<std::string, std::string>>{
           {" --detections " + (dir / "gt.json").string() + " " + (dir / "zero.txt").string(),
            "zero.txt:2:5: column 5 (width): expected a width above 0 px, within 1e+07 px, found "
            "0"},
           {" --detections " + (dir / "gt.json").string() + " " + (dir / "far.txt").string(),
            "far.txt:1:3: column 3 (left): expected a number within 1e+07 px, found 1e+300"},
           {" --detections " + (dir / "gt.json").string() + " " + (dir / "late.txt").string(),
            "late.txt:1:1: column 1 (frame): expected a frame in 1..2"},
           {" --detections " + (dir / "det.txt").string() + " " + (dir / "det.txt").string(),
            "det.txt:1:2: expected a gt.json written by hcpf render or hcpf run"},
           {" --detections --events x " + (dir / "gt.json").string() + " " +
                (dir / "det.txt").string(),
            "--events: expected no --events with --detections"},
           {" --min-visible 0.5 " + (dir / "gt.json").string() + " " + (dir / "det.txt").string(),
            "--min-visible: expected --min-visible only with --detections"},
           {" --min-score 0.5 " + (dir / "gt.json").string() + " " + (dir / "det.txt").string(),
            "--min-score: expected --min-score only with --detections"},
           {" --detections --labels " + (dir / "gt.json").string() + " " +
                (dir / "stranger.txt").string(),
            "stranger.txt:2:2: column 2 (id): expected the id of one of the targets (1, 2, 3, 4), "
            "or -1 for a detection of none: --labels reads column 2 as the target, found 9"},
           {" --detections --labels " + (dir / "gt.json").string() + " " +
                (dir / "fraction.txt").string(),
            "fraction.txt:1:2: column 2 (id): expected the id of one of the targets (1, 2, 3, 4), "
            "or -1 for a detection of none: --labels reads column 2 as the target, found a "
            "fraction (read as 1 by truncation)"},
           {" --labels " + (dir / "gt.json").string() + " " + (dir / "det.txt").string(),
            "--labels: expected --labels only with --detections"}}) {
    const auto bad = RunCommand(kHcpf + " score" + args + " --json " + (dir / "x.json").string());
    EXPECT_EQ(bad.exit_code, 2) << args << "\n" << bad.output;
    EXPECT_NE(bad.output.find(message), std::string::npos) << args << "\n" << bad.output;
    EXPECT_FALSE(fs::exists(dir / "x.json")) << args;
  }
}

TEST(Cli, SameScenarioGivesByteIdenticalOutputs) {
  const fs::path dir = FreshDir("determinism");
  for (const char* name : {"a", "b"}) {
    const auto r =
        RunCommand(kHcpf + " run " + LibraryScenario("climb") + " --out " + (dir / name).string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  // manifest.json differs only in its "timings" (documented); every other file is identical.
  for (const auto& entry : fs::recursive_directory_iterator(dir / "a")) {
    if (!entry.is_regular_file() || entry.path().filename() == "manifest.json") continue;
    const fs::path rel = fs::relative(entry.path(), dir / "a");
    EXPECT_EQ(ReadFile(entry.path()), ReadFile(dir / "b" / rel)) << rel;
  }
}

TEST(Cli, ResolvedScenarioReproducesTheRun) {
  const fs::path dir = FreshDir("resolved");
  auto r = RunCommand(kHcpf + " run " + LibraryScenario("bridge-three") +
                      " --set tracker.particles=300 --out " + (dir / "first").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = RunCommand(kHcpf + " run " + (dir / "first" / "scenario.resolved.yaml").string() + " --out " +
                 (dir / "second").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char* f : {"scenario.resolved.yaml", "gt/gt.txt", "detections.txt", "gt.json"}) {
    EXPECT_EQ(ReadFile(dir / "first" / f), ReadFile(dir / "second" / f)) << f;
  }
  EXPECT_NE(ReadFile(dir / "first" / "scenario.resolved.yaml").find("particles: 300"),
            std::string::npos);
}

TEST(Cli, BadInputExitsTwoAndWritesNothing) {
  const fs::path dir = FreshDir("bad");
  const fs::path bad = dir / "bad.yaml";
  std::ofstream(bad)
      << "frames: 10\ncamera:\n  resolution: [320, 240]\n  path: [{frame: 0, position: [0, 0, 50], "
         "look_at: [0, 0.1, 0]}]\n"
         "targets:\n  - {id: 1, dimensions_m: [4, 2, 1.5], path: {waypoints: [[0, 0]]}}\n"
         "trakcer: {particles: 10}\n";
  auto r = RunCommand(kHcpf + " run " + bad.string() + " --out " + (dir / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("bad.yaml:7:1"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("did you mean \"tracker\""), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "out"));
  r = RunCommand(kHcpf + " validate " + bad.string());
  EXPECT_EQ(r.exit_code, 2);
  r = RunCommand(kHcpf + " run " + LibraryScenario("crossing") +
                 " --set tracker.particles=-3 --out " + (dir / "out").string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--set tracker.particles=-3"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(dir / "out"));
  // An existing folder that is not an earlier run is not clobbered.
  fs::create_directories(dir / "mine");
  std::ofstream(dir / "mine" / "thesis.tex") << "precious";
  r = RunCommand(kHcpf + " run " + LibraryScenario("crossing") + " --out " +
                 (dir / "mine").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_TRUE(fs::exists(dir / "mine" / "thesis.tex"));
  // A bad-input audit: a sweep file where a scenario goes (run, a sweep's
  // base, a suite's scene) failed at its `seeds: 2` ("expected a mapping of
  // keys"); a file as --cache failed a rendered run midway with exit 1.
  std::ofstream(dir / "sweep.yaml") << "base: " << LibraryScenario("crossing")
                                    << "\nseeds: 2\ngrid: {tracker.particles: [10, 20]}\n";
  r = RunCommand(kHcpf + " run " + (dir / "sweep.yaml").string() + " --out " +
                 (dir / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("sweep.yaml:1:1: base: expected a scenario file, found a sweep file"),
            std::string::npos)
      << r.output;
  std::ofstream(dir / "cache") << "x";
  for (const std::string command : {"run", "render"}) {
    r = RunCommand(kHcpf + " " + command + " " + LibraryScenario("crossing") +
                   " --set observation.source=rendered --cache " + (dir / "cache").string() +
                   " --out " + (dir / "out").string());
    EXPECT_EQ(r.exit_code, 2) << command << ": " << r.output;
    EXPECT_NE(r.output.find("--cache: expected a folder (new or existing), found an existing file"),
              std::string::npos)
        << command << ": " << r.output;
  }
  EXPECT_FALSE(fs::exists(dir / "out"));
  // --cache with --no-cache: --cache was ignored, exit 0 (a bad-input audit).
  for (const std::string& command :
       {"run " + LibraryScenario("crossing"), "render " + LibraryScenario("crossing"),
        "sweep " + (dir / "sweep.yaml").string()}) {
    r = RunCommand(kHcpf + " " + command + " --cache " + (dir / "c").string() +
                   " --no-cache --out " + (dir / "out").string());
    EXPECT_EQ(r.exit_code, 2) << command << ": " << r.output;
    EXPECT_NE(r.output.find("--no-cache: expected either --cache DIR or --no-cache, found both"),
              std::string::npos)
        << command << ": " << r.output;
  }
  EXPECT_FALSE(fs::exists(dir / "out"));
}

TEST(Cli, FailingRunExitsOneAndLeavesNoFolder) {
  // --out in a folder of the kernel's where nothing may be created (even by
  // root): the run cannot create its folder. (A path below a regular file
  // was this test's case; it is bad input now, checked before the run.)
  ASSERT_TRUE(fs::is_directory("/proc")) << "this test needs Linux's /proc";
  const auto r =
      RunCommand(kHcpf + " run " + LibraryScenario("crossing") + " --out /proc/hcpf-test-out");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("run failed"), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists("/proc/hcpf-test-out"));
}

// hcpf report on a run's folder writes its report.html (exit 0, path on
// stdout); on a folder that is neither a run's nor a sweep's it is bad input
// (exit 2) naming the folder, what was expected and what was found.
TEST(Cli, ReportOnARunFolderAndOnAnotherFolder) {
  const fs::path dir = FreshDir("report-run");
  const fs::path run = dir / "climb";
  auto r = RunCommand(kHcpf + " run " + LibraryScenario("climb") +
                      " --set frames=30 --set camera.path.2.frame=29 --set camera.path.1.frame=15"
                      " --set tracker.camera_motion=oracle --out " +
                      run.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = RunCommand(kHcpf + " report " + run.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find((run / "report.html").string()), std::string::npos) << r.output;
  const std::string html = ReadFile(run / "report.html");
  EXPECT_NE(html.find("id=\"plot-camera_motion\""), std::string::npos);
  EXPECT_NE(html.find("camera-motion error (oracle)"), std::string::npos);
  // The run folder with its report can be run into again.
  r = RunCommand(kHcpf + " run " + LibraryScenario("climb") +
                 " --set frames=30 --set camera.path.2.frame=29 --set camera.path.1.frame=15"
                 " --out " +
                 run.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  // Compared with a run of another camera-motion mode: one key differs.
  const fs::path oracle = dir / "oracle";
  r = RunCommand(kHcpf + " run " + LibraryScenario("climb") +
                 " --set frames=30 --set camera.path.2.frame=29 --set camera.path.1.frame=15"
                 " --set tracker.camera_motion=oracle --out " +
                 oracle.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = RunCommand(kHcpf + " report " + run.string() + " --against " + oracle.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("against " + oracle.string() + ": 1 resolved key differs"),
            std::string::npos)
      << r.output;
  EXPECT_NE(ReadFile(run / "report.html").find("<code>tracker.camera_motion</code>"),
            std::string::npos);
  // --against again: a third run beside them, each --against taking one
  // folder (DIR after them is still DIR).
  r = RunCommand(kHcpf + " report --against " + oracle.string() + " --against " + oracle.string() +
                 "/ " + run.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--against: expected each run folder once"), std::string::npos)
      << r.output;
  const fs::path none = dir / "none";
  fs::copy(run, none, fs::copy_options::recursive);
  r = RunCommand(kHcpf + " report --against " + oracle.string() + " --against " + none.string() +
                 " " + run.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("; 1 more run beside them"), std::string::npos) << r.output;
  EXPECT_NE(ReadFile(run / "report.html").find("<th>C</th><th>A − C</th>"), std::string::npos);
  // One word per --against (a review: a list took DIR after it, and a
  // second word became a third run): DIR and --out after it are read as
  // before, and a stray word is refused.
  r = RunCommand(kHcpf + " report --against " + oracle.string() + " " + run.string() + " --out " +
                 (dir / "beside").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir / "beside" / "report.html")) << r.output;
  r = RunCommand(kHcpf + " report " + run.string() + " --against " + oracle.string() + " " +
                 none.string() + " --out " + (dir / "stray").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("expected no more arguments, found \"" + none.string() + "\""),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir / "stray"));

  const fs::path other = dir / "other";
  fs::create_directories(other);
  std::ofstream(other / "notes.txt") << "x";
  r = RunCommand(kHcpf + " report " + other.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(other.string()), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("expected a sweep folder"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("found a folder with neither results.sqlite nor manifest.json"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(other / "report.html"));
  r = RunCommand(kHcpf + " report " + run.string() + " --against " + other.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--against: expected another run folder"), std::string::npos) << r.output;

  // A sweep folder: the run beside its cell's seeds, said in the log line;
  // with another --against after it, bad input.
  const fs::path sweep = dir / "sweep";
  std::ofstream(dir / "sweep.yaml") << "base: " << LibraryScenario("climb")
                                    << "\nseeds: 2\ngrid:\n  frames: [30]\n"
                                       "  camera.path.2.frame: [29]\n  camera.path.1.frame: [15]\n"
                                       "  tracker.camera_motion: [none, oracle]\n";
  r = RunCommand(kHcpf + " sweep " + (dir / "sweep.yaml").string() + " --out " + sweep.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = RunCommand(kHcpf + " report " + oracle.string() + " --against " + sweep.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("; beside 2 finished runs of a cell of " + sweep.string() + " (its own)"),
            std::string::npos)
      << r.output;
  EXPECT_NE(ReadFile(oracle / "report.html").find("<code>tracker.camera_motion = oracle</code>"),
            std::string::npos);
  r = RunCommand(kHcpf + " report " + oracle.string() + " --against " + sweep.string() +
                 " --against " + run.string() + " --out " + (dir / "two").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("--against: expected one sweep folder alone"), std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir / "two"));
}

// The strong-motion and low-texture scenes run on rendered frames too, and
// their camera-motion error is a number (no NaN from the scene filter).
TEST(Cli, StrongMotionAndLowTextureScenesRunRendered) {
  for (const char* scene : {"climb-yaw-dive", "low-texture"}) {
    SCOPED_TRACE(scene);
    const fs::path out = FreshDir(std::string("rendered-") + scene) / "run";
    const auto r =
        RunCommand(kHcpf + " run " + LibraryScenario(scene) +
                   " --set observation.source=rendered --no-cache --out " + out.string());
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const auto metrics = nlohmann::json::parse(ReadFile(out / "metrics.json"));
    const auto& camera = metrics.at("camera_motion");
    EXPECT_TRUE(camera.at("mean_px").is_number()) << camera.dump();
    EXPECT_TRUE(std::isfinite(camera.at("mean_px").get<double>())) << camera.dump();
    EXPECT_TRUE(std::isfinite(camera.at("floor").at("mean_px").get<double>())) << camera.dump();
  }
}

class ShippedScenario : public ::testing::TestWithParam<std::string> {};

TEST_P(ShippedScenario, ValidatesAndRuns) {
  auto r = RunCommand(kHcpf + " validate " + LibraryScenario(GetParam()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::string name = GetParam();
  std::replace(name.begin(), name.end(), '/', '-');
  const fs::path out = FreshDir("shipped-" + name) / "run";
  r = RunCommand(kHcpf + " run " + LibraryScenario(GetParam()) + " --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_GT(fs::file_size(out / "gt" / "gt.txt"), 0u);
}

INSTANTIATE_TEST_SUITE_P(Library, ShippedScenario,
                         ::testing::Values("crossing", "crossing-dominant", "parallel",
                                           "dominant-passes-weak", "bridge-three", "climb",
                                           "thesis/tc1-regular-swap", "thesis/tc2-regular-hijack",
                                           "thesis/tc3-charged", "thesis/tc4-charged-low-variance",
                                           "thesis/tc5-charged-occlusion", "thesis/parallel-close",
                                           "thesis/ch11-single-climb", "thesis/ch11-crossing-climb",
                                           "thesis/ch11-parallel-climb", "climb-yaw-dive",
                                           "low-texture"),
                         [](const auto& info) {
                           std::string n = info.param;
                           std::replace(n.begin(), n.end(), '-', '_');
                           std::replace(n.begin(), n.end(), '/', '_');
                           return n;
                         });

// Rendered library scenarios (a detector on the frames) validate and run;
// a few frames each, to keep the suite short.
class ShippedRenderedScenario : public ::testing::TestWithParam<std::string> {};

TEST_P(ShippedRenderedScenario, ValidatesAndRunsItsDetector) {
  auto r = RunCommand(kHcpf + " validate " + LibraryScenario(GetParam()));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::string name = GetParam();
  std::replace(name.begin(), name.end(), '/', '-');
  const fs::path out = FreshDir("shipped-rendered-" + name) / "run";
  // The climbing camera's last keyframe moves to the last of the 12 frames.
  const std::string climb =
      GetParam().starts_with("thesis/ch10") ? " --set camera.path.1.frame=11" : "";
  r = RunCommand(kHcpf + " run " + LibraryScenario(GetParam()) + " --set frames=12" + climb +
                 " --no-cache --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_GT(fs::file_size(out / "gt" / "gt.txt"), 0u);
  EXPECT_TRUE(fs::exists(out / "det" / "det.txt"));
}

INSTANTIATE_TEST_SUITE_P(Library, ShippedRenderedScenario,
                         ::testing::Values("vision/size-ladder",
                                           "thesis/ch10-static-crossing-low-variance",
                                           "thesis/ch10-static-crossing-high-variance",
                                           "thesis/ch10-static-parallel-high-variance"),
                         [](const auto& info) {
                           std::string n = info.param;
                           std::replace(n.begin(), n.end(), '-', '_');
                           std::replace(n.begin(), n.end(), '/', '_');
                           return n;
                         });

}  // namespace
}  // namespace hcpf
