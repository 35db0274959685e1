// The located YAML reader on its own: overrides and relocation of a module's
// error to the key's line (the scenario schema tests cover the rest).

#include "hcpf/config/yaml_reader.h"

#include <gtest/gtest.h>

#include <memory>

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
      {"name: caf\xE9\n", "f.yaml:1:10:", "0xE9"},       // Latin-1 é
      {"a: 1\nname: ab\xC3\n", "f.yaml:2:9:", "0xC3"},   // cut short at the end
      {"a: 1\nb: \xC0\xAF\n", "f.yaml:2:4:", "0xC0"},    // overlong '/'
      {"b: \xED\xA0\x80\n", "f.yaml:1:4:", "0xED"},      // a surrogate
      {"b: \xF4\x90\x80\x80\n", "f.yaml:1:4:", "0xF4"},  // past U+10FFFF
      {"\xFF\xFE"
       "a\0:\0 \0"
       "1\0",
       "f.yaml:1:1:", "0xFF"}};  // UTF-16
  for (const Case& c : cases) ExpectRefused(c.text, {c.where, "expected UTF-8 text", c.byte});
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

}  // namespace hcpf::config
