// hcpf: the executable. It is thin on purpose: `hcpf score` runs here with
// only the metrics module linked, and every other subcommand (and --help,
// --version) is handed to libhcpf_cli.so, loaded next to the executable.
//
// Why: the full program links OpenCV (with LAPACK, BLAS, gfortran and TBB),
// assimp, tinygltf, EGL and their dependencies, 33 shared libraries whose
// loading and static initialisation cost ~9 ms of CPU before main() runs.
// Scoring a MOT sequence needs none of them, and its whole-process time is a
// target (docs/metrics.md, Performance); the other commands run for seconds
// to hours, where a millisecond of dlopen is nothing.

#include <array>
#include <cstdio>
#include <string>
#include <string_view>

#include "app.h"
#include "hcpf/core/shared_library.h"

namespace {

// The subcommand named on the command line: the first argument that is not an
// option or the value of --log-level (the only global option taking a value,
// see RunApp).
std::string_view Subcommand(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    if (arg == hcpf::cli::kLogLevelOption) {
      ++i;
      continue;
    }
    if (!arg.starts_with("-")) return arg;
  }
  return {};
}

using EntryFn = int (*)(int, char**);

int RunFullCli(int argc, char** argv) {
  std::string tried;
  const auto entry = reinterpret_cast<EntryFn>(hcpf::LoadSymbolNextToExecutable(
      "libhcpf_cli.so", HCPF_CLI_LIBRARY_PATH, "hcpf_cli_main", &tried));
  if (entry != nullptr) return entry(argc, argv);
  std::fprintf(stderr, "hcpf: cannot load the command library libhcpf_cli.so:%s\n", tried.c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  if (Subcommand(argc, argv) == "score") {
    static constexpr std::array<hcpf::cli::AddCommandFn, 1> kScore = {hcpf::cli::AddScoreCommand};
    return hcpf::cli::RunApp(argc, argv, kScore, {});
  }
  return RunFullCli(argc, argv);
}
