#include "hcpf/core/label_placement.h"

#include <algorithm>
#include <array>

namespace hcpf {

std::vector<PixelRect> PlaceLabels(const std::vector<LabelRequest>& labels, PixelRect image,
                                   std::vector<PixelRect> taken) {
  std::vector<PixelRect> out;
  out.reserve(labels.size());
  const auto inside = [&image](const PixelRect& r) {
    return r.x >= image.x && r.y >= image.y && r.x + r.width <= image.x + image.width &&
           r.y + r.height <= image.y + image.height;
  };
  const auto free = [&taken](const PixelRect& r) {
    return std::none_of(taken.begin(), taken.end(),
                        [&r](const PixelRect& t) { return r.Overlaps(t); });
  };
  const auto clear_of_boxes = [&labels](const PixelRect& r) {
    return std::none_of(labels.begin(), labels.end(),
                        [&r](const LabelRequest& l) { return r.Overlaps(l.box); });
  };
  for (const LabelRequest& l : labels) {
    const PixelRect& b = l.box;
    const int w = l.text_width, h = l.text_height;
    const PixelRect above{b.x, b.y - 4 - h, w, h};
    const PixelRect below{b.x, b.y + b.height + 2, w, h};
    const PixelRect right{b.x + b.width + 3, b.y, w, h};
    const PixelRect left{b.x - w - 3, b.y, w, h};
    const PixelRect above2{b.x, above.y - h - 2, w, h};
    const PixelRect below2{b.x, below.y + h + 2, w, h};
    std::array<PixelRect, 6> candidates;
    switch (l.first) {
      case LabelSide::kAbove:
        candidates = {above, below, right, left, above2, below2};
        break;
      case LabelSide::kBelow:
        candidates = {below, above, right, left, below2, above2};
        break;
      case LabelSide::kRight:
        candidates = {right, above, below, left, above2, below2};
        break;
    }
    auto chosen = std::find_if(candidates.begin(), candidates.end(), [&](const PixelRect& c) {
      return inside(c) && free(c) && clear_of_boxes(c);
    });
    if (chosen == candidates.end()) {
      chosen = std::find_if(candidates.begin(), candidates.end(),
                            [&](const PixelRect& c) { return inside(c) && free(c); });
    }
    if (chosen == candidates.end())
      chosen = std::find_if(candidates.begin(), candidates.end(), inside);
    if (chosen == candidates.end()) chosen = candidates.begin();
    out.push_back(*chosen);
    taken.push_back(*chosen);
  }
  return out;
}

}  // namespace hcpf
