#pragma once
// Video files through OpenCV's VideoWriter, loaded as a plugin
// (libhcpf_video.so, built from video_plugin.cc) on first use. Linking
// opencv_videoio into `hcpf` would load FFmpeg and ~100 other shared
// libraries in every process (~40 ms before main(), e.g. for `hcpf score`);
// only runs that write a video pay for it now.

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
};

// Opens `path` for MPEG-4 Part 2 (fourcc mp4v) at `fps`; throws RunError when
// the plugin cannot be loaded or the writer cannot be opened.
std::unique_ptr<VideoSink> OpenVideoSink(const std::string& path, double fps, int width,
                                         int height);

}  // namespace hcpf::scenarios
