#include "hcpf/core/error.h"

#include <fmt/format.h>

#include <cstdio>
#include <cstdlib>

#include "hcpf/core/check.h"
#include "hcpf/core/names.h"

namespace hcpf {

namespace {

// User text in a message, with control characters (a NUL byte, a newline,
// NEL, U+2028: names.h) shown as escapes instead of being written to the
// terminal raw.
std::string Printable(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size();) {
    const ControlCharacter c = ControlCharacterAt(text, i);
    if (c.bytes == 0) {
      out += text[i++];
      continue;
    }
    i += c.bytes;
    if (c.code == '\n') {
      out += "\\n";
    } else if (c.code == '\t') {
      out += "\\t";
    } else if (c.code == '\r') {
      out += "\\r";
    } else if (c.code < 0x80) {
      out += fmt::format("\\x{:02x}", static_cast<uint32_t>(c.code));
    } else {
      out += fmt::format("\\u{:04x}", static_cast<uint32_t>(c.code));
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
