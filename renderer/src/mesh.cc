#include "hcpf/renderer/mesh.h"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <limits>
#include <map>
#include <numbers>
#include <utility>

#include "hcpf/core/check.h"
#include "hcpf/core/error.h"
#include "hcpf/core/text_file.h"
#include "mesh_import.h"

namespace hcpf::renderer {

Eigen::AlignedBox3f MeshData::Bounds() const {
  Eigen::AlignedBox3f box;  // default-constructed = empty
  for (const Eigen::Vector3f& p : positions) box.extend(p);
  return box;
}

void MeshData::Append(const MeshData& other) {
  const auto offset = static_cast<uint32_t>(positions.size());
  positions.insert(positions.end(), other.positions.begin(), other.positions.end());
  normals.insert(normals.end(), other.normals.begin(), other.normals.end());
  uvs.insert(uvs.end(), other.uvs.begin(), other.uvs.end());
  colors.insert(colors.end(), other.colors.begin(), other.colors.end());
  indices.reserve(indices.size() + other.indices.size());
  for (uint32_t i : other.indices) indices.push_back(i + offset);
}

bool MeshData::IsClosed() const {
  // Weld: vertices within eps of one another are one (generators and
  // exporters duplicate vertices per face, and recompute a shared corner
  // with other rounding: the capped cylinders' seams differ in the last
  // bit). eps is 1e-5 of the mesh's size, far above float rounding and far
  // below any gap a model means to have. A map of eps-cells finds
  // earlier vertices in the 27 cells around a vertex.
  // Cells are counted from the bounds' corner, in double: a float mesh's
  // extent reaches 6.8e38 (bounds at -+3.4e38, which overflows float), so
  // its size, eps and the offsets from the corner stay finite and the cells
  // stay below 1e5 + 1 whatever the coordinates. A mesh with a non-finite
  // position, which Validate refuses, is not closed.
  for (const Eigen::Vector3f& p : positions) {
    if (!p.allFinite()) return false;
  }
  // Without a triangle there is nothing to weld (the renderer's terrain
  // arrives so: its indices are chosen per frame; at 1024 cells a side the
  // weld alone took 1.6 s).
  if (indices.size() < 3) return true;
  const Eigen::AlignedBox3f bounds = Bounds();
  const Eigen::Vector3d lo = bounds.isEmpty() ? Eigen::Vector3d(Eigen::Vector3d::Zero())
                                              : Eigen::Vector3d(bounds.min().cast<double>());
  const double size = bounds.isEmpty() ? 0.0 : (bounds.max().cast<double>() - lo).maxCoeff();
  const double eps = std::max(1e-5 * size, static_cast<double>(std::numeric_limits<float>::min()));
  const auto cell_of = [&](const Eigen::Vector3f& p) {
    const Eigen::Vector3d q = (p.cast<double>() - lo) / eps;
    return std::array<int64_t, 3>{static_cast<int64_t>(std::floor(q.x())),
                                  static_cast<int64_t>(std::floor(q.y())),
                                  static_cast<int64_t>(std::floor(q.z()))};
  };
  std::map<std::array<int64_t, 3>, std::vector<uint32_t>> grid;  // cell -> welded ids
  std::vector<Eigen::Vector3f> welded;
  std::vector<uint32_t> weld(positions.size());
  for (size_t i = 0; i < positions.size(); ++i) {
    const Eigen::Vector3f& p = positions[i];
    const std::array<int64_t, 3> c = cell_of(p);
    uint32_t id = static_cast<uint32_t>(welded.size());
    for (int64_t dz = -1; dz <= 1 && id == welded.size(); ++dz) {
      for (int64_t dy = -1; dy <= 1 && id == welded.size(); ++dy) {
        for (int64_t dx = -1; dx <= 1 && id == welded.size(); ++dx) {
          const auto it = grid.find({c[0] + dx, c[1] + dy, c[2] + dz});
          if (it == grid.end()) continue;
          for (const uint32_t w : it->second) {
            if ((welded[w].cast<double>() - p.cast<double>()).cwiseAbs().maxCoeff() <= eps) {
              id = w;
              break;
            }
          }
        }
      }
    }
    if (id == welded.size()) {
      welded.push_back(p);
      grid[c].push_back(id);
    }
    weld[i] = id;
  }
  // +1 for each directed edge a -> b with a < b, -1 for each b -> a.
  std::map<std::pair<uint32_t, uint32_t>, int> balance;
  for (size_t t = 0; t + 2 < indices.size(); t += 3) {
    const uint32_t v[3] = {weld[indices[t]], weld[indices[t + 1]], weld[indices[t + 2]]};
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) continue;
    for (int e = 0; e < 3; ++e) {
      const uint32_t a = v[e];
      const uint32_t b = v[(e + 1) % 3];
      if (a < b) {
        ++balance[{a, b}];
      } else {
        --balance[{b, a}];
      }
    }
  }
  return std::all_of(balance.begin(), balance.end(), [](const auto& e) { return e.second == 0; });
}

