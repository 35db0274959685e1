#pragma once
// A tiny base scenario and sweep files for the sweep/store/report tests.

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "support/process.h"
#include "support/test_scenarios.h"

namespace hcpf::studies::testing {

// A fresh folder with base.yaml (kMinimal, 20 frames, 2 targets, 100 particles),
// named after the test and this process (test binaries run concurrently).
inline std::filesystem::path SweepFolder(const std::string& name) {
  const auto dir = hcpf::testing::FreshDir("sweep-" + name);
  std::ofstream(dir / "base.yaml") << scenarios::testing::kMinimal;
  return dir;
}

inline std::string WriteSweep(const std::filesystem::path& dir, const std::string& text,
                              const std::string& name = "sweep.yaml") {
  std::ofstream(dir / name) << text;
  return (dir / name).string();
}

}  // namespace hcpf::studies::testing
