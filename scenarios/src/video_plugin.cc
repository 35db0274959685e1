// libhcpf_video.so: the one place that links FFmpeg's libraries (see video_sink.h).
//
// Encodes with libavcodec and muxes with libavformat directly rather than
// through OpenCV's VideoWriter, which sets neither the encoder's thread count
// (libx264 splits frames by the machine's core count, and its bytes change
// with it: measured, one core against two) nor the MP4 flags a browser
// wants. Here: H.264 by libx264 on one thread, so one FFmpeg gives the same
// bytes on any machine; a key frame every second, so a browser seeks to any
// frame decoding at most one second of video; the index ("moov") at the
// front of the file (faststart), so playback starts before the whole file is
// read. MPEG-4 Part 2 by FFmpeg's own encoder only where libx264 is absent.

#include <cmath>
#include <cstdio>
#include <memory>
#include <mutex>
#include <opencv2/core.hpp>
#include <string>

#include "video_sink.h"

extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/imgutils.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

namespace {

std::string AvError(int code) {
  char text[AV_ERROR_MAX_STRING_SIZE] = {};
  av_strerror(code, text, sizeof(text));
  return text;
}

class FfmpegVideoSink final : public hcpf::scenarios::VideoSink {
 public:
  ~FfmpegVideoSink() override {
    Close();
    Free();
  }

  // Opens `path`; "" on success, else why not. `mpeg4`: MPEG-4 Part 2 even
  // where libx264 is present.
  std::string Open(const char* path, double fps, int width, int height, bool mpeg4) {
    width_ = width;
    height_ = height;
    // 4:2:0 chroma needs even sides: an odd side gains one row or column,
    // a copy of the last.
    const int coded_width = width + (width & 1);
    const int coded_height = height + (height & 1);
    int err = avformat_alloc_output_context2(&format_, nullptr, "mp4", path);
    if (err < 0 || format_ == nullptr) return "cannot make an MP4 muxer: " + AvError(err);
    const AVCodec* codec = mpeg4 ? nullptr : avcodec_find_encoder_by_name("libx264");
    h264_ = codec != nullptr;
    if (!h264_) codec = avcodec_find_encoder(AV_CODEC_ID_MPEG4);
    if (codec == nullptr) return "this FFmpeg has neither libx264 nor an MPEG-4 Part 2 encoder";
    stream_ = avformat_new_stream(format_, nullptr);
    context_ = avcodec_alloc_context3(codec);
    frame_ = av_frame_alloc();
    packet_ = av_packet_alloc();
    if (stream_ == nullptr || context_ == nullptr || frame_ == nullptr || packet_ == nullptr) {
      return "out of memory";
    }
    context_->width = coded_width;
    context_->height = coded_height;
    context_->pix_fmt = AV_PIX_FMT_YUV420P;
    // The frame rate as a rational (29.97 as 2997/100, 12.5 as 25/2); one
    // tick a frame. At most 65535 either way: MPEG-4 Part 2 refuses more.
    const AVRational rate = av_d2q(fps, 65535);
    context_->framerate = rate;
    context_->time_base = av_inv_q(rate);
    context_->gop_size = std::max(1, static_cast<int>(std::lround(fps)));
    // One thread: libx264 left at 0 ("auto") starts threads by the cores
    // this thread may use, and its bytes change with them
    // (Overlay.SameBytesWhateverTheCoreCount).
    context_->thread_count = 1;
    // Said in the stream so that players do not guess: the frames are sRGB
    // (BT.709 primaries, the sRGB transfer curve), converted below by
    // swscale's BT.601 matrix to limited-range YUV.
    context_->colorspace = AVCOL_SPC_SMPTE170M;
    context_->color_primaries = AVCOL_PRI_BT709;
    context_->color_trc = AVCOL_TRC_IEC61966_2_1;
    context_->color_range = AVCOL_RANGE_MPEG;
    if (!h264_) {
      // A fixed quantiser (FFmpeg's default is a 200 kbit/s target).
      context_->flags |= AV_CODEC_FLAG_QSCALE;
      context_->global_quality = FF_QP2LAMBDA * 3;
    }
    if (format_->oformat->flags & AVFMT_GLOBALHEADER) {
      context_->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
    }
    AVDictionary* codec_options = nullptr;
    if (h264_) {
      // CRF 23 (libx264's default quality) at preset veryfast, on one
      // thread: 240 frames of 640 x 480 in 0.83 s against 1.80 s at preset
      // medium, and a smaller file (0.49 against 0.57 MB; crossing, rendered).
      av_dict_set(&codec_options, "preset", "veryfast", 0);
    }
    err = avcodec_open2(context_, codec, &codec_options);
    av_dict_free(&codec_options);
    if (err < 0) return std::string("cannot open the ") + codec->name + " encoder: " + AvError(err);
    err = avcodec_parameters_from_context(stream_->codecpar, context_);
    if (err < 0) return "cannot describe the stream: " + AvError(err);
    stream_->time_base = context_->time_base;
    stream_->avg_frame_rate = rate;
    err = avio_open(&format_->pb, path, AVIO_FLAG_WRITE);
    if (err < 0) return "cannot create the file: " + AvError(err);
    created_ = true;
    AVDictionary* muxer_options = nullptr;
    av_dict_set(&muxer_options, "movflags", "+faststart", 0);
    err = avformat_write_header(format_, &muxer_options);
    av_dict_free(&muxer_options);
    if (err < 0) return "cannot write the MP4 header: " + AvError(err);
    header_written_ = true;
    frame_->format = AV_PIX_FMT_YUV420P;
    frame_->width = coded_width;
    frame_->height = coded_height;
    err = av_frame_get_buffer(frame_, 0);
    if (err < 0) return "cannot allocate a frame: " + AvError(err);
    // Bit-exact conversion (swscale's own flag; SWS_ACCURATE_RND also turns
    // off its inexact BGR-to-YUV shortcut).
    scale_ = sws_getContext(coded_width, coded_height, AV_PIX_FMT_BGR24, coded_width, coded_height,
                            AV_PIX_FMT_YUV420P,
                            SWS_BICUBIC | SWS_ACCURATE_RND | SWS_BITEXACT | SWS_FULL_CHR_H_INP,
                            nullptr, nullptr, nullptr);
    if (scale_ == nullptr) return "cannot make the BGR to YUV converter";
    return {};
  }

