#include "writers.h"

#include <fmt/format.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <nlohmann/json.hpp>

#include "hcpf/core/error.h"

namespace hcpf::scenarios {

std::string FormatGroundTruthMot(const std::vector<FrameGroundTruth>& frames) {
  std::string out;
  for (const FrameGroundTruth& f : frames) {
    for (const GroundTruthObject& o : f.objects) {
      if (!o.in_frame) continue;
      const BoxPx& b = o.amodal_box;
      out += fmt::format("{},{},{:.3f},{:.3f},{:.3f},{:.3f},1,1,{:.4f}\n", f.frame + 1, Value(o.id),
                         b.left + 1.0, b.top + 1.0, b.width, b.height, o.visible_fraction);
    }
  }
  return out;
}

std::string FormatDetectionsMot(const std::vector<Observation>& observations) {
  std::string out;
  for (const Observation& obs : observations) {
    for (const Detection& d : obs.detections) {
      out += fmt::format("{},-1,{:.3f},{:.3f},{:.3f},{:.3f},{:.4f},-1,-1,-1\n", obs.frame + 1,
                         d.box.left + 1.0, d.box.top + 1.0, d.box.width, d.box.height, d.score);
    }
  }
  return out;
}

std::string FormatSeqinfo(const Scenario& s) {
  return fmt::format(
      "[Sequence]\nname={}\nimDir=frames\nframeRate={}\nseqLength={}\nimWidth={}\nimHeight={}\n"
      "imExt=.png\n",
      s.name, s.world.fps, s.world.frames, s.world.camera.width_px, s.world.camera.height_px);
}

namespace {

nlohmann::json Box(const BoxPx& b) { return {b.left, b.top, b.width, b.height}; }
template <typename M>
nlohmann::json Matrix(const M& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < m.rows(); ++r) {
    nlohmann::json row = nlohmann::json::array();
    for (int c = 0; c < m.cols(); ++c) row.push_back(m(r, c));
    rows.push_back(row);
  }
  return rows;
}
nlohmann::json Vec(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

std::string FormatGroundTruthJson(const Scenario& s, const std::vector<FrameGroundTruth>& frames) {
  nlohmann::json root;
  root["format"] = "hcpf-gt/1";
  root["scenario"] = s.name;
  root["conventions"] = {
      {"frame", "0-based here; MOT files are 1-based"},
      {"boxes", "[left, top, width, height] in pixels, pixel (0,0) covers [0,1)x[0,1)"},
      {"world", "x east, y north, z up, metres"},
      {"camera", "OpenCV: x right, y down, z forward; world_from_camera columns = camera axes"},
      {"image_from_ground", "homography of the plane z = 0 to homogeneous pixels"},
  };
  nlohmann::json list = nlohmann::json::array();
  for (const FrameGroundTruth& f : frames) {
    const CameraIntrinsics& k = f.camera.intrinsics;
    nlohmann::json frame;
    frame["frame"] = f.frame;
    frame["camera"] = {{"width_px", k.width_px},
                       {"height_px", k.height_px},
                       {"K", Matrix(k.K())},
                       {"position_m", Vec(f.camera.pose.position_m)},
                       {"world_from_camera", Matrix(f.camera.pose.world_from_camera)}};
    frame["image_from_ground"] = Matrix(f.image_from_ground);
    nlohmann::json objects = nlohmann::json::array();
    for (const GroundTruthObject& o : f.objects) {
      objects.push_back({{"id", Value(o.id)},
                         {"in_frame", o.in_frame},
                         {"amodal_box", Box(o.amodal_box)},
                         {"visible_box", Box(o.visible_box)},
                         {"visible_fraction", o.visible_fraction},
                         {"truncation", o.truncation},
                         {"pixels_visible", o.pixels_visible},
                         {"pixels_total", o.pixels_total},
                         {"position_m", Vec(o.position_m)},
                         {"heading_deg", o.heading_deg},
                         {"dimensions_m", Vec(o.dimensions_m)}});
    }
    frame["objects"] = std::move(objects);
    list.push_back(std::move(frame));
  }
  root["frames"] = std::move(list);
  return root.dump(1) + "\n";
}

void WriteTextFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw RunError(fmt::format("cannot write {}: {}", path, std::strerror(errno)));
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  out.close();
  if (!out) throw RunError(fmt::format("writing {} failed: {}", path, std::strerror(errno)));
}

}  // namespace hcpf::scenarios
