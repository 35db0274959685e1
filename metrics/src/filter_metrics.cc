#include "hcpf/metrics/filter_metrics.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <unordered_map>

#include "hcpf/core/error.h"
#include "hcpf/metrics/mot_metrics.h"

namespace hcpf::metrics {
namespace {

double Size(const TargetState& t) { return std::max(t.width, t.height); }

// Index of the target whose gate contains (x, y), nearest first; -1 when none.
int CoveredTarget(const std::vector<TargetState>& targets, double x, double y, double gate_factor) {
  int best = -1;
  double best_d = 0.0;
  for (size_t i = 0; i < targets.size(); ++i) {
    const TargetState& t = targets[i];
    const double d = std::hypot(x - t.centre_x, y - t.centre_y);
    if (d <= gate_factor * Size(t) / 2.0 && (best < 0 || d < best_d)) {
      best = static_cast<int>(i);
      best_d = d;
    }
  }
  return best;
}

std::vector<std::pair<int64_t, int64_t>> MapFilters(const FilterSequence& seq,
                                                    double iou_threshold) {
  if (seq.birth_target) return *seq.birth_target;
  Sequence boxes;
  boxes.frames.resize(seq.frames.size());
  for (size_t t = 0; t < seq.frames.size(); ++t) {
    for (const TargetState& o : seq.frames[t].targets) {
      boxes.frames[t].gt.push_back(
          {o.id, BoxPx::FromCentre(o.centre_x, o.centre_y, o.width, o.height)});
    }
    for (const FilterEstimate& f : seq.frames[t].filters)
      boxes.frames[t].hyp.push_back({f.id, f.box});
  }
  std::vector<std::pair<int64_t, int64_t>> mapping;
  for (const auto& [target, filter] : IdentityMatching(boxes, iou_threshold))
    mapping.emplace_back(filter, target);
  std::sort(mapping.begin(), mapping.end());
  return mapping;
}

}  // namespace

const char* FilterStateName(FilterState state) {
  switch (state) {
    case FilterState::kCorrect:
      return "CORRECT";
    case FilterState::kSwapped:
      return "SWAPPED";
    case FilterState::kHijacked:
      return "HIJACKED";
    case FilterState::kStrayed:
      return "STRAYED";
    case FilterState::kLost:
      return "LOST";
    case FilterState::kCoasting:
      return "COASTING";
  }
  return "?";
}

std::span<const Field<FilterMetricsOptions>> FilterMetricsOptions::Fields() {
  using O = FilterMetricsOptions;
  static const std::vector<Field<O>> fields = {
      NumberField("iou_threshold", &O::iou_threshold, AboveUpTo(0, 1), "",
                  "IDF1 mapping of filters to targets (filter-level metrics without "
                  "ground-truth births); CLEAR/Identity/HOTA use TrackEval's fixed rules"),
      NumberField("gate_factor", &O::gate_factor, Closed(0.01, 100), "",
                  "a filter covers a target within gate_factor · max(w, h)/2 of its centre"),
      NumberField("encounter_factor", &O::encounter_factor, Closed(0.01, 100), "",
                  "an encounter: centres closer than encounter_factor · mean size"),
      IntegerField("post_window", &O::post_window, 0, 100'000, "frames",
                   "frames after an encounter ends that still count as after it"),
      NumberField("min_visible", &O::min_visible, Closed(0, 1), "",
                  "below this visible fraction the target's own filter is COASTING"),
      IntegerField("visible_bins", &O::visible_bins, 1, 100, "",
                   "bins of DA accuracy by visible fraction"),
  };
  return fields;
}

void FilterMetricsOptions::Validate() const { CheckFields(*this, Fields(), "metrics"); }

namespace {

// Whether a filter's own target is scored at a frame: there, and at least
// min_visible visible (else the filter is COASTING unless on another target).
bool OwnTargetScored(const TargetState* target, const FilterMetricsOptions& options) {
  return target != nullptr && target->visible_fraction >= options.min_visible;
}

}  // namespace

FilterMetrics ComputeFilterMetrics(const FilterSequence& seq, const FilterMetricsOptions& options) {
  options.Validate();
  FilterMetrics out;
  out.mapping = MapFilters(seq, options.iou_threshold);
  std::unordered_map<int64_t, int64_t> target_of;                // filter -> g(k)
  std::unordered_map<int64_t, std::vector<int64_t>> filters_of;  // target -> its own filters
  for (const auto& [filter, target] : out.mapping) {
    target_of[filter] = target;
    filters_of[target].push_back(filter);
  }
  const int bins = options.visible_bins;
  out.da_by_visibility.resize(bins);
  for (int b = 0; b < bins; ++b) {
    out.da_by_visibility[b].lo = static_cast<double>(b) / bins;
    out.da_by_visibility[b].hi = static_cast<double>(b + 1) / bins;
  }
  const int num_frames = static_cast<int>(seq.frames.size());
  // Per frame: filter id -> state, for the encounter evaluation.
  std::vector<std::unordered_map<int64_t, FilterState>> state_at(num_frames);
  double mass_sum = 0.0;
  int64_t hijacked_total = 0;
  std::vector<int> covered;
  for (int t = 0; t < num_frames; ++t) {
    const FilterFrame& f = seq.frames[t];
    std::unordered_map<int64_t, int> target_index;
    for (size_t i = 0; i < f.targets.size(); ++i)
      target_index[f.targets[i].id] = static_cast<int>(i);
    // Which target each filter covers, and which filters cover each target.
    covered.assign(f.filters.size(), -1);
    std::unordered_map<int64_t, std::vector<int64_t>> covering;  // target id -> filters covering it
    for (size_t k = 0; k < f.filters.size(); ++k) {
      const BoxPx& b = f.filters[k].box;
      covered[k] = CoveredTarget(f.targets, b.centre_x(), b.centre_y(), options.gate_factor);
      if (covered[k] >= 0) covering[f.targets[covered[k]].id].push_back(f.filters[k].id);
    }
    auto covers = [&](int64_t filter, int64_t target) {
      const auto it = covering.find(target);
      return it != covering.end() &&
             std::find(it->second.begin(), it->second.end(), filter) != it->second.end();
    };
    int64_t scored_now = 0;
    int64_t hijacked_now = 0;
    for (size_t k = 0; k < f.filters.size(); ++k) {
      const FilterEstimate& filter = f.filters[k];
      FilterFrameRecord rec;
      rec.frame = t;
      rec.filter = filter.id;
      const auto g_it = target_of.find(filter.id);
      rec.target = g_it == target_of.end() ? -1 : g_it->second;
      const auto own_it = rec.target >= 0 ? target_index.find(rec.target) : target_index.end();
      const bool own_present = own_it != target_index.end();
      const TargetState* own = own_present ? &f.targets[own_it->second] : nullptr;
      const double own_visible = own != nullptr ? own->visible_fraction : 0.0;
      const bool coasting = !OwnTargetScored(own, options);
      rec.covered = covered[k] >= 0 ? f.targets[covered[k]].id : -1;
      if (rec.covered >= 0 && rec.covered == rec.target) {
        rec.state = coasting ? FilterState::kCoasting : FilterState::kCorrect;
      } else if (rec.covered >= 0) {
        // Covers another target o: SWAPPED when o's own filter covers g(k),
        // HIJACKED when o's own filter covers o, STRAYED otherwise.
        bool swapped = false, hijacked = false;
        const auto own_filters = filters_of.find(rec.covered);
        if (own_filters != filters_of.end()) {
          for (int64_t other : own_filters->second) {
            if (other == filter.id) continue;
            if (own_present && covers(other, rec.target)) swapped = true;
            if (covers(other, rec.covered)) hijacked = true;
          }
        }
        rec.state = swapped && !coasting ? FilterState::kSwapped
                    : hijacked           ? FilterState::kHijacked
                                         : FilterState::kStrayed;
      } else {
        rec.state = coasting ? FilterState::kCoasting : FilterState::kLost;
      }
      if (filter.particles) {
        const ParticleCloud& cloud = *filter.particles;
        double total = 0.0, other = 0.0;
        for (size_t i = 0; i < cloud.x.size(); ++i) {
          const double w = cloud.weight.empty() ? 1.0 : cloud.weight[i];
          total += w;
          const int on = CoveredTarget(f.targets, cloud.x[i], cloud.y[i], options.gate_factor);
          if (on >= 0 && f.targets[on].id != rec.target) other += w;
        }
        rec.mass_on_other = total > 0.0 ? other / total : 0.0;
        mass_sum += rec.mass_on_other;
        ++out.frames_with_cloud;
      }
      ++out.state_counts[static_cast<int>(rec.state)];
      if (rec.state != FilterState::kCoasting) {
        ++scored_now;
        const bool correct = rec.state == FilterState::kCorrect;
        const int bin = std::clamp(static_cast<int>(own_visible * bins), 0, bins - 1);
        ++out.da_by_visibility[bin].scored;
        out.da_by_visibility[bin].correct += correct;
      }
      if (rec.state == FilterState::kHijacked) ++hijacked_now;
      state_at[t][filter.id] = rec.state;
      out.records.push_back(rec);
    }
    out.scored += scored_now;
    hijacked_total += hijacked_now;
    // A frame with no scored filter: NaN (null in metrics.json), as overall.
    out.hijacked_fraction.push_back(scored_now > 0 ? static_cast<double>(hijacked_now) / scored_now
                                                   : std::numeric_limits<double>::quiet_NaN());
  }
  const int64_t correct = out.state_counts[static_cast<int>(FilterState::kCorrect)];
  // A fraction of nothing is not a measurement (a third bad-input audit: a
  // run whose targets never entered the image reported DA accuracy 0, and a
  // sweep averaged it in): NaN, null in metrics.json, NULL in a store.
  constexpr double kNothing = std::numeric_limits<double>::quiet_NaN();
  out.da_accuracy = out.scored > 0 ? static_cast<double>(correct) / out.scored : kNothing;
  out.hijacked_fraction_overall =
      out.scored > 0 ? static_cast<double>(hijacked_total) / out.scored : kNothing;
  for (VisibilityBin& b : out.da_by_visibility) {
    b.accuracy = b.scored > 0 ? static_cast<double>(b.correct) / b.scored : kNothing;
  }
  out.mean_mass_on_other = out.frames_with_cloud > 0 ? mass_sum / out.frames_with_cloud : kNothing;

  // Encounters: maximal runs of frames in which two targets are both present and
  // closer than encounter_factor * their mean size (size = max(w, h)).
  std::map<std::pair<int64_t, int64_t>, int> open;  // pair -> first frame of the running interval
  auto close_encounter = [&](const std::pair<int64_t, int64_t>& pair, int first, int last) {
    Encounter e{pair.first, pair.second, first, last,
                std::min(last + options.post_window, num_frames - 1)};
    const auto fa = filters_of.find(pair.first);
    const auto fb = filters_of.find(pair.second);
    if (fa == filters_of.end() || fb == filters_of.end()) return;  // a target without a filter
    // Each target's filters that exist at the evaluation frame, in their
    // states. A target none of whose filters exists then (deleted, or not
    // yet born) is LOST while it is there and at least min_visible visible,
    // else COASTING, as an existing filter's own target would make it: a
    // filter deleted after its target left the image made a clean encounter
    // hijacked (an audit).
    const auto& at_eval = state_at[e.eval_frame];
    const std::vector<TargetState>& targets_then = seq.frames[e.eval_frame].targets;
    const auto states_of = [&](int64_t target, const std::vector<int64_t>& filters) {
      std::vector<FilterState> states;
      for (const int64_t filter : filters) {
        const auto it = at_eval.find(filter);
        if (it != at_eval.end()) states.push_back(it->second);
      }
      if (states.empty()) {
        const auto it = std::find_if(targets_then.begin(), targets_then.end(),
                                     [target](const TargetState& o) { return o.id == target; });
        const bool scored = OwnTargetScored(it != targets_then.end() ? &*it : nullptr, options);
        states.push_back(scored ? FilterState::kLost : FilterState::kCoasting);
      }
      return states;
    };
    bool all_swapped = true;
    for (const auto& [target, filters] :
         {std::pair{pair.first, &fa->second}, std::pair{pair.second, &fb->second}}) {
      for (const FilterState s : states_of(target, *filters)) {
        if (s == FilterState::kHijacked || s == FilterState::kStrayed || s == FilterState::kLost)
          e.hijacked = true;
        if (s != FilterState::kSwapped) all_swapped = false;
      }
    }
    e.swapped = all_swapped;
    out.hijacked_encounters += e.hijacked;
    out.swaps += e.swapped;
    out.encounters.push_back(e);
  };
  for (int t = 0; t < num_frames; ++t) {
    const auto& targets = seq.frames[t].targets;
    std::map<std::pair<int64_t, int64_t>, bool> close_now;
    for (size_t i = 0; i < targets.size(); ++i) {
      for (size_t j = i + 1; j < targets.size(); ++j) {
        const TargetState& a = targets[i];
        const TargetState& b = targets[j];
        const double mean_size = 0.5 * (Size(a) + Size(b));
        if (std::hypot(a.centre_x - b.centre_x, a.centre_y - b.centre_y) <
            options.encounter_factor * mean_size) {
          close_now[{std::min(a.id, b.id), std::max(a.id, b.id)}] = true;
        }
      }
    }
    for (auto it = open.begin(); it != open.end();) {
      if (!close_now.count(it->first)) {
        close_encounter(it->first, it->second, t - 1);
        it = open.erase(it);
      } else {
        ++it;
      }
    }
    for (const auto& [pair, unused] : close_now) open.try_emplace(pair, t);
  }
  for (const auto& [pair, first] : open) close_encounter(pair, first, num_frames - 1);
  std::sort(out.encounters.begin(), out.encounters.end(),
            [](const Encounter& a, const Encounter& b) {
              return std::tie(a.first_frame, a.target_a, a.target_b) <
                     std::tie(b.first_frame, b.target_a, b.target_b);
            });
  // A rate over no encounter is of nothing (NaN, null in metrics.json), not
  // 0: a run whose targets never met says nothing about hijacking.
  out.hijack_rate = out.encounters.empty()
                        ? kNothing
                        : static_cast<double>(out.hijacked_encounters) / out.encounters.size();

  // Re-acquisitions. Each one's frames run from its own frame (the tracker
  // reports a re-seeded filter's new estimate there) to the frame before the
  // same filter's next one, or to the last frame, so together they are the
  // filter's frames from its first re-acquisition on.
  if (seq.reacquired) {
    Reacquisitions& r = out.reacquisitions.emplace();
    r.count = static_cast<int64_t>(seq.reacquired->size());
    std::map<int64_t, int> first_reacquired;
    for (const auto& [frame, filter] : *seq.reacquired) first_reacquired.try_emplace(filter, frame);
    for (const FilterFrameRecord& rec : out.records) {
      const auto first = first_reacquired.find(rec.filter);
      if (first == first_reacquired.end() || rec.frame < first->second ||
          rec.state == FilterState::kCoasting) {
        continue;
      }
      ++r.scored_after;
      r.correct_after += rec.state == FilterState::kCorrect;
    }
  }
  return out;
}

}  // namespace hcpf::metrics
