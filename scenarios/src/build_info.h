#pragma once
// Build provenance; HCPF_* version macros come from compile definitions set in
// scenarios/CMakeLists.txt, the git revision from a file regenerated at every build.

#include <string>

namespace hcpf::scenarios {
std::string GitRevisionAtBuild();
}  // namespace hcpf::scenarios
