// End-to-end tests of hcpf sweep / merge / report / regress through the real
// executable: resume after SIGKILL, SIGINT and SIGTERM, shards + merge, the report in
// headless Chromium, and the regression gate's exit codes.

#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sqlite3.h>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <regex>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "support/process.h"

namespace hcpf {
namespace {

namespace fs = std::filesystem;
using testing::FreshDir;
using testing::ReadFile;
using testing::RunCommand;

using testing::kHcpf;
const fs::path kSource = HCPF_SOURCE_DIR;

// Rows of a results store as text (deterministic columns only: no timings;
// the build that made each run last).
std::vector<std::string> StoreRows(const fs::path& store) {
  std::vector<std::string> rows;
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(store.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
    sqlite3_close(db);
    return rows;
  }
  sqlite3_busy_timeout(db, 5000);
  sqlite3_stmt* s = nullptr;
  const char* sql =
      "SELECT key, run_index, seed, status, da_accuracy, hijack_rate, idf1, hota, mota, ospa, "
      "\"tracker.particles\", build FROM runs ORDER BY run_index";
  if (sqlite3_prepare_v2(db, sql, -1, &s, nullptr) == SQLITE_OK) {
    while (sqlite3_step(s) == SQLITE_ROW) {
      std::string row;
      for (int c = 0; c < sqlite3_column_count(s); ++c) {
        const unsigned char* t = sqlite3_column_text(s, c);
        row += (t ? reinterpret_cast<const char*>(t) : "NULL") + std::string("|");
      }
      rows.push_back(row);
    }
  }
  sqlite3_finalize(s);
  sqlite3_close(db);
  return rows;
}

// A sweep of crossing-dominant (shortened to `frames`): 4 particle counts x 2 resamplers x seeds.
std::string WriteSweep(const fs::path& dir, int seeds = 4, int frames = 60) {
  const std::string base = testing::LibraryScenario("crossing-dominant");
  std::ofstream(dir / "sweep.yaml")
      << "base: " << base << "\n"
      << "seeds: " << seeds << "\n"
      << "grid:\n"
      << "  frames: [" << frames << "]\n"
      << "  tracker.particles: [100, 300, 1000, 3000]\n"
      << "  tracker.resampling.method: [systematic, charged]\n"
      << "report: {x: tracker.particles, series: tracker.resampling.method, "
         "y: [da_accuracy, idf1, ms_per_frame]}\n";
  return (dir / "sweep.yaml").string();
}

// Starts `hcpf args...` as a child (output to `log`) and returns its pid.
// SIGINT, SIGTERM and SIGHUP start at their default action (whatever this
// test was started with), SIGINT ignored when `ignore_sigint`.
pid_t Spawn(const std::vector<std::string>& args, const fs::path& log, bool ignore_sigint = false) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) ::signal(signal_number, SIG_DFL);
    if (ignore_sigint) ::signal(SIGINT, SIG_IGN);
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ::dup2(fd, STDOUT_FILENO);
    ::dup2(fd, STDERR_FILENO);
    std::vector<char*> argv;
    argv.push_back(const_cast<char*>(kHcpf.c_str()));
    for (const std::string& a : args) argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    ::execv(kHcpf.c_str(), argv.data());
    ::_exit(127);
  }
  return pid;
}

class SweepResume : public ::testing::TestWithParam<int> {};

TEST_P(SweepResume, KilledMidwayThenResumedLosesAndRepeatsNothing) {
  const int signal_number = GetParam();
  const fs::path dir = FreshDir("sweep-resume-" + std::to_string(signal_number));
  const std::string sweep = WriteSweep(dir);
  // The uninterrupted reference.
  auto ref =
      RunCommand(kHcpf + " sweep " + sweep + " --out " + (dir / "ref").string() + " --jobs 2");
  ASSERT_EQ(ref.exit_code, 0) << ref.output;
  const std::vector<std::string> expected = StoreRows(dir / "ref" / "results.sqlite");
  ASSERT_EQ(expected.size(), 32U);

  // Kill after a few runs are stored.
  const fs::path out = dir / "out";
  const pid_t pid =
      Spawn({"sweep", sweep, "--out", out.string(), "--jobs", "2"}, dir / "first.log");
  ASSERT_GT(pid, 0);
  size_t stored = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (std::chrono::steady_clock::now() < deadline) {
    if (fs::exists(out / "results.sqlite")) stored = StoreRows(out / "results.sqlite").size();
    if (stored >= 4) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ::kill(pid, signal_number);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status))
      << "the sweep finished before it could be killed; make it longer\n"
      << ReadFile(dir / "first.log");
  // Ctrl-C and a batch system's SIGTERM say how to go on (a SIGKILL cannot).
  const std::string announcement =
      "hcpf sweep: interrupted; the runs finished so far are kept in " + out.string() +
      "/results.sqlite and the same command again resumes the sweep (SIG" +
      ::sigabbrev_np(signal_number) + ")\n";
  const bool announced = ReadFile(dir / "first.log").find(announcement) != std::string::npos;
  EXPECT_EQ(announced, signal_number != SIGKILL) << ReadFile(dir / "first.log");
  const size_t after_kill = StoreRows(out / "results.sqlite").size();
  ASSERT_GE(after_kill, 4U);
  ASSERT_LT(after_kill, 32U) << "the kill came too late to test resuming";

  // Resume: reuses exactly what was stored, computes the rest.
  auto second = RunCommand(kHcpf + " sweep " + sweep + " --out " + out.string() + " --jobs 2");
  ASSERT_EQ(second.exit_code, 0) << second.output;
  const std::regex finished(
      "sweep finished: 32 runs, ([0-9]+) reused, ([0-9]+) computed, 0 failed");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(second.output, m, finished)) << second.output;
  EXPECT_EQ(std::stoul(m[1]), after_kill);
  EXPECT_EQ(std::stoul(m[2]), 32U - after_kill);
  // The final store equals the uninterrupted one: nothing lost, nothing twice.
  EXPECT_EQ(StoreRows(out / "results.sqlite"), expected);
  // One finished folder per run; no partial folders left behind.
  int folders = 0;
  for (const auto& e : fs::directory_iterator(out / "runs")) {
    EXPECT_EQ(e.path().filename().string().find(".partial-"), std::string::npos) << e.path();
    EXPECT_TRUE(fs::exists(e.path() / "manifest.json")) << e.path();
    ++folders;
  }
  EXPECT_EQ(folders, 32);
  // A third invocation computes nothing.
  auto third = RunCommand(kHcpf + " sweep " + sweep + " --out " + out.string() + " --jobs 2");
  EXPECT_NE(third.output.find("32 reused, 0 computed"), std::string::npos) << third.output;
}

