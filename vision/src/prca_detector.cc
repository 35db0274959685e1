// PRCA, Pattern Recognition by Cluster Accumulation (prca.h; Bhatia 2011,
// section 3.3). The steps follow the thesis's pseudo code:
//   model preparation: FormClusters, ClusterStatistics, D_m^i (PrepareModel);
//   scene recognition: FormClusters and ClusterStatistics once per frame,
//   then per model RankedList (eqs. 3.5, 3.6), PairErrorSum (eqs. 3.7, 3.8),
//   VoteCircle (eq. 3.9) and ArgMax (eq. 3.10).
// No smoothing anywhere: the thesis clusters the raw pixels and the vote
// ring's width (ring_px) is the only tolerance the accumulator has.

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <limits>
#include <numeric>
#include <opencv2/core.hpp>
#include <unordered_map>

#include "cv_image.h"
#include "hcpf/core/union_find.h"
#include "hcpf/vision/prca.h"

namespace hcpf::vision {

std::span<const Field<PrcaOptions>> PrcaOptions::Fields() {
  using O = PrcaOptions;
  static const std::vector<Field<O>> fields = {
      // 442 > sqrt(3) * 255, the largest RGB distance: gamma = 442 makes every
      // pair of neighbours similar.
      NumberField("gamma", &O::gamma, AboveUpTo(0, 442), "",
                  "γ: 8-neighbours are similar when their RGB distance is below γ"),
      // rho = 1 would need more than all neighbours similar: no pixel could
      // join a cluster.
      NumberField("rho", &O::rho, FieldRange{.lo = 0, .hi = 1, .hi_open = true}, "",
                  "ρ: a pixel clusters when more than ρ of its 8-neighbours are similar"),
      IntegerField("min_cluster_px", &O::min_cluster_px, 1, 1'000'000, "px",
                   "smaller clusters are noise"),
      IntegerField("max_model_clusters", &O::max_model_clusters, 1, 256, "",
                   "N_m: at most this many (the largest) model clusters"),
      ChoiceField<&O::colour_norm>("colour_norm", "normalisation of pixel colour in X_i"),
      // eta is at most sqrt(3) (colour unit vectors differ by at most sqrt(2),
      // the size term by at most 1): lambda = 2 accepts every pair.
      NumberField("lambda", &O::lambda, AboveUpTo(0, 2), "",
                  "λ: a valid match has match error η < λ"),
      IntegerField("max_matches", &O::max_matches, 1, 64, "",
                   "length of each model cluster's ranked list"),
      NumberField("ring_px", &O::ring_px, Closed(0.5, 16), "px",
                  "half-width of the vote ring at distance D"),
      NumberField("min_score", &O::min_score, AboveUpTo(0, 1), "",
                  "normalised peak vote (peak / N_m) needed for a detection"),
      FlagField("subpixel_peak", &O::subpixel_peak,
                "the detection's centre refined by a parabola through the argmax and its "
                "neighbours (false: the argmax pixel's centre, the thesis)"),
      NumberField("scale_min", &O::scale_min, Closed(0.25, 1), "",
                  "smallest scale searched (target size / model size; 1: the thesis)"),
      NumberField("scale_max", &O::scale_max, Closed(1, 4), "",
                  "largest scale searched (1: the thesis)"),
      NumberField("scale_step", &O::scale_step, Closed(1.05, 2), "",
                  "ratio of successive scales searched (2^(1/4): four per octave)"),
      NumberField("window_scale", &O::window_scale, Closed(1, 20), "",
                  "windowed search: window side = scale × predicted box side"),
      NumberField("cell_px", &O::cell_px, Closed(1, 64), "px", "map cell size"),
  };
  return fields;
}

void PrcaOptions::Validate(std::string_view prefix) const { CheckFields(*this, Fields(), prefix); }

std::vector<double> PrcaOptions::Scales() const {
  // k from the lowest with step^k >= scale_min to the highest with step^k <=
  // scale_max; the 1e-9 keeps an end that is meant to be a power of the step
  // (scale_max = step^2) in spite of rounding in the logarithms.
  const double log_step = std::log(scale_step);
  const int k_lo = static_cast<int>(std::ceil(std::log(scale_min) / log_step - 1e-9));
  const int k_hi = static_cast<int>(std::floor(std::log(scale_max) / log_step + 1e-9));
  std::vector<int> ks;
  for (int k = k_lo; k <= k_hi; ++k) ks.push_back(k);
  // 0 first, then -1, 1, -2, 2, ...: by distance from 1 in octaves, smaller first.
  std::stable_sort(ks.begin(), ks.end(), [](int a, int b) {
    return std::abs(a) < std::abs(b) || (std::abs(a) == std::abs(b) && a < b);
  });
  std::vector<double> scales;
  for (int k : ks) scales.push_back(k == 0 ? 1.0 : std::pow(scale_step, k));
  return scales;
}

namespace prca {
namespace {

// Neighbour bits of the 8-neighbourhood, k = 0 .. 7: (-1,-1) (0,-1) (1,-1)
// (-1,0) (1,0) (-1,1) (0,1) (1,1); the opposite of bit k is bit 7 - k.
constexpr uint8_t kBitE = 1u << 4;
constexpr uint8_t kBitSW = 1u << 5;
constexpr uint8_t kBitS = 1u << 6;
constexpr uint8_t kBitSE = 1u << 7;
constexpr auto kPopCount = [] {
  std::array<uint8_t, 256> t{};
  for (int i = 0; i < 256; ++i) {
    t[static_cast<size_t>(i)] = static_cast<uint8_t>(std::popcount(static_cast<unsigned>(i)));
  }
  return t;
}();
constexpr uint8_t Opposite(uint8_t bit) {
  return static_cast<uint8_t>(1u << (7 - std::countr_zero(bit)));
}

}  // namespace

ClusteredImage FormClusters(const ImageView& image, const PrcaOptions& options) {
  ClusteredImage out;
  if (image.empty()) return out;
  const int w = image.width;
  const int h = image.height;
  const size_t n = static_cast<size_t>(w) * h;
  out.width = w;
  out.height = h;
  // ||RGB(p) - RGB(q)||^2 is an integer: below gamma^2 means at most `limit`.
  const int limit = static_cast<int>(std::ceil(options.gamma * options.gamma)) - 1;

  // Sim (eq. 3.4) as one bit per neighbour: each pair is compared once, from
  // its earlier pixel, and the bit set on both. Branch-free row loops: on
  // textured ground the outcome is too irregular to predict.
  std::vector<uint8_t> sim(n, 0);
  std::vector<uint8_t> pair(static_cast<size_t>(w));
  const auto compare = [&](const uint8_t* a, const uint8_t* b, int count) {
    for (int x = 0; x < count; ++x) {
      const int dr = a[3 * x] - b[3 * x];
      const int dg = a[3 * x + 1] - b[3 * x + 1];
      const int db = a[3 * x + 2] - b[3 * x + 2];
      pair[static_cast<size_t>(x)] = static_cast<uint8_t>(dr * dr + dg * dg + db * db <= limit);
    }
  };
  // Sets `bit` on s[x] and its opposite on t[x + shift] where pair[x].
  const auto mark = [&](uint8_t* s, uint8_t* t, int shift, int count, uint8_t bit) {
    const uint8_t opposite = Opposite(bit);
    for (int x = 0; x < count; ++x) {
      s[x] |= static_cast<uint8_t>(pair[static_cast<size_t>(x)] * bit);
    }
    for (int x = 0; x < count; ++x) {
      t[x + shift] |= static_cast<uint8_t>(pair[static_cast<size_t>(x)] * opposite);
    }
  };
  for (int y = 0; y < h; ++y) {
    const uint8_t* row = image.at(0, y);
    uint8_t* s = sim.data() + static_cast<size_t>(y) * w;
    compare(row, row + 3, w - 1);  // E
    mark(s, s, 1, w - 1, kBitE);
    if (y + 1 == h) continue;
    const uint8_t* below = image.at(0, y + 1);
    uint8_t* sb = s + w;
    compare(row, below, w);  // S
    mark(s, sb, 0, w, kBitS);
    compare(row + 3, below, w - 1);  // SW, from x + 1
    mark(s + 1, sb, 0, w - 1, kBitSW);
    compare(row, below + 3, w - 1);  // SE
    mark(s, sb, 1, w - 1, kBitSE);
  }

  // Density: |Sim| / |Neigh| > rho with |Neigh| = 8 everywhere: a
  // neighbour outside the image is never similar. (Counting only the
  // neighbours inside would make a model patch's border pixels denser than
  // the same pixels in the scene, whose outer neighbours are background.)
  // Dense pixels start as their own root; the others are -1 (in no
  // cluster). `out.labels` serves as the union-find forest, then holds each
  // component's size at its root, then the labels.
  const int min_similar = static_cast<int>(std::floor(8.0 * options.rho)) + 1;
  std::vector<int32_t>& parent = out.labels;
  parent.resize(n);
  for (size_t p = 0; p < n; ++p) {
    parent[p] = kPopCount[sim[p]] >= min_similar ? static_cast<int32_t>(p) : -1;
  }
  // Links: similar 8-neighbours that are both dense (the later half of the
  // neighbourhood; the earlier half linked this pixel already). A link hangs
  // the later root under the earlier one, so a parent is never after its
  // child in row-major order and every root is its component's first pixel.
  const auto link = [&](int32_t& root, int32_t q) {
    if (parent[q] < 0) return;
    const int32_t rq = FindRoot(parent, q);
    if (rq < root) {
      parent[root] = rq;
      root = rq;
    } else if (rq > root) {
      parent[rq] = root;
    }
  };
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const int32_t p = y * w + x;
      const uint8_t bits = sim[static_cast<size_t>(p)];
      if (parent[p] < 0 || (bits & (kBitE | kBitSW | kBitS | kBitSE)) == 0) continue;
      int32_t root = FindRoot(parent, p);
      if (bits & kBitE) link(root, p + 1);
      if (bits & kBitSW) link(root, p + w - 1);
      if (bits & kBitS) link(root, p + w);
      if (bits & kBitSE) link(root, p + w + 1);
    }
  }
  // Flatten (a parent comes earlier, so it is flat already) and count: a
  // root holds -2 - (its component's size - 1), a member its root's index.
  for (size_t p = 0; p < n; ++p) {
    const int32_t q = parent[p];
    if (q < 0) continue;
    if (static_cast<size_t>(q) == p) {
      parent[p] = -2;
    } else {
      // q is a root (counting, so negative) or a member already flattened.
      const int32_t up = parent[static_cast<size_t>(q)];
      const int32_t root = up >= 0 ? up : q;
      parent[p] = root;
      --parent[static_cast<size_t>(root)];
    }
  }
  // Label the roots in row-major order (a root comes before its members).
  for (size_t p = 0; p < n; ++p) {
    const int32_t v = parent[p];
    if (v == -1) continue;
    if (v <= -2) {
      parent[p] = -1 - v >= options.min_cluster_px ? out.count++ : -1;
    } else {
      parent[p] = parent[static_cast<size_t>(v)];
    }
  }
  return out;
}

