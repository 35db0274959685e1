// Scenario -> resolved YAML. Writes every key the loader reads, in the same
// structure, so loading the output gives back the same Scenario and writing
// that gives back the same text (tested).

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "hcpf/config/fields_yaml.h"
#include "hcpf/config/yaml_reader.h"
#include "hcpf/core/check.h"
#include "hcpf/core/rng.h"
#include "hcpf/scenarios/models.h"
#include "hcpf/scenarios/scenario.h"

namespace hcpf::scenarios {

using config::WriteFields;
namespace {

class Writer {
 public:
  Writer() { out_ << YAML::BeginMap; }
  std::string Finish() {
    out_ << YAML::EndMap;
    return std::string(out_.c_str()) + "\n";
  }
  YAML::Emitter& out() { return out_; }

  void Num(const char* key, double v) {
    out_ << YAML::Key << key << YAML::Value << FormatNumber(v);
  }
  void Int(const char* key, int64_t v) {
    out_ << YAML::Key << key << YAML::Value << std::to_string(v);
  }
  void U64(const char* key, uint64_t v) {
    out_ << YAML::Key << key << YAML::Value << std::to_string(v);
  }
  void Bool(const char* key, bool v) {
    out_ << YAML::Key << key << YAML::Value << (v ? "true" : "false");
  }
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
  // A nested mapping of an Options struct's declared fields.
  template <class O>
  void Section(const char* key, const O& o) {
    Begin(key);
    WriteFields(out_, o, O::Fields());
    End();
  }

 private:
  YAML::Emitter out_;
};

const char* OccluderKindName(OccluderKind k) {
  switch (k) {
    case OccluderKind::kBridge:
      return "bridge";
    case OccluderKind::kBuilding:
      return "building";
    case OccluderKind::kTree:
      return "tree";
    case OccluderKind::kMesh:
      return "mesh";
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
  WriteFields(w.out(), s.world.terrain, TerrainSpec::Fields());
  w.End();
  w.Section("sun", s.world.sun);
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
  w.List("resolution",
         std::vector<double>{static_cast<double>(c.width_px), static_cast<double>(c.height_px)});
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

  w.Section("sensor", s.sensor);

  const SimulatedObservationOptions& sim = s.observation.simulated;
  w.Begin("observation");
  WriteFields(w.out(), s.observation, ObservationOptions::Fields());
  w.Begin("simulated");
  WriteFields(w.out(), sim, SimulatedObservationOptions::Fields());
  w.out() << YAML::Key << "strength" << YAML::Value << YAML::BeginMap;
  for (const TargetSpec& t : s.world.targets) {
    w.Num(std::to_string(Value(t.id)).c_str(), sim.StrengthOf(Value(t.id)));
  }
  w.out() << YAML::EndMap;
  w.End();
  w.End();

  w.Section("renderer", s.renderer);

  const tracker::TrackerOptions& t = s.tracker;
  w.Begin("tracker");
  WriteFields(w.out(), t, tracker::TrackerOptions::Fields());
  w.Section("dynamics", t.dynamics);
  w.Section("likelihood", t.likelihood);
  w.Section("resampling", t.resampling);
  w.Section("interaction", t.interaction);
  w.Section("association", t.association);
  w.Section("management", t.management);
  w.End();

  w.Begin("metrics");
  WriteFields(w.out(), s.metrics.filters, metrics::FilterMetricsOptions::Fields());
  WriteFields(w.out(), s.metrics.points, metrics::PointMetricsOptions::Fields());
  w.End();
  return w.Finish();
}

std::string ConfigHash(const Scenario& scenario) {
  return HashResolvedYaml(ToResolvedYaml(scenario));
}

std::string HashResolvedYaml(const std::string& resolved_yaml) {
  return fmt::format("{:016x}", Mix64(HashName(resolved_yaml)));
}

std::string ReseedResolvedYaml(const std::string& resolved_yaml, const Scenario& reseeded) {
  // ToResolvedYaml writes `name`, then `seed` and the `seeds` block, then `frames`.
  const size_t begin = resolved_yaml.find("\nseed: ");
  const size_t end = resolved_yaml.find("\nframes: ");
  HCPF_CHECK(begin != std::string::npos && end != std::string::npos && begin < end)
      << "not a resolved scenario";
  return fmt::format(
      "{}\nseed: {}\nseeds:\n  world: {}\n  observation: {}\n  tracker: {}\n  renderer: {}{}",
      std::string_view(resolved_yaml).substr(0, begin), reseeded.seed, reseeded.seeds.world,
      reseeded.seeds.observation, reseeded.seeds.tracker, reseeded.seeds.renderer,
      std::string_view(resolved_yaml).substr(end));
}

}  // namespace hcpf::scenarios