INSTANTIATE_TEST_SUITE_P(Signals, SweepResume, ::testing::Values(SIGKILL, SIGINT, SIGTERM),
                         [](const auto& info) {
                           return std::string("SIG") + ::sigabbrev_np(info.param);
                         });

// The state and parent of process `pid` (fields 3 and 4 of /proc/<pid>/stat),
// or nothing when there is no such process.
std::optional<std::pair<char, pid_t>> ProcessStat(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text;
  if (!std::getline(stat, text)) return std::nullopt;
  const size_t close = text.rfind(')');  // the command name may hold spaces
  if (close == std::string::npos) return std::nullopt;
  std::istringstream rest(text.substr(close + 2));
  char state = 0;
  pid_t ppid = 0;
  if (!(rest >> state >> ppid)) return std::nullopt;
  return std::make_pair(state, ppid);
}

// Whether `pid` still runs: it exists and is not a zombie waiting to be reaped.
bool Running(pid_t pid) {
  const auto stat = ProcessStat(pid);
  return stat && stat->first != 'Z';
}

// The running children of `parent`.
std::vector<pid_t> ChildrenOf(pid_t parent) {
  std::vector<pid_t> children;
  for (const auto& entry : fs::directory_iterator("/proc")) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    const pid_t pid = static_cast<pid_t>(std::stol(name));
    const auto stat = ProcessStat(pid);
    if (stat && stat->second == parent && stat->first != 'Z') children.push_back(pid);
  }
  return children;
}

// Crashes one of the sweep `parent`'s `hcpf run` children (SIGSEGV, as a
// segfault or the OOM killer would) once one has been exec'd, waiting up to
// 60 s; false when no child was seen.
bool CrashOneChildRun(pid_t parent) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (std::chrono::steady_clock::now() < deadline) {
    for (const pid_t child : ChildrenOf(parent)) {
      // Once it is `hcpf run` (a child just forked is still the sweep).
      const fs::path proc = fs::path("/proc") / std::to_string(child);
      if (ReadFile(proc / "cmdline").find(std::string("\0run\0", 5)) == std::string::npos) {
        continue;
      }
      if (::kill(child, SIGSEGV) == 0) return true;
    }
  }
  return false;
}

// hcpf with `args` (its output in `log_file`), one of its `hcpf run` children
// crashed (CrashOneChildRun), waited for: whether a child was crashed, how
// hcpf ended, its log.
struct CrashedChildRun {
  bool crashed = false;
  int status = 0;
  std::string log;
};
CrashedChildRun RunAndCrashOneChild(const std::vector<std::string>& args,
                                    const fs::path& log_file) {
  CrashedChildRun result;
  const pid_t pid = Spawn(args, log_file);
  if (pid <= 0) return result;
  result.crashed = CrashOneChildRun(pid);
  ::waitpid(pid, &result.status, 0);
  result.log = ReadFile(log_file);
  return result;
}

// An --isolate sweep sent SIGTERM alone (not its process group: a batch
// system's kill of the main process) takes its runs with it; they used to go
// on writing into the folder after the sweep had gone.
TEST(SweepInterrupt, AnIsolatedSweepKilledAloneTakesItsRunsWithIt) {
  const fs::path dir = FreshDir("sweep-isolate-killed");
  // Runs of several seconds each (600000 particles a filter), so a run
  // outliving the sweep would be seen.
  std::ofstream(dir / "sweep.yaml") << "base: " << testing::LibraryScenario("crossing-dominant")
                                    << "\nseeds: 2\ngrid:\n  tracker.particles: [600000]\n";
  const fs::path out = dir / "out";
  const pid_t pid = Spawn(
      {"sweep", (dir / "sweep.yaml").string(), "--out", out.string(), "--jobs", "2", "--isolate"},
      dir / "first.log");
  ASSERT_GT(pid, 0);
  // The sweep's children are its runs (`hcpf run` on OUT/runs/<key>.input.yaml).
  auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  std::vector<pid_t> runs = ChildrenOf(pid);
  while (std::chrono::steady_clock::now() < deadline && runs.empty()) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    runs = ChildrenOf(pid);
  }
  ASSERT_FALSE(runs.empty()) << ReadFile(dir / "first.log");
  ::kill(pid, SIGTERM);
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << ReadFile(dir / "first.log");
  // The runs end within moments (SIGTERM from the kernel when the sweep is
  // gone); a run left going would take seconds more.
  deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  const auto still_running = [&] {
    std::vector<pid_t> left;
    for (const pid_t run : runs) {
      if (Running(run)) left.push_back(run);
    }
    return left;
  };
  std::vector<pid_t> left = still_running();
  while (!left.empty() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
    left = still_running();
  }
  for (const pid_t run : left) ::kill(run, SIGKILL);
  EXPECT_TRUE(left.empty()) << left.size() << " run(s) outlived the sweep";
}

