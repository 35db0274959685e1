#include "hcpf/core/world.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "hcpf/core/check.h"
#include "hcpf/core/rng.h"

namespace hcpf {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;
constexpr double kRadToDeg = 180.0 / std::numbers::pi;
constexpr double kBridgeDeckThicknessM = 1.0;
constexpr double kBridgePierLengthM = 1.5;

Eigen::Vector3d RotateZ(const Eigen::Vector3d& v, double yaw_rad) {
  const double c = std::cos(yaw_rad);
  const double s = std::sin(yaw_rad);
  return {c * v.x() - s * v.y(), s * v.x() + c * v.y(), v.z()};
}

}  // namespace

std::vector<std::string_view> TerrainSpec::TextureNames() {
  return {"grass", "dirt", "asphalt", "sand"};
}

std::span<const Field<TerrainSpec>> TerrainSpec::Fields() {
  using O = TerrainSpec;
  static const std::vector<Field<O>> fields = {
      VectorField<&O::size_m>("size_m", "x, y", Closed(1, 1e6), "m",
                              "extent of the ground, centred on the origin"),
      NumberField("relief_m", &O::relief_m, Closed(0, 1000), "m",
                  "peak-to-peak bound of the height field"),
      WordField<&O::texture, &TerrainSpec::TextureNames>("texture", "ground texture"),
      FlagField("roads", &O::roads, "draw asphalt roads along target paths (renderer)"),
  };
  return fields;
}

std::span<const Field<SunSpec>> SunSpec::Fields() {
  using O = SunSpec;
  static const std::vector<Field<O>> fields = {
      NumberField("azimuth_deg", &O::azimuth_deg, Closed(0, 360), "deg", "clockwise from north"),
      NumberField("elevation_deg", &O::elevation_deg, Closed(1, 90), "deg", "above the horizon"),
      FlagField("shadows", &O::shadows, "cast shadows (renderer)"),
  };
  return fields;
}

double TerrainSpec::HeightAt(double x_m, double y_m) const {
  if (relief_m <= 0.0) return 0.0;
  static constexpr double kWavelengthM[4] = {80.0, 40.0, 20.0, 10.0};
  static constexpr double kAmplitude[4] = {1.0, 0.5, 0.25, 0.125};
  static constexpr double kAmplitudeSum = 1.875;
  Rng rng = Rng(seed).Fork("terrain/waves");
  double h = 0.0;
  for (int i = 0; i < 4; ++i) {
    const double theta = 2.0 * std::numbers::pi * rng.Uniform();
    const double phase = 2.0 * std::numbers::pi * rng.Uniform();
    const double along = std::cos(theta) * x_m + std::sin(theta) * y_m;
    h += kAmplitude[i] * std::sin(2.0 * std::numbers::pi * along / kWavelengthM[i] + phase);
  }
  return 0.5 * relief_m * h / kAmplitudeSum;
}

Eigen::Vector3d SunSpec::Direction() const {
  const double az = azimuth_deg * kDegToRad;
  const double el = elevation_deg * kDegToRad;
  return {std::sin(az) * std::cos(el), std::cos(az) * std::cos(el), std::sin(el)};
}

std::optional<double> OrientedBox::Intersect(const Eigen::Vector3d& origin,
                                             const Eigen::Vector3d& dir) const {
  const double yaw = -yaw_deg * kDegToRad;
  const Eigen::Vector3d o = RotateZ(origin - centre_m, yaw);
  const Eigen::Vector3d d = RotateZ(dir, yaw);
  double t_min = 0.0;
  double t_max = std::numeric_limits<double>::infinity();
  for (int axis = 0; axis < 3; ++axis) {
    const double h = half_size_m[axis];
    if (std::abs(d[axis]) < 1e-15) {
      if (o[axis] < -h || o[axis] > h) return std::nullopt;
      continue;
    }
    double t0 = (-h - o[axis]) / d[axis];
    double t1 = (h - o[axis]) / d[axis];
    if (t0 > t1) std::swap(t0, t1);
    t_min = std::max(t_min, t0);
    t_max = std::min(t_max, t1);
    if (t_min > t_max) return std::nullopt;
  }
  return t_min;
}

std::array<Eigen::Vector3d, 8> OrientedBox::Corners() const {
  std::array<Eigen::Vector3d, 8> corners;
  const double yaw = yaw_deg * kDegToRad;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d local((i & 1) ? half_size_m.x() : -half_size_m.x(),
                                (i & 2) ? half_size_m.y() : -half_size_m.y(),
                                (i & 4) ? half_size_m.z() : -half_size_m.z());
    corners[i] = centre_m + RotateZ(local, yaw);
  }
  return corners;
}

