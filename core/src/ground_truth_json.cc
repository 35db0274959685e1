#include "hcpf/core/ground_truth_json.h"

#include <fmt/format.h>

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "hcpf/core/error.h"

namespace hcpf {
namespace {

nlohmann::json BoxToJson(const BoxPx& b) { return {b.left, b.top, b.width, b.height}; }

nlohmann::json VecToJson(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

template <typename M>
nlohmann::json MatrixToJson(const M& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < m.rows(); ++r) {
    nlohmann::json row = nlohmann::json::array();
    for (int c = 0; c < m.cols(); ++c) row.push_back(m(r, c));
    rows.push_back(row);
  }
  return rows;
}

// Reading, strictly and naming what is wrong: each field of the type
// GroundTruthToJson writes (a bad-input audit: a hand-edited gt.json gave the
// JSON library's text and only "frames[i]", and a frame 3.5 or an id 1.7 was
// truncated without a word). `key` is the path within the frame.
[[noreturn]] void Bad(const std::string& key, const std::string& expected,
                      const nlohmann::json* found) {
  std::string text = found == nullptr ? std::string("nothing") : found->dump();
  if (text.size() > 60) text = text.substr(0, 57) + "...";
  throw InputError(SourceLocation{"", 0, 0, key}, expected, text);
}

const nlohmann::json& Member(const nlohmann::json& j, const std::string& name,
                             const std::string& key, const std::string& expected) {
  if (!j.is_object() || !j.contains(name)) Bad(key, expected, nullptr);
  return j[name];
}

double Number(const nlohmann::json& j, const std::string& key) {
  if (!j.is_number()) Bad(key, "a number", &j);
  return j.get<double>();
}

int64_t Whole(const nlohmann::json& j, const std::string& key, int64_t lo, int64_t hi) {
  if (!j.is_number_integer() || j.get<int64_t>() < lo || j.get<int64_t>() > hi) {
    Bad(key, fmt::format("a whole number in [{}, {}]", lo, hi), &j);
  }
  return j.get<int64_t>();
}

std::vector<double> Numbers(const nlohmann::json& j, size_t n, const std::string& key,
                            const std::string& what) {
  if (!j.is_array() || j.size() != n) Bad(key, what, &j);
  std::vector<double> v;
  for (size_t i = 0; i < n; ++i) v.push_back(Number(j[i], fmt::format("{}[{}]", key, i)));
  return v;
}

BoxPx BoxFromJson(const nlohmann::json& j, const std::string& key) {
  const std::vector<double> v = Numbers(j, 4, key, "[left, top, width, height]");
  return {v[0], v[1], v[2], v[3]};
}

Eigen::Vector3d VecFromJson(const nlohmann::json& j, const std::string& key) {
  const std::vector<double> v = Numbers(j, 3, key, "[x, y, z]");
  return {v[0], v[1], v[2]};
}

template <typename M>
void MatrixFromJson(const nlohmann::json& j, M& m, const std::string& key) {
  const std::string what = fmt::format("a {} x {} matrix (a list of rows)", m.rows(), m.cols());
  if (!j.is_array() || j.size() != static_cast<size_t>(m.rows())) Bad(key, what, &j);
  for (int r = 0; r < m.rows(); ++r) {
    const std::vector<double> row =
        Numbers(j[static_cast<size_t>(r)], static_cast<size_t>(m.cols()),
                fmt::format("{}[{}]", key, r), what);
    for (int c = 0; c < m.cols(); ++c) m(r, c) = row[static_cast<size_t>(c)];
  }
}

}  // namespace

nlohmann::json GroundTruthToJson(const FrameGroundTruth& gt) {
  const CameraIntrinsics& k = gt.camera.intrinsics;
  nlohmann::json frame;
  frame["frame"] = gt.frame;
  frame["camera"] = {{"width_px", k.width_px},
                     {"height_px", k.height_px},
                     {"K", MatrixToJson(k.K())},
                     {"position_m", VecToJson(gt.camera.pose.position_m)},
                     {"world_from_camera", MatrixToJson(gt.camera.pose.world_from_camera)}};
  frame["image_from_ground"] = MatrixToJson(gt.image_from_ground);
  nlohmann::json objects = nlohmann::json::array();
  for (const GroundTruthObject& o : gt.objects) {
    objects.push_back({{"id", Value(o.id)},
                       {"in_frame", o.in_frame},
                       {"amodal_box", BoxToJson(o.amodal_box)},
                       {"visible_box", BoxToJson(o.visible_box)},
                       {"visible_fraction", o.visible_fraction},
                       {"truncation", o.truncation},
                       {"pixels_visible", o.pixels_visible},
                       {"pixels_total", o.pixels_total},
                       {"position_m", VecToJson(o.position_m)},
                       {"heading_deg", o.heading_deg},
                       {"dimensions_m", VecToJson(o.dimensions_m)}});
  }
  frame["objects"] = std::move(objects);
  return frame;
}

FrameGroundTruth GroundTruthFromJson(const nlohmann::json& j) {
  constexpr int64_t kMaxInt = std::numeric_limits<int32_t>::max();
  if (!j.is_object()) Bad("", "a frame (a JSON object)", &j);
  FrameGroundTruth gt;
  gt.frame =
      static_cast<int>(Whole(Member(j, "frame", "frame", "a frame number"), "frame", 0, kMaxInt));
  const nlohmann::json& camera = Member(j, "camera", "camera", "the frame's camera");
  const auto camera_member = [&](const char* name, const std::string& expected) -> const auto& {
    return Member(camera, name, std::string("camera.") + name, expected);
  };
  Eigen::Matrix3d K;
  MatrixFromJson(camera_member("K", "the intrinsic matrix"), K, "camera.K");
  gt.camera.intrinsics = {
      static_cast<int>(Whole(camera_member("width_px", "a width"), "camera.width_px", 0, kMaxInt)),
      static_cast<int>(
          Whole(camera_member("height_px", "a height"), "camera.height_px", 0, kMaxInt)),
      K(0, 0),
      K(1, 1),
      K(0, 2),
      K(1, 2)};
  gt.camera.pose.position_m =
      VecFromJson(camera_member("position_m", "a position"), "camera.position_m");
  MatrixFromJson(camera_member("world_from_camera", "a rotation"), gt.camera.pose.world_from_camera,
                 "camera.world_from_camera");
  MatrixFromJson(Member(j, "image_from_ground", "image_from_ground", "a homography"),
                 gt.image_from_ground, "image_from_ground");
  const nlohmann::json& objects = Member(j, "objects", "objects", "a list of objects");
  if (!objects.is_array()) Bad("objects", "a list of objects", &objects);
  for (size_t i = 0; i < objects.size(); ++i) {
    const nlohmann::json& o = objects[i];
    const std::string at = fmt::format("objects[{}]", i);
    const auto field = [&](const char* name) -> const nlohmann::json& {
      return Member(o, name, at + "." + name, std::string("the object's ") + name);
    };
    GroundTruthObject obj;
    obj.id = ObjectId{static_cast<int32_t>(Whole(field("id"), at + ".id", 0, kMaxInt))};
    if (!field("in_frame").is_boolean()) Bad(at + ".in_frame", "true or false", &field("in_frame"));
    obj.in_frame = field("in_frame").get<bool>();
    obj.amodal_box = BoxFromJson(field("amodal_box"), at + ".amodal_box");
    obj.visible_box = BoxFromJson(field("visible_box"), at + ".visible_box");
    obj.visible_fraction = Number(field("visible_fraction"), at + ".visible_fraction");
    obj.truncation = Number(field("truncation"), at + ".truncation");
    obj.pixels_visible = Whole(field("pixels_visible"), at + ".pixels_visible", -1,
                               std::numeric_limits<int64_t>::max());
    obj.pixels_total =
        Whole(field("pixels_total"), at + ".pixels_total", -1, std::numeric_limits<int64_t>::max());
    obj.position_m = VecFromJson(field("position_m"), at + ".position_m");
    obj.heading_deg = Number(field("heading_deg"), at + ".heading_deg");
    obj.dimensions_m = VecFromJson(field("dimensions_m"), at + ".dimensions_m");
    gt.objects.push_back(obj);
  }
  return gt;
}

}  // namespace hcpf
