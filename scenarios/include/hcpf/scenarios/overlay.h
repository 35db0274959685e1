#pragma once
// overlay.mp4 of a run: per frame the image (rendered frame, or a plain
// background at detection level), ground-truth boxes (white, "gt <id>"),
// each filter's estimate box and particle cloud in the filter's colour, and
// the filter's state (CORRECT / HIJACKED / ...) as a label.
//
//   WriteOverlayVideo(out / "overlay.mp4", scenario, truth, reports, scores.filters, nullptr);
//
// Particles are drawn only when the tracker kept them (tracker.keep_particles > 0).

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "hcpf/core/ground_truth.h"
#include "hcpf/metrics/filter_metrics.h"
#include "hcpf/renderer/renderer.h"
#include "hcpf/scenarios/scenario.h"
#include "hcpf/tracker/tracker.h"

namespace hcpf::scenarios {

// Writes `path` with OpenCV's VideoWriter (MPEG-4 Part 2, fourcc mp4v) at the
// scenario's fps and camera resolution, one video frame per entry of `truth`.
// `reports` (same length as truth, or empty) and `filters` (states; nullopt =
// no labels) are optional content. `frames`, when given, must hold one image
// per frame of the camera's size. Throws RunError when the writer cannot be
// opened; HCPF_CHECK on mismatched lengths.
void WriteOverlayVideo(const std::string& path, const Scenario& scenario,
                       const std::vector<FrameGroundTruth>& truth,
                       const std::vector<tracker::FrameReport>& reports,
                       const std::optional<metrics::FilterMetrics>& filters,
                       const std::vector<RgbImage>* frames);

// The same with frames fetched one at a time (e.g. read back from the frame
// cache), so a long rendered run need not hold every frame in memory.
// `frame_at(f)` returns frame f's image, or nullopt for the plain background.
using OverlayFrameSource = std::function<std::optional<RgbImage>(int frame)>;
void WriteOverlayVideo(const std::string& path, const Scenario& scenario,
                       const std::vector<FrameGroundTruth>& truth,
                       const std::vector<tracker::FrameReport>& reports,
                       const std::optional<metrics::FilterMetrics>& filters,
                       const OverlayFrameSource& frame_at);

// The largest width and height an overlay video may have: MPEG-4 Part 2
// codes them in 13 bits, and FFmpeg's encoder refuses 8192.
inline constexpr int kMaxVideoSide = 8191;

// InputError naming `option` (e.g. "--video") when the scenario's camera is
// larger than kMaxVideoSide either way: checked before a run starts, so a
// run asked for a video does not fail at its end (a second bad-input audit).
void CheckVideoFits(const Scenario& scenario, const std::string& option);

}  // namespace hcpf::scenarios
