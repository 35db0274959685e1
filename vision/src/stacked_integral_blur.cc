#include "hcpf/vision/stacked_integral_blur.h"

#include <Eigen/Dense>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <opencv2/imgproc.hpp>

#include "cv_image.h"
#include "hcpf/core/check.h"
#include "hcpf/core/instruction_set.h"

namespace hcpf::vision {

GreyImage ToGrey(const ImageView& rgb) {
  GreyImage grey;
  if (rgb.empty()) return grey;
  grey.width = rgb.width;
  grey.height = rgb.height;
  grey.pixels.resize(static_cast<size_t>(rgb.width) * rgb.height);
  // OpenCV's vectorised conversion (15-bit BT.601 coefficients, rounded half
  // up): 0.07 ms for 640 x 480 on one core against 0.37 ms for the plain
  // per-pixel loop this replaced, with the same bits (docs/performance.md).
  cv::Mat dst(grey.height, grey.width, CV_8U, grey.pixels.data());
  cv::cvtColor(internal::RgbMat(rgb), dst, cv::COLOR_RGB2GRAY);
  return grey;
}

double StackedBoxKernel::Variance() const {
  double variance = 0.0;
  for (size_t k = 0; k < radii.size(); ++k) {
    const double n = 2.0 * radii[k] + 1.0;
    variance += weights[k] * (n * n - 1.0) / 12.0;
  }
  return variance;
}

namespace {

constexpr double kMinSigma = 0.5;
constexpr double kMaxSigma = 64.0;
constexpr int kMinBoxes = 3;
constexpr int kMaxBoxes = 5;
// Candidate radius sets enumerated exhaustively up to this many (one
// (K+2)^2 solve each, ~0.3 us): K = 5 up to sigma ~ 4, K = 4 up to ~ 5.3,
// K = 3 up to ~ 10. At small sigma coordinate descent stops in poor local
// minima (sigma = 1.5, K = 5: 200x the optimum's error from one start; still
// 1.8x from four starts at sigma = 1.9 with a limit of 500). Above the limit,
// descent from the four starts came within 6.1 % of the exhaustive optimum
// everywhere both were run (sigma step 0.1; K = 3 to sigma 30, K = 4 to 14,
// K = 5 to 7), and a limit of 20,000 found no better sets, at up to 5 ms.
constexpr double kExhaustiveLimit = 5000.0;

// The objective of the fit, for one sigma: squared L2 distances between the
// 1-D marginals of the boxes and the sampled Gaussian. The marginal of box r
// is b_r(x) = 1 / n on |x| <= r (n = 2 r + 1); the Gaussian profile is
// g(x) = exp(-x^2 / 2 sigma^2) / Z, normalised over |x| <= 8 sigma + r_max
// (the mass it leaves out is < 1e-15). With sum w_k = 1 the marginal error is
// sum_k w_k (b_k - g), so the squared error is w^T G w with the Gram matrix
//   G_ij = <b_i - g, b_j - g> = 1 / max(n_i, n_j) - C_i / n_i - C_j / n_j + <g, g>,
// C_r = sum_{|x| <= r} g(x) (the closed form avoids a sum per pair).
//
// Why the marginal and not the 2-D profile: the same fit of the 2-D kernel
// to the 2-D Gaussian (the white-noise-optimal L2 fit) gave worse 8-bit RMSE
// on rendered frames wherever edges dominate: 0.88 against 0.58 grey levels
// at sigma = 10, K = 4 on renderer/tests/golden/oblique_frame0.png (over the
// 0.7 bound from sigma = 7 on); it was better, by at most 0.07, only at some
// sigma < 7 on the smoother frames. An edge's blurred profile is the
// kernel's projection on the edge normal, for axis-aligned edges exactly the
// marginal. docs/vision.md has the table.
class MarginalObjective {
 public:
  MarginalObjective(double sigma, int max_radius) : variance_(sigma * sigma) {
    const int half = static_cast<int>(std::ceil(8.0 * sigma)) + max_radius;
    std::vector<double> g(half + 1);
    double total = 0.0;
    for (int x = 0; x <= half; ++x) {
      g[x] = std::exp(-0.5 * x * x / variance_);
      total += x == 0 ? g[x] : 2.0 * g[x];
    }
    double squares = 0.0;
    for (int x = 0; x <= half; ++x) {
      g[x] /= total;
      squares += (x == 0 ? 1.0 : 2.0) * g[x] * g[x];
    }
    g_dot_g_ = squares;
    inside_.resize(max_radius + 1);
    double inside = g[0];
    inside_[0] = inside;
    for (int r = 1; r <= max_radius; ++r) {
      inside += 2.0 * g[r];
      inside_[r] = inside;
    }
  }

