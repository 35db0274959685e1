#include "hcpf/core/ground_truth.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace hcpf {

BoxPx ProjectBox(const CameraState& camera, const OrientedBox& box, bool* all_in_front) {
  double x0 = std::numeric_limits<double>::infinity();
  double y0 = x0;
  double x1 = -x0;
  double y1 = -x0;
  bool ok = true;
  for (const Eigen::Vector3d& corner : box.Corners()) {
    const auto p = camera.Project(corner);
    if (!p) {
      ok = false;
      continue;
    }
    x0 = std::min(x0, p->x());
    y0 = std::min(y0, p->y());
    x1 = std::max(x1, p->x());
    y1 = std::max(y1, p->y());
  }
  if (all_in_front != nullptr) *all_in_front = ok;
  if (!ok) return {};
  return BoxPx::FromCorners(x0, y0, x1, y1);
}

FrameGroundTruth ComputeGroundTruth(const WorldSpec& world, int frame,
                                    const AnalyticVisibilityOptions& options) {
  FrameGroundTruth gt;
  gt.frame = frame;
  gt.camera = EvaluateCamera(world.camera, frame);
  gt.image_from_ground = gt.camera.ImageFromGround(0.0);

  // What may block a ray: every occluder box and every present target's box,
  // each with the image box a ray must pass through to hit it. A box wholly
  // in front of the camera is convex and so is its image (a pinhole's), the
  // hull of its corners' images: a ray through (u, v) hits it only where
  // (u, v) lies inside its projected box. Padded against rounding, that test
  // skips only rays that cannot hit; a box reaching behind the camera has no
  // image box and is tested on every ray. Testing every ray against every
  // box made the truth quadratic in targets (a scale audit: 160 targets x 500
  // frames took 65 s).
  struct Blocker {
    OrientedBox box;
    BoxPx projected;             // ProjectBox: a target's amodal box
    bool in_front = false;       // every corner in front of the camera
    std::optional<BoxPx> image;  // padded; nullopt: test every ray
  };
  const auto blocker = [&](const OrientedBox& box) {
    Blocker b{.box = box};
    b.projected = ProjectBox(gt.camera, box, &b.in_front);
    if (b.in_front) {
      const BoxPx& p = b.projected;
      const double pad = 1e-3 + 1e-9 * std::max({std::abs(p.left), std::abs(p.top),
                                                 std::abs(p.right()), std::abs(p.bottom())});
      b.image = BoxPx::FromCorners(p.left - pad, p.top - pad, p.right() + pad, p.bottom() + pad);
    }
    return b;
  };
  const auto may_hit = [](const Blocker& b, double u, double v) {
    return !b.image || (u >= b.image->left && u <= b.image->right() && v >= b.image->top &&
                        v <= b.image->bottom());
  };
  const auto may_hit_any = [](const Blocker& b, const BoxPx& region) {
    return !b.image || (b.image->left <= region.right() && region.left <= b.image->right() &&
                        b.image->top <= region.bottom() && region.top <= b.image->bottom());
  };
  std::vector<Blocker> occluders;
  for (const OccluderSpec& o : world.occluders) {
    for (const OrientedBox& b : o.Boxes(world.terrain)) occluders.push_back(blocker(b));
  }
  struct Present {
    const TargetSpec* spec;
    TargetPose pose;
    Blocker blocker;
  };
  std::vector<Present> present;
  for (const TargetSpec& t : world.targets) {
    const TargetPose pose = EvaluateTarget(t, world.terrain, frame, world.fps);
    if (pose.present) present.push_back({&t, pose, blocker(pose.Box(t.dimensions_m))});
  }

  const BoxPx image{0.0, 0.0, static_cast<double>(gt.camera.intrinsics.width_px),
                    static_cast<double>(gt.camera.intrinsics.height_px)};
  const Eigen::Vector3d origin = gt.camera.pose.position_m;
  const int n = std::max(1, options.grid);
  std::vector<const Blocker*> nearby;  // those whose image meets the target's
  for (size_t i = 0; i < present.size(); ++i) {
    const Present& p = present[i];
    GroundTruthObject obj;
    obj.id = p.spec->id;
    obj.position_m = p.pose.position_m;
    obj.heading_deg = p.pose.heading_deg;
    obj.dimensions_m = p.spec->dimensions_m;
    obj.amodal_box = p.blocker.projected;
    const BoxPx clipped = Intersect(obj.amodal_box, image);
    obj.in_frame = p.blocker.in_front && !clipped.empty();
    // In front of the camera but out of frame: none of the box is in the
    // image, truncation 1 as the renderer writes (it was left 0 here: a
    // review). Behind the camera there is no box: 0, as the renderer.
    if (p.blocker.in_front && clipped.empty()) obj.truncation = 1.0;
    if (obj.in_frame) {
      obj.truncation = 1.0 - clipped.area() / obj.amodal_box.area();
      // Occluders first, then the other targets, each in the world's order.
      nearby.clear();
      for (const Blocker& o : occluders) {
        if (may_hit_any(o, clipped)) nearby.push_back(&o);
      }
      for (size_t j = 0; j < present.size(); ++j) {
        if (j != i && may_hit_any(present[j].blocker, clipped)) {
          nearby.push_back(&present[j].blocker);
        }
      }
      // Cast a ray through the centre of each lattice cell of the clipped box.
      const double cw = clipped.width / n;
      const double ch = clipped.height / n;
      int target_hits = 0;
      int visible_hits = 0;
      BoxPx visible;
      for (int gy = 0; gy < n; ++gy) {
        for (int gx = 0; gx < n; ++gx) {
          const double u = clipped.left + (gx + 0.5) * cw;
          const double v = clipped.top + (gy + 0.5) * ch;
          const Eigen::Vector3d dir = gt.camera.RayDirection(u, v);
          const auto t_hit = p.blocker.box.Intersect(origin, dir);
          if (!t_hit) continue;
          ++target_hits;
          bool blocked = false;
          for (const Blocker* b : nearby) {
            if (!may_hit(*b, u, v)) continue;
            const auto t_other = b->box.Intersect(origin, dir);
            if (t_other && *t_other < *t_hit) {
              blocked = true;
              break;
            }
          }
          if (blocked) continue;
          ++visible_hits;
          visible = Union(visible, BoxPx{clipped.left + gx * cw, clipped.top + gy * ch, cw, ch});
        }
      }
      obj.visible_fraction =
          target_hits > 0 ? static_cast<double>(visible_hits) / target_hits : 0.0;
      obj.visible_box = visible;
    }
    gt.objects.push_back(obj);
  }
  return gt;
}

std::optional<Eigen::Vector2d> ImageVelocity(const FrameGroundTruth& previous,
                                             const FrameGroundTruth& current, ObjectId id,
                                             bool without_camera_motion) {
  const auto centre = [id](const FrameGroundTruth& gt) -> std::optional<Eigen::Vector2d> {
    for (const GroundTruthObject& o : gt.objects) {
      if (o.id == id) return Eigen::Vector2d(o.amodal_box.centre_x(), o.amodal_box.centre_y());
    }
    return std::nullopt;
  };
  const std::optional<Eigen::Vector2d> before = centre(previous);
  const std::optional<Eigen::Vector2d> now = centre(current);
  if (!before || !now) return std::nullopt;
  Eigen::Vector2d from = *before;
  if (without_camera_motion) {
    const Eigen::Vector3d carried = current.image_from_ground *
                                    previous.image_from_ground.inverse() *
                                    Eigen::Vector3d(before->x(), before->y(), 1.0);
    from = carried.head<2>() / carried.z();
    if (!from.allFinite()) return std::nullopt;
  }
  return *now - from;
}

}  // namespace hcpf
