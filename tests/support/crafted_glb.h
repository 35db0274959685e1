#pragma once
// Writes small binary glTF (GLB) files byte by byte, independently of the
// library under test, so tests can hand the loader files with hostile
// accessor fields (the bad-input campaign of issue 15, item 1).

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace hcpf::testing {

// One triangle: a 36-byte buffer of three float VEC3 positions, one buffer
// view over all of it, and a POSITION accessor whose `count` and `byteOffset`
// the caller picks (written as JSON integers, so any 64-bit value fits).
// With count 3 and byteOffset 0 the file is a valid one-triangle model.
// `claimed_bin_bytes` is what the BIN chunk header and the buffer's
// byteLength say; more than 36 makes a chunk that runs past the file's end.
inline void WriteTriangleGlb(const std::filesystem::path& path, uint64_t count,
                             uint64_t byte_offset, uint32_t claimed_bin_bytes = 36) {
  const float positions[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::string json =
      "{\"asset\":{\"version\":\"2.0\"},\"buffers\":[{\"byteLength\":" +
      std::to_string(claimed_bin_bytes) +
      "}],"
      "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":36}],"
      "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"type\":\"VEC3\",\"count\":" +
      std::to_string(count) + ",\"byteOffset\":" + std::to_string(byte_offset) +
      "}],\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0}}]}],"
      "\"nodes\":[{\"mesh\":0}],\"scenes\":[{\"nodes\":[0]}],\"scene\":0}";
  while (json.size() % 4 != 0) json += ' ';  // chunks are 4-byte aligned
  const uint32_t bin_bytes = sizeof(positions);
  std::vector<char> out;
  auto u32 = [&out](uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
  };
  u32(0x46546C67);  // "glTF"
  u32(2);           // version
  u32(static_cast<uint32_t>(12 + 8 + json.size() + 8 + bin_bytes));
  u32(static_cast<uint32_t>(json.size()));
  u32(0x4E4F534A);  // "JSON"
  out.insert(out.end(), json.begin(), json.end());
  u32(claimed_bin_bytes);
  u32(0x004E4942);  // "BIN\0"
  const char* bin = reinterpret_cast<const char*>(positions);
  out.insert(out.end(), bin, bin + bin_bytes);
  std::ofstream(path, std::ios::binary).write(out.data(), static_cast<std::streamsize>(out.size()));
}

}  // namespace hcpf::testing
