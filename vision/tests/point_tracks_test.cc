#include "hcpf/vision/point_tracks.h"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <vector>

#include "hcpf/core/error.h"
#include "hcpf/core/rng.h"

namespace hcpf::vision {
namespace {

constexpr int kFrameWidth = 640;
constexpr int kFrameHeight = 480;

Eigen::Vector2d ApplyInverse(const SimilarityMotion& s, const Eigen::Vector2d& q) {
  const double k = std::exp(-s.log_scale);
  const Eigen::Vector2d d(q.x() - s.tx_px, q.y() - s.ty_px);
  const double c = std::cos(s.rotation_rad), n = std::sin(s.rotation_rad);
  return {k * (c * d.x() + n * d.y()), k * (-n * d.x() + c * d.y())};
}

// Mean over the four corners of a 640 x 480 image of |a(c) - b(c)|, px (the
// metric of metrics::CornerDisplacementPx, between two similarities).
double CornerDisplacement(const SimilarityMotion& a, const SimilarityMotion& b) {
  double sum = 0.0;
  for (const Eigen::Vector2d& c :
       {Eigen::Vector2d(0, 0), Eigen::Vector2d(kFrameWidth, 0),
        Eigen::Vector2d(kFrameWidth, kFrameHeight), Eigen::Vector2d(0, kFrameHeight)}) {
    sum += (Apply(a, c) - Apply(b, c)).norm();
  }
  return sum / 4.0;
}

// A continuous ground texture: value noise (smoothstep-interpolated random
// lattice values) of 32, 9 and 4 px cells, defined for any (x, y) within 64
// px of the 640 x 480 frame, in [0, 1).
class Texture {
 public:
  Texture() {
    Rng rng(2024);
    for (Octave& o : octaves_) {
      o.nx = static_cast<int>((kFrameWidth + 2 * kMargin) / o.cell) + 3;
      o.ny = static_cast<int>((kFrameHeight + 2 * kMargin) / o.cell) + 3;
      o.values.resize(static_cast<size_t>(o.nx) * o.ny);
      for (double& v : o.values) v = rng.Uniform();
    }
  }
  double operator()(double x, double y) const {
    double sum = 0.0;
    for (const Octave& o : octaves_) {
      const double fx = (x + kMargin) / o.cell, fy = (y + kMargin) / o.cell;
      const int i = static_cast<int>(std::floor(fx)), j = static_cast<int>(std::floor(fy));
      const double tx = Smooth(fx - i), ty = Smooth(fy - j);
      const double a = o.At(i, j) + tx * (o.At(i + 1, j) - o.At(i, j));
      const double b = o.At(i, j + 1) + tx * (o.At(i + 1, j + 1) - o.At(i, j + 1));
      sum += o.weight * (a + ty * (b - a));
    }
    return sum;
  }

