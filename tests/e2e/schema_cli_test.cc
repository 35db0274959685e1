// `hcpf validate` accepts exactly what `hcpf run` accepts: every number and
// integer key that `hcpf schema` declares, set just outside its declared
// range, is refused by both commands with exit 2, the file:line: of the value
// and the dotted key, and the run leaves no output folder.

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "support/process.h"

namespace hcpf {
namespace {

namespace fs = std::filesystem;
using testing::FreshDir;
using testing::RunCommand;

using testing::kHcpf;

// One number, integer or vector row of `hcpf schema`: its section ("camera",
// "targets[i].path type=constant_turn", "scenario" for the top level) and key.
struct DeclaredKey {
  std::string section;
  std::string key;
  bool integer = false;
  bool vector = false;  // set element 0; the others keep their (valid) values
  std::string default_cell;
  double lo = 0, hi = 0;
  bool lo_open = false, hi_open = false;
};

std::string Trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" `");
  const size_t b = s.find_last_not_of(" `");
  return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

// The number, integer and vector rows of `hcpf schema`'s tables.
std::vector<DeclaredKey> DeclaredKeys() {
  const auto r = RunCommand(kHcpf + " --log-level warn schema");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  std::vector<DeclaredKey> keys;
  std::istringstream in(r.output);
  std::string line, section;
  while (std::getline(in, line)) {
    if (line.rfind("## `", 0) == 0) section = Trim(line.substr(3));
    if (line.rfind("| `", 0) != 0) continue;
    std::vector<std::string> cells;
    std::string cell;
    for (size_t i = 1; i < line.size(); ++i) {
      if (line[i] == '|' && line[i - 1] != '\\') {
        cells.push_back(Trim(cell));
        cell.clear();
      } else {
        cell += line[i];
      }
    }
    if (cells.size() < 5) continue;
    const bool vector = cells[1].rfind("[", 0) == 0 || cells[1].rfind("list of [", 0) == 0;
    if (cells[1] != "number" && cells[1] != "integer" && !vector) continue;
    std::string range = cells[4];  // "[0, 1000]", "(0, 16]", "[16, 8192] whole each"
    range = range.substr(0, range.find_first_of(")]") + 1);
    DeclaredKey k;
    k.section = section;
    k.key = cells[0];
    k.integer = cells[1] == "integer" || cells[4].find("whole") != std::string::npos;
    k.vector = vector;
    k.default_cell = cells[3];
    k.lo_open = range.front() == '(';
    k.hi_open = range.back() == ')';
    const size_t comma = range.find(',');
    k.lo = std::stod(range.substr(1, comma - 1));
    k.hi = std::stod(range.substr(comma + 1, range.size() - comma - 2));
    keys.push_back(k);
  }
  return keys;
}

std::string Number(double v) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.10g", v);
  return buffer;
}

// A valid scenario with an item of every list and every kind: the keys of a
// list item are set on the item whose `kind` / `type` the section names.
const char* const kBase = R"(frames: 10
camera:
  resolution: [320, 240]
  path:
    - frame: 0
      position: [0, 0, 50]
      look_at: [0, 0.1, 0]
world:
  occluders:
    - kind: bridge
      from: [-20, 0]
      to: [20, 0]
    - kind: building
      at: [30, 30]
    - kind: tree
      at: [-30, 30]
    - kind: mesh
      model: assets/vehicles/car.glb
      at: [30, -30]
targets:
  - id: 1
    dimensions_m: [4, 2, 1.5]
    path:
      type: waypoints
      waypoints: [[0, 0], [10, 0]]
      stops:
        - at_m: 1
          duration_s: 1
  - id: 2
    dimensions_m: [4, 2, 1.5]
    path:
      type: constant_turn
      start: [5, 5]
)";

