#pragma once
// Image outputs of the renderer (OpenCV inside, not in this header).

#include <string>
#include <vector>

#include "hcpf/renderer/renderer.h"

namespace hcpf::renderer {

// Depth as a 16-bit PNG in millimetres (0 = nothing drawn or beyond 65.535 m
// is clamped to 65535). Throws hcpf::RunError.
void WriteDepthPng(const DepthImage& depth, const std::string& path);
// Instance ids as a 16-bit PNG: ObjectId value + 1, 0 = no target. Throws
// hcpf::RunError.
void WriteInstancePng(const InstanceImage& ids, const std::string& path);

struct ContactSheetOptions {
  int columns = 4;           // thumbnails per row, >= 1
  int thumb_width_px = 320;  // thumbnails keep the frame's aspect ratio
};

// A grid of frames (in the given order) with their ground truth drawn:
// amodal boxes yellow, visible boxes green, the target id and the visible
// fraction beside each box (placed so that no two labels overlap where the
// thumbnail has room: internal::PlaceLabels), the 1-based frame number in the
// corner.
RgbImage MakeContactSheet(const std::vector<RenderedFrame>& frames,
                          const ContactSheetOptions& options = {});

namespace internal {

// A rectangle of whole pixels: columns [x, x + width), rows [y, y + height).
struct PixelRect {
  int x = 0, y = 0, width = 0, height = 0;
  bool Overlaps(const PixelRect& o) const {
    return x < o.x + o.width && o.x < x + width && y < o.y + o.height && o.y < y + height;
  }
  friend bool operator==(const PixelRect&, const PixelRect&) = default;
};

// Where the labels of one thumbnail go: label i (`sizes[i]`: its width and
// height, halo included) beside box i, at the first of these places that
// lies inside the `width` x `height` thumbnail and overlaps neither `taken`,
// nor a label placed before it, nor another box: above the box at its left
// edge, below it at its left edge, above it ending at its right edge, below
// it ending there, right of the box at its top, left of it at its top. When
// every place covers another box, the first that overlaps no label; when
// none is free (a crowd of targets), the first place, moved inside the
// thumbnail. Returns the labels' rectangles, in the order of `boxes`.
std::vector<PixelRect> PlaceLabels(const std::vector<PixelRect>& boxes,
                                   const std::vector<PixelRect>& sizes, int width, int height,
                                   std::vector<PixelRect> taken);

}  // namespace internal

}  // namespace hcpf::renderer
