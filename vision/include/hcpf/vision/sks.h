#pragma once
// Simple K Space (SKS; Bhatia 2011, section 2.5, after Krish et al.): a
// generalised-Hough detector of target models. Scale- and rotation-invariant
// Harris-Laplace keypoints (Mikolajczyk & Schmid, "Scale & affine invariant
// interest point detectors", IJCV 60(1), 2004) carry a gradient-orientation
// descriptor; every keypoint of a model remembers where the model's reference
// point (its patch centre) lies relative to it. Each keypoint of the frame
// that matches a model keypoint votes, with the match's confidence psi, for
// where that model's reference point would be (eq. 2.14); the accumulator's
// peak is the detection (eq. 2.15) and the accumulator is the model's map.
// docs/vision.md ("SKS detector") gives the algorithm as implemented, the
// choices where the thesis is silent, and the measured speed.

#include <memory>
#include <span>
#include <string_view>

#include "hcpf/core/fields.h"

namespace hcpf::vision {

// detector.h (which defines Detector) may include this header for
// SksOptions; callers of MakeSksDetector include detector.h.
class Detector;

// Every parameter of the SKS detector. Scales are Gaussian standard
// deviations in frame pixels; Harris responses are in grey levels^4
// (grey levels 0..255, scale-normalised derivatives).
struct SksOptions {
  // Keypoints (Harris-Laplace): integration scales
  // sigma_k = base_sigma * scale_step^k, k = 0 .. scales - 1; derivative
  // scale derivative_ratio * sigma_k (Mikolajczyk & Schmid's s = 0.7).
  double base_sigma = 1.2;
  double scale_step = 1.41421356;  // sqrt(2): two scales per octave
  int scales = 6;                  // sigma_k from 1.2 to 6.8 px
  double derivative_ratio = 0.7;
  double harris_alpha = 0.04;  // det(C) - alpha trace^2(C)
  // Minimum Harris response of a keypoint (grey levels^4): an ideal 90-degree
  // step corner reaches it from about 38 grey levels of contrast at the
  // finest scale (its response is 2.0e6 (contrast / 255)^4).
  double harris_threshold = 1000.0;
  int max_keypoints = 1000;       // per frame: the strongest Harris responses first
  int max_model_keypoints = 200;  // per target model
  // Descriptor: gradient orientations relative to the keypoint's dominant
  // orientation, in an inner disc and `descriptor_sectors` outer sectors of
  // radius descriptor_radius * sigma.
  double orientation_peak_ratio = 0.8;  // extra orientations for peaks >= ratio x highest
  double descriptor_radius = 3.0;       // in units of the keypoint's scale
  int descriptor_bins = 8;              // orientation bins per histogram
  int descriptor_sectors = 4;           // sectors of the outer ring
  // Matching and voting.
  double match_distance = 0.6;  // largest descriptor distance (unit vectors) that votes
  double vote_sigma_px = 3.0;   // Gaussian spread of one vote in the accumulator
  // Pose clustering at a peak: votes agree when their rotations differ by at
  // most rotation_tolerance_deg and their scale ratios by at most a factor
  // scale_tolerance.
  double rotation_tolerance_deg = 20.0;
  double scale_tolerance = 1.3;
  // Detection: the support of the best pose (its agreeing votes, one per
  // keypoint pair, each weighing psi in (0, 1], Gaussian-weighted by distance
  // to the pose's centre) must reach min_votes (1.5: two keypoints agreeing
  // well), and support / (number of model keypoints) must reach min_score.
  double min_votes = 1.5;
  double min_score = 0.1;
  double window_scale = 3.0;  // window side = scale x predicted box side
  double cell_px = 4.0;       // accumulator (map) cell size
  static std::span<const Field<SksOptions>> Fields();
  void Validate(std::string_view prefix = "observation.sks") const;
};

// The SKS detector ("sks"): uses_models() is true. For every model, in model
// order, one map, its vote accumulator (psi-weighted votes per cell, >= 0),
// and at most one detection (Detection::target set to the model's target):
// the best pose-consistent accumulator peak, when its support reaches
// min_votes and support / (number of model keypoints) reaches min_score; that
// ratio, at most 1, is the score. The box is the model's patch turned and
// zoomed by the pose, as an axis-aligned box, clipped to the image. A model
// with a search window is searched in AroundBox(window, window_scale): only
// frame keypoints inside it vote, votes landing outside it are dropped (the
// map is 0 beyond 2 vote_sigma_px of it) and the box is clipped to it.
// Validates `options` (InputError).
//
// Contract (detector.h's, plus): deterministic and independent of `rng`
// (SKS draws nothing). The frame's keypoints are computed once per call and
// shared by all models; when every model has a window and the windows (each
// grown by 3 x the largest scale) cover less than the frame, they are
// computed per window instead, so that a windowed search costs O(window
// pixels). A model patch smaller than 8 px a side has no keypoints and is
// never detected.
std::unique_ptr<Detector> MakeSksDetector(const SksOptions& options);

}  // namespace hcpf::vision
