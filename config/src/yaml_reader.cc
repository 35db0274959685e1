#include "hcpf/config/yaml_reader.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/eventhandler.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>
#include <utility>
#include <vector>

#include "hcpf/core/text_file.h"

namespace hcpf::config {
namespace {

std::string Quote(const std::string& s) { return "\"" + s + "\""; }

// An integer written with a leading zero (0500, -05): YAML 1.2, and
// yaml-cpp, read it as decimal, YAML 1.1 readers (PyYAML) as octal (0500 is
// 320 there), so a file means two things: refused, with kLeadingZeroHint (an
// audit found 0500 read as 500 without a word).
bool HasLeadingZero(const std::string& text) {
  const size_t digits = !text.empty() && (text[0] == '+' || text[0] == '-') ? 1 : 0;
  return text.size() >= digits + 2 && text[digits] == '0' &&
         std::all_of(text.begin() + static_cast<std::ptrdiff_t>(digits), text.end(),
                     [](char c) { return c >= '0' && c <= '9'; });
}

constexpr const char* kLeadingZeroHint =
    "no leading zero: YAML 1.1 readers take 0500 as octal (320), so write 500";

// The hint for a number that failed to read: kLeadingZeroHint when its text
// has a leading zero, else none.
std::string NumberHint(const YAML::Node& node) {
  return node.IsScalar() && HasLeadingZero(node.Scalar()) ? kLeadingZeroHint : "";
}

bool ParseDouble(const std::string& text, double* out) {
  if (text.empty() || StartsWithTwoSigns(text) || HasLeadingZero(text)) return false;
  // YAML spellings of infinity/NaN are not accepted anywhere in the schema.
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  if (*begin == '+') ++begin;
  auto [ptr, ec] = std::from_chars(begin, end, *out);
  return ec == std::errc() && ptr == end && std::isfinite(*out);
}

bool ParseInt(const std::string& text, int64_t* out) {
  if (text.empty() || StartsWithTwoSigns(text) || HasLeadingZero(text)) return false;
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  if (*begin == '+') ++begin;
  auto [ptr, ec] = std::from_chars(begin, end, *out);
  return ec == std::errc() && ptr == end;
}

std::string RangeText(double lo, double hi) { return Closed(lo, hi).Text(); }

// The code point of the UTF-8 sequence at `text[i]` and its length in bytes
// (a byte that starts no sequence counts as itself, one byte long).
std::pair<char32_t, size_t> CodePointAt(std::string_view text, size_t i) {
  const auto b = [&text](size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char lead = b(i);
  const size_t more = lead >= 0xF0 ? 3 : lead >= 0xE0 ? 2 : lead >= 0xC0 ? 1 : 0;
  if (more == 0 || i + more >= text.size()) return {lead, 1};
  char32_t cp = lead & (0x3F >> more);
  for (size_t k = 1; k <= more; ++k) {
    if ((b(i + k) & 0xC0) != 0x80) return {lead, 1};
    cp = (cp << 6) | (b(i + k) & 0x3F);
  }
  return {cp, more + 1};
}

// Characters that do not show, or show as a plain space, in an editor: in a
// key they make a typo nobody can see.
const char* InvisibleName(char32_t cp) {
  switch (cp) {
    case 0x00A0:
      return "NO-BREAK SPACE";
    case 0x00AD:
      return "SOFT HYPHEN";
    case 0x200B:
      return "ZERO WIDTH SPACE";
    case 0x200C:
      return "ZERO WIDTH NON-JOINER";
    case 0x200D:
      return "ZERO WIDTH JOINER";
    case 0x2060:
      return "WORD JOINER";
    case 0x202F:
      return "NARROW NO-BREAK SPACE";
    case 0xFEFF:
      return "ZERO WIDTH NO-BREAK SPACE";
    default:
      return nullptr;
  }
}

// A character past ASCII that an editor shows as an ASCII one: a key,
// choice or number written with it was refused with a message whose "found"
// looked the same as the expected text (`frаmes` with a Cyrillic а, `−40`
// with a minus sign: letters from another keyboard layout, a minus from a
// word processor).
struct LookAlike {
  char32_t code_point;
  char ascii;
  const char* name;
};

constexpr LookAlike kLookAlikes[] = {
    {0x0430, 'a', "CYRILLIC SMALL LETTER A"},
    {0x0441, 'c', "CYRILLIC SMALL LETTER ES"},
    {0x0501, 'd', "CYRILLIC SMALL LETTER KOMI DE"},
    {0x0435, 'e', "CYRILLIC SMALL LETTER IE"},
    {0x04BB, 'h', "CYRILLIC SMALL LETTER SHHA"},
    {0x0456, 'i', "CYRILLIC SMALL LETTER BYELORUSSIAN-UKRAINIAN I"},
    {0x03B9, 'i', "GREEK SMALL LETTER IOTA"},
    {0x0458, 'j', "CYRILLIC SMALL LETTER JE"},
    {0x043E, 'o', "CYRILLIC SMALL LETTER O"},
    {0x03BF, 'o', "GREEK SMALL LETTER OMICRON"},
    {0x0440, 'p', "CYRILLIC SMALL LETTER ER"},
    {0x03C1, 'p', "GREEK SMALL LETTER RHO"},
    {0x0455, 's', "CYRILLIC SMALL LETTER DZE"},
    {0x03BD, 'v', "GREEK SMALL LETTER NU"},
    {0x0445, 'x', "CYRILLIC SMALL LETTER HA"},
    {0x0443, 'y', "CYRILLIC SMALL LETTER U"},
    {0x2010, '-', "HYPHEN"},
    {0x2011, '-', "NON-BREAKING HYPHEN"},
    {0x2012, '-', "FIGURE DASH"},
    {0x2013, '-', "EN DASH"},
    {0x2212, '-', "MINUS SIGN"},
    {0xFE63, '-', "SMALL HYPHEN-MINUS"},
    {0xFF0D, '-', "FULLWIDTH HYPHEN-MINUS"},
    {0x2024, '.', "ONE DOT LEADER"},
    {0xFF0E, '.', "FULLWIDTH FULL STOP"},
};

const LookAlike* LookAlikeOf(char32_t cp) {
  for (const LookAlike& entry : kLookAlikes) {
    if (entry.code_point == cp) return &entry;
  }
  return nullptr;
}

// `text` with its invisible characters written as \uXXXX; `note` gets "(it
// holds U+200B ZERO WIDTH SPACE)", naming every code point past ASCII, when
// one is invisible or looks like an ASCII character ("U+0430 CYRILLIC SMALL
// LETTER A, which looks like 'a'"), else "".
std::string EscapeInvisible(const std::string& text, std::string* note = nullptr) {
  std::string shown;
  std::vector<std::string> held;
  bool confusing = false;
  for (size_t i = 0; i < text.size();) {
    const auto [cp, length] = CodePointAt(text, i);
    const char* name = cp >= 0x80 ? InvisibleName(cp) : nullptr;
    const LookAlike* look_alike = cp >= 0x80 ? LookAlikeOf(cp) : nullptr;
    if (name != nullptr) {
      confusing = true;
      shown += fmt::format("\\u{:04X}", static_cast<uint32_t>(cp));
    } else {
      shown.append(text, i, length);
    }
    if (cp >= 0x80) {
      std::string item = fmt::format("U+{:04X}", static_cast<uint32_t>(cp));
      if (name != nullptr) item += std::string(" ") + name;
      if (look_alike != nullptr) {
        confusing = true;
        item += fmt::format(" {}, which looks like '{}'", look_alike->name, look_alike->ascii);
      }
      if (std::find(held.begin(), held.end(), item) == held.end()) held.push_back(item);
    }
    i += length;
  }
  if (note != nullptr) *note = confusing ? fmt::format("(it holds {})", fmt::join(held, "; ")) : "";
  return shown;
}

// `text` in quotes, its invisible characters shown: "fr\u200Bames" (it
// holds U+200B ZERO WIDTH SPACE). Other text is only quoted.
std::string QuoteShowingInvisible(const std::string& text) {
  std::string note;
  const std::string shown = Quote(EscapeInvisible(text, &note));
  return note.empty() ? shown : shown + " " + note;
}

// A key as compared for "did you mean": invisible characters dropped,
// look-alikes read as the ASCII character they look like, ASCII letters in
// lower case (keys are all lower case).
std::string Normalised(const std::string& key) {
  std::string out;
  for (size_t i = 0; i < key.size();) {
    const auto [cp, length] = CodePointAt(key, i);
    if (cp < 0x80) {
      out += static_cast<char>(std::tolower(static_cast<unsigned char>(key[i])));
    } else if (const LookAlike* look_alike = LookAlikeOf(cp); look_alike != nullptr) {
      out += look_alike->ascii;
    } else if (InvisibleName(cp) == nullptr) {
      out.append(key, i, length);
    }
    i += length;
  }
  return out;
}

constexpr std::string_view kStrTag = "tag:yaml.org,2002:str";

// What a scalar is read as.
enum class ScalarKind { kNumber, kInteger, kBoolean };

// A scalar YAML reads as `kind`: plain, or with the core tag of that kind
// (!!int or !!float for a number, !!int for an integer, !!bool). A quoted
// "30" or a !!str 30 is text: a second bad-input audit found them read as
// numbers. A tag that says otherwise than the text is refused (`!!int 30.5`
// was read as 30.5, `!!float 240` as the integer 240: a tag stated and then
// ignored).
bool TypedScalar(const YAML::Node& node, ScalarKind kind = ScalarKind::kNumber) {
  if (!node.IsScalar()) return false;
  const std::string& tag = node.Tag();
  if (tag == "?") return true;
  int64_t integer = 0;
  switch (kind) {
    case ScalarKind::kBoolean:
      return tag == "tag:yaml.org,2002:bool";
    case ScalarKind::kInteger:
      return tag == "tag:yaml.org,2002:int";
    case ScalarKind::kNumber:
      return tag == "tag:yaml.org,2002:float" ||
             (tag == "tag:yaml.org,2002:int" && ParseInt(node.Scalar(), &integer));
  }
  return false;
}

// How a tag is written in a file: !!int for a YAML core tag, else as given.
std::string TagText(const std::string& tag) {
  constexpr std::string_view kCore = "tag:yaml.org,2002:";
  if (tag.rfind(kCore, 0) == 0) return "!!" + tag.substr(kCore.size());
  if (!tag.empty() && tag[0] == '!') return tag;
  return "!<" + tag + ">";
}

// Whether a node's `tag` is none (written or made by an override), the
// non-specific one of a quoted value, or the core tag `kind` of what it is
// read as (!!map, !!seq, !!str): other tags were silently ignored (a third
// bad-input audit: `name: !!binary aGVsbG8=`, `tracker: !!seq` on a mapping).
bool PlainTag(const std::string& tag, std::string_view kind) {
  return tag.empty() || tag == "?" || tag == "!" || tag == "tag:yaml.org,2002:" + std::string(kind);
}

}  // namespace

std::string FlowText(const YAML::Node& node) {
  YAML::Emitter out;
  out.SetMapFormat(YAML::Flow);
  out.SetSeqFormat(YAML::Flow);
  out << node;
  return out.c_str();
}

std::string DescribeNullRoot(const YAML::Node& root) {
  if (root.IsDefined() && root.Mark().line >= 0) {
    return "a null value (~ or null) where a mapping goes";
  }
  return "an empty file (nothing but blanks or comments)";
}

YamlReader::YamlReader(YAML::Node node, std::string path,
                       std::shared_ptr<const YamlContext> context)
    : node_(std::move(node)),
      path_(std::move(path)),
      context_(std::move(context)),
      asked_(std::make_shared<std::set<std::string>>()) {}

namespace {

// What the parser reports of one document: where its first value starts (-1
// when it is empty) and where its last event was.
struct DocumentSpan {
  int first_line = -1;
  int last_pos = -1;
  YAML::Mark last;
};

// A scalar the parser handed out with a tag other than "?" (a quoted one, or
// one with a tag): where its node starts (its properties included) and its
// dotted key path.
struct TaggedScalar {
  YAML::Mark mark;
  std::string path;  // the value's dotted path; a key's: its mapping's
  bool key = false;  // a key of a mapping
};

// Walks a stream's documents without building them. YAML::LoadAll cannot be
// used: in yaml-cpp 0.7 a stray ',' makes the parser hand out empty documents
// forever without consuming input (jbeder/yaml-cpp#1040, fixed upstream by
// #1319 after Debian 12's version). A document that ends where the previous
// one ended is that loop. It also keeps the dotted key path of every node
// and the scalars that may be quoted, to check their closing quotes.
class DocumentScanner final : public YAML::EventHandler {
 public:
  DocumentSpan Take() {
    DocumentSpan out = span_;
    span_ = {};
    return out;
  }
  const std::vector<TaggedScalar>& tagged() const { return tagged_; }
  // Where the last event was, and the path of the node after it.
  const YAML::Mark& last() const { return span_.last; }
  // Whether the node after the last event is a key of a mapping.
  bool NextIsKey() const { return !stack_.empty() && stack_.back().map && stack_.back().key_next; }
  std::string NextPath() const {
    if (stack_.empty()) return "";
    const Level& level = stack_.back();
    if (!level.map) return level.path + "[" + std::to_string(level.index) + "]";
    if (level.key_next) return level.path;
    return level.path.empty() ? level.key : level.path + "." + level.key;
  }
  void OnDocumentStart(const YAML::Mark& mark) override {
    stack_.clear();
    Saw(mark, false);
  }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark& mark, YAML::anchor_t) override {
    Enter("~");
    Saw(mark, false);
  }
  void OnAlias(const YAML::Mark& mark, YAML::anchor_t) override {
    Enter("*");
    Saw(mark, true);
  }
  void OnScalar(const YAML::Mark& mark, const std::string& tag, YAML::anchor_t,
                const std::string& value) override {
    const std::string path = Enter(value);
    // A quoted key is named by its mapping's path: the text of a key whose
    // quote never closes is the rest of the file (`[20, "40]` gave the key
    // path "particles[1].40] ", a bad-input audit). An error adds the word
    // before the colon on the quote's line (QuotedKeyPath).
    const bool key = !stack_.empty() && stack_.back().map && !stack_.back().key_next;
    if (tag != "?") tagged_.push_back({mark, key ? stack_.back().path : path, key});
    Saw(mark, true);
  }
  void OnSequenceStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t,
                       YAML::EmitterStyle::value) override {
    stack_.push_back({false, Enter("?")});
    Saw(mark, true);
  }
  void OnSequenceEnd() override { Leave(); }
  void OnMapStart(const YAML::Mark& mark, const std::string&, YAML::anchor_t,
                  YAML::EmitterStyle::value) override {
    stack_.push_back({true, Enter("?")});
    Saw(mark, true);
  }
  void OnMapEnd() override { Leave(); }

