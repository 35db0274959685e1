#pragma once
// PRCA, Pattern Recognition by Cluster Accumulation (Bhatia 2011, section
// 3.3): a rotation-invariant radiometric detector for small or blurred
// targets. Each image is cut into clusters by a modified DBSCAN (eq. 3.4);
// model clusters are matched to scene clusters by their mean normalised
// colour and relative size (eq. 3.5) into ranked lists (eq. 3.6); each pair is
// checked against every other pair by the walk ratio (eqs. 3.7, 3.8); and
// every matched scene cluster votes for the model's reference point on a
// circle of radius D around its centroid (eq. 3.9). The accumulator's argmax
// (eq. 3.10) is the detection. docs/vision.md (PRCA) gives each step, the
// choices made where the thesis is silent, and the benchmark.
//
// The stages are public (namespace prca) so that tests and studies can check
// each against hand-worked values; the Detector is MakePrcaDetector().

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <span>
#include <string_view>
#include <utility>
#include <vector>

#include "hcpf/core/enum_names.h"
#include "hcpf/core/fields.h"
#include "hcpf/core/image.h"
#include "hcpf/vision/detector.h"

namespace hcpf::vision {

// How a pixel's colour is normalised before the cluster statistics (the
// thesis: r = R / ||(R, G, B)||).
enum class PrcaColourNorm {
  kL2,  // "l2": (R, G, B) / sqrt(R^2 + G^2 + B^2), the thesis's norm; black -> (1, 1, 1) / sqrt(3)
  kL1,  // "l1": (R, G, B) / (R + G + B), chromaticity; black -> (1, 1, 1) / 3
  kNone,  // "none": (R, G, B) / 255, no illumination invariance
};

}  // namespace hcpf::vision

template <>
struct hcpf::EnumNames<hcpf::vision::PrcaColourNorm> {
  static constexpr std::array kNames = {
      std::pair{hcpf::vision::PrcaColourNorm::kL2, std::string_view("l2")},
      std::pair{hcpf::vision::PrcaColourNorm::kL1, std::string_view("l1")},
      std::pair{hcpf::vision::PrcaColourNorm::kNone, std::string_view("none")}};
};

