#include "hcpf/scenarios/overlay.h"

#include <fmt/format.h>

#include <map>
#include <opencv2/imgproc.hpp>

#include "hcpf/core/check.h"
#include "hcpf/core/error.h"
#include "video_sink.h"

namespace hcpf::scenarios {

namespace {

// Filter colours (BGR), by filter id: none yellow, the detections' colour.
cv::Scalar FilterColour(int64_t id) {
  static const cv::Scalar kColours[] = {{255, 128, 0}, {255, 0, 200},   {0, 255, 128},
                                        {0, 128, 255}, {128, 128, 255}, {255, 255, 0},
                                        {200, 0, 128}, {0, 0, 200}};
  return kColours[static_cast<size_t>(id < 0 ? -id : id) % std::size(kColours)];
}

cv::Scalar StateColour(metrics::FilterState state) {
  switch (state) {
    case metrics::FilterState::kCorrect:
      return {80, 220, 80};
    case metrics::FilterState::kSwapped:
      return {0, 200, 255};
    case metrics::FilterState::kHijacked:
      return {40, 40, 255};
    case metrics::FilterState::kStrayed:
      return {0, 140, 255};
    case metrics::FilterState::kLost:
      return {160, 160, 160};
    case metrics::FilterState::kCoasting:
      return {255, 200, 120};
  }
  return {255, 255, 255};
}

cv::Rect ToRect(const BoxPx& b) {
  return {static_cast<int>(std::lround(b.left)), static_cast<int>(std::lround(b.top)),
          static_cast<int>(std::lround(b.width)), static_cast<int>(std::lround(b.height))};
}

void Label(cv::Mat& image, const std::string& text, cv::Point at, const cv::Scalar& colour,
           double scale = 0.4) {
  at.y = std::max(at.y, 12);
  cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, {0, 0, 0}, 3, cv::LINE_AA);
  cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, colour, 1, cv::LINE_AA);
}

// Detections: thin boxes in one colour, apart from the filters' (by id) and
// the truth's (white), so a frame shows at a glance where the detector fired.
// Drawn last: a detection on its filter's box shows as a line inside it.
const cv::Scalar kDetectionColour{0, 255, 255};  // BGR: yellow

void DrawDetection(cv::Mat& image, const Detection& d) {
  const cv::Rect r = ToRect(d.box);
  cv::rectangle(image, r, kDetectionColour, 1, cv::LINE_AA);
  // The label beside the box (the truth's is below it, a filter's above):
  // the target whose model fired, and the score unless every detection has
  // the same (the oracle's 1).
  std::string text;
  if (d.target) text = fmt::format("m{}", Value(*d.target));
  if (d.target || d.score < 1.0) {
    text += fmt::format("{}{:.2f}", text.empty() ? "" : " ", d.score);
  }
  if (!text.empty()) {
    Label(image, text, {r.x + r.width + 3, r.y + r.height / 2 + 4}, kDetectionColour, 0.35);
  }
}

}  // namespace

OverlayVideo WriteOverlayVideo(const std::string& path, const Scenario& scenario,
                               const OverlayContent& content, const std::vector<RgbImage>* frames) {
  HCPF_CHECK(frames == nullptr || frames->size() == content.truth.size())
      << frames->size() << " images for " << content.truth.size() << " frames";
  OverlayFrameSource source;
  if (frames != nullptr) {
    source = [frames](int f) -> std::optional<RgbImage> { return (*frames)[f]; };
  }
  return WriteOverlayVideo(path, scenario, content, source);
}

void CheckVideoFits(const Scenario& scenario, const std::string& option) {
  const int width = scenario.world.camera.width_px;
  const int height = scenario.world.camera.height_px;
  if (width <= kMaxVideoSide && height <= kMaxVideoSide) return;
  throw InputError(
      SourceLocation{"command line", 0, 0, option},
      fmt::format(
          "a camera.resolution of at most [{0}, {0}] for the overlay video (MPEG-4's limit)",
          kMaxVideoSide),
      fmt::format("[{}, {}] in scenario \"{}\"", width, height, scenario.name),
      "nothing was run; leave out " + option + " or lower camera.resolution");
}