std::vector<ClusterStats> ClusterStatistics(const ImageView& image, const ClusteredImage& clustered,
                                            PrcaColourNorm colour_norm) {
  struct Sums {
    double r = 0, g = 0, b = 0;
    int64_t x = 0, y = 0;
    int n = 0;
  };
  // The normalised colour of black, where the norm is undefined: neutral grey.
  const float neutral = colour_norm == PrcaColourNorm::kL2   ? 0.57735026919f  // 1 / sqrt(3)
                        : colour_norm == PrcaColourNorm::kL1 ? 1.0f / 3.0f
                                                             : 0.0f;
  std::vector<Sums> sums(static_cast<size_t>(clustered.count));
  for (int y = 0; y < clustered.height; ++y) {
    const int32_t* labels = clustered.labels.data() + static_cast<size_t>(y) * clustered.width;
    const uint8_t* row = image.at(0, y);
    for (int x = 0; x < clustered.width; ++x) {
      const int32_t label = labels[x];
      if (label < 0) continue;
      const int r = row[3 * x], g = row[3 * x + 1], b = row[3 * x + 2];
      // Single precision per pixel is ample: the sums are kept in double.
      float scale = 1.0f / 255.0f;
      if (colour_norm == PrcaColourNorm::kL2) {
        const int norm2 = r * r + g * g + b * b;
        scale = norm2 > 0 ? 1.0f / std::sqrt(static_cast<float>(norm2)) : 0.0f;
      } else if (colour_norm == PrcaColourNorm::kL1) {
        const int norm = r + g + b;
        scale = norm > 0 ? 1.0f / static_cast<float>(norm) : 0.0f;
      }
      Sums& s = sums[static_cast<size_t>(label)];
      if (scale > 0.0f || colour_norm == PrcaColourNorm::kNone) {
        s.r += static_cast<float>(r) * scale;
        s.g += static_cast<float>(g) * scale;
        s.b += static_cast<float>(b) * scale;
      } else {
        s.r += neutral;
        s.g += neutral;
        s.b += neutral;
      }
      s.x += x;
      s.y += y;
      ++s.n;
    }
  }
  std::vector<ClusterStats> stats;
  stats.reserve(sums.size());
  for (const Sums& s : sums) {
    const double inv = s.n > 0 ? 1.0 / s.n : 0.0;
    stats.push_back({.r = s.r * inv,
                     .g = s.g * inv,
                     .b = s.b * inv,
                     .omega = s.n,
                     .cx = static_cast<double>(s.x) * inv + 0.5,
                     .cy = static_cast<double>(s.y) * inv + 0.5});
  }
  return stats;
}

