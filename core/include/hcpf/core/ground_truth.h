#pragma once
// Per-frame ground truth: what each target looks like in the image. The world
// model computes it analytically (projected 3-D boxes, visibility by ray
// sampling against occluders); the renderer fills the same types pixel-exactly.

#include <cstdint>
#include <optional>
#include <vector>

#include "hcpf/core/camera.h"
#include "hcpf/core/types.h"
#include "hcpf/core/world.h"

namespace hcpf {

struct GroundTruthObject {
  ObjectId id{};
  bool in_frame = false;          // some of the amodal box is inside the image
  BoxPx amodal_box;               // bounding box of the projected 3-D box (unclipped)
  BoxPx visible_box;              // bounding box of the visible part (empty if none)
  double visible_fraction = 0.0;  // visible / unoccluded target area inside the image
  double truncation = 0.0;        // fraction of the amodal box area outside the image
  int64_t pixels_visible = -1;    // renderer only (-1 = analytic estimate)
  int64_t pixels_total = -1;      // renderer only: pixels of the unoccluded render
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  double heading_deg = 0.0;
  Eigen::Vector3d dimensions_m = Eigen::Vector3d::Zero();
};

struct FrameGroundTruth {
  int frame = 0;  // 0-based
  CameraState camera;
  Eigen::Matrix3d image_from_ground = Eigen::Matrix3d::Identity();  // ground plane z = 0
  std::vector<GroundTruthObject> objects;  // present targets only, in scenario order
};

struct AnalyticVisibilityOptions {
  // Rays cast per target on a grid x grid lattice over its amodal box; the
  // visible fraction is then resolved to about 1/grid² (24² = 576 rays).
  int grid = 24;
};

// Projects every present target at `frame` and estimates its visibility by
// casting rays against occluder boxes and the other targets' boxes.
FrameGroundTruth ComputeGroundTruth(const WorldSpec& world, int frame,
                                    const AnalyticVisibilityOptions& options = {});

// Target `id`'s image motion into `current` from `previous` (the frame
// before), px/frame: the displacement of its amodal box's centre. With
// `without_camera_motion` the part the camera's own motion explains is taken
// out: the previous centre is first carried into `current`'s image through
// the ground plane (current.image_from_ground · previous.image_from_ground⁻¹),
// so what remains is the target's motion over the ground as `current` sees it
// (the velocity a particle needs when the camera's motion is applied to it
// separately). nullopt when the target is absent from either frame or the
// carried centre is not finite (the ground plane seen edge-on).
std::optional<Eigen::Vector2d> ImageVelocity(const FrameGroundTruth& previous,
                                             const FrameGroundTruth& current, ObjectId id,
                                             bool without_camera_motion);

// Bounding box of the projection of a 3-D box; `all_in_front` is false when a
// corner lies behind the camera (the box is then not usable).
BoxPx ProjectBox(const CameraState& camera, const OrientedBox& box, bool* all_in_front);

}  // namespace hcpf
