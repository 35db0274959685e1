// glTF 2.0 import and GLB export through tinygltf (Debian's libtinygltf holds
// the implementation; we only include its declarations).

#define TINYGLTF_NO_INCLUDE_STB_IMAGE
#define TINYGLTF_NO_INCLUDE_STB_IMAGE_WRITE
#include <fmt/format.h>
#include <tiny_gltf.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>

#include "hcpf/core/error.h"
#include "hcpf/core/text_file.h"
#include "mesh_import.h"

namespace hcpf::renderer {
namespace internal {
namespace {

// An accessor's elements as located in its buffer: `count` elements of
// `element_bytes` bytes, `stride` bytes apart, the first at `first`.
struct AccessorBytes {
  const unsigned char* first = nullptr;
  size_t stride = 0;
  size_t count = 0;
  int component_size = 0;
};

// Locates accessor `index`'s bytes, checking (without any sum or product that
// can wrap: every field is a file's 64-bit value) that the buffer view lies in
// its buffer and that every element lies in the view. `what` names the
// accessor's use in messages ("POSITION accessor 0").
AccessorBytes LocateAccessor(const tinygltf::Model& model, int index, int components,
                             const std::string& what, const std::string& path) {
  const tinygltf::Accessor& acc = model.accessors.at(static_cast<size_t>(index));
  if (acc.sparse.isSparse || acc.bufferView < 0) {
    throw InputError(
        fmt::format("{}: {}: sparse or buffer-less glTF accessors are not supported", path, what));
  }
  const tinygltf::BufferView& view = model.bufferViews.at(static_cast<size_t>(acc.bufferView));
  const tinygltf::Buffer& buffer = model.buffers.at(static_cast<size_t>(view.buffer));
  const size_t size = buffer.data.size();
  if (view.byteOffset > size || view.byteLength > size - view.byteOffset) {
    throw InputError(fmt::format(
        "{}: {}: buffer view {} (byteOffset {}, byteLength {}) lies outside its buffer of {} bytes",
        path, what, acc.bufferView, view.byteOffset, view.byteLength, size));
  }
  AccessorBytes out;
  out.component_size = tinygltf::GetComponentSizeInBytes(static_cast<uint32_t>(acc.componentType));
  const int stride = acc.ByteStride(view);
  if (stride <= 0 || out.component_size <= 0) {
    throw InputError(fmt::format("{}: {} has an invalid layout (componentType {}, type {})", path,
                                 what, acc.componentType, acc.type));
  }
  out.stride = static_cast<size_t>(stride);
  out.count = acc.count;
  const size_t element_bytes =
      static_cast<size_t>(components) * static_cast<size_t>(out.component_size);
  // Bytes of the view from the accessor's start; every element must fit.
  const bool offset_inside = acc.byteOffset <= view.byteLength;
  const size_t room = offset_inside ? view.byteLength - acc.byteOffset : 0;
  const bool fits =
      offset_inside && (acc.count == 0 || (element_bytes <= room &&
                                           acc.count - 1 <= (room - element_bytes) / out.stride));
  if (!fits) {
    throw InputError(fmt::format(
        "{}: {} (count {}, byteOffset {}, {} bytes apart) reads past the end of buffer view {} "
        "({} bytes)",
        path, what, acc.count, acc.byteOffset, out.stride, acc.bufferView, view.byteLength));
  }
  out.first = buffer.data.data() + view.byteOffset + acc.byteOffset;
  return out;
}

// Reads an accessor as floats (count * components), converting normalised
// integer components to [0, 1] as the spec defines.
std::vector<float> ReadFloats(const tinygltf::Model& model, int accessor_index,
                              int expected_components, const std::string& what,
                              const std::string& path) {
  const tinygltf::Accessor& acc = model.accessors.at(static_cast<size_t>(accessor_index));
  const std::string label = fmt::format("{} accessor {}", what, accessor_index);
  const int components = tinygltf::GetNumComponentsInType(static_cast<uint32_t>(acc.type));
  if (components < expected_components) {
    throw InputError(fmt::format("{}: {} has {} components, expected at least {}", path, label,
                                 components, expected_components));
  }
  const AccessorBytes bytes = LocateAccessor(model, accessor_index, components, label, path);
  std::vector<float> out;
  out.reserve(bytes.count * static_cast<size_t>(expected_components));
  for (size_t i = 0; i < bytes.count; ++i) {
    const unsigned char* element = bytes.first + i * bytes.stride;
    for (int c = 0; c < expected_components; ++c) {
      const unsigned char* p = element + c * bytes.component_size;
      float value = 0.0f;
      switch (acc.componentType) {
        case TINYGLTF_COMPONENT_TYPE_FLOAT:
          std::memcpy(&value, p, 4);
          break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
          value = acc.normalized ? p[0] / 255.0f : static_cast<float>(p[0]);
          break;
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
          uint16_t s;
          std::memcpy(&s, p, 2);
          value = acc.normalized ? s / 65535.0f : static_cast<float>(s);
          break;
        }
        default:
          throw InputError(fmt::format("{}: {} has unsupported component type {}", path, label,
                                       acc.componentType));
      }
      out.push_back(value);
    }
  }
  return out;
}

std::vector<uint32_t> ReadIndices(const tinygltf::Model& model, int accessor_index,
                                  const std::string& path) {
  const tinygltf::Accessor& acc = model.accessors.at(static_cast<size_t>(accessor_index));
  const std::string label = fmt::format("index accessor {}", accessor_index);
  const AccessorBytes bytes = LocateAccessor(model, accessor_index, 1, label, path);
  std::vector<uint32_t> out(bytes.count);
  for (size_t i = 0; i < bytes.count; ++i) {
    const unsigned char* p = bytes.first + i * bytes.stride;
    switch (acc.componentType) {
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        out[i] = p[0];
        break;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t s;
        std::memcpy(&s, p, 2);
        out[i] = s;
        break;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
        std::memcpy(&out[i], p, 4);
        break;
      default:
        throw InputError(fmt::format("{}: {} has unsupported component type {}", path, label,
                                     acc.componentType));
    }
  }
  return out;
}

Eigen::Matrix4d NodeTransform(const tinygltf::Node& node) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  if (node.matrix.size() == 16) {
    for (int i = 0; i < 16; ++i) m(i % 4, i / 4) = node.matrix[static_cast<size_t>(i)];
    return m;
  }
  Eigen::Matrix4d t = Eigen::Matrix4d::Identity();
  Eigen::Matrix4d r = Eigen::Matrix4d::Identity();
  Eigen::Matrix4d s = Eigen::Matrix4d::Identity();
  if (node.translation.size() == 3) {
    t.block<3, 1>(0, 3) =
        Eigen::Vector3d(node.translation[0], node.translation[1], node.translation[2]);
  }
  if (node.rotation.size() == 4) {  // glTF stores (x, y, z, w)
    const Eigen::Quaterniond q(node.rotation[3], node.rotation[0], node.rotation[1],
                               node.rotation[2]);
    r.block<3, 3>(0, 0) = q.normalized().toRotationMatrix();
  }
  if (node.scale.size() == 3) {
    s.diagonal().head<3>() = Eigen::Vector3d(node.scale[0], node.scale[1], node.scale[2]);
  }
  return t * r * s;
}

void AppendPrimitive(const tinygltf::Model& model, const tinygltf::Primitive& prim,
                     const Eigen::Matrix4d& world, const std::string& path, MeshData& out) {
  if (prim.mode != TINYGLTF_MODE_TRIANGLES && prim.mode != -1) return;  // points/lines/strips
  const auto pos_it = prim.attributes.find("POSITION");
  if (pos_it == prim.attributes.end()) return;
  const std::vector<float> pos = ReadFloats(model, pos_it->second, 3, "POSITION", path);
  const size_t n = pos.size() / 3;
  MeshData part;
  part.positions.resize(n);
  const Eigen::Matrix3d linear = world.block<3, 3>(0, 0);
  const Eigen::Vector3d offset = world.block<3, 1>(0, 3);
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d p(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
    part.positions[i] = FromYUp((linear * p + offset).cast<float>());
  }
  bool has_normals = false;
  if (auto it = prim.attributes.find("NORMAL"); it != prim.attributes.end()) {
    const std::vector<float> nrm = ReadFloats(model, it->second, 3, "NORMAL", path);
    if (nrm.size() == pos.size()) {
      has_normals = true;
      const Eigen::Matrix3d normal_matrix = linear.inverse().transpose();
      part.normals.resize(n);
      for (size_t i = 0; i < n; ++i) {
        const Eigen::Vector3d v(nrm[3 * i], nrm[3 * i + 1], nrm[3 * i + 2]);
        part.normals[i] = FromYUp((normal_matrix * v).normalized().cast<float>());
      }
    }
  }
  part.uvs.assign(n, Eigen::Vector2f::Zero());
  if (auto it = prim.attributes.find("TEXCOORD_0"); it != prim.attributes.end()) {
    const std::vector<float> uv = ReadFloats(model, it->second, 2, "TEXCOORD_0", path);
    if (uv.size() == 2 * n) {
      for (size_t i = 0; i < n; ++i) part.uvs[i] = {uv[2 * i], uv[2 * i + 1]};
    }
  }
  Eigen::Vector3f base_color = Eigen::Vector3f::Ones();
  if (prim.material >= 0 && static_cast<size_t>(prim.material) < model.materials.size()) {
    const auto& f =
        model.materials[static_cast<size_t>(prim.material)].pbrMetallicRoughness.baseColorFactor;
    if (f.size() >= 3)
      base_color = Eigen::Vector3f(static_cast<float>(f[0]), static_cast<float>(f[1]),
                                   static_cast<float>(f[2]));
  }
  part.colors.assign(n, base_color);
  if (auto it = prim.attributes.find("COLOR_0"); it != prim.attributes.end()) {
    const std::vector<float> col = ReadFloats(model, it->second, 3, "COLOR_0", path);
    if (col.size() == 3 * n) {
      for (size_t i = 0; i < n; ++i) {
        part.colors[i] =
            base_color.cwiseProduct(Eigen::Vector3f(col[3 * i], col[3 * i + 1], col[3 * i + 2]));
      }
    }
  }
  if (prim.indices >= 0) {
    part.indices = ReadIndices(model, prim.indices, path);
  } else {
    part.indices.resize(n);
    for (size_t i = 0; i < n; ++i) part.indices[i] = static_cast<uint32_t>(i);
  }
  part.indices.resize(part.indices.size() / 3 * 3);
  for (uint32_t i : part.indices) {
    if (i >= n)
      throw InputError(fmt::format("{}: glTF index {} out of range ({} vertices)", path, i, n));
  }
  // A transform with negative determinant mirrors the mesh and flips winding.
  if (linear.determinant() < 0.0) {
    for (size_t t = 0; t + 2 < part.indices.size(); t += 3) {
      std::swap(part.indices[t + 1], part.indices[t + 2]);
    }
  }
  if (!has_normals) ComputeFlatNormals(part);
  out.Append(part);
}

void VisitNode(const tinygltf::Model& model, int node_index, const Eigen::Matrix4d& parent,
               const std::string& path, MeshData& out, int depth) {
  if (depth > 64) throw InputError(fmt::format("{}: glTF node hierarchy too deep (cycle?)", path));
  const tinygltf::Node& node = model.nodes.at(static_cast<size_t>(node_index));
  const Eigen::Matrix4d world = parent * NodeTransform(node);
  if (node.mesh >= 0) {
    for (const tinygltf::Primitive& prim :
         model.meshes.at(static_cast<size_t>(node.mesh)).primitives) {
      AppendPrimitive(model, prim, world, path, out);
    }
  }
  for (int child : node.children) VisitNode(model, child, world, path, out, depth + 1);
}

// glTF files and the buffers they name are read whole; a vehicle model is a
// few MiB.
constexpr uint64_t kMaxModelBytes = uint64_t{256} << 20;

uint32_t LittleEndian32(const std::string& bytes, size_t at) {
  uint32_t v = 0;
  for (int k = 3; k >= 0; --k) v = (v << 8) | static_cast<unsigned char>(bytes[at + k]);
  return v;
}

// The 12-byte GLB header: magic "glTF", version 2, total length = file size.
void CheckGlbHeader(const std::string& path, uint64_t size) {
  const std::string header = ReadFilePrefix(path, 12);
  if (header.size() < 12 || header.compare(0, 4, "glTF") != 0) {
    std::string start;
    for (size_t i = 0; i < std::min<size_t>(header.size(), 4); ++i) {
      start += fmt::format("{:02x}", static_cast<unsigned char>(header[i]));
    }
    throw InputError(fmt::format(
        "{}: expected a binary glTF file (starting with the bytes \"glTF\"), found {} bytes "
        "starting with 0x{}",
        path, size, start.empty() ? "(none)" : start));
  }
  const uint32_t version = LittleEndian32(header, 4);
  const uint32_t length = LittleEndian32(header, 8);
  if (version != 2) {
    throw InputError(fmt::format("{}: expected glTF version 2, found version {}", path, version));
  }
  if (length != size) {
    throw InputError(fmt::format(
        "{}: the GLB header gives a length of {} bytes but the file has {} (truncated?)", path,
        length, size));
  }
}

// The chunk layout after a good header, once `size` is known to be at most
// kMaxModelBytes.
void CheckGlbChunks(const std::string& path, uint64_t size) {
  // The chunk layout, checked here because tinygltf 2.7 leaves out the BIN
  // chunk's 8-byte header when it compares the chunk's length with the file's
  // and then copies up to 8 bytes past the end of what it read (found by
  // fuzz_gltf). A JSON chunk, then optionally one BIN chunk, each inside the
  // file.
  if (size < 20) {
    throw InputError(
        fmt::format("{}: expected a GLB header and a JSON chunk header (20 bytes), found {} bytes",
                    path, size));
  }
  // (A file that shrank since `size` was taken reads short: a truncated file.)
  auto prefix = [&](size_t count) {
    std::string bytes = ReadFilePrefix(path, count);
    if (bytes.size() < count) {
      throw InputError(fmt::format("{}: the file changed while being read (truncated?)", path));
    }
    return bytes;
  };
  const uint64_t json_length = LittleEndian32(prefix(20), 12);
  const uint64_t json_end = 20 + json_length;
  if (json_end > size) {
    throw InputError(
        fmt::format("{}: the JSON chunk claims {} bytes but only {} follow its header (truncated?)",
                    path, json_length, size - 20));
  }
  if (json_end == size) return;  // no BIN chunk
  if (json_end + 8 > size) {
    throw InputError(
        fmt::format("{}: expected an 8-byte BIN chunk header after the JSON chunk, found {} bytes",
                    path, size - json_end));
  }
  const uint64_t bin_length = LittleEndian32(prefix(json_end + 8), json_end);
  if (json_end + 8 + bin_length > size) {
    throw InputError(
        fmt::format("{}: the BIN chunk claims {} bytes but only {} follow its header (truncated?)",
                    path, bin_length, size - json_end - 8));
  }
}

// tinygltf's file reader for buffers named by URI, with our checks.
bool ReadBufferFile(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                    void* /*user_data*/) {
  try {
    const std::string bytes = ReadInputFile(path, "a glTF buffer", kMaxModelBytes);
    out->assign(bytes.begin(), bytes.end());
    return true;
  } catch (const InputError& e) {
    if (err != nullptr) *err += e.what();
    return false;
  }
}

}  // namespace

