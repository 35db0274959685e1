// Fusion of several registered detectors (thesis chapter 10, "multiple
// detectors"): each runs on the frame, their detections are merged by a
// greedy suppression that lets agreement raise the score, and their maps are
// averaged after each is scaled to a peak of 1. docs/vision.md, "Fusion".

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "detectors.h"
#include "hcpf/core/check.h"
#include "hcpf/vision/detectors.h"

namespace hcpf::vision::internal {
namespace {

constexpr double kSameObjectIou = 0.5;  // detections this close are one object

class FusedDetector final : public Detector {
 public:
  explicit FusedDetector(std::vector<std::unique_ptr<Detector>> parts) : parts_(std::move(parts)) {
    for (const auto& p : parts_) {
      if (!name_.empty()) name_ += '+';
      name_ += p->name();
      history_ = std::max(history_, p->history());
      uses_models_ = uses_models_ || p->uses_models();
    }
  }

  DetectorOutput Detect(const DetectorInput& input, Rng& rng) const override {
    std::vector<DetectorOutput> outs;
    outs.reserve(parts_.size());
    for (const auto& p : parts_) {
      DetectorInput in = input;
      in.previous = input.previous.first(
          std::min<size_t>(input.previous.size(), static_cast<size_t>(p->history())));
      if (!p->uses_models()) {
        in.models = {};
        in.windows = {};
      }
      Rng part_rng = rng.Fork(p->name());
      outs.push_back(p->Detect(in, part_rng));
    }
    DetectorOutput fused;
    fused.detections = MergeDetections(outs);
    if (!input.models.empty()) fused.maps = MergeMaps(outs, input);
    return fused;
  }

  bool uses_models() const override { return uses_models_; }
  int history() const override { return history_; }
  std::string_view name() const override { return name_; }

 private:
  // Highest score first (ties: earlier part, then earlier detection); a
  // detection of the same target (or both untargeted) overlapping a kept one
  // at IoU >= 0.5 is absorbed into it: the kept box stays, its score becomes
  // the noisy-OR 1 - prod(1 - s) of everything absorbed.
  static std::vector<Detection> MergeDetections(const std::vector<DetectorOutput>& outs) {
    std::vector<Detection> all;
    for (const DetectorOutput& o : outs)
      all.insert(all.end(), o.detections.begin(), o.detections.end());
    std::vector<size_t> order(all.size());
    std::iota(order.begin(), order.end(), size_t{0});
    std::stable_sort(order.begin(), order.end(),
                     [&](size_t a, size_t b) { return all[a].score > all[b].score; });
    std::vector<Detection> kept;
    std::vector<double> miss;  // prod(1 - s) per kept detection
    for (size_t i : order) {
      const Detection& d = all[i];
      bool absorbed = false;
      for (size_t k = 0; k < kept.size() && !absorbed; ++k) {
        if (kept[k].target == d.target && Iou(kept[k].box, d.box) >= kSameObjectIou) {
          miss[k] *= 1.0 - d.score;
          absorbed = true;
        }
      }
      if (!absorbed) {
        kept.push_back(d);
        miss.push_back(1.0 - d.score);
      }
    }
    for (size_t k = 0; k < kept.size(); ++k) kept[k].score = std::clamp(1.0 - miss[k], 0.0, 1.0);
    return kept;
  }

  // Per model: the mean over the parts of each part's map scaled to a peak of
  // 1 (a part whose map is all zero adds 0), sampled on the finest part's grid.
  static std::vector<TargetMap> MergeMaps(const std::vector<DetectorOutput>& outs,
                                          const DetectorInput& input) {
    double cell_px = 0.0;
    for (const DetectorOutput& o : outs) {
      for (const TargetMap& m : o.maps) {
        cell_px = cell_px == 0.0 ? m.map.cell_px : std::min(cell_px, m.map.cell_px);
      }
    }
    std::vector<TargetMap> maps;
    if (cell_px == 0.0) return maps;
    const int width = static_cast<int>(std::ceil(input.image.width / cell_px));
    const int height = static_cast<int>(std::ceil(input.image.height / cell_px));
    for (size_t model = 0; model < input.models.size(); ++model) {
      TargetMap out{.target = input.models[model].target};
      out.map.width = width;
      out.map.height = height;
      out.map.cell_px = cell_px;
      out.map.values.assign(static_cast<size_t>(width) * height, 0.0f);
      int parts = 0;
      for (const DetectorOutput& o : outs) {
        if (o.maps.empty()) continue;
        HCPF_CHECK(o.maps.size() == input.models.size()) << "a map per model";
        const LikelihoodMap& m = o.maps[model].map;
        ++parts;
        const float peak =
            m.values.empty() ? 0.0f : *std::max_element(m.values.begin(), m.values.end());
        if (!(peak > 0.0f)) continue;
        for (int cy = 0; cy < height; ++cy) {
          for (int cx = 0; cx < width; ++cx) {
            const double v = m.Sample((cx + 0.5) * cell_px, (cy + 0.5) * cell_px) / peak;
            out.map.values[static_cast<size_t>(cy) * width + cx] += static_cast<float>(v);
          }
        }
      }
      if (parts > 0) {
        for (float& v : out.map.values) v = std::max(0.0f, v / static_cast<float>(parts));
      }
      maps.push_back(std::move(out));
    }
    return maps;
  }

  std::vector<std::unique_ptr<Detector>> parts_;
  std::string name_;
  int history_ = 0;
  bool uses_models_ = false;
};

}  // namespace

std::unique_ptr<Detector> MakeFusedDetector(std::vector<std::unique_ptr<Detector>> parts) {
  return std::make_unique<FusedDetector>(std::move(parts));
}

}  // namespace hcpf::vision::internal
