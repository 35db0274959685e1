// ReadGroundTruthJson and DetectionTruthOf: the truth `hcpf score
// --detections` scores a detector's file against.

#include "hcpf/metrics/detection_truth.h"

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "hcpf/core/error.h"
#include "hcpf/core/ground_truth_json.h"
#include "support/process.h"

namespace hcpf::metrics {
namespace {

namespace fs = std::filesystem;

// A 100 x 80 px frame with one target per box.
FrameGroundTruth Frame(int index, const std::vector<BoxPx>& boxes) {
  FrameGroundTruth f;
  f.frame = index;
  f.camera.intrinsics = {100, 80, 100.0, 100.0, 50.0, 40.0};
  for (size_t i = 0; i < boxes.size(); ++i) {
    GroundTruthObject o;
    o.id = ObjectId{static_cast<int32_t>(i + 1)};
    o.in_frame = true;
    o.amodal_box = o.visible_box = boxes[i];
    o.visible_fraction = 0.5 + 0.1 * static_cast<double>(i);
    o.truncation = 0.25 * static_cast<double>(i);
    f.objects.push_back(o);
  }
  return f;
}

std::string Write(const fs::path& path, const nlohmann::json& j) {
  std::ofstream(path) << j.dump(1);
  return path.string();
}

std::string ErrorOf(const std::string& path) {
  try {
    ReadGroundTruthJson(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(DetectionTruth, ClipsEachInFrameTargetToTheImageAndKeepsItsVisibility) {
  FrameGroundTruth f = Frame(0, {{10, 10, 20, 20}, {90, 70, 20, 20}, {-5, 0, 10, 10}});
  GroundTruthObject gone;
  gone.id = ObjectId{9};
  gone.in_frame = false;
  f.objects.push_back(gone);
  const std::vector<DetectionTruth> truth = DetectionTruthOf(f);
  ASSERT_EQ(truth.size(), 3u);  // the target outside the image is left out
  EXPECT_EQ(truth[0].box, (BoxPx{10, 10, 20, 20}));
  EXPECT_EQ(truth[1].box, (BoxPx{90, 70, 10, 10}));  // the image ends at 100 x 80
  EXPECT_EQ(truth[2].box, (BoxPx{0, 0, 5, 10}));
  EXPECT_EQ(Value(truth[2].target), 3);
  EXPECT_DOUBLE_EQ(truth[2].visible_fraction, 0.7);
  EXPECT_DOUBLE_EQ(truth[2].truncation, 0.5);
}

TEST(DetectionTruth, ReadsAGtJsonFrameByFrame) {
  const auto dir = ::hcpf::testing::FreshDir("detection-truth");
  const nlohmann::json frames = {GroundTruthToJson(Frame(0, {{10, 10, 20, 20}})),
                                 GroundTruthToJson(Frame(1, {{12, 10, 20, 20}, {0, 0, 4, 4}}))};
  const GroundTruthFile file = ReadGroundTruthJson(Write(
      dir / "gt.json", {{"format", "hcpf-gt/1"}, {"source", "analytic"}, {"frames", frames}}));
  EXPECT_EQ(file.source, "analytic");
  ASSERT_EQ(file.frames.size(), 2u);
  EXPECT_EQ(file.frames[1].objects.size(), 2u);
  EXPECT_EQ(file.frames[1].objects[0].amodal_box, (BoxPx{12, 10, 20, 20}));
  EXPECT_EQ(file.frames[1].camera.intrinsics.width_px, 100);
}

TEST(DetectionTruth, AFileThatIsNotAGtJsonIsNamedWithWhatIsWrong) {
  const auto dir = ::hcpf::testing::FreshDir("detection-truth-bad");
  const nlohmann::json frame0 = GroundTruthToJson(Frame(0, {{10, 10, 20, 20}}));
  // A syntax error: its line and column.
  std::ofstream(dir / "broken.json") << "{\n \"format\": \"hcpf-gt/1\",\n \"frames\": [\n}\n";
  const std::string broken = ErrorOf((dir / "broken.json").string());
  EXPECT_NE(broken.find("broken.json:4:1"), std::string::npos) << broken;
  EXPECT_NE(broken.find("does not parse as JSON"), std::string::npos) << broken;
  // On line 1 after a byte-order mark, the column an editor shows: the bad
  // '}' of {"format": } is its twelfth character, byte 14 of the file.
  std::ofstream(dir / "marked.json") << "\xEF\xBB\xBF{\"format\": }\n";
  const std::string marked = ErrorOf((dir / "marked.json").string());
  EXPECT_NE(marked.find("marked.json:1:12"), std::string::npos) << marked;
  // Another JSON file (a metrics.json).
  const std::string other = ErrorOf(Write(dir / "metrics.json", {{"mot", 1}}));
  EXPECT_NE(other.find("format: expected a gt.json written by hcpf render or hcpf run (format "
                       "\"hcpf-gt/1\"), found no \"format\" key"),
            std::string::npos)
      << other;
  // A frame without a field, and frames out of order.
  nlohmann::json missing = frame0;
  missing["objects"][0].erase("truncation");
  const std::string field = ErrorOf(
      Write(dir / "a.json",
            {{"format", "hcpf-gt/1"}, {"source", "rendered"}, {"frames", {frame0, missing}}}));
  // By its path, not the JSON library's text (a bad-input audit).
  EXPECT_NE(field.find("frames[1].objects[0].truncation: expected the object's truncation, found "
                       "nothing"),
            std::string::npos)
      << field;
  // A fractional id, and an id two objects of a frame share (a bad-input
  // audit: 1.7 was read as 1, and the pair accepted).
  nlohmann::json fractional = frame0;
  fractional["objects"][0]["id"] = 1.7;
  const std::string id = ErrorOf(Write(
      dir / "f.json", {{"format", "hcpf-gt/1"}, {"source", "rendered"}, {"frames", {fractional}}}));
  EXPECT_NE(id.find("frames[0].objects[0].id: expected a whole number in [0, 2147483647], found "
                    "1.7"),
            std::string::npos)
      << id;
  nlohmann::json twice = frame0;
  twice["objects"].push_back(frame0["objects"][0]);
  const std::string shared = ErrorOf(Write(
      dir / "g.json", {{"format", "hcpf-gt/1"}, {"source", "rendered"}, {"frames", {twice}}}));
  EXPECT_NE(shared.find("frames[0].objects[" + std::to_string(twice["objects"].size() - 1) +
                        "].id: expected an id no other object of the frame has"),
            std::string::npos)
      << shared;
  const std::string order = ErrorOf(
      Write(dir / "b.json",
            {{"format", "hcpf-gt/1"}, {"source", "rendered"}, {"frames", {frame0, frame0}}}));
  EXPECT_NE(order.find("frames[1].frame: expected 1, found 0"), std::string::npos) << order;
  // Values the scores cannot read: a negative width, a visible fraction
  // above 1.
  nlohmann::json negative = frame0;
  negative["objects"][0]["amodal_box"] = {10, 10, -5, 20};
  const std::string box = ErrorOf(Write(
      dir / "d.json", {{"format", "hcpf-gt/1"}, {"source", "rendered"}, {"frames", {negative}}}));
  EXPECT_NE(box.find("frames[0].objects[0].amodal_box: expected [left, top, width, height] in "
                     "pixels, width and height at least 0"),
            std::string::npos)
      << box;
  EXPECT_NE(box.find("found [10, 10, -5, 20]"), std::string::npos) << box;
  nlohmann::json over = frame0;
  over["objects"][0]["visible_fraction"] = 7.5;
  const std::string fraction = ErrorOf(
      Write(dir / "e.json", {{"format", "hcpf-gt/1"}, {"source", "rendered"}, {"frames", {over}}}));
  EXPECT_NE(fraction.find(
                "frames[0].objects[0].visible_fraction: expected a fraction in [0, 1], found 7.5"),
            std::string::npos)
      << fraction;
  const std::string source = ErrorOf(
      Write(dir / "c.json", {{"format", "hcpf-gt/1"}, {"source", "drawn"}, {"frames", {frame0}}}));
  EXPECT_NE(source.find("source: expected \"rendered\" or \"analytic\", found \"drawn\""),
            std::string::npos)
      << source;
}

}  // namespace
}  // namespace hcpf::metrics
