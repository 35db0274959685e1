#pragma once
// Where the text labels of boxes drawn on an image go, so that they neither
// overlap each other nor, where there is room, cover another box: the
// overlay video's labels (scenarios/src/overlay.cc) and the contact sheet's
// (renderer/src/image_io.cc).

#include <vector>

namespace hcpf {

// A rectangle in pixels: columns [x, x + width), rows [y, y + height).
struct PixelRect {
  int x = 0, y = 0, width = 0, height = 0;
  bool Overlaps(const PixelRect& o) const {
    return x < o.x + o.width && o.x < x + width && y < o.y + o.height && o.y < y + height;
  }
  friend bool operator==(const PixelRect&, const PixelRect&) = default;
};

// The side of its box a label tries first.
enum class LabelSide { kAbove, kBelow, kRight };

// A label to place beside `box`: its text's size (outline included) and the
// side it tries first.
struct LabelRequest {
  PixelRect box;
  int text_width = 0, text_height = 0;
  LabelSide first = LabelSide::kAbove;
};

// Where each label's text goes (its rectangle), in order. The candidates:
// above its box (4 px up), below it (2 px down), right of it and left of it
// (3 px aside, level with its top), then a line further up and down; in that
// order from `first` (kBelow: below, above, right, left, further down,
// further up; kRight: right, above, below, left, further up, further down).
// A label takes the first candidate that lies inside `image` and overlaps
// neither `taken`, nor a label placed before it, nor the box of another
// request whose box does not overlap its own; else the first inside the
// image that overlaps no label and nothing taken (it covers a box); else the
// first inside the image; else the first, moved inside the image. In a crowd
// labels may still overlap: there is no room. At the crossing of two
// vehicles "F1 F2 CORRECT" were drawn on each other and "gt 1" under a box
// (an audit), and the contact sheet's labels over each other (another).
std::vector<PixelRect> PlaceLabels(const std::vector<LabelRequest>& labels, PixelRect image,
                                   std::vector<PixelRect> taken);

}  // namespace hcpf
