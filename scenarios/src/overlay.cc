#include "hcpf/scenarios/overlay.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "hcpf/core/check.h"
#include "hcpf/core/enum_names.h"
#include "hcpf/core/error.h"
#include "hcpf/core/label_placement.h"
#include "video_sink.h"

namespace hcpf::scenarios {

namespace {

// Filter colours (BGR), by filter id. None is a state's colour (below), the
// detections' yellow or the truth's white: filter 2's lime box under a green
// CORRECT label read as one thing (an audit). Cyan, pink, green, magenta,
// olive, teal, light green, rose.
cv::Scalar FilterColour(int64_t id) {
  static const cv::Scalar kColours[] = {{207, 190, 23},  {194, 119, 227}, {44, 160, 44},
                                        {204, 51, 255},  {34, 189, 188},  {128, 128, 0},
                                        {138, 223, 152}, {150, 150, 255}};
  return kColours[static_cast<size_t>(id < 0 ? -id : id) % std::size(kColours)];
}

// The state labels' colours (BGR): those of the run report's timeline
// (studies/src/run_report.cc kStateColours), so a state reads the same in
// the video and on the page.
cv::Scalar StateColour(metrics::FilterState state) {
  switch (state) {
    case metrics::FilterState::kCorrect:
      return {180, 119, 31};  // #1f77b4
    case metrics::FilterState::kSwapped:
      return {14, 127, 255};  // #ff7f0e
    case metrics::FilterState::kHijacked:
      return {40, 39, 214};  // #d62728
    case metrics::FilterState::kStrayed:
      return {75, 86, 140};  // #8c564b
    case metrics::FilterState::kLost:
      return {189, 103, 148};  // #9467bd
    case metrics::FilterState::kCoasting:
      return {225, 202, 158};  // #9ecae1
  }
  return {255, 255, 255};
}

}  // namespace

namespace internal {

std::string OverlayRunTag(const Scenario& scenario) {
  if (scenario.tracker_choice.external()) {
    // A path among the command's words by its file name: a program's folder
    // (held as an absolute path) would fill the line. Not an option
    // ("--model=/a/b.onnx") nor a word without a folder (a review).
    std::string words;
    for (const std::string& word : scenario.tracker_choice.command) {
      const bool path = word.find('/') != std::string::npos && !word.starts_with("-");
      const std::string name = path ? std::filesystem::path(word).filename().string() : word;
      words += (words.empty() ? "" : " ") + (name.empty() ? word : name);
    }
    return fmt::format("seed {}, tracker: external ({})", scenario.seed, words);
  }
  // The likelihood and the camera motion too when not the defaults
  // (detections_mixture, none), which the main job and the chapter-10 sweeps
  // compare: two runs differing only there had one tag (a review). Only
  // then, so the line fits a 640 px frame.
  const tracker::TrackerOptions defaults;
  std::string tag =
      fmt::format("seed {}, {} particles, {} resampling", scenario.seed, scenario.tracker.particles,
                  NameOf(scenario.tracker.resampling.method));
  if (scenario.tracker.likelihood.model != defaults.likelihood.model) {
    tag += fmt::format(", {} likelihood", NameOf(scenario.tracker.likelihood.model));
  }
  if (scenario.tracker.camera_motion != defaults.camera_motion) {
    tag += fmt::format(", camera motion {}", NameOf(scenario.tracker.camera_motion));
  }
  return tag;
}

std::vector<std::string> OverlayHeaderLines(const Scenario& scenario, int frame, bool detections) {
  std::vector<std::string> lines = {fmt::format("{}  frame {}", scenario.name, frame + 1),
                                    OverlayRunTag(scenario)};
  if (detections) {
    const std::string detector = scenario.observation.source == ObservationSource::kRendered
                                     ? scenario.observation.DetectorName()
                                     : "simulated";
    lines.push_back(fmt::format("detections ({})", detector));
  }
  return lines;
}

}  // namespace internal

namespace {

cv::Rect ToRect(const BoxPx& b) {
  return {static_cast<int>(std::lround(b.left)), static_cast<int>(std::lround(b.top)),
          static_cast<int>(std::lround(b.width)), static_cast<int>(std::lround(b.height))};
}

constexpr double kLabelScale = 0.4;

// The rectangle a label's text covers, outline included, for PlaceLabels.
cv::Size LabelSize(const std::string& text, double scale, int* text_height) {
  int baseline = 0;
  const cv::Size size = cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, scale, 3, &baseline);
  *text_height = size.height;
  return {size.width, size.height + baseline};
}

}  // namespace