 private:
  static constexpr double kMargin = 64.0;
  static double Smooth(double t) { return t * t * (3.0 - 2.0 * t); }
  struct Octave {
    double cell;
    double weight;
    int nx = 0, ny = 0;
    std::vector<double> values;
    double At(int i, int j) const {
      i = std::clamp(i, 0, nx - 1);
      j = std::clamp(j, 0, ny - 1);
      return values[static_cast<size_t>(j) * nx + i];
    }
  };
  Octave octaves_[3] = {{32.0, 0.4}, {9.0, 0.35}, {4.0, 0.25}};
};

const Texture& GroundTexture() {
  static const Texture texture;
  return texture;
}

// A vehicle: a bright body with a dark stripe, drawn over the ground.
struct Patch {
  BoxPx box;
};

// The ground seen after the camera moved by `motion` (frame t: the pixel
// whose centre is c shows the ground point motion^-1(c); the identity gives
// frame t-1), with `patches` drawn on top at their boxes (in frame t's
// pixels). Pixel (x, y) has its centre at (x + 0.5, y + 0.5), so `motion` is
// exactly the map from frame t-1 to frame t pixels in the project's
// convention.
RgbImage Render(const SimilarityMotion& motion, const std::vector<Patch>& patches = {}) {
  RgbImage image{.width = kFrameWidth, .height = kFrameHeight};
  image.pixels.resize(3 * static_cast<size_t>(kFrameWidth) * kFrameHeight);
  for (int y = 0; y < kFrameHeight; ++y) {
    for (int x = 0; x < kFrameWidth; ++x) {
      const Eigen::Vector2d g = ApplyInverse(motion, {x + 0.5, y + 0.5});
      double v = 40.0 + 180.0 * GroundTexture()(g.x(), g.y());
      for (const Patch& p : patches) {
        const double u = x + 0.5 - p.box.left, w = y + 0.5 - p.box.top;
        if (u < 0 || w < 0 || u >= p.box.width || w >= p.box.height) continue;
        v = (u > 0.3 * p.box.width && u < 0.45 * p.box.width) ? 20.0 : 245.0;
        if (w > 0.6 * p.box.height && u > 0.6 * p.box.width) v = 120.0;
      }
      uint8_t* px = image.at(x, y);
      const auto level = static_cast<uint8_t>(std::clamp(std::lround(v), 0L, 255L));
      px[0] = px[1] = px[2] = level;
    }
  }
  return image;
}

const SimilarityMotion kMotion{
    .tx_px = 2.3, .ty_px = -1.7, .log_scale = std::log(1.01), .rotation_rad = 0.005};

bool Inside(const BoxPx& box, const Eigen::Vector2d& p, double grow) {
  return p.x() >= box.left - grow && p.x() <= box.left + box.width + grow &&
         p.y() >= box.top - grow && p.y() <= box.top + box.height + grow;
}

struct Accuracy {
  size_t tracks = 0;
  double median_px = 0.0;
  double max_px = 0.0;
};

Accuracy TrackAccuracy(const std::vector<PointTrack>& tracks, const SimilarityMotion& truth) {
  std::vector<double> errors;
  for (const PointTrack& t : tracks) errors.push_back((t.q - Apply(truth, t.p)).norm());
  std::sort(errors.begin(), errors.end());
  if (errors.empty()) return {};
  return {errors.size(), errors[errors.size() / 2], errors.back()};
}

// Frames t-1 and t of a textured ground under a known similarity, rendered
// exactly (no resampling of a rendered image: each frame samples the
// continuous texture at its own pixel centres).
// The defaults track at full resolution with an 11 px window.
// Tolerances: Lucas-Kanade on this texture (8-bit quantisation noise 0.29
// grey levels rms against gradients of ~10 levels/px) is limited by the
// window's unmodelled deformation (1 % scale and 0.005 rad: up to 0.05 px at
// the rim of an 11 px window, nearly symmetric) and the smoothstep texture's
// kinks at its 4 px lattice lines. Measured track errors (391 tracks): median
// 0.026 px, max 0.071 px at full resolution; median 0.047, max 0.115 px with
// the flow at half resolution (each half-resolution pixel is 2 px). The
// bounds are about 2x those: a half-pixel slip in the coordinate conventions
// (0.5 px on every track) or a track off by a pixel fails them. (Without the
// edge band, tracks within 13 px of the frame's edge erred by up to 0.48 px.)
TEST(TrackBackgroundPoints, TracksFollowAKnownSimilarity) {
  const RgbImage previous = Render({});
  const RgbImage current = Render(kMotion);
  const PointTrackerOptions options;
  const std::vector<PointTrack> tracks = TrackBackgroundPoints(previous, current, {}, 0.0, options);
  ASSERT_GE(tracks.size(), 200u);  // 400 corners asked for on a richly textured frame
  EXPECT_LE(tracks.size(), static_cast<size_t>(options.max_corners));
  const Accuracy a = TrackAccuracy(tracks, kMotion);
  EXPECT_LT(a.median_px, 0.05);
  EXPECT_LT(a.max_px, 0.15);
  for (const PointTrack& t : tracks) {
    EXPECT_TRUE(t.q.x() >= 0 && t.q.y() >= 0 && t.q.x() < kFrameWidth && t.q.y() < kFrameHeight);
  }
}

TEST(TrackBackgroundPoints, HalfResolutionFlowMapsBackToFullResolutionPixels) {
  const RgbImage previous = Render({});
  const RgbImage current = Render(kMotion);
  PointTrackerOptions options;
  options.flow_scale = 0.5;
  options.window_px = 11;
  const Accuracy a =
      TrackAccuracy(TrackBackgroundPoints(previous, current, {}, 0.0, options), kMotion);
  ASSERT_GE(a.tracks, 200u);
  EXPECT_LT(a.median_px, 0.1);
  EXPECT_LT(a.max_px, 0.25);
}

// RANSAC's similarity from the image tracks: the corners of the 640 x 480
// image land within 0.1 px of where the true motion takes them (measured:
// 0.003 px; the track errors above averaged over ~390 tracks). A half-pixel
// convention slip would not show here (it moves the fit by (sR - I) 0.5,
// ~0.005 px); the half-resolution test above catches it.
TEST(EstimateSimilarityRansac, RecoversTheSimilarityFromImageTracks) {
  const std::vector<PointTrack> tracks =
      TrackBackgroundPoints(Render({}), Render(kMotion), {}, 0.0, PointTrackerOptions{});
  const std::optional<SimilarityMotion> s = EstimateSimilarityRansac(tracks, RansacOptions{});
  ASSERT_TRUE(s.has_value());
  EXPECT_LT(CornerDisplacement(*s, kMotion), 0.1);
  EXPECT_NEAR(s->log_scale, kMotion.log_scale, 2e-4);
  EXPECT_NEAR(s->rotation_rad, kMotion.rotation_rad, 2e-4);
}

// A vehicle (40 x 20 px, high contrast: the strongest corners of the frame)
// moves (6, 3) px between the frames on a ground that does not move. With
// its frame t-1 box excluded (grown by 4 px) no track starts in the grown
// box; without it, some do.
TEST(TrackBackgroundPoints, ExcludedBoxesGiveNoTracks) {
  const BoxPx box{300, 200, 40, 20};
  const BoxPx moved{306, 203, 40, 20};
  const RgbImage previous = Render({}, {{box}});
  const RgbImage current = Render({}, {{moved}});
  const PointTrackerOptions options;
  const std::vector<BoxPx> exclude = {box};
  const std::vector<PointTrack> masked =
      TrackBackgroundPoints(previous, current, exclude, 4.0, options);
  ASSERT_FALSE(masked.empty());
  for (const PointTrack& t : masked) EXPECT_FALSE(Inside(box, t.p, 4.0)) << t.p.transpose();
  const std::vector<PointTrack> open = TrackBackgroundPoints(previous, current, {}, 4.0, options);
  const auto in_box = std::count_if(open.begin(), open.end(),
                                    [&](const PointTrack& t) { return Inside(box, t.p, 0.0); });
  EXPECT_GE(in_box, 1);
}

// 200 tracks of the similarity with 0.1 px Gaussian noise, 60 of them (30 %)
// replaced by gross outliers (q anywhere in the image). The least-squares
// fit of 140 inliers with 0.1 px noise moves the corners by about
// 0.1 / sqrt(140) x (a few, the lever arm of the corners) ~ 0.02 px
// (measured: 0.019 px); 0.1 px is 5x that, and one outlier kept would move
// them by more than a pixel.
TEST(EstimateSimilarityRansac, RecoversTheSimilarityDespite30PercentOutliers) {
  Rng rng(99);
  std::vector<PointTrack> tracks;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector2d p(rng.Uniform(0, kFrameWidth), rng.Uniform(0, kFrameHeight));
    Eigen::Vector2d q = Apply(kMotion, p) + 0.1 * Eigen::Vector2d(rng.Normal(), rng.Normal());
    if (i % 10 < 3) q = Eigen::Vector2d(rng.Uniform(0, kFrameWidth), rng.Uniform(0, kFrameHeight));
    tracks.push_back({p, q});
  }
  const std::optional<SimilarityMotion> s = EstimateSimilarityRansac(tracks, RansacOptions{});
  ASSERT_TRUE(s.has_value());
  EXPECT_LT(CornerDisplacement(*s, kMotion), 0.1);
}

TEST(EstimateSimilarityRansac, FewerThanThreeTracksGiveNothing) {
  std::vector<PointTrack> tracks;
  for (int n = 0; n < 3; ++n) {
    EXPECT_FALSE(EstimateSimilarityRansac(tracks, RansacOptions{}).has_value()) << n;
    const Eigen::Vector2d p(100.0 * n + 10, 50.0 * n + 20);
    tracks.push_back({p, Apply(kMotion, p)});
  }
  // Three tracks, one not finite: two usable.
  tracks[1].q.x() = std::nan("");
  EXPECT_FALSE(EstimateSimilarityRansac(tracks, RansacOptions{}).has_value());
  // Three exact tracks: the similarity itself.
  tracks[1].q = Apply(kMotion, tracks[1].p);
  const std::optional<SimilarityMotion> s = EstimateSimilarityRansac(tracks, RansacOptions{});
  ASSERT_TRUE(s.has_value());
  EXPECT_LT(CornerDisplacement(*s, kMotion), 1e-3);
}

// A similarity with perspective terms, centred on the image centre.
Eigen::Vector2d MapH(const Eigen::Matrix3d& h, const Eigen::Vector2d& p) {
  const Eigen::Vector3d v = h * Eigen::Vector3d(p.x(), p.y(), 1.0);
  return v.head<2>() / v.z();
}

// The perspective stage (tracker.perspective): tracks of a known
// H = [similarity; g h 1] about the centre, with 0.1 px noise and 20 % gross
// outliers. FitPerspective on the RANSAC similarity's inliers recovers
// (g, h) = (2e-5, -3e-5) within 3e-6: g x at a corner (x ~ 400 px) is then
// right to 0.1 % of |q|, ~0.5 px of the ~3 px the perspective moves it
// (a loose bound: a least-squares fit of ~240 tracks with 0.1 px noise does
// better). Exact tracks with the perspective removed are the numerator
// similarity's; without perspective the fit gives (0, 0).
TEST(FitPerspective, RecoversThePerspectiveTermsOfAHomography) {
  const Eigen::Vector2d centre(0.5 * kFrameWidth, 0.5 * kFrameHeight);
  const Eigen::Vector2d gh(2e-5, -3e-5);
  const Eigen::Matrix3d h = PerspectiveHomography(kMotion, gh, centre);
  Rng rng(5);
  std::vector<PointTrack> tracks;
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector2d p(rng.Uniform(0, kFrameWidth), rng.Uniform(0, kFrameHeight));
    Eigen::Vector2d q = MapH(h, p) + 0.1 * Eigen::Vector2d(rng.Normal(), rng.Normal());
    if (i % 5 == 0) q = Eigen::Vector2d(rng.Uniform(0, kFrameWidth), rng.Uniform(0, kFrameHeight));
    tracks.push_back({p, q});
  }
  const std::optional<SimilarityMotion> guide = EstimateSimilarityRansac(tracks, RansacOptions{});
  ASSERT_TRUE(guide.has_value());
  const std::optional<Eigen::Vector2d> fitted = FitPerspective(tracks, *guide, 2.0, centre);
  ASSERT_TRUE(fitted.has_value());
  EXPECT_NEAR(fitted->x(), gh.x(), 3e-6);
  EXPECT_NEAR(fitted->y(), gh.y(), 3e-6);
  // Exact tracks with the perspective taken out are the numerator similarity's.
  std::vector<PointTrack> exact;
  for (const PointTrack& t : tracks) exact.push_back({t.p, MapH(h, t.p)});
  for (const PointTrack& t : RemovePerspective(exact, gh, centre)) {
    EXPECT_LT((t.q - Apply(kMotion, t.p)).norm(), 1e-9);
  }
  // Without perspective the fit says so.
  std::vector<PointTrack> flat;
  for (const PointTrack& t : exact) flat.push_back({t.p, Apply(kMotion, t.p)});
  const std::optional<Eigen::Vector2d> none = FitPerspective(flat, kMotion, 2.0, centre);
  ASSERT_TRUE(none.has_value());
  EXPECT_LT(none->norm(), 1e-12);
  // Fewer than 8 inliers: nothing.
  const std::vector<PointTrack> few(exact.begin(), exact.begin() + 7);
  EXPECT_FALSE(FitPerspective(few, *guide, 2.0, centre).has_value());
  EXPECT_FALSE(FitPerspective(exact, *guide, 1e-9, centre).has_value()) << "no inlier";
}

