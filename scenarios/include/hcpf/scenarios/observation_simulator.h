#pragma once
// The simulated (oracle) detector of detection-level mode: turns a frame's
// ground truth into an Observation. It lives in scenarios/ because it reads
// ground truth; results label it "oracle".
//
// Per frame, from the stream Rng(seeds.observation).Fork("frame", f):
//  - each in-frame target is detected with probability
//      p = p_detect * visible_fraction^visibility_exponent  (0 below min_visible),
//    drawn from the sub-stream Fork("target", id) so that one target's draws
//    never shift another's;
//  - a detection's centre is the amodal box centre plus N(0, sigma_px²) per
//    axis, its width and height are multiplied by exp(N(0, size_sigma²)), its
//    score is strength * visible_fraction;
//  - clutter: Poisson(clutter_per_frame) boxes (sub-stream "clutter"), centres
//    uniform over the image, sizes those of a random in-frame target (or 5 % of
//    the image width when there is none), score uniform in [0, max strength]
//    of the in-frame targets (in [0, 1] when there is none);
//  - optional likelihood map: per cell, the sum over visible targets of
//      strength * visible_fraction * exp(-d² / (2 s²)),  s = map_blob_scale * (w + h) / 4,
//    plus a noise floor uniform in [0, map_noise] (sub-stream "map").

#include "hcpf/core/ground_truth.h"
#include "hcpf/core/rng.h"
#include "hcpf/core/types.h"
#include "hcpf/scenarios/scenario.h"

namespace hcpf::scenarios {

Observation SimulateObservation(const FrameGroundTruth& gt,
                                const SimulatedObservationOptions& options,
                                uint64_t observation_seed);

}  // namespace hcpf::scenarios