namespace internal {

std::string FitHeaderLine(const std::string& text, double scale, int max_width_px) {
  int text_height = 0;
  const auto fits = [&](const std::string& t) {
    return LabelSize(t, scale, &text_height).width <= max_width_px;
  };
  if (fits(text)) return text;
  const std::string kCut = " ..";
  std::string kept = text;
  for (size_t comma = kept.rfind(", "); comma != std::string::npos; comma = kept.rfind(", ")) {
    kept.resize(comma);
    if (fits(kept + kCut)) return kept + kCut;
  }
  // Whole UTF-8 characters only (a review: a cut inside one drew '?').
  const auto pop_character = [&kept] {
    while (!kept.empty() && (static_cast<unsigned char>(kept.back()) & 0xC0) == 0x80) {
      kept.pop_back();
    }
    if (!kept.empty()) kept.pop_back();
  };
  while (!kept.empty() && !fits(kept + kCut)) pop_character();
  return kept.empty() ? std::string() : kept + kCut;
}

}  // namespace internal

namespace {

void Label(cv::Mat& image, const std::string& text, cv::Point at, const cv::Scalar& colour,
           double scale = kLabelScale) {
  at.y = std::max(at.y, 12);
  cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, {0, 0, 0}, 3, cv::LINE_AA);
  cv::putText(image, text, at, cv::FONT_HERSHEY_SIMPLEX, scale, colour, 1, cv::LINE_AA);
}

// Detections: thin boxes in one colour, apart from the filters' (by id) and
// the truth's (white), so a frame shows at a glance where the detector fired.
// Drawn last: a detection on its filter's box shows as a line inside it.
const cv::Scalar kDetectionColour{0, 255, 255};  // BGR: yellow

