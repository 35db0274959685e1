#pragma once
// Private: the per-library importers behind LoadMesh().

#include <cstdint>
#include <string>

#include "hcpf/renderer/mesh.h"

namespace hcpf::renderer::internal {

// glTF 2.0 (.gltf / .glb) through tinygltf; converts y-up to z-up. `size`:
// the file's size, from LoadMesh's CheckRegularFile.
MeshData LoadGltf(const std::string& path, uint64_t size);
// Everything else assimp reads; converts y-up to z-up.
MeshData LoadWithAssimp(const std::string& path);

// The axis mapping from the glTF / y-up file convention to the model frame:
// (X, Y, Z)_file -> (Z, X, Y). A cyclic permutation, so a proper rotation.
inline Eigen::Vector3f FromYUp(const Eigen::Vector3f& v) { return {v.z(), v.x(), v.y()}; }
inline Eigen::Vector3f ToYUp(const Eigen::Vector3f& v) { return {v.y(), v.z(), v.x()}; }

// Fills flat per-face normals for a mesh that has none: every triangle gets
// its own three vertices (indices rewritten).
void ComputeFlatNormals(MeshData& mesh);

}  // namespace hcpf::renderer::internal
