// `hcpf validate` accepts exactly what `hcpf run` accepts: every number and
// integer key that `hcpf schema` declares, set just outside its declared
// range, is refused by both commands with exit 2, the file:line: of the value
// and the dotted key, and the run leaves no output folder.

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "support/process.h"

namespace hcpf {
namespace {

namespace fs = std::filesystem;
using testing::FreshDir;
using testing::RunCommand;

const std::string kHcpf = HCPF_EXE;

struct DeclaredKey {
  std::string dotted;  // "tracker.dynamics.sigma_pos_px"
  bool integer = false;
  double lo = 0, hi = 0;
  bool lo_open = false, hi_open = false;
};

std::string Trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" `");
  const size_t b = s.find_last_not_of(" `");
  return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
}

// The number and integer rows of `hcpf schema`'s tables.
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
    if (cells.size() < 5 || (cells[1] != "number" && cells[1] != "integer")) continue;
    const std::string& range = cells[4];  // "[0, 1000]", "(0, 16]", "(0, inf)"
    DeclaredKey k;
    k.dotted = section + "." + cells[0];
    k.integer = cells[1] == "integer";
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

TEST(SchemaCli, EveryDeclaredRangeIsRefusedByValidateAndRunAlike) {
  const std::vector<DeclaredKey> keys = DeclaredKeys();
  ASSERT_GT(keys.size(), 40u) << "hcpf schema lists too few keys";
  const fs::path dir = FreshDir("schema-cli");
  const std::string base =
      "frames: 10\n"
      "camera:\n"
      "  resolution: [320, 240]\n"
      "  path: [{frame: 0, position: [0, 0, 50], look_at: [0, 0.1, 0]}]\n"
      "targets:\n"
      "  - id: 1\n"
      "    dimensions_m: [4, 2, 1.5]\n"
      "    path: {waypoints: [[0, 0]]}\n";  // 8 lines
  int checked = 0;
  for (const DeclaredKey& k : keys) {
    std::vector<double> outside;
    const double step_lo = k.integer ? 1.0 : std::max(1.0, std::abs(k.lo)) * 1e-3;
    const double step_hi = k.integer ? 1.0 : std::max(1.0, std::abs(k.hi)) * 1e-3;
    if (std::isfinite(k.lo)) outside.push_back(k.lo_open ? k.lo : k.lo - step_lo);
    if (std::isfinite(k.hi)) outside.push_back(k.hi_open ? k.hi : k.hi + step_hi);
    for (double value : outside) {
      // The dotted key as nested mappings, the value on the last line.
      std::string text = base;
      std::string indent;
      size_t start = 0;
      int line = 8;
      while (true) {
        const size_t dot = k.dotted.find('.', start);
        const std::string part = k.dotted.substr(start, dot - start);
        ++line;
        if (dot == std::string::npos) {
          text += indent + part + ": " + Number(value) + "\n";
          break;
        }
        text += indent + part + ":\n";
        indent += "  ";
        start = dot + 1;
      }
      const fs::path file = dir / "s.yaml";
      std::ofstream(file) << text;
      const fs::path out = dir / "out";
      for (const std::string& command :
           {kHcpf + " validate " + file.string(),
            kHcpf + " run " + file.string() + " --out " + out.string()}) {
        const auto r = RunCommand(command);
        EXPECT_EQ(r.exit_code, 2) << k.dotted << " = " << Number(value) << ": " << command << "\n"
                                  << r.output;
        EXPECT_NE(r.output.find(file.string() + ":" + std::to_string(line) + ":"),
                  std::string::npos)
            << k.dotted << " = " << Number(value) << "\n"
            << r.output;
        EXPECT_NE(r.output.find(k.dotted), std::string::npos) << r.output;
        EXPECT_FALSE(fs::exists(out)) << command;
      }
      ++checked;
    }
  }
  EXPECT_GT(checked, 80);
}

}  // namespace
}  // namespace hcpf
