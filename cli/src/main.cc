// hcpf: the HCPF Bench command line. Parses arguments, dispatches to the
// subcommand, maps errors to exit codes (0 ok, 1 run failed, 2 bad input).

#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <vector>

#include "command.h"
#include "hcpf/core/error.h"
#include "hcpf/scenarios/version.h"

int main(int argc, char** argv) {
  // Logging goes to stderr; stdout is reserved for requested machine output.
  auto logger = spdlog::stderr_color_mt("hcpf");
  spdlog::set_default_logger(logger);
  spdlog::set_pattern("[%H:%M:%S.%e] [%^%l%$] %v");

  CLI::App app{"HCPF Bench: synthetic-scene evaluation harness for multi-target tracking"};
  app.set_version_flag("--version", hcpf::scenarios::VersionString());
  app.require_subcommand(1);
  std::string log_level = "info";
  app.add_option("--log-level", log_level, "trace, debug, info, warn, error or off")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "off"}))
      ->capture_default_str();

  std::vector<hcpf::cli::Command> commands = {
      hcpf::cli::AddValidateCommand(app),
      hcpf::cli::AddRenderCommand(app),
      hcpf::cli::AddRunCommand(app),
      hcpf::cli::AddScoreCommand(app),
      hcpf::cli::AddSweepCommand(app),
      hcpf::cli::AddMergeCommand(app),
      hcpf::cli::AddReportCommand(app),
      hcpf::cli::AddRegressCommand(app),
  };

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return 2;
  }
  spdlog::set_level(spdlog::level::from_str(log_level));

  for (const auto& command : commands) {
    if (!command.app->parsed()) continue;
    try {
      return command.run();
    } catch (const hcpf::InputError& e) {
      spdlog::error("{}", e.what());
      return 2;
    } catch (const std::exception& e) {
      spdlog::error("{} failed: {}", command.app->get_name(), e.what());
      return 1;
    }
  }
  return 2;
}
