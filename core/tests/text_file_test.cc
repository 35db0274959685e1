#include "hcpf/core/text_file.h"

#include <fcntl.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "hcpf/core/error.h"
#include "support/process.h"

namespace hcpf {
namespace {

namespace fs = std::filesystem;

std::string ReadAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

// A write that fails part-way (here the file-size limit a full disk stands
// in for) leaves the earlier file whole and no temporary file: written in
// place, report.html was cut to the limit and looked complete in a browser
// (determinism audit D4). An existing file keeps its permissions, and a
// symbolic link is written through, as when files were truncated in place.
// Byte offsets to 1-based lines and columns, worked by hand on "ab\ncd\n\nx":
// bytes 0 'a', 2 the first newline, 3 'c', 6 the empty line's newline, 7 'x'.
TEST(TextFile, PositionOfCountsLinesAndColumnsFromOne) {
  const std::string text = "ab\ncd\n\nx";
  const auto position = [](const std::string& of, size_t offset) {
    const TextPosition p = PositionOf(of, offset);
    return std::pair{p.line, p.column};
  };
  const auto at = [&](size_t offset) { return position(text, offset); };
  EXPECT_EQ(at(0), std::pair(1, 1));
  EXPECT_EQ(at(2), std::pair(1, 3));
  EXPECT_EQ(at(3), std::pair(2, 1));
  EXPECT_EQ(at(4), std::pair(2, 2));
  EXPECT_EQ(at(6), std::pair(3, 1));
  EXPECT_EQ(at(7), std::pair(4, 1));
  EXPECT_EQ(at(8), std::pair(4, 2));    // the end
  EXPECT_EQ(at(100), std::pair(4, 2));  // past it: the end
  // A byte-order mark (bytes 0-2 of "\xEF\xBB\xBFab\ncd") is no column, as an
  // editor shows the file: 'a' (byte 3) is column 1, 'b' 2, 'c' (byte 6)
  // column 1 of line 2; a byte of the mark itself is column 1.
  const std::string marked =
      "\xEF\xBB\xBF"
      "ab\ncd";
  const auto marked_at = [&](size_t offset) { return position(marked, offset); };
  EXPECT_EQ(marked_at(0), std::pair(1, 1));
  EXPECT_EQ(marked_at(2), std::pair(1, 1));
  EXPECT_EQ(marked_at(3), std::pair(1, 1));
  EXPECT_EQ(marked_at(4), std::pair(1, 2));
  EXPECT_EQ(marked_at(6), std::pair(2, 1));
  EXPECT_EQ(marked_at(7), std::pair(2, 2));
}

TEST(WriteTextFile, ReplacesAFileWholeOrNotAtAll) {
  const fs::path dir =
      fs::temp_directory_path() / ("hcpf_core_write_text_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path report = dir / "report.html";
  WriteTextFile(report.string(), "<html>good</html>\n");
  ::chmod(report.c_str(), 0640);

  const int code = hcpf::testing::InChildWithFileSizeLimit(64, [&] {
    try {
      WriteTextFile(report.string(), std::string(1000, 'x'));
    } catch (const RunError& e) {
      return std::string(e.what()).find("writing " + report.string() + " failed") == 0 ? 0 : 3;
    }
    return 4;  // no error
  });
  EXPECT_EQ(code, 0) << "3: another message, 4: no error";
  EXPECT_EQ(ReadAll(report), "<html>good</html>\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), {}), 1) << "a temporary file was left";

  WriteTextFile(report.string(), "<html>new</html>\n");
  EXPECT_EQ(ReadAll(report), "<html>new</html>\n");
  struct stat st {};
  ASSERT_EQ(::stat(report.c_str(), &st), 0);
  EXPECT_EQ(st.st_mode & 07777, 0640u);

  fs::create_symlink(report, dir / "link.html");
  WriteTextFile((dir / "link.html").string(), "through the link\n");
  EXPECT_TRUE(fs::is_symlink(dir / "link.html"));
  EXPECT_EQ(ReadAll(report), "through the link\n");

  EXPECT_THROW(WriteTextFile((dir / "no" / "such.txt").string(), "x"), RunError);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), {}), 2);
  fs::remove_all(dir);
}

// A path that is standard output (`--json /dev/stdout`, or the file stdout
// was redirected to) is written after what the process printed there: opened
// again, /dev/stdout started at offset 0 of the redirected file, and the
// table printed before it was written over the JSON (docs audit, 2026-12-05).
// In a child whose stdout is a file: what it prints, then two writes.
TEST(WriteTextFile, StandardOutputIsWrittenAfterWhatWasPrintedThere) {
  const fs::path dir =
      fs::temp_directory_path() / ("hcpf_core_write_stdout_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const fs::path out = dir / "out.txt";
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const int fd = ::open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0 || ::dup2(fd, STDOUT_FILENO) < 0) ::_exit(3);
    if (!IsStandardOutput("/dev/stdout") || !IsStandardOutput(out.string()) ||
        IsStandardOutput((dir / "other.txt").string()) || IsStandardOutput("")) {
      ::_exit(4);
    }
    std::printf("table\n");
    try {
      WriteTextFile("/dev/stdout", "{\"json\": 1}\n");
      WriteTextFile(out.string(), "events\n");
    } catch (const std::exception&) {
      ::_exit(5);
    }
    std::fflush(stdout);
    ::_exit(0);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "3: no redirection, 4: IsStandardOutput, 5: a write threw";
  EXPECT_EQ(ReadAll(out), "table\n{\"json\": 1}\nevents\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), {}), 1) << "a temporary file was left";
  fs::remove_all(dir);
}

// Folder checks (a run's --out, a report's --out) tell what a killed write
// left from a file of the user's by its name.
TEST(WriteTextFile, ItsTemporaryFilesAreKnownByName) {
  EXPECT_EQ(TempFileTarget(".report.html.tmp-123-0"), "report.html");
  EXPECT_EQ(TempFileTarget(".gt.txt.tmp-7-12"), "gt.txt");
  // The names TempFileFor gives (WriteTextFile's, the sweep's contact sheet)
  // are known, and two are never the same.
  const fs::path first = TempFileFor("out/contact_sheet.png");
  EXPECT_EQ(first.parent_path(), "out");
  EXPECT_EQ(TempFileTarget(first.filename().string()), "contact_sheet.png");
  EXPECT_NE(TempFileFor("out/contact_sheet.png"), first);
  for (const char* other : {"report.html", ".report.html", ".report.html.tmp-",
                            ".report.html.tmp-1", ".report.html.tmp-1-", ".report.html.tmp-x-1",
                            "report.html.tmp-1-2", "..tmp-1-2", ".tmp-1-2"}) {
    EXPECT_EQ(TempFileTarget(other), "") << other;
  }
}

// Those of processes that no longer run are removed; the rest stay.
TEST(WriteTextFile, StaleTemporaryFilesAreRemoved) {
  const fs::path dir =
      fs::temp_directory_path() / ("hcpf_core_stale_temp_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) ::_exit(0);
  ASSERT_EQ(::waitpid(child, nullptr, 0), child);  // its pid now names no process
  const std::string dead = ".report.html.tmp-" + std::to_string(child) + "-3";
  const std::string live = ".report.html.tmp-" + std::to_string(::getpid()) + "-0";
  for (const std::string& name :
       {dead, live, std::string("report.html"), std::string(".notes.tmp-x-1")}) {
    std::ofstream(dir / name) << "x";
  }
  RemoveStaleTempFiles(dir);
  EXPECT_FALSE(fs::exists(dir / dead));
  EXPECT_TRUE(fs::exists(dir / live));
  EXPECT_TRUE(fs::exists(dir / "report.html"));
  EXPECT_TRUE(fs::exists(dir / ".notes.tmp-x-1"));
  fs::remove_all(dir);
}

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
