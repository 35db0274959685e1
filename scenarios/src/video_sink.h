#pragma once
// Video files through FFmpeg's libraries, loaded as a plugin
// (libhcpf_video.so, built from video_plugin.cc) on first use. Linking
// FFmpeg into `hcpf` would load it and its many shared libraries in every
// process (~40 ms before main(), measured with opencv_videoio, e.g. for
// `hcpf score`); only runs that write a video pay for it now.

#include <memory>
#include <opencv2/core.hpp>
#include <string>

namespace hcpf::scenarios {

class VideoSink {
 public:
  virtual ~VideoSink() = default;
  // Appends one 8-bit BGR frame of the size the sink was opened with.
  virtual void Write(const cv::Mat& bgr) = 0;
  // Finishes the file.
  virtual void Close() = 0;
  // The codec it writes: "avc1" (H.264) or "mp4v" (MPEG-4 Part 2).
  virtual const char* fourcc() const = 0;
  // Why a Write or Close failed (the first failure; later frames are
  // dropped), "" when none did.
  virtual const char* error() const = 0;
};

// Which encoder a sink uses.
enum class VideoCodec {
  kH264WherePresent,  // libx264, else MPEG-4 Part 2 (what runs write)
  kMpeg4Part2,        // FFmpeg's own MPEG-4 Part 2 encoder (the fallback, for its tests)
};

// Opens `path` for H.264 (fourcc avc1, libx264) at `fps`, or for MPEG-4
// Part 2 (mp4v) when FFmpeg has no libx264 or `codec` asks for it; throws
// RunError when the plugin cannot be loaded or the encoder or file cannot
// be opened.
std::unique_ptr<VideoSink> OpenVideoSink(const std::string& path, double fps, int width, int height,
                                         VideoCodec codec = VideoCodec::kH264WherePresent);

}  // namespace hcpf::scenarios