// `hcpf run` and `hcpf render` interrupted (Ctrl-C, a batch system's
// SIGTERM) end by the signal as before, and say what is left: nothing in
// --out (written through a staging folder), the frames rendered so far in
// the frame cache. They used to end silently.
TEST(RunInterrupt, RunAndRenderSayWhatIsLeft) {
  const fs::path dir = FreshDir("run-interrupted");
  struct Case {
    std::string command;
    int signal_number;
  };
  for (const Case& c : {Case{"run", SIGINT}, Case{"render", SIGTERM}}) {
    const fs::path out = dir / (c.command + "-out");
    const fs::path cache = dir / (c.command + "-cache");
    std::vector<std::string> args = {c.command, testing::LibraryScenario("crossing"),
                                     "--out",   out.string(),
                                     "--cache", cache.string()};
    if (c.command == "run") {
      args.insert(args.end(), {"--set", "observation.source=rendered"});
    }
    const fs::path log = dir / (c.command + ".log");
    const pid_t pid = Spawn(args, log);
    ASSERT_GT(pid, 0);
    // Interrupted once a few frames are in the cache.
    const auto cached = [&] {
      size_t files = 0;
      std::error_code ec;
      for (fs::recursive_directory_iterator it(cache, ec), end; !ec && it != end;
           it.increment(ec)) {
        files += it->is_regular_file(ec) ? 1 : 0;
      }
      return files;
    };
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (std::chrono::steady_clock::now() < deadline && cached() < 4) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    ::kill(pid, c.signal_number);
    int status = 0;
    ::waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFSIGNALED(status)) << "it finished before it could be interrupted\n"
                                     << ReadFile(log);
    EXPECT_EQ(WTERMSIG(status), c.signal_number);
    EXPECT_NE(ReadFile(log).find(
                  "hcpf " + c.command + ": interrupted; nothing was written to " + out.string() +
                  " (an earlier output there is kept; what was written so far, in " + out.string() +
                  ".partial-" + std::to_string(pid) +
                  ", is removed by the next hcpf run or hcpf render into it); the frames "
                  "rendered so far are kept in the frame cache " +
                  cache.string() + ", so the same command again starts from them (SIG" +
                  ::sigabbrev_np(c.signal_number) + ")\n"),
              std::string::npos)
        << ReadFile(log);
    EXPECT_FALSE(fs::exists(out));
    EXPECT_GE(cached(), 4U);
    // The staging folder the message names is there, and the next command
    // into the same folder removes it (its process no longer runs).
    const fs::path partial = out.string() + ".partial-" + std::to_string(pid);
    EXPECT_TRUE(fs::is_directory(partial));
    std::string again = kHcpf;
    for (const std::string& a : args) again += " " + a;
    const auto r = RunCommand(again + " --set frames=20");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_FALSE(fs::exists(partial));
    EXPECT_TRUE(fs::exists(out / "manifest.json"));
  }
}

// `hcpf regress` interrupted says what is left: no baseline, JUnit or
// Markdown file written, and its temporary run folder, which the next regress
// removes (it used to end silently and leave TMPDIR/hcpf-regress-<pid>, run
// folders and all, for good).
TEST(RunInterrupt, RegressSaysWhatIsLeftAndTheNextRemovesItsRunFolder) {
  const fs::path dir = FreshDir("regress-interrupted");
  const fs::path tmp = dir / "tmp";
  fs::create_directories(tmp);
  // A scene of several seconds (600000 particles a filter).
  std::ofstream(dir / "suite.yaml")
      << "scenes:\n  - {name: slow, scenario: " << testing::LibraryScenario("crossing-dominant")
      << ", set: {tracker.particles: 600000}}\n"
         "metrics:\n  idf1: {tolerance: 0.01}\n";
  const fs::path baseline = dir / "baseline.json", junit = dir / "junit.xml";
  const char* old_tmpdir = std::getenv("TMPDIR");
  const std::string kept_tmpdir = old_tmpdir ? old_tmpdir : "";
  ::setenv("TMPDIR", tmp.c_str(), 1);
  const pid_t pid = Spawn({"regress", (dir / "suite.yaml").string(), "--baseline",
                           baseline.string(), "--update-baseline", "--junit", junit.string()},
                          dir / "first.log");
  if (old_tmpdir) {
    ::setenv("TMPDIR", kept_tmpdir.c_str(), 1);
  } else {
    ::unsetenv("TMPDIR");
  }
  ASSERT_GT(pid, 0);
  const fs::path runs = tmp / ("hcpf-regress.partial-" + std::to_string(pid));
  // Interrupted once the scene's run is under way (its staging folder is in
  // the run folder).
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  std::error_code ec;
  while (std::chrono::steady_clock::now() < deadline &&
         (!fs::exists(runs, ec) || fs::is_empty(runs, ec))) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ::kill(pid, SIGINT);
  int status = 0;
  ::waitpid(pid, &status, 0);
  const std::string log = ReadFile(dir / "first.log");
  ASSERT_TRUE(WIFSIGNALED(status)) << "it finished before it could be interrupted\n" << log;
  EXPECT_EQ(WTERMSIG(status), SIGINT);
  EXPECT_NE(log.find("hcpf regress: interrupted before every scene had run; nothing was written "
                     "to " +
                     baseline.string() + ", " + junit.string() +
                     " (an earlier file is kept); the temporary run folder " + runs.string() +
                     " is removed by the next hcpf regress (SIGINT)\n"),
            std::string::npos)
      << log;
  EXPECT_FALSE(fs::exists(baseline));
  EXPECT_FALSE(fs::exists(junit));
  ASSERT_TRUE(fs::exists(runs));

  // The next regress removes it, and nothing else in TMPDIR.
  fs::create_directories(tmp / "hcpf-regress.partial-1");  // init's: a live process
  fs::create_directories(tmp / "other");
  std::ofstream(dir / "quick.yaml")
      << "scenes:\n  - {name: q, scenario: " << testing::LibraryScenario("crossing-dominant")
      << ", set: {frames: 5}}\nmetrics:\n  idf1: {tolerance: 0.01}\n";
  const auto next = RunCommand("TMPDIR=" + tmp.string() + " " + kHcpf + " regress " +
                               (dir / "quick.yaml").string() + " --baseline " +
                               (dir / "quick.json").string() + " --update-baseline");
  ASSERT_EQ(next.exit_code, 0) << next.output;
  EXPECT_FALSE(fs::exists(runs));
  EXPECT_TRUE(fs::exists(tmp / "hcpf-regress.partial-1"));
  EXPECT_TRUE(fs::exists(tmp / "other"));
  // Its own temporary folder is gone too.
  EXPECT_EQ(std::distance(fs::directory_iterator(tmp), {}), 2);
}

