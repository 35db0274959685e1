#include "hcpf/studies/run_queue.h"

#include <fmt/format.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

#include "hcpf/core/error.h"
#include "hcpf/core/subprocess.h"
#include "hcpf/core/text_file.h"
#include "hcpf/scenarios/frames.h"

namespace hcpf::studies {

using scenarios::RunOptions;
using scenarios::ToResolvedYaml;

namespace fs = std::filesystem;

std::vector<std::vector<const SweepRun*>> RunWaves(std::span<const SweepRun* const> runs,
                                                   const std::string& frame_cache_dir) {
  std::vector<std::vector<const SweepRun*>> waves(2);
  std::set<std::string> scenes;
  for (const SweepRun* run : runs) {
    const bool rendered = run->rendered() && !frame_cache_dir.empty();
    bool reuses_frames = false;
    if (rendered) {
      const scenarios::Scenario scenario = run->scenario();
      reuses_frames = !scenes.insert(scenarios::PixelHashOf(scenario)).second;
    }
    waves[reuses_frames ? 1 : 0].push_back(run);
  }
  return waves;
}

void InProcessExecutor::Execute(const SweepRun& run, const RunOptions& options) const {
  scenarios::RunScenario(run.scenario(), options);
}

namespace {

std::string Tail(const fs::path& log, size_t max_chars) {
  std::ifstream in(log);
  std::stringstream text;
  text << in.rdbuf();
  std::string t = text.str();
  while (!t.empty() && (t.back() == '\n' || t.back() == ' ')) t.pop_back();
  return t.size() > max_chars ? "..." + t.substr(t.size() - max_chars) : t;
}

}  // namespace

ChildProcessExecutor::ChildProcessExecutor(std::string hcpf_exe, std::string runs_dir)
    : exe_(std::move(hcpf_exe)), runs_dir_(std::move(runs_dir)) {}

// Throws RunError naming the exit status or signal with the end of the
// child's log.
void ChildProcessExecutor::Execute(const SweepRun& run, const RunOptions& run_options) const {
  ExecuteScenario(run.scenario(), (fs::path(runs_dir_) / run.key).string(), run_options);
}

void ChildProcessExecutor::ExecuteScenario(const scenarios::Scenario& scenario,
                                           const std::string& files,
                                           const RunOptions& run_options) const {
  const std::string& exe = exe_;
  const fs::path input = files + ".input.yaml";
  const fs::path log = files + ".log";
  fs::create_directories(input.parent_path());  // DIR/b of DIR/b/seed-1.input.yaml
  WriteTextFile(input.string(), ToResolvedYaml(scenario));
  std::vector<std::string> args = {exe,
                                   "--log-level",
                                   "warn",
                                   "run",
                                   input.string(),
                                   "--out",
                                   run_options.out_dir,
                                   "--threads",
                                   std::to_string(run_options.threads)};
  if (run_options.video) args.push_back("--video");
  if (run_options.frame_cache_dir.empty()) {
    args.push_back("--no-cache");
  } else {
    args.push_back("--cache");
    args.push_back(run_options.frame_cache_dir);
  }
  const ProcessStatus status = RunProcess(args, log.string());
  if (!status.started) throw RunError(fmt::format("cannot start {}: {}", exe, status.error));
  std::error_code ec;
  fs::remove(input, ec);
  if (status.ok()) {
    fs::remove(log, ec);
    return;
  }
  const std::string tail = Tail(log, 600);
  if (status.signal != 0) {
    throw RunError(fmt::format("crashed: killed by signal {} ({}); log {}: {}", status.signal,
                               ::strsignal(status.signal), log.string(), tail));
  }
  throw RunError(fmt::format("hcpf run exited with status {}: {}", status.exit_code, tail));
}

}  // namespace hcpf::studies
