// DifferingLeaves: what a refused rendering and a run report's comparison
// list as the keys two resolved scenarios differ in.

#include "hcpf/config/yaml_leaves.h"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace hcpf::config