void MeshData::Transform(const Eigen::Vector3f& scale, const Eigen::Vector3f& offset) {
  for (Eigen::Vector3f& p : positions) p = scale.cwiseProduct(p) + offset;
  // Normals transform with the inverse transpose: divide by the scale.
  const Eigen::Vector3f inv = scale.cwiseInverse();
  for (Eigen::Vector3f& n : normals) {
    n = inv.cwiseProduct(n);
    const float len = n.norm();
    if (len > 0.0f) n /= len;
  }
  // A mirroring scale flips the winding; keep triangles front-facing.
  if (scale.x() * scale.y() * scale.z() < 0.0f) {
    for (size_t t = 0; t + 2 < indices.size(); t += 3) std::swap(indices[t + 1], indices[t + 2]);
  }
}

void MeshData::Validate(const std::string& source) const {
  const size_t n = positions.size();
  if (normals.size() != n || uvs.size() != n || colors.size() != n) {
    throw InputError(
        fmt::format("{}: mesh attributes disagree in length (positions {}, "
                    "normals {}, uvs {}, colors {})",
                    source, n, normals.size(), uvs.size(), colors.size()));
  }
  if (indices.empty() || indices.size() % 3 != 0) {
    throw InputError(fmt::format("{}: expected a mesh with triangles, found {} indices", source,
                                 indices.size()));
  }
  for (uint32_t i : indices) {
    if (i >= n) {
      throw InputError(fmt::format("{}: index {} out of range for {} vertices", source, i, n));
    }
  }
  for (const Eigen::Vector3f& p : positions) {
    if (!p.allFinite()) throw InputError(fmt::format("{}: non-finite vertex position", source));
  }
}

namespace {

// The double nearest the shortest decimal that reads back as `f`: 6.9f gives
// 6.9, where widening it gives 6.900000095367432.
double ShortestDecimal(float f) {
  std::array<char, 32> text{};
  const auto written = std::to_chars(text.data(), text.data() + text.size(), f);
  HCPF_CHECK(written.ec == std::errc());
  double d = 0.0;
  const auto read = std::from_chars(text.data(), written.ptr, d);
  HCPF_CHECK(read.ec == std::errc());
  return d;
}

}  // namespace

Eigen::Vector3d MeshDimensions(const MeshData& mesh) {
  if (mesh.positions.empty()) return Eigen::Vector3d::Zero();
  const Eigen::AlignedBox3f b = mesh.Bounds();
  // The bounds are floats: read each as the decimal it was written as, take
  // the difference in doubles and keep a float's precision, so that a model
  // from z = 1.1 to 3.3 is 2.2 m high (not 2.1999998, the float difference,
  // nor 2.1999999999999997) in the resolved scenario and its hash. Casting
  // back to float (the renderer's scale) gives the float extent within an ulp.
  Eigen::Vector3d d;
  for (int i = 0; i < 3; ++i) {
    const double extent = ShortestDecimal(b.max()[i]) - ShortestDecimal(b.min()[i]);
    d[i] = ShortestDecimal(static_cast<float>(extent));
  }
  return d;
}