double MatchScore(const ClusterStats& model, const ClusterStats& scene) {
  const double big = std::max(model.omega, scene.omega);
  const double dw = big > 0 ? (model.omega - scene.omega) / big : 0.0;
  const double dr = model.r - scene.r;
  const double dg = model.g - scene.g;
  const double db = model.b - scene.b;
  return std::sqrt(dr * dr + dg * dg + db * db + dw * dw);
}

std::vector<RankedMatch> RankedList(const ClusterStats& model_cluster,
                                    std::span<const ClusterStats> scene,
                                    std::span<const int32_t> candidates, double lambda,
                                    int max_matches) {
  std::vector<RankedMatch> list;
  for (int32_t j : candidates) {
    const double eta = MatchScore(model_cluster, scene[static_cast<size_t>(j)]);
    if (eta < lambda) list.push_back({j, eta});
  }
  const auto better = [](const RankedMatch& a, const RankedMatch& b) {
    return a.eta < b.eta || (a.eta == b.eta && a.scene < b.scene);
  };
  const size_t keep = std::min(list.size(), static_cast<size_t>(std::max(0, max_matches)));
  std::partial_sort(list.begin(), list.begin() + static_cast<std::ptrdiff_t>(keep), list.end(),
                    better);
  list.resize(keep);
  return list;
}

