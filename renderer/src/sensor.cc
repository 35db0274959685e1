// Sensor effects on the 8-bit image (OpenCV, kept out of public headers).

#include <algorithm>
#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>
#include <span>

#include "codecs.h"
#include "hcpf/core/instruction_set.h"
#include "hcpf/core/rng.h"
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

constexpr size_t kNoiseLanes = 8;

// `n` words (a multiple of kNoiseLanes) of the lanes' states s0..s3, lane by
// lane, advancing them; built for AVX-512, AVX2 and the baseline, the CPU's
// widest run (hcpf/core/instruction_set.h), every build the same words.
HCPF_DISPATCHED(void, FillLanes,
                (uint64_t* __restrict s0, uint64_t* __restrict s1, uint64_t* __restrict s2,
                 uint64_t* __restrict s3, uint64_t* __restrict out, size_t n),
                (s0, s1, s2, s3, out, n), {
                  for (size_t k = 0; k < n; k += kNoiseLanes) {
                    for (size_t l = 0; l < kNoiseLanes; ++l)
                      out[k + l] = Xoshiro256StarStar(s0[l], s1[l], s2[l], s3[l]);
                  }
                })

// Eight xoshiro256** streams advanced in lockstep, lane l the stream
// Rng::Fork("noise/lane", l) of the frame's: no step depends on another
// lane's, so the step vectorises (fixed trip count; FillLanes). Word 8k + l
// of the output is lane l's k-th draw. One stream made the noise wait on its
// own serial dependency chain (~0.9 ns a word, 720,000 words a 800 x 600
// frame).
class NoiseWords {
 public:
  static constexpr size_t kLanes = kNoiseLanes;
  explicit NoiseWords(const Rng& rng) {
    for (size_t l = 0; l < kLanes; ++l) {
      const std::array<uint64_t, 4> s = rng.Fork("noise/lane", static_cast<int64_t>(l)).state();
      s0_[l] = s[0];
      s1_[l] = s[1];
      s2_[l] = s[2];
      s3_[l] = s[3];
    }
  }
  // `n` words, a multiple of kLanes.
  void Fill(uint64_t* out, size_t n) {
    FillLanes(s0_.data(), s1_.data(), s2_.data(), s3_.data(), out, n);
  }

 private:
  alignas(64) std::array<uint64_t, kLanes> s0_{}, s1_{}, s2_{}, s3_{};
};

inline uint8_t AddClamp(uint8_t p, int16_t k) {
  return static_cast<uint8_t>(std::clamp<int16_t>(static_cast<int16_t>(p + k), 0, 255));
}

// Independent N(0, sigma^2) noise on every byte (pixel and channel), in
// memory order, rounded to the nearest level and clamped to [0, 255]:
// p = clamp(p + K, 0, 255), where K = round(sigma z) is drawn directly from
// its exact distribution (rounded_gaussian.h), 32 bits of NoiseWords per
// value (the low half of each 64-bit word first): no normal variate and no
// floating point per value, and the same seed gives the same bytes on every
// platform. Three passes per block: the words, the table lookups (sixteen at
// a time where the table allows), the add-clamp (vectorised).
void AddNoise(double sigma, const Rng& rng, std::span<uint8_t> pixels) {
  const internal::RoundedGaussianTable table(sigma);
  NoiseWords draws(rng);
  alignas(64) std::array<uint64_t, kNoiseBlock / 2> words;
  alignas(64) std::array<int16_t, kNoiseBlock> noise;  // |K| <= 255
  for (size_t start = 0; start < pixels.size(); start += kNoiseBlock) {
    const size_t m = std::min(kNoiseBlock, pixels.size() - start);
    // Whole blocks of words even for the last, shorter block: a value's
    // words depend on its position only.
    draws.Fill(words.data(), words.size());
    table.SampleWords(words.data(), words.size(), noise.data());
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