 private:
  struct Level {
    bool map = false;
    std::string path;
    int index = 0;  // the next list item
    bool key_next = true;
    std::string key;
  };
  // The dotted path of the node that starts now (a key names its own path);
  // `scalar` is its text, kept when the node is a key.
  std::string Enter(const std::string& scalar) {
    if (stack_.empty()) return "";
    Level& level = stack_.back();
    const auto join = [&level](const std::string& key) {
      return level.path.empty() ? key : level.path + "." + key;
    };
    if (!level.map) return level.path + "[" + std::to_string(level.index++) + "]";
    level.key_next = !level.key_next;
    if (!level.key_next) level.key = scalar;  // this node is a key
    return join(level.key);
  }
  void Leave() {
    if (!stack_.empty()) stack_.pop_back();
  }
  void Saw(const YAML::Mark& mark, bool value) {
    if (value && span_.first_line < 0) span_.first_line = mark.line;
    span_.last_pos = mark.pos;
    span_.last = mark;
  }
  DocumentSpan span_;
  std::vector<Level> stack_;
  std::vector<TaggedScalar> tagged_;
};

// The offset of the closing quote of the quoted scalar whose opening quote is
// at `open` (`\\` escapes in double quotes, '' in single ones), or npos when
// the text ends first.
size_t ClosingQuote(const std::string& text, size_t open) {
  const char quote = text[open];
  for (size_t i = open + 1; i < text.size(); ++i) {
    if (quote == '"' && text[i] == '\\') {
      ++i;
    } else if (text[i] == quote) {
      if (quote == '\'' && i + 1 < text.size() && text[i + 1] == '\'') {
        ++i;
      } else {
        return i;
      }
    }
  }
  return std::string::npos;
}

// The offset of the opening quote of a scalar node starting at `pos` (past
// its tag and anchor), or npos when it is not quoted.
size_t OpeningQuote(const std::string& text, size_t pos) {
  while (pos < text.size()) {
    const char c = text[pos];
    if (c == ' ' || c == '\t' || c == '\r' || c == '\n') {
      ++pos;
    } else if (c == '!' || c == '&') {
      while (pos < text.size() && text[pos] != ' ' && text[pos] != '\t' && text[pos] != '\n') ++pos;
    } else if (c == '#') {
      while (pos < text.size() && text[pos] != '\n') ++pos;
    } else {
      break;
    }
  }
  return pos < text.size() && (text[pos] == '"' || text[pos] == '\'') ? pos : std::string::npos;
}

// The offset of a quote after `from` that opens a value (after a blank, a
// line start or one of : - [ { , ?) and is never closed, or npos.
size_t UnclosedQuote(const std::string& text, size_t from) {
  for (size_t i = from; i < text.size();) {
    const size_t q = text.find_first_of("\"'#", i);
    if (q == std::string::npos) return q;
    if (text[q] == '#') {
      // A comment (after a blank or at a line's start) runs to the line's
      // end: an apostrophe there opens nothing (a review found "# don't"
      // reported as the quote left open).
      const bool comment =
          q == 0 || text[q - 1] == ' ' || text[q - 1] == '\t' || text[q - 1] == '\n';
      i = comment ? text.find('\n', q) : q + 1;
      if (i == std::string::npos) return i;
      continue;
    }
    const size_t before = q == 0 ? std::string::npos : text.find_last_not_of(" \t", q - 1);
    const bool opens = before == std::string::npos ||
                       std::string_view(":-[{,?\n").find(text[before]) != std::string::npos ||
                       q > before + 1;
    if (!opens) {
      i = q + 1;
      continue;
    }
    const size_t close = ClosingQuote(text, q);
    if (close == std::string::npos) return q;
    i = close + 1;
  }
  return std::string::npos;
}

// The column (from 0) where a line's content starts past its indentation
// and block-list dashes (`  - name: x` -> 4): where its key is.
size_t KeyColumn(std::string_view line) {
  size_t i = 0;
  while (true) {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
    if (i + 1 < line.size() && line[i] == '-' && (line[i + 1] == ' ' || line[i + 1] == '\t')) {
      ++i;
      continue;
    }
    return i;
  }
}

// Whether `line` reads as a `key:` line of a mapping (`  particles: 50`,
// `- id: 2`): a word, a colon, then a blank or the end.
bool LooksLikeKeyLine(std::string_view line) {
  size_t i = 0;
  const auto blanks = [&] {
    while (i < line.size() && (line[i] == ' ' || line[i] == '\t')) ++i;
  };
  blanks();
  while (i + 1 < line.size() && line[i] == '-' && (line[i + 1] == ' ' || line[i + 1] == '\t')) {
    ++i;
    blanks();
  }
  const size_t word = i;
  while (i < line.size() && (std::isalnum(static_cast<unsigned char>(line[i])) || line[i] == '_' ||
                             (i > word && (line[i] == '.' || line[i] == '-')))) {
    ++i;
  }
  if (i == word) return false;
  blanks();
  return i < line.size() && line[i] == ':' &&
         (i + 1 == line.size() || line[i + 1] == ' ' || line[i + 1] == '\t' || line[i + 1] == '\r');
}

// Refuses a tab or a no-break space (U+00A0) where YAML wants a space, on
// line `line` (0-based, where yaml-cpp reported a syntax error) or the line
// before it: a tab in the indentation, or U+00A0 in it or after a key's
// colon. yaml-cpp says only "illegal map value", for U+00A0 on the next line
// (a third bad-input audit); both come in with text pasted from web pages.
void CheckBlanks(const std::string& text, const std::string& file, int line) {
  constexpr std::string_view kNbsp = "\xC2\xA0";
  const std::string nbsp = "U+00A0 (no-break space)";
  const size_t bom = ByteOrderMarkLength(text);
  std::vector<size_t> starts = {bom};
  for (size_t at = text.find('\n'); at != std::string::npos; at = text.find('\n', at + 1)) {
    starts.push_back(at + 1);
  }
  for (const int n : {line, line - 1}) {
    if (n < 0 || n >= static_cast<int>(starts.size())) continue;
    const size_t start = starts[n];
    const size_t end = std::min(text.find('\n', start), text.size());
    const std::string_view content(text.data() + start, end - start);
    const auto refuse = [&](size_t offset, const std::string& expected, const std::string& found) {
      throw InputError(SourceLocation{file, n + 1, static_cast<int>(offset) + 1, ""}, expected,
                       found);
    };
    for (size_t i = 0; i < content.size(); ++i) {
      if (content[i] == '\t') refuse(i, "indentation with spaces", "a tab");
      if (content.substr(i, 2) == kNbsp) refuse(i, "indentation with spaces", nbsp);
      // A list item's dash ("  -\tid: 2" gave "illegal map value"): the
      // blank after it indents the item's content. Only on the line of the
      // error, which is where yaml-cpp reports it: the line before may be
      // text of a block scalar (a review).
      if (content[i] == '-' && i + 1 < content.size() && n == line) {
        if (content[i + 1] == '\t') refuse(i + 1, "a space after '-'", "a tab");
        if (content.substr(i + 1, 2) == kNbsp) refuse(i + 1, "a space after '-'", nbsp);
        if (content[i + 1] == ' ') continue;
      }
      if (content[i] != ' ') break;
    }
    // Up to a comment or a quote, where U+00A0 may be text.
    const size_t stop = std::min(content.find_first_of("#\"'"), content.size());
    const size_t colon = content.substr(0, stop).find(std::string(":") + std::string(kNbsp));
    if (colon != std::string_view::npos) refuse(colon + 1, "a space after ':'", nbsp);
  }
}

// The dotted path to name a quoted scalar left open by: a value's own; a
// key's, its mapping's and, where the quote's line reads `"word: ...`, the
// word (`"seed: 3` at the top level had no key to name, a review; the text
// yaml-cpp read as the key is the rest of the file).
std::string QuotedKeyPath(const std::string& text, size_t open, const TaggedScalar& scalar) {
  if (!scalar.key) return scalar.path;
  const size_t line_end = std::min(text.find('\n', open), text.size());
  const std::string_view rest(text.data() + open + 1, line_end - open - 1);
  if (!LooksLikeKeyLine(rest) || KeyColumn(rest) != 0) return scalar.path;
  std::string_view word = rest.substr(0, rest.find(':'));
  word = word.substr(0, word.find_last_not_of(" \t") + 1);
  return scalar.path.empty() ? std::string(word) : scalar.path + "." + std::string(word);
}

// Refuses a quoted scalar that is never closed, or that goes on over a line
// that reads as a key: yaml-cpp reads an unclosed quote at the end of a file
// that ends in a newline as a value running to the end, so `name: "small`
// silently took in the rest of the file (a third bad-input audit). A quoted
// value that spans lines is valid YAML and is kept when no line inside it
// looks like a key.
void CheckQuotedScalars(const std::string& text, const std::string& file,
                        const std::vector<TaggedScalar>& scalars) {
  // yaml-cpp's positions do not count a byte-order mark.
  const size_t bom = ByteOrderMarkLength(text);
  for (const TaggedScalar& scalar : scalars) {
    const size_t open = OpeningQuote(text, static_cast<size_t>(scalar.mark.pos) + bom);
    if (open == std::string::npos) continue;
    const size_t close = ClosingQuote(text, open);
    // Most quoted values close on their own line: nothing more to look at
    // (and no position to count, which made the check quadratic in the
    // number of quoted values: a review).
    if (close != std::string::npos && text.find('\n', open) > close) continue;
    const TextPosition from = PositionOf(text, open);
    const SourceLocation where{file, from.line, from.column, QuotedKeyPath(text, open, scalar)};
    const std::string quote = text[open] == '"' ? "a \" quote" : "a ' quote";
    // The key that owns the value: a continuation line that reads as a key
    // no deeper than it is a key of that mapping or an outer one; deeper, it
    // is text of the value (`name: "crossing of` / `  two: targets"`).
    const size_t line_of_open =
        text.rfind('\n', open) == std::string::npos ? bom : text.rfind('\n', open) + 1;
    const size_t owner_column =
        KeyColumn(std::string_view(text.data() + line_of_open, open - line_of_open));
    const std::string expected = "a quoted value closed before the next key";
    const std::string hint =
        "close the quote on the line where the value ends, or write text over several lines "
        "as a block scalar: key: >";
    if (close == std::string::npos) {
      throw InputError(where, expected,
                       fmt::format("{} opened at line {} that is never closed (it runs on to the "
                                   "end of the file)",
                                   quote, from.line),
                       hint);
    }
    size_t line_start = text.find('\n', open);
    for (int line = from.line + 1; line_start < close; ++line) {
      ++line_start;
      const size_t line_end = std::min(text.find('\n', line_start), close);
      const std::string_view content(text.data() + line_start, line_end - line_start);
      if (LooksLikeKeyLine(content) && KeyColumn(content) <= owner_column) {
        std::string shown(content.substr(content.find_first_not_of(" \t")));
        shown.erase(shown.find_last_not_of(" \t\r") + 1);
        throw InputError(where, expected,
                         fmt::format("{} opened at line {} that runs on to line {}, taking in "
                                     "line {} (\"{}\"), which reads as a key",
                                     quote, from.line, PositionOf(text, close).line, line, shown),
                         hint);
      }
      line_start = text.find('\n', line_start);
    }
  }
}

// The offset of the first byte that does not belong to well-formed UTF-8
// (Unicode's table 3-7: no overlong forms, surrogates or code points past
// U+10FFFF), or npos.
size_t FirstNonUtf8(const std::string& text) {
  const auto byte = [&text](size_t i) { return static_cast<unsigned char>(text[i]); };
  const auto in = [](unsigned char b, unsigned lo, unsigned hi) { return b >= lo && b <= hi; };
  size_t i = 0;
  while (i < text.size()) {
    const unsigned char b = byte(i);
    if (b < 0x80) {
      ++i;
      continue;
    }
    size_t more = 0;
    unsigned lo = 0x80, hi = 0xBF;  // the range of the second byte
    if (in(b, 0xC2, 0xDF)) {
      more = 1;
    } else if (in(b, 0xE0, 0xEF)) {
      more = 2;
      if (b == 0xE0) lo = 0xA0;
      if (b == 0xED) hi = 0x9F;
    } else if (in(b, 0xF0, 0xF4)) {
      more = 3;
      if (b == 0xF0) lo = 0x90;
      if (b == 0xF4) hi = 0x8F;
    } else {
      return i;
    }
    if (i + more >= text.size() || !in(byte(i + 1), lo, hi)) return i;
    for (size_t k = 2; k <= more; ++k) {
      if (!in(byte(i + k), 0x80, 0xBF)) return i;
    }
    i += more + 1;
  }
  return std::string::npos;
}

}  // namespace