double WalkRatio(const ClusteredImage& clustered, std::span<const ClusterStats> stats, int32_t a,
                 int32_t b) {
  if (a > b) std::swap(a, b);
  const auto pixel = [&](double v, int size) {
    return std::clamp(static_cast<int>(std::floor(v)), 0, size - 1);
  };
  const ClusterStats& sa = stats[static_cast<size_t>(a)];
  const ClusterStats& sb = stats[static_cast<size_t>(b)];
  int x = pixel(sa.cx, clustered.width);
  int y = pixel(sa.cy, clustered.height);
  const int x1 = pixel(sb.cx, clustered.width);
  const int y1 = pixel(sb.cy, clustered.height);
  const int dx = std::abs(x1 - x);
  const int dy = -std::abs(y1 - y);
  const int sx = x < x1 ? 1 : -1;
  const int sy = y < y1 ? 1 : -1;
  int err = dx + dy;
  int either = 0;
  int neither = 0;
  for (;;) {
    const int32_t label = clustered.at(x, y);
    if (label == a || label == b) {
      ++either;
    } else {
      ++neither;
    }
    if (x == x1 && y == y1) break;
    const int e2 = 2 * err;
    if (e2 >= dy) {
      err += dy;
      x += sx;
    }
    if (e2 <= dx) {
      err += dx;
      y += sy;
    }
  }
  return static_cast<double>(neither) / std::max(either, 1);
}

double WalkRatioError(double model_walk_ratio, double scene_walk_ratio) {
  const double m = std::max(model_walk_ratio, scene_walk_ratio);
  return m > 0.0 ? std::abs(model_walk_ratio - scene_walk_ratio) / m : 0.0;
}

double PairErrorSum(int i, int32_t j, std::span<const std::vector<RankedMatch>> lists,
                    const std::function<double(int, int)>& model_walk,
                    const std::function<double(int32_t, int32_t)>& scene_walk) {
  double sum = 0.0;
  int terms = 0;
  for (int q = 0; q < static_cast<int>(lists.size()); ++q) {
    if (q == i) continue;
    double mwre = std::numeric_limits<double>::infinity();
    double model_ratio = -1.0;  // WR_n(i, q), computed only when some r exists
    for (const RankedMatch& r : lists[static_cast<size_t>(q)]) {
      if (r.scene == j) continue;
      if (model_ratio < 0.0) model_ratio = model_walk(i, q);
      mwre = std::min(mwre, WalkRatioError(model_ratio, scene_walk(j, r.scene)));
    }
    if (std::isfinite(mwre)) {
      sum += mwre;
      ++terms;
    }
  }
  return terms > 0 ? sum / terms : 0.0;
}

double VoteWeight(double eta, double pair_error_sum, double lambda) {
  return 1.0 - (eta + pair_error_sum) / (1.0 + lambda);
}

