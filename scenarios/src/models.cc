#include "hcpf/scenarios/models.h"

#include <fmt/format.h>

#include <filesystem>
#include <map>
#include <mutex>

#include "hcpf/config/file_lookup.h"
#include "hcpf/renderer/mesh.h"

namespace hcpf::scenarios {

namespace fs = std::filesystem;

std::string ResolveModelPath(const std::string& written, const std::string& scenario_file,
                             const SourceLocation& where, const std::string& expected) {
  const bool from_file = !scenario_file.empty() && scenario_file.rfind("--set", 0) != 0;
  const std::string beside =
      from_file ? fs::absolute(fs::path(scenario_file)).parent_path().string() : std::string();
  return fs::weakly_canonical(config::FindFileOrFail(where, written, beside, expected)).string();
}

std::string ProjectRelativePath(const std::string& file) {
  std::error_code ec;
  const fs::path path = fs::weakly_canonical(fs::absolute(file, ec), ec);
  const fs::path rel =
      path.lexically_relative(fs::weakly_canonical(fs::path(HCPF_PROJECT_SOURCE_DIR), ec));
  return !rel.empty() && *rel.begin() != ".." ? rel.generic_string() : path.string();
}

std::string PortableModelPath(const std::string& resolved) {
  // Relative to the first of the project's folder and the current folder
  // that holds it: a second clone run from its own folder (or a checkout
  // mounted elsewhere than the binary was built) writes the same path, so
  // the same configuration hash (a determinism audit found the clone's
  // absolute path, and sweeps that could then be neither resumed from there
  // nor merged). Both are places the lookup (ResolveModelPath) looks in.
  std::error_code ec;
  for (const fs::path& folder :
       {fs::weakly_canonical(fs::path(HCPF_PROJECT_SOURCE_DIR)), fs::current_path(ec)}) {
    if (folder.empty() || folder == folder.root_path()) continue;  // "/" holds every file
    const fs::path rel = fs::path(resolved).lexically_relative(fs::weakly_canonical(folder));
    if (!rel.empty() && *rel.begin() != ".." && rel.is_relative()) return rel.generic_string();
  }
  return resolved;
}

Eigen::Vector3d ModelDimensions(const std::string& path, const SourceLocation& where) {
  // Scenario files name the same few models many times (sweeps load one
  // scenario per run): keep the dimensions of each file once read.
  static std::mutex mutex;
  static std::map<std::string, Eigen::Vector3d> cache;
  {
    std::lock_guard lock(mutex);
    if (auto it = cache.find(path); it != cache.end()) return it->second;
  }
  Eigen::Vector3d dims;
  try {
    dims = renderer::MeshDimensions(renderer::LoadMesh(path));
  } catch (const InputError& e) {
    throw InputError(where, "a readable mesh file", fmt::format("\"{}\": {}", path, e.what()));
  }
  std::lock_guard lock(mutex);
  cache[path] = dims;
  return dims;
}

}  // namespace hcpf::scenarios
