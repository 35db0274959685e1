// libFuzzer target `assimp`: an .obj, .ply or .stl file -> MeshData
// (LoadMesh, through Debian's libassimp and renderer/src/mesh_assimp.cc). The
// first byte picks the extension (so the importer): 0 .obj, 1 .ply, 2 .stl,
// modulo 3; the rest is the file, written to a scratch file because LoadMesh
// takes a path. MeshData::IsClosed runs on what loaded, as the renderer asks
// of every mesh it uploads.
//
// libassimp 5.2.5's PLY reader hangs, crashes and aborts on small malformed
// files (docs/fuzzing.md, "Third-party problems"), so LoadMesh refuses .ply
// models before assimp sees them; PLY inputs check that refusal
// (fuzz/regressions/assimp/*.ply). Its leaks are suppressed in fuzz/lsan.supp.

#include <cstddef>
#include <cstdint>
#include <string>

#include "fuzz_support.h"
#include "hcpf/renderer/mesh.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const hcpf::fuzz::ScratchDir scratch;
  if (size < 1) return 0;
  static const char* const kExtensions[] = {".obj", ".ply", ".stl"};
  const int format = data[0] % 3;
  const std::string path = scratch.Write(data + 1, size - 1, kExtensions[format]);
  hcpf::fuzz::ExpectInputErrorOnly([&] {
    const hcpf::renderer::MeshData mesh = hcpf::renderer::LoadMesh(path);
    static_cast<void>(mesh.IsClosed());
  });
  return 0;
}
