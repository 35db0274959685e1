#pragma once
// Runs a command line through the shell for end-to-end tests and captures
// its exit code and output.

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

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

inline std::string ReadFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A fresh, empty temporary folder for one test. The process id is part of the
// name: CTest runs tests in parallel processes, and two builds may test at once.
inline std::filesystem::path FreshDir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() /
                   ("hcpf-test-" + name + "-" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// A shipped scenario, scenarios/library/<name>.yaml (name may hold a
// subfolder: "thesis/tc2-regular-hijack").
inline std::string LibraryScenario(const std::string& name) {
  return (std::filesystem::path(HCPF_SOURCE_DIR) / "scenarios" / "library" / (name + ".yaml"))
      .string();
}

}  // namespace hcpf::testing
