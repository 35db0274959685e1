#pragma once
// Private: the factories of the registered detectors (detector.cc's registry).

#include <memory>

#include "hcpf/vision/detector.h"

namespace hcpf::vision::internal {

std::unique_ptr<Detector> MakeNccDetector(const NccOptions& options);
std::unique_ptr<Detector> MakeColourDetector(const ColourOptions& options);
std::unique_ptr<Detector> MakeDiffDetector(const DiffOptions& options);

}  // namespace hcpf::vision::internal
