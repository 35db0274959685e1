#pragma once
// A yaml-cpp wrapper that knows where it is: the file, the dotted key path and
// the line/column of every node. Every key a reader asks about is recorded, so
// Finish() can reject the keys nobody asked about with a "did you mean".
// Used by scenarios/ and the sweep and regression-suite readers; library
// modules never see YAML.

#include <yaml-cpp/yaml.h>

#include <Eigen/Core>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "hcpf/config/overrides.h"
#include "hcpf/core/did_you_mean.h"
#include "hcpf/core/error.h"
#include "hcpf/core/fields.h"

namespace hcpf::config {

// A seed as written (a YAML scalar, a command-line value): decimal digits
// only, below 2^64; nullopt for anything else (empty, a sign, a space,
// another base, out of range).
std::optional<uint64_t> ParseSeed(std::string_view text);

// Shared by every node read from one document.
struct YamlContext {
  std::string file;
  // Dotted path prefix -> the `--set` override that put it there (its text
  // and index), for locations of values that came from the command line.
  struct OverrideOrigin {
    std::string label;
    int index = -1;
  };
  std::map<std::string, OverrideOrigin> overrides;
};

class YamlReader {
 public:
  YamlReader(YAML::Node node, std::string path, std::shared_ptr<const YamlContext> context);

  // Parses `text` (already read from `file`); throws InputError on a syntax
  // error with the parser's line and column.
  static YAML::Node Parse(const std::string& text, const std::string& file);
  static YAML::Node ParseFile(const std::string& file);
  // The text of a YAML file (a regular file of at most 16 MiB: scenarios and
  // sweep files are a few KiB, so a mistaken path such as a log, a video or
  // /dev/zero is refused before it is read). InputError naming the file.
  static std::string ReadFile(const std::string& file);

  const std::string& path() const { return path_; }
  const YAML::Node& node() const { return node_; }
  SourceLocation Where() const;
  SourceLocation WhereKey(const std::string& key) const;
  [[noreturn]] void Fail(const std::string& expected, const std::string& hint = {}) const;

  // This node must be a mapping (an absent/null node counts as empty).
  void ExpectMap() const;
  bool Has(const std::string& key);
  // Child mapping/list/scalar; required ones throw naming the missing key.
  YamlReader Child(const std::string& key);
  std::optional<YamlReader> Optional(const std::string& key);
  std::vector<YamlReader> Items() const;  // this node must be a list
  // A reader for a key node of this mapping (to validate keys as values).
  YamlReader Key(const YAML::Node& key_node) const {
    return YamlReader(key_node, ChildPath(key_node.Scalar()), context_);
  }

  double Number(const std::string& key, std::optional<double> fallback, double lo, double hi);
  double Number(const std::string& key, std::optional<double> fallback, const FieldRange& range);
  int64_t Integer(const std::string& key, std::optional<int64_t> fallback, int64_t lo, int64_t hi);
  uint64_t Seed(const std::string& key, std::optional<uint64_t> fallback);
  bool Bool(const std::string& key, std::optional<bool> fallback);
  std::string String(const std::string& key, std::optional<std::string> fallback);
  std::string Enum(const std::string& key, std::optional<std::string> fallback,
                   const std::vector<std::string>& choices);
  // A list of exactly N numbers in [lo, hi].
  Eigen::VectorXd Vector(const std::string& key, int n, std::optional<Eigen::VectorXd> fallback,
                         double lo, double hi);

  // Value accessors on this node itself (for list items).
  double AsNumber(double lo, double hi) const;
  double AsNumber(const FieldRange& range) const;
  int64_t AsInteger(int64_t lo, int64_t hi) const;
  Eigen::VectorXd AsVector(int n, double lo, double hi) const;
  // One of `choices` (a "did you mean" hint for a near miss).
  std::string AsEnum(const std::vector<std::string>& choices) const;

  // Runs `validate` (a module's Validate(), whose InputError names a dotted
  // key below this node, e.g. "sensor.exposure") and rethrows its error at
  // the file line and column of that key, or of its nearest written ancestor
  // when the key was left at its default. The error's fields are kept as they
  // are; only the location changes.
  void Relocate(const std::function<void()>& validate) const;

  // Rejects keys of this mapping that no reader asked about.
  void Finish() const;

 private:
  std::string ChildPath(const std::string& key) const;
  YamlReader MakeChild(const std::string& key) const;
  std::string Describe() const;  // what this node is, for "found ..."

  YAML::Node node_;
  YAML::Mark key_mark_ = YAML::Mark::null_mark();  // where this node's key is written
  std::string path_;
  std::shared_ptr<const YamlContext> context_;
  std::shared_ptr<std::set<std::string>> asked_;
};

// Applies each `--set` override to `root` (a mapping) in order and records in
// `context` where each value came from, so errors about it name the override
// (its text and index) instead of a file line.
void ApplyOverrides(YAML::Node root, const std::vector<Override>& overrides, YamlContext* context);

// Flow-style YAML text of a node, usable as an override value (`[320, 240]`).
std::string FlowText(const YAML::Node& node);

// What a file's root node that holds no value is, for an error's "found":
// "an empty file (nothing but blanks or comments)", or, when the document
// writes a null (`~`, `null`), "a null value (~ or null) where a mapping
// goes" (a second bad-input audit: a file of `~` was called empty).
std::string DescribeNullRoot(const YAML::Node& root);

}  // namespace hcpf::config
