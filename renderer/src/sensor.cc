// Sensor effects on the 8-bit image (OpenCV, kept out of public headers).

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

#include "hcpf/core/error.h"
#include "hcpf/renderer/renderer.h"

namespace hcpf::renderer {

void ApplySensorEffects(const SensorOptions& options, Rng rng, RgbImage& image) {
  if (image.pixels.empty()) return;
  cv::Mat mat(image.height, image.width, CV_8UC3, image.pixels.data());
  if (options.exposure != 1.0) {
    mat.convertTo(mat, CV_8UC3, options.exposure);  // saturating, rounds to nearest
  }
  if (options.blur_px > 0.0) {
    cv::GaussianBlur(mat, mat, cv::Size(0, 0), options.blur_px, options.blur_px,
                     cv::BORDER_REFLECT_101);
  }
  if (options.noise_sigma > 0.0) {
    // Our own normals (hcpf::Rng), not cv::randn: the same seed gives the
    // same noise on every platform.
    for (uint8_t& v : image.pixels) {
      const double x = std::round(v + options.noise_sigma * rng.Normal());
      v = static_cast<uint8_t>(std::clamp(x, 0.0, 255.0));
    }
  }
  if (options.jpeg_quality > 0) {
    cv::Mat bgr;
    cv::cvtColor(mat, bgr, cv::COLOR_RGB2BGR);
    std::vector<uint8_t> encoded;
    cv::imencode(".jpg", bgr, encoded, {cv::IMWRITE_JPEG_QUALITY, options.jpeg_quality});
    const cv::Mat decoded = cv::imdecode(encoded, cv::IMREAD_COLOR);
    cv::cvtColor(decoded, mat, cv::COLOR_BGR2RGB);
  }
  // Every step above wrote into `mat`, which wraps image.pixels (same size
  // and type, so OpenCV never reallocated it).
  if (mat.data != image.pixels.data()) {
    std::copy(mat.datastart, mat.dataend, image.pixels.begin());
  }
}

void WritePng(const RgbImage& image, const std::string& path) {
  const cv::Mat rgb(image.height, image.width, CV_8UC3, const_cast<uint8_t*>(image.pixels.data()));
  cv::Mat bgr;
  cv::cvtColor(rgb, bgr, cv::COLOR_RGB2BGR);
  bool ok = false;
  try {
    ok = cv::imwrite(path, bgr);
  } catch (const cv::Exception& e) {
    throw RunError(std::string("cannot write PNG ") + path + ": " + e.what());
  }
  if (!ok) throw RunError("cannot write PNG " + path);
}

RgbImage ReadPng(const std::string& path) {
  const cv::Mat bgr = cv::imread(path, cv::IMREAD_COLOR);
  if (bgr.empty()) throw InputError(path + ": cannot read image");
  cv::Mat rgb;
  cv::cvtColor(bgr, rgb, cv::COLOR_BGR2RGB);
  RgbImage image;
  image.width = rgb.cols;
  image.height = rgb.rows;
  image.pixels.assign(rgb.datastart, rgb.dataend);
  return image;
}

}  // namespace hcpf::renderer
