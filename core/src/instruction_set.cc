#include "hcpf/core/instruction_set.h"

#include <atomic>
#include <cstdio>

#include "hcpf/core/check.h"

namespace hcpf {
namespace {

InstructionSet Widest() {
  for (const InstructionSet set : {InstructionSet::kAvx512, InstructionSet::kAvx2}) {
    if (CpuHas(set)) return set;
  }
  return InstructionSet::kBaseline;
}

// -1 until the first ask (a constant initialiser, so a loop run during
// another file's static initialisation finds it too), then the set.
std::atomic<int> active{-1};

InstructionSet Active() {
  const int set = active.load(std::memory_order_relaxed);
  if (set >= 0) return static_cast<InstructionSet>(set);
  // Only over the -1: a test's set made meanwhile stays.
  int expected = -1;
  const int widest = static_cast<int>(Widest());
  return active.compare_exchange_strong(expected, widest, std::memory_order_relaxed)
             ? static_cast<InstructionSet>(widest)
             : static_cast<InstructionSet>(expected);
}

}  // namespace

bool CpuHas(InstructionSet set) {
  __builtin_cpu_init();
  switch (set) {
    case InstructionSet::kAvx512:
      return __builtin_cpu_supports("avx512f") != 0;
    case InstructionSet::kAvx2:
      return __builtin_cpu_supports("avx2") != 0;
    case InstructionSet::kBaseline:
      break;
  }
  return true;
}

InstructionSet ActiveInstructionSet() { return Active(); }

namespace testing {

ScopedInstructionSet::ScopedInstructionSet(InstructionSet set) : previous_(Active()) {
  HCPF_CHECK(CpuHas(set)) << "this CPU lacks " << NameOf(set);
  active.store(static_cast<int>(set));
}

ScopedInstructionSet::~ScopedInstructionSet() { active.store(static_cast<int>(previous_)); }

void ForEachInstructionSetOfThisCpu(const std::function<void(InstructionSet)>& body) {
  for (const auto& [set, name] : EnumNames<InstructionSet>::kNames) {
    if (!CpuHas(set)) {
      std::printf("[ SKIPPED  ] %s: this CPU lacks it\n", name.data());
      continue;
    }
    const ScopedInstructionSet scoped(set);
    body(set);
  }
}

}  // namespace testing
}  // namespace hcpf
