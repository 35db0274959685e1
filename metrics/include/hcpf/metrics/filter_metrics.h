#pragma once
// Filter-level metrics, the thesis's own measures (DESIGN.md "Metrics";
// docs/metrics.md has the full definitions with examples):
//   per filter per frame state CORRECT / SWAPPED / HIJACKED / STRAYED / LOST / COASTING,
//   data-association accuracy, encounters, hijack rate, swap count, per-frame
//   hijacked fraction, accuracy binned by visible fraction, and the particle
//   mass of each filter lying on another target.
//
// Each filter k has a target g(k): the target it was born for (given), or else
// its Identity (IDF1) match computed from the filters' boxes. Filter k *covers*
// target o at frame t when its estimate's centre lies within
// gate_factor * max(w_o, h_o) / 2 of o's centre; the nearest such target wins.

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "hcpf/core/fields.h"
#include "hcpf/core/types.h"

namespace hcpf::metrics {

struct FilterMetricsOptions {
  double gate_factor = 1.0;       // > 0, coverage radius in half target sizes
  double encounter_factor = 2.0;  // > 0, encounter when centre distance < factor * mean size
  int post_window = 10;           // >= 0 frames after an encounter ends
  double min_visible = 0.1;       // in [0, 1]: below, the target's own filter is COASTING
  double iou_threshold = 0.5;     // (0, 1]: IDF1 mapping of filters to targets
  int visible_bins = 4;           // >= 1 equal-width bins of the visible fraction on [0, 1]
  // The `metrics.*` keys of these options (core/fields.h).
  static std::span<const Field<FilterMetricsOptions>> Fields();
  // Throws hcpf::InputError naming the field ("metrics.gate_factor", ...).
  void Validate() const;
};

struct TargetState {
  int64_t id = 0;
  double centre_x = 0.0, centre_y = 0.0;  // pixels
  double width = 0.0, height = 0.0;       // pixels
  double visible_fraction = 1.0;          // 0..1
};

// Particle positions (pixels) and linear, non-negative weights (empty weights
// = uniform).
struct ParticleCloud {
  std::vector<double> x, y, weight;
};

struct FilterEstimate {
  int64_t id = 0;
  BoxPx box;  // the estimate; its centre decides coverage
  std::optional<ParticleCloud> particles;
};

// Everything in frame t: targets present and filters alive.
struct FilterFrame {
  std::vector<TargetState> targets;
  std::vector<FilterEstimate> filters;
};

struct FilterSequence {
  std::vector<FilterFrame> frames;
  // filter id -> target id it was born for (init: ground_truth). When absent the
  // IDF1 matching of filter boxes to target boxes decides.
  std::optional<std::vector<std::pair<int64_t, int64_t>>> birth_target;
  // (frame index, filter id): the filter was re-seeded, or born again, from
  // its own target's detections at the end of that frame, in frame order.
  // Absent when the tracker did not re-acquire (management.reacquire: none).
  std::optional<std::vector<std::pair<int, int64_t>>> reacquired;
};

enum class FilterState { kCorrect, kSwapped, kHijacked, kStrayed, kLost, kCoasting };
inline constexpr int kNumFilterStates = 6;
const char* FilterStateName(FilterState state);

struct FilterFrameRecord {
  int frame = 0;  // index into FilterSequence::frames
  int64_t filter = 0;
  int64_t target = -1;   // g(k), -1 when the filter has none
  int64_t covered = -1;  // target covered, -1 when none
  FilterState state = FilterState::kLost;
  double mass_on_other = -1.0;  // share of particle weight on a target != g(k); -1 without cloud
};

struct Encounter {
  int64_t target_a = 0, target_b = 0;   // a < b
  int first_frame = 0, last_frame = 0;  // inclusive
  int eval_frame = 0;                   // min(last_frame + post_window, last frame of the sequence)
  // A filter of a or b HIJACKED/STRAYED/LOST at eval_frame, or gone while its
  // target is in view and at least min_visible visible (gone otherwise counts
  // as COASTING, not as hijacked).
  bool hijacked = false;
  bool swapped = false;  // the filters of a and b both SWAPPED at eval_frame
};

struct VisibilityBin {
  double lo = 0.0, hi = 1.0;
  int64_t scored = 0, correct = 0;
  double accuracy = 0.0;  // correct / scored, NaN when nothing scored
};

// What became of the filters re-acquired (FilterSequence::reacquired): over
// each re-acquired filter's frames from the frame of its first re-acquisition
// on (that frame included, to the end), the scored filter-frames and the
// CORRECT ones.
struct Reacquisitions {
  int64_t count = 0;
  int64_t scored_after = 0;
  int64_t correct_after = 0;
};

struct FilterMetrics {
  std::vector<std::pair<int64_t, int64_t>> mapping;  // filter id -> target id used
  std::vector<FilterFrameRecord> records;            // frame-major, filters in input order
  std::array<int64_t, kNumFilterStates> state_counts{};
  int64_t scored = 0;        // filter-frames not COASTING
  double da_accuracy = 0.0;  // CORRECT / scored (NaN when nothing scored)
  std::vector<Encounter> encounters;
  int64_t hijacked_encounters = 0;
  int64_t swaps = 0;
  double hijack_rate = 0.0;                // hijacked encounters / encounters (NaN: none)
  std::vector<double> hijacked_fraction;   // per frame: HIJACKED / scored filters (NaN: none)
  double hijacked_fraction_overall = 0.0;  // HIJACKED / scored over all frames (NaN: none)
  std::vector<VisibilityBin> da_by_visibility;
  double mean_mass_on_other = 0.0;  // over filter-frames with a cloud (NaN: none)
  int64_t frames_with_cloud = 0;
  std::optional<Reacquisitions> reacquisitions;  // when FilterSequence::reacquired is set
};

FilterMetrics ComputeFilterMetrics(const FilterSequence& seq, const FilterMetricsOptions& options);

}  // namespace hcpf::metrics
