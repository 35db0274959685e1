#pragma once
// Private: the observation source of a run whose `observation.detector` is a
// vision/ detector. It sees every rendered frame once, in order (as
// ProduceFrames hands them out, rendered or from the cache), cuts each
// target's model from the frame's pixels at its pixel-exact ground-truth box
// in the first frame where the target is wholly inside the image and at least
// 75 % visible (its filter is born earlier, at its first in-frame appearance;
// until its model exists the target has no detections), and runs the
// detector on the frame.

#include <deque>
#include <memory>
#include <vector>

#include "hcpf/core/types.h"
#include "hcpf/renderer/renderer.h"
#include "hcpf/scenarios/scenario.h"
#include "hcpf/vision/detectors.h"

namespace hcpf::scenarios::internal {

class DetectionPass {
 public:
  explicit DetectionPass(const Scenario& scenario);
  void Add(const renderer::RenderedFrame& frame);
  // The observations of every frame added, in order.
  std::vector<Observation> Take() { return std::move(observations_); }
  const std::vector<vision::TargetModel>& models() const { return models_; }

 private:
  std::unique_ptr<vision::Detector> detector_;
  Rng rng_;
  std::vector<vision::TargetModel> models_;
  std::vector<Observation> observations_;
  std::deque<RgbImage> recent_;  // the detector's history() latest frames, newest first
};

}  // namespace hcpf::scenarios::internal