YAML::Node YamlReader::Parse(const std::string& text, const std::string& file) {
  // A UTF-16 or UTF-32 byte-order mark (a Windows editor's "Unicode"): named
  // as such, not as a Latin-1 byte (an audit).
  for (const auto& [mark, encoding] : {std::pair<std::string_view, std::string_view>{
                                           std::string_view("\x00\x00\xFE\xFF", 4), "UTF-32BE"},
                                       {std::string_view("\xFF\xFE\x00\x00", 4), "UTF-32LE"},
                                       {"\xFE\xFF", "UTF-16BE"},
                                       {"\xFF\xFE", "UTF-16LE"}}) {
    if (!text.starts_with(mark)) continue;
    std::string bytes;
    for (const char c : mark) {
      bytes += fmt::format("{}{:02X}", bytes.empty() ? "" : " ", static_cast<unsigned char>(c));
    }
    throw InputError(SourceLocation{file, 1, 1, ""}, "UTF-8 text",
                     fmt::format("a {} byte-order mark ({}): the file is {}", encoding, bytes,
                                 encoding.substr(0, 6)),
                     fmt::format("save the file as UTF-8, e.g. iconv -f {} -t UTF-8", encoding));
  }
  if (const size_t bad = FirstNonUtf8(text); bad != std::string::npos) {
    // yaml-cpp passes such bytes through into strings, where they break the
    // JSON outputs much later: refuse them here, where the line is known.
    const TextPosition at = PositionOf(text, bad);
    throw InputError(SourceLocation{file, at.line, at.column, ""}, "UTF-8 text",
                     fmt::format("the byte 0x{:02X}, which UTF-8 does not allow there",
                                 static_cast<unsigned char>(text[bad])),
                     "save the file as UTF-8; a Latin-1 editor writes é as the byte 0xE9");
  }
  std::vector<DocumentSpan> documents;
  YAML::Node first;
  DocumentScanner scanner;
  try {
    std::istringstream in(text);
    YAML::Parser parser(in);
    while (parser.HandleNextDocument(scanner)) {
      const DocumentSpan span = scanner.Take();
      if (!documents.empty() && span.last_pos == documents.back().last_pos) {
        throw InputError(SourceLocation{file, span.last.line + 1, span.last.column + 1, ""},
                         "valid YAML",
                         "a syntax error: a character that starts no value (a stray ',' or "
                         "bracket?)");
      }
      documents.push_back(span);
    }
    if (documents.size() <= 1) first = YAML::Load(text);
  } catch (const YAML::DeepRecursion& e) {
    SourceLocation where{file, e.mark.line + 1, e.mark.column + 1, ""};
    // (yaml-cpp's own message for this is "bad file".)
    throw InputError(where, "YAML nested less deeply",
                     fmt::format("lists or mappings nested {} levels deep", e.depth()));
  } catch (const YAML::ParserException& e) {
    // A quote left open earlier takes in the lines after it until the next
    // quote closes it, and the error comes later: report the quote.
    CheckQuotedScalars(text, file, scanner.tagged());
    if (e.msg == YAML::ErrorMsg::EOF_IN_SCALAR) {
      // A quote still open where a file without a final newline ends: say so
      // at the quote (yaml-cpp reports the end of the file).
      const size_t bom = ByteOrderMarkLength(text);
      const size_t open =
          UnclosedQuote(text, scanner.last().pos < 0 ? 0 : scanner.last().pos + bom);
      if (open != std::string::npos) {
        YAML::Mark mark;
        mark.pos = static_cast<int>(open - bom);
        CheckQuotedScalars(text, file,
                           {TaggedScalar{mark, scanner.NextPath(), scanner.NextIsKey()}});
      }
    }
    CheckBlanks(text, file, e.mark.line);
    SourceLocation where{file, e.mark.line + 1, e.mark.column + 1, ""};
    throw InputError(where, "valid YAML", "a syntax error: " + e.msg);
  }
  CheckQuotedScalars(text, file, scanner.tagged());
  if (first.IsScalar() && first.Tag() == "?") {
    // A one-line file "frames:<U+00A0>20" is a single plain value, no
    // mapping, and was refused as "a single value" without a word on why.
    // Every one: a comment line above may hold one (a review).
    for (size_t nbsp = text.find(":\xC2\xA0"); nbsp != std::string::npos;
         nbsp = text.find(":\xC2\xA0", nbsp + 1)) {
      CheckBlanks(text, file,
                  static_cast<int>(std::count(text.begin(), text.begin() + nbsp, '\n')));
    }
  }
  if (documents.size() > 1) {
    // A stray "---" or "..." line ends the first document: everything after
    // it would be silently ignored. Report the separator before the second
    // document (the last one in the file when the second is empty).
    const int second_line = documents[1].first_line;  // 0-based, -1 when empty
    int separator = 0;
    std::istringstream lines(text);
    std::string line;
    for (int n = 0; std::getline(lines, line); ++n) {
      const bool is_separator = line.rfind("---", 0) == 0 || line.rfind("...", 0) == 0;
      if (is_separator && (second_line < 0 || n <= second_line)) separator = n + 1;
    }
    throw InputError(SourceLocation{file, separator, separator > 0 ? 1 : 0, ""},
                     "one YAML document",
                     "a second document after a '---' or '...' line (everything after it "
                     "would be ignored)",
                     "remove the line, or put the second document in a file of its own");
  }
  return first;
}

