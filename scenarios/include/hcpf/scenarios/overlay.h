#pragma once
// overlay.mp4 of a run: per frame the image (rendered frame, or a plain
// background at detection level), ground-truth boxes (white, "gt <id>"), the
// frame's detections (thin yellow boxes; a target-specific detector's are
// labelled with the target whose model fired, "m<id>", and their score), each
// filter's estimate box and particle cloud in the filter's colour, and the
// filter's state (CORRECT / HIJACKED / ...) as a label; a header (top left)
// names the scene, the frame, the run (seed, tracker) and the detector
// (internal::OverlayHeaderLines).
//
//   WriteOverlayVideo(out / "overlay.mp4", scenario,
//                     {.truth = truth, .reports = reports, .observations = observations,
//                      .filters = &*scores.filters},
//                     nullptr);
//
// Particles are drawn only when the tracker kept them (tracker.keep_particles > 0).

#include <functional>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hcpf/core/ground_truth.h"
#include "hcpf/core/types.h"
#include "hcpf/metrics/filter_metrics.h"
#include "hcpf/renderer/renderer.h"
#include "hcpf/scenarios/scenario.h"
#include "hcpf/tracker/tracker.h"

namespace hcpf::scenarios {

// What an overlay draws over the frames. `truth` gives one video frame per
// entry; `reports` and `observations` hold one entry per frame too, or none
// (no filters; no detections).
struct OverlayContent {
  std::span<const FrameGroundTruth> truth;
  std::span<const tracker::FrameReport> reports;
  std::span<const Observation> observations;
  const metrics::FilterMetrics* filters = nullptr;  // state labels; null: none
};

// What was written: the codec, and the frames at their rate and size.
struct OverlayVideo {
  std::string fourcc;              // "avc1" or "mp4v"
  std::string codec;               // "H.264" or "MPEG-4 Part 2"
  bool plays_in_browsers = false;  // H.264 in MP4 does; MPEG-4 Part 2 does not
  int frames = 0;
  double fps = 0.0;
  int width = 0, height = 0;
};

// Writes `path` with FFmpeg (the plugin of scenarios/src/video_plugin.cc) at
// the scenario's fps and camera resolution: H.264 (fourcc avc1, FFmpeg's
// libx264), or MPEG-4 Part 2 (mp4v) when FFmpeg has no libx264. `frames`,
// when given, must hold one image per frame of the camera's size. Throws
// RunError when the video cannot be opened or written; HCPF_CHECK on
// mismatched lengths.
OverlayVideo WriteOverlayVideo(const std::string& path, const Scenario& scenario,
                               const OverlayContent& content, const std::vector<RgbImage>* frames);

// The same with frames fetched one at a time (e.g. read back from the frame
// cache), so a long rendered run need not hold every frame in memory.
// `frame_at(f)` returns frame f's image, or nullopt for the plain background.
using OverlayFrameSource = std::function<std::optional<RgbImage>(int frame)>;
OverlayVideo WriteOverlayVideo(const std::string& path, const Scenario& scenario,
                               const OverlayContent& content, const OverlayFrameSource& frame_at);

// The largest width and height an overlay video may have: MPEG-4 Part 2 (the
// fallback) codes them in 13 bits, and FFmpeg's encoder refuses 8192.
inline constexpr int kMaxVideoSide = 8191;

// H.264's largest level (6.2, Annex A, Table A-1) codes frames of at most
// 139,264 macroblocks of 16 x 16 px (8176 x 4352, say) and 16,711,680
// macroblocks a second (1920 x 1080 at 2048 fps). libx264 writes a larger or
// faster video all the same, declaring level 6.2, which it exceeds, so a
// browser may refuse it: such a video is not said to play in browsers
// (OverlayVideo::plays_in_browsers), and a run warns before it starts
// (VideoLevelNote). (Each side's limit, sqrt(8 x 139,264) macroblocks =
// 16,880 px, is past kMaxVideoSide.)
inline constexpr int64_t kMaxH264FrameMacroblocks = 139264;
inline constexpr double kMaxH264MacroblocksPerSecond = 16711680.0;
bool FitsAnH264Level(int width, int height, double fps);

namespace internal {

// The run's tag: its seed and tracker, in the run report header's words
// ("seed 7, 500 particles, charged resampling"; an external tracker's
// "seed 7, tracker: external (python3 sort.py)", its command's words by
// their file names). Plain ASCII words: the video's Hershey font draws
// nothing else.
std::string OverlayRunTag(const Scenario& scenario);

// The header's lines (top left), top to bottom: the scene and the frame
// (`frame` from 0, shown from 1 as gt/gt.txt, filters.csv and the report
// count it), the run's tag (OverlayRunTag), and, when the run has
// detections, the detector ("detections (sks)", "(simulated)" at detection
// level). Two runs' videos side by side (`hcpf report --against`) both read
// "crossing  frame 1": the tag tells them apart, in a screenshot too.
std::vector<std::string> OverlayHeaderLines(const Scenario& scenario, int frame, bool detections);

// `text` as drawn at `scale` in a frame `max_width_px` wide: whole when it
// fits, else without its last ", "-separated clauses (the run tag's
// likelihood, camera motion, resampling ...) and then its last characters,
// ending in " .." to show the cut. The header's lines ran off frames
// narrower than about 260 px (an audit).
std::string FitHeaderLine(const std::string& text, double scale, int max_width_px);

}  // namespace internal

// InputError naming `option` (e.g. "--video") when the scenario's camera is
// larger than kMaxVideoSide either way: checked before a run starts, so a
// run asked for a video does not fail at its end (a second bad-input audit).
void CheckVideoFits(const Scenario& scenario, const std::string& option);

// A warning when the scenario's video is larger or faster than any H.264
// level codes (FitsAnH264Level), "" otherwise.
std::string VideoLevelNote(const Scenario& scenario);

}  // namespace hcpf::scenarios
