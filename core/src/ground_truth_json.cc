#include "hcpf/core/ground_truth_json.h"

#include <fmt/format.h>

#include <array>
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
// truncated without a word). A field's path in the frame ("camera.K[1][2]",
// "objects[3].amodal_box") is put together only for an error: building it
// for every field made reading ten times slower (a review).
struct Path {
  const char* section = "";  // "", "camera" or "objects"
  int object = -1;           // objects[object]
  const char* field = "";    // a key of the section
  int i = -1, j = -1;        // list items below it
  Path At(int index) const {
    Path p = *this;
    (p.i < 0 ? p.i : p.j) = index;
    return p;
  }
  std::string str() const {
    std::string s = section;
    if (object >= 0) s += fmt::format("[{}]", object);
    if (*field != '\0') s += (s.empty() ? "" : ".") + std::string(field);
    if (i >= 0) s += fmt::format("[{}]", i);
    if (j >= 0) s += fmt::format("[{}]", j);
    return s;
  }
};

[[noreturn]] void Bad(const Path& key, const std::string& expected, const nlohmann::json* found) {
  std::string text = found == nullptr ? std::string("nothing") : found->dump();
  if (text.size() > 60) text = text.substr(0, 57) + "...";
  throw InputError(SourceLocation{"", 0, 0, key.str()}, expected, text);
}

// `expected` nullptr: "the object's <field>".
const nlohmann::json& Member(const nlohmann::json& j, const Path& key, const char* expected) {
  if (j.is_object()) {
    const auto it = j.find(key.field);
    if (it != j.end()) return *it;
  }
  Bad(key, expected != nullptr ? expected : fmt::format("the object's {}", key.field), nullptr);
}

double Number(const nlohmann::json& j, const Path& key) {
  if (!j.is_number()) Bad(key, "a number", &j);
  return j.get<double>();
}

int64_t Whole(const nlohmann::json& j, const Path& key, int64_t lo, int64_t hi) {
  if (!j.is_number_integer() || j.get<int64_t>() < lo || j.get<int64_t>() > hi) {
    Bad(key, fmt::format("a whole number in [{}, {}]", lo, hi), &j);
  }
  return j.get<int64_t>();
}

template <size_t N>
std::array<double, N> Numbers(const nlohmann::json& j, const Path& key, const char* what) {
  if (!j.is_array() || j.size() != N) Bad(key, what, &j);
  std::array<double, N> v{};
  for (size_t i = 0; i < N; ++i) v[i] = Number(j[i], key.At(static_cast<int>(i)));
  return v;
}

BoxPx BoxFromJson(const nlohmann::json& j, const Path& key) {
  const auto v = Numbers<4>(j, key, "[left, top, width, height]");
  return {v[0], v[1], v[2], v[3]};
}

Eigen::Vector3d VecFromJson(const nlohmann::json& j, const Path& key) {
  const auto v = Numbers<3>(j, key, "[x, y, z]");
  return {v[0], v[1], v[2]};
}

// A 3 x 3 matrix as a list of rows.
void MatrixFromJson(const nlohmann::json& j, Eigen::Matrix3d& m, const Path& key) {
  const char* what = "a 3 x 3 matrix (a list of rows)";
  if (!j.is_array() || j.size() != 3) Bad(key, what, &j);
  for (int r = 0; r < 3; ++r) {
    const auto row = Numbers<3>(j[static_cast<size_t>(r)], key.At(r), what);
    for (int c = 0; c < 3; ++c) m(r, c) = row[static_cast<size_t>(c)];
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
  constexpr int64_t kMaxCount = std::numeric_limits<int64_t>::max();
  if (!j.is_object()) Bad(Path{}, "a frame (a JSON object)", &j);
  FrameGroundTruth gt;
  const Path frame{.field = "frame"};
  gt.frame = static_cast<int>(Whole(Member(j, frame, "a frame number"), frame, 0, kMaxInt));
  const nlohmann::json& camera = Member(j, {.field = "camera"}, "the frame's camera");
  const auto in_camera = [&](const char* name, const char* expected) -> const nlohmann::json& {
    return Member(camera, {.section = "camera", .field = name}, expected);
  };
  Eigen::Matrix3d K;
  MatrixFromJson(in_camera("K", "the intrinsic matrix"), K, {.section = "camera", .field = "K"});
  const Path width{.section = "camera", .field = "width_px"};
  const Path height{.section = "camera", .field = "height_px"};
  gt.camera.intrinsics = {
      static_cast<int>(Whole(in_camera("width_px", "a width"), width, 0, kMaxInt)),
      static_cast<int>(Whole(in_camera("height_px", "a height"), height, 0, kMaxInt)),
      K(0, 0),
      K(1, 1),
      K(0, 2),
      K(1, 2)};
  gt.camera.pose.position_m = VecFromJson(in_camera("position_m", "a position"),
                                          {.section = "camera", .field = "position_m"});
  MatrixFromJson(in_camera("world_from_camera", "a rotation"), gt.camera.pose.world_from_camera,
                 {.section = "camera", .field = "world_from_camera"});
  const Path ground{.field = "image_from_ground"};
  MatrixFromJson(Member(j, ground, "a homography"), gt.image_from_ground, ground);
  const Path list{.field = "objects"};
  const nlohmann::json& objects = Member(j, list, "a list of objects");
  if (!objects.is_array()) Bad(list, "a list of objects", &objects);
  gt.objects.reserve(objects.size());
  for (size_t i = 0; i < objects.size(); ++i) {
    const nlohmann::json& o = objects[i];
    const auto at = [i](const char* name) {
      return Path{.section = "objects", .object = static_cast<int>(i), .field = name};
    };
    const auto field = [&](const char* name) -> const nlohmann::json& {
      return Member(o, at(name), nullptr);
    };
    GroundTruthObject obj;
    obj.id = ObjectId{static_cast<int32_t>(Whole(field("id"), at("id"), 0, kMaxInt))};
    const nlohmann::json& in_frame = field("in_frame");
    if (!in_frame.is_boolean()) Bad(at("in_frame"), "true or false", &in_frame);
    obj.in_frame = in_frame.get<bool>();
    obj.amodal_box = BoxFromJson(field("amodal_box"), at("amodal_box"));
    obj.visible_box = BoxFromJson(field("visible_box"), at("visible_box"));
    obj.visible_fraction = Number(field("visible_fraction"), at("visible_fraction"));
    obj.truncation = Number(field("truncation"), at("truncation"));
    obj.pixels_visible = Whole(field("pixels_visible"), at("pixels_visible"), -1, kMaxCount);
    obj.pixels_total = Whole(field("pixels_total"), at("pixels_total"), -1, kMaxCount);
    obj.position_m = VecFromJson(field("position_m"), at("position_m"));
    obj.heading_deg = Number(field("heading_deg"), at("heading_deg"));
    obj.dimensions_m = VecFromJson(field("dimensions_m"), at("dimensions_m"));
    gt.objects.push_back(obj);
  }
  return gt;
}

}  // namespace hcpf
