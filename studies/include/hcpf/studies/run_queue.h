#pragma once
// How a study hands out its runs: in which order (RunWaves) and by what
// (RunExecutor: in this process's threads, or each in a child process).

#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hcpf/scenarios/run.h"
#include "hcpf/studies/sweep.h"

namespace hcpf::studies {

// The runs of one sweep shard split into waves that run one after the other:
// with a frame cache, the first run of each rendered scene (runs with the same
// pixel hash share every frame) goes in the first wave and the runs that reuse
// its frames in the second, so two workers never render the same frames.
// Without a cache, or at detection level, every run is in the first wave.
// Each wave keeps the order of `runs`. Always two waves (either may be empty).
std::vector<std::vector<const SweepRun*>> RunWaves(std::span<const SweepRun* const> runs,
                                                   const std::string& frame_cache_dir);

// Executes one run into options.out_dir (a folder RunScenario's rules
// apply to). Throws when the run fails (the message says why). Const and
// called concurrently from several worker threads.
class RunExecutor {
 public:
  virtual ~RunExecutor() = default;
  virtual void Execute(const SweepRun& run, const scenarios::RunOptions& options) const = 0;
  virtual std::string_view name() const = 0;
};

// RunScenario in the calling thread.
class InProcessExecutor final : public RunExecutor {
 public:
  void Execute(const SweepRun& run, const scenarios::RunOptions& options) const override;
  std::string_view name() const override { return "threads"; }
};

// `hcpf run <the run's resolved scenario> --out ...` in a child process, so a
// run that crashes (a signal, an abort) fails that run only. The resolved
// scenario reproduces the run exactly. The child's output goes to
// `<runs_dir>/<key>.log`, kept when the run fails and quoted in the error.
class ChildProcessExecutor final : public RunExecutor {
 public:
  ChildProcessExecutor(std::string hcpf_exe, std::string runs_dir);
  void Execute(const SweepRun& run, const scenarios::RunOptions& options) const override;
  // The same for any scenario (hcpf regress's scenes), its input and log
  // files named `files` + ".input.yaml" and ".log" (a path no other
  // concurrent run uses, its folder made when missing; runs_dir is not used).
  void ExecuteScenario(const scenarios::Scenario& scenario, const std::string& files,
                       const scenarios::RunOptions& options) const;
  std::string_view name() const override { return "child processes"; }

 private:
  std::string exe_;
  std::string runs_dir_;
};

}  // namespace hcpf::studies
