#include "hcpf/core/shared_library.h"

#include <dlfcn.h>

#include <filesystem>

namespace hcpf {

void* LoadSymbolNextToExecutable(std::string_view file_name, const std::string& build_path,
                                 const char* symbol, std::string* tried) {
  std::error_code ec;
  const auto exe_dir = std::filesystem::read_symlink("/proc/self/exe", ec).parent_path();
  tried->clear();
  for (const std::string& path : {(exe_dir / file_name).string(), build_path}) {
    void* handle = ::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (handle == nullptr) {
      *tried += "\n  " + path + ": " + ::dlerror();
      continue;
    }
    if (void* address = ::dlsym(handle, symbol); address != nullptr) return address;
    *tried += "\n  " + path + ": no " + symbol;
  }
  return nullptr;
}

}  // namespace hcpf
