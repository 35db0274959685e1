#pragma once
// The scalar leaves of two YAML documents that differ, by dotted key: what a
// refused rendering (observation.file.rendering) and `hcpf report RUN
// --against OTHER` say changed between two resolved scenarios.

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace hcpf::config {

// A leaf that differs between two documents: its dotted key
// ("targets[1].path.speed_mps"; an empty list is the leaf "[]") and its text
// in each, nullopt where that document does not have it.
struct LeafDifference {
  std::string key;
  std::optional<std::string> first;
  std::optional<std::string> second;
};

// Dotted keys in order, with list indices as numbers: "a[2]" before "a[10]".
struct LeafKeyLess {
  bool operator()(const std::string& a, const std::string& b) const;
};

// Every scalar leaf of one YAML document: its text by dotted key (a null is
// the text "null", an empty list the leaf "[]"). Flatten a document once
// where it is compared with many.
using YamlLeaves = std::map<std::string, std::string, LeafKeyLess>;

// The leaves of a YAML text. Throws YAML::Exception on text that is not YAML.
YamlLeaves FlattenYaml(const std::string& yaml);

// The scalar leaves that differ between two documents, in key order.
std::vector<LeafDifference> DifferingLeaves(const YamlLeaves& first, const YamlLeaves& second);

// The same for two YAML texts. Throws YAML::Exception on text that is not
// YAML.
std::vector<LeafDifference> DifferingLeaves(const std::string& first_yaml,
                                            const std::string& second_yaml);

}  // namespace hcpf::config
