#include "hcpf/scenarios/render_folder.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <nlohmann/json.hpp>

#include "hcpf/core/error.h"
#include "hcpf/metrics/mot_io.h"
#include "hcpf/renderer/image_io.h"
#include "hcpf/scenarios/frames.h"
#include "hcpf/scenarios/output_folder.h"
#include "hcpf/scenarios/version.h"
#include "writers.h"

namespace hcpf::scenarios {

namespace fs = std::filesystem;

RenderFolderSummary RenderToFolder(const Scenario& scenario, const RenderFolderOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  if (!options.cache_dir.empty()) CheckFolderArgument(options.cache_dir, "--cache");
  StagedFolder staged(options.out_dir);
  const fs::path& dir = staged.partial();
  std::error_code ec;
  fs::create_directories(dir / "frames", ec);
  fs::create_directories(dir / "gt", ec);
  if (ec) throw RunError(fmt::format("cannot create {}: {}", dir.string(), ec.message()));

  const int frames = scenario.world.frames;
  const int sheet_n = std::clamp(options.sheet_frames, 1, frames);
  std::vector<int> sheet_frames;
  for (int i = 0; i < sheet_n; ++i) {
    sheet_frames.push_back(sheet_n == 1 ? 0 : i * (frames - 1) / (sheet_n - 1));
  }
  std::vector<renderer::RenderedFrame> sheet;
  FrameSourceOptions frame_options;
  frame_options.render = true;
  frame_options.cache_dir = options.cache_dir;
  frame_options.workers = options.threads;
  // PNG encoding (zlib) costs more than a GPU's frame: each frame's files are
  // written on the frame's worker thread, several frames at once.
  std::atomic<int64_t> saturated{0};  // depth pixels past the PNG's range
  frame_options.on_frame_work = [frames_dir = (dir / "frames").string(),
                                 unit = scenario.renderer.depth_unit_mm,
                                 &saturated](const renderer::RenderedFrame& frame) {
    WriteFrameImages(frame, frames_dir, true, unit, &saturated);
  };
  frame_options.on_frame = [&](const renderer::RenderedFrame& frame) {
    if (std::find(sheet_frames.begin(), sheet_frames.end(), frame.frame) != sheet_frames.end()) {
      renderer::RenderedFrame thumb;
      thumb.frame = frame.frame;
      thumb.rgb = frame.rgb;
      thumb.ground_truth = frame.ground_truth;
      sheet.push_back(std::move(thumb));
    }
  };
  const SceneFrames scene = ProduceFrames(scenario, frame_options);
  if (const std::string note = DepthSaturationNote(saturated, scenario.renderer.depth_unit_mm);
      !note.empty()) {
    spdlog::warn("render \"{}\": {}", scenario.name, note);
  }

  WriteTextFile((dir / "scenario.resolved.yaml").string(), ToResolvedYaml(scenario));
  WriteTextFile((dir / "gt" / "gt.txt").string(),
                metrics::FormatMotGroundTruth(GroundTruthRows(scene.truth)));
  metrics::WriteSeqInfo((dir / "seqinfo.ini").string(), SeqInfoOf(scenario));
  WriteTextFile((dir / "gt.json").string(), FormatGroundTruthJson(scenario, scene.truth, true));
  renderer::WritePng(renderer::MakeContactSheet(sheet), (dir / "contact_sheet.png").string());

  RenderFolderSummary summary;
  summary.out_dir = staged.out().string();
  summary.frames = frames;
  summary.frames_rendered = scene.frames_rendered;
  summary.frames_from_cache = scene.frames_from_cache;
  summary.wall_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  nlohmann::json manifest = ManifestProvenance("hcpf-render/1", scenario, scene);
  manifest["frames"] = frames;
  manifest["timings"] = {{"total_s", summary.wall_time_s}};
  manifest["nondeterministic_fields"] = {"timings", "frames_rendered", "frames_from_cache",
                                         "gl_renderer", "frame_cache_renderers"};
  WriteTextFile((dir / "manifest.json").string(), manifest.dump(2) + "\n");
  staged.Publish();
  return summary;
}

}  // namespace hcpf::scenarios
