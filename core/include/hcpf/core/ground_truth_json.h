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
// == g. Throws nlohmann::json::exception when a field is missing or of the
// wrong type.
FrameGroundTruth GroundTruthFromJson(const nlohmann::json& j);

}  // namespace hcpf