void VoteCircle(Accumulator& accumulator, double cx, double cy, double radius_px, double ring_px,
                double weight) {
  if (accumulator.width <= 0 || accumulator.height <= 0 || !(weight > 0.0)) return;
  const double outer = radius_px + ring_px;
  const double inner = radius_px - ring_px;
  const int x_end = accumulator.x0 + accumulator.width;  // one past the last column
  const int y0 = std::max(accumulator.y0, static_cast<int>(std::floor(cy - outer)));
  const int y1 =
      std::min(accumulator.y0 + accumulator.height - 1, static_cast<int>(std::ceil(cy + outer)));
  const double inv_ring = 1.0 / ring_px;
  for (int y = y0; y <= y1; ++y) {
    const double dy = y + 0.5 - cy;
    const double outer_dx2 = outer * outer - dy * dy;
    if (outer_dx2 < 0.0) continue;
    const double xo = std::sqrt(outer_dx2);
    // Inside the inner circle no pixel gets a vote: the row is two spans.
    const double xi =
        (inner > 0.0 && std::abs(dy) < inner) ? std::sqrt(inner * inner - dy * dy) : -1.0;
    // The row's first pixel is x0 (indexed x - x0: a pointer x0 before the
    // row would point before the array, undefined; a review).
    float* row =
        accumulator.votes.data() + static_cast<size_t>(y - accumulator.y0) * accumulator.width;
    const auto span = [&](double from, double to) {
      // Pixel centres x + 0.5 in [from, to].
      const int xa = std::max(accumulator.x0, static_cast<int>(std::ceil(from - 0.5)));
      const int xb = std::min(x_end - 1, static_cast<int>(std::floor(to - 0.5)));
      for (int x = xa; x <= xb; ++x) {
        const double dx = x + 0.5 - cx;
        const double e = std::abs(std::sqrt(dx * dx + dy * dy) - radius_px);
        const double v = 1.0 - e * inv_ring;
        if (v > 0.0) row[x - accumulator.x0] += static_cast<float>(weight * v);
      }
    };
    if (xi < 0.0) {
      span(cx - xo, cx + xo);
    } else {
      span(cx - xo, cx - xi);
      span(cx + xi, cx + xo);
    }
  }
}

Peak ArgMax(const Accumulator& accumulator) {
  Peak peak;
  for (int y = 0; y < accumulator.height; ++y) {
    const float* row = accumulator.votes.data() + static_cast<size_t>(y) * accumulator.width;
    for (int x = 0; x < accumulator.width; ++x) {
      if (peak.x < 0 || row[x] > peak.votes) {
        peak = {accumulator.x0 + x, accumulator.y0 + y, row[x]};
      }
    }
  }
  return peak;
}

SubPixel SubPixelPeak(const Accumulator& accumulator, const Peak& peak) {
  SubPixel offset;
  if (peak.x < 0) return offset;
  // Along one axis: the votes before, at and after the peak.
  const auto vertex = [](double l, double c, double r) {
    const double curvature = l - 2.0 * c + r;
    // c is at least l and r (the argmax): curvature <= 0, and 0 only when
    // all three are equal (a plateau: no better centre than the pixel's).
    if (!(curvature < 0.0)) return 0.0;
    return std::clamp((l - r) / (2.0 * curvature), -0.5, 0.5);
  };
  const int x = peak.x, y = peak.y;
  const double c = accumulator.at(x, y);
  if (x > accumulator.x0 && x + 1 < accumulator.x0 + accumulator.width) {
    offset.dx = vertex(accumulator.at(x - 1, y), c, accumulator.at(x + 1, y));
  }
  if (y > accumulator.y0 && y + 1 < accumulator.y0 + accumulator.height) {
    offset.dy = vertex(accumulator.at(x, y - 1), c, accumulator.at(x, y + 1));
  }
  return offset;
}

