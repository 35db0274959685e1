// overlay.mp4: written as H.264, read back by OpenCV with the right frame count and size, boxes
// drawn.

#include "hcpf/scenarios/overlay.h"

#include <gtest/gtest.h>
#include <sched.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>

#include "hcpf/core/error.h"
#include "support/process.h"
#include "support/test_scenarios.h"
#include "video_sink.h"

namespace hcpf::scenarios {
namespace {

namespace fs = std::filesystem;

// `frames` frames of the scenario: their ground truth, and images of the
// camera's size in one colour.
struct Clip {
  std::vector<FrameGroundTruth> truth;
  std::vector<RgbImage> images;
};

Clip PlainClip(const Scenario& scenario, int frames, std::array<uint8_t, 3> rgb) {
  Clip clip;
  const int width = scenario.world.camera.width_px;
  const int height = scenario.world.camera.height_px;
  for (int f = 0; f < frames; ++f) {
    clip.truth.push_back(ComputeGroundTruth(scenario.world, f));
    RgbImage image;
    image.width = width;
    image.height = height;
    image.pixels.resize(static_cast<size_t>(width) * height * 3);
    for (size_t i = 0; i < image.pixels.size(); i += 3) {
      std::copy(rgb.begin(), rgb.end(), image.pixels.begin() + static_cast<std::ptrdiff_t>(i));
    }
    clip.images.push_back(std::move(image));
  }
  return clip;
}

// H.264's largest level codes frames of up to 139,264 macroblocks and
// 16,711,680 macroblocks a second; libx264 wrote an 8190 x 8190 overlay
// declaring that level (a scale audit). Such a video, or one too fast, is
// not said to play in browsers, and a run says so before it starts.
TEST(Overlay, AVideoLargerOrFasterThanAnyH264LevelIsSaidSo) {
  EXPECT_TRUE(FitsAnH264Level(8176, 4352, 30));   // 511 x 272 = 138,992 macroblocks
  EXPECT_TRUE(FitsAnH264Level(8191, 4352, 30));   // 512 x 272 = 139,264
  EXPECT_FALSE(FitsAnH264Level(8191, 4353, 30));  // 512 x 273
  EXPECT_FALSE(FitsAnH264Level(8190, 8190, 30));
  EXPECT_TRUE(FitsAnH264Level(640, 480, 30));
  EXPECT_TRUE(FitsAnH264Level(1920, 1080, 2048));   // 8160 x 2048 = 16,711,680 a second
  EXPECT_FALSE(FitsAnH264Level(1920, 1080, 2049));  // past it
  const auto load = [](const std::string& resolution, const std::string& fps) {
    return LoadScenarioText(
        testing::kMinimal, "v.yaml",
        {ParseOverride("camera.resolution=" + resolution), ParseOverride("fps=" + fps)});
  };
  EXPECT_EQ(VideoLevelNote(load("[640, 480]", "30")), "");
  EXPECT_EQ(VideoLevelNote(load("[8190, 8190]", "30")),
            "--video: a 8190x8190 frame is larger than any H.264 level codes (139264 macroblocks "
            "of 16x16 px at most, 8176x4352 say): the video is written, but a browser may refuse "
            "to play it, and the report links it instead of showing it");
  EXPECT_EQ(VideoLevelNote(load("[1920, 1080]", "2100")),
            "--video: 1920x1080 at 2100 fps is faster than any H.264 level codes (16711680 "
            "macroblocks of 16x16 px a second at most, 1920x1080 at 2048 fps say): the video is "
            "written, but a browser may refuse to play it, and the report links it instead of "
            "showing it");
}

TEST(Overlay, VideoReadsBackWithFrameCountAndSize) {
  const auto dir = ::hcpf::testing::FreshDir("overlay");
  const Scenario scenario =
      LoadScenarioText(testing::kMinimal, "minimal.yaml");  // 20 frames, 320x240
  std::vector<FrameGroundTruth> truth;
  std::vector<tracker::FrameReport> reports;
  for (int f = 0; f < scenario.world.frames; ++f) {
    truth.push_back(ComputeGroundTruth(scenario.world, f));
    tracker::FrameReport report;
    report.frame = f;
    // One filter sitting on target 1's box with a small cloud at its centre.
    for (const GroundTruthObject& o : truth.back().objects) {
      if (Value(o.id) != 1) continue;
      tracker::FilterReport fr;
      fr.id = TrackId{1};
      fr.box = o.amodal_box;
      fr.particles.push_back({static_cast<float>(o.amodal_box.centre_x()),
                              static_cast<float>(o.amodal_box.centre_y()), 1.0F});
      report.filters.push_back(fr);
    }
    reports.push_back(report);
  }
  metrics::FilterMetrics states;
  states.records.push_back({0, 1, 1, 1, metrics::FilterState::kCorrect, -1.0});
  const std::string path = (dir / "overlay.mp4").string();
  WriteOverlayVideo(path, scenario, {.truth = truth, .reports = reports, .filters = &states},
                    nullptr);
  ASSERT_TRUE(fs::exists(path));

  cv::VideoCapture in(path);
  ASSERT_TRUE(in.isOpened());
  EXPECT_EQ(static_cast<int>(in.get(cv::CAP_PROP_FRAME_WIDTH)), 320);
  EXPECT_EQ(static_cast<int>(in.get(cv::CAP_PROP_FRAME_HEIGHT)), 240);
  int frames = 0;
  cv::Mat image, first;
  while (in.read(image)) {
    if (frames == 0) first = image.clone();
    if (frames == 10) {  // kept for a look (CI artefact)
      fs::create_directories(fs::path(HCPF_BINARY_DIR) / "artifacts");
      cv::imwrite((fs::path(HCPF_BINARY_DIR) / "artifacts" / "overlay_frame10.png").string(),
                  image);
    }
    ++frames;
  }
  EXPECT_EQ(frames, 20);
  // Frame 0: the plain background (BGR 58, 82, 62) away from targets, and the
  // drawn boxes elsewhere: enough pixels differ strongly from the background.
  ASSERT_FALSE(first.empty());
  const cv::Vec3b corner = first.at<cv::Vec3b>(230, 310);
  EXPECT_NEAR(corner[0], 58, 12);  // lossy codec: within a few grey levels
  EXPECT_NEAR(corner[1], 82, 12);
  int drawn = 0;
  for (int y = 0; y < first.rows; ++y) {
    for (int x = 0; x < first.cols; ++x) {
      const cv::Vec3b p = first.at<cv::Vec3b>(y, x);
      if (std::abs(p[0] - 58) + std::abs(p[1] - 82) + std::abs(p[2] - 62) > 150) ++drawn;
    }
  }
  EXPECT_GT(drawn, 100);
}

// The video is H.264 in MP4, which browsers play (the run report shows it):
// the writer says so, and the file says so itself (its sample entry "avc1"
// with the decoder configuration "avcC", and the codec FFmpeg reads back).
TEST(Overlay, WritesH264ThatBrowsersPlay) {
  const auto dir = ::hcpf::testing::FreshDir("overlay-h264");
  const Scenario scenario = LoadScenarioText(testing::kMinimal, "minimal.yaml");  // 320x240
  std::vector<FrameGroundTruth> truth;
  for (int f = 0; f < 6; ++f) truth.push_back(ComputeGroundTruth(scenario.world, f));
  const std::string path = (dir / "overlay.mp4").string();
  const OverlayVideo video = WriteOverlayVideo(path, scenario, {.truth = truth}, nullptr);
  EXPECT_EQ(video.fourcc, "avc1");
  EXPECT_EQ(video.codec, "H.264");
  EXPECT_TRUE(video.plays_in_browsers);
  EXPECT_EQ(video.frames, 6);
  EXPECT_EQ(video.fps, scenario.world.fps);
  EXPECT_EQ(video.width, 320);
  EXPECT_EQ(video.height, 240);
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  ASSERT_GT(bytes.size(), 8u);
  EXPECT_EQ(bytes.substr(4, 4), "ftyp") << "an MP4 (ISO base media) file";
  EXPECT_NE(bytes.find("avc1"), std::string::npos);
  EXPECT_NE(bytes.find("avcC"), std::string::npos);
  EXPECT_EQ(bytes.find("mp4v"), std::string::npos);
  cv::VideoCapture capture(path);
  ASSERT_TRUE(capture.isOpened());
  const int code = static_cast<int>(capture.get(cv::CAP_PROP_FOURCC));
  std::string fourcc;
  for (int i = 0; i < 4; ++i) fourcc += static_cast<char>((code >> (8 * i)) & 0xff);
  EXPECT_TRUE(fourcc == "avc1" || fourcc == "h264" || fourcc == "H264") << fourcc;
}

// Where FFmpeg has no libx264 the overlay is MPEG-4 Part 2 (mp4v). Forced
// here (Debian's FFmpeg has libx264), the fallback writes a file that reads
// back with every frame, its size and rate, the mp4v sample entry and
// pixels near those written, and the same bytes a second time. Frames: a
// smooth texture (noise blurred, like a rendered scene) moving 2 px a frame.
TEST(Overlay, Mpeg4Part2FallbackReadsBackNearTheFramesWritten) {
  const auto dir = ::hcpf::testing::FreshDir("overlay-mpeg4");
  cv::Mat texture(240 + 60, 320 + 60, CV_8UC3);
  cv::RNG rng(5);
  rng.fill(texture, cv::RNG::UNIFORM, 0, 255);
  cv::GaussianBlur(texture, texture, cv::Size(0, 0), 2.0);
  cv::normalize(texture, texture, 0, 255, cv::NORM_MINMAX);
  std::vector<cv::Mat> frames;
  for (int f = 0; f < 25; ++f) frames.push_back(texture(cv::Rect(2 * f, f, 320, 240)).clone());
  const auto write = [&](const std::string& name) {
    const std::string path = (dir / name).string();
    const auto sink = OpenVideoSink(path, 12.5, 320, 240, VideoCodec::kMpeg4Part2);
    EXPECT_STREQ(sink->fourcc(), "mp4v");
    for (const cv::Mat& frame : frames) sink->Write(frame);
    sink->Close();
    EXPECT_STREQ(sink->error(), "");
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  const std::string bytes = write("first.mp4");
  ASSERT_GT(bytes.size(), 8u);
  EXPECT_EQ(bytes.substr(4, 4), "ftyp");
  EXPECT_NE(bytes.find("mp4v"), std::string::npos);
  EXPECT_EQ(bytes.find("avcC"), std::string::npos);
  EXPECT_TRUE(write("second.mp4") == bytes) << "one encoder thread: the same bytes again";

  cv::VideoCapture in((dir / "first.mp4").string());
  ASSERT_TRUE(in.isOpened());
  EXPECT_NEAR(in.get(cv::CAP_PROP_FPS), 12.5, 1e-6);  // stored as the rational 25/2
  const int code = static_cast<int>(in.get(cv::CAP_PROP_FOURCC));
  std::string fourcc;
  for (int i = 0; i < 4; ++i) fourcc += static_cast<char>((code >> (8 * i)) & 0xff);
  EXPECT_TRUE(fourcc == "mp4v" || fourcc == "FMP4") << fourcc;
  // Each frame read back is nearest (PSNR) the frame written in its place,
  // of all 25: none lost, repeated or out of order.
  cv::Mat image;
  size_t read = 0;
  double worst_psnr = 1e9;
  while (in.read(image)) {
    ASSERT_LT(read, frames.size());
    ASSERT_EQ(image.size(), frames[read].size());
    size_t nearest = 0;
    for (size_t k = 1; k < frames.size(); ++k) {
      if (cv::PSNR(image, frames[k]) > cv::PSNR(image, frames[nearest])) nearest = k;
    }
    EXPECT_EQ(nearest, read);
    worst_psnr = std::min(worst_psnr, cv::PSNR(image, frames[read]));
    ++read;
  }
  EXPECT_EQ(read, frames.size());
  // A fixed quantiser of 3 on 4:2:0 colour: 31.5 dB at worst on these
  // frames (FFmpeg 5.1, Debian 12); 28 dB leaves room for another FFmpeg's
  // rounding, and is far above a frame of another scene (about 10 dB).
  EXPECT_GT(worst_psnr, 28.0) << worst_psnr;
}

// H.264 codes 4:2:0 colour, which needs even sides: a camera of 321 x 241
// gives a video of 322 x 242 whose extra column and row copy the last ones
// (a grey image with a white last column: the copy is white too).
TEST(Overlay, AnOddSideGainsACopyOfItsLastRowOrColumn) {
  const auto dir = ::hcpf::testing::FreshDir("overlay-odd");
  const Scenario scenario =
      LoadScenarioText(testing::kMinimal, "minimal.yaml", {{"camera.resolution", "[321, 241]"}});
  auto [truth, images] = PlainClip(scenario, 3, {90, 90, 90});
  for (RgbImage& image : images) {
    for (int y = 0; y < 241; ++y) {
      for (int c = 0; c < 3; ++c) image.pixels[(static_cast<size_t>(y) * 321 + 320) * 3 + c] = 255;
    }
  }
  const std::string path = (dir / "overlay.mp4").string();
  const OverlayVideo video = WriteOverlayVideo(path, scenario, {.truth = truth}, &images);
  EXPECT_EQ(video.width, 321);
  EXPECT_EQ(video.height, 241);
  cv::VideoCapture in(path);
  cv::Mat image;
  int frames = 0;
  cv::Mat first;
  while (in.read(image)) {
    if (frames++ == 0) first = image.clone();
  }
  EXPECT_EQ(frames, 3);
  ASSERT_EQ(first.cols, 322);
  ASSERT_EQ(first.rows, 242);
  // Mid-height, away from the labels: the last two columns white, the one
  // before them grey (a lossy codec: within a few grey levels).
  for (const int x : {320, 321}) EXPECT_GT(first.at<cv::Vec3b>(200, x)[1], 225) << x;
  EXPECT_NEAR(first.at<cv::Vec3b>(200, 300)[1], 90, 12);
  EXPECT_NEAR(first.at<cv::Vec3b>(241, 100)[1], 90, 12) << "the copied last row";
}

// One FFmpeg writes the same bytes whatever the machine's core count: the
// encoder runs one thread (libx264 left to itself starts threads by the
// cores the calling thread may use, and its bytes change with them). Written
// once on every core this thread may use and once on one core alone, from
// textured frames that move (a still plain frame might code alike anyway).
TEST(Overlay, SameBytesWhateverTheCoreCount) {
  cpu_set_t all;
  CPU_ZERO(&all);
  ASSERT_EQ(sched_getaffinity(0, sizeof(all), &all), 0);
  if (CPU_COUNT(&all) < 2) GTEST_SKIP() << "one core only: nothing to compare with";
  const auto dir = ::hcpf::testing::FreshDir("overlay-cores");
  const Scenario scenario = LoadScenarioText(testing::kMinimal, "minimal.yaml");  // 320x240
  std::vector<FrameGroundTruth> truth;
  std::vector<RgbImage> images;
  cv::Mat texture(240 + 40, 320 + 40, CV_8UC3);
  cv::RNG rng(11);
  rng.fill(texture, cv::RNG::UNIFORM, 0, 255);
  for (int f = 0; f < 30; ++f) {
    truth.push_back(ComputeGroundTruth(scenario.world, f));
    const cv::Mat view = texture(cv::Rect(f, f / 2, 320, 240)).clone();
    RgbImage image;
    image.width = 320;
    image.height = 240;
    image.pixels.assign(view.data, view.data + view.total() * 3);
    images.push_back(std::move(image));
  }
  const auto write = [&](const std::string& name) {
    const std::string path = (dir / name).string();
    WriteOverlayVideo(path, scenario, {.truth = truth}, &images);
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  };
  const std::string on_all = write("all.mp4");
  cpu_set_t one;
  CPU_ZERO(&one);
  for (int cpu = 0; cpu < CPU_SETSIZE; ++cpu) {
    if (CPU_ISSET(cpu, &all)) {
      CPU_SET(cpu, &one);
      break;
    }
  }
  // Every core back whatever happens: later tests of this process run here.
  struct Restore {
    cpu_set_t cores;
    ~Restore() { sched_setaffinity(0, sizeof(cores), &cores); }
  } restore{all};
  ASSERT_EQ(sched_setaffinity(0, sizeof(one), &one), 0);
  const std::string on_one = write("one.mp4");
  ASSERT_GT(on_all.size(), 1000u);
  EXPECT_TRUE(on_all == on_one) << on_all.size() << " bytes on " << CPU_COUNT(&all) << " cores, "
                                << on_one.size() << " on one";
}

// The header says which run it is (an audit: two runs' videos side by side
// in `hcpf report --against` both read "crossing frame 1 / detections
// (sks)"): the scene and frame, the run's seed and tracker in the run
// report's words, then the detector when there are detections.
TEST(Overlay, HeaderLinesTagTheRun) {
  Scenario scenario = LoadScenarioText(testing::kMinimal, "minimal.yaml");
  scenario.seed = 12;
  scenario.tracker.particles = 250;
  scenario.tracker.resampling.method = tracker::ResamplingMethod::kSystematic;
  EXPECT_EQ(internal::OverlayHeaderLines(scenario, 4, false),
            (std::vector<std::string>{"minimal  frame 5",
                                      "seed 12, 250 particles, systematic "
                                      "resampling"}));
  EXPECT_EQ(
      internal::OverlayHeaderLines(scenario, 0, true),
      (std::vector<std::string>{"minimal  frame 1", "seed 12, 250 particles, systematic resampling",
                                "detections (simulated)"}));
  // Charged resampling, as the shipped scenes run it.
  scenario.tracker.resampling.method = tracker::ResamplingMethod::kCharged;
  EXPECT_EQ(internal::OverlayRunTag(scenario), "seed 12, 250 particles, charged resampling");
  // The likelihood and the camera motion when not the defaults (a review:
  // runs differing only there had one tag).
  scenario.tracker.likelihood.model = tracker::LikelihoodModel::kAssociated;
  scenario.tracker.camera_motion = tracker::CameraMotionMode::kSceneFilter;
  EXPECT_EQ(internal::OverlayRunTag(scenario),
            "seed 12, 250 particles, charged resampling, associated likelihood, camera motion "
            "scene_filter");
  // An external tracker: its program's paths by their file names; options
  // and words without a folder as they are.
  scenario.tracker_choice.type = TrackerType::kExternal;
  scenario.tracker_choice.command = {
      "/usr/bin/python3", "/opt/trackers/sort.py", "--iou", "0.3", "--model=/a/b.onnx", "1/2x"};
  EXPECT_EQ(internal::OverlayRunTag(scenario),
            "seed 12, tracker: external (python3 sort.py --iou 0.3 --model=/a/b.onnx 2x)");
}

// The header on a narrow frame (an audit: the tag ran off frames narrower
// than about 260 px). The width is OpenCV's, as the overlay draws it
// (Hershey simplex, thickness 3).
TEST(Overlay, HeaderLinesAreCutToTheFrame) {
  const auto width = [](const std::string& text) {
    int baseline = 0;
    return cv::getTextSize(text, cv::FONT_HERSHEY_SIMPLEX, 0.35, 3, &baseline).width;
  };
  const std::string tag =
      "seed 12, 250 particles, charged resampling, associated likelihood, camera motion "
      "scene_filter";
  // Room for all of it: as it is.
  EXPECT_EQ(internal::FitHeaderLine(tag, 0.35, width(tag)), tag);
  // One pixel short: the last clause goes, and " .." says so.
  EXPECT_EQ(internal::FitHeaderLine(tag, 0.35, width(tag) - 1),
            "seed 12, 250 particles, charged resampling, associated likelihood ..");
  // Room for the first three clauses and the mark, not for a fourth.
  const std::string three = "seed 12, 250 particles, charged resampling ..";
  EXPECT_EQ(internal::FitHeaderLine(tag, 0.35, width(three)), three);
  // Narrower than the first clause: its characters are cut.
  const std::string cut = internal::FitHeaderLine(tag, 0.35, width("seed 1 .."));
  EXPECT_EQ(cut, "seed 1 ..");
  // No room at all: nothing.
  EXPECT_EQ(internal::FitHeaderLine(tag, 0.35, 2), "");
  // Whole UTF-8 characters are cut (a review: a cut inside a two-byte "é"
  // left its first byte, drawn as '?'): at every width the text kept before
  // " .." is an even number of bytes.
  std::string accents;
  for (int i = 0; i < 30; ++i) accents += "\xC3\xA9";
  for (int w = 10; w < width(accents); w += 7) {
    const std::string cut_accents = internal::FitHeaderLine(accents, 0.35, w);
    if (cut_accents.empty()) continue;
    ASSERT_GE(cut_accents.size(), 3U);
    EXPECT_EQ((cut_accents.size() - 3) % 2, 0U) << w;
  }
}

// The tag is drawn: the header's second line (its rectangle: x from 6,
// baseline y 31, about 8 px tall at scale 0.35), on the plain background,
// where nothing else is drawn in minimal's first frame (its targets are
// below y 80).
TEST(Overlay, DrawsTheRunTagUnderTheSceneLine) {
  const auto dir = ::hcpf::testing::FreshDir("overlay-tag");
  const Scenario scenario = LoadScenarioText(testing::kMinimal, "minimal.yaml");  // 320x240
  const std::vector<FrameGroundTruth> truth = {ComputeGroundTruth(scenario.world, 0)};
  for (const GroundTruthObject& o : truth[0].objects) {
    if (o.in_frame) {
      ASSERT_GT(o.amodal_box.top, 60.0) << "a target near the header";
    }
  }
  const std::string path = (dir / "overlay.mp4").string();
  WriteOverlayVideo(path, scenario, {.truth = truth}, nullptr);
  cv::VideoCapture in(path);
  cv::Mat image;
  ASSERT_TRUE(in.read(image));
  int white = 0;
  for (int y = 23; y <= 33; ++y) {
    for (int x = 6; x < 200; ++x) {
      const cv::Vec3b p = image.at<cv::Vec3b>(y, x);
      if (p[0] > 180 && p[1] > 180 && p[2] > 180) ++white;
    }
  }
  EXPECT_GT(white, 40);
}

TEST(Overlay, UnwritablePathIsARunError) {
  const Scenario scenario = LoadScenarioText(testing::kMinimal, "minimal.yaml");
  EXPECT_THROW(WriteOverlayVideo("/nonexistent/dir/overlay.mp4", scenario, {}, nullptr), RunError);
}

// The frame's detections are drawn (thin yellow boxes), where they are, and
// only when observations are given.
TEST(Overlay, DrawsTheFramesDetections) {
  const auto dir = ::hcpf::testing::FreshDir("overlay-detections");
  const Scenario scenario = LoadScenarioText(testing::kMinimal, "minimal.yaml");  // 320x240
  std::vector<FrameGroundTruth> truth;
  std::vector<Observation> observations;
  // A box in the lower right, away from the targets and the labels.
  const BoxPx box{220.0, 150.0, 60.0, 40.0};
  for (int f = 0; f < 3; ++f) {
    truth.push_back(ComputeGroundTruth(scenario.world, f));
    Observation o;
    o.frame = f;
    o.detections.push_back({.box = box, .score = 0.8, .target = ObjectId{1}});
    observations.push_back(o);
  }
  const auto yellow_on_box_edge = [&](const std::string& path) {
    cv::VideoCapture in(path);
    cv::Mat image;
    EXPECT_TRUE(in.read(image));
    if (image.empty()) return 0;
    int yellow = 0;
    for (int x = 222; x < 278; ++x) {
      for (const int y : {150, 189}) {  // the top and bottom edges
        const cv::Vec3b p = image.at<cv::Vec3b>(y, x);
        // BGR yellow (0, 255, 255) on the plain background (58, 82, 62):
        // red and green far up, blue down (a lossy codec blurs a 1-px line).
        if (p[2] > 140 && p[1] > 140 && p[0] < 120) ++yellow;
      }
    }
    return yellow;
  };
  const std::string with = (dir / "with.mp4").string();
  WriteOverlayVideo(with, scenario, {.truth = truth, .observations = observations}, nullptr);
  const std::string without = (dir / "without.mp4").string();
  WriteOverlayVideo(without, scenario, {.truth = truth}, nullptr);
  EXPECT_GT(yellow_on_box_edge(with), 56);  // of 112 edge pixels
  EXPECT_EQ(yellow_on_box_edge(without), 0);
}

}  // namespace
}  // namespace hcpf::scenarios

namespace hcpf::scenarios {
namespace {

TEST(Overlay, DrawsOnTheGivenFrames) {
  const auto dir = ::hcpf::testing::FreshDir("overlay-frames");
  const Scenario scenario = LoadScenarioText(testing::kMinimal, "minimal.yaml");  // 320x240
  const auto [truth, images] = PlainClip(scenario, 5, {200, 100, 50});            // RGB
  const std::string path = (dir / "overlay.mp4").string();
  WriteOverlayVideo(path, scenario, {.truth = truth}, &images);
  cv::VideoCapture in(path);
  cv::Mat image;
  ASSERT_TRUE(in.read(image));
  // OpenCV frames are BGR: the RGB (200, 100, 50) image reads back as (50, 100, 200).
  const cv::Vec3b corner = image.at<cv::Vec3b>(230, 310);
  EXPECT_NEAR(corner[0], 50, 12);
  EXPECT_NEAR(corner[1], 100, 12);
  EXPECT_NEAR(corner[2], 200, 12);
  int frames = 1;
  while (in.read(image)) ++frames;
  EXPECT_EQ(frames, 5);
}

}  // namespace
}  // namespace hcpf::scenarios
