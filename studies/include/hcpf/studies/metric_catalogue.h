#pragma once
// The metrics a study records for every run, each named once. The results
// store makes one column per entry and reads it from the run folder by its
// JSON pointer, sweep files and regression suites name metrics from it, the
// report labels its plots with it, the regression gate takes its direction
// from it, and `hcpf report`'s summary.csv lists them in this order.

#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hcpf/studies/statistics.h"

namespace hcpf::studies {

struct CatalogueMetric {
  std::string_view name;     // store column and YAML name, e.g. "da_accuracy"
  std::string_view file;     // the run-folder file it is read from: metrics.json | manifest.json
  std::string_view pointer;  // JSON pointer (RFC 6901) into that file, e.g. "/filters/da_accuracy"
  bool higher_is_better;
  std::string_view label;  // for plots and tables, e.g. "data-association accuracy"
  std::string_view unit;   // "" when dimensionless
  // The values one run can have, and whether the value is a proportion (a
  // fraction of counted events: its across-seed mean gets a Wilson interval,
  // statistics.h); the report's bands never leave this range.
  MetricRange range;
  // The value is 1000 × (the pointed value) / manifest.json's "/frames"
  // (milliseconds per frame of a time in seconds).
  bool per_frame_ms = false;
};

// Every metric, in the order of the store's columns.
std::span<const CatalogueMetric> MetricCatalogue();

// The entry named `name`, or nullptr.
const CatalogueMetric* FindMetric(std::string_view name);

// Whether `metric` is a time the run measured (manifest.json's timings:
// ms_per_frame, wall_time_s). Such a value depends on the machine's load and
// on the order runs ran in (the first runs of a rendered sweep render the
// frames the others read from the cache), not only on the run's settings:
// reports plot and table it but do not test it (docs/sweeps.md).
bool MachineDependent(std::string_view metric);

// Whether `metric` describes the run or its scene rather than scores it:
// the target size the detector faced (det_size_px), the camera-motion floor
// (the best any similarity does on these frames), how often filters were
// re-acquired. Its catalogue direction orders values, but a difference in it
// is no better or worse: the run report does not colour it.
bool Descriptive(std::string_view metric);

// The names, in catalogue order (built once).
const std::vector<std::string>& MetricNames();

}  // namespace hcpf::studies
