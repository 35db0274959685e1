#include "video_sink.h"

#include <fmt/format.h>

#include <mutex>

#include "hcpf/core/error.h"
#include "hcpf/core/shared_library.h"

namespace hcpf::scenarios {

// The plugin's entry point; `mpeg4` is 1 for VideoCodec::kMpeg4Part2.
using OpenFn = VideoSink* (*)(const char* path, double fps, int width, int height, int mpeg4,
                              char* error, int error_size);

namespace {

// The plugin next to the executable (an installed layout), else where the
// build put it.
OpenFn LoadPlugin() {
  static std::once_flag once;
  static OpenFn open = nullptr;
  static std::string failure;
  std::call_once(once, [] {
    std::string tried;
    open = reinterpret_cast<OpenFn>(LoadSymbolNextToExecutable(
        "libhcpf_video.so", HCPF_VIDEO_PLUGIN_PATH, "hcpf_open_video_sink_v2", &tried));
    if (open == nullptr) failure = "cannot load the video plugin libhcpf_video.so:" + tried;
  });
  if (open == nullptr) throw RunError(failure);
  return open;
}

}  // namespace

std::unique_ptr<VideoSink> OpenVideoSink(const std::string& path, double fps, int width, int height,
                                         VideoCodec codec) {
  const OpenFn open = LoadPlugin();
  char error[512] = {};
  VideoSink* sink = open(path.c_str(), fps, width, height, codec == VideoCodec::kMpeg4Part2 ? 1 : 0,
                         error, sizeof(error));
  if (sink == nullptr) throw RunError(fmt::format("cannot write video {}: {}", path, error));
  return std::unique_ptr<VideoSink>(sink);
}

}  // namespace hcpf::scenarios