namespace hcpf::vision {

struct PrcaOptions {
  // Clustering (eq. 3.4). gamma: two 8-neighbours are similar when their
  // (R, G, B) distance (L2, grey levels) is below gamma. rho: a pixel joins a
  // cluster only when more than rho of its 8 neighbours are similar to it
  // (a neighbour outside the image is never similar). The defaults were
  // chosen on the synthetic scenes of the tests and bench/prca_bench.cc
  // (docs/vision.md (PRCA), "Defaults").
  double gamma = 16.0;
  double rho = 0.3;
  // Clusters of fewer pixels are noise (in no cluster), in model and scene.
  int min_cluster_px = 3;
  // N_m is at most this: the model's largest clusters are kept.
  int max_model_clusters = 16;
  // Cluster statistics (eq. 3.5).
  PrcaColourNorm colour_norm = PrcaColourNorm::kL2;
  // Match (eqs. 3.5, 3.6): a scene cluster is a valid match of a model
  // cluster when eta < lambda; the ranked list keeps the best max_matches.
  double lambda = 0.5;
  int max_matches = 4;
  // Accumulator (eq. 3.9): the vote of a pixel whose centre is e px from the
  // circle of radius D falls linearly from the full vote at e = 0 to none at
  // e = ring_px.
  double ring_px = 1.5;
  // Detection (eq. 3.10): the argmax's normalised vote (peak / N_m, at most
  // 1) needed for a detection; it is also the detection's score.
  double min_score = 0.25;
  // The detection's centre (an extension; the thesis takes the argmax
  // pixel's centre, up to half a pixel off the votes' peak): false, the
  // argmax pixel's centre; true, refined by a parabola through the argmax
  // and its two neighbours along x and along y (SubPixelPeak).
  bool subpixel_peak = false;
  // Scales searched (an extension; the thesis matches the model at its own
  // scale only): s = scale_step^k for every integer k with scale_min <= s <=
  // scale_max. At scale s the model is its patch resampled to s times its
  // size (area averaging when shrinking, bilinear when enlarging), clustered
  // and measured like the patch itself, so that its clusters are those the
  // target shows from s times nearer: sizes, centroids, D and walk ratios
  // (and the clusters lost to mixed pixels at their borders) all follow. The
  // scale whose argmax has the most votes gives the detection, a box of the
  // model's size times s. The default, 1 and 1, is the thesis's PRCA.
  double scale_min = 1.0;
  double scale_max = 1.0;
  double scale_step = 1.189207115002721;  // 2^(1/4): four scales per octave
  double window_scale = 3.0;  // windowed search: window side = scale x predicted box side
  double cell_px = 4.0;       // map cell size
  static std::span<const Field<PrcaOptions>> Fields();
  void Validate(std::string_view prefix = "observation.prca") const;
  // The scales searched, in the order they are tried: 1 (always in
  // [scale_min, scale_max]), then by distance from 1 in octaves, the smaller
  // of two equally far first. An earlier scale keeps a tie of votes.
  std::vector<double> Scales() const;
};

// The PRCA detector with `options` validated (throws InputError otherwise).
// For each model, one detection (the accumulator's argmax, model-sized box)
// when its normalised vote reaches min_score, and the accumulator (votes /
// N_m, max-pooled into cells) as the model's map.
std::unique_ptr<Detector> MakePrcaDetector(const PrcaOptions& options);

namespace prca {

// A clustered image C (eq. 3.4): one label per pixel, row-major; -1 where the
// pixel is in no cluster. Labels run 0 .. count - 1 in the order of each
// cluster's first pixel in a row-major scan.
struct ClusteredImage {
  int width = 0;
  int height = 0;
  int count = 0;
  std::vector<int32_t> labels;
  int32_t at(int x, int y) const { return labels[static_cast<size_t>(y) * width + x]; }
};

// The modified DBSCAN of eq. 3.4 over the 8-neighbourhood: pixels p and q
// are linked when they are 8-neighbours, ||RGB(p) - RGB(q)||_2 < gamma, and
// both are dense (|Sim| / |Neigh| > rho, |Neigh| = 8, a neighbour outside
// the image never similar); a cluster is a connected component of links
// with at least min_cluster_px pixels. O(pixels) (union-find).
ClusteredImage FormClusters(const ImageView& image, const PrcaOptions& options);

// A cluster's statistics X_i = [<r>, <g>, <b>, omega_i] (eq. 3.5) and its
// centroid, the mean of its pixel centres (pixel (x, y) has centre
// (x + 0.5, y + 0.5)).
struct ClusterStats {
  double r = 0.0;
  double g = 0.0;
  double b = 0.0;
  int omega = 0;  // cardinality, px
  double cx = 0.0;
  double cy = 0.0;
};

// The statistics of clusters 0 .. clustered.count - 1 of `image`.
std::vector<ClusterStats> ClusterStatistics(const ImageView& image, const ClusteredImage& clustered,
                                            PrcaColourNorm colour_norm);

// eta (eq. 3.5): || [<r>, <g>, <b>, omega / omega_big]_m - [...]_s ||_2
// with omega_big = max(omega_m, omega_s). A match error: 0 for identical
// statistics; below 2 (each colour in [0, 1], the size ratio in (0, 1]), and
// at most sqrt(3) under l2 and l1 normalisation, whose colours are unit
// vectors or sum to 1. (`none`, R / 255: black against white is sqrt(3) in
// colour alone.)
double MatchScore(const ClusterStats& model, const ClusterStats& scene);

struct RankedMatch {
  int32_t scene = -1;  // index of the scene cluster
  double eta = 0.0;
  friend bool operator==(const RankedMatch&, const RankedMatch&) = default;
};

// The ranked list L_m^i (eq. 3.6) of one model cluster over the scene
// clusters `candidates` (indices into `scene`): those with eta < lambda,
// best (lowest eta) first, ties by lower index, at most max_matches.
std::vector<RankedMatch> RankedList(const ClusterStats& model_cluster,
                                    std::span<const ClusterStats> scene,
                                    std::span<const int32_t> candidates, double lambda,
                                    int max_matches);

// WR_n (eq. 3.7) of clusters a != b of `clustered`: along the digital line
// (Bresenham) between their centroids' pixels, drawn from the lower label
// to the higher, the number of pixels in neither cluster over the number in
// either (the denominator taken as 1 when no line pixel is in either).
double WalkRatio(const ClusteredImage& clustered, std::span<const ClusterStats> stats, int32_t a,
                 int32_t b);

// WRE (eq. 3.7) = |WR_m - WR_s| / max(WR_m, WR_s), in [0, 1]; 0 when both
// walk ratios are 0.
double WalkRatioError(double model_walk_ratio, double scene_walk_ratio);

// The pair error sum PES(C_m^i, C_s^j) (eq. 3.8), normalised to [0, 1]: for
// every other model cluster q whose ranked list holds a scene cluster r != j,
// MWRE = min_r WRE(WR_n(m: i, q), WR_n(s: j, r)); PES is their mean (0 when
// there is no such q). `lists[q]` is L_m^q; `model_walk(i, q)` and
// `scene_walk(j, r)` give WR_n in the model and the scene.
double PairErrorSum(int i, int32_t j, std::span<const std::vector<RankedMatch>> lists,
                    const std::function<double(int, int)>& model_walk,
                    const std::function<double(int32_t, int32_t)>& scene_walk);

// The weight of one vote: 1 - (eta + PES) / (1 + lambda), in (0, 1] for a
// valid match (eta < lambda, PES in [0, 1]).
double VoteWeight(double eta, double pair_error_sum, double lambda);

// Votes over a rectangle of the image's pixels: width x height pixels, row
// major, whose first is image pixel (x0, y0).
struct Accumulator {
  int x0 = 0;
  int y0 = 0;
  int width = 0;
  int height = 0;
  std::vector<float> votes;
  // The votes at image pixel (x, y), inside the rectangle.
  float at(int x, int y) const {
    return votes[static_cast<size_t>(y - y0) * width + static_cast<size_t>(x - x0)];
  }
};

// Eq. 3.9: adds weight * max(0, 1 - |d - radius_px| / ring_px) to every
// pixel of the accumulator whose centre is at distance d from (cx, cy)
// (image pixel coordinates).
void VoteCircle(Accumulator& accumulator, double cx, double cy, double radius_px, double ring_px,
                double weight);

// Eq. 3.10: the image pixel with the most votes (the first in row-major
// order among equals) and its votes; (-1, -1, 0) for an empty accumulator.
struct Peak {
  int x = -1;
  int y = -1;
  float votes = 0.0f;
};
Peak ArgMax(const Accumulator& accumulator);

// The peak's offset from the argmax pixel's centre, per axis the vertex of
// the parabola through the votes at the argmax and its two neighbours along
// that axis: (l - r) / (2 (l - 2c + r)), in [-0.5, 0.5]. On a tie with one
// neighbour the vertex is the point halfway between the two (+-0.5); 0 along
// an axis where a neighbour is outside the accumulator or the three votes
// are equal. {0, 0} for an empty peak.
struct SubPixel {
  double dx = 0.0;
  double dy = 0.0;
};
SubPixel SubPixelPeak(const Accumulator& accumulator, const Peak& peak);

}  // namespace prca
}  // namespace hcpf::vision
