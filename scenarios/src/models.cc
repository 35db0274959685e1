#include "hcpf/scenarios/models.h"

#include <fmt/format.h>

#include <filesystem>
#include <map>
#include <mutex>

#include "detection_cache.h"
#include "hcpf/config/file_lookup.h"
#include "hcpf/core/text_file.h"
#include "hcpf/renderer/mesh.h"
#include "hcpf/renderer/renderer.h"

namespace hcpf::scenarios {

namespace fs = std::filesystem;

std::string ResolveModelPath(const std::string& written, const std::string& scenario_file,
                             const SourceLocation& where, const std::string& expected) {
  const bool from_file = !scenario_file.empty() && scenario_file.rfind("--set", 0) != 0;
  const std::string beside =
      from_file ? fs::absolute(fs::path(scenario_file)).parent_path().string() : std::string();
  return fs::weakly_canonical(config::FindFileOrFail(where, written, beside, expected)).string();
}

std::string PortableModelPath(const std::string& resolved) {
  // Relative to the project's folder only: that is the same wherever hcpf
  // is started. (Relative to the current folder too was tried on
  // 2026-12-05 and reverted the same day: a review found the run's identity
  // then depending on the folder hcpf was started from, a resolved scenario
  // that no longer loaded from another folder, and an external tracker in
  // the current folder written as a bare name, looked up on PATH.)
  const fs::path root = fs::weakly_canonical(fs::path(HCPF_PROJECT_SOURCE_DIR));
  const fs::path rel = fs::path(resolved).lexically_relative(root);
  if (!rel.empty() && *rel.begin() != "..") return rel.generic_string();
  return resolved;
}

std::string ProjectRelativePath(const std::string& file) {
  std::error_code ec;
  return PortableModelPath(fs::weakly_canonical(fs::absolute(file, ec), ec).string());
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

namespace {

// Read whole to be digested: a vehicle model is a few MiB (the glTF loader
// caps a file at 256 MiB; assimp's formats have no cap of their own).
constexpr uint64_t kMaxModelFileBytes = uint64_t{1} << 30;

}  // namespace

std::string ModelDigest(const std::string& path, const SourceLocation& where) {
  const auto read = [&](const fs::path& file) {
    try {
      return ReadInputFile(file.string(), "a model file", kMaxModelFileBytes);
    } catch (const InputError& e) {
      throw InputError(where, "a readable model file", e.what());
    }
  };
  const std::string bytes = read(path);
  XXH3_state_t* state = XXH3_createState();
  HCPF_CHECK(state != nullptr) << "XXH3_createState";
  XXH3_128bits_reset(state);
  const auto add = [&](const std::string& text) {
    const uint64_t size = text.size();
    XXH3_128bits_update(state, &size, sizeof(size));
    XXH3_128bits_update(state, text.data(), text.size());
  };
  add(bytes);
  try {
    for (const fs::path& side : renderer::ModelSideFiles(path, bytes)) {
      add(side.lexically_relative(fs::path(path).parent_path()).generic_string());
      add(read(side));
    }
  } catch (...) {
    XXH3_freeState(state);
    throw;
  }
  const XXH128_hash_t digest = XXH3_128bits_digest(state);
  XXH3_freeState(state);
  return internal::DigestHex(digest);
}

}  // namespace hcpf::scenarios
