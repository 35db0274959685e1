#include "hcpf/core/error.h"

#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>

#include "hcpf/core/check.h"

namespace hcpf {

namespace {

// User text in a message, with control characters (a NUL byte, a newline,
// NEL, U+2028: names.h) shown as escapes instead of being written to the
// terminal raw.
std::string Printable(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    const auto u = static_cast<unsigned char>(c);
    const auto next = [&](size_t k) {
      return i + k < text.size() ? static_cast<unsigned char>(text[i + k]) : 0u;
    };
    if (u == 0xC2 && next(1) >= 0x80 && next(1) <= 0x9F) {
      out += fmt::format("\\u{:04x}", next(1));
      i += 1;
    } else if (u == 0xE2 && next(1) == 0x80 && (next(2) == 0xA8 || next(2) == 0xA9)) {
      out += next(2) == 0xA8 ? "\\u2028" : "\\u2029";
      i += 2;
    } else if (c == '\n') {
      out += "\\n";
    } else if (c == '\t') {
      out += "\\t";
    } else if (c == '\r') {
      out += "\\r";
    } else if (u < 0x20 || u == 0x7f) {
      static const char kHex[] = "0123456789abcdef";
      out += "\\x";
      out += kHex[u >> 4];
      out += kHex[u & 15];
    } else {
      out += c;
    }
  }
  return out;
}

}  // namespace

std::string FormatInputError(const SourceLocation& where, const std::string& expected,
                             const std::string& found, const std::string& hint) {
  // A check made away from any file (a library's Validate() on options built
  // in code) has no location: the message then starts at the key. Errors from
  // files and the command line are located by their reader.
  std::string out = Printable(where.file);
  // (Appended piece by piece: GCC 12 at -O3 warns falsely, -Wrestrict, on
  // "literal" + std::string temporaries.)
  if (!out.empty() && where.line > 0) {
    out += ':';
    out += std::to_string(where.line);
    if (where.column > 0) {
      out += ':';
      out += std::to_string(where.column);
    }
  }
  if (!out.empty()) out += ": ";
  if (!where.key.empty()) out += Printable(where.key) + ": ";
  out += "expected " + expected + ", found " + Printable(found);
  if (!hint.empty()) out += " (" + hint + ")";
  return out;
}

InputError::InputError(SourceLocation where, std::string expected, std::string found,
                       std::string hint)
    : Error(FormatInputError(where, expected, found, hint)),
      where_(std::move(where)),
      expected_(std::move(expected)),
      found_(std::move(found)),
      hint_(std::move(hint)) {}

InputError::InputError(const std::string& message) : Error(message) {}

namespace internal {

void CheckFailed(const char* file, int line, const char* condition, const std::string& message) {
  std::fprintf(stderr, "HCPF_CHECK failed at %s:%d: %s%s%s\n", file, line, condition,
               message.empty() ? "" : ": ", message.c_str());
  std::fflush(stderr);
  std::abort();
}

}  // namespace internal
}  // namespace hcpf
