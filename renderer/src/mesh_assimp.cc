// Import of .obj, .fbx, .dae and .stl through assimp (.ply is refused in mesh.cc).

#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <fmt/format.h>

#include <assimp/Importer.hpp>

#include "hcpf/core/error.h"
#include "mesh_import.h"

namespace hcpf::renderer::internal {

MeshData LoadWithAssimp(const std::string& path) {
  Assimp::Importer importer;
  // Flatten the node hierarchy into world space, triangulate, drop points and
  // lines; flat normals where the file has none.
  const unsigned flags = aiProcess_Triangulate | aiProcess_PreTransformVertices |
                         aiProcess_SortByPType | aiProcess_GenNormals |
                         aiProcess_JoinIdenticalVertices;
  const aiScene* scene = importer.ReadFile(path, flags);
  if (scene == nullptr || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) != 0) {
    throw InputError(fmt::format("{}: cannot read model: {}", path, importer.GetErrorString()));
  }
  MeshData mesh;
  for (unsigned m = 0; m < scene->mNumMeshes; ++m) {
    const aiMesh* in = scene->mMeshes[m];
    if ((in->mPrimitiveTypes & aiPrimitiveType_TRIANGLE) == 0) continue;
    Eigen::Vector3f base_color = Eigen::Vector3f::Ones();
    if (in->mMaterialIndex < scene->mNumMaterials) {
      const aiMaterial* mat = scene->mMaterials[in->mMaterialIndex];
      aiColor4D c;
      if (aiGetMaterialColor(mat, AI_MATKEY_BASE_COLOR, &c) == AI_SUCCESS ||
          aiGetMaterialColor(mat, AI_MATKEY_COLOR_DIFFUSE, &c) == AI_SUCCESS) {
        base_color = {c.r, c.g, c.b};
      }
    }
    MeshData part;
    const unsigned n = in->mNumVertices;
    part.positions.resize(n);
    part.normals.resize(n);
    part.uvs.assign(n, Eigen::Vector2f::Zero());
    part.colors.assign(n, base_color);
    for (unsigned i = 0; i < n; ++i) {
      const aiVector3D& p = in->mVertices[i];
      part.positions[i] = FromYUp({p.x, p.y, p.z});
      if (in->HasNormals()) {
        const aiVector3D& q = in->mNormals[i];
        part.normals[i] = FromYUp(Eigen::Vector3f(q.x, q.y, q.z).normalized());
      }
      if (in->HasTextureCoords(0)) {
        part.uvs[i] = {in->mTextureCoords[0][i].x, in->mTextureCoords[0][i].y};
      }
      if (in->HasVertexColors(0)) {
        const aiColor4D& c = in->mColors[0][i];
        part.colors[i] = base_color.cwiseProduct(Eigen::Vector3f(c.r, c.g, c.b));
      }
    }
    for (unsigned f = 0; f < in->mNumFaces; ++f) {
      const aiFace& face = in->mFaces[f];
      if (face.mNumIndices != 3) continue;
      part.indices.insert(part.indices.end(),
                          {face.mIndices[0], face.mIndices[1], face.mIndices[2]});
    }
    if (!in->HasNormals()) ComputeFlatNormals(part);
    mesh.Append(part);
  }
  if (mesh.empty()) throw InputError(fmt::format("{}: model file holds no triangles", path));
  return mesh;
}

}  // namespace hcpf::renderer::internal