MeshData LoadMesh(const std::string& path) {
  if (!std::filesystem::exists(path)) {
    throw InputError(fmt::format("{}: model file not found", path));
  }
  const uint64_t size = CheckRegularFile(path, "a model file");  // not a directory, FIFO or device
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  MeshData mesh;
  if (ext == ".glb" || ext == ".gltf") {
    mesh = internal::LoadGltf(path, size);
  } else if (ext == ".ply") {
    // Debian 12's libassimp 5.2 PLY reader hangs, crashes (SIGSEGV) or aborts
    // on small malformed files (docs/fuzzing.md, fuzz/regressions/assimp): a
    // model file must never take the tool down, so PLY is not read at all.
    throw InputError(fmt::format(
        "{}: PLY models are not accepted (the PLY reader of Debian 12's assimp crashes on "
        "malformed files); convert the model to .glb, e.g. with Blender or assimp export",
        path));
  } else if (ext == ".obj" || ext == ".fbx" || ext == ".dae" || ext == ".stl") {
    mesh = internal::LoadWithAssimp(path);
  } else {
    throw InputError(
        fmt::format("{}: expected a model file ending in .glb, .gltf, .obj, .fbx, .dae or .stl, "
                    "found extension \"{}\"",
                    path, ext));
  }
  mesh.Validate(path);
  return mesh;
}

// ---------------------------------------------------------------------------
// MeshBuilder

namespace {

// Appends a convex planar polygon as a triangle fan whose winding matches
// `normal` (counter-clockwise seen from the side `normal` points to).
void AddPolygon(MeshData& mesh, const std::vector<Eigen::Vector3f>& points,
                const std::vector<Eigen::Vector2f>& uvs, const Eigen::Vector3f& normal,
                const Eigen::Vector3f& color) {
  HCPF_CHECK(points.size() >= 3 && uvs.size() == points.size());
  const auto base = static_cast<uint32_t>(mesh.positions.size());
  for (size_t i = 0; i < points.size(); ++i) {
    mesh.positions.push_back(points[i]);
    mesh.normals.push_back(normal);
    mesh.uvs.push_back(uvs[i]);
    mesh.colors.push_back(color);
  }
  const Eigen::Vector3f geometric = (points[1] - points[0]).cross(points[2] - points[0]);
  const bool flip = geometric.dot(normal) < 0.0f;
  for (uint32_t i = 1; i + 1 < points.size(); ++i) {
    mesh.indices.push_back(base);
    mesh.indices.push_back(base + (flip ? i + 1 : i));
    mesh.indices.push_back(base + (flip ? i : i + 1));
  }
}

}  // namespace