std::string YamlReader::ReadFile(const std::string& file) {
  constexpr uint64_t kMaxYamlBytes = uint64_t{16} << 20;
  return ReadInputFile(file, "a YAML file", kMaxYamlBytes);
}

YAML::Node YamlReader::ParseFile(const std::string& file) { return Parse(ReadFile(file), file); }

SourceLocation YamlReader::Where() const {
  SourceLocation where{context_->file, 0, 0, path_};
  // List indices may be written either way ("a[0]" or "a.0").
  const auto normalised = [](const std::string& p) {
    std::string out;
    for (char c : p) {
      if (c == '[') {
        out += '.';
      } else if (c != ']') {
        out += c;
      }
    }
    return out;
  };
  const std::string mine = normalised(path_);
  // A value set on the command line is reported there: the key itself, a
  // key below it, or an item of a list it set (`--set camera.resolution=[320,
  // abc]`: camera.resolution[1]; `--set camera.resolution.0=320.5`:
  // camera.resolution[0]).
  for (const auto& [prefix, origin] : context_->overrides) {
    const std::string theirs = normalised(prefix);
    if (mine == theirs || mine.rfind(theirs + ".", 0) == 0) {
      where.file = origin.label;
      where.override_index = origin.index;
      return where;
    }
  }
  if (node_.IsDefined()) {
    // An empty value ("particles:") has no position of its own (the parser
    // marks the next token, often on the next line): report its key's.
    const YAML::Mark mark = node_.IsNull() && key_mark_.line >= 0 ? key_mark_ : node_.Mark();
    if (mark.line >= 0) {
      where.line = mark.line + 1;
      where.column = mark.column + 1;
    }
  }
  if (where.line == 0) {
    // A node the file does not hold was made by an override on the way to
    // its key (`--set trackr.particles=10` makes "trackr"): report that
    // override.
    for (const auto& [prefix, origin] : context_->overrides) {
      const std::string theirs = normalised(prefix);
      if (!mine.empty() && (theirs == mine || theirs.rfind(mine + ".", 0) == 0)) {
        where.file = origin.label;
        where.override_index = origin.index;
        return where;
      }
    }
  }
  return where;
}

