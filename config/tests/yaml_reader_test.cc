// The located YAML reader on its own: overrides and relocation of a module's
// error to the key's line (the scenario schema tests cover the rest).

#include "hcpf/config/yaml_reader.h"

#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "hcpf/config/overrides.h"
#include "hcpf/core/error.h"

namespace hcpf::config {
namespace {

YamlReader Root(YAML::Node node, const std::string& file = "f.yaml") {
  auto context = std::make_shared<YamlContext>();
  context->file = file;
  return YamlReader(node, "", context);
}

TEST(Overrides, ParseSplitsAtTheFirstEqualsAndLabelsTheText) {
  const Override o = ParseOverride("a.b=c=d");
  EXPECT_EQ(o.key, "a.b");
  EXPECT_EQ(o.value, "c=d");
  EXPECT_EQ(o.Label(), "--set a.b=c=d");
  EXPECT_THROW(ParseOverride("no-equals"), InputError);
  EXPECT_THROW(ParseOverride("=5"), InputError);
}

TEST(Overrides, ValuesFromAnOverrideAreLocatedThereWithTheirIndex) {
  YAML::Node root = YamlReader::Parse("a:\n  b: 1\n", "f.yaml");
  auto context = std::make_shared<YamlContext>();
  context->file = "f.yaml";
  ApplyOverrides(root, {{"x", "1"}, {"a.b", "oops"}}, context.get());
  YamlReader r(root, "", context);
  try {
    r.Child("a").Number("b", std::nullopt, 0, 10);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "--set a.b=oops");
    EXPECT_EQ(e.where().override_index, 1);
    EXPECT_EQ(e.where().key, "a.b");
  }
}

TEST(Overrides, AnUnparsableValueNamesItsOverride) {
  YAML::Node root = YamlReader::Parse("a: 1\n", "f.yaml");
  YamlContext context;
  try {
    ApplyOverrides(root, {{"a", "[1, 2"}}, &context);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().override_index, 0);
    EXPECT_NE(std::string(e.what()).find("--set a=[1, 2"), std::string::npos) << e.what();
  }
}

// A module's Validate() names a dotted key but no file: Relocate puts its
// error at that key's line and column, or at the nearest written ancestor.
TEST(YamlReader, RelocateMovesAModulesErrorToTheKeysLine) {
  const YamlReader root = Root(YamlReader::Parse("top: 1\nsection:\n  key: 5\n", "f.yaml"));
  const auto fail_at = [](const std::string& key) {
    return [key] { throw InputError(SourceLocation{{}, 0, 0, key}, "less", "5", "a hint"); };
  };
  try {
    root.Relocate(fail_at("section.key"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "f.yaml");
    EXPECT_EQ(e.where().line, 3);
    EXPECT_EQ(e.where().column, 8);
    EXPECT_EQ(e.where().key, "section.key");
    EXPECT_EQ(e.hint(), "a hint");
  }
  try {
    root.Relocate(fail_at("section.absent"));  // left at its default
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, 3);  // the section's first entry
    EXPECT_EQ(e.where().key, "section.absent");
  }
  EXPECT_NO_THROW(root.Relocate([] {}));
}

TEST(YamlReader, DidYouMeanAllowsAThirdOfTheWordToDiffer) {
  EXPECT_EQ(ClosestMatch("trakcer", {"tracker", "metrics"}), "tracker");
  EXPECT_EQ(ClosestMatch("xyz", {"tracker", "metrics"}), "");
  // A dropped suffix (issue 15, item 16).
  EXPECT_EQ(ClosestMatch("azimuth", {"azimuth_deg", "elevation_deg", "shadows"}), "azimuth_deg");
  EXPECT_EQ(ClosestMatch("max_missed", {"confirm_hits", "max_missed_frames"}), "max_missed_frames");
  EXPECT_EQ(ClosestMatch("sigma", {"model", "sigma_px", "sigma_log_size"}), "sigma_px");
  EXPECT_EQ(ClosestMatch("sigma", {"sigma_px", "sigma_py"}), "");  // a tie: no guess
  // Two adjacent letters swapped are one edit (a third bad-input audit:
  // `--set targets.0.paht.speed_mps=3` had no "did you mean "path"?").
  EXPECT_EQ(EditDistance("paht", "path"), 1);
  EXPECT_EQ(EditDistance("ab", "ba"), 1);
  EXPECT_EQ(EditDistance("kitten", "sitting"), 3);  // substitutions and insertions as before
  EXPECT_EQ(ClosestMatch("paht", {"id", "path", "model", "dimensions_m"}), "path");
}

