// libFuzzer target `gltf`: a binary glTF (.glb) file -> MeshData (LoadMesh,
// through tinygltf and renderer/src/mesh_gltf.cc). LoadMesh takes a path: the
// input is written to a scratch file first.

#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "hcpf/renderer/mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const hcpf::fuzz::ScratchDir scratch;
  const std::string path = scratch.Write(data, size, ".glb");
  hcpf::fuzz::ExpectInputErrorOnly([&] { hcpf::renderer::LoadMesh(path); });
  return 0;
}
