// Simple K Space (SksOptions in sks.h). docs/vision.md ("SKS detector") gives
// the algorithm as implemented and the reasons for its choices; the comments
// here say why the code is as it is.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <opencv2/imgproc.hpp>
#include <type_traits>
#include <utility>
#include <vector>

#include "cv_image.h"
#include "hcpf/core/check.h"
#include "hcpf/core/instruction_set.h"
#include "hcpf/vision/detector.h"
#include "hcpf/vision/sks.h"
#include "hcpf/vision/stacked_integral_blur.h"

namespace hcpf::vision {

std::span<const Field<SksOptions>> SksOptions::Fields() {
  using O = SksOptions;
  static const std::vector<Field<O>> fields = {
      NumberField("base_sigma", &O::base_sigma, Closed(1, 4), "px",
                  "smallest Harris integration scale"),
      NumberField("scale_step", &O::scale_step, Closed(1.1, 2), "",
                  "ratio of successive integration scales"),
      IntegerField("scales", &O::scales, 1, 12, "", "number of integration scales"),
      NumberField("derivative_ratio", &O::derivative_ratio, Closed(0.5, 1), "",
                  "derivative scale / integration scale"),
      NumberField("harris_alpha", &O::harris_alpha, Closed(0.01, 0.2), "",
                  "α of the Harris measure det(C) − α trace²(C)"),
      NumberField("harris_threshold", &O::harris_threshold, AboveUpTo(0, 1e9), "grey⁴",
                  "smallest Harris response of a keypoint (scale-normalised, grey levels 0–255)"),
      IntegerField("max_keypoints", &O::max_keypoints, 1, 100000, "",
                   "keypoints per frame, strongest Harris response first"),
      IntegerField("max_model_keypoints", &O::max_model_keypoints, 1, 100000, "",
                   "keypoints per target model, strongest Harris response first"),
      NumberField("orientation_peak_ratio", &O::orientation_peak_ratio, AboveUpTo(0, 1), "",
                  "a keypoint also takes every orientation peak ≥ ratio × the highest"),
      NumberField("descriptor_radius", &O::descriptor_radius, Closed(1, 8), "",
                  "descriptor disc radius in units of the keypoint's scale"),
      IntegerField("descriptor_bins", &O::descriptor_bins, 4, 36, "",
                   "gradient-orientation bins of each descriptor histogram"),
      IntegerField("descriptor_sectors", &O::descriptor_sectors, 1, 16, "",
                   "sectors of the descriptor's outer ring"),
      NumberField("match_distance", &O::match_distance, AboveUpTo(0, 1.5), "",
                  "largest descriptor distance (unit vectors) at which a keypoint votes"),
      NumberField("vote_sigma_px", &O::vote_sigma_px, Closed(0.5, 32), "px",
                  "Gaussian spread of one vote in the accumulator"),
      NumberField("rotation_tolerance_deg", &O::rotation_tolerance_deg, Closed(1, 180), "°",
                  "pose clustering: largest rotation difference between agreeing votes"),
      NumberField("scale_tolerance", &O::scale_tolerance, Closed(1.01, 4), "",
                  "pose clustering: largest scale-ratio factor between agreeing votes"),
      NumberField("min_votes", &O::min_votes, AboveUpTo(0, 1000), "",
                  "accumulator peak (votes weighted by match confidence) for a detection"),
      NumberField("min_score", &O::min_score, Closed(0, 1), "",
                  "peak / model keypoints needed for a detection (the detection's score)"),
      NumberField("window_scale", &O::window_scale, Closed(1, 20), "",
                  "windowed search: window side = scale × predicted box side"),
      NumberField("cell_px", &O::cell_px, Closed(1, 64), "px", "map cell size"),
  };
  return fields;
}

void SksOptions::Validate(std::string_view prefix) const { CheckFields(*this, Fields(), prefix); }

namespace {

using internal::AroundBox;
using internal::ClipToImage;
using internal::WindowOf;

constexpr double kPi = std::numbers::pi;
constexpr double kTwoPi = 2.0 * std::numbers::pi;
// An octave (a 2x decimation) is processed only while both its sides are at
// least this many pixels: below, the smallest integration window (radius
// 3 base_sigma >= 3 px) covers the whole image and every response is border.
constexpr int kMinOctaveSide = 8;
// Anti-aliasing blur before each 2x decimation, in the finer octave's pixels
// (about the width of OpenCV's pyrDown kernel); it leaves the coarser octave
// with an inherent blur of 0.5 of its pixels, which later smoothings and the
// Laplacian kernels account for.
constexpr double kAntiAliasSigma = 1.0;
// Orientation assignment as in SIFT (Lowe 2004, section 5): 36 bins, a
// Gaussian window of 1.5 x the keypoint's scale.
constexpr int kOrientationBins = 36;
constexpr double kOrientationWindow = 1.5;
// SIFT's illumination clip: descriptor entries above this (after L2
// normalisation) are cut and the vector renormalised (Lowe 2004, section 6.1).
constexpr float kDescriptorClip = 0.2f;
// Boxes per stacked-integral-image kernel: the blur's own default.
constexpr int kStackedBoxes = 4;
// Descriptors are padded to a multiple of this many floats so the distance
// loop runs in whole vector-register chunks.
constexpr int kDescriptorChunk = 8;
// Accumulator peaks whose votes are pose-clustered per model, highest first:
// a target's own peak is among the highest few, and each costs O(votes).
constexpr int kPeaksVerified = 5;
// Pairs of model keypoints closer than this (px) do not measure a cluster's
// scale: keypoint positions are good to about half a pixel, so a ratio of
// distances of at least this is good to about 10 %.
constexpr double kMinPairPx = 8.0;

// ---------------------------------------------------------------- smoothing

// One Gaussian smoothing: its standard deviation and the stacked-box kernel
// that stands for it (empty below sigma 0.5, where the smoothing is skipped:
// a sampled Gaussian that narrow is within a few per cent of a delta, and the
// stacked blur's kernel fit is not defined there).
struct Blur {
  double sigma = 0.0;
  StackedBoxKernel boxes;
};

Blur MakeBlur(double sigma) {
  Blur blur{.sigma = sigma};
  if (sigma >= 0.5) blur.boxes = MakeStackedBoxKernel(sigma, kStackedBoxes);
  return blur;
}

void ResizeLike(int width, int height, GreyImageF& image) {
  image.width = width;
  image.height = height;
  image.pixels.resize(static_cast<size_t>(width) * height);  // keeps its capacity
}

// THE Gaussian smoothing of this file: every smoothing of the detector goes
// through here. 8-bit images (the octave images) go through the stacked
// integral image blur; float images (the structure tensor's products of
// derivatives, whose range the 8-bit blur's input cannot hold) through an
// exact separable Gaussian with the same clamp-to-edge border and the same
// bytes on every machine (SeparableGaussianBlur: cv::GaussianBlur's float
// kernels differ with the CPU's vector extensions). `out` must not be `in`.
template <typename Image>
void Smooth(const Image& in, const Blur& blur, GreyImageF& out) {
  ResizeLike(in.width, in.height, out);
  if (blur.boxes.radii.empty()) {
    std::copy(in.pixels.begin(), in.pixels.end(), out.pixels.begin());
    return;
  }
  if constexpr (std::is_same_v<Image, GreyImage>) {
    StackedIntegralBlur(in, blur.boxes, out);
  } else {
    static_assert(std::is_same_v<Image, GreyImageF>);
    SeparableGaussianBlur(in, blur.sigma, out);
  }
}

// ---------------------------------------------------------------- scales

// The scale-normalised Laplacian sigma^2 (Lxx + Lyy) at one scale, as a
// sampled kernel applied at single points: only keypoint candidates need it,
// so smoothing the whole image at every scale would be wasted. (A point
// evaluation of a derivative filter, not a smoothing of the image.)
struct LaplacianKernel {
  int radius = 0;
  std::vector<float> taps;  // (2 radius + 1)^2, row-major, summing to 0
};

// The kernel for total scale `sigma` on an image already blurred by
// `inherent` (both in that image's pixels): the Laplacian of a Gaussian of
// sqrt(sigma^2 - inherent^2) (at least 0.5), times sigma^2 so that responses
// compare across scales (Lindeberg's normalisation).
LaplacianKernel MakeLaplacian(double sigma, double inherent) {
  const double s = std::sqrt(std::max(0.25, sigma * sigma - inherent * inherent));
  LaplacianKernel k;
  k.radius = static_cast<int>(std::ceil(3.0 * s));
  const int n = 2 * k.radius + 1;
  std::vector<double> taps(static_cast<size_t>(n) * n);
  double sum = 0.0;
  for (int dy = -k.radius; dy <= k.radius; ++dy) {
    for (int dx = -k.radius; dx <= k.radius; ++dx) {
      const double r2 = dx * dx + dy * dy;
      const double v = (r2 - 2.0 * s * s) / (s * s * s * s) * std::exp(-r2 / (2.0 * s * s)) /
                       (2.0 * kPi * s * s);
      taps[static_cast<size_t>(dy + k.radius) * n + dx + k.radius] = v;
      sum += v;
    }
  }
  // Zero sum (the truncated tails leave a small bias): a flat image then has
  // exactly zero Laplacian at every scale.
  const double bias = sum / static_cast<double>(taps.size());
  k.taps.resize(taps.size());
  for (size_t i = 0; i < taps.size(); ++i) {
    k.taps[i] = static_cast<float>(sigma * sigma * (taps[i] - bias));
  }
  return k;
}

// The absolute normalised Laplacian of `image` at pixel (x, y) (clamp-to-edge).
float LaplacianAt(const GreyImage& image, const LaplacianKernel& k, int x, int y) {
  const int n = 2 * k.radius + 1;
  const bool inside =
      x >= k.radius && y >= k.radius && x + k.radius < image.width && y + k.radius < image.height;
  float sum = 0.0f;
  for (int dy = -k.radius; dy <= k.radius; ++dy) {
    const float* taps = k.taps.data() + static_cast<size_t>(dy + k.radius) * n;
    if (inside) {
      const uint8_t* row = image.row(y + dy) + (x - k.radius);
      for (int i = 0; i < n; ++i) sum += taps[i] * row[i];
    } else {
      const uint8_t* row = image.row(std::clamp(y + dy, 0, image.height - 1));
      for (int i = 0; i < n; ++i) {
        sum += taps[i] * row[std::clamp(x - k.radius + i, 0, image.width - 1)];
      }
    }
  }
  return std::abs(sum);
}

// Everything about integration scale k that does not depend on the image.
struct Scale {
  int octave = 0;
  double sigma = 0.0;                        // integration scale, in the octave's pixels
  double derivative = 0.0;                   // derivative scale, in the octave's pixels
  Blur derivative_blur;                      // from the octave image to the derivative scale
  Blur integration_blur;                     // of the products of derivatives
  std::array<LaplacianKernel, 3> laplacian;  // at sigma / step, sigma, sigma * step
};

// The scale space of the options, built once per detector.
struct ScaleSpace {
  std::vector<Scale> scales;
  int octaves = 0;
  double step = 1.0;
  Blur anti_alias;
};

// The inherent blur of octave o's image, in its pixels: 0 for the frame (its
// own camera blur is not known), then each decimation's anti-aliasing carried
// down (variances add, then halve in pixels: quarter in variance).
double InherentBlur(int octave) {
  double variance = 0.0;
  for (int o = 1; o <= octave; ++o) {
    variance = (variance + kAntiAliasSigma * kAntiAliasSigma) / 4.0;
  }
  return std::sqrt(variance);
}

ScaleSpace MakeScaleSpace(const SksOptions& options) {
  ScaleSpace space;
  space.step = options.scale_step;
  space.anti_alias = MakeBlur(kAntiAliasSigma);
  for (int k = 0; k < options.scales; ++k) {
    const double ratio = std::pow(options.scale_step, k);
    // The octave in whose pixels the scale falls in [base, 2 base): 2^o <=
    // ratio (the tolerance keeps sqrt(2)^2 in the next octave).
    const int octave = static_cast<int>(std::floor(std::log2(ratio) + 1e-6));
    Scale s;
    s.octave = octave;
    s.sigma = options.base_sigma * ratio / std::ldexp(1.0, octave);
    s.derivative = options.derivative_ratio * s.sigma;
    const double inherent = InherentBlur(octave);
    s.derivative_blur =
        MakeBlur(std::sqrt(std::max(0.0, s.derivative * s.derivative - inherent * inherent)));
    s.integration_blur = MakeBlur(s.sigma);
    s.laplacian = {MakeLaplacian(s.sigma / options.scale_step, inherent),
                   MakeLaplacian(s.sigma, inherent),
                   MakeLaplacian(s.sigma * options.scale_step, inherent)};
    space.octaves = std::max(space.octaves, octave + 1);
    space.scales.push_back(std::move(s));
  }
  return space;
}

// ---------------------------------------------------------------- keypoints

// The features of one image: one per keypoint and dominant orientation.
// Positions are in continuous pixel coordinates (pixel (i, j) covers
// [i, i + 1) x [j, j + 1)) of the frame (or patch) they were found in.
struct Features {
  int dims = 0;                           // descriptor length, padded to kDescriptorChunk
  int points = 0;                         // keypoints (a keypoint may have several features)
  std::vector<int> point;                 // the keypoint of each feature, 0 .. points - 1
  std::vector<float> x, y, scale, angle;  // scale: integration scale in px; angle in rad
  std::vector<float> descriptors;         // size() x dims, row-major, unit length
  size_t size() const { return x.size(); }
};

// A Harris local maximum at one scale.
struct Candidate {
  float response = 0.0f;
  int scale = 0;               // index into ScaleSpace::scales
  int ix = 0, iy = 0;          // pixel in the octave's image
  float fx = 0.0f, fy = 0.0f;  // sub-pixel position in the octave's pixels
  float sigma = 0.0f;          // characteristic scale in the octave's pixels (once selected)
  int first = 0, count = 0;    // its features (once described)
};

// Strongest first; ties by scale, row, column (a total order, so the result
// does not depend on the sort's algorithm).
bool Stronger(const Candidate& a, const Candidate& b) {
  if (a.response != b.response) return a.response > b.response;
  if (a.scale != b.scale) return a.scale < b.scale;
  if (a.iy != b.iy) return a.iy < b.iy;
  return a.ix < b.ix;
}

// The offset of a parabola's vertex through (-1, l), (0, c), (1, r), within
// [-0.5, 0.5] (0 when the three do not bend downwards).
float Vertex(float l, float c, float r) {
  const float curvature = l - 2.0f * c + r;
  if (!(curvature < 0.0f)) return 0.0f;
  return std::clamp(0.5f * (l - r) / curvature, -0.5f, 0.5f);
}

// atan2(y, x) in [0, 2 pi), to 1e-5 rad: atan on [0, 1] by Abramowitz &
// Stegun's polynomial 4.4.49 (|error| <= 1e-5), folded into the octants. The
// finest bins it feeds are 2 pi / 36 wide, and it is several times faster
// than std::atan2 on the descriptor's hot path.
float Angle(float y, float x) {
  const float ax = std::abs(x), ay = std::abs(y);
  const float big = std::max(ax, ay);
  if (big == 0.0f) return 0.0f;
  const float t = std::min(ax, ay) / big;
  const float t2 = t * t;
  float a = t * (0.9998660f +
                 t2 * (-0.3302995f + t2 * (0.1801410f + t2 * (-0.0851330f + t2 * 0.0208351f))));
  if (ay > ax) a = static_cast<float>(kPi / 2) - a;
  if (x < 0.0f) a = static_cast<float>(kPi) - a;
  if (y < 0.0f) a = static_cast<float>(kTwoPi) - a;
  return a >= static_cast<float>(kTwoPi) ? 0.0f : a;
}

// Scratch images of one extraction, sized for its largest octave and reused
// by every scale (fresh memory is expensive: it is touched page by page).
// `smooth` holds the current scale's derivative-smoothed image until its
// keypoints are described.
struct Workspace {
  GreyImageF smooth, xx, xy, yy, spare;
};

// The per-pixel loops of the Harris response (and, below, LocalMaxima's
// scan, NextChunkAbove), built for AVX-512, AVX2
// and the x86-64 baseline (HCPF_DISPATCHED, hcpf/core/instruction_set.h) and
// written in chunks of a fixed count, which GCC 12's -O2 vectorises (its
// "very cheap" cost model takes no loop with a run-time trip count). Each
// value is the same IEEE expression in every build (no FMA:
// -ffp-contract=off), so every build gives the same bytes
// (SksDetector.EveryInstructionSetGivesTheSameOutput). Before, as plain
// scalar loops, they were about half of the keypoint extraction's time
// (docs/performance.md).
constexpr size_t kHarrisChunk = 16;

// For x in [1, n - 1): a = half (row[x + 1] - row[x - 1]),
// b = half (down[x] - up[x]); xx = a^2, xy = a b, yy = b^2.
HCPF_DISPATCHED(void, InteriorProducts,
                (const float* __restrict row, const float* __restrict up,
                 const float* __restrict down, float half, float* __restrict xx,
                 float* __restrict xy, float* __restrict yy, size_t n),
                (row, up, down, half, xx, xy, yy, n), {
                  auto at = [&](size_t x) {
                    const float a = half * (row[x + 1] - row[x - 1]);
                    const float b = half * (down[x] - up[x]);
                    xx[x] = a * a;
                    xy[x] = a * b;
                    yy[x] = b * b;
                  };
                  size_t x = 1;
                  for (; x + kHarrisChunk < n; x += kHarrisChunk) {
                    for (size_t j = 0; j < kHarrisChunk; ++j) at(x + j);
                  }
                  for (; x + 1 < n; ++x) at(x);
                })

// out[i] = p[i] q[i] - r[i]^2 - a (p[i] + q[i])^2: det(C) - a trace^2(C)
// with C = [p, r; r, q].
HCPF_DISPATCHED(void, HarrisOfTensor,
                (const float* __restrict p, const float* __restrict q, const float* __restrict r,
                 float a, float* __restrict out, size_t n),
                (p, q, r, a, out, n), {
                  auto at = [&](size_t i) {
                    const float trace = p[i] + q[i];
                    out[i] = p[i] * q[i] - r[i] * r[i] - a * trace * trace;
                  };
                  size_t i = 0;
                  for (; i + kHarrisChunk <= n; i += kHarrisChunk) {
                    for (size_t j = 0; j < kHarrisChunk; ++j) at(i + j);
                  }
                  for (; i < n; ++i) at(i);
                })

// The Harris responses det(C) - alpha trace^2(C) of one scale into
// `ws.spare`, with C = sigma_D^2 G(sigma_I) * [Lx^2, LxLy; LxLy, Ly^2]
// (Mikolajczyk & Schmid 2004, eq. 2).
void HarrisResponse(const GreyImage& image, const Scale& s, double alpha, Workspace& ws) {
  Smooth(image, s.derivative_blur, ws.smooth);
  const int w = image.width, h = image.height;
  ResizeLike(w, h, ws.xx);
  ResizeLike(w, h, ws.xy);
  ResizeLike(w, h, ws.yy);
  // Central differences (one-sided at the clamp-to-edge border), times the
  // derivative scale: sigma_D L_x is the same for a feature at any scale.
  const float half = static_cast<float>(0.5 * s.derivative);
  for (int y = 0; y < h; ++y) {
    const float* row = ws.smooth.row(y);
    const float* up = ws.smooth.row(std::max(0, y - 1));
    const float* down = ws.smooth.row(std::min(h - 1, y + 1));
    float* pxx = ws.xx.row(y);
    float* pxy = ws.xy.row(y);
    float* pyy = ws.yy.row(y);
    auto store = [&](int x, float a) {
      const float b = half * (down[x] - up[x]);
      pxx[x] = a * a;
      pxy[x] = a * b;
      pyy[x] = b * b;
    };
    store(0, half * (row[std::min(w - 1, 1)] - row[0]));
    InteriorProducts(row, up, down, half, pxx, pxy, pyy, static_cast<size_t>(w));
    if (w > 1) store(w - 1, half * (row[w - 1] - row[w - 2]));
  }
  for (GreyImageF* product : {&ws.xx, &ws.xy, &ws.yy}) {
    Smooth(*product, s.integration_blur, ws.spare);
    std::swap(*product, ws.spare);
  }
  ResizeLike(w, h, ws.spare);
  const float a = static_cast<float>(alpha);
  HarrisOfTensor(ws.xx.pixels.data(), ws.yy.pixels.data(), ws.xy.pixels.data(), a,
                 ws.spare.pixels.data(), ws.spare.pixels.size());
}

// The start of the first whole chunk of row[from, n) (from a multiple of
// kHarrisChunk) holding a value above `threshold`, or where the whole chunks
// end (the last n % kHarrisChunk values are not looked at). Most of a
// response is below the threshold: LocalMaxima skips it a chunk at a time.
HCPF_DISPATCHED(size_t, NextChunkAbove,
                (const float* __restrict row, float threshold, size_t from, size_t n),
                (row, threshold, from, n), {
                  size_t c = from;
                  for (; c + kHarrisChunk <= n; c += kHarrisChunk) {
                    int above = 0;
                    for (size_t j = 0; j < kHarrisChunk; ++j) above |= row[c + j] > threshold;
                    if (above != 0) break;
                  }
                  return c;
                })

// 3 x 3 local maxima of `response` above `threshold` (a pixel must beat its
// earlier neighbours strictly and equal or beat its later ones, so a plateau
// yields exactly one), with sub-pixel positions.
void LocalMaxima(const GreyImageF& response, float threshold, int scale,
                 std::vector<Candidate>& out) {
  const int w = response.width, h = response.height;
  for (int y = 0; y < h; ++y) {
    const float* row = response.row(y);
    const float* up = y > 0 ? response.row(y - 1) : nullptr;
    const float* down = y + 1 < h ? response.row(y + 1) : nullptr;
    for (int x = 0; x < w; ++x) {
      if (x % kHarrisChunk == 0) {
        // Every value of the chunks skipped is at or below the threshold.
        x = static_cast<int>(NextChunkAbove(row, threshold, x, w));
        if (x >= w) break;
      }
      const float v = row[x];
      if (!(v > threshold)) continue;
      bool peak = true;
      for (int dx = -1; dx <= 1 && peak; ++dx) {
        const int nx = x + dx;
        if (nx < 0 || nx >= w) continue;
        if (up != nullptr && !(v > up[nx])) peak = false;
        if (down != nullptr && !(v >= down[nx])) peak = false;
        if (dx == -1 && !(v > row[nx])) peak = false;
        if (dx == 1 && !(v >= row[nx])) peak = false;
      }
      if (!peak) continue;
      Candidate c{.response = v, .scale = scale, .ix = x, .iy = y};
      c.fx = static_cast<float>(x);
      c.fy = static_cast<float>(y);
      if (x > 0 && x + 1 < w) c.fx += Vertex(row[x - 1], v, row[x + 1]);
      if (up != nullptr && down != nullptr) c.fy += Vertex(up[x], v, down[x]);
      out.push_back(c);
    }
  }
}

// Every other pixel of `smooth`, rounded to 8 bits, into `out`: pixel (i, j)
// of the result is pixel (2i, 2j), so the centre of pixel i lies at 2i + 0.5 in the
// finer octave's continuous coordinates.
void Decimate(const GreyImageF& smooth, GreyImage& out) {
  out.width = (smooth.width + 1) / 2;
  out.height = (smooth.height + 1) / 2;
  out.pixels.resize(static_cast<size_t>(out.width) * out.height);  // keeps its capacity
  for (int y = 0; y < out.height; ++y) {
    const float* in = smooth.row(2 * y);
    uint8_t* row = out.row(y);
    for (int x = 0; x < out.width; ++x) {
      row[x] = static_cast<uint8_t>(std::clamp(in[2 * x] + 0.5f, 0.0f, 255.0f));
    }
  }
}

class FeatureExtractor {
 public:
  FeatureExtractor(const SksOptions& options, const ScaleSpace& space)
      : options_(options), space_(space) {
    const int raw = options.descriptor_bins * (1 + options.descriptor_sectors);
    dims_ = (raw + kDescriptorChunk - 1) / kDescriptorChunk * kDescriptorChunk;
  }

