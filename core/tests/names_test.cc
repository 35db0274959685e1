#include "hcpf/core/names.h"

#include <gtest/gtest.h>

namespace hcpf {
namespace {

TEST(FirstControlCharacter, FindsEveryLineBreakingCharacter) {
  EXPECT_EQ(FirstControlCharacter("crossing-2 é 中 🚗"), "");
  EXPECT_EQ(FirstControlCharacter(""), "");
  EXPECT_EQ(FirstControlCharacter("a\nb"), "U+000A");
  EXPECT_EQ(FirstControlCharacter("a\tb"), "U+0009");
  EXPECT_EQ(FirstControlCharacter("a\x7F"), "U+007F");
  EXPECT_EQ(FirstControlCharacter("a\xC2\x85z"), "U+0085");  // NEL
  EXPECT_EQ(FirstControlCharacter("\xC2\x80"), "U+0080");
  EXPECT_EQ(FirstControlCharacter("\xC2\x9F"), "U+009F");
  EXPECT_EQ(FirstControlCharacter("a\xE2\x80\xA8z"), "U+2028");
  EXPECT_EQ(FirstControlCharacter("a\xE2\x80\xA9z"), "U+2029");
  // Their neighbours print: U+00A0 (no-break space), U+2027 (hyphenation
  // point).
  EXPECT_EQ(FirstControlCharacter("\xC2\xA0\xE2\x80\xA7"), "");
  EXPECT_EQ(FirstControlCharacter("ab\ncd\r"), "U+000A");  // the first one
}

TEST(FolderNameProblem, AcceptsOnlyOneFolderName) {
  EXPECT_EQ(FolderNameProblem("crossing"), "");
  EXPECT_EQ(FolderNameProblem("crossing seed 2.v1"), "");
  EXPECT_EQ(FolderNameProblem("..a"), "");
  EXPECT_NE(FolderNameProblem(""), "");
  EXPECT_NE(FolderNameProblem("."), "");
  EXPECT_NE(FolderNameProblem(".."), "");
  EXPECT_NE(FolderNameProblem("../victim"), "");
  EXPECT_NE(FolderNameProblem("a/b"), "");
  EXPECT_NE(FolderNameProblem("/abs"), "");
  EXPECT_NE(FolderNameProblem("a\\b"), "");
  EXPECT_NE(FolderNameProblem("a\xC2\x85"), "");
  EXPECT_NE(FolderNameProblem("tab\there").find("U+0009"), std::string::npos);
}

}  // namespace
}  // namespace hcpf