SourceLocation YamlReader::WhereKey(const std::string& key) const {
  SourceLocation where = Where();
  // A missing key is reported where its mapping's own key is written
  // ("camera:"), which is more useful than the mapping's first entry.
  if (where.file == context_->file && key_mark_.line >= 0) {
    where.line = key_mark_.line + 1;
    where.column = key_mark_.column + 1;
  }
  where.key = ChildPath(key);
  return where;
}

void YamlReader::Fail(const std::string& expected, const std::string& hint) const {
  throw InputError(Where(), expected, Describe(), hint);
}

std::string YamlReader::Describe() const {
  if (!node_.IsDefined() || node_.IsNull()) return "nothing (an empty value)";
  // A tag is named: `frames: !foo 20` said 'found "20"' (a third bad-input
  // audit).
  const std::string& tag = node_.Tag();
  if (node_.IsMap()) {
    // An empty one is said to be (`metrics: {}` "found a mapping" where a
    // mapping of metrics was expected: a bad-input audit).
    const std::string map = node_.size() == 0 ? "an empty mapping" : "a mapping";
    return PlainTag(tag, "map") ? map : map + " tagged " + TagText(tag);
  }
  if (node_.IsSequence()) {
    const std::string list = fmt::format("a list of {} item(s)", node_.size());
    return PlainTag(tag, "seq") ? list : list + " tagged " + TagText(tag);
  }
  // Quoted or tagged !!str, a number or boolean is text: say so, or the
  // message would read 'expected an integer, found "30"'.
  const std::string& text = node_.Scalar();
  double number = 0.0;
  if ((node_.Tag() == "!" || node_.Tag() == kStrTag) &&
      (ParseDouble(text, &number) || text == "true" || text == "false")) {
    return fmt::format("the text {} ({}: write it without {} for a {})", Quote(text),
                       node_.Tag() == "!" ? "in quotes" : "tagged !!str",
                       node_.Tag() == "!" ? "them" : "the tag",
                       text == "true" || text == "false" ? "boolean" : "number");
  }
  return QuoteShowingInvisible(text) +
         (PlainTag(tag, "str") ? "" : " (tagged " + TagText(tag) + ")");
}

