#pragma once
// The world model: a plain description of a scene (terrain, sun, occluders,
// targets and their paths, the camera path) and its evaluation at a frame,
// without pixels. scenarios/ fills a WorldSpec from YAML; the renderer draws
// it; ground_truth.h projects it.

#include <Eigen/Core>
#include <array>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hcpf/core/camera.h"
#include "hcpf/core/fields.h"
#include "hcpf/core/types.h"

namespace hcpf {

// Height field: a seeded sum of four plane waves (wavelengths 80, 40, 20 and
// 10 m) scaled so heights stay within [-relief_m/2, +relief_m/2].
struct TerrainSpec {
  Eigen::Vector2d size_m{400.0, 400.0};  // extent in x and y, centred on the origin
  double relief_m = 0.0;                 // peak-to-peak bound of the height field
  std::string texture = "grass";         // grass | dirt | asphalt | sand
  bool roads = false;                    // draw asphalt roads along target paths
  uint64_t seed = 0;                     // derived from the scenario seed

  // The declared fields (size_m, relief_m, texture, roads; core/fields.h).
  static std::span<const Field<TerrainSpec>> Fields();
  static std::vector<std::string_view> TextureNames();
  double HeightAt(double x_m, double y_m) const;
};

struct SunSpec {
  double azimuth_deg = 135.0;   // clockwise from north (y) towards east (x)
  double elevation_deg = 35.0;  // above the horizon
  bool shadows = true;
  // The declared fields (core/fields.h).
  static std::span<const Field<SunSpec>> Fields();
  // Unit vector pointing from the ground towards the sun.
  Eigen::Vector3d Direction() const;
};

// An oriented box in the world: centre, half sizes along its own axes, and a
// yaw (counter-clockwise from +x, degrees) about +z.
struct OrientedBox {
  Eigen::Vector3d centre_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d half_size_m = Eigen::Vector3d::Ones();
  double yaw_deg = 0.0;
  // Ray-box intersection (slab method): smallest t >= 0 with origin + t*dir
  // inside the box, or nullopt.
  std::optional<double> Intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& dir) const;
  std::array<Eigen::Vector3d, 8> Corners() const;
};

enum class OccluderKind { kBridge, kBuilding, kTree, kMesh };
template <>
struct EnumNames<OccluderKind> {
  static constexpr std::array kNames = {
      std::pair{OccluderKind::kBridge, std::string_view("bridge")},
      std::pair{OccluderKind::kBuilding, std::string_view("building")},
      std::pair{OccluderKind::kTree, std::string_view("tree")},
      std::pair{OccluderKind::kMesh, std::string_view("mesh")}};
};

struct OccluderSpec {
  OccluderKind kind = OccluderKind::kBuilding;
  // bridge: deck from `from` to `to` (x, y) at `height_m`, `width_m` wide.
  Eigen::Vector2d from_m = Eigen::Vector2d::Zero();
  Eigen::Vector2d to_m = Eigen::Vector2d::Zero();
  double width_m = 8.0;
  double height_m = 6.0;  // bridge deck top / tree height
  // building / tree / mesh: position; building: size (x, y, z).
  Eigen::Vector2d at_m = Eigen::Vector2d::Zero();
  Eigen::Vector3d size_m{10.0, 10.0, 10.0};
  double yaw_deg = 0.0;
  std::string model;  // mesh occluders: path of the model file
  // mesh occluders: XXH3-128 of the model's content (the loader fills it,
  // scenarios/models.h, ModelDigest), so the resolved scenario names the
  // model by what it holds as well as where it lies.
  std::string model_digest;
  double scale = 1.0;  // mesh occluders: uniform scale
  // The boxes this occluder is made of, for analytic visibility (and the
  // renderer's own primitive meshes). Mesh occluders are their model's
  // bounding box (size_m, filled by the loader), standing on the terrain.
  std::vector<OrientedBox> Boxes(const TerrainSpec& terrain) const;
};

// A stop along a waypoint path: wait `duration_s` after `at_m` metres travelled.
struct PathStop {
  double at_m = 0.0;
  double duration_s = 0.0;
};

enum class PathKind { kWaypoints, kConstantTurn };
template <>
struct EnumNames<PathKind> {
  static constexpr std::array kNames = {
      std::pair{PathKind::kWaypoints, std::string_view("waypoints")},
      std::pair{PathKind::kConstantTurn, std::string_view("constant_turn")}};
};

struct TargetPathSpec {
  PathKind kind = PathKind::kWaypoints;
  std::vector<Eigen::Vector2d> waypoints_m;  // kWaypoints (one point = static target)
  double speed_mps = 5.0;
  std::vector<PathStop> stops;                        // kWaypoints: stop-and-go
  Eigen::Vector2d start_m = Eigen::Vector2d::Zero();  // kConstantTurn
  double heading_deg = 0.0;      // kConstantTurn start heading; static-target heading
  double turn_rate_deg_s = 0.0;  // kConstantTurn, positive = counter-clockwise
  int start_frame = 0;           // first frame the target exists
  int end_frame = -1;            // last frame it exists (-1 = to the end)
  bool vanish_at_end = false;    // kWaypoints: leave the scene at the last waypoint
};

struct TargetSpec {
  ObjectId id{};
  std::string model;                            // vehicle model file ("" = plain box)
  std::string model_digest;                     // its content (as OccluderSpec's)
  Eigen::Vector3d tint{0.5, 0.5, 0.5};          // RGB in [0, 1]
  Eigen::Vector3d dimensions_m{4.5, 2.0, 1.6};  // length, width, height
  TargetPathSpec path;
};

struct CameraKeyframe {
  int frame = 0;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d look_at_m = Eigen::Vector3d::Zero();
};

struct CameraSpec {
  int width_px = 640;
  int height_px = 480;
  double hfov_deg = 40.0;
  std::vector<CameraKeyframe> path;  // sorted by frame, at least one
  double shake_px = 0.0;             // std. dev. of per-frame image jitter
  uint64_t shake_seed = 0;           // derived from the scenario seed
};

struct WorldSpec {
  int frames = 0;
  double fps = 30.0;
  TerrainSpec terrain;
  SunSpec sun;
  std::vector<OccluderSpec> occluders;
  std::vector<TargetSpec> targets;
  CameraSpec camera;
};

// A target's state at one frame.
struct TargetPose {
  bool present = false;
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();  // centre of the base, on the terrain
  double heading_deg = 0.0;  // direction of travel, counter-clockwise from +x
  double speed_mps = 0.0;
  // The target's 3-D box.
  OrientedBox Box(const Eigen::Vector3d& dimensions_m) const;
};

// Position along a polyline path after travelling `distance_m` (clamped), with
// the heading of the segment it is on.
TargetPose EvaluatePath(const TargetPathSpec& path, int frame, double fps);
TargetPose EvaluateTarget(const TargetSpec& target, const TerrainSpec& terrain, int frame,
                          double fps);

// The camera's position and look-at point at a frame, interpolated with a
// C1 cubic (Catmull–Rom tangents, one-sided at the ends) between keyframes.
struct CameraPathPoint {
  Eigen::Vector3d position_m;
  Eigen::Vector3d look_at_m;
};
CameraPathPoint InterpolateCamera(const CameraSpec& camera, int frame);

// Camera at a frame: its pose looking from InterpolateCamera's position at
// its look-at point (they must differ), then the seeded shake added to the
// optical centre.
CameraState EvaluateCamera(const CameraSpec& camera, int frame);

// Length of a polyline.
double PathLength(const std::vector<Eigen::Vector2d>& waypoints_m);

}  // namespace hcpf