OverlayVideo WriteOverlayVideo(const std::string& path, const Scenario& scenario,
                               const OverlayContent& content, const OverlayFrameSource& frame_at) {
  const std::span<const FrameGroundTruth> truth = content.truth;
  const std::span<const tracker::FrameReport> reports = content.reports;
  const std::span<const Observation> observations = content.observations;
  HCPF_CHECK(reports.empty() || reports.size() == truth.size())
      << reports.size() << " reports for " << truth.size() << " frames";
  HCPF_CHECK(observations.empty() || observations.size() == truth.size())
      << observations.size() << " observations for " << truth.size() << " frames";
  const int width = scenario.world.camera.width_px;
  const int height = scenario.world.camera.height_px;
  // FFmpeg, through the video plugin.
  const std::unique_ptr<VideoSink> writer = OpenVideoSink(path, scenario.world.fps, width, height);
  // (frame, filter) -> state.
  std::map<std::pair<int, int64_t>, metrics::FilterState> states;
  if (content.filters != nullptr) {
    for (const metrics::FilterFrameRecord& r : content.filters->records)
      states[{r.frame, r.filter}] = r.state;
  }
  const std::string detector = scenario.observation.source == ObservationSource::kRendered
                                   ? scenario.observation.DetectorName()
                                   : "simulated";
  cv::Mat image(height, width, CV_8UC3);
  for (size_t f = 0; f < truth.size(); ++f) {
    const std::optional<RgbImage> frame = frame_at ? frame_at(static_cast<int>(f)) : std::nullopt;
    if (frame) {
      const RgbImage& rgb = *frame;
      HCPF_CHECK(rgb.width == width && rgb.height == height)
          << "frame " << f << " is " << rgb.width << "x" << rgb.height << ", the camera " << width
          << "x" << height;
      const cv::Mat view(height, width, CV_8UC3, const_cast<uint8_t*>(rgb.pixels.data()));
      cv::cvtColor(view, image, cv::COLOR_RGB2BGR);
    } else {
      image.setTo(cv::Scalar(58, 82, 62));  // plain background at detection level
    }
    for (const GroundTruthObject& o : truth[f].objects) {
      if (!o.in_frame) continue;
      const cv::Rect r = ToRect(o.amodal_box);
      cv::rectangle(image, r, {255, 255, 255}, 1, cv::LINE_AA);
      Label(image, fmt::format("gt {}", Value(o.id)), {r.x, r.y + r.height + 12}, {255, 255, 255});
    }
    if (!reports.empty()) {
      for (const tracker::FilterReport& fr : reports[f].filters) {
        const int64_t id = Value(fr.id);
        const cv::Scalar colour = FilterColour(id);
        for (const tracker::ParticlePoint& p : fr.particles) {
          const cv::Point at(static_cast<int>(std::lround(p.x_px)),
                             static_cast<int>(std::lround(p.y_px)));
          if (at.x >= 0 && at.y >= 0 && at.x < width && at.y < height) {
            image.at<cv::Vec3b>(at) =
                cv::Vec3b(static_cast<uint8_t>(colour[0]), static_cast<uint8_t>(colour[1]),
                          static_cast<uint8_t>(colour[2]));
          }
        }
        const cv::Rect r = ToRect(fr.box);
        cv::rectangle(image, r, colour, 2, cv::LINE_AA);
        std::string text = fmt::format("F{}", id);
        cv::Scalar text_colour = colour;
        const auto it = states.find({static_cast<int>(f), id});
        if (it != states.end()) {
          text += std::string(" ") + metrics::FilterStateName(it->second);
          text_colour = StateColour(it->second);
        }
        Label(image, text, {r.x, r.y - 4}, text_colour);
      }
    }
    if (!observations.empty()) {
      for (const Detection& d : observations[f].detections) DrawDetection(image, d);
    }
    // Frames counted from 1, as gt/gt.txt, filters.csv and the report do.
    Label(image, fmt::format("{}  frame {}", scenario.name, truth[f].frame + 1), {6, 16},
          {255, 255, 255});
    if (!observations.empty()) {
      Label(image, fmt::format("detections ({})", detector), {6, 32}, kDetectionColour, 0.35);
    }
    writer->Write(image);
  }
  writer->Close();
  if (const std::string error = writer->error(); !error.empty()) {
    throw RunError(fmt::format("cannot write video {}: {}", path, error));
  }
  const bool h264 = std::string(writer->fourcc()) == "avc1";
  return {.fourcc = writer->fourcc(),
          .codec = h264 ? "H.264" : "MPEG-4 Part 2",
          .plays_in_browsers = h264,
          .frames = static_cast<int>(truth.size()),
          .fps = scenario.world.fps,
          .width = width,
          .height = height};
}

}  // namespace hcpf::scenarios
