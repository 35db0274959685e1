#pragma once
// `--set key=value` overrides of the command line and of sweep cells: the
// dotted key (list items by index, `targets.0.path.speed_mps`) and a YAML value
// (`1000`, `[320, 240]`, `charged`). Applied to a document before it is read
// (ApplyOverrides, hcpf/config/yaml_reader.h) with the same checks as a file.

#include <string>

namespace hcpf::config {

struct Override {
  std::string key;
  std::string value;
  // "--set key=value": how messages name a value that came from here.
  std::string Label() const { return "--set " + key + "=" + value; }
};

// Parses "key=value"; throws InputError when there is no '=' or no key.
Override ParseOverride(const std::string& text);

// Whether dotted key `key` lies inside `parent` (`tracker.particles` inside
// `tracker`; not `tracker.particles_x` inside `tracker.particles`). Two such
// overrides of one document conflict: sweeps and suites refuse them, and
// ApplyOverrides refuses a section given after a key inside it (it would
// discard that key), while a key after its section sets both.
bool IsKeyInside(const std::string& key, const std::string& parent);

}  // namespace hcpf::config
