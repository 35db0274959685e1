#pragma once
// Private: the observation source of a run whose `observation.detector` is a
// vision/ detector. It sees every rendered frame once, in order (as
// ProduceFrames hands them out, rendered or from the cache), cuts each
// target's model from the frame's pixels at its pixel-exact ground-truth box
// in the first frame where the target is wholly inside the image and at least
// 75 % visible (under `init: ground_truth` its filter is born then, from the
// same box: until its model exists nothing can detect the target), and runs the
// detector on the frame, or reads its output from the detection cache
// (detection_cache.h) when the frame cache is on. A labelled detection file
// (`observation.file.labels`) has no models: the file knows a target from its
// first row labelled with it, and its filter is born then.

#include <deque>
#include <memory>
#include <set>
#include <span>
#include <vector>

#include "detection_cache.h"
#include "hcpf/core/types.h"
#include "hcpf/renderer/renderer.h"
#include "hcpf/scenarios/scenario.h"
#include "hcpf/vision/detectors.h"

namespace hcpf::scenarios::internal {

class DetectionPass {
 public:
  // The visible fraction a target needs, wholly inside the image, for its
  // model to be cut.
  static constexpr double kModelVisible = 0.75;

  // `cache_dir`: the frame cache's folder ("" = no detection cache).
  DetectionPass(const Scenario& scenario, const std::string& cache_dir);
  // Detects in `frame` (searching each model's window, when given, else the
  // whole frame) and returns the frame's observation.
  Observation& Add(const renderer::RenderedFrame& frame,
                   std::span<const vision::SearchWindow> windows = {});
  int frames_from_cache() const { return from_cache_; }
  // The observations of every frame added, in order.
  std::vector<Observation> Take() { return std::move(observations_); }
  const std::vector<vision::TargetModel>& models() const { return models_; }
  // Whether the detector can report `target` from the frame last added on:
  // always for a model-free detector, once its model is cut for a model-based
  // one, once a row labelled with it was read for a labelled file.
  bool Detects(ObjectId target) const;

 private:
  std::string Key(const renderer::RenderedFrame& frame, const XXH128_hash_t& digest, const Rng& rng,
                  std::span<const vision::SearchWindow> windows) const;

  std::unique_ptr<vision::Detector> detector_;
  std::string options_text_;    // the detector's name and options, for the cache key
  bool labelled_file_ = false;  // observation.file.labels
  Rng rng_;
  std::vector<vision::TargetModel> models_;
  std::set<int32_t> labelled_targets_;          // of a labelled file: the targets seen so far
  std::vector<XXH128_hash_t> model_digests_;    // of each model's patch
  std::vector<XXH128_hash_t> context_digests_;  // of each model's context
  std::vector<Observation> observations_;
  std::deque<RgbImage> recent_;  // the detector's history() latest frames, newest first
  std::deque<XXH128_hash_t> recent_digests_;
  std::unique_ptr<DetectionCache> cache_;
  int from_cache_ = 0;
};

}  // namespace hcpf::scenarios::internal
