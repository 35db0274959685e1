// End-to-end test of the MPI executor: `mpirun --oversubscribe -n 3 hcpf
// sweep` against the thread pool's `hcpf sweep --jobs 2` on the same sweep,
// resuming, a rank that dies, and a refused folder. Registered only when CMake
// found MPI and mpirun (tests/e2e/sweep.cmake).

#include <gtest/gtest.h>
#include <signal.h>
#include <sqlite3.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "support/process.h"

namespace hcpf {
namespace {

namespace fs = std::filesystem;
using testing::FreshDir;
using testing::ReadFile;
using testing::RunCommand;

using testing::kHcpf;

// mpirun as root (CI runs as root; Open MPI refuses without both variables),
// more ranks than the 2 cores of CI (--oversubscribe) and no core binding
// (bound ranks would be pinned to cores the other test processes use too).
const std::string kMpirun = "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 " +
                            std::string(HCPF_MPIEXEC) + " --oversubscribe --bind-to none";
std::string Mpirun(int ranks, const std::string& args) {
  return kMpirun + " -n " + std::to_string(ranks) + " " + kHcpf + " " + args;
}

// Every row of a results store: key -> column -> value, REAL values written
// exactly (hex float) so that equal text means the same double. The timing
// columns are left out: they are the only values that differ between runs.
using StoreRows = std::map<std::string, std::map<std::string, std::string>>;
StoreRows ReadStore(const fs::path& store) {
  StoreRows rows;
  sqlite3* db = nullptr;
  if (sqlite3_open_v2(store.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
    sqlite3_close(db);
    return rows;
  }
  sqlite3_busy_timeout(db, 5000);
  sqlite3_stmt* s = nullptr;
  if (sqlite3_prepare_v2(db, "SELECT * FROM runs", -1, &s, nullptr) == SQLITE_OK) {
    while (sqlite3_step(s) == SQLITE_ROW) {
      std::map<std::string, std::string> row;
      for (int c = 0; c < sqlite3_column_count(s); ++c) {
        const std::string name = sqlite3_column_name(s, c);
        if (name == "ms_per_frame" || name == "wall_time_s") continue;
        switch (sqlite3_column_type(s, c)) {
          case SQLITE_NULL:
            row[name] = "NULL";
            break;
          case SQLITE_FLOAT: {
            char text[64];
            std::snprintf(text, sizeof text, "%a", sqlite3_column_double(s, c));
            row[name] = text;
            break;
          }
          default:
            row[name] = reinterpret_cast<const char*>(sqlite3_column_text(s, c));
        }
      }
      rows[row["key"]] = row;
    }
  }
  sqlite3_finalize(s);
  sqlite3_close(db);
  return rows;
}

// Deletes the row of `key` from a results store.
bool DeleteRow(const fs::path& store, const std::string& key) {
  sqlite3* db = nullptr;
  bool ok = sqlite3_open(store.c_str(), &db) == SQLITE_OK;
  sqlite3_stmt* s = nullptr;
  ok = ok && sqlite3_prepare_v2(db, "DELETE FROM runs WHERE key = ?", -1, &s, nullptr) == SQLITE_OK;
  ok = ok && sqlite3_bind_text(s, 1, key.c_str(), -1, SQLITE_TRANSIENT) == SQLITE_OK;
  ok = ok && sqlite3_step(s) == SQLITE_DONE && sqlite3_changes(db) == 1;
  sqlite3_finalize(s);
  sqlite3_close(db);
  return ok;
}

// crossing-dominant shortened to 40 frames: 2 particle counts x 2 resamplers
// x `seeds` seeds.
std::string WriteSweep(const fs::path& dir, int seeds,
                       const std::string& particles = "[100, 1000]") {
  const std::string base = testing::LibraryScenario("crossing-dominant");
  std::ofstream(dir / "sweep.yaml") << "base: " << base << "\n"
                                    << "seeds: " << seeds << "\n"
                                    << "grid:\n"
                                    << "  frames: [40]\n"
                                    << "  tracker.particles: " << particles << "\n"
                                    << "  tracker.resampling.method: [systematic, charged]\n";
  return (dir / "sweep.yaml").string();
}

// How often `needle` occurs in `text`.
int Count(const std::string& text, const std::string& needle) {
  int n = 0;
  for (size_t at = text.find(needle); at != std::string::npos; at = text.find(needle, at + 1)) ++n;
  return n;
}

// Run folders of a sweep folder; fails the test on a staging folder.
int FinishedRunFolders(const fs::path& out) {
  int folders = 0;
  for (const auto& e : fs::directory_iterator(out / "runs")) {
    EXPECT_EQ(e.path().filename().string().find(".partial-"), std::string::npos) << e.path();
    EXPECT_TRUE(fs::exists(e.path() / "manifest.json")) << e.path();
    ++folders;
  }
  return folders;
}

TEST(MpiSweep, StoreEqualsTheThreadPoolsAndRerunningResumes) {
  const fs::path dir = FreshDir("sweep-mpi");
  const std::string sweep = WriteSweep(dir, 2);  // 8 runs
  const auto pool = RunCommand(kHcpf + " sweep " + sweep + " --out " + (dir / "pool").string() +
                               " --jobs 2 --no-cache");
  ASSERT_EQ(pool.exit_code, 0) << pool.output;
  const StoreRows expected = ReadStore(dir / "pool" / "results.sqlite");
  ASSERT_EQ(expected.size(), 8U);

  const fs::path out = dir / "mpi";
  const auto mpi =
      RunCommand(Mpirun(3, "sweep " + sweep + " --out " + out.string() + " --no-cache"));
  ASSERT_EQ(mpi.exit_code, 0) << mpi.output;
  EXPECT_NE(mpi.output.find("8 to compute with 2 MPI worker rank(s)"), std::string::npos)
      << mpi.output;
  // Only rank 0 reports.
  EXPECT_EQ(Count(mpi.output, "sweep finished: 8 runs, 0 reused, 8 computed, 0 failed"), 1)
      << mpi.output;
  // Same config hashes, same metric values (bit for bit), nothing else.
  const StoreRows got = ReadStore(out / "results.sqlite");
  EXPECT_EQ(got, expected);
  EXPECT_EQ(FinishedRunFolders(out), 8);

  // Resume: a deleted run folder and a deleted row are computed again, the
  // other six reused; the store ends equal again.
  const std::string folder_key = expected.begin()->first;
  const std::string row_key = std::next(expected.begin(), 5)->first;
  fs::remove_all(out / "runs" / folder_key);
  ASSERT_TRUE(DeleteRow(out / "results.sqlite", row_key));
  const auto resumed =
      RunCommand(Mpirun(3, "sweep " + sweep + " --out " + out.string() + " --no-cache"));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  EXPECT_NE(resumed.output.find("sweep finished: 8 runs, 6 reused, 2 computed, 0 failed"),
            std::string::npos)
      << resumed.output;
  EXPECT_EQ(ReadStore(out / "results.sqlite"), expected);
  EXPECT_EQ(FinishedRunFolders(out), 8);

  // Rank 0 refuses a folder holding another sweep: exit 2 with its message,
  // the worker ranks stop without a word.
  fs::create_directories(dir / "other");
  const std::string other = WriteSweep(dir / "other", 3);
  const auto refused =
      RunCommand(Mpirun(3, "sweep " + other + " --out " + out.string() + " --no-cache"));
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_EQ(Count(refused.output, "a store of another sweep"), 1) << refused.output;
  EXPECT_EQ(ReadStore(out / "results.sqlite"), expected);
}

// hcpf sweep --seed under mpirun: every rank seeds the runs from the same
// root seed, so the store equals the thread pool's with --seed, the store
// records the root seed, and the log says it once (rank 0).
TEST(MpiSweep, ARootSeedFromTheCommandLineReachesEveryRank) {
  const fs::path dir = FreshDir("sweep-mpi-seed");
  const std::string sweep = WriteSweep(dir, 2);  // 8 runs
  const auto pool = RunCommand(kHcpf + " sweep " + sweep + " --seed 5 --out " +
                               (dir / "pool").string() + " --jobs 2 --no-cache");
  ASSERT_EQ(pool.exit_code, 0) << pool.output;
  const StoreRows expected = ReadStore(dir / "pool" / "results.sqlite");
  ASSERT_EQ(expected.size(), 8U);
  const auto mpi = RunCommand(
      Mpirun(3, "sweep " + sweep + " --seed 5 --out " + (dir / "mpi").string() + " --no-cache"));
  ASSERT_EQ(mpi.exit_code, 0) << mpi.output;
  EXPECT_EQ(ReadStore(dir / "mpi" / "results.sqlite"), expected);
  EXPECT_EQ(Count(mpi.output, "runs seeded from root seed 5 (--seed; the sweep file's seed: 1)"), 1)
      << mpi.output;
  std::string root_seed;
  sqlite3* db = nullptr;
  if (sqlite3_open_v2((dir / "mpi" / "results.sqlite").c_str(), &db, SQLITE_OPEN_READONLY,
                      nullptr) == SQLITE_OK) {
    sqlite3_stmt* s = nullptr;
    if (sqlite3_prepare_v2(db, "SELECT value FROM meta WHERE name = 'root_seed'", -1, &s,
                           nullptr) == SQLITE_OK &&
        sqlite3_step(s) == SQLITE_ROW) {
      root_seed = reinterpret_cast<const char*>(sqlite3_column_text(s, 0));
    }
    sqlite3_finalize(s);
  }
  sqlite3_close(db);
  EXPECT_EQ(root_seed, "5");
  // Without --seed the runs are others (root seed 1).
  const auto plain = RunCommand(kHcpf + " sweep " + sweep + " --out " + (dir / "plain").string() +
                                " --jobs 2 --no-cache");
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  const StoreRows other = ReadStore(dir / "plain" / "results.sqlite");
  ASSERT_EQ(other.size(), 8U);
  for (const auto& [key, row] : other) EXPECT_EQ(expected.count(key), 0U) << key;
}

TEST(MpiSweep, RanksThatExpandAnotherSweepStopTheJobBeforeAnyRun) {
  // Rank 0 starts in a/, ranks 1 and 2 in b/ (mpirun's MPMD form), each
  // reading its own sweep.yaml: 2 seeds there, 3 here.
  const fs::path dir = FreshDir("sweep-mpi-mismatch");
  fs::create_directories(dir / "a");
  fs::create_directories(dir / "b");
  WriteSweep(dir / "a", 2);
  WriteSweep(dir / "b", 3);
  const fs::path out = dir / "out";
  const std::string args = "sweep sweep.yaml --out " + out.string() + " --no-cache";
  const auto r =
      RunCommand(kMpirun + " -n 1 -wdir " + (dir / "a").string() + " " + kHcpf + " " + args +
                 " : -n 2 -wdir " + (dir / "b").string() + " " + kHcpf + " " + args);
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("2 of 3 MPI ranks expanded sweep.yaml to another run list than rank 0"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(out / "results.sqlite"));
}

TEST(MpiSweep, ProcessesAloneInTheirMpiWorldAreRefused) {
  // PMI_SIZE is what MPICH's launcher sets; an Open MPI process started with
  // it is a world of its own (a singleton), like each of R processes that
  // MPICH's mpiexec would start: running the sweep in each would race.
  const fs::path dir = FreshDir("sweep-mpi-singleton");
  const std::string sweep = WriteSweep(dir, 2);
  const auto r =
      RunCommand("OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 PMI_SIZE=3 " + kHcpf +
                 " sweep " + sweep + " --out " + (dir / "out").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("started as 3 processes by an MPI launcher, but each is alone in its "
                          "MPI world"),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(dir / "out"));
}

// The environment of process `pid`, NUL-separated entries.
std::string EnvironmentOf(pid_t pid) {
  return ReadFile(fs::path("/proc") / std::to_string(pid) / "environ");
}

// Processes whose environment holds `entry` and whose executable is hcpf.
std::vector<pid_t> ProcessesWith(const std::string& entry) {
  std::vector<pid_t> found;
  for (const auto& e : fs::directory_iterator("/proc")) {
    const std::string name = e.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    const pid_t pid = static_cast<pid_t>(std::stol(name));
    std::error_code ec;
    if (fs::read_symlink(e.path() / "exe", ec) != fs::canonical(kHcpf)) continue;
    const std::string env = EnvironmentOf(pid);
    if (env.find(std::string("\0", 1) + entry + std::string("\0", 1)) != std::string::npos ||
        env.starts_with(entry + std::string("\0", 1))) {
      found.push_back(pid);
    }
  }
  return found;
}

TEST(MpiSweep, ARankThatDiesEndsTheJobAndRerunningLosesAndRepeatsNothing) {
  const fs::path dir = FreshDir("sweep-mpi-kill");
  // 32 runs of 0.08 s and 0.5 s, killed after the first is stored: about
  // 4 s of runs are left at the kill on two worker ranks. (16 runs of at most
  // 0.25 s, killed after 3, once all finished first on a loaded machine.)
  const std::string sweep = WriteSweep(dir, 8, "[1000, 20000]");
  const auto pool = RunCommand(kHcpf + " sweep " + sweep + " --out " + (dir / "pool").string() +
                               " --jobs 2 --no-cache");
  ASSERT_EQ(pool.exit_code, 0) << pool.output;
  const StoreRows expected = ReadStore(dir / "pool" / "results.sqlite");
  ASSERT_EQ(expected.size(), 32U);

  // Start the MPI sweep in the background with a marker in its environment,
  // and SIGKILL worker rank 1 once a few runs are stored.
  const fs::path out = dir / "mpi";
  const std::string marker = "HCPF_TEST_SWEEP=" + std::to_string(::getpid());
  const pid_t shell = ::fork();
  if (shell == 0) {
    const std::string command =
        marker + " " + Mpirun(3, "sweep " + sweep + " --out " + out.string() + " --no-cache") +
        " > " + (dir / "first.log").string() + " 2>&1";
    ::execl("/bin/sh", "sh", "-c", command.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  ASSERT_GT(shell, 0);
  bool killed = false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!killed && std::chrono::steady_clock::now() < deadline) {
    if (fs::exists(out / "results.sqlite") && !ReadStore(out / "results.sqlite").empty()) {
      for (const pid_t pid : ProcessesWith("OMPI_COMM_WORLD_RANK=1")) {
        if (EnvironmentOf(pid).find(marker) != std::string::npos && ::kill(pid, SIGKILL) == 0)
          killed = true;
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  int status = 0;
  ::waitpid(shell, &status, 0);
  ASSERT_TRUE(killed) << ReadFile(dir / "first.log");
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) != 0) << ReadFile(dir / "first.log");
  const size_t after_kill = ReadStore(out / "results.sqlite").size();
  ASSERT_LT(after_kill, 32U) << "the kill came too late to test resuming";

  const auto resumed =
      RunCommand(Mpirun(3, "sweep " + sweep + " --out " + out.string() + " --no-cache"));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
  const std::regex finished(
      "sweep finished: 32 runs, ([0-9]+) reused, ([0-9]+) computed, 0 failed");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(resumed.output, m, finished)) << resumed.output;
  EXPECT_EQ(std::stoul(m[1]), after_kill);
  EXPECT_EQ(std::stoul(m[2]), 32U - after_kill);
  EXPECT_EQ(ReadStore(out / "results.sqlite"), expected);
  EXPECT_EQ(FinishedRunFolders(out), 32);
}

}  // namespace
}  // namespace hcpf