// Parse refuses `text` (as f.yaml) with a message holding every part.
void ExpectRefused(const std::string& text, std::initializer_list<const char*> parts) {
  try {
    YamlReader::Parse(text, "f.yaml");
    ADD_FAILURE() << "accepted: " << text;
  } catch (const InputError& e) {
    const std::string message = e.what();
    for (const char* part : parts) EXPECT_NE(message.find(part), std::string::npos) << message;
  }
}

}  // namespace
// Found by the fuzzer (fuzz/regressions/scenario, sweep): yaml-cpp 0.7's
// LoadAll loops forever on a stray ','; Parse reports it at its place.
TEST(YamlReader, StrayCommaIsASyntaxErrorNotAHang) {
  struct Case {
    const char* text;
    const char* where;
  };
  for (const Case& c : {Case{",\n", "f.yaml:1:1:"}, Case{"- 1\n,\n", "f.yaml:2:1:"},
                        Case{"a: 1\n,\n", "f.yaml:2:"}}) {
    ExpectRefused(c.text, {c.where, "valid YAML"});
  }
  // Two documents are still reported as such, and one document still parses.
  EXPECT_THROW(YamlReader::Parse("a: 1\n---\nb: 2\n", "f.yaml"), InputError);
  EXPECT_EQ(YamlReader::Parse("a: 1\n", "f.yaml")["a"].as<int>(), 1);
  EXPECT_TRUE(YamlReader::Parse("# only a comment\n", "f.yaml").IsNull());
}

// Found by a bad-input audit: a name saved as Latin-1 ("caf\xE9") passed
// hcpf validate, and hcpf run then failed writing its JSON (exit 1). Bytes
// that are not UTF-8 are refused where they are, by line and column.
TEST(YamlReader, TextThatIsNotUtf8IsRefusedAtItsByte) {
  struct Case {
    std::string text;
    const char* where;
    const char* byte;
  };
  const std::vector<Case> cases = {
      {"name: caf\xE9\n", "f.yaml:1:10:", "0xE9"},        // Latin-1 é
      {"\xEF\xBB\xBFname: caf\xE9\n", "f.yaml:1:10:",     // after a byte-order mark,
       "0xE9"},                                           // no column
      {"a: 1\nname: ab\xC3\n", "f.yaml:2:9:", "0xC3"},    // cut short at the end
      {"a: 1\nb: \xC0\xAF\n", "f.yaml:2:4:", "0xC0"},     // overlong '/'
      {"b: \xED\xA0\x80\n", "f.yaml:1:4:", "0xED"},       // a surrogate
      {"b: \xF4\x90\x80\x80\n", "f.yaml:1:4:", "0xF4"}};  // past U+10FFFF
  for (const Case& c : cases) ExpectRefused(c.text, {c.where, "expected UTF-8 text", c.byte});
  // A UTF-16 or UTF-32 file's byte-order mark is named as one, with the
  // command that converts it (until 2026-12-06 "the byte 0xFF" and a hint
  // about Latin-1: an audit). UTF-32LE's mark begins as UTF-16LE's.
  ExpectRefused(std::string("\xFF\xFE"
                            "a\0:\0 \0"
                            "1\0",
                            10),
                {"f.yaml:1:1:", "expected UTF-8 text",
                 "found a UTF-16LE byte-order mark (FF FE): the file is UTF-16",
                 "iconv -f UTF-16LE -t UTF-8"});
  ExpectRefused(std::string("\xFE\xFF\0a", 4), {"a UTF-16BE byte-order mark (FE FF)"});
  ExpectRefused(std::string("\xFF\xFE\0\0a\0\0\0", 8),
                {"a UTF-32LE byte-order mark (FF FE 00 00): the file is UTF-32"});
  ExpectRefused(std::string("\0\0\xFE\xFF\0\0\0a", 8), {"a UTF-32BE byte-order mark"});
  // Well-formed UTF-8 of every length parses, a byte-order mark too.
  EXPECT_EQ(YamlReader::Parse("name: caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x9A\x97\n", "f.yaml")["name"]
                .as<std::string>(),
            "caf\xC3\xA9 \xE2\x82\xAC \xF0\x9F\x9A\x97");
  EXPECT_EQ(YamlReader::Parse("\xEF\xBB\xBF"
                              "a: 1\n",
                              "f.yaml")["a"]
                .as<int>(),
            1);
}

