// Scenario -> resolved YAML. Writes every key the loader reads, in the same
// structure, so loading the output gives back the same Scenario and writing
// that gives back the same text (tested).

#include <yaml-cpp/yaml.h>

#include <fmt/format.h>

#include "hcpf/core/rng.h"
#include "hcpf/scenarios/models.h"
#include "hcpf/scenarios/scenario.h"
#include "yaml_reader.h"

namespace hcpf::scenarios {
namespace {

class Writer {
 public:
  Writer() { out_ << YAML::BeginMap; }
  std::string Finish() {
    out_ << YAML::EndMap;
    return std::string(out_.c_str()) + "\n";
  }
  YAML::Emitter& out() { return out_; }

  void Num(const char* key, double v) { out_ << YAML::Key << key << YAML::Value << FormatNumber(v); }
  void Int(const char* key, int64_t v) { out_ << YAML::Key << key << YAML::Value << std::to_string(v); }
  void U64(const char* key, uint64_t v) { out_ << YAML::Key << key << YAML::Value << std::to_string(v); }
  void Bool(const char* key, bool v) { out_ << YAML::Key << key << YAML::Value << (v ? "true" : "false"); }
  void Str(const char* key, const std::string& v) {
    out_ << YAML::Key << key << YAML::Value << YAML::DoubleQuoted << v;
  }
  void Word(const char* key, const std::string& v) { out_ << YAML::Key << key << YAML::Value << v; }
  template <typename Vec>
  void List(const char* key, const Vec& v) {
    out_ << YAML::Key << key << YAML::Value;
    Flow(v);
  }
  template <typename Vec>
  void Flow(const Vec& v) {
    out_ << YAML::Flow << YAML::BeginSeq;
    for (int i = 0; i < static_cast<int>(v.size()); ++i) out_ << FormatNumber(v[i]);
    out_ << YAML::EndSeq;
  }
  void Begin(const char* key) { out_ << YAML::Key << key << YAML::Value << YAML::BeginMap; }
  void End() { out_ << YAML::EndMap; }

