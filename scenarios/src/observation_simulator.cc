#include "hcpf/scenarios/observation_simulator.h"

#include <algorithm>
#include <cmath>

namespace hcpf::scenarios {

Observation SimulateObservation(const FrameGroundTruth& gt, const SimulatedObservationOptions& o,
                                uint64_t observation_seed) {
  Observation obs;
  obs.frame = gt.frame;
  const Rng frame_rng = Rng(observation_seed).Fork("frame", gt.frame);
  const int width = gt.camera.intrinsics.width_px;
  const int height = gt.camera.intrinsics.height_px;

  std::vector<const GroundTruthObject*> in_frame;
  double max_strength = 0.0;
  for (const GroundTruthObject& object : gt.objects) {
    if (!object.in_frame) continue;
    in_frame.push_back(&object);
    max_strength = std::max(max_strength, o.StrengthOf(Value(object.id)));
  }

  for (const GroundTruthObject* object : in_frame) {
    Rng rng = frame_rng.Fork("target", Value(object->id));
    const double vis = object->visible_fraction;
    const double p = vis < o.min_visible ? 0.0 : o.p_detect * std::pow(vis, o.visibility_exponent);
    // Draw every variate whether or not the target is detected, so that a
    // change of p_detect does not shift the noise of later frames or targets.
    const double u = rng.Uniform();
    const double dx = rng.Normal(0.0, o.sigma_px);
    const double dy = rng.Normal(0.0, o.sigma_px);
    const double sw = std::exp(rng.Normal(0.0, o.size_sigma));
    const double sh = std::exp(rng.Normal(0.0, o.size_sigma));
    if (u >= p) continue;
    const BoxPx& b = object->amodal_box;
    Detection d;
    d.box = BoxPx::FromCentre(b.centre_x() + dx, b.centre_y() + dy, b.width * sw, b.height * sh);
    d.score = o.StrengthOf(Value(object->id)) * vis;
    d.source = object->id;
    obs.detections.push_back(d);
  }

  Rng clutter = frame_rng.Fork("clutter");
  const int64_t n_clutter = clutter.Poisson(o.clutter_per_frame);
  for (int64_t i = 0; i < n_clutter; ++i) {
    const double cx = clutter.Uniform(0.0, width);
    const double cy = clutter.Uniform(0.0, height);
    double w = 0.05 * width;
    double h = 0.05 * width;
    const double pick = clutter.Uniform();
    if (!in_frame.empty()) {
      const size_t k = std::min(in_frame.size() - 1, static_cast<size_t>(pick * in_frame.size()));
      w = in_frame[k]->amodal_box.width;
      h = in_frame[k]->amodal_box.height;
    }
    // In [0, max strength]; [0, 1] only when no target is in the frame (a
    // frame of targets of strength 0 gave clutter up to 1 above them: audit).
    const double score = clutter.Uniform() * (in_frame.empty() ? 1.0 : max_strength);
    obs.detections.push_back(Detection{BoxPx::FromCentre(cx, cy, w, h), score, std::nullopt});
  }

  if (o.likelihood_map) {
    LikelihoodMap map;
    map.cell_px = o.map_cell_px;
    map.width = std::max(1, static_cast<int>(std::ceil(width / o.map_cell_px)));
    map.height = std::max(1, static_cast<int>(std::ceil(height / o.map_cell_px)));
    map.values.assign(static_cast<size_t>(map.width) * map.height, 0.0f);
    Rng noise = frame_rng.Fork("map");
    for (float& v : map.values) v = static_cast<float>(noise.Uniform() * o.map_noise);
    for (const GroundTruthObject* object : in_frame) {
      const double amplitude = o.StrengthOf(Value(object->id)) * object->visible_fraction;
      if (amplitude <= 0.0) continue;
      const BoxPx& b = object->amodal_box;
      const double s = std::max(1e-3, o.map_blob_scale * (b.width + b.height) / 4.0);
      // Blobs are cut off at 4 sigma, where exp(-8) = 3e-4 of the peak.
      const double reach = 4.0 * s;
      const int x0 = std::max(0, static_cast<int>((b.centre_x() - reach) / map.cell_px));
      const int x1 =
          std::min(map.width - 1, static_cast<int>((b.centre_x() + reach) / map.cell_px));
      const int y0 = std::max(0, static_cast<int>((b.centre_y() - reach) / map.cell_px));
      const int y1 =
          std::min(map.height - 1, static_cast<int>((b.centre_y() + reach) / map.cell_px));
      for (int cy = y0; cy <= y1; ++cy) {
        for (int cx = x0; cx <= x1; ++cx) {
          const double px = (cx + 0.5) * map.cell_px - b.centre_x();
          const double py = (cy + 0.5) * map.cell_px - b.centre_y();
          map.values[static_cast<size_t>(cy) * map.width + cx] +=
              static_cast<float>(amplitude * std::exp(-(px * px + py * py) / (2.0 * s * s)));
        }
      }
    }
    obs.likelihood = std::move(map);
  }
  return obs;
}

}  // namespace hcpf::scenarios
