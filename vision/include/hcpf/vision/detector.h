#pragma once
// The Detector role: one rendered frame in, detections (and, where the method
// has an accumulator, one likelihood map per target model) out. The run
// pipeline builds one detector per run and calls it for every frame; the
// tracker reads what it returns as its Observation.

#include <array>
#include <memory>
#include <optional>
#include <span>
#include <string_view>
#include <vector>

#include "hcpf/core/enum_names.h"
#include "hcpf/core/fields.h"
#include "hcpf/core/image.h"
#include "hcpf/core/rng.h"
#include "hcpf/core/types.h"

namespace hcpf::vision {

// A target's appearance model: the pixels inside its ground-truth box in the
// first frame it is in view (the moment and box `init: ground_truth` uses).
// Manifests label detectors that use it "model from ground truth".
struct TargetModel {
  ObjectId target{};
  int frame = 0;
  BoxPx box;       // where the patch was cut, in that frame's pixels
  RgbImage patch;  // the pixels of `box` rounded outwards and clipped to the frame
  // The patch with its surroundings in the same frame: the patch grown by
  // kModelContextPx on every side, clipped to the frame; the patch's top-left
  // pixel is context pixel (context_x, context_y). Detectors whose filters
  // reach beyond a feature's position (SKS) describe the model's features on
  // it, so that a feature at the patch's edge sees what the same place sees
  // in a frame (the target's outline against its background) rather than
  // the patch's clamped border. Empty (and the offsets 0) where the patch is.
  RgbImage context;
  int context_x = 0;
  int context_y = 0;
};

// The surroundings TargetModel::context keeps on each side of the patch, px:
// at least the reach of SKS's default filters (3 x its largest scale, 21 px).
inline constexpr int kModelContextPx = 32;

// The model of `target` cut from `image` at `box` (rounded outwards to whole
// pixels, clipped to the image), with its context. An empty patch (and
// context) when the box misses the image.
TargetModel CutTargetModel(const ImageView& image, const BoxPx& box, ObjectId target, int frame);

// Where a windowed detector searches for one target: around the tracker's
// prediction of it. `box` is the predicted box; its size also gives the
// target's expected scale.
struct SearchWindow {
  ObjectId target{};
  BoxPx box;
};

// What a detector sees of one frame.
struct DetectorInput {
  ImageView image;  // the frame
  int frame = 0;
  // Earlier frames, newest first: up to Detector::history() of them (fewer at
  // the start of a run).
  std::span<const ImageView> previous;
  // Target models (model-based detectors); empty for model-free ones.
  std::span<const TargetModel> models;
  // Windowed search: one window per model to search near; a model without a
  // window (or an empty list) is searched for in the whole frame.
  std::span<const SearchWindow> windows;
};

struct DetectorOutput {
  // Detections; a target-specific detector sets Detection::target to the
  // model it matched.
  std::vector<Detection> detections;
  // One per model, in model order (model-based detectors): the model's
  // accumulator over the image, cells of `cell_px` pixels, ceil(width /
  // cell_px) x ceil(height / cell_px) of them, values >= 0.
  std::vector<TargetMap> maps;
};

// Contract: Detect is const and stateless (one instance serves every frame
// and every thread); deterministic given its input and `rng` (its only source
// of randomness); every detection box lies inside the image with positive
// width and height; every score is in [0, 1]; every map is of the size given
// above with values >= 0; an empty image or a uniform frame gives no
// detection and no error; cost O(pixels) per model (a windowed search
// O(window pixels)). A contract suite (vision/tests/detector_contract_test.cc)
// runs against every registered detector; the cost clause, a matter of time,
// is measured by bench/detector_cost_bench.cc instead.
class Detector {
 public:
  virtual ~Detector() = default;
  virtual DetectorOutput Detect(const DetectorInput& input, Rng& rng) const = 0;
  // Whether Detect needs target models (and gives target-specific output).
  virtual bool uses_models() const = 0;
  // How many earlier frames Detect reads (DetectorInput::previous).
  virtual int history() const { return 0; }
  virtual std::string_view name() const = 0;
};

// Normalised cross-correlation template matching (OpenCV's TM_CCOEFF_NORMED
// on grey levels): for each model, the best match of its patch in the whole
// frame, or in a window around the target's prediction with the patch scaled
// to the predicted box; a detection where the peak correlation reaches
// `min_correlation`.
struct NccOptions {
  double min_correlation = 0.6;  // peak NCC needed for a detection
  double window_scale = 3.0;     // window side = scale x predicted box side
  double cell_px = 4.0;          // map cell size
  static std::span<const Field<NccOptions>> Fields();
  void Validate(std::string_view prefix = "observation.ncc") const;
};

// Colour-histogram back-projection: each model's hue-saturation histogram is
// back-projected onto the frame, averaged over a box of the model's size, and
// the peak becomes a detection when it stands out from the frame's mean by
// `min_contrast` (so a frame of the model's own colour everywhere detects
// nothing).
struct ColourOptions {
  int hue_bins = 30;
  int saturation_bins = 32;
  double min_contrast = 0.3;  // (peak - mean) / (1 - mean) needed for a detection
  double window_scale = 3.0;  // window side = scale x predicted box side
  double cell_px = 4.0;
  static std::span<const Field<ColourOptions>> Fields();
  void Validate(std::string_view prefix = "observation.colour") const;
};

// Motion-compensated 3-frame differencing, the classic model-free detector
// of wide-area aerial video: frames t-g and t-2g (g = frame_gap) are
// registered to frame t by
// a global similarity (corners tracked by pyramidal Lucas-Kanade, a RANSAC
// fit, OpenCV's estimateAffinePartial2D), each is subtracted from frame t
// (grey levels, lightly smoothed), and pixels that differ from both by more
// than `threshold` form connected components; each component of at least
// `min_area_px` pixels is a detection (its bounding box). Not
// target-specific; nothing before frame 2g. A gap of several frames lets a
// slow vehicle move clear of its earlier positions (at one frame only its
// edges differ).
struct DiffOptions {
  int frame_gap = 5;             // g: frames between the three compared
  double threshold = 25.0;       // grey levels
  int min_area_px = 12;          // smallest component
  double smooth_sigma_px = 1.0;  // stacked-integral-image blur before differencing
  int max_corners = 400;         // corners tracked for the registration
  double ransac_px = 2.0;        // RANSAC inlier distance
  int merge_px = 6;              // moving pixels this close are one detection
  static std::span<const Field<DiffOptions>> Fields();
  void Validate(std::string_view prefix = "observation.diff") const;
};

// The registry of named detectors (DetectorNames, MakeDetector) is in
// hcpf/vision/detectors.h.

}  // namespace hcpf::vision
