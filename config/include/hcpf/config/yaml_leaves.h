#pragma once
// The scalar leaves of two YAML documents that differ, by dotted key: what a
// refused rendering (observation.file.rendering) and `hcpf report RUN
// --against OTHER` say changed between two resolved scenarios.

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

// The scalar leaves that differ between two YAML texts, in key order (list
// indices as numbers: "a[2]" before "a[10]"). A null
// is the text "null". Throws YAML::Exception on text that is not YAML.
std::vector<LeafDifference> DifferingLeaves(const std::string& first_yaml,
                                            const std::string& second_yaml);

}  // namespace hcpf::config
