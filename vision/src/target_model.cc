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
  const int cx0 = std::max(0, x0 - kModelContextPx);
  const int cy0 = std::max(0, y0 - kModelContextPx);
  const int cx1 = std::min(image.width, x1 + kModelContextPx);
  const int cy1 = std::min(image.height, y1 + kModelContextPx);
  model.context.width = cx1 - cx0;
  model.context.height = cy1 - cy0;
  model.context.pixels.resize(3 * static_cast<size_t>(model.context.width) * model.context.height);
  for (int y = cy0; y < cy1; ++y) {
    std::memcpy(model.context.at(0, y - cy0), image.at(cx0, y), 3 * static_cast<size_t>(cx1 - cx0));
  }
  model.context_x = x0 - cx0;
  model.context_y = y0 - cy0;
  return model;
}

}  // namespace hcpf::vision