std::vector<OrientedBox> OccluderSpec::Boxes(const TerrainSpec& terrain) const {
  std::vector<OrientedBox> boxes;
  switch (kind) {
    case OccluderKind::kBridge: {
      const Eigen::Vector2d mid = 0.5 * (from_m + to_m);
      const Eigen::Vector2d span = to_m - from_m;
      const double yaw = std::atan2(span.y(), span.x()) * kRadToDeg;
      const double ground = terrain.HeightAt(mid.x(), mid.y());
      OrientedBox deck;
      deck.centre_m = {mid.x(), mid.y(), ground + height_m - 0.5 * kBridgeDeckThicknessM};
      deck.half_size_m = {0.5 * span.norm(), 0.5 * width_m, 0.5 * kBridgeDeckThicknessM};
      deck.yaw_deg = yaw;
      boxes.push_back(deck);
      const double pier_height = std::max(0.0, height_m - kBridgeDeckThicknessM);
      if (pier_height > 0.0) {
        for (const Eigen::Vector2d& end : {from_m, to_m}) {
          OrientedBox pier;
          pier.centre_m = {end.x(), end.y(), ground + 0.5 * pier_height};
          pier.half_size_m = {0.5 * kBridgePierLengthM, 0.5 * width_m, 0.5 * pier_height};
          pier.yaw_deg = yaw;
          boxes.push_back(pier);
        }
      }
      break;
    }
    case OccluderKind::kBuilding:
    case OccluderKind::kMesh: {
      const Eigen::Vector3d size = kind == OccluderKind::kMesh ? size_m * scale : size_m;
      OrientedBox b;
      b.centre_m = {at_m.x(), at_m.y(), terrain.HeightAt(at_m.x(), at_m.y()) + 0.5 * size.z()};
      b.half_size_m = 0.5 * size;
      b.yaw_deg = yaw_deg;
      boxes.push_back(b);
      break;
    }
    case OccluderKind::kTree: {
      // Trunk 0.4 m square up to 40 % of the height; canopy a box 60 % of the
      // height wide from 35 % of the height to the top.
      const double ground = terrain.HeightAt(at_m.x(), at_m.y());
      OrientedBox trunk;
      trunk.centre_m = {at_m.x(), at_m.y(), ground + 0.2 * height_m};
      trunk.half_size_m = {0.2, 0.2, 0.2 * height_m};
      boxes.push_back(trunk);
      OrientedBox canopy;
      canopy.centre_m = {at_m.x(), at_m.y(), ground + 0.675 * height_m};
      canopy.half_size_m = {0.3 * height_m, 0.3 * height_m, 0.325 * height_m};
      boxes.push_back(canopy);
      break;
    }
  }
  return boxes;
}

double PathLength(const std::vector<Eigen::Vector2d>& waypoints_m) {
  double length = 0.0;
  for (size_t i = 1; i < waypoints_m.size(); ++i) {
    length += (waypoints_m[i] - waypoints_m[i - 1]).norm();
  }
  return length;
}

OrientedBox TargetPose::Box(const Eigen::Vector3d& dimensions_m) const {
  OrientedBox b;
  b.centre_m = position_m + Eigen::Vector3d(0.0, 0.0, 0.5 * dimensions_m.z());
  b.half_size_m = 0.5 * dimensions_m;
  b.yaw_deg = heading_deg;
  return b;
}

