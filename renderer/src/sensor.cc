// Sensor effects on the 8-bit image (OpenCV, kept out of public headers).

#include <algorithm>
#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <span>

#include "codecs.h"
#include "hcpf/renderer/renderer.h"
#include "rounded_gaussian.h"

namespace hcpf::renderer {
namespace {

// Random words are drawn a block at a time into a buffer that stays in L1
// (two noise values per 64-bit word), turned into integer noise, then added.
constexpr size_t kNoiseBlock = 8192;
// The add-clamp loop runs over fixed chunks of this many values: GCC 12 at
// -O2 (the "very cheap" vectoriser cost model) vectorises only loops whose
// trip count is a compile-time constant.
constexpr size_t kChunk = 16;

inline uint8_t AddClamp(uint8_t p, int16_t k) {
  return static_cast<uint8_t>(std::clamp<int16_t>(static_cast<int16_t>(p + k), 0, 255));
}

// Independent N(0, sigma^2) noise on every byte (pixel and channel), in
// memory order, rounded to the nearest level and clamped to [0, 255]:
// p = clamp(p + K, 0, 255), where K = round(sigma z) is drawn directly from
// its exact distribution (rounded_gaussian.h), 32 bits of hcpf::Rng per
// value (the low half of each 64-bit word first): no normal variate and no
// floating point per value, and the same seed gives the same bytes on every
// platform. Two passes per block: the table lookups (scalar), then the
// add-clamp (vectorised).
void AddNoise(double sigma, Rng& rng, std::span<uint8_t> pixels) {
  const internal::RoundedGaussianTable table(sigma);
  std::array<uint64_t, kNoiseBlock / 2> words;
  std::array<int16_t, kNoiseBlock> noise;  // |K| <= 255
  for (size_t start = 0; start < pixels.size(); start += kNoiseBlock) {
    const size_t m = std::min(kNoiseBlock, pixels.size() - start);
    for (size_t i = 0; i < (m + 1) / 2; ++i) words[i] = rng.NextU64();
    size_t i = 0;
    for (; i + 1 < m; i += 2) {
      const uint64_t w = words[i / 2];
      noise[i] = static_cast<int16_t>(table.Sample(static_cast<uint32_t>(w)));
      noise[i + 1] = static_cast<int16_t>(table.Sample(static_cast<uint32_t>(w >> 32)));
    }
    if (i < m) noise[i] = static_cast<int16_t>(table.Sample(static_cast<uint32_t>(words[i / 2])));
    uint8_t* __restrict p = pixels.data() + start;
    const int16_t* __restrict k = noise.data();
    size_t c = 0;
    for (; c + kChunk <= m; c += kChunk) {
      for (size_t j = 0; j < kChunk; ++j) p[c + j] = AddClamp(p[c + j], k[c + j]);
    }
    for (; c < m; ++c) p[c] = AddClamp(p[c], k[c]);
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