MeshBuilder& MeshBuilder::AddQuad(const Eigen::Vector3f& p0, const Eigen::Vector3f& p1,
                                  const Eigen::Vector3f& p2, const Eigen::Vector3f& p3,
                                  const Eigen::Vector3f& color) {
  const Eigen::Vector3f normal = (p1 - p0).cross(p2 - p0).normalized();
  AddPolygon(mesh_, {p0, p1, p2, p3}, {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, normal, color);
  return *this;
}

MeshBuilder& MeshBuilder::AddOrientedBox(const Eigen::Vector3f& centre,
                                         const Eigen::Vector3f& half_size, float yaw_rad,
                                         const Eigen::Vector3f& color) {
  const float c = std::cos(yaw_rad);
  const float s = std::sin(yaw_rad);
  Eigen::Matrix3f r;
  r << c, -s, 0, s, c, 0, 0, 0, 1;
  const auto corner = [&](int sx, int sy, int sz) -> Eigen::Vector3f {
    return centre + r * Eigen::Vector3f(sx * half_size.x(), sy * half_size.y(), sz * half_size.z());
  };
  // Each face: its outward axis and the four corners around it.
  for (int axis = 0; axis < 3; ++axis) {
    for (int sign : {-1, 1}) {
      std::vector<Eigen::Vector3f> pts;
      const int a1 = (axis + 1) % 3;
      const int a2 = (axis + 2) % 3;
      for (auto [u, v] : {std::pair{-1, -1}, std::pair{1, -1}, std::pair{1, 1}, std::pair{-1, 1}}) {
        int sgn[3];
        sgn[axis] = sign;
        sgn[a1] = u;
        sgn[a2] = v;
        pts.push_back(corner(sgn[0], sgn[1], sgn[2]));
      }
      Eigen::Vector3f n = Eigen::Vector3f::Zero();
      n[axis] = static_cast<float>(sign);
      AddPolygon(mesh_, pts, {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, r * n, color);
    }
  }
  return *this;
}

MeshBuilder& MeshBuilder::AddBox(const Eigen::Vector3f& min, const Eigen::Vector3f& max,
                                 const Eigen::Vector3f& color) {
  return AddOrientedBox(0.5f * (min + max), 0.5f * (max - min), 0.0f, color);
}

MeshBuilder& MeshBuilder::AddCylinder(const Eigen::Vector3f& a, const Eigen::Vector3f& b,
                                      float radius, int segments, const Eigen::Vector3f& color) {
  HCPF_CHECK(segments >= 3 && radius > 0.0f);
  const Eigen::Vector3f axis = (b - a).normalized();
  const Eigen::Vector3f helper =
      std::abs(axis.z()) < 0.9f ? Eigen::Vector3f::UnitZ() : Eigen::Vector3f::UnitX();
  const Eigen::Vector3f u = axis.cross(helper).normalized();
  const Eigen::Vector3f v = axis.cross(u);
  const auto dir = [&](float t) { return std::cos(t) * u + std::sin(t) * v; };
  const float step = 2.0f * std::numbers::pi_v<float> / static_cast<float>(segments);
  std::vector<Eigen::Vector3f> cap_a, cap_b;
  std::vector<Eigen::Vector2f> cap_uv;
  for (int i = 0; i < segments; ++i) {
    const float t0 = step * static_cast<float>(i);
    const float t1 = t0 + step;
    const Eigen::Vector3f n = dir(0.5f * (t0 + t1));
    AddPolygon(
        mesh_,
        {a + radius * dir(t0), a + radius * dir(t1), b + radius * dir(t1), b + radius * dir(t0)},
        {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, n, color);
    cap_a.push_back(a + radius * dir(t0));
    cap_b.push_back(b + radius * dir(t0));
    cap_uv.emplace_back(0.5f + 0.5f * std::cos(t0), 0.5f + 0.5f * std::sin(t0));
  }
  AddPolygon(mesh_, cap_a, cap_uv, -axis, color);
  AddPolygon(mesh_, cap_b, cap_uv, axis, color);
  return *this;
}

}  // namespace hcpf::renderer

namespace hcpf::renderer::internal {

void ComputeFlatNormals(MeshData& mesh) {
  MeshData flat;
  const size_t n = mesh.indices.size();
  flat.positions.reserve(n);
  for (size_t t = 0; t + 2 < n; t += 3) {
    const uint32_t i[3] = {mesh.indices[t], mesh.indices[t + 1], mesh.indices[t + 2]};
    const Eigen::Vector3f& p0 = mesh.positions[i[0]];
    Eigen::Vector3f normal = (mesh.positions[i[1]] - p0).cross(mesh.positions[i[2]] - p0);
    const float len = normal.norm();
    normal = len > 0.0f ? Eigen::Vector3f(normal / len) : Eigen::Vector3f::UnitZ();
    for (uint32_t k : i) {
      flat.indices.push_back(static_cast<uint32_t>(flat.positions.size()));
      flat.positions.push_back(mesh.positions[k]);
      flat.normals.push_back(normal);
      flat.uvs.push_back(k < mesh.uvs.size() ? mesh.uvs[k] : Eigen::Vector2f::Zero());
      flat.colors.push_back(k < mesh.colors.size() ? mesh.colors[k] : Eigen::Vector3f::Ones());
    }
  }
  mesh = std::move(flat);
}

}  // namespace hcpf::renderer::internal
