#include "hcpf/studies/metric_catalogue.h"

namespace hcpf::studies {

std::span<const CatalogueMetric> MetricCatalogue() {
  // The store's columns: keep the order and append (a store made with an
  // older catalogue gets the new columns when it is opened for writing).
  // Ranges. Proportions are fractions of counted events (docs/metrics.md):
  // DA accuracy = CORRECT / scored filter-frames, hijack rate = hijacked
  // encounters / encounters, hijacked fraction = HIJACKED / scored filters,
  // detection precision / recall = matched / detections or targets. IDF1,
  // HOTA, DetA, AssA, MOTP (mean IoU) and F1 lie in [0, 1] but are F-scores,
  // geometric means or means of IoU, not fractions of one kind of event: t
  // intervals cut to [0, 1]. MOTA = 1 − (FN + FP + IDSW) / gt is at most 1
  // and unbounded below. Counts, times and distances are >= 0.
  constexpr MetricRange kProportion = MetricRange::Proportion();
  constexpr MetricRange kUnit = MetricRange::UnitInterval();
  constexpr MetricRange kAtMostOne = MetricRange::AtMost(1.0);
  constexpr MetricRange kNonNegative = MetricRange::NonNegative();
  constexpr MetricRange kCount = MetricRange::NonNegative();
  static constexpr CatalogueMetric kMetrics[] = {
      {"da_accuracy", "metrics.json", "/filters/da_accuracy", true, "data-association accuracy", "",
       kProportion},
      {"hijack_rate", "metrics.json", "/filters/hijack_rate", false, "hijack rate", "",
       kProportion},
      {"hijacked_fraction", "metrics.json", "/filters/hijacked_fraction", false,
       "fraction of filter-frames hijacked", "", kProportion},
      {"swaps", "metrics.json", "/filters/swaps", false, "filter swaps", "", kCount},
      {"idf1", "metrics.json", "/mot/IDF1", true, "IDF1", "", kUnit},
      {"hota", "metrics.json", "/mot/HOTA", true, "HOTA", "", kUnit},
      {"mota", "metrics.json", "/mot/MOTA", true, "MOTA", "", kAtMostOne},
      {"motp", "metrics.json", "/mot/MOTP", true, "MOTP", "", kUnit},
      {"deta", "metrics.json", "/mot/DetA", true, "detection accuracy (DetA)", "", kUnit},
      {"assa", "metrics.json", "/mot/AssA", true, "association accuracy (AssA)", "", kUnit},
      {"ospa", "metrics.json", "/ospa/mean", false, "OSPA distance (mean)", "px", kNonNegative},
      {"ms_per_frame", "manifest.json", "/timings/tracker_s", false, "tracker time per frame", "ms",
       kNonNegative, true},
      {"wall_time_s", "manifest.json", "/timings/total_s", false, "wall time of the run", "s",
       kNonNegative},
      // The hierarchical filter: mean corner displacement of the applied
      // camera motion against the true motion (none: the camera's own motion).
      {"camera_motion_error_px", "metrics.json", "/camera_motion/mean_px", false,
       "camera-motion error (mean corner displacement)", "px", kNonNegative},
      // The same for the similarity closest to the true motion at the corners:
      // the floor any similarity estimate has on these frames.
      {"camera_motion_floor_px", "metrics.json", "/camera_motion/floor/mean_px", false,
       "camera-motion error floor (best similarity)", "px", kNonNegative},
      // Rendered runs: detection quality against pixel-exact truth (IoU >= 0.5).
      {"det_precision", "metrics.json", "/detection/iou/precision", true, "detection precision", "",
       kProportion},
      {"det_recall", "metrics.json", "/detection/iou/recall", true, "detection recall", "",
       kProportion},
      {"det_f1", "metrics.json", "/detection/iou/f1", true, "detection F1", "", kUnit},
      // The condition (visible fraction >= 0.75), the lenient centre
      // rule (what a tracker needs of a small target), and the size the
      // counts are about (sweeps against target size: report.x_metric).
      // The subset scored alone: detections on less visible targets neither
      // true nor false (metrics.json detection.mostly_visible; until
      // 2026-12-07 the recall was the visibility bin's, from the matching
      // over every target).
      {"det_recall_visible", "metrics.json", "/detection/mostly_visible/iou/recall", true,
       "detection recall at visible fraction >= 0.75", "", kProportion},
      {"det_precision_visible", "metrics.json", "/detection/mostly_visible/iou/precision", true,
       "detection precision at visible fraction >= 0.75", "", kProportion},
      {"det_recall_centre", "metrics.json", "/detection/centre/recall", true,
       "detection recall, centre rule", "", kProportion},
      {"det_precision_centre", "metrics.json", "/detection/centre/precision", true,
       "detection precision, centre rule", "", kProportion},
      {"det_size_px", "metrics.json", "/detection/median_size_px", true,
       "median target size (sqrt of box area)", "px", kNonNegative},
      // tracker.management.reacquire: how often a filter was found again, and
      // the share of its scored frames after that in which it was CORRECT.
      {"reacquisitions", "metrics.json", "/filters/reacquisitions/count", false,
       "filters re-acquired", "", kCount},
      {"reacquired_correct_fraction", "metrics.json", "/filters/reacquisitions/correct_fraction",
       true, "fraction of filter-frames CORRECT after a re-acquisition", "", kProportion},
      // Rendered runs: the detector over every score threshold (COCO's
      // 101-point AP at IoU >= 0.5, docs/vision.md).
      {"det_ap", "metrics.json", "/detection/precision_recall/average_precision", true,
       "detection average precision (AP50)", "", kUnit},
      {"det_ap_visible", "metrics.json",
       "/detection/mostly_visible/precision_recall/average_precision", true,
       "detection AP50 at visible fraction >= 0.75", "", kUnit},
      // Target-specific detectors: the share of their boxes on a target
      // whose label names it (NULL for the oracle and model-free detectors).
      {"det_label_accuracy", "metrics.json", "/detection/labels/accuracy", true,
       "detection label accuracy", "", kProportion},
  };
  return kMetrics;
}

const CatalogueMetric* FindMetric(std::string_view name) {
  for (const CatalogueMetric& m : MetricCatalogue()) {
    if (m.name == name) return &m;
  }
  return nullptr;
}

bool MachineDependent(std::string_view metric) {
  const CatalogueMetric* entry = FindMetric(metric);
  return entry != nullptr && entry->file == "manifest.json";
}

bool Descriptive(std::string_view metric) {
  return metric == "det_size_px" || metric == "camera_motion_floor_px" ||
         metric == "reacquisitions";
}

const std::vector<std::string>& MetricNames() {
  static const std::vector<std::string> kNames = [] {
    std::vector<std::string> names;
    for (const CatalogueMetric& m : MetricCatalogue()) names.emplace_back(m.name);
    return names;
  }();
  return kNames;
}

}  // namespace hcpf::studies
