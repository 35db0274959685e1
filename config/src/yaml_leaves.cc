#include "hcpf/config/yaml_leaves.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <cctype>
#include <map>

namespace hcpf::config {

bool LeafKeyLess::operator()(const std::string& a, const std::string& b) const {
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (std::isdigit(static_cast<unsigned char>(a[i])) &&
        std::isdigit(static_cast<unsigned char>(b[j]))) {
      size_t ei = i, ej = j;
      while (ei < a.size() && std::isdigit(static_cast<unsigned char>(a[ei]))) ++ei;
      while (ej < b.size() && std::isdigit(static_cast<unsigned char>(b[ej]))) ++ej;
      // Leading zeros aside, the longer run of digits is the larger number.
      size_t si = i, sj = j;
      while (si + 1 < ei && a[si] == '0') ++si;
      while (sj + 1 < ej && b[sj] == '0') ++sj;
      if (ei - si != ej - sj) return ei - si < ej - sj;
      const int c = a.compare(si, ei - si, b, sj, ej - sj);
      if (c != 0) return c < 0;
      if (ei - i != ej - j) return ei - i < ej - j;  // "01" after "1"
      i = ei;
      j = ej;
    } else {
      if (a[i] != b[j]) return static_cast<unsigned char>(a[i]) < static_cast<unsigned char>(b[j]);
      ++i;
      ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

namespace {

// Every scalar leaf of `node` under its dotted key.
void Flatten(const YAML::Node& node, const std::string& key, YamlLeaves* leaves) {
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

YamlLeaves FlattenYaml(const std::string& yaml) {
  YamlLeaves leaves;
  Flatten(YAML::Load(yaml), "", &leaves);
  return leaves;
}

std::vector<LeafDifference> DifferingLeaves(const std::string& first_yaml,
                                            const std::string& second_yaml) {
  return DifferingLeaves(FlattenYaml(first_yaml), FlattenYaml(second_yaml));
}

std::vector<LeafDifference> DifferingLeaves(const YamlLeaves& first, const YamlLeaves& second) {
  const LeafKeyLess less;
  std::vector<LeafDifference> out;
  auto a = first.begin();
  auto b = second.begin();
  while (a != first.end() || b != second.end()) {
    if (b == second.end() || (a != first.end() && less(a->first, b->first))) {
      out.push_back({a->first, a->second, std::nullopt});
      ++a;
    } else if (a == first.end() || less(b->first, a->first)) {
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
