#pragma once
// Always-on internal consistency checks. A failed check is a bug in HCPF Bench,
// never bad user input (that throws hcpf::InputError): it prints the file, the
// line and the condition, then aborts.

#include <sstream>
#include <string>

namespace hcpf::internal {

[[noreturn]] void CheckFailed(const char* file, int line, const char* condition,
                              const std::string& message);

// Collects an optional streamed message: HCPF_CHECK(x > 0) << "x=" << x;
class CheckMessage {
 public:
  CheckMessage(const char* file, int line, const char* condition)
      : file_(file), line_(line), condition_(condition) {}
  [[noreturn]] ~CheckMessage() { CheckFailed(file_, line_, condition_, stream_.str()); }
  template <typename T>
  CheckMessage& operator<<(const T& value) {
    stream_ << value;
    return *this;
  }

 private:
  const char* file_;
  int line_;
  const char* condition_;
  std::ostringstream stream_;
};

}  // namespace hcpf::internal

#define HCPF_CHECK(condition) \
  if (condition) {            \
  } else                      \
    ::hcpf::internal::CheckMessage(__FILE__, __LINE__, #condition)
