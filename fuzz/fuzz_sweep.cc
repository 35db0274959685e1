// libFuzzer target `sweep`: sweep YAML text -> validated SweepSpec
// (LoadSweepText) and, for small sweeps, the expansion into runs (ExpandSweep),
// which loads the base scenario once per run with the swept values as `--set`
// overrides.

#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "hcpf/studies/sweep.h"

namespace {

namespace studies = hcpf::studies;

// Each run reads, validates and hashes the base scenario (~8 ms here under
// ASan/UBSan): a cap keeps inputs fast; `seeds: 100000` must not take minutes.
constexpr int64_t kMaxExpandedRuns = 4;

void LoadAndExpand(const std::string& text) {
  // As if in scenarios/sweeps/, so `base: ../library/crossing.yaml` resolves
  // as in the repository's own sweep files.
  static const std::string kDir = HCPF_SOURCE_DIR "/scenarios/sweeps";
  const studies::SweepSpec spec = studies::LoadSweepText(text, kDir + "/fuzz-input.yaml", kDir);
  const int64_t count = spec.RunCount();
  if (count < 1) hcpf::fuzz::Fail("RunCount() of a valid sweep is " + std::to_string(count));
  if (count > kMaxExpandedRuns) return;
  const std::vector<studies::SweepRun> runs = studies::ExpandSweep(spec);
  if (static_cast<int64_t>(runs.size()) != count) {
    hcpf::fuzz::Fail("ExpandSweep gave " + std::to_string(runs.size()) + " runs, RunCount() " +
                     std::to_string(count));
  }
  studies::SweepHash(runs);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  hcpf::fuzz::ExpectInputErrorOnly([&] { LoadAndExpand(text); });
  return 0;
}
