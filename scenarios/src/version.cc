#include "hcpf/scenarios/version.h"

#include <fmt/format.h>
#include <spdlog/version.h>

#include <Eigen/Core>
#include <opencv2/core/version.hpp>

#include "build_info.h"
#include "hcpf/core/error.h"
#include "hcpf/renderer/gl_context.h"

namespace hcpf::scenarios {

std::string ProjectVersion() { return HCPF_VERSION; }

std::string GitRevision() { return GitRevisionAtBuild(); }

std::string BuildName(std::string_view version, std::string_view revision) {
  return fmt::format("{} at {}", version, revision);
}

std::string BuildName() { return BuildName(HCPF_VERSION, GitRevision()); }

std::string VersionString() { return fmt::format("hcpf {} (git {})", HCPF_VERSION, GitRevision()); }

std::string GlDescription() {
  try {
    const auto context = renderer::GlContext::Create(renderer::GlBackend::kAuto);
    const renderer::GlInfo& gl = context->info();
    return fmt::format("GL (backend auto): {}, renderer \"{}\", vendor \"{}\", OpenGL {}",
                       gl.platform, gl.renderer, gl.vendor, gl.version);
  } catch (const Error& e) {
    return fmt::format("GL (backend auto): none ({})", e.what());
  }
}

std::map<std::string, std::string> LibraryVersions() {
  return {
      {"opencv", CV_VERSION},
      {"eigen",
       fmt::format("{}.{}.{}", EIGEN_WORLD_VERSION, EIGEN_MAJOR_VERSION, EIGEN_MINOR_VERSION)},
      {"spdlog", fmt::format("{}.{}.{}", SPDLOG_VER_MAJOR, SPDLOG_VER_MINOR, SPDLOG_VER_PATCH)},
      {"fmt",
       fmt::format("{}.{}.{}", FMT_VERSION / 10000, FMT_VERSION / 100 % 100, FMT_VERSION % 100)},
      {"yaml-cpp", HCPF_YAMLCPP_VERSION},
      {"assimp", HCPF_ASSIMP_VERSION},
      {"tinygltf", HCPF_TINYGLTF_VERSION},
      {"mesa", HCPF_MESA_VERSION},
  };
}

}  // namespace hcpf::scenarios