// Draws a detection's box and returns its label (placed with the others),
// right of the box first (the truth's is below it first, a filter's above):
// the target whose model fired, and the score unless every detection has the
// same (the oracle's 1); "" for none.
std::string DrawDetection(cv::Mat& image, const Detection& d) {
  cv::rectangle(image, ToRect(d.box), kDetectionColour, 1, cv::LINE_AA);
  std::string text;
  if (d.target) text = fmt::format("m{}", Value(*d.target));
  if (d.target || d.score < 1.0) {
    text += fmt::format("{}{:.2f}", text.empty() ? "" : " ", d.score);
  }
  return text;
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

namespace {

int64_t Macroblocks(int width, int height) {
  return ((int64_t{width} + 15) / 16) * ((int64_t{height} + 15) / 16);
}

}  // namespace

bool FitsAnH264Level(int width, int height, double fps) {
  const int64_t mbs = Macroblocks(width, height);
  return mbs <= kMaxH264FrameMacroblocks &&
         static_cast<double>(mbs) * fps <= kMaxH264MacroblocksPerSecond;
}

std::string VideoLevelNote(const Scenario& scenario) {
  const int width = scenario.world.camera.width_px;
  const int height = scenario.world.camera.height_px;
  const double fps = scenario.world.fps;
  if (FitsAnH264Level(width, height, fps)) return {};
  const int64_t mbs = Macroblocks(width, height);
  const std::string why =
      mbs > kMaxH264FrameMacroblocks
          ? fmt::format(
                "a {}x{} frame is larger than any H.264 level codes ({} macroblocks of "
                "16x16 px at most, 8176x4352 say)",
                width, height, kMaxH264FrameMacroblocks)
          : fmt::format(
                "{}x{} at {} fps is faster than any H.264 level codes ({} macroblocks "
                "of 16x16 px a second at most, 1920x1080 at 2048 fps say)",
                width, height, fps, kMaxH264MacroblocksPerSecond);
  return fmt::format(
      "--video: {}: the video is written, but a browser may refuse to play it, and the report "
      "links it instead of showing it",
      why);
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
    // Labels are placed apart once every box is known, and drawn last.
    struct PendingLabel {
      std::string text;
      cv::Scalar colour;
      int text_height = 0;
      double scale = kLabelScale;
    };
    std::vector<PendingLabel> pending;
    std::vector<LabelRequest> requests;
    const auto request = [&](std::string text, const cv::Rect& r, const cv::Scalar& colour,
                             LabelSide first, double scale = kLabelScale) {
      int text_height = 0;
      const cv::Size size = LabelSize(text, scale, &text_height);
      requests.push_back({.box = {r.x, r.y, r.width, r.height},
                          .text_width = size.width,
                          .text_height = size.height,
                          .first = first});
      pending.push_back({std::move(text), colour, text_height, scale});
    };
    for (const GroundTruthObject& o : truth[f].objects) {
      if (!o.in_frame) continue;
      const cv::Rect r = ToRect(o.amodal_box);
      cv::rectangle(image, r, {255, 255, 255}, 1, cv::LINE_AA);
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
        request(text, r, text_colour, LabelSide::kAbove);
      }
    }
    for (const GroundTruthObject& o : truth[f].objects) {
      if (o.in_frame)
        request(fmt::format("gt {}", Value(o.id)), ToRect(o.amodal_box), {255, 255, 255},
                LabelSide::kBelow);
    }
    if (!observations.empty()) {
      for (const Detection& d : observations[f].detections) {
        std::string text = DrawDetection(image, d);
        if (!text.empty()) {
          request(std::move(text), ToRect(d.box), kDetectionColour, LabelSide::kRight, 0.35);
        }
      }
    }
    // The header's lines (top left, internal::OverlayHeaderLines), whose
    // rectangles the labels keep off: the scene and frame in white, the
    // run's tag in white, smaller, the detector in the detections' yellow.
    struct HeaderLine {
      std::string text;
      cv::Point at;
      cv::Scalar colour;
      double scale;
    };
    std::vector<HeaderLine> header;
    const std::vector<std::string> header_text =
        internal::OverlayHeaderLines(scenario, truth[f].frame, !observations.empty());
    for (size_t i = 0; i < header_text.size(); ++i) {
      const double scale = i == 0 ? kLabelScale : 0.35;
      // From x = 6, with as much room on the right.
      header.push_back({internal::FitHeaderLine(header_text[i], scale, width - 12),
                        {6, 16 + 15 * static_cast<int>(i)},
                        i == 2 ? kDetectionColour : cv::Scalar(255, 255, 255),
                        scale});
    }
    std::vector<PixelRect> taken;
    for (const HeaderLine& line : header) {
      int text_height = 0;
      const cv::Size size = LabelSize(line.text, line.scale, &text_height);
      taken.push_back({line.at.x, line.at.y - text_height, size.width, size.height});
    }
    const std::vector<PixelRect> placed = PlaceLabels(requests, {0, 0, width, height}, taken);
    for (size_t i = 0; i < pending.size(); ++i) {
      Label(image, pending[i].text, {placed[i].x, placed[i].y + pending[i].text_height},
            pending[i].colour, pending[i].scale);
    }
    for (const HeaderLine& line : header) Label(image, line.text, line.at, line.colour, line.scale);
    writer->Write(image);
  }
  writer->Close();
  if (const std::string error = writer->error(); !error.empty()) {
    throw RunError(fmt::format("cannot write video {}: {}", path, error));
  }
  const bool h264 = std::string(writer->fourcc()) == "avc1";
  return {.fourcc = writer->fourcc(),
          .codec = h264 ? "H.264" : "MPEG-4 Part 2",
          .plays_in_browsers = h264 && FitsAnH264Level(width, height, scenario.world.fps),
          .frames = static_cast<int>(truth.size()),
          .fps = scenario.world.fps,
          .width = width,
          .height = height};
}

}  // namespace hcpf::scenarios