 private:
  YAML::Emitter out_;
};

const char* OccluderKindName(OccluderKind k) {
  switch (k) {
    case OccluderKind::kBridge: return "bridge";
    case OccluderKind::kBuilding: return "building";
    case OccluderKind::kTree: return "tree";
    case OccluderKind::kMesh: return "mesh";
  }
  return "building";
}

}  // namespace

std::string ToResolvedYaml(const Scenario& s) {
  Writer w;
  w.Str("name", s.name);
  w.U64("seed", s.seed);
  w.Begin("seeds");
  w.U64("world", s.seeds.world);
  w.U64("observation", s.seeds.observation);
  w.U64("tracker", s.seeds.tracker);
  w.U64("renderer", s.seeds.renderer);
  w.End();
  w.Int("frames", s.world.frames);
  w.Num("fps", s.world.fps);

  w.Begin("world");
  w.Begin("terrain");
  w.List("size_m", s.world.terrain.size_m);
  w.Num("relief_m", s.world.terrain.relief_m);
  w.Word("texture", s.world.terrain.texture);
  w.Bool("roads", s.world.terrain.roads);
  w.End();
  w.Begin("sun");
  w.Num("azimuth_deg", s.world.sun.azimuth_deg);
  w.Num("elevation_deg", s.world.sun.elevation_deg);
  w.Bool("shadows", s.world.sun.shadows);
  w.End();
  w.out() << YAML::Key << "occluders" << YAML::Value << YAML::BeginSeq;
  for (const OccluderSpec& o : s.world.occluders) {
    w.out() << YAML::BeginMap;
    w.Word("kind", OccluderKindName(o.kind));
    switch (o.kind) {
      case OccluderKind::kBridge:
        w.List("from", o.from_m);
        w.List("to", o.to_m);
        w.Num("width_m", o.width_m);
        w.Num("height_m", o.height_m);
        break;
      case OccluderKind::kBuilding:
        w.List("at", o.at_m);
        w.List("size_m", o.size_m);
        w.Num("yaw_deg", o.yaw_deg);
        break;
      case OccluderKind::kTree:
        w.List("at", o.at_m);
        w.Num("height_m", o.height_m);
        break;
      case OccluderKind::kMesh:
        w.Str("model", PortableModelPath(o.model));
        w.List("at", o.at_m);
        w.Num("yaw_deg", o.yaw_deg);
        w.Num("scale", o.scale);
        break;
    }
    w.out() << YAML::EndMap;
  }
  w.out() << YAML::EndSeq;
  w.End();

  const CameraSpec& c = s.world.camera;
  w.Begin("camera");
  w.List("resolution", std::vector<double>{static_cast<double>(c.width_px), static_cast<double>(c.height_px)});
  w.Num("fov_deg", c.hfov_deg);
  w.Num("shake_px", c.shake_px);
  w.out() << YAML::Key << "path" << YAML::Value << YAML::BeginSeq;
  for (const CameraKeyframe& k : c.path) {
    w.out() << YAML::Flow << YAML::BeginMap;
    w.Int("frame", k.frame);
    w.List("position", k.position_m);
    w.List("look_at", k.look_at_m);
    w.out() << YAML::EndMap;
  }
  w.out() << YAML::EndSeq;
  w.End();

  w.out() << YAML::Key << "targets" << YAML::Value << YAML::BeginSeq;
  for (const TargetSpec& t : s.world.targets) {
    w.out() << YAML::BeginMap;
    w.Int("id", Value(t.id));
    if (!t.model.empty()) w.Str("model", PortableModelPath(t.model));
    w.List("dimensions_m", t.dimensions_m);
    w.List("tint", t.tint);
    const TargetPathSpec& p = t.path;
    w.Begin("path");
    w.Word("type", p.kind == PathKind::kWaypoints ? "waypoints" : "constant_turn");
    w.Int("start_frame", p.start_frame);
    w.Int("end_frame", p.end_frame);
    w.Num("speed_mps", p.speed_mps);
    w.Num("heading_deg", p.heading_deg);
    if (p.kind == PathKind::kWaypoints) {
      w.out() << YAML::Key << "waypoints" << YAML::Value << YAML::Flow << YAML::BeginSeq;
      for (const auto& wp : p.waypoints_m) w.Flow(wp);
      w.out() << YAML::EndSeq;
      w.Word("at_end", p.vanish_at_end ? "vanish" : "stay");
      w.out() << YAML::Key << "stops" << YAML::Value << YAML::BeginSeq;
      for (const PathStop& stop : p.stops) {
        w.out() << YAML::Flow << YAML::BeginMap;
        w.Num("at_m", stop.at_m);
        w.Num("duration_s", stop.duration_s);
        w.out() << YAML::EndMap;
      }
      w.out() << YAML::EndSeq;
    } else {
      w.List("start", p.start_m);
      w.Num("turn_rate_deg_s", p.turn_rate_deg_s);
    }
    w.End();
    w.out() << YAML::EndMap;
  }
  w.out() << YAML::EndSeq;

  w.Begin("sensor");
  w.Num("noise_sigma", s.sensor.noise_sigma);
  w.Num("blur_px", s.sensor.blur_px);
  w.Int("jpeg_quality", s.sensor.jpeg_quality);
  w.Num("exposure", s.sensor.exposure);
  w.End();

  const SimulatedObservationOptions& sim = s.observation.simulated;
  w.Begin("observation");
  w.Word("source", s.observation.source == ObservationSource::kRendered ? "rendered" : "simulated");
  w.Word("detector", s.observation.detector);
  w.Begin("simulated");
  w.Num("sigma_px", sim.sigma_px);
  w.Num("size_sigma", sim.size_sigma);
  w.Num("p_detect", sim.p_detect);
  w.Num("visibility_exponent", sim.visibility_exponent);
  w.Num("min_visible", sim.min_visible);
  w.Num("clutter_per_frame", sim.clutter_per_frame);
  w.Bool("likelihood_map", sim.likelihood_map);
  w.Num("map_cell_px", sim.map_cell_px);
  w.Num("map_blob_scale", sim.map_blob_scale);
  w.Num("map_noise", sim.map_noise);
  w.out() << YAML::Key << "strength" << YAML::Value << YAML::BeginMap;
  for (const TargetSpec& t : s.world.targets) {
    w.Num(std::to_string(Value(t.id)).c_str(), sim.StrengthOf(Value(t.id)));
  }
  w.out() << YAML::EndMap;
  w.End();
  w.End();

  w.Begin("renderer");
  w.Word("backend", s.renderer.backend);
  w.Int("shadow_map_size", s.renderer.shadow_map_size);
  w.Int("pcf_radius", s.renderer.pcf_radius);
  w.Bool("write_frames", s.renderer.write_frames);
  w.Bool("write_depth", s.renderer.write_depth);
  w.Bool("write_instance_ids", s.renderer.write_instance_ids);
  w.End();

  const tracker::TrackerOptions& t = s.tracker;
  using tracker::ToString;
  const auto word = [&w](const char* key, std::string_view v) { w.Word(key, std::string(v)); };
  w.Begin("tracker");
  w.Int("particles", t.particles);
  w.Int("keep_particles", t.keep_particles);
  word("init", ToString(t.init));
  w.Begin("dynamics");
  word("model", ToString(t.dynamics.model));
  w.Num("sigma_pos_px", t.dynamics.sigma_pos_px);
  w.Num("sigma_vel_px", t.dynamics.sigma_vel_px);
  w.Num("sigma_log_scale", t.dynamics.sigma_log_scale);
  w.End();
  w.Begin("likelihood");
  word("model", ToString(t.likelihood.model));
  w.Num("sigma_px", t.likelihood.sigma_px);
  w.Num("clutter_density", t.likelihood.clutter_density);
  w.Bool("use_scores", t.likelihood.use_scores);
  w.Num("sigma_log_size", t.likelihood.sigma_log_size);
  w.Num("map_floor", t.likelihood.map_floor);
  w.End();
  w.Begin("resampling");
  word("method", ToString(t.resampling.method));
  w.Num("ess_threshold", t.resampling.ess_threshold);
  word("potential", ToString(t.resampling.potential));
  w.Num("charge", t.resampling.charge);
  w.Num("beta", t.resampling.beta);
  w.Num("softening_px", t.resampling.softening_px);
  w.Int("max_tries", t.resampling.max_tries);
  word("candidates", ToString(t.resampling.candidates));
  w.End();
  w.Begin("interaction");
  word("model", ToString(t.interaction.model));
  w.Num("lambda", t.interaction.lambda);
  w.Num("radius_px", t.interaction.radius_px);
  w.End();
  w.Begin("association");
  word("method", ToString(t.association.method));
  word("gate", ToString(t.association.gate));
  w.Num("gate_mahalanobis_sq", t.association.gate_mahalanobis_sq);
  w.Num("measurement_sigma_px", t.association.measurement_sigma_px);
  w.Num("min_iou", t.association.min_iou);
  w.End();
  const auto& m = t.management;
  w.Begin("management");
  w.Int("confirm_hits", m.confirm_hits);
  w.Int("confirm_window", m.confirm_window);
  w.Num("tentative_gate_px", m.tentative_gate_px);
  w.Int("max_missed_frames", m.max_missed_frames);
  w.Bool("coast_without_support", m.coast_without_support);
  w.Num("birth_sigma_px", m.birth_sigma_px);
  w.Num("birth_sigma_vel_px", m.birth_sigma_vel_px);
  w.Num("birth_sigma_log_scale", m.birth_sigma_log_scale);
  w.End();
  w.End();

  const auto& f = s.metrics.filters;
  const auto& p = s.metrics.points;
  w.Begin("metrics");
  w.Num("iou_threshold", f.iou_threshold);
  w.Num("gate_factor", f.gate_factor);
  w.Num("encounter_factor", f.encounter_factor);
  w.Int("post_window", f.post_window);
  w.Num("min_visible", f.min_visible);
  w.Int("visible_bins", f.visible_bins);
  w.Num("ospa_cutoff_px", p.cutoff_px);
  w.Num("ospa_order", p.order);
  w.Num("gospa_switching_penalty", p.switching_penalty);
  w.End();
  return w.Finish();
}

std::string ConfigHash(const Scenario& scenario) {
  const std::string text = ToResolvedYaml(scenario);
  return fmt::format("{:016x}", Mix64(HashName(text)));
}

}  // namespace hcpf::scenarios
