#pragma once
// Image evidence of the camera's frame-to-frame motion: background corners of
// frame t-1 tracked into frame t (PointTrack, core/similarity_motion.h), and
// the RANSAC baseline that fits one similarity to them. The scene filter
// (tracker/) weighs its motion hypotheses by the tracks; the baseline is what
// it is compared with (docs/vision.md, "Background point tracks and the
// RANSAC baseline", has the measurements behind every default).

#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "hcpf/core/fields.h"
#include "hcpf/core/image.h"
#include "hcpf/core/similarity_motion.h"
#include "hcpf/core/types.h"

namespace hcpf::vision {

// Background point tracking (`tracker.point_tracker.*`): Shi-Tomasi
// corners (OpenCV's goodFeaturesToTrack, 3 x 3 blocks) of frame t-1's grey
// levels resized to `corner_scale`, away from the excluded boxes, tracked into
// frame t by pyramidal Lucas-Kanade (calcOpticalFlowPyrLK) on the grey levels
// resized to `flow_scale` (1: full resolution), and kept when the track is
// found and, tracked back from frame t, returns within `forward_backward_px`
// of where it started.
struct PointTrackerOptions {
  // Most corners tracked (the scene filter handles at most 500 points).
  // Defaults: measured on the climb scenario's rendered frames
  // (docs/vision.md): full-resolution flow reaches the similarity model's
  // floor there, 7 % below half-resolution flow, at 2.6 ms a frame.
  int max_corners = 400;
  // A corner's smaller structure-tensor eigenvalue must reach this fraction of
  // the strongest corner's in the frame (goodFeaturesToTrack's qualityLevel).
  double quality_level = 0.01;
  // Closest two corners may be, full-resolution px.
  double min_distance_px = 16.0;
  // Resolution corners are found at, as a fraction of the frame's (0.5: the
  // BoT-SORT GMC "sparseOptFlow" recipe, a quarter of the pixels).
  double corner_scale = 0.5;
  // Resolution Lucas-Kanade runs at, as a fraction of the frame's.
  double flow_scale = 1.0;
  // Side of Lucas-Kanade's square window, px of the image it runs on (at
  // flow_scale).
  int window_px = 11;
  // Pyramid levels above the image Lucas-Kanade runs on (0: that image only).
  int pyramid_levels = 3;
  // Largest distance, full-resolution px, between a corner and its track
  // followed back from frame t into frame t-1; 0 switches the check off.
  double forward_backward_px = 0.0;
  static std::span<const Field<PointTrackerOptions>> Fields();
  void Validate(std::string_view prefix = "tracker.point_tracker") const;
};

// Tracks of background points from `previous` (frame t-1) into `current`
// (frame t). p is a corner of `previous`, q where it is found in `current`,
// both in full-resolution pixels of the images as given, with the project's
// pixel convention (pixel (0, 0) covers [0, 1) x [0, 1): a pixel's centre is
// at +0.5; docs/conventions.md). No corner is taken from a pixel that
// overlaps any `exclude` box grown by `mask_dilation_px` on every side (the
// targets' estimates: moving targets must not explain the scene), so no
// track's p lies inside such a grown box. Both p and q lie at least half a
// Lucas-Kanade window (window_px / 2 / flow_scale full-resolution px) inside
// the frame's edge, where the window reaches past the image and biases the
// track. At most max_corners tracks.
//
// Preconditions: `options` valid (Validate; throws InputError otherwise);
// mask_dilation_px finite and >= 0 (else InputError); both images of the
// same size (else InputError). An empty image pair, a uniform frame t-1 or a
// frame t-1 masked everywhere gives an empty vector, no error.
// Order: the corners' order (strongest first). Deterministic: the same inputs
// give the same tracks bit for bit, whatever OpenCV's thread count. Const and
// stateless: safe to call from several threads. Cost: O(pixels) for the grey
// levels, resizing and pyramids, plus O(max_corners x window_px^2 x levels)
// for the two Lucas-Kanade passes (forward and, when the check is on,
// backward).
std::vector<PointTrack> TrackBackgroundPoints(const ImageView& previous, const ImageView& current,
                                              std::span<const BoxPx> exclude,
                                              double mask_dilation_px,
                                              const PointTrackerOptions& options);

// The RANSAC baseline (`tracker.ransac.*`): OpenCV's estimateAffinePartial2D
// with cv::RANSAC, a 4-degree-of-freedom similarity (rotation, uniform scale,
// translation) fitted to the tracks, refined by Levenberg-Marquardt on the
// inliers.
struct RansacOptions {
  // A track is an inlier when S(p) lands within this of q, px.
  double threshold_px = 2.0;
  // Most RANSAC iterations (fewer when `confidence` is reached).
  int max_iterations = 2000;
  // Probability of having drawn an outlier-free sample that ends the search.
  double confidence = 0.99;
  // Levenberg-Marquardt iterations on the inliers (0: none).
  int refine_iterations = 10;
  static std::span<const Field<RansacOptions>> Fields();
  void Validate(std::string_view prefix = "tracker.ransac") const;
};

// The similarity S with S(p) ~ q over the tracks' RANSAC inliers
// (SimilarityMotion: p' = exp(log_scale) R(rotation) p + t, in the tracks'
// coordinates), or nullopt when fewer than 3 tracks have finite coordinates
// (those that do not are ignored) or OpenCV finds no model.
// Preconditions: `options` valid (Validate; throws InputError otherwise).
// Deterministic (OpenCV seeds its RANSAC with a fixed state; the same tracks
// in the same order give the same result). Const and stateless. Cost: O(n x
// iterations).
std::optional<SimilarityMotion> EstimateSimilarityRansac(std::span<const PointTrack> tracks,
                                                         const RansacOptions& options);

// `tracker.perspective.*`: the scene filter's perspective stage (docs/tracker.md).
struct PerspectiveOptions {
  // Whether the scene filter fits the perspective terms each frame.
  bool enabled = false;
  // Tracks within this of the RANSAC similarity enter the fit, px.
  double inlier_px = 2.0;
  static std::span<const Field<PerspectiveOptions>> Fields();
  void Validate(std::string_view prefix = "tracker.perspective") const;
};

// The perspective terms (g, h) of a frame-to-frame homography of the form
//   H = [a -b tx; b a ty; g h 1]  (a similarity with perspective)
// in coordinates centred on `centre` (x = p - centre), fitted by linear least
// squares over the tracks that `guide` maps within `inlier_px` of their q:
// q (1 + g x + h y) = a x + t (complex form; every track two rows of a
// 6-parameter system, DLT-style). nullopt with fewer than 8 such tracks, a
// system that is not positive definite, or a fit whose denominator
// 1 + g x + h y leaves [kMinPerspectiveDenominator, 1 / that] at a corner of
// the image centred on `centre` (2 centre.x wide, 2 centre.y high): a
// corner's scale halved or doubled from one frame to the next is no camera's
// motion, and at 0 the corner is behind the camera. Cost O(n).
inline constexpr double kMinPerspectiveDenominator = 0.5;
std::optional<Eigen::Vector2d> FitPerspective(std::span<const PointTrack> tracks,
                                              const SimilarityMotion& guide, double inlier_px,
                                              const Eigen::Vector2d& centre);

// The homography in pixels of similarity `numerator` (pixels) with perspective
// terms `gh` in coordinates centred on `centre`: q = S(p) / (1 + g x + h y) in
// centred coordinates, where S is `numerator` re-expressed about `centre`.
Eigen::Matrix3d PerspectiveHomography(const SimilarityMotion& numerator, const Eigen::Vector2d& gh,
                                      const Eigen::Vector2d& centre);

// The tracks with q replaced by q' = centre + (q - centre) (1 + g x + h y):
// the points a similarity maps p to when the motion is
// PerspectiveHomography(S, gh, centre).
std::vector<PointTrack> RemovePerspective(std::span<const PointTrack> tracks,
                                          const Eigen::Vector2d& gh, const Eigen::Vector2d& centre);

}  // namespace hcpf::vision
