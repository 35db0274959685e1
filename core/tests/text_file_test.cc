#include "hcpf/core/text_file.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "hcpf/core/error.h"

namespace hcpf {
namespace {

namespace fs = std::filesystem;

// The message of the InputError CheckFilesToWrite throws, or "" when it accepts.
std::string Refusal(const std::vector<FileToWrite>& writes, const std::vector<FileRead>& reads,
                    const std::vector<fs::path>& under = {}) {
  try {
    CheckFilesToWrite(writes, reads, under, "score", "nothing was written");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// Each rule of CheckFilesToWrite, the one check `hcpf score` (--json,
// --events) and `hcpf regress` (--baseline, --junit, --markdown) make of the
// files they will write. Inputs are compared as files, not as names: a
// symbolic or a hard link to an input is that input.
TEST(CheckFilesToWrite, RefusesWhatWouldFailLateOrDestroyAnInput) {
  const fs::path dir =
      fs::temp_directory_path() / ("hcpf_core_files_to_write_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "reads" / "sub");
  const std::string gt = (dir / "gt.txt").string();
  std::ofstream(gt) << "1,1,1,1,1,1,1,1,1\n";
  fs::create_hard_link(gt, dir / "hard.txt");
  fs::create_symlink(gt, dir / "soft.txt");
  const std::vector<FileRead> reads = {{gt, "the ground truth (GT)"}, {"", "no --seqinfo"}};

  EXPECT_EQ(Refusal({{(dir / "out.json").string(), "--json"}}, reads), "");
  EXPECT_EQ(Refusal({}, reads), "");
  EXPECT_NE(Refusal({{dir.string(), "--json"}}, reads)
                .find("--json: expected a file to write, "
                      "found a folder"),
            std::string::npos);
  EXPECT_NE(Refusal({{(dir / "no" / "out.json").string(), "--json"}}, reads)
                .find("expected a file in an existing folder, found no folder"),
            std::string::npos);
  for (const char* name : {"gt.txt", "hard.txt", "soft.txt"}) {
    const std::string message = Refusal({{(dir / name).string(), "--events"}}, reads);
    EXPECT_NE(message.find("--events: expected a file score does not read, found the ground "
                           "truth (GT) (nothing was written)"),
              std::string::npos)
        << name << ": " << message;
  }
  // Two outputs naming one file (spelled differently): the second is refused.
  EXPECT_NE(Refusal({{(dir / "o.json").string(), "--json"},
                     {(dir / "reads" / ".." / "o.json").string(), "--events"}},
                    reads)
                .find("--events: expected a file of its own, found the file --json writes too"),
            std::string::npos);
  // A file inside a folder the command reads whole, at any depth; beside it is fine.
  EXPECT_NE(Refusal({{(dir / "reads" / "sub" / "o.json").string(), "--json"}}, {}, {dir / "reads"})
                .find("expected a file outside the folders score reads, found a file in"),
            std::string::npos);
  EXPECT_EQ(Refusal({{(dir / "readsx.json").string(), "--json"}}, {}, {dir / "reads"}), "");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hcpf
