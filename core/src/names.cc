#include "hcpf/core/names.h"

#include <fmt/format.h>

namespace hcpf {

ControlCharacter ControlCharacterAt(std::string_view text, size_t i) {
  const auto byte = [&](size_t k) {
    return i + k < text.size() ? static_cast<unsigned char>(text[i + k]) : 0u;
  };
  if (i >= text.size()) return {};
  const unsigned char b = byte(0);
  if (b < 0x20 || b == 0x7F) return {b, 1};
  // U+0080..U+009F are C2 80..C2 9F; U+2028 and U+2029 are E2 80 A8/A9.
  if (b == 0xC2 && byte(1) >= 0x80 && byte(1) <= 0x9F) return {byte(1), 2};
  if (b == 0xE2 && byte(1) == 0x80 && (byte(2) == 0xA8 || byte(2) == 0xA9))
    return {0x2000 + byte(2) - 0x80, 3};
  return {};
}

std::string FirstControlCharacter(std::string_view text) {
  for (size_t i = 0; i < text.size(); ++i) {
    if (const ControlCharacter c = ControlCharacterAt(text, i); c.bytes > 0)
      return fmt::format("U+{:04X}", static_cast<uint32_t>(c.code));
  }
  return "";
}

std::string FolderNameProblem(std::string_view name) {
  if (name.empty()) return "an empty name";
  if (name == "." || name == "..")
    return fmt::format("\"{}\", which names no folder of its own", name);
  if (name.find_first_of("/\\") != std::string_view::npos)
    return fmt::format("\"{}\", whose '/' or '\\' would nest or escape the folder", name);
  if (const std::string c = FirstControlCharacter(name); !c.empty())
    return fmt::format("a name with the control character {}", c);
  return "";
}

}  // namespace hcpf
