#include "hcpf/studies/metric_catalogue.h"

namespace hcpf::studies {

std::span<const CatalogueMetric> MetricCatalogue() {
  // The store's columns: keep the order and append (a store made with an
  // older catalogue gets the new columns when it is opened for writing).
  static constexpr CatalogueMetric kMetrics[] = {
      {"da_accuracy", "metrics.json", "/filters/da_accuracy", true, "data-association accuracy",
       ""},
      {"hijack_rate", "metrics.json", "/filters/hijack_rate", false, "hijack rate", ""},
      {"hijacked_fraction", "metrics.json", "/filters/hijacked_fraction", false,
       "fraction of filter-frames hijacked", ""},
      {"swaps", "metrics.json", "/filters/swaps", false, "filter swaps", ""},
      {"idf1", "metrics.json", "/mot/IDF1", true, "IDF1", ""},
      {"hota", "metrics.json", "/mot/HOTA", true, "HOTA", ""},
      {"mota", "metrics.json", "/mot/MOTA", true, "MOTA", ""},
      {"motp", "metrics.json", "/mot/MOTP", true, "MOTP", ""},
      {"deta", "metrics.json", "/mot/DetA", true, "detection accuracy (DetA)", ""},
      {"assa", "metrics.json", "/mot/AssA", true, "association accuracy (AssA)", ""},
      {"ospa", "metrics.json", "/ospa/mean", false, "OSPA distance (mean)", "px"},
      {"ms_per_frame", "manifest.json", "/timings/tracker_s", false, "tracker time per frame", "ms",
       true},
      {"wall_time_s", "manifest.json", "/timings/total_s", false, "wall time of the run", "s"},
      // The hierarchical filter: mean corner displacement of the applied
      // camera motion against the true motion (none: the camera's own motion).
      {"camera_motion_error_px", "metrics.json", "/camera_motion/mean_px", false,
       "camera-motion error (mean corner displacement)", "px"},
      // Rendered runs: detection quality against pixel-exact truth (IoU >= 0.5).
      {"det_precision", "metrics.json", "/detection/iou/precision", true, "detection precision",
       ""},
      {"det_recall", "metrics.json", "/detection/iou/recall", true, "detection recall", ""},
      {"det_f1", "metrics.json", "/detection/iou/f1", true, "detection F1", ""},
      // The condition (visible fraction >= 0.75), the lenient centre
      // rule (what a tracker needs of a small target), and the size the
      // counts are about (sweeps against target size: report.x_metric).
      {"det_recall_visible", "metrics.json", "/detection/by_visibility/3/iou/recall", true,
       "detection recall at visible fraction >= 0.75", ""},
      {"det_recall_centre", "metrics.json", "/detection/centre/recall", true,
       "detection recall, centre rule", ""},
      {"det_precision_centre", "metrics.json", "/detection/centre/precision", true,
       "detection precision, centre rule", ""},
      {"det_size_px", "metrics.json", "/detection/median_size_px", true,
       "median target size (sqrt of box area)", "px"},
  };
  return kMetrics;
}

const CatalogueMetric* FindMetric(std::string_view name) {
  for (const CatalogueMetric& m : MetricCatalogue()) {
    if (m.name == name) return &m;
  }
  return nullptr;
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
