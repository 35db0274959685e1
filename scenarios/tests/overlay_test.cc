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
  WriteOverlayVideo(path, scenario, truth, reports, states, nullptr);
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
  EXPECT_THROW(
      WriteOverlayVideo("/nonexistent/dir/overlay.mp4", scenario, {}, {}, std::nullopt, nullptr),
      RunError);
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
  WriteOverlayVideo(path, scenario, truth, {}, std::nullopt, &images);
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