MeshData LoadGltf(const std::string& path, uint64_t size) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string err;
  std::string warn;
  const bool binary = std::filesystem::path(path).extension() == ".glb" ||
                      std::filesystem::path(path).extension() == ".GLB";
  // tinygltf reads a file whole before it looks at it: check its size and, for
  // a .glb, its 12-byte header first, so a wrong file costs nothing.
  if (binary) CheckGlbHeader(path, size);
  if (size > kMaxModelBytes) {
    throw InputError(fmt::format("{}: expected a glTF model of at most {} MiB, found {:.1f} MiB",
                                 path, kMaxModelBytes >> 20, size / 1048576.0));
  }
  if (binary) CheckGlbChunks(path, size);
  // Buffers a .gltf names by URI go through the same checks (a URI may name a
  // device or a huge file).
  tinygltf::FsCallbacks callbacks{&tinygltf::FileExists, &tinygltf::ExpandFilePath, &ReadBufferFile,
                                  &tinygltf::WriteWholeFile, nullptr};
  loader.SetFsCallbacks(callbacks);
  bool ok = false;
  try {
    ok = binary ? loader.LoadBinaryFromFile(&model, &err, &warn, path)
                : loader.LoadASCIIFromFile(&model, &err, &warn, path);
  } catch (const std::exception& e) {
    throw InputError(fmt::format("{}: cannot read glTF: {}", path, e.what()));
  }
  if (!ok) throw InputError(fmt::format("{}: cannot read glTF: {}", path, err));
  MeshData mesh;
  try {
    if (!model.scenes.empty()) {
      const size_t scene = model.defaultScene >= 0 ? static_cast<size_t>(model.defaultScene) : 0;
      for (int node : model.scenes.at(scene).nodes) {
        VisitNode(model, node, Eigen::Matrix4d::Identity(), path, mesh, 0);
      }
    } else {
      for (const tinygltf::Mesh& m : model.meshes) {
        for (const tinygltf::Primitive& prim : m.primitives) {
          AppendPrimitive(model, prim, Eigen::Matrix4d::Identity(), path, mesh);
        }
      }
    }
  } catch (const std::out_of_range&) {
    throw InputError(
        fmt::format("{}: glTF refers to a missing node, mesh, accessor or buffer", path));
  }
  if (mesh.empty()) throw InputError(fmt::format("{}: glTF file holds no triangles", path));
  return mesh;
}

}  // namespace internal

