#pragma once
// The registry of named detectors: every detector's options, its name, and
// the factory the run pipeline and the contract suite use.

#include <memory>
#include <string_view>
#include <vector>

#include "hcpf/vision/detector.h"
#include "hcpf/vision/prca.h"
#include "hcpf/vision/sks.h"

namespace hcpf::vision {

// The options of every registered detector (`observation.<name>.*`).
struct DetectorOptions {
  NccOptions ncc;
  ColourOptions colour;
  PrcaOptions prca;
  SksOptions sks;
  DiffOptions diff;
};

// The registered detectors' names, in a fixed order ("ncc", "colour", "prca",
// "sks", "diff").
std::vector<std::string_view> DetectorNames();
// The detector called `name` (one of DetectorNames()) with its options
// validated, or the fusion of several such detectors named joined by '+'
// ("sks+prca": each runs on the frame; detections merged, maps averaged,
// docs/vision.md "Fusion"); nullptr for an unknown name or a name listed
// twice.
std::unique_ptr<Detector> MakeDetector(std::string_view name, const DetectorOptions& options);

}  // namespace hcpf::vision