// The node a section's keys live in, within `root`.
// `dotted` gets the node's path as messages write it ("targets[1].path").
YAML::Node SectionNode(YAML::Node root, const std::string& section, std::string* dotted) {
  const size_t space = section.find(' ');
  const std::string mapping = section.substr(0, space);
  const std::string selector = space == std::string::npos ? "" : section.substr(space + 1);
  if (mapping == "scenario") return root;
  YAML::Node node = root;
  size_t start = 0;
  while (start <= mapping.size()) {
    const size_t dot = mapping.find('.', start);
    std::string part = mapping.substr(start, dot == std::string::npos ? dot : dot - start);
    const bool item = part.size() > 3 && part.compare(part.size() - 3, 3, "[i]") == 0;
    if (item) part.resize(part.size() - 3);
    *dotted += (dotted->empty() ? "" : ".") + part;
    if (!node[part]) node[part] = YAML::Node(item ? YAML::NodeType::Sequence : YAML::NodeType::Map);
    node.reset(node[part]);  // rebinds (`=` would assign into the node)
    if (item) {
      // The item the selector names ("kind=tree", "type=constant_turn" on the
      // next level), else the first.
      YAML::Node chosen = node[0];
      size_t index = 0;
      const size_t eq = selector.find('=');
      for (size_t i = 0; i < node.size() && eq != std::string::npos; ++i) {
        const std::string key = selector.substr(0, eq), value = selector.substr(eq + 1);
        const bool here = node[i][key] && node[i][key].as<std::string>() == value;
        const bool below = node[i]["path"] && node[i]["path"][key] &&
                           node[i]["path"][key].as<std::string>() == value;
        if (here || below) {
          chosen.reset(node[i]);
          index = i;
          break;
        }
      }
      node.reset(chosen);
      *dotted += "[" + std::to_string(index) + "]";
    }
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return node;
}

// `hcpf schema --update DOC` rewrites the user's document whole or not at
// all: on a full disk (here a file-size limit under the document's size) it
// fails and leaves the document as it was, where it was truncated in place
// (and the failure, seen only at a close nobody checked, could pass as
// success). Written where it fits, the tables are regenerated.
TEST(SchemaCli, UpdateRewritesADocumentWholeOrNotAtAll) {
  const fs::path dir = FreshDir("schema-update");
  const std::string shipped = testing::ReadFile(fs::path(HCPF_SOURCE_DIR) / "docs" / "scenario.md");
  ASSERT_GT(shipped.size(), 20000U);
  // One generated row gone: the document needs rewriting.
  const size_t table = shipped.find("<!-- generated by `hcpf schema`: scenario -->");
  ASSERT_NE(table, std::string::npos);
  const size_t row = shipped.find("\n| `", table) + 1;
  const std::string stale = shipped.substr(0, row) + shipped.substr(shipped.find('\n', row) + 1);
  const fs::path doc = dir / "scenario.md";
  std::ofstream(doc, std::ios::binary) << stale;
  auto r = RunCommand("( trap '' XFSZ; ulimit -f 8; " + kHcpf + " schema --update " + doc.string() +
                      " )");
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_NE(r.output.find("File too large"), std::string::npos) << r.output;
  EXPECT_EQ(testing::ReadFile(doc), stale);
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), {}), 1) << "a temporary file was left";
  r = RunCommand(kHcpf + " schema --update " + doc.string());
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(testing::ReadFile(doc), shipped);
}

// --update naming a folder or a missing file says which (an audit: a folder
// was "found none", a missing file "found No such file or directory").
TEST(SchemaCli, UpdateOfAFolderOrAMissingFileSaysWhich) {
  const fs::path dir = FreshDir("schema-update-bad");
  auto r = RunCommand(kHcpf + " schema --update " + dir.string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find(dir.string() + ": --update: expected a markdown file with generated "
                                         "tables, found a folder"),
            std::string::npos)
      << r.output;
  r = RunCommand(kHcpf + " schema --update " + (dir / "none.md").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("none.md: --update: expected a markdown file with generated tables, "
                          "found no such file"),
            std::string::npos)
      << r.output;
}

