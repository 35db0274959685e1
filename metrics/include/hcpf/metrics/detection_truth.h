#pragma once
// The truth a detector is scored against (metrics/detection_quality.h), from
// a run's ground truth in memory or from the gt.json that `hcpf render` and
// `hcpf run` write, so a detector of the user's own, run on the rendered
// frames, is scored exactly as the built-in ones are:
//
//   const GroundTruthFile gt = ReadGroundTruthJson("out/crossing/gt.json");
//   std::vector<DetectionFrame> frames(gt.frames.size());
//   for (size_t f = 0; f < frames.size(); ++f) frames[f].truth = DetectionTruthOf(gt.frames[f]);

#include <set>
#include <string>
#include <vector>

#include "hcpf/core/ground_truth.h"
#include "hcpf/metrics/detection_quality.h"
#include "hcpf/metrics/mot_io.h"

namespace hcpf::metrics {

// Pixel coordinates beyond this are no camera's: a box read from a file
// (gt.json, det.txt) with a larger one is bad input.
inline constexpr double kMaxCoordinatePx = 1e7;

// Each in-frame target of `frame`: its amodal box clipped to the image (the
// frame's camera size), its visible fraction and its truncation by the image
// border. Targets wholly outside the image are left out.
std::vector<DetectionTruth> DetectionTruthOf(const FrameGroundTruth& frame);

struct GroundTruthFile {
  std::string source;                    // "rendered" (pixel-exact) or "analytic" (detection level)
  std::vector<FrameGroundTruth> frames;  // frames[f].frame == f
};

// Reads a gt.json (format "hcpf-gt/1", docs/outputs.md). Anything else, a
// file that does not parse, or a frame that is missing a field or out of
// order, is an InputError naming the file (the line and column of a syntax
// error; the frame's index otherwise).
GroundTruthFile ReadGroundTruthJson(const std::string& path);

// One detection of a det.txt: its 0-based frame, its box in 0-based pixels
// and its score, and the file's line it came from.
struct DetectionFileRow {
  int frame = 0;
  Detection detection;
  int64_t id = -1;  // column 2 as written (-1 in MOTChallenge's det.txt)
  int line = 0;
  bool id_whole = true;  // MotRow::id_whole
};

// The detections of a MOTChallenge det.txt (frame, id, left, top, width,
// height, score; 1-based frames and pixels; ids kept in `id`, which scoring ignores) read with
// MotFileKind::kDetections. A box whose width or height is not above 0, a
// coordinate beyond kMaxCoordinatePx or a score that is not finite is an
// InputError at the file, line and column.
std::vector<DetectionFileRow> DetectionRowsOf(const MotFile& file);

// Reads column 2 of `rows` (of the det.txt `file`) as each detection's target
// (Detection::target): an id of `targets`, or -1 for a detection of no
// target; any other id is an InputError at its line and column 2, whose
// message names `labels_option` (what asked for labels, e.g. "--labels").
void ReadDetectionLabels(const MotFile& file, const std::set<int64_t>& targets,
                         const std::string& labels_option, std::vector<DetectionFileRow>* rows);

}  // namespace hcpf::metrics