TargetPose EvaluatePath(const TargetPathSpec& path, int frame, double fps) {
  TargetPose pose;
  if (frame < path.start_frame || (path.end_frame >= 0 && frame > path.end_frame)) return pose;
  pose.present = true;
  const double t = (frame - path.start_frame) / fps;

  if (path.kind == PathKind::kConstantTurn) {
    const double theta0 = path.heading_deg * kDegToRad;
    const double omega = path.turn_rate_deg_s * kDegToRad;
    const double v = path.speed_mps;
    Eigen::Vector2d p;
    if (std::abs(omega) < 1e-12) {
      p = path.start_m + v * t * Eigen::Vector2d(std::cos(theta0), std::sin(theta0));
    } else {
      const double theta = theta0 + omega * t;
      p = path.start_m + (v / omega) * Eigen::Vector2d(std::sin(theta) - std::sin(theta0),
                                                       std::cos(theta0) - std::cos(theta));
    }
    pose.position_m = {p.x(), p.y(), 0.0};
    pose.heading_deg = path.heading_deg + path.turn_rate_deg_s * t;
    pose.speed_mps = v;
    return pose;
  }

  const auto& w = path.waypoints_m;
  HCPF_CHECK(!w.empty()) << "waypoint path without waypoints";
  if (w.size() == 1) {
    pose.position_m = {w[0].x(), w[0].y(), 0.0};
    pose.heading_deg = path.heading_deg;
    return pose;
  }
  const double length = PathLength(w);
  // Distance travelled after t seconds, waiting at each stop.
  double distance = 0.0;
  double time_left = t;
  bool stopped = false;
  for (const PathStop& stop : path.stops) {
    const double leg = std::max(0.0, stop.at_m - distance);
    if (time_left * path.speed_mps <= leg) break;
    time_left -= leg / path.speed_mps;
    distance = stop.at_m;
    if (time_left <= stop.duration_s) {
      stopped = true;
      time_left = 0.0;
      break;
    }
    time_left -= stop.duration_s;
  }
  distance += time_left * path.speed_mps;
  pose.speed_mps = stopped ? 0.0 : path.speed_mps;
  if (distance >= length) {
    distance = length;
    pose.speed_mps = 0.0;
    if (path.vanish_at_end) {
      pose.present = false;
      return pose;
    }
  }
  double walked = 0.0;
  for (size_t i = 1; i < w.size(); ++i) {
    const Eigen::Vector2d seg = w[i] - w[i - 1];
    const double seg_len = seg.norm();
    const bool last = i + 1 == w.size();
    if (distance < walked + seg_len || last) {
      const double f = seg_len > 0.0 ? std::clamp((distance - walked) / seg_len, 0.0, 1.0) : 0.0;
      const Eigen::Vector2d p = w[i - 1] + f * seg;
      pose.position_m = {p.x(), p.y(), 0.0};
      pose.heading_deg = std::atan2(seg.y(), seg.x()) * kRadToDeg;
      break;
    }
    walked += seg_len;
  }
  return pose;
}

TargetPose EvaluateTarget(const TargetSpec& target, const TerrainSpec& terrain, int frame,
                          double fps) {
  TargetPose pose = EvaluatePath(target.path, frame, fps);
  if (pose.present) {
    pose.position_m.z() = terrain.HeightAt(pose.position_m.x(), pose.position_m.y());
  }
  return pose;
}

namespace {

// Catmull–Rom tangent at keyframe i (units per frame), one-sided at the ends.
template <typename Getter>
Eigen::Vector3d Tangent(const std::vector<CameraKeyframe>& keys, size_t i, Getter get) {
  const size_t n = keys.size();
  const size_t a = i == 0 ? 0 : i - 1;
  const size_t b = i + 1 >= n ? n - 1 : i + 1;
  return (get(keys[b]) - get(keys[a])) / static_cast<double>(keys[b].frame - keys[a].frame);
}

template <typename Getter>
Eigen::Vector3d Interpolate(const std::vector<CameraKeyframe>& keys, double frame, Getter get) {
  if (keys.size() == 1 || frame <= keys.front().frame) return get(keys.front());
  if (frame >= keys.back().frame) return get(keys.back());
  size_t i = 0;
  while (i + 1 < keys.size() && keys[i + 1].frame <= frame) ++i;
  const double h = keys[i + 1].frame - keys[i].frame;
  const double s = (frame - keys[i].frame) / h;
  const double s2 = s * s;
  const double s3 = s2 * s;
  const double h00 = 2 * s3 - 3 * s2 + 1;
  const double h10 = s3 - 2 * s2 + s;
  const double h01 = -2 * s3 + 3 * s2;
  const double h11 = s3 - s2;
  return h00 * get(keys[i]) + h10 * h * Tangent(keys, i, get) + h01 * get(keys[i + 1]) +
         h11 * h * Tangent(keys, i + 1, get);
}

}  // namespace

CameraPathPoint InterpolateCamera(const CameraSpec& camera, int frame) {
  HCPF_CHECK(!camera.path.empty()) << "camera path without keyframes";
  const auto position = [](const CameraKeyframe& k) { return k.position_m; };
  const auto look_at = [](const CameraKeyframe& k) { return k.look_at_m; };
  return {Interpolate(camera.path, frame, position), Interpolate(camera.path, frame, look_at)};
}

CameraState EvaluateCamera(const CameraSpec& camera, int frame) {
  const CameraPathPoint at = InterpolateCamera(camera, frame);
  CameraState state;
  state.intrinsics =
      CameraIntrinsics::FromHorizontalFov(camera.width_px, camera.height_px, camera.hfov_deg);
  state.pose = CameraPose::LookAt(at.position_m, at.look_at_m);
  if (camera.shake_px > 0.0) {
    Rng shake = Rng(camera.shake_seed).Fork("camera/shake", frame);
    state.intrinsics.cx_px += shake.Normal(0.0, camera.shake_px);
    state.intrinsics.cy_px += shake.Normal(0.0, camera.shake_px);
  }
  return state;
}

}  // namespace hcpf
