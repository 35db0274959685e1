#pragma once
// The parts of running a sweep that the thread pool (RunSweep, sweep_run.cc)
// and the MPI executor (RunSweepMpi, mpi_sweep.cc) share: everything before
// the first run (PrepareSweep), one run turned into its store record
// (ExecuteRun) and the contact sheet at the end. Private to studies/.

#include <atomic>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "hcpf/studies/results_store.h"
#include "hcpf/studies/run_queue.h"
#include "hcpf/studies/sweep.h"

namespace hcpf::studies::internal {

// The line that heads each base scenario's resolved YAML in a grid.base
// sweep's meta.base_resolved ("# base: VALUE\n", VALUE as the grid writes
// it): written by the sweep, read back for each base's seed by the store.
inline std::string BaseResolvedHead(const std::string& value) { return "# base: " + value + "\n"; }

// The advisory lock on DIR/sweep.lock (one sweep process per folder),
// released when this object is destroyed or the process ends however it ends.
class FolderLock {
 public:
  // Throws InputError naming `option` (--out, or merge's OUT) when another
  // process holds the lock, RunError when the lock file cannot be opened.
  explicit FolderLock(const std::filesystem::path& out, const std::string& out_argument,
                      const std::string& option = "--out");
  ~FolderLock();
  FolderLock(FolderLock&& other) noexcept;
  FolderLock& operator=(FolderLock&&) = delete;
  FolderLock(const FolderLock&) = delete;
  FolderLock& operator=(const FolderLock&) = delete;

 private:
  int fd_ = -1;
};

// Whether a process holds DIR/sweep.lock now (a sweep writing to DIR); false
// when there is no lock file.
bool FolderLockHeld(const std::filesystem::path& dir);

// A sweep ready to compute: DIR locked by this process, its store open, the
// runs of this shard that are not finished split into waves (RunWaves).
struct SweepPlan {
  std::filesystem::path out;
  std::unique_ptr<FolderLock> lock;
  std::unique_ptr<ResultsStore> store;
  SweepResult result;  // total and reused filled in
  std::vector<std::vector<const SweepRun*>> waves;
  int64_t todo = 0;  // runs in all waves
};

// Everything RunSweep does before its first run: validates the options,
// creates DIR/runs, takes the folder lock, removes staging folders of dead
// processes, opens or creates the store (InputError when it holds another
// sweep), reuses the finished runs whose folders are intact (checked with
// options.jobs threads), copies those it lacks from the stores of
// options.reuse_dirs, and logs what is left, computed by `workers` (e.g.
// "2 worker(s)").
SweepPlan PrepareSweep(const SweepSpec& spec, const std::vector<SweepRun>& runs,
                       const SweepOptions& options, const std::string& workers);

// Copies `from` (a file, or a folder with what it holds; of a folder only
// `files`, paths relative to it, when that is not empty) to
// "<to>.partial-<pid>" and renames that over `to`, so `to` is whole or as it
// was. RunError naming both when it cannot.
void CopyWhole(const std::filesystem::path& from, const std::filesystem::path& to,
               const std::vector<std::string>& files = {});

// A sweep's executors: worker threads, and child processes for the runs
// SweepOptions::InChildProcess names (options.ChildExe()).
class RunExecutors {
 public:
  explicit RunExecutors(const SweepOptions& options);
  // Called once per run, when it starts; counts the rendered runs it sends.
  const RunExecutor& For(const SweepRun& run) const;
  // Rendered runs sent to child processes, and those kept in worker threads
  // because their frames were all cached (SweepOptions::FramesAllCached),
  // under render_exe.
  int64_t rendered_in_children() const { return rendered_in_children_; }
  int64_t cached_in_threads() const { return cached_in_threads_; }

 private:
  const SweepOptions& options_;
  InProcessExecutor in_process_;
  std::unique_ptr<ChildProcessExecutor> child_;
  mutable std::atomic<int64_t> rendered_in_children_{0};
  mutable std::atomic<int64_t> cached_in_threads_{0};
};

// The store record of `run` before it is computed: key, index, seed, values,
// run_dir; ok = false.
RunRecord NewRecord(const SweepRun& run);

// Computes `run` into DIR/runs/<key> with the options every sweep run gets
// (options.run_threads threads, no progress, the frame cache, video on seed
// index 0) and returns its record. A run that fails is returned with ok = false and the
// message (never thrown).
RunRecord ExecuteRun(const SweepRun& run, const SweepOptions& options, const RunExecutor& executor);

// DIR/contact_sheet.png from the first rendered run's cached frames (see
// sweep_run.cc); nothing when there is none.
void WriteContactSheet(const std::filesystem::path& out, const std::vector<SweepRun>& runs,
                       const std::string& cache_dir);

}  // namespace hcpf::studies::internal