// An integer with a leading zero is read as decimal by YAML 1.2 (yaml-cpp)
// and as octal by YAML 1.1 readers (PyYAML: 0500 is 320): refused wherever a
// number, an integer or a seed is read, with the hint that says why (an
// audit found `particles: 0500` run with 500). Zero itself, a decimal
// fraction and an exponent are no such case.
TEST(YamlReader, IntegersWithALeadingZeroAreRefused) {
  const auto error_of = [](const std::string& text, const std::function<void(YamlReader&)>& read) {
    YamlReader r(YamlReader::Parse(text, "f.yaml"), "", std::make_shared<YamlContext>());
    try {
      read(r);
      return std::string("(no error)");
    } catch (const InputError& e) {
      return e.found() + " | " + e.hint();
    }
  };
  const auto integer = [](YamlReader& r) { r.Integer("a", std::nullopt, -1000, 1000); };
  const auto number = [](YamlReader& r) { r.Number("a", std::nullopt, -1000.0, 1000.0); };
  const auto seed = [](YamlReader& r) { r.Seed("a", std::nullopt); };
  const auto vector = [](YamlReader& r) { r.Child("a").AsVector(2, -1000.0, 1000.0); };
  const std::string hint =
      "no leading zero: YAML 1.1 readers take 0500 as octal (320), so write 500";
  EXPECT_EQ(error_of("a: 0500\n", integer), "\"0500\" | " + hint);
  EXPECT_EQ(error_of("a: -05\n", integer), "\"-05\" | " + hint);
  EXPECT_EQ(error_of("a: +00\n", number), "\"+00\" | " + hint);
  EXPECT_EQ(error_of("a: 010\n", seed), "\"010\" | " + hint);
  EXPECT_EQ(error_of("a: [1, 010]\n", vector), "\"010\" | " + hint);
  for (const char* fine : {"a: 0\n", "a: -0\n", "a: 500\n", "a: 10\n"}) {
    EXPECT_EQ(error_of(fine, integer), "(no error)") << fine;
    EXPECT_EQ(error_of(fine, number), "(no error)") << fine;
  }
  for (const char* fine : {"a: 0.5\n", "a: 00.5\n", "a: 1e-05\n", "a: 0e0\n"}) {
    EXPECT_EQ(error_of(fine, number), "(no error)") << fine;
  }
}

