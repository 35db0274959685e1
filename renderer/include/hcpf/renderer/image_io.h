#pragma once
// Image outputs of the renderer (OpenCV inside, not in this header).

#include <cstdint>
#include <string>
#include <vector>

#include "hcpf/renderer/renderer.h"

namespace hcpf::renderer {

// Depth as a 16-bit grey PNG in units of `unit_mm` millimetres, rounded; 0
// where nothing was drawn. A depth beyond 65535 units is written 65535;
// returns how many pixels were (65.5 m at 1 mm: every pixel of a camera
// 100 m up; a review). Throws hcpf::RunError.
int64_t WriteDepthPng(const DepthImage& depth, const std::string& path, double unit_mm = 1.0);
// Instance ids as a 16-bit PNG: ObjectId value + 1, 0 = no target. Throws
// hcpf::RunError.
void WriteInstancePng(const InstanceImage& ids, const std::string& path);

struct ContactSheetOptions {
  int columns = 4;           // thumbnails per row, >= 1
  int thumb_width_px = 320;  // thumbnails keep the frame's aspect ratio
};

// A grid of frames (in the given order) with their ground truth drawn:
// amodal boxes yellow, visible boxes green, the target id and the visible
// fraction beside each box (placed by hcpf::PlaceLabels: apart from each
// other and off the other boxes where the thumbnail has room), the 1-based
// frame number in the corner.
RgbImage MakeContactSheet(const std::vector<RenderedFrame>& frames,
                          const ContactSheetOptions& options = {});

}  // namespace hcpf::renderer
