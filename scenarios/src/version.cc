#include "hcpf/scenarios/version.h"

#include <fmt/format.h>
#include <spdlog/version.h>

#include <Eigen/Core>
#include <opencv2/core/version.hpp>

#include "build_info.h"

namespace hcpf::scenarios {

std::string ProjectVersion() { return HCPF_VERSION; }

std::string GitRevision() { return GitRevisionAtBuild(); }

std::string VersionString() { return fmt::format("hcpf {} (git {})", HCPF_VERSION, GitRevision()); }

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
