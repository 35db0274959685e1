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

  // Calls f(name, options) for every registered detector, in DetectorNames()
  // order: the one list the scenario reader, writer, schema and detection
  // cache walk, so a new detector is added here and in MakeDetector only.
  template <class F>
  void ForEach(F&& f) {
    f("ncc", ncc);
    f("colour", colour);
    f("prca", prca);
    f("sks", sks);
    f("diff", diff);
  }
  template <class F>
  void ForEach(F&& f) const {
    const_cast<DetectorOptions*>(this)->ForEach(
        [&f](const char* name, const auto& options) { f(name, options); });
  }
};

// The registered detectors' names, in a fixed order ("ncc", "colour", "prca",
// "sks", "diff"; DetectorOptions::ForEach's).
std::vector<std::string_view> DetectorNames();
// The detector called `name` (one of DetectorNames()) with its options
// validated, or the fusion of several such detectors named joined by '+'
// ("sks+prca": each runs on the frame; detections merged, maps averaged,
// docs/vision.md "Fusion"); nullptr for an unknown name or a name listed
// twice.
std::unique_ptr<Detector> MakeDetector(std::string_view name, const DetectorOptions& options);

}  // namespace hcpf::vision
