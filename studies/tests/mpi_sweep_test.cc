// The MPI executor's launcher detection and its fall-backs (the executor
// itself is tested end to end under mpirun: tests/e2e/sweep_mpi_test.cc).

#include "hcpf/studies/mpi_sweep.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <filesystem>
#include <map>
#include <string>

#include "sweep_fixture.h"

namespace hcpf::studies {
namespace {

// LaunchedRankCount over a fake environment.
int RanksOf(const std::map<std::string, std::string>& env) {
  return LaunchedRankCount([&env](const char* name) -> const char* {
    const auto it = env.find(name);
    return it == env.end() ? nullptr : it->second.c_str();
  });
}

TEST(MpiLaunch, RankCountFromTheLauncherEnvironment) {
  EXPECT_EQ(RanksOf({}), 1);
  EXPECT_EQ(RanksOf({{"OMPI_COMM_WORLD_SIZE", "3"}, {"OMPI_COMM_WORLD_RANK", "2"}}), 3);
  EXPECT_EQ(RanksOf({{"OMPI_COMM_WORLD_SIZE", "1"}}), 1);
  EXPECT_EQ(RanksOf({{"PMI_SIZE", "16"}}), 16);
  // srun --mpi=pmix: the step's task count.
  EXPECT_EQ(RanksOf({{"PMIX_RANK", "0"}, {"SLURM_STEP_NUM_TASKS", "8"}}), 8);
  // A batch script's own environment (no launcher variables) is one process,
  // whatever Slurm allocated.
  EXPECT_EQ(RanksOf({{"SLURM_STEP_NUM_TASKS", "8"}, {"SLURM_NTASKS", "8"}}), 1);
  // Values that are not positive integers are ignored.
  EXPECT_EQ(RanksOf({{"OMPI_COMM_WORLD_SIZE", "three"}, {"PMI_SIZE", "4"}}), 4);
  EXPECT_EQ(RanksOf({{"OMPI_COMM_WORLD_SIZE", "0"}}), 1);
  EXPECT_EQ(RanksOf({{"OMPI_COMM_WORLD_SIZE", "2x"}}), 1);
  EXPECT_EQ(RanksOf({{"OMPI_COMM_WORLD_SIZE", ""}}), 1);
}

// IsFirstLaunchedRank over a fake environment: rank 0, or no launcher, is
// the first; another rank is not; the first rank variable set decides.
TEST(MpiLaunch, FirstRankFromTheLauncherEnvironment) {
  const auto first = [](const std::map<std::string, std::string>& env) {
    return IsFirstLaunchedRank([&env](const char* name) -> const char* {
      const auto it = env.find(name);
      return it == env.end() ? nullptr : it->second.c_str();
    });
  };
  EXPECT_TRUE(first({}));
  EXPECT_TRUE(first({{"OMPI_COMM_WORLD_SIZE", "3"}, {"OMPI_COMM_WORLD_RANK", "0"}}));
  EXPECT_FALSE(first({{"OMPI_COMM_WORLD_SIZE", "3"}, {"OMPI_COMM_WORLD_RANK", "2"}}));
  EXPECT_FALSE(first({{"PMI_SIZE", "16"}, {"PMI_RANK", "5"}}));
  EXPECT_TRUE(first({{"PMIX_RANK", "0"}, {"SLURM_STEP_NUM_TASKS", "8"}}));
  EXPECT_FALSE(first({{"PMIX_RANK", "1"}, {"SLURM_STEP_NUM_TASKS", "8"}}));
  EXPECT_FALSE(first({{"OMPI_COMM_WORLD_RANK", "1"}, {"PMI_RANK", "0"}}));
}

// Two particle counts x 2 seeds of the fixture's base scenario.
constexpr const char* kMpiSweep = R"(base: base.yaml
seeds: 2
grid:
  tracker.particles: [50, 100]
)";

TEST(RunSweepMpi, WithoutALauncherIsTheThreadPool) {
  const auto dir = testing::SweepFolder("mpi-no-launcher");
  const SweepSpec spec = LoadSweepFile(testing::WriteSweep(dir, kMpiSweep));
  SweepOptions options;
  options.out_dir = (dir / "out").string();
  options.jobs = 2;
  options.progress = false;
  ASSERT_EQ(LaunchedRankCount(), 1) << "run the unit tests without mpirun";
  const std::optional<SweepResult> r = RunSweepMpi(spec, ExpandSweep(spec), options);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->total, 4);
  EXPECT_EQ(r->computed, 4);
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "results.sqlite"));
}

// Only a build without MPI can run this (with MPI, the same launch would
// initialise MPI in the test process): tested where CMake found no MPI.
TEST(RunSweepMpi, ABuildWithoutMpiLaunchedAsSeveralRanksRefusesToStart) {
  if (MpiExecutorBuilt()) GTEST_SKIP() << "this build has MPI (tests/e2e/sweep_mpi_test.cc)";
  const auto dir = testing::SweepFolder("mpi-not-built");
  const SweepSpec spec = LoadSweepFile(testing::WriteSweep(dir, kMpiSweep));
  SweepOptions options;
  options.out_dir = (dir / "out").string();
  options.progress = false;
  ::setenv("OMPI_COMM_WORLD_SIZE", "3", 1);
  try {
    RunSweepMpi(spec, ExpandSweep(spec), options);
    ADD_FAILURE() << "no error";
  } catch (const RunError& e) {
    EXPECT_NE(std::string(e.what()).find("started as 3 processes by an MPI launcher"),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("built without MPI"), std::string::npos) << e.what();
  }
  ::unsetenv("OMPI_COMM_WORLD_SIZE");
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
}

}  // namespace
}  // namespace hcpf::studies