  void Write(const cv::Mat& bgr) override {
    if (!error_.empty() || closed_) return;
    if (bgr.type() != CV_8UC3 || bgr.cols != width_ || bgr.rows != height_) {
      error_ = "a frame of another size or type than the video's";
      return;
    }
    cv::Mat coded = bgr;
    if (context_->width != width_ || context_->height != height_) {
      cv::copyMakeBorder(bgr, padded_, 0, context_->height - height_, 0, context_->width - width_,
                         cv::BORDER_REPLICATE);
      coded = padded_;
    } else if (!bgr.isContinuous()) {
      coded = bgr.clone();
    }
    if (const int err = av_frame_make_writable(frame_); err < 0) {
      error_ = "cannot reuse the frame buffer: " + AvError(err);
      return;
    }
    const uint8_t* source[] = {coded.data};
    const int stride[] = {static_cast<int>(coded.step[0])};
    sws_scale(scale_, source, stride, 0, coded.rows, frame_->data, frame_->linesize);
    frame_->pts = next_pts_++;
    Encode(frame_);
  }

  void Close() override {
    if (closed_ || format_ == nullptr) return;
    closed_ = true;
    // After a failure the file is not finished (the caller reports the
    // failure and the run's folder is not kept).
    if (header_written_ && error_.empty()) {
      if (context_ != nullptr && avcodec_is_open(context_)) Encode(nullptr);  // flush
      if (const int err = av_write_trailer(format_); err < 0 && error_.empty()) {
        error_ = "cannot finish the file: " + AvError(err);
      }
    }
    if (format_->pb != nullptr) {
      if (const int err = avio_closep(&format_->pb); err < 0 && error_.empty()) {
        error_ = "cannot close the file: " + AvError(err);
      }
    }
  }

  const char* fourcc() const override { return h264_ ? "avc1" : "mp4v"; }
  const char* error() const override { return error_.c_str(); }
  bool created() const { return created_; }
  // Closes the file without finishing it (after a failed Open).
  void Abandon() {
    closed_ = true;
    if (format_ != nullptr && format_->pb != nullptr) avio_closep(&format_->pb);
  }

 private:
  // Sends `frame` (null: the end) and writes what the encoder returns; the
  // first failure is kept in error_ (callers stop at it).
  void Encode(AVFrame* frame) {
    if (const int err = avcodec_send_frame(context_, frame); err < 0) {
      error_ = "the encoder refused a frame: " + AvError(err);
      return;
    }
    while (true) {
      int err = avcodec_receive_packet(context_, packet_);
      if (err == AVERROR(EAGAIN) || err == AVERROR_EOF) return;
      if (err < 0) {
        error_ = "the encoder failed: " + AvError(err);
        return;
      }
      av_packet_rescale_ts(packet_, context_->time_base, stream_->time_base);
      packet_->stream_index = stream_->index;
      err = av_interleaved_write_frame(format_, packet_);
      if (err < 0) {
        error_ = "cannot write to the file: " + AvError(err);
        return;
      }
    }
  }

  void Free() {
    sws_freeContext(scale_);
    av_packet_free(&packet_);
    av_frame_free(&frame_);
    avcodec_free_context(&context_);
    if (format_ != nullptr) {
      if (format_->pb != nullptr) avio_closep(&format_->pb);
      avformat_free_context(format_);
      format_ = nullptr;
    }
  }

  AVFormatContext* format_ = nullptr;
  AVStream* stream_ = nullptr;
  AVCodecContext* context_ = nullptr;
  AVFrame* frame_ = nullptr;
  AVPacket* packet_ = nullptr;
  SwsContext* scale_ = nullptr;
  cv::Mat padded_;
  bool h264_ = true;  // libx264; else MPEG-4 Part 2
  int width_ = 0, height_ = 0;
  int64_t next_pts_ = 0;
  std::string error_;  // the first failure after Open; "" while none
  bool header_written_ = false;
  bool created_ = false;
  bool closed_ = false;
};

}  // namespace

extern "C" __attribute__((visibility("default"))) hcpf::scenarios::VideoSink*
hcpf_open_video_sink_v2(const char* path, double fps, int width, int height, int mpeg4, char* error,
                        int error_size) {
  // FFmpeg's own messages (libx264's settings and statistics, one block per
  // video) would interleave on stderr in a sweep; failures come back as
  // this sink's errors.
  static std::once_flag quiet;
  std::call_once(quiet, [] { av_log_set_level(AV_LOG_ERROR); });
  std::unique_ptr<FfmpegVideoSink> sink;
  std::string why;
  try {
    sink = std::make_unique<FfmpegVideoSink>();
    why = sink->Open(path, fps, width, height, mpeg4 != 0);
    if (why.empty()) return sink.release();
  } catch (const std::exception& e) {
    why = e.what();
  }
  // The file a failed Open created is closed unfinished and removed (never
  // a path it did not create).
  if (sink != nullptr && sink->created()) {
    sink->Abandon();
    std::remove(path);
  }
  std::snprintf(error, static_cast<size_t>(error_size), "FFmpeg, for %dx%d at %g fps: %s", width,
                height, fps, why.c_str());
  return nullptr;
}
