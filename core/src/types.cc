#include "hcpf/core/types.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hcpf {

BoxPx Intersect(const BoxPx& a, const BoxPx& b) {
  const double x0 = std::max(a.left, b.left);
  const double y0 = std::max(a.top, b.top);
  const double x1 = std::min(a.right(), b.right());
  const double y1 = std::min(a.bottom(), b.bottom());
  if (x1 <= x0 || y1 <= y0) return {x0, y0, 0.0, 0.0};
  return BoxPx::FromCorners(x0, y0, x1, y1);
}

BoxPx Union(const BoxPx& a, const BoxPx& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  return BoxPx::FromCorners(std::min(a.left, b.left), std::min(a.top, b.top),
                            std::max(a.right(), b.right()), std::max(a.bottom(), b.bottom()));
}

double Iou(const BoxPx& a, const BoxPx& b) {
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  const double area_a = a.area();
  const double area_b = b.area();
  if (area_a <= kEps || area_b <= kEps) return 0.0;
  const double inter = Intersect(a, b).area();
  const double uni = area_a + area_b - inter;
  if (uni <= kEps) return 0.0;
  return inter / uni;
}

double LikelihoodMap::Sample(double x_px, double y_px) const {
  if (width <= 0 || height <= 0) return 0.0;
  const double gx = std::clamp(x_px / cell_px - 0.5, 0.0, static_cast<double>(width - 1));
  const double gy = std::clamp(y_px / cell_px - 0.5, 0.0, static_cast<double>(height - 1));
  const int x0 = static_cast<int>(gx);
  const int y0 = static_cast<int>(gy);
  const int x1 = std::min(x0 + 1, width - 1);
  const int y1 = std::min(y0 + 1, height - 1);
  const double fx = gx - x0;
  const double fy = gy - y0;
  const double top = (1.0 - fx) * At(x0, y0) + fx * At(x1, y0);
  const double bottom = (1.0 - fx) * At(x0, y1) + fx * At(x1, y1);
  return (1.0 - fy) * top + fy * bottom;
}

}  // namespace hcpf

namespace hcpf {

bool Observation::target_specific() const {
  return !target_maps.empty() ||
         std::any_of(detections.begin(), detections.end(),
                     [](const Detection& d) { return d.target.has_value(); });
}

}  // namespace hcpf
