// The instruction-set dispatch: the default set is the widest the CPU has, a
// test's ScopedInstructionSet changes it and puts the earlier one back, and
// a loop defined with HCPF_DISPATCHED gives the same bytes in every build.
// (The modules' own loops are compared build by build in their tests:
// tracker/tests/isa_clones_test.cc, vision/tests/separable_gaussian_blur_test.cc,
// vision/tests/stacked_integral_blur_test.cc, renderer/tests/options_test.cc.)
#include "hcpf/core/instruction_set.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <map>
#include <vector>

namespace hcpf {
namespace {

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
  int runs = 0;
  testing::ForEachInstructionSetOfThisCpu([&](InstructionSet set) {
    EXPECT_EQ(ActiveInstructionSet(), set);
    std::vector<float> out(n);
    MixedSum(a.data(), b.data(), 0.3f, out.data(), n);
    EXPECT_EQ(std::memcmp(out.data(), expected.data(), n * sizeof(float)), 0) << NameOf(set);
    ++runs;
  });
  // Every set the CPU has, each once.
  EXPECT_EQ(runs, 1 + (CpuHas(InstructionSet::kAvx2) ? 1 : 0) +
                      (CpuHas(InstructionSet::kAvx512) ? 1 : 0));
}

// The dispatcher runs the build of the active set: a loop compiled here
// with contraction allowed fuses a * b + c in its AVX-512 build (which has
// FMA) and in no other, so that build's bytes differ from the baseline's
// where the fused result rounds otherwise (AVX2 has no FMA: its build cannot
// be told from the baseline this way; EachSetsOwnBuildRuns tells it).
#pragma GCC push_options
#pragma GCC optimize("O2", "fp-contract=fast")
HCPF_DISPATCHED(void, FusedWhereItCan, (const double* a, const double* b, double* out, int n),
                (a, b, out, n), {
                  for (int i = 0; i < n; ++i) out[i] = a[i] * b[i] + 1.0;
                })
#pragma GCC pop_options

TEST(InstructionSet, TheActiveSetsBuildRuns) {
  if (!CpuHas(InstructionSet::kAvx512)) {
    std::printf("[ SKIPPED  ] avx512f: this CPU lacks it\n");
    return;
  }
  const int n = 64;
  std::vector<double> a(n), b(n), baseline(n), wide(n);
  for (int i = 0; i < n; ++i) {
    a[i] = 1.0 + 1.0 / (i + 3);
    b[i] = 1.0 - 1.0 / (i + 7);
  }
  {
    const testing::ScopedInstructionSet scoped(InstructionSet::kBaseline);
    FusedWhereItCan(a.data(), b.data(), baseline.data(), n);
  }
  {
    const testing::ScopedInstructionSet scoped(InstructionSet::kAvx512);
    FusedWhereItCan(a.data(), b.data(), wide.data(), n);
  }
  int fused = 0;
  for (int i = 0; i < n; ++i) {
    // The baseline build rounds the product, then the sum.
    const double product = a[i] * b[i];
    EXPECT_EQ(baseline[i], product + 1.0) << i;
    fused += wide[i] != baseline[i] ? 1 : 0;
  }
  EXPECT_GT(fused, 0) << "the AVX-512 build gave the baseline's bytes everywhere: did it run?";
}

// Each set's own build runs, AVX2's included: a sum whose order follows the
// vector width. With reassociation allowed here (never in the project's
// code) GCC keeps partial sums per vector lane, so 2^53 + 1 rounds back to
// 2^53 (half-way, to even) in some lanes and not in others, depending on
// which elements share a lane: 2 doubles wide in the baseline (SSE2), 4 in
// the AVX2 build. The dispatched call must give each set's own build's sum,
// called by its name.
#pragma GCC push_options
#pragma GCC optimize("O3", "associative-math", "no-signed-zeros", "no-trapping-math")
HCPF_DISPATCHED(double, LaneSum, (const double* x, int n), (x, n), {
  double s = 0.0;
  for (int i = 0; i < n; ++i) s += x[i];
  return s;
})
#pragma GCC pop_options

TEST(InstructionSet, EachSetsOwnBuildRuns) {
  // Every 8: 2^53, 1, 1, 1, -2^53, 1, 1, 1.
  const int n = 64;
  std::vector<double> x(n, 1.0);
  for (int i = 0; i < n; i += 8) {
    x[static_cast<size_t>(i)] = 0x1p53;
    x[static_cast<size_t>(i) + 4] = -0x1p53;
  }
  std::map<InstructionSet, double> sums;
  testing::ForEachInstructionSetOfThisCpu([&](InstructionSet set) {
    const double own = set == InstructionSet::kAvx512 ? LaneSumAvx512(x.data(), n)
                       : set == InstructionSet::kAvx2 ? LaneSumAvx2(x.data(), n)
                                                      : LaneSumBaseline(x.data(), n);
    EXPECT_EQ(LaneSum(x.data(), n), own) << NameOf(set);
    sums[set] = own;
  });
  for (const auto& [set, sum] : sums) std::printf("  %s: %.17g\n", NameOf(set).data(), sum);
    // The baseline's and AVX2's builds differ here, so the check above tells
    // them apart (AVX-512's may use AVX2's width: TheActiveSetsBuildRuns).
    // Under AddressSanitizer (the asan and dev presets) the checked loads keep
    // the loop scalar in every build, which then all add in order (31 here).
#if !defined(__SANITIZE_ADDRESS__)
  if (CpuHas(InstructionSet::kAvx2)) {
    EXPECT_NE(sums.at(InstructionSet::kBaseline), sums.at(InstructionSet::kAvx2))
        << "both " << sums.at(InstructionSet::kBaseline);
  }
#else
  std::printf("[ SKIPPED  ] AddressSanitizer: unvectorised, the sums cannot tell builds apart\n");
#endif
}

}  // namespace
}  // namespace hcpf
