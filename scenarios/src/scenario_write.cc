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

}  // namespace

std::string ToResolvedYaml(const Scenario& s) {
  Writer w;
  WriteFields(w.out(), s, ScenarioFields());  // name, seed
  w.Begin("seeds");
  WriteFields(w.out(), s.seeds, SeedFields());
  w.End();
  WriteFields(w.out(), s.world, WorldFields());  // frames, fps

  w.Begin("world");
  w.Section("terrain", s.world.terrain);
  w.Section("sun", s.world.sun);
  w.out() << YAML::Key << "occluders" << YAML::Value << YAML::BeginSeq;
  for (const OccluderSpec& o : s.world.occluders) {
    w.out() << YAML::BeginMap;
    WriteFields(w.out(), o, OccluderKindFields());
    WriteFields(w.out(), o, OccluderFields(o.kind));
    w.out() << YAML::EndMap;
  }
  w.out() << YAML::EndSeq;
  w.End();

  const CameraSpec& c = s.world.camera;
  w.Begin("camera");
  WriteFields(w.out(), c, CameraFields());
  w.out() << YAML::Key << "path" << YAML::Value << YAML::BeginSeq;
  for (const CameraKeyframe& k : c.path) {
    w.out() << YAML::Flow << YAML::BeginMap;
    WriteFields(w.out(), k, KeyframeFields());
    w.out() << YAML::EndMap;
  }
  w.out() << YAML::EndSeq;
  w.End();

  w.out() << YAML::Key << "targets" << YAML::Value << YAML::BeginSeq;
  for (const TargetSpec& t : s.world.targets) {
    w.out() << YAML::BeginMap;
    WriteFields(w.out(), t, TargetFields());
    const TargetPathSpec& p = t.path;
    w.Begin("path");
    WriteFields(w.out(), p, PathFields());
    WriteFields(w.out(), p, PathFields(p.kind));
    if (p.kind == PathKind::kWaypoints) {
      w.out() << YAML::Key << "stops" << YAML::Value << YAML::BeginSeq;
      for (const PathStop& stop : p.stops) {
        w.out() << YAML::Flow << YAML::BeginMap;
        WriteFields(w.out(), stop, StopFields());
        w.out() << YAML::EndMap;
      }
      w.out() << YAML::EndSeq;
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
  // Only the detector in use: the options of the others do not change the
  // run, so they are not part of its identity (config hash).
  const vision::DetectorOptions& detectors = s.observation.detectors;
  detectors.ForEach([&](const char* name, const auto& options) {
    if (s.observation.Uses(name)) w.Section(name, options);
  });
  if (s.observation.from_file()) w.Section("file", s.observation.file);
  w.End();

  w.Section("renderer", s.renderer);

  const tracker::TrackerOptions& t = s.tracker;
  w.Begin("tracker");
  if (s.tracker_choice.external()) {
    // Only the keys that take effect (scenario.h); a program inside the
    // project folder relative to it, as model paths are written.
    TrackerChoice choice = s.tracker_choice;
    if (choice.command.front().find('/') != std::string::npos) {
      choice.command.front() = PortableModelPath(choice.command.front());
    }
    WriteFields(w.out(), choice, TrackerChoice::Fields());
  } else {
    // tracker.type: particle_filter (the default) is not written, so the
    // resolved YAML and config hash of every particle-filter scenario are
    // those from before external trackers.
    WriteFields(w.out(), t, tracker::TrackerOptions::Fields());
    w.Section("dynamics", t.dynamics);
    w.Section("likelihood", t.likelihood);
    w.Section("resampling", t.resampling);
    w.Section("interaction", t.interaction);
    w.Section("association", t.association);
    w.Section("management", t.management);
    w.Section("scene_filter", t.scene_filter);
    if (UsesPointTracker(s)) w.Section("point_tracker", s.point_tracker);
    if (UsesRansac(s)) w.Section("ransac", s.ransac);
    if (UsesPerspective(s)) w.Section("perspective", s.perspective);
  }
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
