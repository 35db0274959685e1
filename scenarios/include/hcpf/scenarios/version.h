#pragma once
// Version and build provenance of HCPF Bench, for `hcpf --version` and run manifests.

#include <map>
#include <string>
#include <string_view>

namespace hcpf::scenarios {

// "hcpf 0.1.0 (git abcdef123456)"
std::string VersionString();
std::string ProjectVersion();
// Git revision of the source tree at build time ("unknown" outside a checkout),
// with "-dirty" when it had uncommitted changes.
std::string GitRevision();
// "0.1.0 at abcdef123456": the build as a run's manifest names it
// (hcpf_version at git_revision), and as the results store records it.
std::string BuildName();
// The same name of another build: "<version> at <revision>".
std::string BuildName(std::string_view version, std::string_view revision);
// The OpenGL context `renderer.backend: auto` gets on this machine, for
// `hcpf --version`: "GL (backend auto): egl device 0 (hardware), renderer
// \"NVIDIA H100 ...\", OpenGL 4.6 ...", or why none could be made. Creates and
// drops a context (tens of milliseconds).
std::string GlDescription();
// Versions of the libraries built against (OpenCV, assimp, yaml-cpp, Mesa, ...).
std::map<std::string, std::string> LibraryVersions();

}  // namespace hcpf::scenarios
