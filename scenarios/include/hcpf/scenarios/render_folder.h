#pragma once
// `hcpf render`: a scenario's frames with pixel-exact ground truth, written as
// a MOTChallenge-style sequence folder (layout in docs/renderer.md):
//   frames/000001.png ... (+ _depth.png / _ids.png when renderer.write_depth /
//   write_instance_ids), gt/gt.txt + seqinfo.ini, gt.json, contact_sheet.png
//   (sampled frames with ground-truth boxes), scenario.resolved.yaml, manifest.json.

#include <string>

#include "hcpf/scenarios/scenario.h"

namespace hcpf::scenarios {

struct RenderFolderOptions {
  std::string out_dir;
  std::string cache_dir;  // "" = no frame cache
  int sheet_frames = 16;  // frames sampled into the contact sheet, >= 1
  // Threads for the frames' sensor effects and cache writes
  // (FrameSourceOptions::workers) and for writing their PNG files, several
  // frames at once; the files are the same for any value. `hcpf render
  // --threads`.
  int threads = 1;
};

struct RenderFolderSummary {
  std::string out_dir;
  int frames = 0;
  int frames_rendered = 0;
  int frames_from_cache = 0;
  double wall_time_s = 0.0;
};

RenderFolderSummary RenderToFolder(const Scenario& scenario, const RenderFolderOptions& options);

}  // namespace hcpf::scenarios