std::string YamlReader::ChildPath(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

void YamlReader::ExpectMap() const {
  if (node_.IsDefined() && !node_.IsNull() && (!node_.IsMap() || !PlainTag(node_.Tag(), "map"))) {
    Fail("a mapping of keys");
  }
  // yaml-cpp does not merge `<<: *anchor`: the merged keys were missing and
  // the first one asked for reported "the key is missing" (a second bad-input
  // audit). Said at the merge key, before any key of the mapping is read.
  if (const YAML::Node& view = node_; view.IsMap() && view["<<"].IsDefined()) {
    for (const auto& entry : view) {
      if (!entry.first.IsScalar() || entry.first.Scalar() != "<<") continue;
      throw InputError(YamlReader(entry.first, ChildPath("<<"), context_).Where(),
                       "keys written out in full",
                       "a YAML merge key (<<), which the YAML reader (yaml-cpp) does not merge",
                       "write the anchored mapping's keys here; an alias of a whole value "
                       "(key: *anchor) is read");
    }
  }
}

bool YamlReader::Has(const std::string& key) {
  ExpectMap();
  asked_->insert(key);
  if (!node_.IsDefined() || node_.IsNull()) return false;
  // Present even when its value is empty or null ("particles:", "fov_deg: ~"):
  // a value reader then reports "found nothing" at that line instead of
  // silently taking the default. Only a section may be empty (ExpectMap
  // accepts null: all defaults).
  return node_[key].IsDefined();
}

YamlReader YamlReader::Child(const std::string& key) {
  if (!Has(key)) {
    // A misspelt required key ("target:", "Id:", "fr<U+200B>ames:") was
    // reported as missing, at the parent, and never named (a third bad-input
    // audit): report a key nobody asked for that is near it, at its own line.
    const YAML::Node& view = node_;
    std::optional<YAML::Node> near;
    int near_distance = 0;
    for (const auto& entry : view) {
      if (!entry.first.IsScalar() || asked_->count(entry.first.Scalar()) > 0) continue;
      const std::string spelt = Normalised(entry.first.Scalar());
      if (ClosestMatch(spelt, {key}) != key) continue;
      const int distance = EditDistance(spelt, key);
      if (!near || distance < near_distance) {
        near = entry.first;
        near_distance = distance;
      }
    }
    if (near) {
      const std::string dotted = ChildPath(EscapeInvisible(near->Scalar()));
      throw InputError(YamlReader(*near, dotted, context_).Where(),
                       fmt::format("the required key \"{}\"", key),
                       "the unknown key " + QuoteShowingInvisible(near->Scalar()),
                       fmt::format("did you mean \"{}\"?", key));
    }
    throw InputError(WhereKey(key), fmt::format("the required key \"{}\"", key),
                     "nothing (the key is missing)");
  }
  return MakeChild(key);
}

YamlReader YamlReader::MakeChild(const std::string& key) const {
  YamlReader child(node_[key], ChildPath(key), context_);
  for (const auto& entry : node_) {
    if (entry.first.Scalar() == key) {
      child.key_mark_ = entry.first.Mark();
      break;
    }
  }
  return child;
}

std::optional<YamlReader> YamlReader::Optional(const std::string& key) {
  if (!Has(key)) return std::nullopt;
  return MakeChild(key);
}

std::vector<YamlReader> YamlReader::Items() const {
  if (node_.IsSequence() && !PlainTag(node_.Tag(), "seq")) Fail("a list");
  if (!node_.IsSequence()) {
    // `--set world.occluders.0.kind=tree` where the file has no occluders
    // makes a mapping with the key "0" (a mapping may have number keys):
    // say what happened (a second bad-input audit found "expected a list,
    // found a mapping" alone).
    bool number_keys = node_.IsMap() && node_.size() > 0;
    for (const auto& entry : node_) {
      if (!number_keys) break;
      const std::string key = entry.first.IsScalar() ? entry.first.Scalar() : "";
      number_keys = !key.empty() && key.find_first_not_of("0123456789") == std::string::npos;
    }
    const SourceLocation where = Where();
    if (number_keys && where.override_index >= 0) {
      Fail("a list",
           "a --set with a list index made a mapping: the list is not written, so set it whole, "
           "e.g. --set " +
               path_ + "=[...]");
    }
    Fail("a list");
  }
  std::vector<YamlReader> items;
  for (size_t i = 0; i < node_.size(); ++i) {
    items.emplace_back(node_[i], path_ + "[" + std::to_string(i) + "]", context_);
  }
  return items;
}

double YamlReader::AsNumber(double lo, double hi) const { return AsNumber(Closed(lo, hi)); }

double YamlReader::AsNumber(const FieldRange& range) const {
  double value = 0.0;
  if (!TypedScalar(node_) || !ParseDouble(node_.Scalar(), &value) || !range.Contains(value)) {
    Fail(FieldExpectation(FieldType::kNumber, range), NumberHint(node_));
  }
  return value;
}

int64_t YamlReader::AsInteger(int64_t lo, int64_t hi) const {
  int64_t value = 0;
  const std::string expected = fmt::format("an integer in [{}, {}]", lo, hi);
  if (!TypedScalar(node_, ScalarKind::kInteger) || !ParseInt(node_.Scalar(), &value)) {
    Fail(expected, NumberHint(node_));
  }
  if (value < lo || value > hi) Fail(expected);
  return value;
}

Eigen::VectorXd YamlReader::AsVector(int n, double lo, double hi) const {
  const std::string expected = fmt::format("a list of {} numbers in {}", n, RangeText(lo, hi));
  if (!node_.IsSequence() || static_cast<int>(node_.size()) != n) Fail(expected);
  Eigen::VectorXd v(n);
  for (int i = 0; i < n; ++i) {
    YamlReader item(node_[i], path_ + "[" + std::to_string(i) + "]", context_);
    double value = 0.0;
    if (!TypedScalar(item.node_) || !ParseDouble(item.node_.Scalar(), &value) || value < lo ||
        value > hi) {
      item.Fail(fmt::format("a number in {}", RangeText(lo, hi)), NumberHint(item.node_));
    }
    v[i] = value;
  }
  return v;
}

double YamlReader::Number(const std::string& key, std::optional<double> fallback, double lo,
                          double hi) {
  return Number(key, fallback, Closed(lo, hi));
}

double YamlReader::Number(const std::string& key, std::optional<double> fallback,
                          const FieldRange& range) {
  if (!Has(key)) {
    if (fallback) return *fallback;
    Child(key);  // throws "required"
  }
  return Child(key).AsNumber(range);
}

int64_t YamlReader::Integer(const std::string& key, std::optional<int64_t> fallback, int64_t lo,
                            int64_t hi) {
  if (!Has(key)) {
    if (fallback) return *fallback;
    Child(key);
  }
  return Child(key).AsInteger(lo, hi);
}

std::optional<uint64_t> ParseSeed(std::string_view text) {
  uint64_t value = 0;
  const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || ec != std::errc() || ptr != text.data() + text.size()) return std::nullopt;
  return value;
}