// Eight tracks of a plain similarity bunched within 5 px, 0.5 px noise: the
// perspective terms are barely determined, and some fits extrapolate to a
// corner with 1 + g x + h y at 0 or below, behind the camera, where the
// pipeline stopped the run (a review: 22 of 1000 such trials). No fit
// returned may halve or double a corner's scale; some are refused.
TEST(FitPerspective, AFitNoCameraMakesIsNoFit) {
  const Eigen::Vector2d centre(0.5 * kFrameWidth, 0.5 * kFrameHeight);
  int refused = 0, kept = 0;
  for (uint64_t seed = 0; seed < 300; ++seed) {
    Rng rng(seed);
    std::vector<PointTrack> tracks;
    for (int i = 0; i < 8; ++i) {
      const Eigen::Vector2d p(100.0 + rng.Uniform(0, 5), 80.0 + rng.Uniform(0, 5));
      tracks.push_back({p, Apply(kMotion, p) + 0.5 * Eigen::Vector2d(rng.Normal(), rng.Normal())});
    }
    const std::optional<Eigen::Vector2d> gh = FitPerspective(tracks, kMotion, 3.0, centre);
    if (!gh) {
      ++refused;
      continue;
    }
    ++kept;
    for (const double sx : {-1.0, 1.0}) {
      for (const double sy : {-1.0, 1.0}) {
        const double d = 1.0 + gh->x() * sx * centre.x() + gh->y() * sy * centre.y();
        EXPECT_GE(d, 0.5) << seed;
        EXPECT_LE(d, 2.0) << seed;
      }
    }
  }
  EXPECT_GT(refused, 0);
  EXPECT_GT(kept, 0);
}

