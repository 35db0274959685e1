// Sensor effects on the 8-bit image (OpenCV, kept out of public headers).

#include <algorithm>
#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <span>

#include "codecs.h"
#include "hcpf/core/error.h"
#include "hcpf/renderer/renderer.h"
#include "rounded_gaussian.h"

namespace hcpf::renderer {
namespace {

// Random words are drawn a block at a time into a buffer that stays in L1
// (two noise values per 64-bit word), then turned into noise.
constexpr size_t kNoiseBlock = 8192;

// Independent N(0, sigma^2) noise on every byte (pixel and channel), in
// memory order, rounded to the nearest level and clamped to [0, 255]:
// p = clamp(p + K, 0, 255), where K = round(sigma z) is drawn directly from
// its exact distribution (rounded_gaussian.h), 32 bits of hcpf::Rng per
// value: no normal variate and no floating point per value, and the same seed
// gives the same bytes on every platform.
void AddNoise(double sigma, Rng& rng, std::span<uint8_t> pixels) {
  const internal::RoundedGaussianTable table(sigma);
  std::array<uint64_t, kNoiseBlock / 2> words;
  for (size_t start = 0; start < pixels.size(); start += kNoiseBlock) {
    const size_t m = std::min(kNoiseBlock, pixels.size() - start);
    const size_t word_count = (m + 1) / 2;
    for (size_t i = 0; i < word_count; ++i) words[i] = rng.NextU64();
    uint8_t* p = pixels.data() + start;
    const auto add = [&](size_t i, uint32_t u) {
      p[i] = static_cast<uint8_t>(std::clamp(int32_t{p[i]} + table.Sample(u), 0, 255));
    };
    // The low half of word i / 2 for even i, the high half for odd i (an
    // odd last value leaves the high half unused).
    size_t i = 0;
    for (; i + 1 < m; i += 2) {
      const uint64_t w = words[i / 2];
      add(i, static_cast<uint32_t>(w));
      add(i + 1, static_cast<uint32_t>(w >> 32));
    }
    if (i < m) add(i, static_cast<uint32_t>(words[i / 2]));
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