TEST(SchemaCli, EveryDeclaredRangeIsRefusedByValidateAndRunAlike) {
  const std::vector<DeclaredKey> keys = DeclaredKeys();
  ASSERT_GT(keys.size(), 60u) << "hcpf schema lists too few keys";
  const fs::path dir = FreshDir("schema-cli");
  {
    std::ofstream(dir / "base.yaml") << kBase;
    const auto r = RunCommand("cd " + std::string(HCPF_SOURCE_DIR) + " && " + kHcpf + " validate " +
                              (dir / "base.yaml").string());
    ASSERT_EQ(r.exit_code, 0) << "the base scenario must be valid\n" << r.output;
  }
  int checked = 0;
  std::set<std::string> sections;
  for (const DeclaredKey& k : keys) {
    std::vector<double> outside;
    const double step_lo = k.integer ? 1.0 : std::max(1.0, std::abs(k.lo)) * 1e-3;
    const double step_hi = k.integer ? 1.0 : std::max(1.0, std::abs(k.hi)) * 1e-3;
    if (std::isfinite(k.lo)) outside.push_back(k.lo_open ? k.lo : k.lo - step_lo);
    if (std::isfinite(k.hi)) outside.push_back(k.hi_open ? k.hi : k.hi + step_hi);
    for (double value : outside) {
      // The base scenario with a sentinel where the value goes, emitted in
      // block style; the value's line is the sentinel's.
      YAML::Node root = YAML::Load(kBase);
      std::string dotted;
      YAML::Node parent = SectionNode(root, k.section, &dotted);
      dotted += (dotted.empty() ? "" : ".") + k.key;
      const std::string leaf = k.key.substr(k.key.rfind('.') + 1);
      YAML::Node at = parent;
      if (k.key.find('.') != std::string::npos) {
        const std::string head = k.key.substr(0, k.key.find('.'));
        if (!at[head]) at[head] = YAML::Node(YAML::NodeType::Map);
        at.reset(at[head]);
      }
      if (k.vector) {
        if (!at[leaf]) at[leaf] = YAML::Load(k.default_cell);
        YAML::Node v = at[leaf];
        if (v[0].IsSequence()) v.reset(v[0]);  // a list of points: the first point's x
        v[0] = "SENTINEL";
      } else {
        at[leaf] = "SENTINEL";
      }
      YAML::Emitter emitter;
      emitter << root;
      std::string text = emitter.c_str();
      const size_t pos = text.find("SENTINEL");
      ASSERT_NE(pos, std::string::npos);
      const int line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + pos, '\n'));
      text.replace(pos, 8, Number(value));
      const fs::path file = dir / "s.yaml";
      std::ofstream(file) << text << "\n";
      const fs::path out = dir / "out";
      for (const std::string& command :
           {kHcpf + " validate " + file.string(),
            kHcpf + " run " + file.string() + " --out " + out.string()}) {
        const auto r = RunCommand("cd " + std::string(HCPF_SOURCE_DIR) + " && " + command);
        const std::string what = k.section + " " + k.key + " = " + Number(value) + "\n" + text;
        EXPECT_EQ(r.exit_code, 2) << what << command << "\n" << r.output;
        EXPECT_NE(r.output.find(file.string() + ":" + std::to_string(line) + ":"),
                  std::string::npos)
            << what << r.output;
        EXPECT_NE(r.output.find(dotted), std::string::npos) << what << r.output;
        EXPECT_FALSE(fs::exists(out)) << command;
      }
      sections.insert(k.section);
      ++checked;
    }
  }
  EXPECT_GT(checked, 120);
  // Every section with a numeric key was reached, list items and kinds included.
  for (const char* s :
       {"scenario", "world", "world.occluders[i] kind=bridge", "world.occluders[i] kind=building",
        "world.occluders[i] kind=tree", "world.occluders[i] kind=mesh", "camera", "camera.path[i]",
        "targets[i]", "targets[i].path", "targets[i].path type=waypoints",
        "targets[i].path type=constant_turn", "targets[i].path.stops[i]", "sensor", "tracker",
        "metrics"}) {
    EXPECT_EQ(sections.count(s), 1u) << s;
  }
}

}  // namespace
}  // namespace hcpf
