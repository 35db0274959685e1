#include "hcpf/core/text_file.h"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <fstream>

#include "hcpf/core/error.h"

namespace hcpf {

void WriteTextFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw RunError(fmt::format("cannot write {}: {}", path, std::strerror(errno)));
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  out.close();
  if (!out) throw RunError(fmt::format("writing {} failed: {}", path, std::strerror(errno)));
}

}  // namespace hcpf
