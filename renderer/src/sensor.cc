// Sensor effects on the 8-bit image (OpenCV, kept out of public headers).

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include "codecs.h"
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
    codecs::JpegRoundTrip(image.width, image.height, options.jpeg_quality, mat.data);
  }
  // Every step above wrote into `mat`, which wraps image.pixels (same size
  // and type, so OpenCV never reallocated it).
  if (mat.data != image.pixels.data()) {
    std::copy(mat.datastart, mat.dataend, image.pixels.begin());
  }
}

void WritePng(const RgbImage& image, const std::string& path) {
  codecs::WritePngRgb8(path, image.width, image.height, image.pixels.data());
}

RgbImage ReadPng(const std::string& path) {
  RgbImage image;
  image.pixels = codecs::ReadPngRgb8(path, &image.width, &image.height);
  return image;
}

}  // namespace hcpf::renderer
