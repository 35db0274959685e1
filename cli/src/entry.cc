// libhcpf_cli.so: every `hcpf` subcommand. The executable (main.cc) loads it
// for anything but `hcpf score`.

#include <array>

#include "app.h"
#include "hcpf/scenarios/version.h"

extern "C" __attribute__((visibility("default"))) int hcpf_cli_main(int argc, char** argv) {
  using namespace hcpf::cli;
  static constexpr std::array<AddCommandFn, 11> kCommands = {
      AddValidateCommand, AddRenderCommand, AddRunCommand,    AddScoreCommand,
      AddSweepCommand,    AddMergeCommand,  AddReportCommand, AddRegressCommand,
      AddExportCommand,   AddSchemaCommand, AddCacheCommand,
  };
  return RunApp(argc, argv, kCommands, [] {
    return hcpf::scenarios::VersionString() + "\n" + hcpf::scenarios::GlDescription();
  });
}