namespace {

// MODEL PREPARATION: the model's clusters (at most max_model_clusters, the
// largest, relabelled 0 .. N_m - 1 in label order; the others count as
// background in walk ratios), their statistics, D_m^i and the model's walk
// ratios WR_n(i, q).
struct Model {
  ClusteredImage clusters;
  std::vector<ClusterStats> stats;
  std::vector<double> d_px;  // D_m^i: cluster centroid to the patch centre
  std::vector<double> walk;  // N_m x N_m
  int count() const { return static_cast<int>(stats.size()); }
};

Model PrepareModel(const TargetModel& target, const PrcaOptions& options, double scale) {
  Model m;
  if (target.patch.width <= 0 || target.patch.height <= 0) return m;
  // At a scale other than 1, the patch resampled to scale x its size: area
  // averaging when shrinking (each pixel the mean of what it covers, as a
  // camera further away would record it), bilinear when enlarging.
  const cv::Mat original(target.patch.height, target.patch.width, CV_8UC3,
                         const_cast<uint8_t*>(target.patch.pixels.data()));
  cv::Mat resampled;
  if (scale != 1.0) {
    const cv::Size size(std::max(1, static_cast<int>(std::lround(scale * original.cols))),
                        std::max(1, static_cast<int>(std::lround(scale * original.rows))));
    cv::resize(original, resampled, size, 0, 0, scale < 1.0 ? cv::INTER_AREA : cv::INTER_LINEAR);
  } else {
    resampled = original;
  }
  const ImageView patch(resampled.data, resampled.cols, resampled.rows, resampled.step[0]);
  m.clusters = FormClusters(patch, options);
  std::vector<ClusterStats> all = ClusterStatistics(patch, m.clusters, options.colour_norm);
  std::vector<int32_t> order(all.size());
  std::iota(order.begin(), order.end(), 0);
  const size_t keep = std::min(order.size(), static_cast<size_t>(options.max_model_clusters));
  std::stable_sort(order.begin(), order.end(),
                   [&](int32_t a, int32_t b) { return all[a].omega > all[b].omega; });
  order.resize(keep);
  std::sort(order.begin(), order.end());
  std::vector<int32_t> relabel(all.size(), -1);
  for (size_t k = 0; k < order.size(); ++k) {
    relabel[static_cast<size_t>(order[k])] = static_cast<int32_t>(k);
    m.stats.push_back(all[static_cast<size_t>(order[k])]);
  }
  for (int32_t& label : m.clusters.labels) {
    if (label >= 0) label = relabel[static_cast<size_t>(label)];
  }
  m.clusters.count = static_cast<int>(keep);
  // The reference point: the centre of the model image.
  const double rx = 0.5 * patch.width;
  const double ry = 0.5 * patch.height;
  for (const ClusterStats& s : m.stats) m.d_px.push_back(std::hypot(s.cx - rx, s.cy - ry));
  const int n = m.count();
  m.walk.assign(static_cast<size_t>(n) * n, 0.0);
  for (int i = 0; i < n; ++i) {
    for (int q = i + 1; q < n; ++q) {
      const double wr = WalkRatio(m.clusters, m.stats, i, q);
      m.walk[static_cast<size_t>(i) * n + q] = wr;
      m.walk[static_cast<size_t>(q) * n + i] = wr;
    }
  }
  return m;
}

// One vote of eq. 3.9: a circle of radius D_m^i around a matched scene
// cluster's centroid, with its weight.
struct Circle {
  double cx = 0.0;
  double cy = 0.0;
  double radius_px = 0.0;
  double weight = 0.0;
};

// One model's votes at each scale searched (PrcaOptions::Scales order).
struct ModelVotes {
  int clusters = 0;                          // N_m
  std::vector<std::vector<Circle>> circles;  // per scale
};

// The scene's walk ratios, computed on first use and shared by every model
// of the frame (local to one Detect call).
class SceneWalks {
 public:
  SceneWalks(const ClusteredImage& clusters, std::span<const ClusterStats> stats)
      : clusters_(clusters), stats_(stats) {}
  double operator()(int32_t a, int32_t b) {
    if (a > b) std::swap(a, b);
    const uint64_t key = (static_cast<uint64_t>(a) << 32) | static_cast<uint32_t>(b);
    const auto [it, inserted] = cache_.try_emplace(key, 0.0);
    if (inserted) it->second = WalkRatio(clusters_, stats_, a, b);
    return it->second;
  }

 private:
  const ClusteredImage& clusters_;
  std::span<const ClusterStats> stats_;
  std::unordered_map<uint64_t, double> cache_;
};

class PrcaDetector final : public Detector {
 public:
  explicit PrcaDetector(const PrcaOptions& options) : options_(options) {
    options_.Validate();
    scales_ = options_.Scales();
  }