  // The features of the strongest `max_keypoints` Harris-Laplace keypoints of
  // `grey`, positions shifted by (x0, y0).
  Features Extract(const GreyImage& grey, int max_keypoints, double x0, double y0) const;

 private:
  struct Sample {
    float r2, magnitude, orientation, position;
  };
  // Appends the features (one per dominant orientation) of keypoint `c`,
  // whose scale's derivative-smoothed image is `smooth`.
  void Describe(const Candidate& c, const GreyImageF& smooth, int point, double x0, double y0,
                std::vector<Sample>& samples, Features& out) const;

  const SksOptions& options_;
  const ScaleSpace& space_;
  int dims_ = 0;
};

Features FeatureExtractor::Extract(const GreyImage& grey, int max_keypoints, double x0,
                                   double y0) const {
  Features out;
  out.dims = dims_;
  if (grey.width < kMinOctaveSide || grey.height < kMinOctaveSide) return out;
  // Scratch, per thread and kept between calls (Detect is const and may run
  // on several threads at once; Extract never runs inside itself): images of
  // a frame's size are hundreds of kilobytes, and fresh memory is touched
  // page by page (docs/vision.md, "Speed"). Every buffer is resized (or
  // cleared) before use, so nothing carries over from an earlier call.
  thread_local Workspace ws;
  thread_local std::vector<GreyImage> decimated;  // octaves 1, 2, ...
  thread_local Features all;
  thread_local std::vector<Candidate> keypoints;
  thread_local std::vector<Candidate> candidates;
  thread_local std::vector<Sample> samples;
  // The octave images: the image, then 2x decimations while large enough.
  std::vector<const GreyImage*> octaves = {&grey};
  if (decimated.size() < static_cast<size_t>(space_.octaves)) decimated.resize(space_.octaves);
  while (static_cast<int>(octaves.size()) < space_.octaves) {
    const GreyImage& finer = *octaves.back();
    if ((finer.width + 1) / 2 < kMinOctaveSide || (finer.height + 1) / 2 < kMinOctaveSide) break;
    Smooth(finer, space_.anti_alias, ws.spare);
    GreyImage& coarser = decimated[octaves.size() - 1];
    Decimate(ws.spare, coarser);
    octaves.push_back(&coarser);
  }

  // Scale by scale: Harris maxima, the Laplacian's scale selection, then the
  // descriptors of the keypoints kept, while that scale's derivative-smoothed
  // image is at hand. Harris-Laplace (Mikolajczyk & Schmid 2004, sec. 3.1):
  // a candidate is a keypoint where the normalised Laplacian peaks over the
  // neighbouring scales: above both neighbours inside the scale range; at the
  // range's ends, above the one neighbour there is (sharp corners peak below
  // any scale in range, and would otherwise all be lost).
  all.dims = dims_;
  all.points = 0;
  for (auto* v : {&all.x, &all.y, &all.scale, &all.angle, &all.descriptors}) v->clear();
  all.point.clear();
  keypoints.clear();
  const auto threshold = static_cast<float>(options_.harris_threshold);
  const int last = static_cast<int>(space_.scales.size()) - 1;
  for (int k = 0; k <= last; ++k) {
    const Scale& s = space_.scales[k];
    if (s.octave >= static_cast<int>(octaves.size())) continue;
    const GreyImage& image = *octaves[s.octave];
    HarrisResponse(image, s, options_.harris_alpha, ws);
    candidates.clear();
    LocalMaxima(ws.spare, threshold, k, candidates);
    for (Candidate& c : candidates) {
      const float at = LaplacianAt(image, s.laplacian[1], c.ix, c.iy);
      const float below = k == 0 ? 0.0f : LaplacianAt(image, s.laplacian[0], c.ix, c.iy);
      const float above = k == last ? 0.0f : LaplacianAt(image, s.laplacian[2], c.ix, c.iy);
      if (!(at > below && at > above)) continue;
      // Inside the range, the characteristic scale between the sampled ones:
      // the parabola's vertex over log(scale).
      const double offset = k == 0 || k == last ? 0.0 : Vertex(below, at, above);
      c.sigma = static_cast<float>(s.sigma * std::pow(space_.step, offset));
      c.first = static_cast<int>(all.size());
      Describe(c, ws.smooth, static_cast<int>(keypoints.size()), x0, y0, samples, all);
      c.count = static_cast<int>(all.size()) - c.first;
      if (c.count > 0) keypoints.push_back(c);
    }
  }

  // The strongest max_keypoints keypoints, their features in that order.
  std::sort(keypoints.begin(), keypoints.end(), Stronger);
  if (static_cast<int>(keypoints.size()) > max_keypoints) keypoints.resize(max_keypoints);
  for (const Candidate& c : keypoints) {
    for (int f = c.first; f < c.first + c.count; ++f) {
      out.point.push_back(out.points);
      out.x.push_back(all.x[f]);
      out.y.push_back(all.y[f]);
      out.scale.push_back(all.scale[f]);
      out.angle.push_back(all.angle[f]);
      const float* d = all.descriptors.data() + static_cast<size_t>(f) * dims_;
      out.descriptors.insert(out.descriptors.end(), d, d + dims_);
    }
    ++out.points;
  }
  return out;
}

void FeatureExtractor::Describe(const Candidate& c, const GreyImageF& smooth, int point, double x0,
                                double y0, std::vector<Sample>& samples, Features& out) const {
  const int w = smooth.width, h = smooth.height;
  const float sigma = c.sigma;
  const float radius = static_cast<float>(options_.descriptor_radius) * sigma;
  const float radius2 = radius * radius;
  const int reach = static_cast<int>(std::ceil(radius));
  // Gradients (central differences of the derivative-smoothed image) in the
  // disc, as magnitude, orientation and the sample's direction from the
  // keypoint. Pixels outside the image are not sampled.
  samples.clear();
  for (int y = std::max(0, c.iy - reach); y <= std::min(h - 1, c.iy + reach); ++y) {
    const float dy = static_cast<float>(y) - c.fy;
    const float* row = smooth.row(y);
    const float* up = smooth.row(std::max(0, y - 1));
    const float* down = smooth.row(std::min(h - 1, y + 1));
    for (int x = std::max(0, c.ix - reach); x <= std::min(w - 1, c.ix + reach); ++x) {
      const float dx = static_cast<float>(x) - c.fx;
      const float r2 = dx * dx + dy * dy;
      if (r2 > radius2) continue;
      const float gx = row[std::min(w - 1, x + 1)] - row[std::max(0, x - 1)];
      const float gy = down[x] - up[x];
      const float m = std::sqrt(gx * gx + gy * gy);
      if (!(m > 0.0f)) continue;
      samples.push_back({r2, m, Angle(gy, gx), Angle(dy, dx)});
    }
  }
  if (samples.empty()) return;

  // Dominant orientations (SIFT): a Gaussian-weighted, magnitude-weighted
  // histogram, smoothed twice with [1 2 1] / 4, every peak at least
  // orientation_peak_ratio x the highest, refined by a parabola.
  std::array<float, kOrientationBins> hist{};
  const float window = static_cast<float>(kOrientationWindow) * sigma;
  const float inv_window = -0.5f / (window * window);
  const float to_bin = kOrientationBins / static_cast<float>(kTwoPi);
  for (const Sample& p : samples) {
    const float b = p.orientation * to_bin - 0.5f;  // bin i is centred on (i + 0.5) / to_bin
    const float f = b - std::floor(b);
    const int i0 = (static_cast<int>(std::floor(b)) + kOrientationBins) % kOrientationBins;
    const float v = p.magnitude * std::exp(p.r2 * inv_window);
    hist[i0] += (1.0f - f) * v;
    hist[(i0 + 1) % kOrientationBins] += f * v;
  }
  for (int pass = 0; pass < 2; ++pass) {
    std::array<float, kOrientationBins> smoothed{};
    for (int i = 0; i < kOrientationBins; ++i) {
      smoothed[i] = 0.25f * hist[(i + kOrientationBins - 1) % kOrientationBins] + 0.5f * hist[i] +
                    0.25f * hist[(i + 1) % kOrientationBins];
    }
    hist = smoothed;
  }
  const float highest = *std::max_element(hist.begin(), hist.end());
  if (!(highest > 0.0f)) return;

  const double octave_px = std::ldexp(1.0, space_.scales[c.scale].octave);
  const int bins = options_.descriptor_bins;
  const int sectors = options_.descriptor_sectors;
  const float to_orientation_bin = bins / static_cast<float>(kTwoPi);
  const float to_sector = sectors / static_cast<float>(kTwoPi);
  const float inner2 = 0.25f * radius2;                // inner disc: radius / 2
  const float inv_weight = -0.5f / (0.25f * radius2);  // Gaussian of sigma radius / 2
  const auto peak_floor = static_cast<float>(options_.orientation_peak_ratio) * highest;
  for (int i = 0; i < kOrientationBins; ++i) {
    const float left = hist[(i + kOrientationBins - 1) % kOrientationBins];
    const float right = hist[(i + 1) % kOrientationBins];
    const float v = hist[i];
    if (!(v > left && v >= right && v >= peak_floor)) continue;
    float theta = (static_cast<float>(i) + 0.5f + Vertex(left, v, right)) / to_bin;
    theta = std::fmod(theta + static_cast<float>(kTwoPi), static_cast<float>(kTwoPi));

    // The descriptor, relative to theta: an orientation histogram of the
    // inner disc, then one per sector of the outer ring, sectors counted from
    // theta; bilinear in orientation and sector, Gaussian-weighted.
    const size_t base = out.descriptors.size();
    out.descriptors.resize(base + dims_, 0.0f);
    float* d = out.descriptors.data() + base;
    for (const Sample& p : samples) {
      float o = p.orientation - theta;
      if (o < 0.0f) o += static_cast<float>(kTwoPi);
      const float ob = o * to_orientation_bin;
      const int o0 = std::min(bins - 1, static_cast<int>(ob));
      const float fo = ob - static_cast<float>(o0);
      const int o1 = (o0 + 1) % bins;
      const float weight = p.magnitude * std::exp(p.r2 * inv_weight);
      if (p.r2 < inner2) {
        d[o0] += (1.0f - fo) * weight;
        d[o1] += fo * weight;
        continue;
      }
      float q = p.position - theta;
      if (q < 0.0f) q += static_cast<float>(kTwoPi);
      const float sb = q * to_sector - 0.5f;  // sector j is centred on (j + 0.5) / to_sector
      const float fs = sb - std::floor(sb);
      const int s0 = (static_cast<int>(std::floor(sb)) + sectors) % sectors;
      float* h0 = d + bins * (1 + s0);
      float* h1 = d + bins * (1 + (s0 + 1) % sectors);
      h0[o0] += (1.0f - fs) * (1.0f - fo) * weight;
      h0[o1] += (1.0f - fs) * fo * weight;
      h1[o0] += fs * (1.0f - fo) * weight;
      h1[o1] += fs * fo * weight;
    }
    // Unit length, entries clipped at kDescriptorClip, unit length again
    // (every sample has a positive magnitude and weight, so the norm is > 0;
    // the check only guards against underflow).
    bool described = true;
    for (int pass = 0; pass < 2 && described; ++pass) {
      float norm = 0.0f;
      for (int j = 0; j < dims_; ++j) norm += d[j] * d[j];
      norm = std::sqrt(norm);
      described = norm > 0.0f;
      for (int j = 0; j < dims_ && described; ++j) {
        d[j] /= norm;
        if (pass == 0) d[j] = std::min(d[j], kDescriptorClip);
      }
    }
    if (!described) {
      out.descriptors.resize(base);
      continue;
    }
    out.point.push_back(point);
    out.x.push_back(static_cast<float>(x0 + octave_px * c.fx + 0.5));
    out.y.push_back(static_cast<float>(y0 + octave_px * c.fy + 0.5));
    out.scale.push_back(static_cast<float>(octave_px * sigma));
    out.angle.push_back(theta);
  }
}

// The features of the strongest `max_points` keypoints of `all` that lie on
// a w x h patch at the origin: within their own scale of it (a keypoint's
// position is good to about its scale, and the outline's corners, the
// strongest keypoints of a vehicle, sit on the patch's edge).
Features KeypointsOnPatch(const Features& all, double w, double h, int max_points) {
  Features out;
  out.dims = all.dims;
  int last = -1;
  for (size_t f = 0; f < all.size(); ++f) {
    const double s = all.scale[f];
    if (!(all.x[f] >= -s && all.x[f] < w + s && all.y[f] >= -s && all.y[f] < h + s)) continue;
    if (all.point[f] != last) {
      if (out.points == max_points) break;
      last = all.point[f];
      ++out.points;
    }
    out.point.push_back(out.points - 1);
    out.x.push_back(all.x[f]);
    out.y.push_back(all.y[f]);
    out.scale.push_back(all.scale[f]);
    out.angle.push_back(all.angle[f]);
    const float* d = all.descriptors.data() + f * static_cast<size_t>(all.dims);
    out.descriptors.insert(out.descriptors.end(), d, d + all.dims);
  }
  return out;
}

// ---------------------------------------------------------------- voting

// The squared distance of two descriptors of `dims` floats (a multiple of
// kDescriptorChunk), accumulated in kDescriptorChunk independent lanes so the
// compiler can keep them in one vector register.
float Distance2(const float* a, const float* b, int dims) {
  std::array<float, kDescriptorChunk> lanes{};
  for (int j = 0; j < dims; j += kDescriptorChunk) {
    for (int l = 0; l < kDescriptorChunk; ++l) {
      const float e = a[j + l] - b[j + l];
      lanes[l] += e * e;
    }
  }
  float sum = 0.0f;
  for (float v : lanes) sum += v;
  return sum;
}

// One frame feature's vote for where a model's reference point is.
struct Vote {
  int frame_point = 0;         // the frame keypoint that cast it
  int model_point = 0;         // the model keypoint it matched
  float x = 0.0f, y = 0.0f;    // the reference point, frame px
  float fx = 0.0f, fy = 0.0f;  // the frame keypoint, frame px
  float mx = 0.0f, my = 0.0f;  // the model keypoint, patch px
  float weight = 0.0f;         // psi in (0, 1]
  float scale = 1.0f;          // frame keypoint scale / model keypoint scale
  float log_scale = 0.0f;      // log(scale)
  float rotation = 0.0f;       // frame keypoint orientation - model keypoint orientation (rad)
};

// A target model's features and its patch size (its reference point is the
// patch centre).
struct Model {
  Features features;
  double width = 0.0, height = 0.0;
};

// A rectangle of the frame in continuous pixel coordinates.
struct Region {
  double left = 0.0, top = 0.0, right = 0.0, bottom = 0.0;
  bool Contains(double x, double y) const {
    return x >= left && x < right && y >= top && y < bottom;
  }
};

// Every frame feature inside `region` votes through every model feature
// within `match_distance` of its descriptor (psi = 1 - distance /
// match_distance): the thesis's psi_m(r, theta) looked up for every model
// entry the descriptor matches, so that repeated structure (alike corners)
// votes for all its places and the true one collects the coincidences. A
// vote = frame point + (frame scale / model scale) x the model point's offset
// to the reference point rotated by the orientation difference; votes outside
// `region` are dropped.
std::vector<Vote> CastVotes(const Features& frame, const Model& model, const Region& region,
                            double match_distance) {
  std::vector<Vote> votes;
  const Features& m = model.features;
  const auto limit2 = static_cast<float>(match_distance * match_distance);
  const double cx = 0.5 * model.width, cy = 0.5 * model.height;
  for (size_t i = 0; i < frame.size(); ++i) {
    if (!region.Contains(frame.x[i], frame.y[i])) continue;
    const float* d = frame.descriptors.data() + i * frame.dims;
    for (size_t j = 0; j < m.size(); ++j) {
      const float e = Distance2(d, m.descriptors.data() + j * m.dims, m.dims);
      if (!(e < limit2)) continue;
      const double rho = frame.scale[i] / m.scale[j];
      const double rotation = frame.angle[i] - m.angle[j];
      const double c = std::cos(rotation), s = std::sin(rotation);
      const double ox = cx - m.x[j], oy = cy - m.y[j];
      const double vx = frame.x[i] + rho * (c * ox - s * oy);
      const double vy = frame.y[i] + rho * (s * ox + c * oy);
      if (!region.Contains(vx, vy)) continue;
      votes.push_back({.frame_point = frame.point[i],
                       .model_point = m.point[j],
                       .x = static_cast<float>(vx),
                       .y = static_cast<float>(vy),
                       .fx = frame.x[i],
                       .fy = frame.y[i],
                       .mx = m.x[j],
                       .my = m.y[j],
                       .weight = static_cast<float>(1.0 - std::sqrt(e) / match_distance),
                       .scale = static_cast<float>(rho),
                       .log_scale = static_cast<float>(std::log(rho)),
                       .rotation = static_cast<float>(rotation)});
    }
  }
  return votes;
}

// Each vote spread as a Gaussian of `sigma_px` (truncated at 2 sigma) over
// the cells of `map`: a cell's value is the psi-weighted count of votes near
// its centre.
void Accumulate(std::span<const Vote> votes, double sigma_px, LikelihoodMap& map) {
  const double reach = 2.0 * sigma_px;
  const double inv = -0.5 / (sigma_px * sigma_px);
  for (const Vote& v : votes) {
    const int cx0 = std::max(0, static_cast<int>(std::floor((v.x - reach) / map.cell_px)));
    const int cx1 =
        std::min(map.width - 1, static_cast<int>(std::floor((v.x + reach) / map.cell_px)));
    const int cy0 = std::max(0, static_cast<int>(std::floor((v.y - reach) / map.cell_px)));
    const int cy1 =
        std::min(map.height - 1, static_cast<int>(std::floor((v.y + reach) / map.cell_px)));
    for (int cy = cy0; cy <= cy1; ++cy) {
      const double ey = (cy + 0.5) * map.cell_px - v.y;
      for (int cx = cx0; cx <= cx1; ++cx) {
        const double ex = (cx + 0.5) * map.cell_px - v.x;
        const double e2 = ex * ex + ey * ey;
        if (e2 > reach * reach) continue;
        map.values[static_cast<size_t>(cy) * map.width + cx] +=
            static_cast<float>(v.weight * std::exp(e2 * inv));
      }
    }
  }
}

// The accumulator's local maxima (a cell >= its 8 neighbours, earlier ones
// strictly) of at least `floor`, highest first (ties in raster order), at
// most `count`.
std::vector<int> PeakCells(const LikelihoodMap& map, float floor, int count) {
  std::vector<int> cells;
  for (int cy = 0; cy < map.height; ++cy) {
    for (int cx = 0; cx < map.width; ++cx) {
      const float v = map.At(cx, cy);
      if (!(v >= floor && v > 0.0f)) continue;
      bool peak = true;
      for (int dy = -1; dy <= 1 && peak; ++dy) {
        for (int dx = -1; dx <= 1 && peak; ++dx) {
          const int nx = cx + dx, ny = cy + dy;
          if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= map.width || ny >= map.height) {
            continue;
          }
          const float n = map.At(nx, ny);
          const bool earlier = dy < 0 || (dy == 0 && dx < 0);
          if (earlier ? !(v > n) : !(v >= n)) peak = false;
        }
      }
      if (peak) cells.push_back(cy * map.width + cx);
    }
  }
  std::stable_sort(cells.begin(), cells.end(),
                   [&](int a, int b) { return map.values[a] > map.values[b]; });
  if (static_cast<int>(cells.size()) > count) cells.resize(count);
  return cells;
}

// A pose of the model at an accumulator peak, from the votes that agree on it.
struct Pose {
  double support = 0.0;  // agreeing votes' psi, Gaussian-weighted by distance to (x, y)
  double x = 0.0, y = 0.0, scale = 1.0, rotation = 0.0;
};

// The scale of a cluster of one-to-one matches: the median, over pairs of
// matches whose model keypoints are at least kMinPairPx apart, of the ratio
// of the frame keypoints' distance to the model keypoints' distance (the
// scale of the similarity between them). The keypoints' own scale ratios are
// coarser: most corners' characteristic scale is at an end of the scale
// range, where the Laplacian cannot refine it, so their ratio stays 1 whatever
// the zoom. They are the fallback (psi-weighted median) for a cluster without
// such a pair.
double ClusterScale(std::span<const Vote* const> group) {
  std::vector<double> ratios;
  for (size_t a = 0; a < group.size(); ++a) {
    for (size_t b = a + 1; b < group.size(); ++b) {
      const double model = std::hypot(group[a]->mx - group[b]->mx, group[a]->my - group[b]->my);
      if (model < kMinPairPx) continue;
      ratios.push_back(std::hypot(group[a]->fx - group[b]->fx, group[a]->fy - group[b]->fy) /
                       model);
    }
  }
  if (!ratios.empty()) {
    const auto middle = ratios.begin() + static_cast<std::ptrdiff_t>(ratios.size() / 2);
    std::nth_element(ratios.begin(), middle, ratios.end());
    return *middle;
  }
  std::vector<std::pair<float, float>> scales;  // (scale ratio, psi)
  double total = 0.0;
  for (const Vote* v : group) {
    scales.emplace_back(v->scale, v->weight);
    total += v->weight;
  }
  std::sort(scales.begin(), scales.end());
  double cumulative = 0.0;
  for (const auto& [scale, w] : scales) {
    cumulative += w;
    if (cumulative >= 0.5 * total) return scale;
  }
  return 1.0;
}

// Pose clustering at one peak (Lowe 2004, section 7.3, clusters Hough votes
// the same way): of the votes within `reach` of (x0, y0), the largest group
// that agrees with one of them on rotation (within `rotation_tolerance` rad)
// and on scale ratio (within a factor `scale_tolerance`), one to one (each
// frame keypoint and each model keypoint counted once, heaviest vote first,
// so that one corner matching several alike ones cannot inflate it). The
// pose: the group's circular-mean rotation, its scale (ClusterScale) and the
// reference point those put it at; its support: the group's psi, weighted by
// the votes' Gaussian around their mean position (three mean-shift steps), in
// the accumulator's units. Clutter votes meet in position by chance, but
// seldom in rotation and scale too.
Pose Verify(std::span<const Vote> votes, double x0, double y0, double reach, double sigma_px,
            double rotation_tolerance, double scale_tolerance, double reference_x,
            double reference_y) {
  std::vector<const Vote*> near;
  for (const Vote& v : votes) {
    if ((v.x - x0) * (v.x - x0) + (v.y - y0) * (v.y - y0) <= reach * reach) near.push_back(&v);
  }
  const auto log_tolerance = static_cast<float>(std::log(scale_tolerance));
  const auto turn_tolerance = static_cast<float>(rotation_tolerance);
  auto agrees = [&](const Vote& a, const Vote& b) {
    // Rotations are differences of angles in [0, 2 pi), so |a - b| < 4 pi.
    float turn = std::abs(a.rotation - b.rotation);
    turn = std::fmod(turn, static_cast<float>(kTwoPi));
    turn = std::min(turn, static_cast<float>(kTwoPi) - turn);
    return turn <= turn_tolerance && std::abs(a.log_scale - b.log_scale) <= log_tolerance;
  };
  double best = 0.0;
  const Vote* seed = nullptr;
  for (const Vote* a : near) {
    double w = 0.0;
    for (const Vote* b : near) {
      if (agrees(*a, *b)) w += b->weight;
    }
    if (w > best) {
      best = w;
      seed = a;
    }
  }
  Pose pose{.x = x0, .y = y0};
  if (seed == nullptr) return pose;
  std::vector<const Vote*> agreeing;
  for (const Vote* b : near) {
    if (agrees(*seed, *b)) agreeing.push_back(b);
  }
  std::stable_sort(agreeing.begin(), agreeing.end(),
                   [](const Vote* a, const Vote* b) { return a->weight > b->weight; });
  std::vector<const Vote*> group;
  for (const Vote* v : agreeing) {
    const bool taken = std::any_of(group.begin(), group.end(), [&](const Vote* u) {
      return u->frame_point == v->frame_point || u->model_point == v->model_point;
    });
    if (!taken) group.push_back(v);
  }
  const double inv = -0.5 / (sigma_px * sigma_px);
  auto kernel = [&](const Vote& v) {
    return v.weight *
           std::exp(((v.x - pose.x) * (v.x - pose.x) + (v.y - pose.y) * (v.y - pose.y)) * inv);
  };
  for (int step = 0; step < 3; ++step) {
    double sx = 0.0, sy = 0.0, sw = 0.0;
    for (const Vote* v : group) {
      const double w = kernel(*v);
      sx += w * v->x;
      sy += w * v->y;
      sw += w;
    }
    if (!(sw > 0.0)) break;
    pose.x = sx / sw;
    pose.y = sy / sw;
  }
  double sin_sum = 0.0, cos_sum = 0.0;
  for (const Vote* v : group) {
    pose.support += kernel(*v);
    sin_sum += v->weight * std::sin(v->rotation);
    cos_sum += v->weight * std::cos(v->rotation);
  }
  pose.rotation = std::atan2(sin_sum, cos_sum);
  pose.scale = ClusterScale(group);
  // The reference point by the cluster's similarity (its scale and
  // rotation): each frame keypoint plus its model keypoint's offset to the
  // reference point, transformed; the psi-weighted mean.
  const double c = std::cos(pose.rotation), s = std::sin(pose.rotation);
  double sx = 0.0, sy = 0.0, sw = 0.0;
  for (const Vote* v : group) {
    const double ox = reference_x - v->mx, oy = reference_y - v->my;
    sx += v->weight * (v->fx + pose.scale * (c * ox - s * oy));
    sy += v->weight * (v->fy + pose.scale * (s * ox + c * oy));
    sw += v->weight;
  }
  pose.x = sx / sw;
  pose.y = sy / sw;
  return pose;
}

// ---------------------------------------------------------------- detector

const SksOptions& Validated(const SksOptions& options) {
  options.Validate();
  return options;
}

// A model's features, positions in its patch's pixels. Described on the
// model's context (the patch and `margin` px around it, as far as the
// context reaches), as the same place of a frame would be: a patch alone
// would be extended by clamping its border, which erases the target's
// outline against the ground, and with it the corners a frame shows there.
// Only keypoints on the patch are the target's (KeypointsOnPatch).
Features ModelFeatures(const FeatureExtractor& extractor, const TargetModel& model, int margin,
                       int max_points) {
  const int w = model.patch.width, h = model.patch.height;
  if (w < kMinOctaveSide || h < kMinOctaveSide) return extractor.Extract(GreyImage{}, 0, 0.0, 0.0);
  if (model.context.width <= 0 || model.context.height <= 0) {
    return extractor.Extract(ToGrey(ImageView(model.patch)), max_points, 0.0, 0.0);
  }
  const int x0 = std::max(0, model.context_x - margin);
  const int y0 = std::max(0, model.context_y - margin);
  const int x1 = std::min(model.context.width, model.context_x + w + margin);
  const int y1 = std::min(model.context.height, model.context_y + h + margin);
  const Features all = extractor.Extract(
      ToGrey(ImageView(model.context).Crop(x0, y0, x1 - x0, y1 - y0)),
      std::numeric_limits<int>::max(), x0 - model.context_x, y0 - model.context_y);
  return KeypointsOnPatch(all, w, h, max_points);
}

class SksDetector final : public Detector {
 public:
  explicit SksDetector(const SksOptions& options)
      : options_(Validated(options)), space_(MakeScaleSpace(options_)) {}

