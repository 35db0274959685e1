// --set overrides applied in order: a section given after a key inside it
// would discard that key, and is refused.

#include "hcpf/config/overrides.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>

#include "hcpf/config/yaml_reader.h"
#include "hcpf/core/error.h"

namespace hcpf::config {
namespace {

YAML::Node Applied(const std::vector<Override>& overrides) {
  YAML::Node root = YamlReader::Parse("tracker:\n  particles: 50\n", "f.yaml");
  YamlContext context;
  context.file = "f.yaml";
  ApplyOverrides(root, overrides, &context);
  return root;
}

// `--set tracker.particles=10 --set tracker={resampling: {method: charged}}`
// ran with 500 particles (the second replaced the section, the first was
// lost; a bad-input audit, exit 0). Refused at the second override, naming
// the first and the order that keeps both.
TEST(Overrides, ASectionAfterAKeyInsideItIsRefused) {
  try {
    Applied({{"tracker.particles", "10"}, {"tracker", "{resampling: {method: charged}}"}});
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "--set tracker={resampling: {method: charged}}");
    EXPECT_EQ(e.where().override_index, 1);
    EXPECT_EQ(e.where().key, "tracker");
    EXPECT_EQ(e.found(), "\"--set tracker.particles=10\", set earlier and lost here");
    EXPECT_NE(e.hint().find("give --set tracker={resampling: {method: charged}} first and --set "
                            "tracker.particles=10 after it"),
              std::string::npos)
        << e.hint();
  }
  // A list replaced after one of its items was set: the same.
  EXPECT_THROW(Applied({{"targets.0.id", "5"}, {"targets", "[{id: 1}]"}}), InputError);
}

// The other order sets both; the same key twice takes the last value (as
// any command line does); keys that only share a prefix do not overlap.
TEST(Overrides, ASectionThenAKeyInsideItSetsBoth) {
  YAML::Node root =
      Applied({{"tracker", "{resampling: {method: charged}}"}, {"tracker.particles", "10"}});
  EXPECT_EQ(root["tracker"]["particles"].as<int>(), 10);
  EXPECT_EQ(root["tracker"]["resampling"]["method"].as<std::string>(), "charged");
  root = Applied({{"tracker.particles", "10"}, {"tracker.particles", "20"}});
  EXPECT_EQ(root["tracker"]["particles"].as<int>(), 20);
  root = Applied({{"tracker.particles_x", "1"}, {"tracker.particles", "30"}});
  EXPECT_EQ(root["tracker"]["particles"].as<int>(), 30);
}

// A key that goes on past a value names the value and the key that reaches
// it (a bad-input audit: "found a value at "x"" for targets.0.id.x).
TEST(Overrides, AKeyPastAValueNamesTheValueWhereItIs) {
  YAML::Node root = YamlReader::Parse("targets:\n  - {id: 1}\n", "f.yaml");
  YamlContext context;
  try {
    ApplyOverrides(root, {{"targets.0.id.x", "1"}}, &context);
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.expected(), "a mapping on the way to the key");
    EXPECT_EQ(e.found(), "the value \"1\" at \"targets.0.id\", which holds no key \"x\"");
  }
}

}  // namespace
}  // namespace hcpf::config
