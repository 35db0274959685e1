#pragma once
// Plain mesh data, independent of GL: what the importers produce and what the
// GL layer uploads. Nothing here needs a GL context.
//
// Model axis convention (every MeshData in HCPF Bench, after import):
//   +x forward (the vehicle's length), +y left, +z up, metres; the origin is the
//   centre of the base (bounds centred in x and y, min z = 0) for the generated
//   vehicles. The renderer re-centres every model on its base anyway, so a
//   model with another origin still stands on the terrain.
// File conventions on import:
//   glTF / GLB is +Y up, +Z forward, +X left (glTF 2.0 spec, section 3.4). The
//   importer maps (X, Y, Z)_gltf -> (x, y, z) = (Z, X, Y), a proper rotation.
//   .obj, .fbx, .dae and .stl are read with the same y-up mapping (the
//   convention OBJ exporters use by default); export z-up models as y-up.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

namespace hcpf::renderer {

// An indexed triangle mesh. Every vertex attribute vector has the same length
// (positions.size()); `indices` holds 3 entries per triangle.
struct MeshData {
  std::vector<Eigen::Vector3f> positions;  // model frame, metres
  std::vector<Eigen::Vector3f> normals;    // unit length
  std::vector<Eigen::Vector2f> uvs;        // texture coordinates (0 when the file has none)
  std::vector<Eigen::Vector3f> colors;     // linear RGB in [0, 1]; multiplied by a tint
  std::vector<uint32_t> indices;

  size_t vertex_count() const { return positions.size(); }
  size_t triangle_count() const { return indices.size() / 3; }
  bool empty() const { return indices.empty(); }
  // Axis-aligned bounds of the positions (empty box for an empty mesh).
  Eigen::AlignedBox3f Bounds() const;
  // Appends `other`, offsetting its indices.
  void Append(const MeshData& other);
  // Whether the triangles bound a solid, consistently wound: with vertices
  // within 1e-5 of the mesh's size taken as one, every directed edge a -> b is matched
  // by as many b -> a (degenerate triangles are ignored; an empty mesh is
  // closed). Seen from outside, the first surface a ray meets is then one
  // facing the ray, so a depth pass that culls the faces turned away from
  // its eye keeps the same nearest depths.
  bool IsClosed() const;
  // Applies x -> scale.cwiseProduct(x) + offset to positions and fixes the normals.
  void Transform(const Eigen::Vector3f& scale, const Eigen::Vector3f& offset);
  // Checks the invariants above; throws hcpf::InputError naming `source`.
  void Validate(const std::string& source) const;
};

// Loads a model file into MeshData (one mesh: all nodes flattened with their
// transforms, every primitive triangulated). .glb/.gltf through tinygltf;
// .obj/.fbx/.dae/.stl through assimp (.ply is refused: see mesh.cc). Colours come from COLOR_0 /
// vertex colours when present, else from the material's base (diffuse) colour, else white. Missing
// normals are computed per face (flat shading). Throws hcpf::InputError naming the file when it
// cannot be read, has an unsupported extension, or holds no triangles.
MeshData LoadMesh(const std::string& path);

// Writes `mesh` as a binary glTF (.glb) file in the glTF axis convention
// (inverse of the import mapping), one primitive with POSITION, NORMAL,
// TEXCOORD_0, COLOR_0 and 32-bit indices. Throws hcpf::RunError on failure.
void WriteGlb(const MeshData& mesh, const std::string& path);

// (length, width, height) of the mesh's bounds: extents along x, y, z, each
// a float's precision written as the decimals the model was made with (a
// model 6.9 m long gives 6.9, not 6.900000095367432).
Eigen::Vector3d MeshDimensions(const MeshData& mesh);

// Builds meshes from primitives with flat normals and indexed vertices (4
// vertices per box face, shared by its two triangles).
class MeshBuilder {
 public:
  // Axis-aligned box between `min` and `max` (model frame).
  MeshBuilder& AddBox(const Eigen::Vector3f& min, const Eigen::Vector3f& max,
                      const Eigen::Vector3f& color);
  // Box with its own rotation about z (radians) around `centre`.
  MeshBuilder& AddOrientedBox(const Eigen::Vector3f& centre, const Eigen::Vector3f& half_size,
                              float yaw_rad, const Eigen::Vector3f& color);
  // Closed prism approximating a cylinder: axis from `a` to `b`, `segments` sides.
  MeshBuilder& AddCylinder(const Eigen::Vector3f& a, const Eigen::Vector3f& b, float radius,
                           int segments, const Eigen::Vector3f& color);
  // A quad (two triangles) with the given corners in counter-clockwise order
  // seen from the side its normal points to; uvs map to the unit square.
  MeshBuilder& AddQuad(const Eigen::Vector3f& p0, const Eigen::Vector3f& p1,
                       const Eigen::Vector3f& p2, const Eigen::Vector3f& p3,
                       const Eigen::Vector3f& color);
  const MeshData& mesh() const { return mesh_; }
  MeshData Take() { return std::move(mesh_); }

 private:
  MeshData mesh_;
};

}  // namespace hcpf::renderer
