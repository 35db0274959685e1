// StagedFolder (output_folder.h): the staging folders of dead processes
// beside an output.

#include "hcpf/scenarios/output_folder.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <string>

namespace hcpf::scenarios {
namespace {

namespace fs = std::filesystem;

// A process id that no process has now: a child that has exited and been
// waited for.
std::string DeadPid() {
  const pid_t child = fork();
  if (child == 0) _exit(0);
  int status = 0;
  waitpid(child, &status, 0);
  return std::to_string(child);
}

// Removed by default; left when the caller has cleaned the parent folder
// itself (a sweep's runs/, listed once under its lock instead of once per
// run: a scale audit found a 20,000-run sweep quadratic).
TEST(StagedFolder, RemovesADeadProcesssStagingFolderUnlessAskedNotTo) {
  const fs::path dir =
      fs::path(::testing::TempDir()) / ("hcpf-staged-" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string dead = DeadPid();
  const fs::path stale = dir / ("out.partial-" + dead);
  fs::create_directories(stale);
  {
    const StagedFolder kept(dir / "out", false);
    EXPECT_TRUE(fs::exists(stale));
    EXPECT_TRUE(fs::exists(kept.partial()));
  }
  {
    const StagedFolder cleaned(dir / "out");
    EXPECT_FALSE(fs::exists(stale));
  }
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hcpf::scenarios
