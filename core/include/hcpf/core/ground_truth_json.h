#pragma once
// The one JSON encoding of a frame's ground truth: the items of gt.json's
// `frames` list (docs/outputs.md) and the frame cache's per-frame records are
// both written and read here.

#include <nlohmann/json.hpp>

#include "hcpf/core/ground_truth.h"

namespace hcpf {

// {frame, camera {width_px, height_px, K, position_m, world_from_camera},
//  image_from_ground, objects [...]}; doubles keep full precision.
nlohmann::json GroundTruthToJson(const FrameGroundTruth& gt);

// The inverse of GroundTruthToJson: GroundTruthFromJson(GroundTruthToJson(g))
// == g. Throws InputError whose key is the path in the frame ("objects[0].
// visible_box", "camera.K[1]"; no file: the caller names it) when a field is
// missing or not of the type written: ids, frames and pixel counts whole
// numbers (a frame 3.5 or an id 1.7 is refused, not truncated).
FrameGroundTruth GroundTruthFromJson(const nlohmann::json& j);

}  // namespace hcpf
