#include "hcpf/core/ground_truth_json.h"

namespace hcpf {
namespace {

nlohmann::json BoxToJson(const BoxPx& b) { return {b.left, b.top, b.width, b.height}; }

BoxPx BoxFromJson(const nlohmann::json& j) {
  return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>(),
          j.at(3).get<double>()};
}

nlohmann::json VecToJson(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

Eigen::Vector3d VecFromJson(const nlohmann::json& j) {
  return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()};
}

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

template <typename M>
void MatrixFromJson(const nlohmann::json& j, M& m) {
  for (int r = 0; r < m.rows(); ++r) {
    for (int c = 0; c < m.cols(); ++c) m(r, c) = j.at(r).at(c).template get<double>();
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
  FrameGroundTruth gt;
  gt.frame = j.at("frame").get<int>();
  const nlohmann::json& camera = j.at("camera");
  Eigen::Matrix3d K;
  MatrixFromJson(camera.at("K"), K);
  gt.camera.intrinsics = {camera.at("width_px").get<int>(),
                          camera.at("height_px").get<int>(),
                          K(0, 0),
                          K(1, 1),
                          K(0, 2),
                          K(1, 2)};
  gt.camera.pose.position_m = VecFromJson(camera.at("position_m"));
  MatrixFromJson(camera.at("world_from_camera"), gt.camera.pose.world_from_camera);
  MatrixFromJson(j.at("image_from_ground"), gt.image_from_ground);
  for (const nlohmann::json& o : j.at("objects")) {
    GroundTruthObject obj;
    obj.id = ObjectId{o.at("id").get<int32_t>()};
    obj.in_frame = o.at("in_frame").get<bool>();
    obj.amodal_box = BoxFromJson(o.at("amodal_box"));
    obj.visible_box = BoxFromJson(o.at("visible_box"));
    obj.visible_fraction = o.at("visible_fraction").get<double>();
    obj.truncation = o.at("truncation").get<double>();
    obj.pixels_visible = o.at("pixels_visible").get<int64_t>();
    obj.pixels_total = o.at("pixels_total").get<int64_t>();
    obj.position_m = VecFromJson(o.at("position_m"));
    obj.heading_deg = o.at("heading_deg").get<double>();
    obj.dimensions_m = VecFromJson(o.at("dimensions_m"));
    gt.objects.push_back(obj);
  }
  return gt;
}

}  // namespace hcpf
