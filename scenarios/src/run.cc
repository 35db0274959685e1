#include "hcpf/scenarios/run.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "hcpf/core/error.h"
#include "hcpf/core/ground_truth.h"
#include "hcpf/scenarios/observation_simulator.h"
#include "hcpf/scenarios/version.h"
#include "writers.h"

namespace hcpf::scenarios {

namespace fs = std::filesystem;

namespace {

using Clock = std::chrono::steady_clock;

double Seconds(Clock::time_point since) {
  return std::chrono::duration<double>(Clock::now() - since).count();
}

// The output folder must be new, empty, or an earlier run's (it has a
// manifest.json): never clobber a folder of the user's.
void CheckOutputFolder(const fs::path& out) {
  std::error_code ec;
  if (!fs::exists(out, ec)) return;
  if (!fs::is_directory(out, ec)) {
    throw InputError(SourceLocation{out.string(), 0, 0, "--out"}, "a folder for the run's outputs",
                     "an existing file");
  }
  if (fs::is_empty(out, ec) || fs::exists(out / "manifest.json", ec)) return;
  throw InputError(SourceLocation{out.string(), 0, 0, "--out"},
                   "a new or empty folder, or an earlier run's folder (with manifest.json)",
                   "a folder with other files in it");
}

// Moves the finished temporary folder into place, replacing an earlier run.
void Publish(const fs::path& partial, const fs::path& out) {
  std::error_code ec;
  if (fs::exists(out, ec)) fs::remove_all(out, ec);
  if (ec) throw RunError(fmt::format("cannot replace {}: {}", out.string(), ec.message()));
  fs::rename(partial, out, ec);
  if (ec) throw RunError(fmt::format("cannot move the run to {}: {}", out.string(), ec.message()));
}

}  // namespace

RunSummary RunScenario(const Scenario& scenario, const RunOptions& options) {
  const auto start = Clock::now();
  const fs::path out = fs::absolute(options.out_dir).lexically_normal();
  CheckOutputFolder(out);
  const fs::path partial = out.string() + fmt::format(".partial-{}", ::getpid());
  std::error_code ec;
  fs::remove_all(partial, ec);
  fs::create_directories(partial / "gt", ec);
  if (ec) throw RunError(fmt::format("cannot create {}: {}", partial.string(), ec.message()));

  RunSummary summary;
  summary.out_dir = out.string();
  summary.frames = scenario.world.frames;
  nlohmann::json timings;
  try {
    // 1. Ground truth, frame by frame.
    auto t0 = Clock::now();
    std::vector<FrameGroundTruth> truth;
    truth.reserve(scenario.world.frames);
    for (int f = 0; f < scenario.world.frames; ++f) {
      truth.push_back(ComputeGroundTruth(scenario.world, f));
    }
    timings["ground_truth_s"] = Seconds(t0);

    // 2. Observations (detection-level mode: the oracle detector).
    t0 = Clock::now();
    std::vector<Observation> observations;
    observations.reserve(truth.size());
    for (const FrameGroundTruth& gt : truth) {
      observations.push_back(
          SimulateObservation(gt, scenario.observation.simulated, scenario.seeds.observation));
      summary.detections += static_cast<int>(observations.back().detections.size());
    }
    timings["observations_s"] = Seconds(t0);

    // 3. Files.
    t0 = Clock::now();
    WriteTextFile((partial / "scenario.resolved.yaml").string(), ToResolvedYaml(scenario));
    const std::string gt_text = FormatGroundTruthMot(truth);
    summary.gt_boxes = static_cast<int>(std::count(gt_text.begin(), gt_text.end(), '\n'));
    WriteTextFile((partial / "gt" / "gt.txt").string(), gt_text);
    WriteTextFile((partial / "seqinfo.ini").string(), FormatSeqinfo(scenario));
    WriteTextFile((partial / "gt.json").string(), FormatGroundTruthJson(scenario, truth));
    WriteTextFile((partial / "detections.txt").string(), FormatDetectionsMot(observations));
    timings["write_s"] = Seconds(t0);
    spdlog::info("tracks.txt and metrics.json are not written: this build has no tracker yet");

    summary.wall_time_s = Seconds(start);
    timings["total_s"] = summary.wall_time_s;
    nlohmann::json manifest;
    manifest["format"] = "hcpf-run/1";
    manifest["hcpf_version"] = ProjectVersion();
    manifest["git_revision"] = GitRevision();
    manifest["scenario"] = scenario.name;
    manifest["config_hash"] = ConfigHash(scenario);
    manifest["seed"] = scenario.seed;
    manifest["seeds"] = {{"world", scenario.seeds.world},
                         {"observation", scenario.seeds.observation},
                         {"tracker", scenario.seeds.tracker},
                         {"renderer", scenario.seeds.renderer}};
    manifest["observation_source"] =
        scenario.observation.source == ObservationSource::kRendered ? "rendered" : "simulated";
    manifest["detector"] = scenario.observation.detector + " (noisy ground truth)";
    manifest["libraries"] = LibraryVersions();
    manifest["gl_renderer"] = nullptr;
    manifest["frames"] = scenario.world.frames;
    manifest["gt_boxes"] = summary.gt_boxes;
    manifest["detections"] = summary.detections;
    manifest["timings"] = timings;
    manifest["nondeterministic_fields"] = {"timings"};
    // Written last: a folder with a manifest is a finished run.
    WriteTextFile((partial / "manifest.json").string(), manifest.dump(2) + "\n");
    Publish(partial, out);
  } catch (...) {
    fs::remove_all(partial, ec);
    throw;
  }
  return summary;
}

}  // namespace hcpf::scenarios