  DetectorOutput Detect(const DetectorInput& input, Rng&) const override;
  bool uses_models() const override { return true; }
  std::string_view name() const override { return "sks"; }

 private:
  SksOptions options_;
  ScaleSpace space_;  // immutable after construction: shared by every call and thread
};

DetectorOutput SksDetector::Detect(const DetectorInput& input, Rng&) const {
  DetectorOutput out;
  const int width = input.image.empty() ? 0 : input.image.width;
  const int height = input.image.empty() ? 0 : input.image.height;
  const FeatureExtractor extractor(options_, space_);

  // Each model's features and search region.
  std::vector<Model> models(input.models.size());
  std::vector<Region> regions(input.models.size());
  std::vector<cv::Rect> areas(input.models.size());  // windowed: where its frame features come from
  std::vector<char> windowed(input.models.size(), 0);
  // Frame keypoints within this many pixels of a window's edge see the
  // pixels beyond it through their filters: 3 sigma of the largest scale.
  const int margin = static_cast<int>(
      std::ceil(3.0 * options_.base_sigma * std::pow(options_.scale_step, options_.scales - 1)));
  const cv::Rect all(0, 0, width, height);
  bool whole_frame = false;  // some model (with a patch, in an image) searches the whole frame
  for (size_t m = 0; m < input.models.size(); ++m) {
    const TargetModel& model = input.models[m];
    if (width == 0 || model.patch.width <= 0 || model.patch.height <= 0) continue;
    models[m].width = model.patch.width;
    models[m].height = model.patch.height;
    models[m].features = ModelFeatures(extractor, model, margin, options_.max_model_keypoints);
    cv::Rect rect = all;
    const SearchWindow* window = WindowOf(input.windows, model.target);
    if (window != nullptr && !window->box.empty()) {
      rect = AroundBox(window->box, options_.window_scale, width, height);
      windowed[m] = 1;
      areas[m] = cv::Rect(rect.x - margin, rect.y - margin, rect.width + 2 * margin,
                          rect.height + 2 * margin) &
                 all;
    } else {
      whole_frame = true;
    }
    regions[m] = {static_cast<double>(rect.x), static_cast<double>(rect.y),
                  static_cast<double>(rect.x + rect.width),
                  static_cast<double>(rect.y + rect.height)};
  }

  // The frame's features: a model with a window takes those of its window
  // (with its margin), so that a windowed search costs O(window pixels);
  // the models without one share the whole frame's, extracted once. Each
  // model's features thus depend on its own window alone. (Until 2026-12-07
  // every model took the whole frame's whenever one model had no window or
  // the windows covered the frame: another target's window, or a new model
  // without one, changed a target's keypoints, scores and boxes; a review.)
  auto features_of = [&](const cv::Rect& area) {
    if (area.area() <= 0) return Features{};
    return extractor.Extract(ToGrey(input.image.Crop(area.x, area.y, area.width, area.height)),
                             options_.max_keypoints, area.x, area.y);
  };
  const Features frame = whole_frame ? features_of(all) : Features{};

  for (size_t m = 0; m < input.models.size(); ++m) {
    const TargetModel& model = input.models[m];
    LikelihoodMap map;
    map.cell_px = options_.cell_px;
    map.width = static_cast<int>(std::ceil(width / options_.cell_px));
    map.height = static_cast<int>(std::ceil(height / options_.cell_px));
    map.values.assign(static_cast<size_t>(map.width) * map.height, 0.0f);
    const std::vector<Vote> votes =
        windowed[m]
            ? CastVotes(features_of(areas[m]), models[m], regions[m], options_.match_distance)
            : CastVotes(frame, models[m], regions[m], options_.match_distance);
    Accumulate(votes, options_.vote_sigma_px, map);

    // The best-supported pose among the highest peaks.
    Pose best;
    for (int cell : PeakCells(map, static_cast<float>(options_.min_votes), kPeaksVerified)) {
      const Pose pose =
          Verify(votes, (cell % map.width + 0.5) * map.cell_px,
                 (cell / map.width + 0.5) * map.cell_px, 2.0 * options_.vote_sigma_px + map.cell_px,
                 options_.vote_sigma_px, options_.rotation_tolerance_deg * kPi / 180.0,
                 options_.scale_tolerance, 0.5 * models[m].width, 0.5 * models[m].height);
      if (pose.support > best.support) best = pose;
    }
    const int points = models[m].features.points;
    const double score = points > 0 ? std::min(1.0, best.support / points) : 0.0;
    if (best.support >= options_.min_votes && score >= options_.min_score) {
      // The patch scaled and rotated by the pose, as an axis-aligned box,
      // clipped to the search region and the image.
      const double c = std::abs(std::cos(best.rotation)), s = std::abs(std::sin(best.rotation));
      const double w = best.scale * (c * models[m].width + s * models[m].height);
      const double h = best.scale * (s * models[m].width + c * models[m].height);
      const Region& r = regions[m];
      const BoxPx box = Intersect(BoxPx::FromCentre(best.x, best.y, w, h),
                                  BoxPx::FromCorners(r.left, r.top, r.right, r.bottom));
      if (const auto inside = ClipToImage(box, width, height)) {
        out.detections.push_back({.box = *inside, .score = score, .target = model.target});
      }
    }
    out.maps.push_back({model.target, std::move(map)});
  }
  return out;
}

}  // namespace

std::unique_ptr<Detector> MakeSksDetector(const SksOptions& options) {
  return std::make_unique<SksDetector>(options);
}

}  // namespace hcpf::vision
