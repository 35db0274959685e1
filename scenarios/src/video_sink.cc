#include "video_sink.h"

#include <dlfcn.h>
#include <fmt/format.h>

#include <filesystem>
#include <mutex>

#include "hcpf/core/error.h"

namespace hcpf::scenarios {

using OpenFn = VideoSink* (*)(const char* path, double fps, int width, int height, char* error,
                              int error_size);

namespace {

// The plugin next to the executable (an installed layout), else where the
// build put it.
OpenFn LoadPlugin() {
  static std::once_flag once;
  static OpenFn open = nullptr;
  static std::string failure;
  std::call_once(once, [] {
    std::error_code ec;
    const auto exe_dir = std::filesystem::read_symlink("/proc/self/exe", ec).parent_path();
    std::string tried;
    for (const std::string& candidate :
         {(exe_dir / "libhcpf_video.so").string(), std::string(HCPF_VIDEO_PLUGIN_PATH)}) {
      void* handle = ::dlopen(candidate.c_str(), RTLD_NOW | RTLD_LOCAL);
      if (handle == nullptr) {
        tried += fmt::format("\n  {}: {}", candidate, ::dlerror());
        continue;
      }
      open = reinterpret_cast<OpenFn>(::dlsym(handle, "hcpf_open_video_sink"));
      if (open != nullptr) return;
      tried += fmt::format("\n  {}: no hcpf_open_video_sink", candidate);
    }
    failure = "cannot load the video plugin libhcpf_video.so:" + tried;
  });
  if (open == nullptr) throw RunError(failure);
  return open;
}

}  // namespace

std::unique_ptr<VideoSink> OpenVideoSink(const std::string& path, double fps, int width, int height) {
  const OpenFn open = LoadPlugin();
  char error[512] = {};
  VideoSink* sink = open(path.c_str(), fps, width, height, error, sizeof(error));
  if (sink == nullptr) throw RunError(fmt::format("cannot write video {}: {}", path, error));
  return std::unique_ptr<VideoSink>(sink);
}

}  // namespace hcpf::scenarios