uint64_t YamlReader::Seed(const std::string& key, std::optional<uint64_t> fallback) {
  if (!Has(key)) {
    if (fallback) return *fallback;
    Child(key);
  }
  YamlReader child = Child(key);
  const std::optional<uint64_t> value =
      TypedScalar(child.node_, ScalarKind::kInteger) && !HasLeadingZero(child.node_.Scalar())
          ? ParseSeed(child.node_.Scalar())
          : std::nullopt;
  if (!value) child.Fail("a non-negative integer seed below 2^64", NumberHint(child.node_));
  return *value;
}

bool YamlReader::Bool(const std::string& key, std::optional<bool> fallback) {
  if (!Has(key)) {
    if (fallback) return *fallback;
    Child(key);
  }
  YamlReader child = Child(key);
  const std::string text =
      TypedScalar(child.node_, ScalarKind::kBoolean) ? child.node_.Scalar() : "";
  if (text == "true") return true;
  if (text == "false") return false;
  child.Fail("true or false");
}

std::string YamlReader::String(const std::string& key, std::optional<std::string> fallback) {
  if (!Has(key)) {
    if (fallback) return *fallback;
    Child(key);
  }
  YamlReader child = Child(key);
  if (!child.node_.IsScalar() || !PlainTag(child.node_.Tag(), "str")) child.Fail("a text value");
  return child.node_.Scalar();
}