TEST(TrackBackgroundPoints, EmptyAndUniformFramesGiveNoTracks) {
  EXPECT_TRUE(TrackBackgroundPoints(ImageView{}, ImageView{}, {}, 0.0, {}).empty());
  RgbImage grey{.width = kFrameWidth, .height = kFrameHeight};
  grey.pixels.assign(3 * static_cast<size_t>(kFrameWidth) * kFrameHeight, 128);
  EXPECT_TRUE(TrackBackgroundPoints(grey, grey, {}, 0.0, {}).empty());
  // Uniform frame t-1, textured frame t: no corner to start from.
  EXPECT_TRUE(TrackBackgroundPoints(grey, Render({}), {}, 0.0, {}).empty());
  // Frame t-1 masked everywhere.
  const std::vector<BoxPx> all = {{0, 0, kFrameWidth, kFrameHeight}};
  EXPECT_TRUE(TrackBackgroundPoints(Render({}), Render(kMotion), all, 0.0, {}).empty());
  // A tiny frame: smaller than the Lucas-Kanade window.
  RgbImage tiny{.width = 4, .height = 3};
  tiny.pixels.assign(36, 0);
  tiny.pixels[13] = 255;
  EXPECT_TRUE(TrackBackgroundPoints(tiny, tiny, {}, 0.0, {}).empty());
}

