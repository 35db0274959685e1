#include "hcpf/scenarios/progress.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace hcpf::scenarios {
namespace {

// The ETA runs at the rate of the later half of the items done. By hand: six
// of 100 items done at 5, 6, 6.5, 6.6, 6.7 and 6.8 s (a rendered sweep's
// first runs render, the later ones read the cache): the last three took
// 6.8 − 6.5 = 0.3 s, 0.1 s each, so 94 left take 9.4 s. The mean rate since
// the start said 6.8 / 6 × 94 = 106.5 s.
TEST(Progress, TheEtaRunsAtTheRateOfTheLaterHalfOfTheItemsDone) {
  const std::vector<double> finished = {5.0, 6.0, 6.5, 6.6, 6.7, 6.8};
  EXPECT_NEAR(Progress::EtaSeconds(finished, 100, 6.8), 9.4, 1e-9);
  // Time since the last item counts: at 7.1 s, (7.1 − 6.5) / 3 × 94.
  EXPECT_NEAR(Progress::EtaSeconds(finished, 100, 7.1), 18.8, 1e-9);
  // One item: from the start, (2 / 1) × 9.
  EXPECT_NEAR(Progress::EtaSeconds({2.0}, 10, 2.0), 18.0, 1e-9);
  // Seven: the later four, from the third item's end (3 s): (7 − 3) / 4 × 3.
  EXPECT_NEAR(Progress::EtaSeconds({1, 2, 3, 4, 5, 6, 7}, 10, 7.0), 3.0, 1e-9);
  EXPECT_TRUE(std::isnan(Progress::EtaSeconds({}, 10, 1.0)));
  EXPECT_TRUE(std::isnan(Progress::EtaSeconds({1.0, 2.0}, 2, 2.0)));
  EXPECT_EQ(Progress::Format("sweep", 6, 100, 0, 6.8, 9.4),
            "sweep 6/100 (6%) 0:07 elapsed, ETA 0:09");
  EXPECT_EQ(Progress::Format("sweep", 6, 100, 1, 6.8),
            "sweep 6/100 (6%) 1 failed, 0:07 elapsed, ETA 1:47");
  EXPECT_EQ(Progress::Format("sweep", 100, 100, 0, 7.0), "sweep 100/100 (100%) 0:07 elapsed");
}

// A run's summary lines: said by a run alone, kept to debug inside a sweep,
// whose progress line they would write over.
TEST(Progress, ARunsSummaryLinesAreDebugInsideASweep) {
  EXPECT_EQ(RunSummaryLevel(true), spdlog::level::info);
  EXPECT_EQ(RunSummaryLevel(false), spdlog::level::debug);
}

}  // namespace
}  // namespace hcpf::scenarios
