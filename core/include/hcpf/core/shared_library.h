#pragma once
// Loading a project library at run time (dlopen): the command library
// libhcpf_cli.so and the video plugin libhcpf_video.so.

#include <string>
#include <string_view>

namespace hcpf {

// Opens `file_name` from the running executable's folder (an installed
// layout), else `build_path` (where the build put it; anything dlopen takes),
// and returns its `symbol`. Returns nullptr when neither gives the symbol and
// sets *tried to one "\n  <path>: <reason>" line per place tried. The library
// stays loaded for the life of the process.
void* LoadSymbolNextToExecutable(std::string_view file_name, const std::string& build_path,
                                 const char* symbol, std::string* tried);

}  // namespace hcpf
