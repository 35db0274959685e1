#pragma once
// One subcommand of `hcpf`. Each cmd_<name>.cc defines an Add<Name>Command()
// that creates its CLI11 subcommand (options bound to state it owns) and
// returns the function to run when that subcommand was chosen.
//
// The function returns the process exit code: 0 success, 1 the run failed.
// Bad input is reported by throwing hcpf::InputError (main maps it to exit 2);
// any other exception becomes exit 1.

#include <CLI/CLI.hpp>
#include <functional>
#include <initializer_list>
#include <ostream>
#include <string>

namespace hcpf::cli {

struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

// Where a command prints its table: standard output, or standard error when
// one of the files it writes (`--json /dev/stdout | jq`; "" for none) is
// standard output, which then carries that file alone.
std::ostream& TableStream(std::initializer_list<std::string> output_paths);

// An output file option's value, with "-" for standard output, as
// /dev/stdout (a CLI11 transform: `--json -` wrote a file named "-" in the
// current folder: an audit).
inline std::string DashIsStandardOutput(std::string path) {
  return path == "-" ? std::string("/dev/stdout") : path;
}

Command AddValidateCommand(CLI::App& parent);
Command AddRunCommand(CLI::App& parent);
Command AddScoreCommand(CLI::App& parent);
Command AddSweepCommand(CLI::App& parent);
Command AddMergeCommand(CLI::App& parent);
Command AddExportCommand(CLI::App& parent);
Command AddReportCommand(CLI::App& parent);
Command AddRegressCommand(CLI::App& parent);
Command AddRenderCommand(CLI::App& parent);
Command AddSchemaCommand(CLI::App& parent);
Command AddCacheCommand(CLI::App& parent);

}  // namespace hcpf::cli
