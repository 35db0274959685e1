// libFuzzer target `gltf`: a binary glTF (.glb) file -> MeshData (LoadMesh,
// through tinygltf and renderer/src/mesh_gltf.cc), then MeshData::IsClosed on
// what loaded, as the renderer asks of every mesh it uploads. LoadMesh takes
// a path: the input is written to a scratch file first.

#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "hcpf/renderer/mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const hcpf::fuzz::ScratchDir scratch;
  const std::string path = scratch.Write(data, size, ".glb");
  hcpf::fuzz::ExpectInputErrorOnly([&] {
    const hcpf::renderer::MeshData mesh = hcpf::renderer::LoadMesh(path);
    static_cast<void>(mesh.IsClosed());
  });
  return 0;
}
