#pragma once
// The project's small error hierarchy. Bad input (files, keys, values, missing
// assets, no GL context) is an InputError: the CLI prints it and exits 2.
// A run that fails for any other reason throws RunError: exit 1.

#include <stdexcept>
#include <string>

namespace hcpf {

// Where in an input file a problem is. Line and column are 1-based; 0 = unknown.
struct SourceLocation {
  std::string file;
  int line = 0;
  int column = 0;
  std::string key;  // dotted key path, e.g. "tracker.resampling.beta"
  // >= 0 when the value came from the command line's `--set` override of this
  // index (0-based, in the order given); `file` then holds the override's text.
  int override_index = -1;
};

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Bad input. The message names file:line:column, the key, what was expected
// and what was found, e.g.
//   scenario.yaml:12:5: tracker.particles: expected an integer in [1, 10000000], found "many"
class InputError : public Error {
 public:
  InputError(SourceLocation where, std::string expected, std::string found, std::string hint = {});
  explicit InputError(const std::string& message);

  const SourceLocation& where() const { return where_; }
  const std::string& expected() const { return expected_; }
  const std::string& found() const { return found_; }
  const std::string& hint() const { return hint_; }

 private:
  SourceLocation where_;
  std::string expected_;
  std::string found_;
  std::string hint_;
};

// A run that could not complete (I/O failure while writing, a component failed).
class RunError : public Error {
 public:
  using Error::Error;
};

// Formats "file:line:column: key: expected E, found F (hint)".
std::string FormatInputError(const SourceLocation& where, const std::string& expected,
                             const std::string& found, const std::string& hint);

}  // namespace hcpf
