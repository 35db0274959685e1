#include "hcpf/config/yaml_leaves.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <map>

namespace hcpf::config {

namespace {

// Every scalar leaf of `node` under its dotted key.
void Flatten(const YAML::Node& node, const std::string& key,
             std::map<std::string, std::string>* leaves) {
  if (node.IsMap()) {
    for (const auto& entry : node) {
      const std::string name = entry.first.Scalar();
      Flatten(entry.second, key.empty() ? name : key + "." + name, leaves);
    }
  } else if (node.IsSequence()) {
    if (node.size() == 0) (*leaves)[key] = "[]";
    for (size_t i = 0; i < node.size(); ++i) {
      Flatten(node[i], fmt::format("{}[{}]", key, i), leaves);
    }
  } else {
    (*leaves)[key] = node.IsNull() ? "null" : node.Scalar();
  }
}

}  // namespace

std::vector<LeafDifference> DifferingLeaves(const std::string& first_yaml,
                                            const std::string& second_yaml) {
  std::map<std::string, std::string> first;
  std::map<std::string, std::string> second;
  Flatten(YAML::Load(first_yaml), "", &first);
  Flatten(YAML::Load(second_yaml), "", &second);
  std::vector<LeafDifference> out;
  auto a = first.begin();
  auto b = second.begin();
  while (a != first.end() || b != second.end()) {
    if (b == second.end() || (a != first.end() && a->first < b->first)) {
      out.push_back({a->first, a->second, std::nullopt});
      ++a;
    } else if (a == first.end() || b->first < a->first) {
      out.push_back({b->first, std::nullopt, b->second});
      ++b;
    } else {
      if (a->second != b->second) out.push_back({a->first, a->second, b->second});
      ++a;
      ++b;
    }
  }
  return out;
}

}  // namespace hcpf::config
