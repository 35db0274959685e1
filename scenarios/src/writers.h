#pragma once
// Writers of a run's files. Numbers are formatted with fixed precision so the
// same inputs give byte-identical files.

#include <string>
#include <vector>

#include "hcpf/core/ground_truth.h"
#include "hcpf/core/types.h"
#include "hcpf/scenarios/scenario.h"

namespace hcpf::scenarios {

// MOT17 ground truth, 9 columns: frame,id,left,top,w,h,consider,class,visibility
// (1-based frames and pixel coordinates; class 1 = evaluated target; visibility
// = visible fraction). Targets entirely outside the image are not written.
std::string FormatGroundTruthMot(const std::vector<FrameGroundTruth>& frames);
// MOT detections: frame,-1,left,top,w,h,score,-1,-1,-1.
std::string FormatDetectionsMot(const std::vector<Observation>& observations);
// seqinfo.ini for TrackEval's MOTChallenge loader.
std::string FormatSeqinfo(const Scenario& scenario);
// gt.json: every field of every frame's ground truth (see docs/outputs.md).
std::string FormatGroundTruthJson(const Scenario& scenario, const std::vector<FrameGroundTruth>& frames);

// Writes `text` to `path`; throws RunError naming the path on failure.
void WriteTextFile(const std::string& path, const std::string& text);

}  // namespace hcpf::scenarios