  DetectorOutput Detect(const DetectorInput& input, Rng&) const override {
    DetectorOutput out;
    const int width = input.image.empty() ? 0 : input.image.width;
    const int height = input.image.empty() ? 0 : input.image.height;
    // Matching first (it needs the scene's clustered image), accumulation
    // after (the clustered image is gone by then, so one frame never holds
    // both pixel-sized buffers).
    std::vector<ModelVotes> votes = Match(input, width, height);
    std::vector<float> buffer;         // the accumulators' storage, reused model after model
    std::vector<float> merged_buffer;  // the maximum over scales (several scales only)
    for (size_t m = 0; m < input.models.size(); ++m) {
      const TargetModel& target = input.models[m];
      const ModelVotes& model = votes[m];
      // Each scale's accumulator covers only the pixels its circles reach;
      // with several scales the map is their maximum over all their pixels.
      Peak peak;
      double peak_scale = 1.0;
      SubPixel offset;  // the peak's, with subpixel_peak
      Accumulator merged;
      if (scales_.size() > 1) {
        merged = AccumulatorOver(model.circles, width, height, std::move(merged_buffer));
      }
      for (size_t k = 0; k < scales_.size(); ++k) {
        const std::span<const Circle> circles = k < model.circles.size()
                                                    ? std::span<const Circle>(model.circles[k])
                                                    : std::span<const Circle>();
        Accumulator accumulator =
            AccumulatorOver(std::span(&circles, 1), width, height, std::move(buffer));
        for (const Circle& c : circles) {
          VoteCircle(accumulator, c.cx, c.cy, c.radius_px, options_.ring_px, c.weight);
        }
        // The argmax (eq. 3.10); an earlier scale keeps a tie.
        const Peak at_scale = ArgMax(accumulator);
        if (at_scale.x >= 0 && (peak.x < 0 || at_scale.votes > peak.votes)) {
          peak = at_scale;
          peak_scale = scales_[k];
          if (options_.subpixel_peak) offset = SubPixelPeak(accumulator, peak);
        }
        if (scales_.size() == 1) {
          merged = std::move(accumulator);
          break;
        }
        MaxInto(merged, accumulator);
        buffer = std::move(accumulator.votes);
      }
      // The map: votes / N_m, max-pooled into cells.
      const double per_cluster = model.clusters > 0 ? 1.0 / model.clusters : 0.0;
      const cv::Mat region =
          merged.votes.empty() ? cv::Mat()
                               : cv::Mat(merged.height, merged.width, CV_32F, merged.votes.data());
      // A vote's pixel x stands for its centre, x + 0.5 (VoteCircle).
      TargetMap map{target.target, internal::PoolToMap(region, merged.x0 + 0.5, merged.y0 + 0.5,
                                                       width, height, options_.cell_px)};
      for (float& v : map.map.values) v = static_cast<float>(v * per_cluster);
      out.maps.push_back(std::move(map));
      if (scales_.size() == 1) {
        buffer = std::move(merged.votes);
      } else {
        merged_buffer = std::move(merged.votes);
      }
      // A detection where the argmax's normalised vote reaches min_score: a
      // box of the model's size at the winning scale.
      const double score = std::min(1.0, peak.votes * per_cluster);
      if (!(peak.votes > 0.0f) || score < options_.min_score) continue;
      const BoxPx box = BoxPx::FromCentre(peak.x + 0.5 + offset.dx, peak.y + 0.5 + offset.dy,
                                          peak_scale * static_cast<double>(target.patch.width),
                                          peak_scale * static_cast<double>(target.patch.height));
      if (const auto inside = internal::ClipToImage(box, width, height)) {
        out.detections.push_back({.box = *inside, .score = score, .target = target.target});
      }
    }
    return out;
  }
  bool uses_models() const override { return true; }
  std::string_view name() const override { return "prca"; }

 private:
  // The scene clusters that may vote for `target`: all, or with a search
  // window, those whose centroid lies inside AroundBox(window, window_scale).
  std::vector<int32_t> Candidates(const DetectorInput& input, const TargetModel& target, int width,
                                  int height, std::span<const ClusterStats> scene_stats,
                                  const std::vector<int32_t>& all) const {
    const SearchWindow* window = internal::WindowOf(input.windows, target.target);
    if (window == nullptr || window->box.empty()) return all;
    const cv::Rect r = internal::AroundBox(window->box, options_.window_scale, width, height);
    std::vector<int32_t> inside;
    for (int32_t j : all) {
      const ClusterStats& s = scene_stats[static_cast<size_t>(j)];
      if (s.cx >= r.x && s.cx < r.x + r.width && s.cy >= r.y && s.cy < r.y + r.height) {
        inside.push_back(j);
      }
    }
    return inside;
  }

