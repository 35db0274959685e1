#pragma once
// Private: the factories of the registered detectors (detector.cc's registry).

#include <memory>
#include <vector>

#include "hcpf/vision/detector.h"

namespace hcpf::vision::internal {

std::unique_ptr<Detector> MakeNccDetector(const NccOptions& options);
std::unique_ptr<Detector> MakeColourDetector(const ColourOptions& options);
std::unique_ptr<Detector> MakeDiffDetector(const DiffOptions& options);
// Two or more detectors run together (fused_detector.cc).
std::unique_ptr<Detector> MakeFusedDetector(std::vector<std::unique_ptr<Detector>> parts);

}  // namespace hcpf::vision::internal
