// Sensor effects on the 8-bit image (OpenCV, kept out of public headers).

#include <algorithm>
#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <span>

#include "codecs.h"
#include "hcpf/core/error.h"
#include "hcpf/core/normal.h"
#include "hcpf/renderer/renderer.h"

namespace hcpf::renderer {
namespace {

// Normals are drawn a block at a time into a buffer that stays in L1 (32 KiB
// of doubles), then added in AddRoundClamp's tight loop.
constexpr size_t kNoiseBlock = 4096;
// AddRoundClamp's inner loop runs over fixed chunks of this many values: GCC
// 12 at -O2 (the "very cheap" vectoriser cost model) vectorises only loops
// whose trip count is a compile-time constant.
constexpr size_t kChunk = 16;

// p = clamp(round(p + sigma * z), 0, 255), rounding half up. Clamping first
// makes the value non-negative, so truncation after adding 0.5 is rounding
// (no std::round / lrint call, and the conversion vectorises). The same rule
// as the old round-then-clamp (now on a float sum, whose error, ~1e-4 grey
// levels for sigma <= 100, matters only at exact half-levels): a sum in
// [-0.5, 0) rounded to -0 and was clamped to 0; one in [255, 255.5) to 255.
inline void AddRoundClampOne(float sigma, double z, uint8_t& p) {
  float x = static_cast<float>(p) + sigma * static_cast<float>(z);
  x = std::max(x, 0.0f);
  x = std::min(x, 255.0f);
  p = static_cast<uint8_t>(static_cast<int32_t>(x + 0.5f));
}

void AddRoundClamp(float sigma, const double* __restrict z, uint8_t* __restrict p, size_t n) {
  size_t i = 0;
  for (; i + kChunk <= n; i += kChunk) {
    for (size_t j = 0; j < kChunk; ++j) AddRoundClampOne(sigma, z[i + j], p[i + j]);
  }
  for (; i < n; ++i) AddRoundClampOne(sigma, z[i], p[i]);
}

// Independent N(0, sigma^2) noise on every byte (pixel and channel), in
// memory order, from the ziggurat generator (core/normal.h): no
// transcendental call for ~99 % of values (the rest take the ziggurat's exact
// rejection step, one exp), and the same seed gives the same bytes on every
// platform.
void AddNoise(double sigma, Rng& rng, std::span<uint8_t> pixels) {
  std::array<double, kNoiseBlock> normals;
  const auto sigma_f = static_cast<float>(sigma);
  for (size_t start = 0; start < pixels.size(); start += kNoiseBlock) {
    const size_t m = std::min(kNoiseBlock, pixels.size() - start);
    FillStandardNormal(rng, std::span<double>(normals.data(), m));
    AddRoundClamp(sigma_f, normals.data(), pixels.data() + start, m);
  }
}

}  // namespace

void ApplySensorEffects(const SensorOptions& options, Rng rng, RgbImage& image) {
  if (image.pixels.empty()) return;
  cv::Mat mat(image.height, image.width, CV_8UC3, image.pixels.data());
  if (options.exposure != 1.0) {
    mat.convertTo(mat, CV_8UC3, options.exposure);  // saturating, rounds to nearest
  }
  if (options.blur_px > 0.0) {
    // cv::GaussianBlur is separable and, for 8-bit images and small kernels,
    // fixed point: at sigma 0.7 on 800x600 it costs ~0.6 ms, not worth
    // replacing (docs/performance.md).
    cv::GaussianBlur(mat, mat, cv::Size(0, 0), options.blur_px, options.blur_px,
                     cv::BORDER_REFLECT_101);
  }
  if (options.noise_sigma > 0.0) {
    // `mat` still wraps image.pixels here (same size and type as before).
    AddNoise(options.noise_sigma, rng, std::span<uint8_t>(mat.data, image.pixels.size()));
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