  // SCENE RECOGNITION up to the votes: the scene's clusters (once for every
  // model), then per model the ranked lists (eqs. 3.5, 3.6), the pair error
  // sums (eqs. 3.7, 3.8) and the circles to vote (eq. 3.9).
  std::vector<ModelVotes> Match(const DetectorInput& input, int width, int height) const {
    std::vector<ModelVotes> votes(input.models.size());
    if (width == 0 || input.models.empty()) return votes;
    const ClusteredImage scene = FormClusters(input.image, options_);
    const std::vector<ClusterStats> scene_stats =
        ClusterStatistics(input.image, scene, options_.colour_norm);
    SceneWalks scene_walk(scene, scene_stats);
    const std::function<double(int32_t, int32_t)> scene_walk_fn = [&](int32_t a, int32_t b) {
      return scene_walk(a, b);
    };
    std::vector<int32_t> all_clusters(scene_stats.size());
    std::iota(all_clusters.begin(), all_clusters.end(), 0);
    for (size_t m = 0; m < input.models.size(); ++m) {
      const TargetModel& target = input.models[m];
      const std::vector<int32_t> candidates =
          Candidates(input, target, width, height, scene_stats, all_clusters);
      for (const double scale : scales_) {
        // The model as the target would look at this scale (PrepareModel).
        const Model model = PrepareModel(target, options_, scale);
        const int n = model.count();
        // N_m is the model's at its own scale: the score is the share of its
        // clusters whose votes agree, and a scale at which some of them
        // vanish cannot win by having fewer to agree.
        if (scale == 1.0) votes[m].clusters = n;
        std::vector<Circle>& circles = votes[m].circles.emplace_back();
        if (n == 0) continue;
        std::vector<std::vector<RankedMatch>> lists;
        for (const ClusterStats& s : model.stats) {
          lists.push_back(
              RankedList(s, scene_stats, candidates, options_.lambda, options_.max_matches));
        }
        const std::function<double(int, int)> model_walk = [&](int i, int q) {
          return model.walk[static_cast<size_t>(i) * n + q];
        };
        for (int i = 0; i < n; ++i) {
          for (const RankedMatch& match : lists[static_cast<size_t>(i)]) {
            const double pes = PairErrorSum(i, match.scene, lists, model_walk, scene_walk_fn);
            const ClusterStats& s = scene_stats[static_cast<size_t>(match.scene)];
            circles.push_back({.cx = s.cx,
                               .cy = s.cy,
                               .radius_px = model.d_px[static_cast<size_t>(i)],
                               .weight = VoteWeight(match.eta, pes, options_.lambda)});
          }
        }
      }
    }
    return votes;
  }

  // A zeroed accumulator over the pixels the rings of all `groups` of
  // circles may reach (clipped to the image; empty when there are no
  // circles), its storage taken from `buffer`.
  template <class Groups>
  Accumulator AccumulatorOver(const Groups& groups, int width, int height,
                              std::vector<float> buffer) const {
    Accumulator a;
    int x0 = width, y0 = height, x1 = 0, y1 = 0;
    for (const auto& circles : groups) {
      for (const Circle& c : circles) {
        const double outer = c.radius_px + options_.ring_px;
        x0 = std::min(x0, std::max(0, static_cast<int>(std::floor(c.cx - outer))));
        y0 = std::min(y0, std::max(0, static_cast<int>(std::floor(c.cy - outer))));
        x1 = std::max(x1, std::min(width, static_cast<int>(std::ceil(c.cx + outer)) + 1));
        y1 = std::max(y1, std::min(height, static_cast<int>(std::ceil(c.cy + outer)) + 1));
      }
    }
    a.votes = std::move(buffer);
    a.votes.clear();
    if (x1 <= x0 || y1 <= y0) return a;
    a.x0 = x0;
    a.y0 = y0;
    a.width = x1 - x0;
    a.height = y1 - y0;
    a.votes.assign(static_cast<size_t>(a.width) * a.height, 0.0f);
    return a;
  }

  // merged = max(merged, part) over part's pixels (merged covers them all).
  static void MaxInto(Accumulator& merged, const Accumulator& part) {
    for (int y = 0; y < part.height; ++y) {
      const float* from = part.votes.data() + static_cast<size_t>(y) * part.width;
      float* to = merged.votes.data() +
                  static_cast<size_t>(y + part.y0 - merged.y0) * merged.width +
                  (part.x0 - merged.x0);
      for (int x = 0; x < part.width; ++x) to[x] = std::max(to[x], from[x]);
    }
  }

  PrcaOptions options_;
  std::vector<double> scales_;  // options_.Scales()
};

}  // namespace
}  // namespace prca

std::unique_ptr<Detector> MakePrcaDetector(const PrcaOptions& options) {
  return std::make_unique<prca::PrcaDetector>(options);
}

}  // namespace hcpf::vision
