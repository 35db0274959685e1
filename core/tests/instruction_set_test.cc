// The instruction-set dispatch: the default set is the widest the CPU has, a
// test's ScopedInstructionSet changes it and puts the earlier one back, and
// a loop defined with HCPF_DISPATCHED gives the same bytes in every build.
// (The modules' own loops are compared build by build in their tests:
// tracker/tests/isa_clones_test.cc, vision/tests/separable_gaussian_blur_test.cc,
// vision/tests/stacked_integral_blur_test.cc, renderer/tests/sensor_test.cc.)
#include "hcpf/core/instruction_set.h"

#include <gtest/gtest.h>

#include <cstring>
#include <vector>

namespace hcpf {
namespace {

constexpr InstructionSet kSets[] = {InstructionSet::kBaseline, InstructionSet::kAvx2,
                                    InstructionSet::kAvx512};

TEST(InstructionSet, TheDefaultIsTheWidestTheCpuHas) {
  EXPECT_TRUE(CpuHas(InstructionSet::kBaseline));
  const InstructionSet widest = CpuHas(InstructionSet::kAvx512) ? InstructionSet::kAvx512
                                : CpuHas(InstructionSet::kAvx2) ? InstructionSet::kAvx2
                                                                : InstructionSet::kBaseline;
  EXPECT_EQ(ActiveInstructionSet(), widest) << NameOf(ActiveInstructionSet());
  EXPECT_EQ(NameOf(InstructionSet::kAvx512), "avx512f");
  EXPECT_EQ(NameOf(InstructionSet::kAvx2), "avx2");
  EXPECT_EQ(NameOf(InstructionSet::kBaseline), "baseline");
}

TEST(InstructionSet, AScopedSetIsActiveUntilItEnds) {
  const InstructionSet before = ActiveInstructionSet();
  {
    const testing::ScopedInstructionSet baseline(InstructionSet::kBaseline);
    EXPECT_EQ(ActiveInstructionSet(), InstructionSet::kBaseline);
    if (CpuHas(InstructionSet::kAvx2)) {
      const testing::ScopedInstructionSet avx2(InstructionSet::kAvx2);
      EXPECT_EQ(ActiveInstructionSet(), InstructionSet::kAvx2);
    }
    EXPECT_EQ(ActiveInstructionSet(), InstructionSet::kBaseline);
  }
  EXPECT_EQ(ActiveInstructionSet(), before);
}

// out[i] = k (a[i] + b[i]) + a[i] b[i]: a multiply-add the AVX-512 build
// would fuse without -ffp-contract=off, and a length of no vector width.
HCPF_DISPATCHED(void, MixedSum, (const float* a, const float* b, float k, float* out, int n),
                (a, b, k, out, n), {
                  for (int i = 0; i < n; ++i) out[i] = k * (a[i] + b[i]) + a[i] * b[i];
                })

TEST(InstructionSet, ADispatchedLoopGivesTheSameBytesInEveryBuild) {
  const int n = 1003;
  std::vector<float> a(n), b(n);
  for (int i = 0; i < n; ++i) {
    a[i] = 1.0f / static_cast<float>(i + 3);
    b[i] = static_cast<float>(i) * 0.37f - 100.0f;
  }
  std::vector<float> expected(n);
  {
    const testing::ScopedInstructionSet baseline(InstructionSet::kBaseline);
    MixedSum(a.data(), b.data(), 0.3f, expected.data(), n);
  }
  // The baseline build against the sum written out here.
  for (int i = 0; i < n; ++i) {
    const float want = 0.3f * (a[i] + b[i]) + a[i] * b[i];
    EXPECT_EQ(std::memcmp(&expected[i], &want, sizeof(float)), 0) << i;
  }
  for (const InstructionSet set : kSets) {
    if (!CpuHas(set)) {
      std::printf("[ SKIPPED  ] %s: this CPU lacks it\n", NameOf(set).data());
      continue;
    }
    const testing::ScopedInstructionSet scoped(set);
    std::vector<float> out(n);
    MixedSum(a.data(), b.data(), 0.3f, out.data(), n);
    EXPECT_EQ(std::memcmp(out.data(), expected.data(), n * sizeof(float)), 0) << NameOf(set);
  }
}

}  // namespace
}  // namespace hcpf