// A sweep started with SIGINT ignored (a background job of a script, nohup)
// keeps ignoring it: it neither stops nor announces an interruption.
TEST(SweepInterrupt, AnIgnoredSigintStaysIgnored) {
  const fs::path dir = FreshDir("sweep-sigint-ignored");
  const std::string sweep = WriteSweep(dir, 2);
  const fs::path out = dir / "out";
  const pid_t pid = Spawn({"sweep", sweep, "--out", out.string(), "--jobs", "2"}, dir / "first.log",
                          /*ignore_sigint=*/true);
  ASSERT_GT(pid, 0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  while (std::chrono::steady_clock::now() < deadline && !fs::exists(out / "results.sqlite")) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ::kill(pid, SIGINT);
  int status = 0;
  ::waitpid(pid, &status, 0);
  const std::string log = ReadFile(dir / "first.log");
  ASSERT_TRUE(WIFEXITED(status)) << log;
  EXPECT_EQ(WEXITSTATUS(status), 0) << log;
  EXPECT_EQ(log.find("interrupted"), std::string::npos) << log;
  EXPECT_NE(log.find("sweep finished: 16 runs"), std::string::npos) << log;
}

TEST(SweepCli, IsolatedRunThatCrashesIsRecordedAndTheOthersFinish) {
  const fs::path dir = FreshDir("sweep-isolate-crash");
  const std::string sweep = WriteSweep(dir);  // 32 runs
  const fs::path out = dir / "out";
  // Crash one run: SIGSEGV to one of the sweep's `hcpf run` children.
  const auto [crashed, status, log] = RunAndCrashOneChild(
      {"sweep", sweep, "--out", out.string(), "--jobs", "2", "--isolate"}, dir / "sweep.log");
  ASSERT_TRUE(crashed) << "no child run was seen: " << log;
  ASSERT_TRUE(WIFEXITED(status)) << log;
  EXPECT_EQ(WEXITSTATUS(status), 1) << log;  // some run failed
  EXPECT_NE(log.find("31 computed, 1 failed"), std::string::npos) << log;
  EXPECT_NE(log.find("crashed: killed by signal 11"), std::string::npos) << log;
  const auto rows = StoreRows(out / "results.sqlite");
  ASSERT_EQ(rows.size(), 32U);
  EXPECT_EQ(
      std::count_if(rows.begin(), rows.end(),
                    [](const std::string& r) { return r.find("|failed|") != std::string::npos; }),
      1);
  // Resuming reruns only the crashed run.
  const auto again =
      RunCommand(kHcpf + " sweep " + sweep + " --out " + out.string() + " --jobs 2 --isolate");
  EXPECT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NE(again.output.find("31 reused, 1 computed, 0 failed"), std::string::npos)
      << again.output;
  // Runs in child processes give the same results as runs in worker threads.
  ASSERT_EQ(
      RunCommand(kHcpf + " sweep " + sweep + " --out " + (dir / "threads").string() + " --jobs 2")
          .exit_code,
      0);
  EXPECT_EQ(StoreRows(out / "results.sqlite"), StoreRows(dir / "threads" / "results.sqlite"));
}

// A process's GL contexts share llvmpipe's one rasteriser, run on the thread
// that draws (docs/sweeps.md): with --jobs 2 each rendered run is a child
// process of its own, without --isolate, so runs render side by side.
// Killing one fails that run alone, as under --isolate, and the results are
// those of --jobs 1, where the runs render in this process.
TEST(SweepCli, RenderedRunsSideBySideEachRunInAProcessOfItsOwn) {
  const fs::path dir = FreshDir("sweep-render-children");
  std::ofstream(dir / "sweep.yaml") << "base: " << testing::LibraryScenario("crossing-dominant")
                                    << "\nseeds: 4\n"
                                       "grid:\n"
                                       "  frames: [30]\n"
                                       "  observation.source: [rendered]\n"
                                       "  tracker.particles: [100, 300]\n";
  const std::string sweep = (dir / "sweep.yaml").string();
  const std::string cache = (dir / "cache").string();
  const fs::path out = dir / "out";
  const auto [crashed, status, log] = RunAndCrashOneChild(
      {"sweep", sweep, "--out", out.string(), "--jobs", "2", "--cache", cache}, dir / "sweep.log");
  ASSERT_TRUE(crashed) << "no child run was seen: " << log;
  ASSERT_TRUE(WIFEXITED(status)) << log;
  EXPECT_EQ(WEXITSTATUS(status), 1) << log;
  EXPECT_NE(log.find("each rendered run in a process of its own (--jobs 2)"), std::string::npos)
      << log;
  EXPECT_NE(log.find("7 computed, 1 failed"), std::string::npos) << log;
  EXPECT_NE(log.find("crashed: killed by signal 11"), std::string::npos) << log;
  const auto again = RunCommand(kHcpf + " sweep " + sweep + " --out " + out.string() +
                                " --jobs 2 --cache " + cache);
  EXPECT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NE(again.output.find("7 reused, 1 computed, 0 failed"), std::string::npos) << again.output;
  const auto one = RunCommand(kHcpf + " sweep " + sweep + " --out " + (dir / "one").string() +
                              " --jobs 1 --cache " + cache);
  ASSERT_EQ(one.exit_code, 0) << one.output;
  EXPECT_EQ(one.output.find("process of its own"), std::string::npos) << one.output;
  const auto rows = StoreRows(out / "results.sqlite");
  EXPECT_EQ(rows.size(), 8U);
  EXPECT_EQ(rows, StoreRows(dir / "one" / "results.sqlite"));
}

TEST(SweepCli, ShardsMergedEqualTheUnshardedSweepAndOtherSweepsAreRefused) {
  const fs::path dir = FreshDir("sweep-shards");
  const std::string sweep = WriteSweep(dir, 2);
  ASSERT_EQ(RunCommand(kHcpf + " sweep " + sweep + " --out " + (dir / "all").string() + " --jobs 2")
                .exit_code,
            0);
  for (int i = 0; i < 2; ++i) {
    auto r = RunCommand(kHcpf + " sweep " + sweep + " --out " +
                        (dir / ("s" + std::to_string(i))).string() + " --jobs 2 --shard " +
                        std::to_string(i) + "/2");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_NE(r.output.find("8 runs in shard " + std::to_string(i) + "/2"), std::string::npos)
        << r.output;
  }
  auto merge = RunCommand(kHcpf + " merge " + (dir / "merged").string() + " " +
                          (dir / "s0").string() + " " + (dir / "s1").string());
  ASSERT_EQ(merge.exit_code, 0) << merge.output;
  EXPECT_NE(merge.output.find("16 runs added, 0 duplicates"), std::string::npos) << merge.output;
  EXPECT_EQ(StoreRows(dir / "merged" / "results.sqlite"),
            StoreRows(dir / "all" / "results.sqlite"));
  // Bad shard spec and a store of another sweep: bad input.
  EXPECT_EQ(
      RunCommand(kHcpf + " sweep " + sweep + " --out " + (dir / "x").string() + " --shard 2/2")
          .exit_code,
      2);
  const std::string other = WriteSweep(FreshDir("sweep-shards-other"), 1);
  ASSERT_EQ(RunCommand(kHcpf + " sweep " + other + " --out " + (dir / "o").string()).exit_code, 0);
  EXPECT_EQ(RunCommand(kHcpf + " merge " + (dir / "m2").string() + " " + (dir / "s0").string() +
                       " " + (dir / "o").string())
                .exit_code,
            2);
}

// The files of every run folder under DIR/runs, by key, minus manifest.json
// (its timings differ between two computations of one run).
std::map<std::string, std::string> RunFiles(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& run : fs::directory_iterator(dir / "runs")) {
    for (const auto& f : fs::recursive_directory_iterator(run.path())) {
      if (!f.is_regular_file() || f.path().filename() == "manifest.json") continue;
      files[fs::relative(f.path(), dir).string()] = ReadFile(f.path());
    }
  }
  return files;
}

