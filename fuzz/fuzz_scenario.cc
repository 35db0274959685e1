// libFuzzer target `scenario`: YAML text -> validated Scenario (LoadScenarioText).
//
// Lines "#set key=value" (YAML comments, so the document itself is unchanged)
// become `--set` overrides, so the override parser and ApplyOverrides are fed
// too. A scenario that loads must round-trip through its resolved YAML, the
// property scenarios/tests/scenario_load_test.cc checks on one hand-written file.

#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "fuzz_support.h"
#include "hcpf/scenarios/scenario.h"

namespace {

using hcpf::InputError;
using hcpf::fuzz::Fail;
namespace scenarios = hcpf::scenarios;

std::vector<scenarios::Override> OverridesIn(const std::string& text) {
  std::vector<scenarios::Override> overrides;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("#set ", 0) == 0) overrides.push_back(scenarios::ParseOverride(line.substr(5)));
  }
  return overrides;
}

void LoadAndRoundTrip(const std::string& text) {
  // Named as if beside the library's scenarios, so their relative model paths
  // (assets/vehicles/*.glb, found through the project root) resolve as they do there.
  static const std::string kFile = HCPF_SOURCE_DIR "/scenarios/library/fuzz-input.yaml";
  const scenarios::Scenario scenario = scenarios::LoadScenarioText(text, kFile, OverridesIn(text));
  const std::string resolved = scenarios::ToResolvedYaml(scenario);
  scenarios::Scenario again;
  try {
    again = scenarios::LoadScenarioText(resolved, kFile);
  } catch (const InputError& e) {
    Fail(std::string("the resolved YAML of a valid scenario is rejected: ") + e.what() +
         "\n--- resolved YAML ---\n" + resolved);
  }
  const std::string second = scenarios::ToResolvedYaml(again);
  if (second != resolved) {
    Fail("the resolved YAML does not round-trip\n--- first ---\n" + resolved +
         "--- after reloading ---\n" + second);
  }
  if (scenarios::ConfigHash(again) != scenarios::ConfigHash(scenario))
    Fail("ConfigHash changed on reloading");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  hcpf::fuzz::ExpectInputErrorOnly([&] { LoadAndRoundTrip(text); });
  return 0;
}
