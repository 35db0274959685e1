#include "detection_pass.h"

#include <fmt/format.h>

#include <algorithm>

#include "hcpf/core/check.h"

namespace hcpf::scenarios::internal {
namespace {
constexpr double kModelVisible = 0.75;  // visible fraction a model is cut at
}  // namespace

DetectionPass::DetectionPass(const Scenario& scenario)
    : detector_(
          vision::MakeDetector(scenario.observation.detector, scenario.observation.detectors)),
      rng_(Rng(scenario.seeds.observation).Fork("detector")) {
  HCPF_CHECK(detector_ != nullptr) << "unknown detector " << scenario.observation.detector;
}

void DetectionPass::Add(const renderer::RenderedFrame& frame) {
  if (detector_->uses_models()) {
    for (const GroundTruthObject& o : frame.ground_truth.objects) {
      const bool known =
          std::any_of(models_.begin(), models_.end(),
                      [&](const vision::TargetModel& m) { return m.target == o.id; });
      // Cut when the target is first wholly inside the image and mostly
      // visible: its first in-frame appearance (where its filter is born) is
      // often a sliver at the border, a model of a few pixels.
      const bool whole = o.in_frame && o.truncation == 0.0 && o.visible_fraction >= kModelVisible;
      if (whole && !known) {
        models_.push_back(vision::CutTargetModel(frame.rgb, o.amodal_box, o.id, frame.frame));
      }
    }
  }
  // Each frame draws from its own stream, so a frame's detections do not
  // depend on which frames came before it.
  Rng rng = rng_.Fork(fmt::format("frame/{}", frame.frame));
  const std::vector<ImageView> previous(recent_.begin(), recent_.end());
  vision::DetectorOutput out = detector_->Detect(
      {.image = frame.rgb, .frame = frame.frame, .previous = previous, .models = models_}, rng);
  if (detector_->history() > 0) {
    recent_.push_front(frame.rgb);
    if (static_cast<int>(recent_.size()) > detector_->history()) recent_.pop_back();
  }
  observations_.push_back({.frame = frame.frame,
                           .detections = std::move(out.detections),
                           .target_maps = std::move(out.maps)});
}

}  // namespace hcpf::scenarios::internal