// hcpf sweep --reuse OTHER: a sweep grown from 2 seeds to 3 copies the 16 runs
// the 2-seed sweep finished and computes the 8 new ones, and its store and run
// files equal a fresh 3-seed sweep's; a donor run whose folder is damaged is
// computed instead; a --reuse that names no other sweep folder is bad input
// before anything is written.
TEST(SweepCli, ReuseCopiesTheRunsAnotherSweepFinishedAndEqualsAFreshSweep) {
  const fs::path dir = FreshDir("sweep-reuse");
  fs::create_directories(dir / "two");
  fs::create_directories(dir / "three");
  const std::string two = WriteSweep(dir / "two", 2);
  const std::string three = WriteSweep(dir / "three", 3);
  auto r = RunCommand(kHcpf + " sweep " + two + " --out " + (dir / "d2").string() + " --jobs 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = RunCommand(kHcpf + " sweep " + three + " --out " + (dir / "fresh").string() + " --jobs 2");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = RunCommand(kHcpf + " sweep " + three + " --out " + (dir / "grown").string() +
                 " --jobs 2 --reuse " + (dir / "d2").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("sweep: 16 runs copied from " + (dir / "d2").string()), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("24 runs, 16 reused (16 copied from --reuse), 8 computed, 0 failed"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(StoreRows(dir / "grown" / "results.sqlite"),
            StoreRows(dir / "fresh" / "results.sqlite"));
  EXPECT_EQ(RunFiles(dir / "grown"), RunFiles(dir / "fresh"));
  // Resumed, the grown sweep has nothing left to do.
  r = RunCommand(kHcpf + " sweep " + three + " --out " + (dir / "grown").string() + " --reuse " +
                 (dir / "d2").string());
  EXPECT_NE(r.output.find("24 runs, 24 reused, 0 computed"), std::string::npos) << r.output;

  // What a run did not write (a report made in its folder later) stays
  // behind; a run made by another build is copied, and said to be.
  std::vector<fs::path> donor_runs;
  for (const auto& e : fs::directory_iterator(dir / "d2" / "runs")) donor_runs.push_back(e.path());
  std::sort(donor_runs.begin(), donor_runs.end());
  std::ofstream(donor_runs[1] / "report.html") << "<html></html>";
  auto manifest = nlohmann::json::parse(ReadFile(donor_runs[1] / "manifest.json"));
  manifest["git_revision"] = "0123456789ab";
  std::ofstream(donor_runs[1] / "manifest.json") << manifest.dump();
  r = RunCommand(kHcpf + " sweep " + three + " --out " + (dir / "other-build").string() +
                 " --jobs 2 --reuse " + (dir / "d2").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("sweep: 1 of the copied runs were made by hcpf " +
                          manifest["hcpf_version"].get<std::string>() +
                          " at 0123456789ab, this is hcpf " +
                          manifest["hcpf_version"].get<std::string>() + " at "),
            std::string::npos)
      << r.output;
  EXPECT_TRUE(fs::exists(dir / "other-build" / "runs" / donor_runs[1].filename() / "tracks.txt"));
  EXPECT_FALSE(fs::exists(dir / "other-build" / "runs" / donor_runs[1].filename() / "report.html"));
  // The store keeps the build the copied run names (the sweep report counts
  // the builds from it): the fresh sweep's rows but that run's build.
  std::vector<std::string> with_other_build = StoreRows(dir / "fresh" / "results.sqlite");
  int other_build_rows = 0;
  for (std::string& row : with_other_build) {
    if (row.rfind(donor_runs[1].filename().string() + "|", 0) != 0) continue;
    row = row.substr(0, row.rfind(" at ")) + " at 0123456789ab|";
    ++other_build_rows;
  }
  EXPECT_EQ(other_build_rows, 1);
  EXPECT_EQ(StoreRows(dir / "other-build" / "results.sqlite"), with_other_build);

  // A folder a sweep or merge holds is not read.
  {
    const int fd = ::open((dir / "d2" / "sweep.lock").c_str(), O_RDWR);
    ASSERT_GE(fd, 0);
    ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
    r = RunCommand(kHcpf + " sweep " + three + " --out " + (dir / "locked").string() + " --reuse " +
                   (dir / "d2").string());
    ::close(fd);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("where a sweep or merge is running"), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "locked" / "runs"));
  }

  // A damaged run folder of the donor is not copied.
  const fs::path damaged = donor_runs[0];
  fs::remove(damaged / "tracks.txt");
  r = RunCommand(kHcpf + " sweep " + three + " --out " + (dir / "again").string() +
                 " --jobs 2 --reuse " + (dir / "d2").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("24 runs, 15 reused (15 copied from --reuse), 9 computed"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(StoreRows(dir / "again" / "results.sqlite"), with_other_build);

  // An external tracker's runs are computed again: its program is in their
  // key by path, not content.
  fs::create_directories(dir / "ext");
  std::ofstream(dir / "ext" / "sweep.yaml")
      << "base: " << testing::LibraryScenario("crossing-dominant") << "\nseeds: 2\ngrid:\n"
      << "  frames: [30]\n  tracker.type: [external]\n  tracker.command: [["
      << (kSource / "examples" / "trackers" / "sort_tracker.py").string() << "]]\n";
  const std::string ext = (dir / "ext" / "sweep.yaml").string();
  r = RunCommand(kHcpf + " sweep " + ext + " --out " + (dir / "e1").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = RunCommand(kHcpf + " sweep " + ext + " --out " + (dir / "e2").string() + " --reuse " +
                 (dir / "e1").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("2 run(s) of an external tracker are computed, not copied"),
            std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("2 runs, 0 reused, 2 computed"), std::string::npos) << r.output;

  fs::create_directories(dir / "plain");
  for (const auto& [reuse, found] : std::vector<std::pair<fs::path, std::string>>{
           {dir / "missing", "no such folder"},
           {dir / "plain", "a folder without results.sqlite"},
           {dir / "bad", "the --out folder itself"}}) {
    if (reuse == dir / "bad") fs::create_directories(dir / "bad");
    if (reuse == dir / "bad") std::ofstream(dir / "bad" / "results.sqlite") << "";
    r = RunCommand(kHcpf + " sweep " + three + " --out " + (dir / "bad").string() + " --reuse " +
                   reuse.string());
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_NE(r.output.find("--reuse: expected another sweep folder"), std::string::npos)
        << r.output;
    EXPECT_NE(r.output.find(found), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(dir / "bad" / "runs")) << reuse;
  }
}

// A model edited in place (one byte of its geometry) is another run: the
// resolved scenario pins its content (targets[i].model_digest), so resuming
// the sweep into its folder is refused as another sweep, and --reuse copies
// none of the old model's runs (until 2026-12-07 a run's key named a model
// by its path alone, and both kept the old model's runs as this one's).
// --move-aside renames the folder of the other sweep and copies what is
// still this sweep's: the runs of the model not edited.
TEST(SweepCli, AModelEditedInPlaceMakesAnotherSweepWhoseRunsAreComputedAgain) {
  const fs::path dir = FreshDir("sweep-model-edited");
  const fs::path model = dir / "tank.glb";
  fs::copy_file(kSource / "assets" / "vehicles" / "tank.glb", model);
  std::ofstream(dir / "sweep.yaml")
      << "base: " << testing::LibraryScenario("crossing-dominant")
      << "\nseeds: 2\ngrid:\n  frames: [30]\n"
      << "  targets.0.model: [\"" << model.string() << "\", assets/vehicles/car.glb]\n";
  const std::string sweep = (dir / "sweep.yaml").string();
  auto r = RunCommand(kHcpf + " sweep " + sweep + " --out " + (dir / "d1").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = RunCommand(kHcpf + " sweep " + sweep + " --out " + (dir / "d1").string() + " --move-aside");
  EXPECT_NE(r.output.find("4 runs, 4 reused, 0 computed"), std::string::npos) << r.output;
  EXPECT_EQ(r.output.find("moved to"), std::string::npos) << r.output;

  // One bit of a vertex coordinate in the binary chunk, the file still a
  // good .glb of the same size.
  std::string bytes = ReadFile(model);
  ASSERT_GT(bytes.size(), 4000u);
  bytes[bytes.size() - 3000] = static_cast<char>(bytes[bytes.size() - 3000] ^ 1);
  std::ofstream(model, std::ios::binary | std::ios::trunc) << bytes;
  r = RunCommand(kHcpf + " sweep " + sweep + " --out " + (dir / "d1").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("meta.sweep_hash: expected a store of this sweep"), std::string::npos)
      << r.output;
  r = RunCommand(kHcpf + " sweep " + sweep + " --out " + (dir / "d2").string() + " --reuse " +
                 (dir / "d1").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("4 runs, 2 reused (2 copied from --reuse), 2 computed"),
            std::string::npos)
      << r.output;
  const std::vector<std::string> fresh = StoreRows(dir / "d2" / "results.sqlite");

  // --move-aside: d1 renamed, the car's runs copied from it, the tank's
  // computed; the store is the one a fresh sweep writes.
  r = RunCommand(kHcpf + " sweep " + sweep + " --out " + (dir / "d1").string() + "/ --move-aside");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::vector<fs::path> aside;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().filename().string().rfind("d1.before-", 0) == 0) aside.push_back(e.path());
  }
  ASSERT_EQ(aside.size(), 1u) << r.output;
  EXPECT_NE(r.output.find("held the store of another sweep"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("moved to " + aside[0].string() + " (--move-aside)"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("4 runs, 2 reused (2 copied from --reuse), 2 computed"),
            std::string::npos)
      << r.output;
  EXPECT_EQ(StoreRows(dir / "d1" / "results.sqlite"), fresh);
  EXPECT_TRUE(fs::exists(aside[0] / "results.sqlite"));
  EXPECT_NE(r.output.find("(its runs keyed by another hcpf, or the sweep file, a scenario or a "
                          "model it names edited since; its hash "),
            std::string::npos)
      << r.output;
  // Another root seed is said as such.
  r = RunCommand(kHcpf + " sweep " + sweep + " --out " + (dir / "d1").string() +
                 " --seed 9 --move-aside");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(
      r.output.find("held the store of another sweep (root seed 1, this sweep's 9; its hash "),
      std::string::npos)
      << r.output;
}

// Chromium on PATH, or "".
std::string FindChromium() {
  for (const char* name : {"chromium", "chromium-browser"}) {
    if (RunCommand(std::string("command -v ") + name).exit_code == 0) return name;
  }
  return "";
}

TEST(ReportInChromium, EveryPlotRendersWithData) {
  const std::string chromium = FindChromium();
  if (chromium.empty())
    GTEST_SKIP() << "chromium is not installed (apt-get install -y chromium): report not rendered";
  const fs::path dir = FreshDir("sweep-report-chromium");
  const std::string sweep = WriteSweep(dir, 3, 150);  // the full crossing: the resamplers differ
  ASSERT_EQ(RunCommand(kHcpf + " sweep " + sweep + " --out " + (dir / "out").string() +
                       " --jobs 2 --video")
                .exit_code,
            0);
  auto report = RunCommand(kHcpf + " report " + (dir / "out").string());
  ASSERT_EQ(report.exit_code, 0) << report.output;
  const fs::path html = dir / "out" / "report.html";
  ASSERT_TRUE(fs::exists(html));
  EXPECT_NE(report.output.find(html.string()), std::string::npos)
      << report.output;  // prints the path

  // The screenshot is kept under the build folder as a CI artefact.
  const fs::path artefacts = fs::path(HCPF_BINARY_DIR) / "artifacts";
  fs::create_directories(artefacts);
  const fs::path png = artefacts / "report_screenshot.png";
  fs::remove(png);
  const fs::path profile = FreshDir("sweep-report-chromium-profile");
  auto shot =
      RunCommand("timeout 120 " + chromium +
                 " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run"
                 " --disable-background-networking --disable-component-update --disable-sync"
                 " --user-data-dir=" +
                 profile.string() + " --screenshot=" + png.string() +
                 " --window-size=1200,3000 file://" + fs::absolute(html).string());
  ASSERT_TRUE(fs::exists(png)) << shot.output;
  const cv::Mat image = cv::imread(png.string(), cv::IMREAD_COLOR);
  ASSERT_EQ(image.cols, 1200);
  // Tall enough for the findings (sentences and the table at a glance) and
  // the first three plots below them.
  ASSERT_EQ(image.rows, 3000);
  // Find each plot's frame: gnuplot draws the axes box in black, so the top
  // and bottom edges are rows with a long run of dark pixels (grid lines are
  // dotted grey, table borders light grey). Inside each frame the two series
  // lines (#1f77b4 blue, #d62728 red) must have been drawn: a legend sample
  // alone is ~150 such pixels, a line across a ~450 px wide plot ~900 or more.
  const auto dark = [](const cv::Vec3b& p) { return std::max({p[0], p[1], p[2]}) < 100; };
  const auto line_colour = [](const cv::Vec3b& p) {
    const auto d = [&](int b, int g, int r) {
      return std::abs(p[0] - b) + std::abs(p[1] - g) + std::abs(p[2] - r);
    };
    return d(180, 119, 31) < 60 || d(40, 39, 214) < 60;
  };
  std::vector<int> edges;  // first row of each cluster of long dark rows
  int last_edge_row = -10;
  for (int y = 0; y < image.rows; ++y) {
    int run = 0, longest = 0;
    for (int x = 0; x < image.cols; ++x) {
      run = dark(image.at<cv::Vec3b>(y, x)) ? run + 1 : 0;
      longest = std::max(longest, run);
    }
    if (longest < 300) continue;
    if (y - last_edge_row > 3) edges.push_back(y);
    last_edge_row = y;
  }
  // The first three frames are the metric plots; the paired-difference plots
  // (charged − systematic) follow the paired table, further down the page.
  ASSERT_GE(edges.size(), 6U) << "expected the top and bottom edges of 3 plot frames in " << png;
  for (size_t p = 0; p < 3; ++p) {
    const int top = edges[2 * p], bottom = edges[2 * p + 1];
    EXPECT_GT(bottom - top, 150) << "plot " << p;
    int coloured = 0;
    for (int y = top; y <= bottom; ++y) {
      for (int x = 0; x < image.cols; ++x) coloured += line_colour(image.at<cv::Vec3b>(y, x));
    }
    EXPECT_GT(coloured, 400) << "plot " << p << " (rows " << top << "-" << bottom
                             << ") has no data lines";
  }
  // --video: the first-seed run of each of the 8 cells has overlay.mp4, linked from the report.
  const std::string page = ReadFile(html);
  size_t links = 0;
  for (size_t at = page.find("/overlay.mp4\""); at != std::string::npos;
       at = page.find("/overlay.mp4\"", at + 1)) {
    ++links;
  }
  EXPECT_EQ(links, 8U);
  // The SVGs carry the data too (a renderer-independent check).
  const std::string text = ReadFile(html);
  size_t svgs = 0;
  for (size_t at = text.find("<svg"); at != std::string::npos; at = text.find("<svg", at + 1))
    ++svgs;
  EXPECT_EQ(svgs, 7U);  // 3 metrics, their paired differences, the scene from above
}

// The run report's script, run by Chromium: opened at "#frame=K", it moves
// the videos to frame K and draws the timeline's cursor there, at the x the
// plot's box gives (left + (K - 0.5) / frames * (right - left), in the SVG's
// own units); a frame past the last is the last. Chromium's headless mode
// does not finish a video seek, so the cursor, which the script draws at
// once, is what is read back from the page (--dump-dom).
TEST(ReportInChromium, TheRunReportsScriptDrawsTheCursorAtTheFrameInTheAddress) {
  const std::string chromium = FindChromium();
  if (chromium.empty())
    GTEST_SKIP() << "chromium is not installed (apt-get install -y chromium): script not run";
  const fs::path dir = FreshDir("run-report-chromium");
  const fs::path run = dir / "run";
  auto r = RunCommand(kHcpf + " run " + (kSource / "scenarios/library/crossing.yaml").string() +
                      " --set frames=40 --out " + run.string() + " --video");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = RunCommand(kHcpf + " report " + run.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string html = ReadFile(run / "report.html");
  const std::regex box(
      "id=\"plot-timeline\" data-frames=\"40\" data-left=\"([0-9.]+)\" data-right=\"([0-9.]+)\"");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(html, m, box)) << "the timeline has no plot box";
  const double left = std::stod(m[1]), right = std::stod(m[2]);
  const fs::path profile = FreshDir("run-report-chromium-profile");
  const auto cursor_at = [&](const std::string& hash) {
    const auto dom = RunCommand(
        "timeout 120 " + chromium +
        " --headless --no-sandbox --disable-gpu --disable-quic --no-first-run"
        " --disable-background-networking --disable-component-update --disable-sync"
        " --autoplay-policy=no-user-gesture-required --virtual-time-budget=5000 --user-data-dir=" +
        profile.string() + " --dump-dom 'file://" + fs::absolute(run / "report.html").string() +
        hash + "' 2>/dev/null");
    std::smatch x;
    const std::regex line("<line id=\"hcpf-cursor\"[^>]* x1=\"([-0-9.e]+)\"");
    return std::regex_search(dom.output, x, line) ? std::stod(x[1]) : -1.0;
  };
  EXPECT_NEAR(cursor_at("#frame=12"), left + (12 - 0.5) / 40 * (right - left), 1e-6);
  EXPECT_NEAR(cursor_at("#frame=999"), left + (40 - 0.5) / 40 * (right - left), 1e-6);
  EXPECT_NEAR(cursor_at(""), left + (1 - 0.5) / 40 * (right - left), 1e-6) << "frame 1 at first";
}

// hcpf regress --jobs 2 runs each rendered scene as `hcpf run` in a child
// process (a process's GL contexts render in turn, docs/sweeps.md): the log
// says so, the baseline is that of --jobs 1, where every scene runs in this
// process, the children's input and log files are gone, and a crashed child
// fails its scene with the signal.
TEST(RegressCli, RenderedScenesSideBySideEachInAProcessOfItsOwn) {
  const fs::path dir = FreshDir("regress-render-children");
  const std::string small = "frames: 30, camera.resolution: [160, 120]";
  std::ofstream(dir / "suite.yaml")
      << "scenes:\n"
      << "  - {name: a, scenario: " << testing::LibraryScenario("crossing-dominant") << ", set: {"
      << small << ", observation.source: rendered}}\n"
      << "  - {name: b, scenario: " << testing::LibraryScenario("crossing") << ", seeds: 2, set: {"
      << small << ", observation.source: rendered}}\n"
      << "  - {name: c, scenario: " << testing::LibraryScenario("crossing-dominant")
      << ", set: {frames: 30}}\n"
      << "metrics:\n  idf1: {tolerance: 0.01}\n  da_accuracy: {tolerance: 0.01}\n";
  const std::string suite = (dir / "suite.yaml").string();
  const auto one = RunCommand(kHcpf + " regress " + suite + " --update-baseline --baseline " +
                              (dir / "one.json").string() + " --jobs 1");
  ASSERT_EQ(one.exit_code, 0) << one.output;
  EXPECT_EQ(one.output.find("process of its own"), std::string::npos) << one.output;
  const auto two =
      RunCommand(kHcpf + " regress " + suite + " --update-baseline --baseline " +
                 (dir / "two.json").string() + " --jobs 2 --work " + (dir / "work").string());
  ASSERT_EQ(two.exit_code, 0) << two.output;
  EXPECT_NE(two.output.find("regress: each rendered run in a process of its own (--jobs 2)"),
            std::string::npos)
      << two.output;
  EXPECT_EQ(ReadFile(dir / "two.json"), ReadFile(dir / "one.json"));
  std::vector<std::string> entries;
  for (const auto& e : fs::directory_iterator(dir / "work"))
    entries.push_back(e.path().filename().string());
  std::sort(entries.begin(), entries.end());
  EXPECT_EQ(entries, (std::vector<std::string>{"a", "b", "c"}));
  entries.clear();
  for (const auto& e : fs::directory_iterator(dir / "work" / "b"))
    entries.push_back(e.path().filename().string());
  std::sort(entries.begin(), entries.end());
  EXPECT_EQ(entries, (std::vector<std::string>{"seed-0", "seed-1"}));
  EXPECT_TRUE(fs::exists(dir / "work" / "b" / "seed-1" / "metrics.json"));

  const auto [crashed, status, log] = RunAndCrashOneChild(
      {"regress", suite, "--baseline", (dir / "one.json").string(), "--jobs", "2"},
      dir / "crash.log");
  ASSERT_TRUE(crashed) << "no child run was seen: " << log;
  ASSERT_TRUE(WIFEXITED(status)) << log;
  EXPECT_EQ(WEXITSTATUS(status), 1) << log;
  EXPECT_NE(log.find("failed: crashed: killed by signal 11"), std::string::npos) << log;
  EXPECT_NE(log.find("(its log went with the temporary run folder; --work DIR keeps it)"),
            std::string::npos)
      << log;
}

TEST(RegressCli, ExitCodesOnTrueAndPlantedBaselines) {
  const fs::path dir = FreshDir("regress-cli");
  const fs::path suite = kSource / "scenarios" / "regress" / "suite.yaml";
  const fs::path baseline = kSource / "scenarios" / "regress" / "baseline.json";
  auto r = RunCommand(kHcpf + " regress " + suite.string() + " --baseline " + baseline.string() +
                      " --jobs 2 --junit " + (dir / "ok.xml").string() + " --markdown " +
                      (dir / "ok.md").string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(ReadFile(dir / "ok.xml").find("failures=\"0\""), std::string::npos);
  // --junit naming standard output: it carries the XML alone, the table goes
  // to stderr (a review: `--junit /dev/stdout > out.xml` held both).
  r = RunCommand("(" + kHcpf + " regress " + suite.string() + " --baseline " + baseline.string() +
                 " --jobs 2 --junit /dev/stdout > " + (dir / "out.xml").string() + " 2> " +
                 (dir / "err.txt").string() + ")");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  const std::string xml = ReadFile(dir / "out.xml");
  EXPECT_EQ(xml.rfind("<?xml", 0), 0u) << xml.substr(0, 200);
  EXPECT_TRUE(xml.ends_with("</testsuites>\n"))
      << xml.substr(xml.size() > 200 ? xml.size() - 200 : 0);
  EXPECT_NE(ReadFile(dir / "err.txt").find("idf1"), std::string::npos);

  // Planted regression: the baseline claims a better IDF1 than reality (on
  // a scene whose IDF1, 0.86, leaves room below 1: a value out of the
  // metric's range is refused).
  nlohmann::json b = nlohmann::json::parse(ReadFile(baseline));
  b["scenes"]["crossing-dominant-systematic"]["metrics"]["idf1"] =
      b["scenes"]["crossing-dominant-systematic"]["metrics"]["idf1"].get<double>() + 0.1;
  std::ofstream(dir / "planted.json") << b.dump(2);
  r = RunCommand(kHcpf + " regress " + suite.string() + " --baseline " +
                 (dir / "planted.json").string() + " --jobs 2 --junit " +
                 (dir / "bad.xml").string() + " --markdown " + (dir / "bad.md").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("WORSE"), std::string::npos) << r.output;
  EXPECT_NE(ReadFile(dir / "bad.xml").find("failures=\"1\""), std::string::npos);
  EXPECT_NE(ReadFile(dir / "bad.md").find("**WORSE**"), std::string::npos);

  // A baseline worse than reality: exit 0 with the refresh hint.
  b["scenes"]["crossing-dominant-systematic"]["metrics"]["idf1"] =
      b["scenes"]["crossing-dominant-systematic"]["metrics"]["idf1"].get<double>() - 0.2;
  std::ofstream(dir / "better.json") << b.dump(2);
  r = RunCommand(kHcpf + " regress " + suite.string() + " --baseline " +
                 (dir / "better.json").string() + " --jobs 2");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("--update-baseline"), std::string::npos) << r.output;

  // Missing baseline, or one lacking a scene: bad input.
  EXPECT_EQ(RunCommand(kHcpf + " regress " + suite.string() + " --baseline " +
                       (dir / "none.json").string())
                .exit_code,
            2);
  b["scenes"].erase("climb");
  std::ofstream(dir / "partial.json") << b.dump(2);
  EXPECT_EQ(RunCommand(kHcpf + " regress " + suite.string() + " --baseline " +
                       (dir / "partial.json").string())
                .exit_code,
            2);
}

}  // namespace
}  // namespace hcpf
