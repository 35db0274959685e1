// libhcpf_video.so: the one place that links opencv_videoio (see video_sink.h).

#include <cstdio>
#include <opencv2/videoio.hpp>

#include "video_sink.h"

namespace {

class OpenCvVideoSink final : public hcpf::scenarios::VideoSink {
 public:
  explicit OpenCvVideoSink(cv::VideoWriter writer) : writer_(std::move(writer)) {}
  ~OpenCvVideoSink() override { Close(); }
  void Write(const cv::Mat& bgr) override { writer_.write(bgr); }
  void Close() override {
    if (writer_.isOpened()) writer_.release();
  }

 private:
  cv::VideoWriter writer_;
};

}  // namespace

extern "C" __attribute__((visibility("default"))) hcpf::scenarios::VideoSink* hcpf_open_video_sink(
    const char* path, double fps, int width, int height, char* error, int error_size) {
  try {
    const int fourcc = cv::VideoWriter::fourcc('m', 'p', '4', 'v');
    // FFmpeg first (real MPEG-4 in an .mp4 container), then whatever OpenCV has.
    cv::VideoWriter writer(path, cv::CAP_FFMPEG, fourcc, fps, cv::Size(width, height), true);
    if (!writer.isOpened()) writer.open(path, fourcc, fps, cv::Size(width, height), true);
    if (!writer.isOpened()) {
      std::snprintf(error, static_cast<size_t>(error_size),
                    "OpenCV's VideoWriter cannot open it for %dx%d at %g fps (FFmpeg's MPEG-4 "
                    "encoder refused it, or OpenCV has no FFmpeg backend)",
                    width, height, fps);
      return nullptr;
    }
    return new OpenCvVideoSink(std::move(writer));
  } catch (const std::exception& e) {
    std::snprintf(error, static_cast<size_t>(error_size), "%s", e.what());
    return nullptr;
  }
}
