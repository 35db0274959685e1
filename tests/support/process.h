#pragma once
// Runs a command line through the shell for end-to-end tests and captures
// its exit code and output.

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <mutex>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

namespace hcpf::testing {

#ifdef HCPF_EXE
// The hcpf executable under test (end-to-end targets define HCPF_EXE).
inline const std::string kHcpf = HCPF_EXE;
#endif

struct ProcessResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr, interleaved
};

inline ProcessResult RunCommand(const std::string& command) {
  ProcessResult result;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return result;
  std::array<char, 4096> buffer{};
  size_t n = 0;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0)
    result.output.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return result;
}

// A file's GNU build ID as binutils' readelf prints it, lowercase hex (""
// when it has none): what the detection cache's key takes from memory, read
// here from the file by another program.
inline std::string ReadelfBuildId(const std::string& file) {
  const std::string output = RunCommand("readelf -n '" + file + "'").output;
  const std::string label = "Build ID: ";
  const size_t at = output.find(label);
  if (at == std::string::npos) return "";
  const size_t begin = at + label.size();
  return output.substr(begin, output.find_first_of(" \n", begin) - begin);
}

inline std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

namespace internal {

// Removes the folders FreshDir made for a test when the test has passed: a
// failed test's folder stays for inspection, and HCPF_KEEP_TEST_DIRS=1 keeps
// every one. (Kept, they had grown to 27 GB of /tmp on the development
// machine: every run of the suite leaves new ones, named by process id.)
class FreshDirCleaner : public ::testing::EmptyTestEventListener {
 public:
  void Add(const std::filesystem::path& dir) {
    const std::lock_guard<std::mutex> lock(mutex_);
    dirs_.push_back(dir);
  }
  void OnTestEnd(const ::testing::TestInfo& info) override {
    const std::lock_guard<std::mutex> lock(mutex_);
    const char* keep = std::getenv("HCPF_KEEP_TEST_DIRS");
    if (info.result()->Passed() && (keep == nullptr || std::string(keep) != "1")) {
      for (const auto& dir : dirs_) {
        std::error_code ec;
        std::filesystem::remove_all(dir, ec);
      }
    }
    dirs_.clear();
  }

 private:
  std::mutex mutex_;
  std::vector<std::filesystem::path> dirs_;
};

// The one cleaner of this test program, appended to GoogleTest's listeners
// (which own it) on first use.
inline FreshDirCleaner& Cleaner() {
  static FreshDirCleaner* const cleaner = [] {
    auto* c = new FreshDirCleaner;
    ::testing::UnitTest::GetInstance()->listeners().Append(c);
    return c;
  }();
  return *cleaner;
}

}  // namespace internal

// A fresh, empty temporary folder for one test, removed when the test passes
// (internal::FreshDirCleaner). The process id is part of the name: CTest runs
// tests in parallel processes, and two builds may test at once.
inline std::filesystem::path FreshDir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("hcpf-test-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  internal::Cleaner().Add(dir);
  return dir;
}

// Runs `body` in a forked child whose files may grow to `max_bytes` at most
// (RLIMIT_FSIZE with SIGXFSZ ignored, so a write beyond fails with EFBIG: a
// full disk, for the code under test) and returns the child's exit code,
// `body`'s return value; -1 when the child did not exit normally. `body`
// must not use GoogleTest's assertions (they would report in the child).
inline int InChildWithFileSizeLimit(uint64_t max_bytes, const std::function<int()>& body) {
  const pid_t child = ::fork();
  if (child < 0) return -1;
  if (child == 0) {
    std::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{static_cast<rlim_t>(max_bytes), static_cast<rlim_t>(max_bytes)};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    int code = 5;  // an exception body did not catch
    try {
      code = body();
    } catch (...) {
    }
    ::_exit(code);
  }
  int status = 0;
  if (::waitpid(child, &status, 0) != child || !WIFEXITED(status)) return -1;
  return WEXITSTATUS(status);
}

// A shipped scenario, scenarios/library/<name>.yaml (name may hold a
// subfolder: "thesis/tc2-regular-hijack").
inline std::string LibraryScenario(const std::string& name) {
  return (std::filesystem::path(HCPF_SOURCE_DIR) / "scenarios" / "library" / (name + ".yaml"))
      .string();
}

}  // namespace hcpf::testing
