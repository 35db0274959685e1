#include "detection_pass.h"

#include <fmt/format.h>

#include <algorithm>

#include "hcpf/core/check.h"
#include "hcpf/scenarios/cache.h"
#include "hcpf/scenarios/frames.h"

namespace hcpf::scenarios::internal {
namespace {
template <class O>
void AppendOptions(std::string& text, std::string_view name, const O& options) {
  text += fmt::format("[{}]", name);
  for (const Field<O>& f : O::Fields()) text += fmt::format("{}={};", f.key, f.ValueText(options));
}

// What the detector is: its name and every option of each detector it runs.
std::string OptionsText(const ObservationOptions& o) {
  std::string text = "hcpf-detections/1;" + o.DetectorName() + ";";
  o.detectors.ForEach([&](const char* name, const auto& options) {
    if (o.Uses(name)) AppendOptions(text, name, options);
  });
  return text;
}
// observation.detector: file: each frame's rows of the det.txt read at load
// time (another program's detections; model-free, not target-specific).
class FileDetector final : public vision::Detector {
 public:
  explicit FileDetector(std::shared_ptr<const std::vector<std::vector<Detection>>> frames)
      : frames_(std::move(frames)) {}
  vision::DetectorOutput Detect(const vision::DetectorInput& input, Rng& /*rng*/) const override {
    vision::DetectorOutput out;
    const auto f = static_cast<size_t>(input.frame);
    if (input.frame >= 0 && f < frames_->size()) out.detections = (*frames_)[f];
    return out;
  }
  bool uses_models() const override { return false; }
  std::string_view name() const override { return "file"; }

 private:
  std::shared_ptr<const std::vector<std::vector<Detection>>> frames_;
};

std::unique_ptr<vision::Detector> MakeDetectorOf(const ObservationOptions& o) {
  if (o.from_file()) {
    HCPF_CHECK(o.file.frames != nullptr) << "observation.file read at load time";
    return std::make_unique<FileDetector>(o.file.frames);
  }
  return vision::MakeDetector(o.DetectorName(), o.detectors);
}

}  // namespace

DetectionPass::DetectionPass(const Scenario& scenario, const std::string& cache_dir)
    : detector_(MakeDetectorOf(scenario.observation)),
      options_text_(OptionsText(scenario.observation)),
      labelled_file_(scenario.observation.from_file() && scenario.observation.file.labels),
      rng_(Rng(scenario.seeds.observation).Fork("detector")) {
  HCPF_CHECK(detector_ != nullptr) << "unknown detector " << scenario.observation.DetectorName();
  // The file's rows are at hand: nothing to cache.
  if (!cache_dir.empty() && ProgramDigest() && !scenario.observation.from_file()) {
    // Labelled with the scene's frame folder (`hcpf cache` lists the
    // outputs under it) and the detector.
    cache_ = std::make_unique<DetectionCache>(
        cache_dir, DetectionLabel(PixelHashOf(scenario), scenario.observation.DetectorName()));
  }
}

std::string DetectionPass::Key(const renderer::RenderedFrame& frame, const XXH128_hash_t& digest,
                               const Rng& rng,
                               std::span<const vision::SearchWindow> windows) const {
  DetectionKey key;
  key.Add(*ProgramDigest());
  key.Add(options_text_);
  key.Add(static_cast<uint64_t>(frame.frame));
  key.Add(rng.identity());
  key.Add(digest);
  key.Add(static_cast<uint64_t>(recent_digests_.size()));
  for (const XXH128_hash_t& d : recent_digests_) key.Add(d);
  key.Add(static_cast<uint64_t>(models_.size()));
  for (size_t i = 0; i < models_.size(); ++i) {
    const vision::TargetModel& m = models_[i];
    key.Add(static_cast<uint64_t>(Value(m.target)));
    key.Add(static_cast<uint64_t>(m.frame));
    for (double v : {m.box.left, m.box.top, m.box.width, m.box.height}) key.Add(v);
    key.Add(model_digests_[i]);
    key.Add(context_digests_[i]);
  }
  key.Add(static_cast<uint64_t>(windows.size()));
  for (const vision::SearchWindow& w : windows) {
    key.Add(static_cast<uint64_t>(Value(w.target)));
    for (double v : {w.box.left, w.box.top, w.box.width, w.box.height}) key.Add(v);
  }
  return key.Finish();
}

bool DetectionPass::Detects(ObjectId target) const {
  if (labelled_file_) return labelled_targets_.contains(Value(target));
  return !detector_->uses_models() ||
         std::any_of(models_.begin(), models_.end(),
                     [&](const vision::TargetModel& m) { return m.target == target; });
}

Observation& DetectionPass::Add(const renderer::RenderedFrame& frame,
                                std::span<const vision::SearchWindow> windows) {
  if (detector_->uses_models()) {
    for (const GroundTruthObject& o : frame.ground_truth.objects) {
      // Cut when the target is first wholly inside the image and mostly
      // visible: its first in-frame appearance is often a sliver at the
      // border, a model of a few pixels.
      const bool whole = o.in_frame && o.truncation == 0.0 && o.visible_fraction >= kModelVisible;
      if (whole && !Detects(o.id)) {
        models_.push_back(vision::CutTargetModel(frame.rgb, o.amodal_box, o.id, frame.frame));
        model_digests_.push_back(PixelDigest(models_.back().patch));
        context_digests_.push_back(PixelDigest(models_.back().context));
      }
    }
  }
  // Each frame draws from its own stream, so a frame's detections do not
  // depend on which frames came before it.
  Rng rng = rng_.Fork(fmt::format("frame/{}", frame.frame));
  const XXH128_hash_t digest = cache_ ? PixelDigest(frame.rgb) : XXH128_hash_t{};
  const std::string key = cache_ ? Key(frame, digest, rng, windows) : std::string();
  std::optional<vision::DetectorOutput> cached;
  if (cache_) cached = cache_->Load(key);
  vision::DetectorOutput out;
  if (cached) {
    out = std::move(*cached);
    ++from_cache_;
  } else {
    const std::vector<ImageView> previous(recent_.begin(), recent_.end());
    out = detector_->Detect({.image = frame.rgb,
                             .frame = frame.frame,
                             .previous = previous,
                             .models = models_,
                             .windows = windows},
                            rng);
    if (cache_) cache_->Store(key, out);
  }
  if (detector_->history() > 0) {
    recent_.push_front(frame.rgb);
    recent_digests_.push_front(digest);
    if (static_cast<int>(recent_.size()) > detector_->history()) {
      recent_.pop_back();
      recent_digests_.pop_back();
    }
  }
  if (labelled_file_) {
    for (const Detection& d : out.detections) {
      if (d.target) labelled_targets_.insert(Value(*d.target));
    }
  }
  observations_.push_back({.frame = frame.frame,
                           .detections = std::move(out.detections),
                           .target_maps = std::move(out.maps)});
  return observations_.back();
}

}  // namespace hcpf::scenarios::internal
