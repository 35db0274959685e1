// overlay.mp4: written, read back by OpenCV with the right frame count and size, boxes drawn.

#include "hcpf/scenarios/overlay.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "hcpf/core/error.h"
#include "support/process.h"
#include "support/test_scenarios.h"

namespace hcpf::scenarios {
namespace {

namespace fs = std::filesystem;

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
  std::vector<FrameGroundTruth> truth;
  std::vector<RgbImage> images;
  for (int f = 0; f < 5; ++f) {
    truth.push_back(ComputeGroundTruth(scenario.world, f));
    RgbImage image;
    image.width = 320;
    image.height = 240;
    image.pixels.assign(320 * 240 * 3, 0);
    for (size_t i = 0; i < image.pixels.size(); i += 3) {
      image.pixels[i] = 200;      // R
      image.pixels[i + 1] = 100;  // G
      image.pixels[i + 2] = 50;   // B
    }
    images.push_back(image);
  }
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