std::string YamlReader::Enum(const std::string& key, std::optional<std::string> fallback,
                             const std::vector<std::string>& choices) {
  if (!Has(key)) {
    if (fallback) return *fallback;
    Child(key);
  }
  return Child(key).AsEnum(choices);
}

std::string YamlReader::AsEnum(const std::vector<std::string>& choices) const {
  std::string joined;
  for (const auto& c : choices) joined += (joined.empty() ? "" : " | ") + c;
  if (!node_.IsScalar() || !PlainTag(node_.Tag(), "str")) Fail("one of " + joined);
  const std::string value = node_.Scalar();
  if (std::find(choices.begin(), choices.end(), value) == choices.end()) {
    const std::string near = ClosestMatch(Normalised(value), choices);
    Fail("one of " + joined, near.empty() ? "" : "did you mean \"" + near + "\"?");
  }
  return value;
}

Eigen::VectorXd YamlReader::Vector(const std::string& key, int n,
                                   std::optional<Eigen::VectorXd> fallback, double lo, double hi) {
  if (!Has(key)) {
    if (fallback) return *fallback;
    Child(key);
  }
  return Child(key).AsVector(n, lo, hi);
}

void YamlReader::Relocate(const std::function<void()>& validate) const {
  try {
    validate();
  } catch (const InputError& e) {
    const std::string& dotted = e.where().key;
    const std::string prefix = path_.empty() ? "" : path_ + ".";
    if (dotted.empty() || dotted.rfind(prefix, 0) != 0) throw;
    YamlReader at = *this;
    size_t start = prefix.size();
    while (start <= dotted.size()) {
      const size_t dot = dotted.find('.', start);
      const std::string part = dotted.substr(start, dot == std::string::npos ? dot : dot - start);
      if (!at.node_.IsMap() || !at.node_[part].IsDefined()) break;
      at = at.MakeChild(part);
      if (dot == std::string::npos) break;
      start = dot + 1;
    }
    SourceLocation where = at.Where();
    where.key = dotted;
    throw InputError(where, e.expected(), e.found(), e.hint());
  }
}

void YamlReader::Finish() const {
  if (!node_.IsDefined() || node_.IsNull() || !node_.IsMap()) return;
  std::vector<std::string> known(asked_->begin(), asked_->end());
  std::set<std::string> seen;
  for (const auto& entry : node_) {
    if (!entry.first.IsScalar() || (entry.first.IsNull() && entry.first.Tag() != "!")) {
      // `~: 3`, `: 3` or `[a, b]: 3`: not a key any reader asks for.
      YamlReader key_reader(entry.first, path_, context_);
      const char* what = entry.first.IsSequence() ? "a list used as a key"
                         : entry.first.IsMap()    ? "a mapping used as a key"
                                                  : "a null key (~ or nothing before the colon)";
      throw InputError(key_reader.Where(), "a key name (a word such as `frames`)", what);
    }
    const std::string key = entry.first.Scalar();
    YamlReader key_reader(entry.first, ChildPath(key), context_);
    if (!seen.insert(key).second) {
      throw InputError(key_reader.Where(), "each key once", "a second \"" + key + "\"");
    }
    if (asked_->count(key) == 0) {
      // Matched without case or invisible characters, which are shown.
      const std::string near = ClosestMatch(Normalised(key), known);
      std::string hint = near.empty() ? "" : "did you mean \"" + near + "\"?";
      std::string all;
      for (const auto& k : known) all += (all.empty() ? "" : ", ") + k;
      throw InputError(YamlReader(entry.first, ChildPath(EscapeInvisible(key)), context_).Where(),
                       "one of the keys " + all, "the unknown key " + QuoteShowingInvisible(key),
                       hint);
    }
  }
}

}  // namespace hcpf::config
