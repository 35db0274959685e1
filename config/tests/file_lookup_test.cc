// Where a file named in a scenario is looked for, and what the error lists.

#include "hcpf/config/file_lookup.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

namespace hcpf::config {
namespace {

namespace fs = std::filesystem;

// The scenario's folder, the current folder and the project folder, each
// listed once when two are one folder (a bad-input audit: "looked at
// /a/x.glb, /a/x.glb, /project/x.glb" when the scenario's folder was the
// current one).
TEST(FindFile, AFolderLookedInTwiceIsListedOnce) {
  std::vector<std::string> looked;
  EXPECT_FALSE(FindFile("no-such-model.glb", fs::current_path().string(), &looked));
  const std::string here = (fs::current_path() / "no-such-model.glb").lexically_normal().string();
  const std::string project =
      (fs::path(HCPF_PROJECT_SOURCE_DIR) / "no-such-model.glb").lexically_normal().string();
  const std::vector<std::string> expected =
      here == project ? std::vector<std::string>{here} : std::vector<std::string>{here, project};
  EXPECT_EQ(looked, expected);
  EXPECT_EQ(NotFoundText("no-such-model.glb", looked),
            "\"no-such-model.glb\", which does not exist (looked at " + here +
                (here == project ? "" : ", " + project) + ")");
}

}  // namespace
}  // namespace hcpf::config
