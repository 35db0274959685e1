#pragma once
// One run of a scenario: world -> ground truth -> observations -> tracker ->
// metrics, written to an output folder (layout in docs/outputs.md).
//
// The folder appears complete or not at all: everything is written to a
// sibling "<out>.partial-<pid>" folder that is renamed into place at the end,
// so a failed or killed run never leaves a folder that looks finished.

#include <span>
#include <string>

#include "hcpf/scenarios/scenario.h"
#include "hcpf/tracker/tracker.h"

namespace hcpf::scenarios {

struct RunOptions {
  std::string out_dir;
  // Worker threads of the tracker's per-filter stages and, for rendered
  // frames, of their sensor effects, cache writes and image files
  // (write_frames and the like); outputs are identical for every value.
  int threads = 1;
  // Also write overlay.mp4: frames (or a plain background at detection level),
  // ground-truth boxes, estimates, particles (tracker.keep_particles > 0) and
  // each filter's state.
  bool video = false;
  // Progress lines for long runs (off inside sweeps, which report their own).
  bool show_progress = true;
  // Rendered scenarios: the frame cache folder ("" = render every time).
  std::string frame_cache_dir;
  // Whether to remove the staging folders of dead processes beside out_dir
  // (StagedFolder). A sweep does that once for its runs/ and sets this false.
  bool remove_stale_siblings = true;
};

struct RunSummary {
  std::string out_dir;
  int frames = 0;
  int gt_boxes = 0;
  int detections = 0;
  double mota = 0.0;
  double idf1 = 0.0;
  double hota = 0.0;
  // Filter-level metrics: NaN for an external tracker (no filters to score).
  double da_accuracy = 0.0;
  double hijack_rate = 0.0;
  double wall_time_s = 0.0;
};

// Runs `scenario` and writes its outputs. Throws InputError when `out_dir`
// exists and is neither empty nor an earlier run's folder; RunError when
// writing fails.
RunSummary RunScenario(const Scenario& scenario, const RunOptions& options);

// After a run with charged resampling: a note when its potential terms
// (tracker::FilterReport::potential_terms, each draw against every other
// filter's charge within reach) cost at least 5 s and half the tracker's
// time at ~2 ns each (measured, run.cc), which happens when many filters
// are within reach of one another, the cost then growing like N K^2 for K
// filters; it names the totals and the keys that set the reach and the
// draws. "" otherwise, and for every other resampler (no terms).
// `particles`: tracker.particles.
std::string ChargedResamplingNote(std::span<const tracker::FrameReport> reports, int particles,
                                  double tracker_seconds);

}  // namespace hcpf::scenarios