// The error of reading `key` of `text` (with `overrides` applied) with
// `read`, or "(no error)".
std::string ReadError(const std::string& text, const std::function<void(YamlReader&)>& read,
                      const std::vector<Override>& overrides = {}) {
  YAML::Node root = YamlReader::Parse(text, "f.yaml");
  auto context = std::make_shared<YamlContext>();
  context->file = "f.yaml";
  try {
    ApplyOverrides(root, overrides, context.get());
    YamlReader r(root, "", context);
    read(r);
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

// A quoted number, or one tagged !!str, is text in YAML: a second bad-input
// audit found `fps: "30"` and `fps: !!str 30` read as 30. The message says
// why the value that looks like a number is not one. Plain and !!int /
// !!float values are numbers; a quoted "true" is not a boolean.
TEST(YamlReader, QuotedNumbersAndBooleansAreText) {
  const auto integer = [](YamlReader& r) { r.Integer("a", std::nullopt, 0, 100); };
  const auto number = [](YamlReader& r) { r.Number("a", std::nullopt, 0, 100); };
  const auto boolean = [](YamlReader& r) { r.Bool("a", std::nullopt); };
  const auto seed = [](YamlReader& r) { r.Seed("a", std::nullopt); };
  const auto vector = [](YamlReader& r) { r.Vector("a", 2, std::nullopt, 0, 100); };
  using Read = std::function<void(YamlReader&)>;
  for (const Read& read : {Read(integer), Read(number), Read(seed)}) {
    EXPECT_EQ(ReadError("a: 30\n", read), "(no error)");
    EXPECT_EQ(ReadError("a: !!int 30\n", read), "(no error)");
    EXPECT_EQ(ReadError("a: \"30\"\n", read).find("f.yaml:1:4: a: expected "), 0u);
    EXPECT_NE(ReadError("a: \"30\"\n", read)
                  .find("found the text \"30\" (in quotes: write it without them for a number)"),
              std::string::npos)
        << ReadError("a: \"30\"\n", read);
    EXPECT_NE(ReadError("a: !!str 30\n", read)
                  .find("found the text \"30\" (tagged !!str: write it without the tag for a "
                        "number)"),
              std::string::npos)
        << ReadError("a: !!str 30\n", read);
    EXPECT_NE(ReadError("a: '30'\n", read).find("in quotes"), std::string::npos);
  }
  EXPECT_EQ(ReadError("a: !!float 2.5\n", number), "(no error)");
  EXPECT_EQ(ReadError("a: [1, 2]\n", vector), "(no error)");
  EXPECT_NE(ReadError("a: [1, \"2\"]\n", vector).find("a[1]: expected a number"),
            std::string::npos);
  EXPECT_EQ(ReadError("a: true\n", boolean), "(no error)");
  EXPECT_EQ(ReadError("a: !!bool true\n", boolean), "(no error)");
  EXPECT_NE(ReadError("a: \"true\"\n", boolean)
                .find("found the text \"true\" (in quotes: write it without them for a boolean)"),
            std::string::npos)
      << ReadError("a: \"true\"\n", boolean);
  // A value from --set that is quoted is text too, and located there.
  EXPECT_EQ(ReadError("a: 1\n", integer, {{"a", "\"30\""}}).find("--set a=\"30\": a: expected"), 0u)
      << ReadError("a: 1\n", integer, {{"a", "\"30\""}});
  // Text keys stay text when quoted.
  EXPECT_EQ(ReadError("a: \"30\"\n", [](YamlReader& r) { r.String("a", std::nullopt); }),
            "(no error)");
}

// A list index is written in decimal without leading zeros: "01" was read
// as 1. A --set with an index where the file has no list made a mapping
// with a number key; reading it as a list says so and how to set the list.
TEST(Overrides, ListIndicesAndListsThatAreNotWritten) {
  const auto items = [](YamlReader& r) { r.Child("b").Items(); };
  EXPECT_EQ(ReadError("b: [1, 2]\n", items, {{"b.1", "3"}}), "(no error)");
  EXPECT_EQ(ReadError("b: [1, 2]\n", items, {{"b.01", "3"}}),
            "--set b.01=3: b.01: expected a list index in [0, 2), found \"01\"");
  EXPECT_EQ(ReadError("a: 1\n", items, {{"b.0.c", "3"}}),
            "--set b.0.c=3: b: expected a list, found a mapping (a --set with a list index made a "
            "mapping: the list is not written, so set it whole, e.g. --set b=[...])");
  // A mapping with number keys in the file is only "not a list".
  EXPECT_EQ(ReadError("b: {0: 1}\n", items), "f.yaml:1:4: b: expected a list, found a mapping");
}

// yaml-cpp does not merge `<<: *anchor`: said at the merge key before any key
// of its mapping is read (the first merged key asked for was "missing").
TEST(YamlReader, MergeKeysAreRefusedWhereTheyAre) {
  const std::string text = "base: &b {x: 1}\nt:\n  <<: *b\n  y: 2\n";
  const std::string e =
      ReadError(text, [](YamlReader& r) { r.Child("t").Number("x", std::nullopt, 0, 10); });
  EXPECT_EQ(e.find("f.yaml:3:3: t.<<: expected keys written out in full, found a YAML merge key "
                   "(<<)"),
            0u)
      << e;
  // An alias of a whole value is read.
  EXPECT_EQ(ReadError(text + "u: *b\n",
                      [](YamlReader& r) { r.Child("u").Number("x", std::nullopt, 0, 10); }),
            "(no error)");
}

// A file of `~` is a null document, not an empty file.
TEST(YamlReader, NullRootIsToldFromAnEmptyFile) {
  EXPECT_EQ(DescribeNullRoot(YamlReader::Parse("", "f.yaml")),
            "an empty file (nothing but blanks or comments)");
  EXPECT_EQ(DescribeNullRoot(YamlReader::Parse("# only a comment\n\n", "f.yaml")),
            "an empty file (nothing but blanks or comments)");
  EXPECT_EQ(DescribeNullRoot(YamlReader::Parse("~\n", "f.yaml")),
            "a null value (~ or null) where a mapping goes");
  EXPECT_EQ(DescribeNullRoot(YamlReader::Parse("# c\nnull\n", "f.yaml")),
            "a null value (~ or null) where a mapping goes");
}

}  // namespace hcpf::config

namespace hcpf::config {
namespace {

// The message of Parse's InputError for `text`, or "(no error)".
std::string ParseError(const std::string& text) {
  try {
    YamlReader::Parse(text, "f.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

// A third bad-input audit: yaml-cpp reads a quote left open in a file that
// ends in a newline as a value running to the end of the file, so
// `name: "small` took in the tracker section after it (exit 0, every tracker
// key at its default). A quote never closed, or one that runs on over a line
// that reads as a key, is refused at the opening quote; a quoted value over
// several lines without such a line is valid YAML and still read.
TEST(YamlReader, AQuoteLeftOpenIsRefusedAtTheQuote) {
  // The error of `text` begins with `prefix` (file:line:column: key: ...).
  const auto ExpectRefusedAs = [](const std::string& text, const std::string& prefix) {
    const std::string error = ParseError(text);
    EXPECT_EQ(error.rfind(prefix, 0), 0u) << error;
  };
  const std::string hint =
      " (close the quote on the line where the value ends, or write text over several lines as "
      "a block scalar: key: >)";
  EXPECT_EQ(ParseError("frames: 20\nname: \"small\ntracker:\n  particles: 50\n"),
            "f.yaml:2:7: name: expected a quoted value closed before the next key, found a \" "
            "quote opened at line 2 that is never closed (it runs on to the end of the file)" +
                hint);
  EXPECT_EQ(ParseError("frames: 20\nname: 'small\ntracker:\n  particles: 50\n"),
            "f.yaml:2:7: name: expected a quoted value closed before the next key, found a ' "
            "quote opened at line 2 that is never closed (it runs on to the end of the file)" +
                hint);
  // The last line, with or without a final newline (yaml-cpp itself reported
  // only the latter, at the end of the file).
  ExpectRefusedAs("frames: 20\nname: \"abc\n",
                  "f.yaml:2:7: name: expected a quoted value closed before the next key");
  ExpectRefusedAs("frames: 20\nname: \"abc",
                  "f.yaml:2:7: name: expected a quoted value closed before the next key");
  // Closed by the next quote in the file: a syntax error follows, the quote
  // is what is reported.
  EXPECT_EQ(ParseError("name: \"small\ntracker:\n  type: \"x\"\n"),
            "f.yaml:1:7: name: expected a quoted value closed before the next key, found a \" "
            "quote opened at line 1 that runs on to line 3, taking in line 2 (\"tracker:\"), "
            "which reads as a key" +
                hint);
  // Deeper keys and list items are named by their dotted path.
  ExpectRefusedAs("a:\n  - b: 'x\n    c: 1\n", "f.yaml:2:8: a[0].b: expected a quoted ");
  // An item of a flow list whose quote never closes: yaml-cpp reads it as
  // the key of a one-pair mapping, whose text (the rest of the file) named
  // it ("a.b[1].40] : ...", a bad-input audit); the item is named.
  ExpectRefusedAs("a:\n  b: [20, \"40]\n", "f.yaml:2:11: a.b[1]: expected a quoted ");
  ExpectRefusedAs("a:\n  b: [20, '40]\nc: 1\n", "f.yaml:2:11: a.b[1]: expected a ");
  // A key whose quote never closes is named by the word before the colon
  // on its line (a review: at the top level nothing was named; yaml-cpp's
  // key is the rest of the file), in a mapping after the mapping's path; a
  // quote before no `word:` names the mapping alone.
  ExpectRefusedAs("name: x\n\"seed: 3\nframes: 10\n",
                  "f.yaml:2:1: seed: expected a quoted value closed before the next key");
  ExpectRefusedAs("name: x\n\"seed: 3", "f.yaml:2:1: seed: expected a quoted ");
  ExpectRefusedAs("a:\n  b: 1\n  'c d: 2\n", "f.yaml:3:3: a: expected a quoted ");
  ExpectRefusedAs("a:\n  b: 1\n  'cd: 2\n", "f.yaml:3:3: a.cd: expected a quoted ");
  // Valid quoted values: over two lines, with escaped quotes, and plain
  // values holding an apostrophe.
  EXPECT_EQ(YamlReader::Parse("name: \"two\n  lines\"\nb: 1\n", "f.yaml")["name"].as<std::string>(),
            "two lines");
  // A continuation line that reads as a key deeper than the value's own key
  // is text of the value (a review found these refused).
  EXPECT_EQ(YamlReader::Parse("name: \"crossing of\n  two: targets\"\nb: 1\n", "f.yaml")["name"]
                .as<std::string>(),
            "crossing of two: targets");
  EXPECT_EQ(
      YamlReader::Parse("a:\n  - b: 'x\n      c: 1'\n", "f.yaml")["a"][0]["b"].as<std::string>(),
      "x c: 1");
  // An apostrophe in a comment is no quote: the one left open (here at the
  // end of a file without a final newline) is reported.
  const std::string comment = "a:\n  b: # 'til the end\n    \"xyz";
  ExpectRefusedAs(comment, "f.yaml:3:5: a.b: expected a quoted value closed");
  EXPECT_EQ(YamlReader::Parse("a: 'it''s: x'\nb: \"say \\\"c: d\\\"\"\n", "f.yaml")["b"]
                .as<std::string>(),
            "say \"c: d\"");
  EXPECT_EQ(YamlReader::Parse("a: it's\nb: !!str \"x\"\n", "f.yaml")["a"].as<std::string>(),
            "it's");
}

// A third bad-input audit: `heading_deg: +-30` was read as -30 (the reader
// skipped a leading '+' and handed "-30" on). Two signs are no number, for
// integers and numbers alike, in a file or a --set; one sign still is.
TEST(YamlReader, TwoSignsAreNotANumber) {
  const auto integer = [](YamlReader& r) { r.Integer("a", std::nullopt, -100, 100); };
  const auto number = [](YamlReader& r) { r.Number("a", std::nullopt, -100, 100); };
  EXPECT_EQ(ReadError("a: +-30\n", integer),
            "f.yaml:1:4: a: expected an integer in [-100, 100], found \"+-30\"");
  EXPECT_EQ(ReadError("a: +-30\n", number),
            "f.yaml:1:4: a: expected a number in [-100, 100], found \"+-30\"");
  EXPECT_EQ(ReadError("a: -+30\n", number),
            "f.yaml:1:4: a: expected a number in [-100, 100], found \"-+30\"");
  EXPECT_EQ(ReadError("a: ++3\n", integer),
            "f.yaml:1:4: a: expected an integer in [-100, 100], found \"++3\"");
  EXPECT_EQ(ReadError("a: 1\n", number, {{"a", "+-30"}}),
            "--set a=+-30: a: expected a number in [-100, 100], found \"+-30\"");
  for (const char* ok : {"a: +30\n", "a: -30\n", "a: 30\n"}) {
    EXPECT_EQ(ReadError(ok, integer), "(no error)") << ok;
    EXPECT_EQ(ReadError(ok, number), "(no error)") << ok;
  }
  // The value read, not only its acceptance.
  EXPECT_EQ(Root(YamlReader::Parse("a: +30\n", "f.yaml")).Number("a", std::nullopt, -100, 100),
            30.0);
}

// A third bad-input audit: a misspelt *required* key ("target:", "Id:",
// "fr<U+200B>ames:") was reported as "found nothing (the key is missing)" at
// the parent's line, with neither the key as written nor a "did you mean"
// (an optional key misspelt got both). A key nobody asked for that is near
// the required one (case and invisible characters aside) is reported at its
// own line, and an invisible character in it is named.
TEST(YamlReader, AMisspeltRequiredKeyIsNamedWhereItIs) {
  EXPECT_EQ(ReadError("name: a\ntarget:\n  - 1\n", [](YamlReader& r) { r.Child("targets"); }),
            "f.yaml:2:1: target: expected the required key \"targets\", found the unknown key "
            "\"target\" (did you mean \"targets\"?)");
  EXPECT_EQ(ReadError("camera:\n  fov_deg: 40\n  resolutoin: [1, 2]\n",
                      [](YamlReader& r) { r.Child("camera").Child("resolution"); }),
            "f.yaml:3:3: camera.resolutoin: expected the required key \"resolution\", found the "
            "unknown key \"resolutoin\" (did you mean \"resolution\"?)");
  EXPECT_EQ(ReadError("t:\n  - id: 1\n  - Id: 2\n",
                      [](YamlReader& r) {
                        for (YamlReader& item : r.Child("t").Items()) {
                          item.Integer("id", std::nullopt, 0, 9);
                        }
                      }),
            "f.yaml:3:5: t[1].Id: expected the required key \"id\", found the unknown key \"Id\" "
            "(did you mean \"id\"?)");
  EXPECT_EQ(ReadError("name: a\nfr\u200Bames: 20\n",
                      [](YamlReader& r) { r.Integer("frames", std::nullopt, 1, 100); }),
            "f.yaml:2:1: fr\\u200Bames: expected the required key \"frames\", found the unknown "
            "key \"fr\\u200Bames\" (it holds U+200B ZERO WIDTH SPACE) (did you mean \"frames\"?)");
  // A key truly missing is still said so, at the parent; a key already read
  // is not taken for a misspelling of another.
  EXPECT_EQ(ReadError("camera:\n  fov_deg: 40\n",
                      [](YamlReader& r) { r.Child("camera").Child("resolution"); }),
            "f.yaml:1:1: camera.resolution: expected the required key \"resolution\", found "
            "nothing (the key is missing)");
  EXPECT_EQ(ReadError("frame: 1\n",
                      [](YamlReader& r) {
                        r.Has("frame");
                        r.Child("frames");
                      }),
            "f.yaml:1:1: frames: expected the required key \"frames\", found nothing (the key is "
            "missing)");
  // An optional key: matched and shown the same way by Finish.
  const auto optional = [](YamlReader& r) {
    r.Integer("particles", 5, 1, 100);
    r.Finish();
  };
  EXPECT_EQ(ReadError("parti\u200Bcles: 50\n", optional),
            "f.yaml:1:1: parti\\u200Bcles: expected one of the keys particles, found the unknown "
            "key \"parti\\u200Bcles\" (it holds U+200B ZERO WIDTH SPACE) (did you mean "
            "\"particles\"?)");
  EXPECT_EQ(ReadError("PARTICLES: 50\n", optional),
            "f.yaml:1:1: PARTICLES: expected one of the keys particles, found the unknown key "
            "\"PARTICLES\" (did you mean \"particles\"?)");
}

// A third bad-input audit: a tab in the indentation, or a no-break space
// (U+00A0, from text pasted out of a web page) after a colon, gave yaml-cpp's
// bare "illegal map value", for U+00A0 on the line after it. Said at the
// character, in the house format; a tab after a colon and U+00A0 inside a
// value are still read.
TEST(YamlReader, TabsAndNoBreakSpacesAreNamedWhereTheyAre) {
  EXPECT_EQ(ParseError("frames: 20\ncamera:\n\tresolution: [320, 240]\n"),
            "f.yaml:3:1: expected indentation with spaces, found a tab");
  EXPECT_EQ(ParseError("t:\n  - id: 1\n  \t dim: 2\n"),
            "f.yaml:3:3: expected indentation with spaces, found a tab");
  EXPECT_EQ(ParseError("frames: 20\nfps:\u00A030\ncamera:\n  resolution: [320, 240]\n"),
            "f.yaml:2:5: expected a space after ':', found U+00A0 (no-break space)");
  EXPECT_EQ(ParseError("a: 1\nframes:\u00A020\ncamera:\n  fov_deg: 40\n"),
            "f.yaml:2:8: expected a space after ':', found U+00A0 (no-break space)");
  EXPECT_EQ(YamlReader::Parse("a:\t1\nb: \"x\u00A0y\"\n", "f.yaml")["a"].as<int>(), 1);
  // After a list's dash, where yaml-cpp said "end of map not found" or
  // "illegal map value"; a one-line file is a single value to yaml-cpp.
  EXPECT_EQ(ParseError("t:\n  -\tid: 1\n"), "f.yaml:2:4: expected a space after '-', found a tab");
  EXPECT_EQ(ParseError("t:\n  -\t{id: 1}\n  - {id: 2}\n"), "(no error)");  // valid YAML
  EXPECT_EQ(ParseError("t:\n  - id: 1\n  -\u00A0id: 2\n"),
            "f.yaml:3:4: expected a space after '-', found U+00A0 (no-break space)");
  EXPECT_EQ(ParseError("frames:\u00A020\n"),
            "f.yaml:1:8: expected a space after ':', found U+00A0 (no-break space)");
  EXPECT_EQ(ParseError("frames:\u00A020"),
            "f.yaml:1:8: expected a space after ':', found U+00A0 (no-break space)");
  EXPECT_EQ(ParseError("# see:\u00A0below\nframes:\u00A020\n"),
            "f.yaml:2:8: expected a space after ':', found U+00A0 (no-break space)");
  // A dash and a tab in a block scalar's text are text: the error is the
  // next line's own.
  EXPECT_EQ(ParseError("name: >\n  -\tfoo\nframes: 20: 3\n").find("a space after '-'"),
            std::string::npos);
  EXPECT_EQ(YamlReader::Parse("b: \"x:\u00A0y\"\n", "f.yaml")["b"].as<std::string>(), "x:\u00A0y");
  // A U+00A0 kept in a value is shown where the value is refused.
  EXPECT_EQ(ReadError("a: 20\u00A0\n", [](YamlReader& r) { r.Integer("a", std::nullopt, 0, 100); }),
            "f.yaml:1:4: a: expected an integer in [0, 100], found \"20\\u00A0\" (it holds U+00A0 "
            "NO-BREAK SPACE)");
}

// A third bad-input audit: `frames: !foo 20` said 'found "20"', as if 20
// were no integer, and tags a reader ignores were accepted (`name: !!binary
// ...`, `tracker: !!seq` on a mapping, `init: !!int ground_truth`). A tag is
// named in "found", and text, mappings and lists with a tag of another kind
// are refused; the core tags of what is read stay accepted.
TEST(YamlReader, TagsAreNamedAndTagsOfAnotherKindRefused) {
  const auto integer = [](YamlReader& r) { r.Integer("a", std::nullopt, 0, 100); };
  const auto number = [](YamlReader& r) { r.Number("a", std::nullopt, 0, 100); };
  const auto text = [](YamlReader& r) { r.String("a", std::nullopt); };
  const auto choice = [](YamlReader& r) { r.Enum("a", std::nullopt, {"x", "y"}); };
  const auto map = [](YamlReader& r) { r.Child("a").Has("b"); };
  const auto list = [](YamlReader& r) { r.Child("a").Items(); };
  EXPECT_EQ(ReadError("a: !foo 20\n", integer),
            "f.yaml:1:4: a: expected an integer in [0, 100], found \"20\" (tagged !foo)");
  EXPECT_EQ(ReadError("a: !!null 40\n", number),
            "f.yaml:1:4: a: expected a number in [0, 100], found \"40\" (tagged !!null)");
  EXPECT_EQ(ReadError("a: !!bool 20\n", integer),
            "f.yaml:1:4: a: expected an integer in [0, 100], found \"20\" (tagged !!bool)");
  EXPECT_EQ(ReadError("a: !!binary aGVsbG8=\n", text),
            "f.yaml:1:4: a: expected a text value, found \"aGVsbG8=\" (tagged !!binary)");
  EXPECT_EQ(ReadError("a: !!int x\n", choice),
            "f.yaml:1:4: a: expected one of x | y, found \"x\" (tagged !!int)");
  EXPECT_EQ(ReadError("a: !!seq\n  b: 1\n", map),
            "f.yaml:1:4: a: expected a mapping of keys, found a mapping tagged !!seq");
  EXPECT_EQ(ReadError("a: !!map [1, 2]\n", list),
            "f.yaml:1:4: a: expected a list, found a list of 2 item(s) tagged !!map");
  for (const char* ok :
       {"a: !!int 20\n", "a: !!int \"20\"\n", "a: !<tag:yaml.org,2002:int> 20\n"}) {
    EXPECT_EQ(ReadError(ok, integer), "(no error)") << ok;
  }
  EXPECT_EQ(ReadError("a: !!str x\n", text), "(no error)");
  EXPECT_EQ(ReadError("a: !!str x\n", choice), "(no error)");
  EXPECT_EQ(ReadError("a: !!map\n  b: 1\n", map), "(no error)");
  EXPECT_EQ(ReadError("a: !!seq [1]\n", list), "(no error)");
}

// Left by the third bad-input audit: a tag that says otherwise than
// its text was stated and then ignored (`fps: !!int 30.5` read as 30.5,
// `frames: !!float 240` as the integer 240). Refused, named; the tags that
// agree stay accepted (an integer is a number).
TEST(YamlReader, ATagThatContradictsItsTextIsRefused) {
  const auto integer = [](YamlReader& r) { r.Integer("a", std::nullopt, 0, 100); };
  const auto number = [](YamlReader& r) { r.Number("a", std::nullopt, 0, 100); };
  const auto seed = [](YamlReader& r) { r.Seed("a", std::nullopt); };
  EXPECT_EQ(ReadError("a: !!int 30.5\n", number),
            "f.yaml:1:4: a: expected a number in [0, 100], found \"30.5\" (tagged !!int)");
  EXPECT_EQ(ReadError("a: !!float 24\n", integer),
            "f.yaml:1:4: a: expected an integer in [0, 100], found \"24\" (tagged !!float)");
  EXPECT_EQ(ReadError("a: !!float 7\n", seed),
            "f.yaml:1:4: a: expected a non-negative integer seed below 2^64, found \"7\" (tagged "
            "!!float)");
  EXPECT_EQ(ReadError("a: !!int 30\n", number), "(no error)");
  EXPECT_EQ(ReadError("a: !!float 30.5\n", number), "(no error)");
  EXPECT_EQ(ReadError("a: !!int 7\n", seed), "(no error)");
  EXPECT_EQ(Root(YamlReader::Parse("a: !!int 30\n", "f.yaml")).Number("a", std::nullopt, 0, 100),
            30.0);
}

// Letters from another keyboard layout and a word processor's minus look
// like ASCII in an editor: `fr<U+0430>mes:` was "the unknown key "frаmes""
// and `[<U+2212>40, 0]` "found "−40"", the found text the same to the eye as
// the expected one. The character is named with what it looks like, and
// "did you mean" reads it as that character.
TEST(YamlReader, LookAlikeCharactersAreNamed) {
  EXPECT_EQ(ReadError("name: a\nfr\u0430mes: 20\n",
                      [](YamlReader& r) { r.Integer("frames", std::nullopt, 1, 100); }),
            "f.yaml:2:1: fr\u0430mes: expected the required key \"frames\", found the unknown "
            "key \"fr\u0430mes\" (it holds U+0430 CYRILLIC SMALL LETTER A, which looks like 'a') "
            "(did you mean \"frames\"?)");
  EXPECT_EQ(ReadError("a: \u221240\n", [](YamlReader& r) { r.Number("a", std::nullopt, -99, 99); }),
            "f.yaml:1:4: a: expected a number in [-99, 99], found \"\u221240\" (it holds U+2212 "
            "MINUS SIGN, which looks like '-')");
  EXPECT_EQ(ReadError("a: ch\u0430rg\u0435d\n",
                      [](YamlReader& r) {
                        r.Enum("a", std::nullopt, {"charged", "systematic"});
                      }),
            "f.yaml:1:4: a: expected one of charged | systematic, found \"ch\u0430rg\u0435d\" (it "
            "holds U+0430 CYRILLIC SMALL LETTER A, which looks like 'a'; U+0435 CYRILLIC SMALL "
            "LETTER IE, which looks like 'e') (did you mean \"charged\"?)");
  // Finish's "did you mean" reads a key made of look-alikes only as the
  // ASCII key, however far in edit distance.
  EXPECT_EQ(ReadError("\u0440\u0430\u0441\u0435: 1\n",
                      [](YamlReader& r) {
                        r.Integer("pace", 5, 1, 100);
                        r.Finish();
                      }),
            "f.yaml:1:1: \u0440\u0430\u0441\u0435: expected one of the keys pace, found the "
            "unknown key \"\u0440\u0430\u0441\u0435\" (it holds U+0440 CYRILLIC SMALL LETTER ER, "
            "which looks like 'p'; U+0430 CYRILLIC SMALL LETTER A, which looks like 'a'; U+0441 "
            "CYRILLIC SMALL LETTER ES, which looks like 'c'; U+0435 CYRILLIC SMALL LETTER IE, "
            "which looks like 'e') (did you mean \"pace\"?)");
  // Other characters past ASCII are text, and not remarked on.
  EXPECT_EQ(ReadError("a: caf\u00E9\n", [](YamlReader& r) { r.Enum("a", std::nullopt, {"cafe"}); }),
            "f.yaml:1:4: a: expected one of cafe, found \"caf\u00E9\"");
}

}  // namespace
}  // namespace hcpf::config
