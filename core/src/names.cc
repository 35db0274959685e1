#include "hcpf/core/names.h"

#include <fmt/format.h>

namespace hcpf {

std::string FirstControlCharacter(std::string_view text) {
  for (size_t i = 0; i < text.size(); ++i) {
    const auto b = static_cast<unsigned char>(text[i]);
    if (b < 0x20 || b == 0x7F) return fmt::format("U+{:04X}", b);
    // U+0080..U+009F are C2 80..C2 9F; U+2028 and U+2029 are E2 80 A8/A9.
    const auto next = [&](size_t k) {
      return i + k < text.size() ? static_cast<unsigned char>(text[i + k]) : 0u;
    };
    if (b == 0xC2 && next(1) >= 0x80 && next(1) <= 0x9F) return fmt::format("U+{:04X}", next(1));
    if (b == 0xE2 && next(1) == 0x80 && (next(2) == 0xA8 || next(2) == 0xA9))
      return fmt::format("U+{:04X}", 0x2000 + next(2) - 0x80);
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
