#pragma once
// The x86-64 instruction sets the project's hot loops are built for, and
// which one they run.
//
// A loop defined with HCPF_DISPATCHED is compiled three times, for AVX-512F,
// AVX2 and the x86-64 baseline (SSE2); each call runs the build of
// ActiveInstructionSet(): the widest this CPU has, unless a test chose another
// with testing::ScopedInstructionSet. Every build must compute the same bytes
// (each value one expression evaluated in a fixed order, element by element,
// and no fused multiply-add: the project's -ffp-contract=off), so that
// machines with and without AVX-512 agree; tests run the library's own loops
// under each set the CPU has and compare. GCC's target_clones, used before,
// chose the build at load time, where no test could reach the others: the
// tests checked copies of the kernels built in the test files (a review).

#include <array>
#include <functional>
#include <string_view>
#include <utility>

#include "hcpf/core/enum_names.h"

namespace hcpf {

enum class InstructionSet { kBaseline, kAvx2, kAvx512 };

// NameOf: "baseline", "avx2", "avx512f".
template <>
struct EnumNames<InstructionSet> {
  static constexpr std::array<std::pair<InstructionSet, std::string_view>, 3> kNames = {{
      {InstructionSet::kBaseline, "baseline"},
      {InstructionSet::kAvx2, "avx2"},
      {InstructionSet::kAvx512, "avx512f"},
  }};
};

// Whether this CPU runs `set` (the baseline: always).
bool CpuHas(InstructionSet set);

// The set HCPF_DISPATCHED loops run now (a relaxed atomic load).
InstructionSet ActiveInstructionSet();

namespace testing {

// Makes every HCPF_DISPATCHED loop of the process run the build for `set`
// (HCPF_CHECK: the CPU has it) until it goes out of scope, then the set
// before. For tests: not to be made while other threads run such loops.
class ScopedInstructionSet {
 public:
  explicit ScopedInstructionSet(InstructionSet set);
  ~ScopedInstructionSet();
  ScopedInstructionSet(const ScopedInstructionSet&) = delete;
  ScopedInstructionSet& operator=(const ScopedInstructionSet&) = delete;

 private:
  InstructionSet previous_;
};

// Calls body(set) for every set this CPU has, the baseline first, each under
// a ScopedInstructionSet; prints a "[ SKIPPED  ]" line for each it lacks.
// The loop of every test that compares a module's builds.
void ForEachInstructionSetOfThisCpu(const std::function<void(InstructionSet)>& body);

}  // namespace testing
}  // namespace hcpf

// Defines the function `ret name params` whose body `...` (a braced block)
// is compiled for each instruction set: as an always-inlined body, called
// from one function per set (name##Avx512, name##Avx2, name##Baseline), and
// `name`, which calls the one ActiveInstructionSet() names. `args` is
// `params`' names in parentheses. Use it inside an anonymous namespace; a
// function the body calls must be inline for the wider builds to vectorise it.
#define HCPF_DISPATCHED(ret, name, params, args, ...)                                         \
  [[gnu::always_inline]] inline ret name##Body params __VA_ARGS__                             \
      __attribute__((target("avx512f"), noinline)) ret name##Avx512 params {                  \
    return name##Body args;                                                                   \
  }                                                                                           \
  __attribute__((target("avx2"), noinline)) ret name##Avx2 params { return name##Body args; } \
  __attribute__((noinline)) ret name##Baseline params { return name##Body args; }             \
  ret name params {                                                                           \
    switch (::hcpf::ActiveInstructionSet()) {                                                 \
      case ::hcpf::InstructionSet::kAvx512:                                                   \
        return name##Avx512 args;                                                             \
      case ::hcpf::InstructionSet::kAvx2:                                                     \
        return name##Avx2 args;                                                               \
      case ::hcpf::InstructionSet::kBaseline:                                                 \
        break;                                                                                \
    }                                                                                         \
    return name##Baseline args;                                                               \
  }
