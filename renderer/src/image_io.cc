#include "hcpf/renderer/image_io.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "codecs.h"
#include "hcpf/core/check.h"
#include "hcpf/core/error.h"
#include "hcpf/core/label_placement.h"

namespace hcpf::renderer {
namespace {

void Write16(const cv::Mat& mat, const std::string& path) {
  codecs::WritePngGray16(path, mat.cols, mat.rows, mat.ptr<uint16_t>(0));
}

}  // namespace

int64_t WriteDepthPng(const DepthImage& depth, const std::string& path, double unit_mm) {
  HCPF_CHECK(unit_mm > 0.0) << "depth unit " << unit_mm;
  cv::Mat mat(depth.height, depth.width, CV_16UC1);
  const double per_metre = 1000.0 / unit_mm;
  int64_t saturated = 0;
  for (int y = 0; y < depth.height; ++y) {
    for (int x = 0; x < depth.width; ++x) {
      const float d = depth.depth_m[static_cast<size_t>(y) * depth.width + x];
      const double units = std::isfinite(d) ? std::round(d * per_metre) : 0.0;
      saturated += units > 65535.0 ? 1 : 0;
      mat.at<uint16_t>(y, x) = static_cast<uint16_t>(std::clamp(units, 0.0, 65535.0));
    }
  }
  Write16(mat, path);
  return saturated;
}

void WriteInstancePng(const InstanceImage& ids, const std::string& path) {
  cv::Mat mat(ids.height, ids.width, CV_16UC1);
  for (int y = 0; y < ids.height; ++y) {
    for (int x = 0; x < ids.width; ++x) {
      const int32_t id = ids.ids[static_cast<size_t>(y) * ids.width + x];
      mat.at<uint16_t>(y, x) = static_cast<uint16_t>(std::clamp(id + 1, 0, 65535));
    }
  }
  Write16(mat, path);
}

namespace {

// The contact sheet's label fonts (FONT_HERSHEY_PLAIN scales).
constexpr double kLabelFont = 0.8;
constexpr double kFrameFont = 1.0;
// The black halo under a label: putText's thickness 3 reaches a pixel
// beyond the 1-pixel text on every side.
constexpr int kHalo = 1;

// The rectangle a label drawn by putText at origin (x, y) covers, halo
// included (the origin is the text's bottom-left, on its baseline).
PixelRect TextRect(const std::string& text, double font, int x, int y) {
  int baseline = 0;
  const cv::Size size = cv::getTextSize(text, cv::FONT_HERSHEY_PLAIN, font, 1, &baseline);
  return {x - kHalo, y - size.height - kHalo, size.width + 2 * kHalo,
          size.height + baseline + 2 * kHalo};
}

// The putText origin that puts a label's rectangle (TextRect) at `place`.
cv::Point TextOrigin(const std::string& text, double font, const PixelRect& place) {
  const PixelRect at_zero = TextRect(text, font, 0, 0);
  return {place.x - at_zero.x, place.y - at_zero.y};
}

}  // namespace

RgbImage MakeContactSheet(const std::vector<RenderedFrame>& frames,
                          const ContactSheetOptions& options) {
  HCPF_CHECK(options.columns >= 1 && options.thumb_width_px >= 16);
  RgbImage sheet;
  if (frames.empty()) return sheet;
  const int w = frames[0].rgb.width;
  const int h = frames[0].rgb.height;
  const int tw = options.thumb_width_px;
  const int th = std::max(1, static_cast<int>(std::lround(static_cast<double>(h) * tw / w)));
  const double scale = static_cast<double>(tw) / w;
  const int cols = std::min<int>(options.columns, static_cast<int>(frames.size()));
  const int rows = (static_cast<int>(frames.size()) + cols - 1) / cols;
  constexpr int kGap = 4;
  cv::Mat canvas(rows * (th + kGap) + kGap, cols * (tw + kGap) + kGap, CV_8UC3,
                 cv::Scalar(40, 40, 40));
  for (size_t i = 0; i < frames.size(); ++i) {
    const RenderedFrame& f = frames[i];
    HCPF_CHECK(f.rgb.width == w && f.rgb.height == h) << "frames of different sizes";
    const cv::Mat rgb(h, w, CV_8UC3, const_cast<uint8_t*>(f.rgb.pixels.data()));
    cv::Mat thumb;
    cv::resize(rgb, thumb, cv::Size(tw, th), 0, 0, cv::INTER_AREA);
    const auto to = [&](double v) { return static_cast<int>(std::lround(v * scale)); };
    // Each box and label is drawn over a black line three pixels wide (and
    // the labels over a black halo), so that a green visible box reads on
    // green grass and a white label on a bright road.
    const cv::Scalar kOutline(0, 0, 0);
    const auto box = [&](const BoxPx& b, const cv::Scalar& colour) {
      const cv::Point tl(to(b.left), to(b.top)), br(to(b.right()), to(b.bottom()));
      cv::rectangle(thumb, tl, br, kOutline, 3);
      cv::rectangle(thumb, tl, br, colour, 1);
    };
    const auto label = [&](const std::string& text, cv::Point at, double font_scale) {
      cv::putText(thumb, text, at, cv::FONT_HERSHEY_PLAIN, font_scale, kOutline, 3);
      cv::putText(thumb, text, at, cv::FONT_HERSHEY_PLAIN, font_scale, cv::Scalar(255, 255, 255),
                  1);
    };
    for (const GroundTruthObject& o : f.ground_truth.objects) {
      if (!o.in_frame) continue;
      box(o.amodal_box, cv::Scalar(255, 220, 0));
      if (!o.visible_box.empty()) box(o.visible_box, cv::Scalar(0, 255, 0));
    }
    // Labels after every box, so that no box's outline crosses a label, and
    // placed so that no two overlap (an audit: two targets side by side at
    // the end of a crossing had their labels printed over each other).
    const std::string frame_number = fmt::format("{}", f.frame + 1);
    std::vector<LabelRequest> requests;
    std::vector<std::string> texts;
    for (const GroundTruthObject& o : f.ground_truth.objects) {
      if (!o.in_frame) continue;
      const BoxPx& a = o.amodal_box;
      texts.push_back(fmt::format("{} {:.2f}", Value(o.id), o.visible_fraction));
      const PixelRect size = TextRect(texts.back(), kLabelFont, 0, 0);
      requests.push_back({.box = {to(a.left), to(a.top), to(a.right()) - to(a.left) + 1,
                                  to(a.bottom()) - to(a.top) + 1},
                          .text_width = size.width,
                          .text_height = size.height});
    }
    const std::vector<PixelRect> places =
        PlaceLabels(requests, {0, 0, tw, th}, {TextRect(frame_number, kFrameFont, 4, 14)});
    for (size_t k = 0; k < texts.size(); ++k) {
      label(texts[k], TextOrigin(texts[k], kLabelFont, places[k]), kLabelFont);
    }
    label(frame_number, cv::Point(4, 14), kFrameFont);
    const int r = static_cast<int>(i) / cols;
    const int c = static_cast<int>(i) % cols;
    thumb.copyTo(canvas(cv::Rect(kGap + c * (tw + kGap), kGap + r * (th + kGap), tw, th)));
  }
  sheet.width = canvas.cols;
  sheet.height = canvas.rows;
  sheet.pixels.assign(canvas.datastart, canvas.dataend);
  return sheet;
}

}  // namespace hcpf::renderer
