#pragma once
// The `hcpf` argument parser and dispatcher, shared by the thin executable
// (main.cc, which runs `hcpf score` itself) and the library with every
// command (entry.cc, libhcpf_cli.so). See main.cc for why there are two.

#include <functional>
#include <span>
#include <string>

#include "command.h"

namespace hcpf::cli {

using AddCommandFn = Command (*)(CLI::App&);

// The one global option that takes a value (main.cc skips it to find the
// subcommand before parsing).
inline constexpr const char* kLogLevelOption = "--log-level";

// Sets up logging (stderr), parses argv with the given subcommands, runs the
// chosen one and maps errors to exit codes (0 ok, 1 run failed, 2 bad input).
// `version()` is printed by --version (called only then: it may create a GL
// context); empty: no --version flag.
int RunApp(int argc, char** argv, std::span<const AddCommandFn> commands,
           const std::function<std::string()>& version);

}  // namespace hcpf::cli
