#pragma once
// Checks on the names a user gives (a scenario's name, a regress scene's
// name): what may be printed on one line, and what may name one folder.

#include <cstddef>
#include <string>
#include <string_view>

namespace hcpf {

// A character that breaks or hides a line (see FirstControlCharacter) found
// at a byte of a text: its code point and its length in bytes (0: none).
struct ControlCharacter {
  char32_t code = 0;
  size_t bytes = 0;
};

// The control character that starts at byte `i` of the UTF-8 `text`, if any.
ControlCharacter ControlCharacterAt(std::string_view text, size_t i);

// The first character of the UTF-8 `text` that would break or hide a line
// where the text is printed (a log line, seqinfo.ini, a table row), written
// as "U+000A"; "" when there is none. Those are the C0 controls, DEL, the C1
// controls (U+0080..U+009F, NEL U+0085 among them) and the line and paragraph
// separators U+2028 and U+2029. `text` must be well-formed UTF-8 (what
// YamlReader accepts).
std::string FirstControlCharacter(std::string_view text);

// Why `name` cannot name one folder inside another, or "" when it can: an
// empty name, "." or "..", a '/' or '\' (which would nest or escape the
// folder), or a control character (FirstControlCharacter).
std::string FolderNameProblem(std::string_view name);

}  // namespace hcpf
