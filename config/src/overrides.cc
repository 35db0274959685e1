#include "hcpf/config/overrides.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <charconv>

#include "hcpf/config/yaml_reader.h"

namespace hcpf::config {
namespace {

// How many places of the tree under `root` hold `node` (aliases of one
// anchor share their node), stopping at 2 or after `budget` nodes visited.
int References(const YAML::Node& root, const YAML::Node& node, int depth, int64_t* budget) {
  if (--*budget < 0 || depth > 600) return 0;
  int count = root.is(node) ? 1 : 0;
  if (root.IsMap()) {
    for (auto it = root.begin(); it != root.end() && count < 2; ++it) {
      count += References(it->second, node, depth + 1, budget);
    }
  } else if (root.IsSequence()) {
    for (auto it = root.begin(); it != root.end() && count < 2; ++it) {
      count += References(*it, node, depth + 1, budget);
    }
  }
  return count;
}

// Sets `value` at the dotted `key` below `root`, creating mappings on the way;
// numeric segments index into lists.
void ApplyOverride(YAML::Node root, const Override& o, int index) {
  const std::string origin = o.Label();
  const SourceLocation at{origin, 0, 0, o.key, index};
  YAML::Node value;
  try {
    value = YamlReader::Parse(o.value, origin);
  } catch (const InputError& e) {
    SourceLocation where = e.where();
    where.override_index = index;
    throw InputError(where, e.expected(), e.found(), e.hint());
  }
  // Nothing (`tracker=`, `tracker=~`) would replace a whole section of the
  // file with its defaults (a second bad-input audit: particles 500 instead
  // of the file's 50, exit 0), and a value with "nothing" is refused anyway.
  if (!value.IsDefined() || value.IsNull()) {
    throw InputError(at, "a value", "nothing",
                     "an override sets a value; to take a key's default, leave it out of the "
                     "file");
  }
  // An empty mapping likewise (`tracker={}`: a fourth bad-input audit
  // found the file's section reset to its defaults, exit 0).
  if (value.IsMap() && value.size() == 0) {
    throw InputError(at, "a value", "an empty mapping, which would reset the file's keys there",
                     "an override sets a value; to take a section's defaults, leave it out of "
                     "the file, or --set its keys one by one");
  }
  std::vector<std::string> parts;
  size_t start = 0;
  while (true) {
    const size_t dot = o.key.find('.', start);
    parts.push_back(o.key.substr(start, dot - start));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  std::vector<YAML::Node> chain{root};
  for (size_t i = 0; i < parts.size(); ++i) {
    const std::string& part = parts[i];
    if (part.empty()) {
      throw InputError(at, "a dotted key such as tracker.particles", "an empty segment");
    }
    YAML::Node current = chain.back();
    const bool last = i + 1 == parts.size();
    // A node an alias shares (`path: *p`) would change in every place that
    // holds it: a second bad-input audit found --set targets.0.path.speed_mps
    // moving target 1 too. Checked once, at the node the override reaches:
    // the one it replaces, or the mapping it adds a key to. Anything inside
    // a shared node is reached through each of its holders, so that node is
    // shared too. (yaml-cpp assigns a value into a node in place, so
    // replacing an alias would replace the anchor's node everywhere; and the
    // nodes are only copy-constructed here, since assigning to a YAML::Node
    // that refers to a node rewrites that node.)
    if (last) {
      const auto reached_node = [&]() -> YAML::Node {
        const YAML::Node& view = current;  // const: no insertion on lookup
        if (view.IsMap() && view[part].IsDefined()) return view[part];
        if (view.IsSequence()) {
          size_t at_index = 0;
          const auto [ptr, ec] = std::from_chars(part.data(), part.data() + part.size(), at_index);
          if (ec == std::errc() && ptr == part.data() + part.size() && at_index < view.size()) {
            return view[at_index];
          }
        }
        return current;
      };
      const YAML::Node reached = reached_node();
      int64_t budget = 1'000'000;
      if (!reached.is(root) && References(root, reached, 0, &budget) > 1) {
        throw InputError(at,
                         "a key inside no node that a YAML alias shares (an override there would "
                         "change every copy)",
                         fmt::format("\"{}\" inside a node written once with an anchor (&) and "
                                     "used again with an alias (*)",
                                     part),
                         "write that node out in full where it is overridden");
      }
    }
    if (current.IsSequence()) {
      size_t index = 0;
      auto [ptr, ec] = std::from_chars(part.data(), part.data() + part.size(), index);
      // "01" is not an index as written (a second bad-input audit: read as 1).
      const bool leading_zero = part.size() > 1 && part[0] == '0';
      if (ec != std::errc() || ptr != part.data() + part.size() || index >= current.size() ||
          leading_zero) {
        throw InputError(at, fmt::format("a list index in [0, {})", current.size()),
                         "\"" + part + "\"");
      }
      if (last) {
        current[index] = value;
      } else {
        chain.push_back(current[index]);
      }
      continue;
    }
    if (!current.IsMap() && !current.IsNull() && current.IsDefined()) {
      // The value is the one the key so far reaches (`targets.0.id` for
      // targets.0.id.x), not at `part`, which it cannot hold (a bad-input
      // audit: "found a value at "x"").
      std::string reached;
      for (size_t k = 0; k < i; ++k) reached += (k == 0 ? "" : ".") + parts[k];
      throw InputError(at, "a mapping on the way to the key",
                       fmt::format("{} at \"{}\", which holds no key \"{}\"",
                                   current.IsScalar() ? "the value \"" + current.Scalar() + "\""
                                                      : std::string("a value"),
                                   reached, part));
    }
    if (last) {
      current[part] = value;
    } else {
      YAML::Node next = current[part];
      if (!next.IsDefined() || next.IsNull()) {
        current[part] = YAML::Node(YAML::NodeType::Map);
        next = current[part];
      }
      chain.push_back(next);
    }
  }
}

std::string OverridePath(const std::string& key) {
  // "targets.0.path" -> "targets[0].path", matching the reader's dotted paths.
  std::string out;
  size_t start = 0;
  while (start <= key.size()) {
    const size_t dot = key.find('.', start);
    const std::string part = key.substr(start, dot == std::string::npos ? dot : dot - start);
    const bool numeric = !part.empty() && std::all_of(part.begin(), part.end(), ::isdigit);
    if (numeric) {
      out += "[" + part + "]";
    } else {
      out += (out.empty() ? "" : ".") + part;
    }
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return out;
}

}  // namespace

bool IsKeyInside(const std::string& key, const std::string& parent) {
  return key.size() > parent.size() && key.compare(0, parent.size(), parent) == 0 &&
         key[parent.size()] == '.';
}

Override ParseOverride(const std::string& text) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw InputError(SourceLocation{"--set " + text, 0, 0, ""},
                     "key=value, e.g. tracker.particles=1000", "\"" + text + "\"");
  }
  return {text.substr(0, eq), text.substr(eq + 1)};
}

void ApplyOverrides(YAML::Node root, const std::vector<Override>& overrides, YamlContext* context) {
  for (size_t i = 0; i < overrides.size(); ++i) {
    const Override& o = overrides[i];
    // A later override of a section replaces it whole, and with it what an
    // earlier one set inside it (a bad-input audit: `--set
    // tracker.particles=10 --set tracker={...}` ran with 500 particles, exit
    // 0; sweeps and suites refuse such overlaps). The other order, a section
    // and then a key inside it, sets both.
    for (size_t j = 0; j < i; ++j) {
      if (!IsKeyInside(overrides[j].key, o.key)) continue;
      throw InputError(
          SourceLocation{o.Label(), 0, 0, o.key, static_cast<int>(i)},
          fmt::format("an override that keeps the earlier ones (it replaces {} whole)",
                      OverridePath(o.key)),
          fmt::format("\"{}\", set earlier and lost here", overrides[j].Label()),
          fmt::format("give {} first and {} after it", o.Label(), overrides[j].Label()));
    }
    ApplyOverride(root, o, static_cast<int>(i));
    context->overrides[OverridePath(o.key)] = {o.Label(), static_cast<int>(i)};
  }
}

}  // namespace hcpf::config