  double Gram(int ri, int rj) const {
    const double ni = 2.0 * ri + 1.0;
    const double nj = 2.0 * rj + 1.0;
    return 1.0 / std::max(ni, nj) - inside_[ri] / ni - inside_[rj] / nj + g_dot_g_;
  }
  double variance() const { return variance_; }

 private:
  double variance_;
  double g_dot_g_ = 0.0;
  std::vector<double> inside_;  // C_r
};

// One candidate kernel: its box radii, weights and error.
struct BoxSet {
  std::array<int, kMaxBoxes> radii{};
  std::array<double, kMaxBoxes> weights{};
  double error = std::numeric_limits<double>::infinity();
  bool feasible = false;  // every weight > 0
};

// Minimises w^T G w subject to sum w = 1 and sum w v = sigma^2, with
// v_k = (n_k^2 - 1) / 12, by its KKT system [2G A^T; A 0] [w; lambda] = [0; b]
// (Nocedal & Wright, "Numerical Optimization", 2nd ed., eq. 16.4). G is the
// Gram matrix of independent vectors (distinct boxes) and the two constraint
// rows are independent for M >= 2 distinct radii, so the system is
// nonsingular; LU with partial pivoting meets both constraints to 4e-16
// relative (worst over sigma in [0.5, 64], K = 3..5).
template <int M>
BoxSet SolveFixed(const MarginalObjective& objective, const std::array<int, kMaxBoxes>& radii) {
  Eigen::Matrix<double, M + 2, M + 2> kkt = Eigen::Matrix<double, M + 2, M + 2>::Zero();
  Eigen::Matrix<double, M + 2, 1> rhs = Eigen::Matrix<double, M + 2, 1>::Zero();
  for (int i = 0; i < M; ++i) {
    for (int j = 0; j < M; ++j) kkt(i, j) = 2.0 * objective.Gram(radii[i], radii[j]);
    const double n = 2.0 * radii[i] + 1.0;
    kkt(i, M) = kkt(M, i) = 1.0;
    kkt(i, M + 1) = kkt(M + 1, i) = (n * n - 1.0) / 12.0;
  }
  rhs(M) = 1.0;
  rhs(M + 1) = objective.variance();
  const Eigen::Matrix<double, M + 2, 1> solution = kkt.partialPivLu().solve(rhs);
  BoxSet c;
  c.radii = radii;
  c.feasible = true;
  for (int i = 0; i < M; ++i) {
    c.weights[i] = solution(i);
    if (!(c.weights[i] > 0.0)) c.feasible = false;
  }
  double error = 0.0;
  for (int i = 0; i < M; ++i) {
    for (int j = 0; j < M; ++j) {
      error += c.weights[i] * c.weights[j] * objective.Gram(radii[i], radii[j]);
    }
  }
  c.error = error;
  return c;
}

BoxSet Solve(const MarginalObjective& objective, const std::array<int, kMaxBoxes>& radii, int m) {
  switch (m) {
    case 2:
      return SolveFixed<2>(objective, radii);
    case 3:
      return SolveFixed<3>(objective, radii);
    case 4:
      return SolveFixed<4>(objective, radii);
    case 5:
      return SolveFixed<5>(objective, radii);
  }
  HCPF_CHECK(false) << m << " boxes";
  return {};
}

bool Better(const BoxSet& a, const BoxSet& b) {
  return a.feasible && (!b.feasible || a.error < b.error);
}

double Binomial(int n, int k) {
  double c = 1.0;
  for (int i = 0; i < k; ++i) c = c * (n - i) / (i + 1);
  return c;
}

// Every strictly increasing m-tuple in [0, max_radius], in lexicographic order.
BoxSet Exhaustive(const MarginalObjective& objective, int m, int max_radius) {
  std::array<int, kMaxBoxes> radii{};
  for (int k = 0; k < m; ++k) radii[k] = k;
  BoxSet best;
  while (true) {
    const BoxSet c = Solve(objective, radii, m);
    if (Better(c, best)) best = c;
    // Next tuple: bump the rightmost radius that can still grow, reset the rest.
    int k = m - 1;
    while (k >= 0 && radii[k] == max_radius - (m - 1 - k)) --k;
    if (k < 0) break;
    ++radii[k];
    for (int j = k + 1; j < m; ++j) radii[j] = radii[j - 1] + 1;
  }
  return best;
}

// Coordinate descent: move one radius at a time to its best value between
// its neighbours, in order, until a sweep changes nothing.
BoxSet Descent(const MarginalObjective& objective, int m, int max_radius,
               std::array<int, kMaxBoxes> radii) {
  BoxSet best = Solve(objective, radii, m);
  for (bool changed = true; changed;) {
    changed = false;
    for (int k = 0; k < m; ++k) {
      const int lo = k == 0 ? 0 : best.radii[k - 1] + 1;
      const int hi = k == m - 1 ? max_radius : best.radii[k + 1] - 1;
      std::array<int, kMaxBoxes> trial = best.radii;
      for (int r = lo; r <= hi; ++r) {
        if (r == best.radii[k]) continue;
        trial[k] = r;
        const BoxSet c = Solve(objective, trial, m);
        if (Better(c, best)) {
          best = c;
          changed = true;
        }
      }
    }
  }
  return best;
}

BoxSet BestSet(double sigma, int m) {
  const int max_radius = static_cast<int>(std::ceil(3.0 * sigma)) + m;
  const MarginalObjective objective(sigma, max_radius);
  if (Binomial(max_radius + 1, m) <= kExhaustiveLimit) return Exhaustive(objective, m, max_radius);
  // Starts r_k = sigma (a + b k / (m - 1)): the optima found by exhaustive
  // search lie near a = 0.5, b = 1.9 (e.g. sigma = 10, K = 4: 6, 11, 16, 24);
  // the other starts guard against a local minimum.
  constexpr std::array<std::array<double, 2>, 4> kStarts = {
      {{0.5, 1.7}, {0.3, 2.0}, {0.8, 1.5}, {0.4, 2.2}}};
  BoxSet best;
  for (const auto& [a, b] : kStarts) {
    std::array<int, kMaxBoxes> radii{};
    for (int k = 0; k < m; ++k) {
      const int r = static_cast<int>(std::lround(sigma * (a + b * k / (m - 1))));
      radii[k] =
          std::clamp(k == 0 ? r : std::max(r, radii[k - 1] + 1), k, max_radius - (m - 1 - k));
    }
    const BoxSet c = Descent(objective, m, max_radius, radii);
    if (Better(c, best)) best = c;
  }
  return best;
}

void CheckKernel(const StackedBoxKernel& kernel) {
  HCPF_CHECK(kernel.boxes() >= 1 && kernel.boxes() <= kMaxBoxes)
      << "stacked kernel with " << kernel.boxes() << " boxes";
  HCPF_CHECK(kernel.weights.size() == kernel.radii.size());
  double sum = 0.0;
  for (int k = 0; k < kernel.boxes(); ++k) {
    HCPF_CHECK(kernel.radii[k] >= (k == 0 ? 0 : kernel.radii[k - 1] + 1))
        << "radii must be >= 0 and strictly increasing; radius " << k << " is " << kernel.radii[k];
    HCPF_CHECK(kernel.weights[k] > 0.0) << "weight " << k << " is " << kernel.weights[k];
    sum += kernel.weights[k];
  }
  HCPF_CHECK(std::abs(sum - 1.0) < 1e-9) << "weights sum to " << sum;
  // The largest box sum, 255 n^2, must fit an int32 (the vector conversion
  // to float is signed): n <= 2901.
  const double n = 2.0 * kernel.max_radius() + 1.0;
  HCPF_CHECK(255.0 * n * n < 2147483648.0) << "box " << n << " px wide is too large";
}

// Entries per chunk of the inner loops. A fixed trip count lets GCC
// vectorise them at -O2 (its "very cheap" cost model takes no loop that needs
// a scalar epilogue or a run-time trip-count check); 16 int32/float = one
// AVX-512 vector, two AVX2 or four SSE2 vectors.
constexpr size_t kChunk = 16;

size_t RoundUpToChunk(size_t n) { return (n + kChunk - 1) / kChunk * kChunk; }

// The hot loops are built for AVX-512, AVX2 and the x86-64 baseline; a call
// runs the build of the CPU's widest set, or of the one a test chose
// (HCPF_DISPATCHED, hcpf/core/instruction_set.h; docs/performance.md has the
// figures). Floating-point results are identical in every build: per pixel
// the same IEEE operations in the same order, no FMA (-ffp-contract=off).

// row[j] = above[j] + sums[j], j < n (a multiple of kChunk). Its own function
// so that the restrict parameters tell GCC the rows do not overlap (they are
// rows of one array, `stride` apart).
HCPF_DISPATCHED(void, AddRow,
                (const uint32_t* __restrict above, const uint32_t* __restrict sums,
                 uint32_t* __restrict row, size_t n),
                (above, sums, row, n), {
                  for (size_t c = 0; c < n; c += kChunk) {
                    for (size_t j = 0; j < kChunk; ++j) row[c + j] = above[c + j] + sums[c + j];
                  }
                })

// The integral image of the input replicate-padded by `pad` on every side:
//   S[i][j] = sum of P[y][x] over y < i, x < j, P[y][x] = I[clamp(y - pad)][clamp(x - pad)],
// (H + 2 pad + 1) rows of `stride` entries (a multiple of kChunk): the
// padding on the right is stride - 1 - W - pad >= pad columns, so rows can be
// read in whole chunks. uint32 wraps for very large images; box sums (< 2^31,
// CheckKernel) are still exact modulo 2^32.
void BuildIntegral(const GreyImage& in, int pad, size_t stride, uint32_t* integral) {
  const int right_pad = static_cast<int>(stride) - 1 - in.width - pad;
  const int padded_height = in.height + 2 * pad;
  std::vector<uint32_t> row_sums(stride);
  std::fill_n(integral, stride, 0u);
  int source_row = -1;
  for (int i = 0; i < padded_height; ++i) {
    const int y = std::clamp(i - pad, 0, in.height - 1);
    if (y != source_row) {
      // Prefix sums of the padded row (the pads repeat the edge pixels):
      // serial, but once per input row, not per padded row.
      source_row = y;
      const uint8_t* p = in.row(y);
      uint32_t sum = 0;
      size_t j = 0;
      row_sums[j++] = 0;
      for (int x = 0; x < pad; ++x) row_sums[j++] = sum += p[0];
      for (int x = 0; x < in.width; ++x) row_sums[j++] = sum += p[x];
      for (int x = 0; x < right_pad; ++x) row_sums[j++] = sum += p[in.width - 1];
    }
    AddRow(integral + i * stride, row_sums.data(), integral + (i + 1) * stride, stride);
  }
}

// acc[x] (+)= scale * (sum of the box of width n whose integral-image corners
// are top[x], top[x + n], bottom[x], bottom[x + n]) for x < width, a multiple
// of kChunk. The uint32 differences wrap back to the true sum.
HCPF_DISPATCHED(void, AccumulateBox,
                (const uint32_t* top, const uint32_t* bottom, int n, float scale, bool first,
                 float* acc, size_t width),
                (top, bottom, n, scale, first, acc, width), {
                  for (size_t c = 0; c < width; c += kChunk) {
                    const uint32_t* __restrict tl = top + c;
                    const uint32_t* __restrict tr = top + c + n;
                    const uint32_t* __restrict bl = bottom + c;
                    const uint32_t* __restrict br = bottom + c + n;
                    float* __restrict out = acc + c;
                    if (first) {
                      for (size_t i = 0; i < kChunk; ++i) {
                        const uint32_t box = br[i] - bl[i] - tr[i] + tl[i];
                        out[i] = scale * static_cast<float>(static_cast<int32_t>(box));
                      }
                    } else {
                      for (size_t i = 0; i < kChunk; ++i) {
                        const uint32_t box = br[i] - bl[i] - tr[i] + tl[i];
                        out[i] += scale * static_cast<float>(static_cast<int32_t>(box));
                      }
                    }
                  }
                })

// Rounds half up; acc is in [0, 255 (1 + 1e-6)] (positive weights summing to
// 1), so acc + 0.5 truncates to [0, 255].
inline uint8_t RoundToByte(float v) { return static_cast<uint8_t>(static_cast<int32_t>(v + 0.5f)); }

HCPF_DISPATCHED(void, RoundToBytes,
                (const float* __restrict acc, uint8_t* __restrict out, size_t width),
                (acc, out, width), {
                  size_t c = 0;
                  for (; c + kChunk <= width; c += kChunk) {
                    for (size_t i = 0; i < kChunk; ++i) out[c + i] = RoundToByte(acc[c + i]);
                  }
                  for (; c < width; ++c) out[c] = RoundToByte(acc[c]);
                })

void CheckInput(const GreyImage& input, const StackedBoxKernel& kernel) {
  HCPF_CHECK(input.width >= 0 && input.height >= 0);
  HCPF_CHECK(input.pixels.size() == static_cast<size_t>(input.width) * input.height)
      << input.pixels.size() << " pixels for " << input.width << " x " << input.height;
  CheckKernel(kernel);
}

// The shared body (inputs checked): computes each output row's float sums
// (a row of RoundUpToChunk(W) entries, the first W meaningful) and hands them
// to `finish(y, sums)`. Reads `input` only while building the integral image,
// before the first row is finished.
template <typename Finish>
void BlurRows(const GreyImage& input, const StackedBoxKernel& kernel, Finish finish) {
  if (input.width == 0 || input.height == 0) return;
  const int pad = kernel.max_radius();
  const size_t width = RoundUpToChunk(input.width);
  // Reads reach column (pad - r) + (width - 1) + n = width + pad + r <= width + 2 pad.
  const size_t stride = RoundUpToChunk(width + 2 * pad + 1);
  const size_t rows = static_cast<size_t>(input.height) + 2 * pad + 1;
  // Not zero-filled: BuildIntegral writes every entry.
  const auto integral = std::make_unique_for_overwrite<uint32_t[]>(rows * stride);
  BuildIntegral(input, pad, stride, integral.get());
  std::array<float, kMaxBoxes> scales{};
  for (int k = 0; k < kernel.boxes(); ++k) {
    const double n = 2.0 * kernel.radii[k] + 1.0;
    scales[k] = static_cast<float>(kernel.weights[k] / (n * n));
  }
  std::vector<float> sums(width);
  for (int y = 0; y < input.height; ++y) {
    for (int k = 0; k < kernel.boxes(); ++k) {
      const int r = kernel.radii[k];
      // Output (x, y) is padded (x + pad, y + pad); its box spans padded rows
      // [y + pad - r, y + pad + r] and columns [x + pad - r, x + pad + r].
      const uint32_t* top = integral.get() + static_cast<size_t>(y + pad - r) * stride + (pad - r);
      const uint32_t* bottom = top + static_cast<size_t>(2 * r + 1) * stride;
      AccumulateBox(top, bottom, 2 * r + 1, scales[k], k == 0, sums.data(), width);
    }
    finish(y, sums.data());
  }
}

template <typename Image>
void ResizeLike(const GreyImage& input, Image& output) {
  output.width = input.width;
  output.height = input.height;
  output.pixels.resize(static_cast<size_t>(input.width) * input.height);
}

}  // namespace

StackedBoxKernel MakeStackedBoxKernel(double sigma, int boxes) {
  HCPF_CHECK(sigma >= kMinSigma && sigma <= kMaxSigma)
      << "sigma " << sigma << " outside [" << kMinSigma << ", " << kMaxSigma << "]";
  HCPF_CHECK(boxes >= kMinBoxes && boxes <= kMaxBoxes) << boxes << " boxes";
  // `boxes` boxes if any such set has positive weights, else fewer (tiny
  // sigma); two boxes always have one (radii 0 and r with (n^2 - 1) / 12 >
  // sigma^2 bracket the variance).
  BoxSet best;
  int m = boxes;
  for (; m >= 2; --m) {
    best = BestSet(sigma, m);
    if (best.feasible) break;
  }
  HCPF_CHECK(best.feasible) << "no stacked box kernel for sigma " << sigma;
  StackedBoxKernel kernel;
  kernel.sigma = sigma;
  kernel.radii.assign(best.radii.begin(), best.radii.begin() + m);
  kernel.weights.assign(best.weights.begin(), best.weights.begin() + m);
  return kernel;
}

void StackedIntegralBlur(const GreyImage& input, const StackedBoxKernel& kernel,
                         GreyImage& output) {
  CheckInput(input, kernel);
  // When `output` is `input` this changes nothing (same size), and BlurRows reads
  // the input only before it finishes the first row.
  ResizeLike(input, output);
  BlurRows(input, kernel,
           [&](int y, const float* sums) { RoundToBytes(sums, output.row(y), input.width); });
}

void StackedIntegralBlur(const GreyImage& input, const StackedBoxKernel& kernel,
                         GreyImageF& output) {
  CheckInput(input, kernel);
  ResizeLike(input, output);
  BlurRows(input, kernel,
           [&](int y, const float* sums) { std::copy_n(sums, input.width, output.row(y)); });
}

}  // namespace hcpf::vision
