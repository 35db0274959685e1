#include <algorithm>
#include <cmath>
#include <cstring>

#include "hcpf/vision/detector.h"

namespace hcpf::vision {

TargetModel CutTargetModel(const ImageView& image, const BoxPx& box, ObjectId target, int frame) {
  TargetModel model{.target = target, .frame = frame, .box = box};
  if (image.empty() || box.empty()) return model;
  const int x0 = std::max(0, static_cast<int>(std::floor(box.left)));
  const int y0 = std::max(0, static_cast<int>(std::floor(box.top)));
  const int x1 = std::min(image.width, static_cast<int>(std::ceil(box.right())));
  const int y1 = std::min(image.height, static_cast<int>(std::ceil(box.bottom())));
  if (x1 <= x0 || y1 <= y0) return model;
  model.patch.width = x1 - x0;
  model.patch.height = y1 - y0;
  model.patch.pixels.resize(3 * static_cast<size_t>(model.patch.width) * model.patch.height);
  for (int y = y0; y < y1; ++y) {
    std::memcpy(model.patch.at(0, y - y0), image.at(x0, y), 3 * static_cast<size_t>(x1 - x0));
  }
  return model;
}

}  // namespace hcpf::vision
