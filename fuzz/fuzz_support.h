#pragma once
// Shared by the libFuzzer targets (docs/fuzzing.md). A target feeds one input
// to one loader; rejecting it with hcpf::InputError is the expected outcome,
// anything else escaping (another exception, a failed property) is a bug and
// must crash so that libFuzzer saves the input.

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <typeinfo>

#include "hcpf/core/error.h"

namespace hcpf::fuzz {

// Prints why and stops with SIGILL: libFuzzer reports a crash and writes the input.
[[noreturn]] inline void Fail(std::string_view what) {
  std::fprintf(stderr, "\nhcpf fuzz: %.*s\n", static_cast<int>(what.size()), what.data());
  std::fflush(stderr);
  __builtin_trap();
}

// HCPF_FUZZ_VERBOSE=1 prints why each input was rejected (to check that seeds load).
inline bool Verbose() {
  static const bool verbose = std::getenv("HCPF_FUZZ_VERBOSE") != nullptr;
  return verbose;
}

// Runs `load`; InputError is a rejected input (fine), any other exception a bug.
template <class F>
void ExpectInputErrorOnly(F&& load) {
  try {
    load();
    if (Verbose()) std::fprintf(stderr, "hcpf fuzz: accepted\n");
  } catch (const InputError& e) {
    // Bad input, reported the documented way.
    if (Verbose()) std::fprintf(stderr, "hcpf fuzz: rejected: %s\n", e.what());
  } catch (const std::exception& e) {
    Fail(std::string("unexpected ") + typeid(e).name() + ": " + e.what());
  } catch (...) {
    Fail("unexpected exception of a non-std type");
  }
}

// A private folder for the inputs of this process (loaders that only take a
// path), removed at exit. Private so that files a model names beside itself
// (an .obj's mtllib, a glTF buffer uri) resolve to nothing of another run.
class ScratchDir {
 public:
  ScratchDir() {
    const char* tmp = std::getenv("TMPDIR");
    dir_ = std::filesystem::path(tmp != nullptr && *tmp != '\0' ? tmp : "/tmp") /
           ("hcpf-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
  }
  ~ScratchDir() {
    std::error_code ec;
    std::filesystem::remove_all(dir_, ec);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  // Writes `size` bytes to <dir>/input<extension> and returns the path. The
  // previous input is removed first: no input can see another's file.
  std::string Write(const uint8_t* data, size_t size, const std::string& extension) const {
    for (const auto& entry : std::filesystem::directory_iterator(dir_)) {
      std::filesystem::remove_all(entry.path());
    }
    const std::string path = (dir_ / ("input" + extension)).string();
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    out.close();
    if (!out) Fail("cannot write the scratch file " + path);
    return path;
  }

  const std::filesystem::path& path() const { return dir_; }

 private:
  std::filesystem::path dir_;
};

}  // namespace hcpf::fuzz
