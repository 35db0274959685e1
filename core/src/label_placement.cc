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
  const auto untaken = [&taken](const PixelRect& r) {
    return std::none_of(taken.begin(), taken.end(),
                        [&r](const PixelRect& t) { return r.Overlaps(t); });
  };
  for (const LabelRequest& l : labels) {
    // Off the other boxes, but not those that overlap its own (the same
    // target's filter, truth and detection boxes nearly coincide: avoiding
    // them would send its labels from side to side as a filter jitters).
    const auto clear_of_boxes = [&labels, &l](const PixelRect& r) {
      return std::none_of(labels.begin(), labels.end(), [&](const LabelRequest& other) {
        return !other.box.Overlaps(l.box) && r.Overlaps(other.box);
      });
    };
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
      return inside(c) && untaken(c) && clear_of_boxes(c);
    });
    if (chosen == candidates.end()) {
      chosen = std::find_if(candidates.begin(), candidates.end(),
                            [&](const PixelRect& c) { return inside(c) && untaken(c); });
    }
    if (chosen == candidates.end()) {
      chosen = std::find_if(candidates.begin(), candidates.end(), inside);
    }
    PixelRect place = chosen != candidates.end() ? *chosen : candidates.front();
    if (chosen == candidates.end()) {
      // Moved inside the image, so that it is drawn at all (a box as tall
      // as a thumbnail left its label off it: a review).
      place.x = std::clamp(place.x, image.x, std::max(image.x, image.x + image.width - w));
      place.y = std::clamp(place.y, image.y, std::max(image.y, image.y + image.height - h));
    }
    out.push_back(place);
    taken.push_back(place);
  }
  return out;
}

}  // namespace hcpf