TEST(TrackBackgroundPoints, RejectsFramesOfDifferentSizesAndBadDilation) {
  const RgbImage frame = Render({});
  RgbImage small{.width = 320, .height = 240};
  small.pixels.assign(3 * 320 * 240, 100);
  EXPECT_THROW(TrackBackgroundPoints(frame, small, {}, 0.0, {}), InputError);
  EXPECT_THROW(TrackBackgroundPoints(frame, ImageView{}, {}, 0.0, {}), InputError);
  EXPECT_THROW(TrackBackgroundPoints(frame, frame, {}, -1.0, {}), InputError);
  EXPECT_THROW(TrackBackgroundPoints(frame, frame, {}, std::nan(""), {}), InputError);
}

bool Same(const std::vector<PointTrack>& a, const std::vector<PointTrack>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (a[i].p != b[i].p || a[i].q != b[i].q) return false;
  }
  return true;
}

// The same inputs give the same tracks bit for bit, with OpenCV on one
// thread or on its default pool (Lucas-Kanade runs points in parallel).
TEST(TrackBackgroundPoints, IsDeterministicWhateverTheThreadCount) {
  const RgbImage previous = Render({}, {{BoxPx{300, 200, 40, 20}}});
  const RgbImage current = Render(kMotion, {{BoxPx{310, 205, 40, 20}}});
  const std::vector<BoxPx> exclude = {{100, 100, 30, 30}};
  const std::vector<PointTrack> first =
      TrackBackgroundPoints(previous, current, exclude, 3.0, PointTrackerOptions{});
  ASSERT_FALSE(first.empty());
  EXPECT_TRUE(Same(first, TrackBackgroundPoints(previous, current, exclude, 3.0, {})));
  const int threads = cv::getNumThreads();
  cv::setNumThreads(1);
  const std::vector<PointTrack> one = TrackBackgroundPoints(previous, current, exclude, 3.0, {});
  cv::setNumThreads(4);
  const std::vector<PointTrack> four = TrackBackgroundPoints(previous, current, exclude, 3.0, {});
  cv::setNumThreads(threads);
  EXPECT_TRUE(Same(first, one));
  EXPECT_TRUE(Same(first, four));
  const std::optional<SimilarityMotion> a = EstimateSimilarityRansac(first, {});
  const std::optional<SimilarityMotion> b = EstimateSimilarityRansac(first, {});
  ASSERT_TRUE(a.has_value());
  EXPECT_EQ(*a, *b);
}

