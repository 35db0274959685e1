// DifferingLeaves: what a refused rendering and a run report's comparison
// list as the keys two resolved scenarios differ in.

#include "hcpf/config/yaml_leaves.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

namespace hcpf::config {
namespace {

TEST(DifferingLeaves, NameEveryScalarThatDiffersByItsDottedKey) {
  // Changed, added and removed leaves, list items by index, in key order.
  const auto differ = DifferingLeaves("a: 1\nb: {c: [1, 2], d: x}\ne: [{f: 1}]\ng: []\n",
                                      "a: 1\nb: {c: [1, 3]}\ne: [{f: 2}]\ng: []\nh: ~\n");
  ASSERT_EQ(differ.size(), 4u);
  EXPECT_EQ(differ[0].key, "b.c[1]");
  EXPECT_EQ(differ[0].first, "2");
  EXPECT_EQ(differ[0].second, "3");
  EXPECT_EQ(differ[1].key, "b.d");
  EXPECT_EQ(differ[1].first, "x");
  EXPECT_EQ(differ[1].second, std::nullopt);
  EXPECT_EQ(differ[2].key, "e[0].f");
  EXPECT_EQ(differ[3].key, "h");
  EXPECT_EQ(differ[3].first, std::nullopt);
  EXPECT_EQ(differ[3].second, "null");
  EXPECT_TRUE(DifferingLeaves("a: [1]\n", "a: [1]\n").empty());
}

TEST(DifferingLeaves, ListIndicesSortAsNumbers) {
  std::string first = "t: [", second = "t: [";
  for (int i = 0; i < 12; ++i) {
    first += std::string(i ? ", " : "") + "0";
    second += std::string(i ? ", " : "") + "1";
  }
  const auto differ = DifferingLeaves(first + "]\n", second + "]\n");
  ASSERT_EQ(differ.size(), 12u);
  for (int i = 0; i < 12; ++i) EXPECT_EQ(differ[i].key, "t[" + std::to_string(i) + "]");
}

TEST(DifferingLeaves, AnEmptyTextIsNotAnAbsentKey) {
  // '' is a value, told apart from a key one document lacks.
  const auto differ = DifferingLeaves("a: ''\n", "b: 1\n");
  ASSERT_EQ(differ.size(), 2u);
  EXPECT_EQ(differ[0].key, "a");
  EXPECT_EQ(differ[0].first, "");
  EXPECT_EQ(differ[0].second, std::nullopt);
  EXPECT_EQ(differ[1].first, std::nullopt);
  EXPECT_EQ(differ[1].second, "1");
}

TEST(DifferingLeaves, FlattenedDocumentsCompareAsTheirTexts) {
  // A document flattened once (FlattenYaml) and compared with many gives
  // what its text gives.
  const YamlLeaves first = FlattenYaml("a: [3, {b: ~}]\nc: []\nd: {e: x}\n");
  ASSERT_EQ(first.size(), 4u);
  auto it = first.begin();
  EXPECT_EQ(it->first, "a[0]");
  EXPECT_EQ((it++)->second, "3");
  EXPECT_EQ(it->first, "a[1].b");
  EXPECT_EQ((it++)->second, "null");
  EXPECT_EQ(it->first, "c");
  EXPECT_EQ((it++)->second, "[]");
  EXPECT_EQ(it->first, "d.e");
  EXPECT_EQ(it->second, "x");
  for (const std::string second : {"a: [3, {b: 1}]\nc: []\n", "a: [4]\nd: {e: y}\nf: 1\n", ""}) {
    const auto from_leaves = DifferingLeaves(first, FlattenYaml(second));
    const auto from_texts = DifferingLeaves("a: [3, {b: ~}]\nc: []\nd: {e: x}\n", second);
    ASSERT_EQ(from_leaves.size(), from_texts.size()) << second;
    for (size_t i = 0; i < from_leaves.size(); ++i) {
      EXPECT_EQ(from_leaves[i].key, from_texts[i].key);
      EXPECT_EQ(from_leaves[i].first, from_texts[i].first);
      EXPECT_EQ(from_leaves[i].second, from_texts[i].second);
    }
  }
  // An empty text is a null document: the one leaf "" (the root).
  EXPECT_EQ(FlattenYaml(""), (YamlLeaves{{"", "null"}}));
  EXPECT_THROW(FlattenYaml("a: [1"), YAML::Exception);
  // Keys in DifferingLeaves's order: list indices as numbers.
  EXPECT_TRUE(LeafKeyLess()("t[2]", "t[10]"));
  EXPECT_FALSE(LeafKeyLess()("t[10]", "t[2]"));
}

}  // namespace
}  // namespace hcpf::config