namespace {

template <typename T>
int AddBufferData(tinygltf::Model& model, const std::vector<T>& data, int target) {
  tinygltf::Buffer& buffer = model.buffers[0];
  // Keep every view 4-byte aligned as the spec requires.
  while (buffer.data.size() % 4 != 0) buffer.data.push_back(0);
  tinygltf::BufferView view;
  view.buffer = 0;
  view.byteOffset = buffer.data.size();
  view.byteLength = data.size() * sizeof(T);
  view.target = target;
  const auto* bytes = reinterpret_cast<const unsigned char*>(data.data());
  buffer.data.insert(buffer.data.end(), bytes, bytes + view.byteLength);
  model.bufferViews.push_back(view);
  return static_cast<int>(model.bufferViews.size() - 1);
}

int AddAccessor(tinygltf::Model& model, int view, int component_type, int type, size_t count) {
  tinygltf::Accessor acc;
  acc.bufferView = view;
  acc.componentType = component_type;
  acc.type = type;
  acc.count = count;
  model.accessors.push_back(acc);
  return static_cast<int>(model.accessors.size() - 1);
}

}  // namespace

void WriteGlb(const MeshData& mesh, const std::string& path) {
  mesh.Validate(path);
  tinygltf::Model model;
  model.asset.version = "2.0";
  model.asset.generator = "HCPF Bench (hcpf::renderer::WriteGlb)";
  model.buffers.resize(1);
  const size_t n = mesh.vertex_count();
  std::vector<float> pos, nrm, uv, col;
  pos.reserve(3 * n);
  nrm.reserve(3 * n);
  uv.reserve(2 * n);
  col.reserve(3 * n);
  Eigen::Vector3f lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
  Eigen::Vector3f hi = -lo;
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3f p = internal::ToYUp(mesh.positions[i]);
    const Eigen::Vector3f q = internal::ToYUp(mesh.normals[i]);
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
    pos.insert(pos.end(), {p.x(), p.y(), p.z()});
    nrm.insert(nrm.end(), {q.x(), q.y(), q.z()});
    uv.insert(uv.end(), {mesh.uvs[i].x(), mesh.uvs[i].y()});
    col.insert(col.end(), {mesh.colors[i].x(), mesh.colors[i].y(), mesh.colors[i].z()});
  }
  tinygltf::Primitive prim;
  prim.mode = TINYGLTF_MODE_TRIANGLES;
  const int pos_acc = AddAccessor(model, AddBufferData(model, pos, TINYGLTF_TARGET_ARRAY_BUFFER),
                                  TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n);
  model.accessors[static_cast<size_t>(pos_acc)].minValues = {lo.x(), lo.y(), lo.z()};
  model.accessors[static_cast<size_t>(pos_acc)].maxValues = {hi.x(), hi.y(), hi.z()};
  prim.attributes["POSITION"] = pos_acc;
  prim.attributes["NORMAL"] =
      AddAccessor(model, AddBufferData(model, nrm, TINYGLTF_TARGET_ARRAY_BUFFER),
                  TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n);
  prim.attributes["TEXCOORD_0"] =
      AddAccessor(model, AddBufferData(model, uv, TINYGLTF_TARGET_ARRAY_BUFFER),
                  TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC2, n);
  prim.attributes["COLOR_0"] =
      AddAccessor(model, AddBufferData(model, col, TINYGLTF_TARGET_ARRAY_BUFFER),
                  TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n);
  prim.indices =
      AddAccessor(model, AddBufferData(model, mesh.indices, TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER),
                  TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT, TINYGLTF_TYPE_SCALAR, mesh.indices.size());
  tinygltf::Material material;
  material.name = "vertex_colour";
  material.pbrMetallicRoughness.baseColorFactor = {1.0, 1.0, 1.0, 1.0};
  material.pbrMetallicRoughness.metallicFactor = 0.0;
  material.pbrMetallicRoughness.roughnessFactor = 0.9;
  model.materials.push_back(material);
  prim.material = 0;
  tinygltf::Mesh gltf_mesh;
  gltf_mesh.name = std::filesystem::path(path).stem().string();
  gltf_mesh.primitives.push_back(prim);
  model.meshes.push_back(gltf_mesh);
  tinygltf::Node node;
  node.mesh = 0;
  node.name = gltf_mesh.name;
  model.nodes.push_back(node);
  tinygltf::Scene scene;
  scene.nodes.push_back(0);
  model.scenes.push_back(scene);
  model.defaultScene = 0;
  tinygltf::TinyGLTF writer;
  if (!writer.WriteGltfSceneToFile(&model, path, /*embedImages=*/true, /*embedBuffers=*/true,
                                   /*prettyPrint=*/false, /*writeBinary=*/true)) {
    throw RunError(fmt::format("{}: cannot write GLB file", path));
  }
}

}  // namespace hcpf::renderer