template <class O>
void ExpectRejected(O options, std::string_view key) {
  try {
    options.Validate();
    ADD_FAILURE() << key << " accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().key, key);
    EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
  }
}

TEST(PointTrackerOptions, DefaultsValidateAndOutOfRangeValuesNameTheirKey) {
  EXPECT_NO_THROW(PointTrackerOptions{}.Validate());
  EXPECT_NO_THROW(RansacOptions{}.Validate());
  const std::string p = "tracker.point_tracker.";
  PointTrackerOptions o;
  o.max_corners = 501;  // the scene filter's cap
  ExpectRejected(o, p + "max_corners");
  o = {};
  o.max_corners = 0;
  ExpectRejected(o, p + "max_corners");
  o = {};
  o.quality_level = 0.0;
  ExpectRejected(o, p + "quality_level");
  o = {};
  o.min_distance_px = -1.0;
  ExpectRejected(o, p + "min_distance_px");
  o = {};
  o.corner_scale = 1.5;
  ExpectRejected(o, p + "corner_scale");
  o = {};
  o.flow_scale = 0.1;
  ExpectRejected(o, p + "flow_scale");
  o = {};
  o.window_px = 3;
  ExpectRejected(o, p + "window_px");
  o = {};
  o.pyramid_levels = -1;
  ExpectRejected(o, p + "pyramid_levels");
  o = {};
  o.forward_backward_px = std::nan("");
  ExpectRejected(o, p + "forward_backward_px");
  // TrackBackgroundPoints validates too.
  o = {};
  o.window_px = 1000;
  const RgbImage frame = Render({});
  EXPECT_THROW(TrackBackgroundPoints(frame, frame, {}, 0.0, o), InputError);

  RansacOptions r;
  r.threshold_px = 0.0;
  ExpectRejected(r, "tracker.ransac.threshold_px");
  r = {};
  r.max_iterations = 0;
  ExpectRejected(r, "tracker.ransac.max_iterations");
  r = {};
  r.confidence = 1.0;
  ExpectRejected(r, "tracker.ransac.confidence");
  r = {};
  r.refine_iterations = -1;
  ExpectRejected(r, "tracker.ransac.refine_iterations");
  EXPECT_THROW(EstimateSimilarityRansac({}, r), InputError);
}

}  // namespace
}  // namespace hcpf::vision
