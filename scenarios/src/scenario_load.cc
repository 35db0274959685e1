// Scenario YAML -> Scenario. Every key is read through a declared field table
// (scenario_fields.cc and the modules' Options), so docs/scenario.md, the
// resolved-YAML writer and this reader cannot disagree; what is written here
// by hand is the structure (lists, kinds) and the rules across keys.

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <unistd.h>

#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <numbers>
#include <set>

#include "detection_cache.h"
#include "hcpf/config/fields_yaml.h"
#include "hcpf/config/file_lookup.h"
#include "hcpf/config/yaml_reader.h"
#include "hcpf/core/names.h"
#include "hcpf/core/rng.h"
#include "hcpf/core/subprocess.h"
#include "hcpf/core/text_file.h"
#include "hcpf/metrics/detection_truth.h"
#include "hcpf/renderer/renderer.h"
#include "hcpf/scenarios/frames.h"
#include "hcpf/scenarios/models.h"
#include "hcpf/scenarios/scenario.h"
#include "rendering_check.h"

namespace hcpf::scenarios {

using config::ApplyOverrides;
using config::ReadFields;
using config::YamlContext;
using config::YamlReader;
uint64_t DeriveSeed(uint64_t seed, const char* name) { return Rng(seed).Fork(name).identity(); }

namespace {

// Every seed not pinned derived from s->seed, and the world's copies of the
// world seed: the one derivation, for loading and for Reseeded.
void DeriveSeeds(Scenario* s) {
  const uint8_t pinned = s->pinned_seeds;
  if (!(pinned & Scenario::kPinnedWorld)) s->seeds.world = DeriveSeed(s->seed, "world");
  if (!(pinned & Scenario::kPinnedObservation))
    s->seeds.observation = DeriveSeed(s->seed, "observation");
  if (!(pinned & Scenario::kPinnedTracker)) s->seeds.tracker = DeriveSeed(s->seed, "tracker");
  if (!(pinned & Scenario::kPinnedRenderer)) s->seeds.renderer = DeriveSeed(s->seed, "renderer");
  s->world.terrain.seed = s->seeds.world;
  s->world.camera.shake_seed = s->seeds.world;
}

void ReadTerrain(YamlReader r, TerrainSpec* t) {
  r.ExpectMap();
  ReadFields(r, *t, TerrainSpec::Fields());
  r.Finish();
}

void ReadSun(YamlReader r, SunSpec* s) {
  r.ExpectMap();
  ReadFields(r, *s, SunSpec::Fields());
  r.Finish();
}

// Model files are named relative to the scenario file (models.h).
config::PathResolver ModelResolver(const std::string& scenario_file) {
  return [scenario_file](const std::string& text, const SourceLocation& where) {
    return ResolveModelPath(text, scenario_file, where);
  };
}

// A frame number must also lie within the scenario's own `frames`.
void CheckFrame(YamlReader& r, const char* key, int value, int lo, int frames) {
  if (value > frames - 1) {
    r.Child(key).Fail(FieldExpectation(FieldType::kInteger, Closed(lo, frames - 1)));
  }
}

// `model_digest` beside a model (models.h, ModelDigest): computed when not
// given, else checked (a model edited since a resolved YAML pinned it, or a
// digest copied from another model, is refused). A box has no file to digest.
void ReadModelDigest(YamlReader& r, const std::string& model, std::string* digest) {
  if (model.empty()) {
    if (!digest->empty()) r.Child("model_digest").Fail("no model_digest without a `model`");
    return;
  }
  const std::string now = ModelDigest(model, r.Child("model").Where());
  if (!digest->empty() && !internal::IsDigestHex(*digest)) {
    r.Child("model_digest")
        .Fail("a digest: 32 lowercase hexadecimal digits, as the resolved YAML writes it");
  }
  if (!digest->empty() && *digest != now) {
    r.Child("model_digest")
        .Fail(fmt::format("{}, the digest of {} as it is now (the model or a file it names "
                          "changed since this digest was written, or the digest is not its)",
                          now, PortableModelPath(model)));
  }
  *digest = now;
}

OccluderSpec ReadOccluder(YamlReader r, const std::string& scenario_file) {
  r.ExpectMap();
  OccluderSpec o;
  ReadFields(r, o, OccluderKindFields());
  o = OccluderDefaults(o.kind);
  ReadFields(r, o, OccluderFields(o.kind), ModelResolver(scenario_file));
  if (o.kind == OccluderKind::kBridge && (o.to_m - o.from_m).norm() < 0.1) {
    r.Child("to").Fail("an end point at least 0.1 m from \"from\"");
  }
  if (o.kind == OccluderKind::kMesh) o.size_m = ModelDimensions(o.model, r.Child("model").Where());
  ReadModelDigest(r, o.model, &o.model_digest);
  r.Finish();
  return o;
}

TargetPathSpec ReadPath(YamlReader r, int frames) {
  r.ExpectMap();
  TargetPathSpec p;
  ReadFields(r, p, PathFields());
  CheckFrame(r, "start_frame", p.start_frame, 0, frames);
  CheckFrame(r, "end_frame", p.end_frame, -1, frames);
  if (p.end_frame >= 0 && p.end_frame < p.start_frame) {
    r.Child("end_frame").Fail(fmt::format("-1 or a frame >= start_frame ({})", p.start_frame));
  }
  ReadFields(r, p, PathFields(p.kind));
  if (p.kind == PathKind::kWaypoints) {
    if (auto stops = r.Optional("stops")) {
      double last = -1.0;
      for (YamlReader s : stops->Items()) {
        s.ExpectMap();
        PathStop stop;
        ReadFields(s, stop, StopFields());
        if (stop.at_m < last) s.Child("at_m").Fail("stops in increasing order of at_m");
        last = stop.at_m;
        s.Finish();
        p.stops.push_back(stop);
      }
    }
    if (p.waypoints_m.size() > 1 && p.speed_mps <= 0.0) {
      r.Child("speed_mps").Fail("a speed > 0 for a path of several waypoints");
    }
  }
  r.Finish();
  return p;
}

TargetSpec ReadTarget(YamlReader r, int frames, const std::string& scenario_file) {
  r.ExpectMap();
  TargetSpec t;
  const bool dimensions_given = r.Has("dimensions_m");
  ReadFields(r, t, TargetFields(), ModelResolver(scenario_file));
  if (!dimensions_given && t.model.empty()) r.Child("dimensions_m");  // neither: missing key
  if (!t.model.empty()) {
    // Read even when the dimensions are given, so that `hcpf validate`
    // refuses a model the rendered run cannot load (a bad-input audit found
    // a garbage .glb valid, then the run failing without a key or line).
    const Eigen::Vector3d dims = ModelDimensions(t.model, r.Child("model").Where());
    if (!dimensions_given) t.dimensions_m = dims;
  }
  ReadModelDigest(r, t.model, &t.model_digest);
  t.path = ReadPath(r.Child("path"), frames);
  r.Finish();
  return t;
}

void ReadCamera(YamlReader r, int frames, CameraSpec* c) {
  r.ExpectMap();
  ReadFields(r, *c, CameraFields());
  YamlReader path = r.Child("path");
  for (YamlReader k : path.Items()) {
    k.ExpectMap();
    CameraKeyframe key;
    ReadFields(k, key, KeyframeFields());
    CheckFrame(k, "frame", key.frame, 0, frames);
    if (!c->path.empty() && key.frame <= c->path.back().frame) {
      k.Child("frame").Fail(
          fmt::format("a frame after the previous keyframe's ({})", c->path.back().frame));
    }
    if ((key.position_m - key.look_at_m).norm() < 1e-6) {
      // The point is named (a bad-input audit: "found a list of 3 item(s)").
      throw InputError(k.Child("look_at").Where(), "a point different from the camera position",
                       fmt::format("[{:g}, {:g}, {:g}], the camera's position there",
                                   key.look_at_m.x(), key.look_at_m.y(), key.look_at_m.z()));
    }
    k.Finish();
    c->path.push_back(key);
  }
  if (c->path.empty()) path.Fail("a list of at least one keyframe");
  r.Finish();
}

// The camera frame by frame along its whole path, as the run evaluates it
// (an audit of valid input: a path whose keyframes were each valid aborted
// the run at a frame where the interpolated camera reached the point it
// looked at; a camera below the ground ran, its targets seen through the
// terrain; one on the ground, or turning 90 degrees or more between two
// frames, failed the run's camera-motion metric without naming a key, after
// validate had said valid). Frames are counted from 0, as the keyframes.
void CheckCameraPath(YamlReader path, const WorldSpec& world) {
  const CameraSpec& camera = world.camera;
  // The terrain's highest point: its height field stays within half its
  // relief of 0, whatever its seed (TerrainSpec::HeightAt).
  const double top = 0.5 * world.terrain.relief_m;
  const auto where_on_path = [&camera](int frame) {
    for (size_t i = 0; i < camera.path.size(); ++i) {
      if (camera.path[i].frame == frame) return fmt::format("at the keyframe of frame {}", frame);
      if (camera.path[i].frame > frame) {
        return i == 0 ? fmt::format("at frame {}, before the first keyframe", frame)
                      : fmt::format("at frame {}, between the keyframes of frames {} and {}", frame,
                                    camera.path[i - 1].frame, camera.path[i].frame);
      }
    }
    return fmt::format("at frame {}, after the last keyframe", frame);
  };
  std::optional<Eigen::Matrix3d> previous;
  for (int frame = 0; frame < world.frames; ++frame) {
    const CameraPathPoint at = InterpolateCamera(camera, frame);
    const Eigen::Vector3d& p = at.position_m;
    if ((p - at.look_at_m).norm() < 1e-6) {
      throw InputError(path.Where(),
                       "a path on which the camera never reaches the point it looks at",
                       fmt::format("the camera and its look_at both at [{:g}, {:g}, {:g}] {}",
                                   p.x(), p.y(), p.z(), where_on_path(frame)));
    }
    if (!(p.z() > top)) {
      throw InputError(
          path.Where(),
          top > 0.0 ? fmt::format("a camera above the ground at every frame: higher than {:g} m, "
                                  "the terrain's highest point (half its relief_m)",
                                  top)
                    : std::string("a camera above the ground at every frame: higher than 0 m"),
          fmt::format("a camera at height {:g} m {}", p.z(), where_on_path(frame)));
    }
    const Eigen::Matrix3d h = EvaluateCamera(camera, frame).ImageFromGround(0.0);
    if (previous) {
      // What the camera-motion metric maps (metrics::CornerDisplacementPx).
      const Eigen::Matrix3d t = h * previous->inverse();
      const double w = camera.width_px, hgt = camera.height_px;
      for (const Eigen::Vector2d& c : {Eigen::Vector2d(0, 0), Eigen::Vector2d(w, 0),
                                       Eigen::Vector2d(w, hgt), Eigen::Vector2d(0, hgt)}) {
        const Eigen::Vector3d q = t * Eigen::Vector3d(c.x(), c.y(), 1.0);
        if (q.z() > 0.0 && q.allFinite()) continue;
        throw InputError(
            path.Where(),
            "a path along which the ground seen at each image corner stays in front of the "
            "camera from one frame to the next (the camera-motion metric maps the corners by "
            "the ground's homography, docs/metrics.md)",
            fmt::format("corner ({:g}, {:g}) mapped to homogeneous z = {:g} from frame {} to {} "
                        "(the camera turns or moves too far between them) {}",
                        c.x(), c.y(), q.z(), frame - 1, frame, where_on_path(frame)));
      }
    }
    previous = h;
  }
}

// A det.txt of a long run: 10 000 frames of a few hundred detections take
// about 100 MB.
constexpr uint64_t kMaxDetectionFileBytes = uint64_t{1} << 30;

// observation.file with detector: file: the det.txt read now, so `hcpf
// validate` checks every row and the resolved YAML pins its content.
void ReadDetectionFile(const YamlReader& root, Scenario* s) {
  DetectionFileOptions& f = s->observation.file;
  const std::string text =
      ReadInputFile(f.path, "a det.txt (observation.file.path)", kMaxDetectionFileBytes);
  const std::string digest = internal::DigestHex(XXH3_128bits(text.data(), text.size()));
  // A digest that is none (a bad-input audit: "xyz" was said to be the digest
  // of the file before it changed).
  if (!f.digest.empty() && !internal::IsDigestHex(f.digest)) {
    root.Relocate([&] {
      FailOption("observation.file", "digest",
                 "a digest: 32 lowercase hexadecimal digits, as the manifest's detection_file "
                 "writes it",
                 "\"" + f.digest + "\"");
    });
  }
  if (!f.digest.empty() && f.digest != digest) {
    root.Relocate([&] {
      FailOption("observation.file", "digest",
                 fmt::format("{}, the digest of {} as it is now (the file changed since this "
                             "digest was written, or the digest is not its)",
                             digest, f.path),
                 "\"" + f.digest + "\"");
    });
  }
  f.digest = digest;
  const metrics::MotFile file =
      metrics::ParseMotText(text, f.path, metrics::MotFileKind::kDetections, s->world.frames);
  // The particle filter weighs each detection by its score.
  const bool weighed = !s->tracker_choice.external() && s->tracker.likelihood.use_scores;
  auto frames =
      std::make_shared<std::vector<std::vector<Detection>>>(static_cast<size_t>(s->world.frames));
  std::vector<metrics::DetectionFileRow> rows = metrics::DetectionRowsOf(file);
  if (f.labels) {
    std::set<int64_t> ids;
    for (const TargetSpec& t : s->world.targets) ids.insert(Value(t.id));
    metrics::ReadDetectionLabels(file, ids, "observation.file.labels: true", &rows);
  }
  for (const metrics::DetectionFileRow& row : rows) {
    const double score = row.detection.score;
    ++f.rows;
    if (score < f.min_score) {
      ++f.left_out;
      continue;
    }
    if (weighed && !(score >= 0.0 && score <= 1.0)) {
      throw InputError(
          SourceLocation{f.path, row.line, 7, "column 7 (score)"},
          fmt::format("a score in [0, 1], which tracker.likelihood.use_scores: true makes the "
                      "detection's weight (or use_scores: false{})",
                      score < 0.0 ? fmt::format(", or an observation.file.min_score above {:g} "
                                                "leaving the row out",
                                                score)
                                  : ""),
          fmt::format("{:g}", score));
    }
    (*frames)[static_cast<size_t>(row.frame)].push_back(row.detection);
  }
  f.frames = std::move(frames);
}

// One nested section of `parent` from its Options' declared fields.
template <class O>
void ReadSection(YamlReader& parent, const char* key, O* o) {
  if (auto section = parent.Optional(key)) {
    section->ExpectMap();
    ReadFields(*section, *o, O::Fields());
    section->Finish();
  }
}

void ReadSimulated(YamlReader r, const std::set<int32_t>& ids, SimulatedObservationOptions* s) {
  r.ExpectMap();
  ReadFields(r, *s, SimulatedObservationOptions::Fields());
  if (auto strength = r.Optional("strength")) {
    strength->ExpectMap();
    std::map<int32_t, std::string> written;  // id -> how it was first written
    for (const auto& entry : strength->node()) {
      const std::string text = entry.first.Scalar();
      const int64_t id = strength->Key(entry.first).AsInteger(1, 1'000'000'000);
      if (ids.count(static_cast<int32_t>(id)) == 0) {
        strength->Key(entry.first)
            .Fail("the id of one of the targets", fmt::format("there is no target with id {}", id));
      }
      // {1: 1.0, 1: 0.3} or {1: 1.0, 01: 0.3}: one of the two would be lost.
      const auto [first, inserted] = written.emplace(static_cast<int32_t>(id), text);
      if (!inserted) {
        strength->Key(entry.first)
            .Fail("each target id once",
                  fmt::format("target {} already has a strength (written \"{}\")", id,
                              first->second));
      }
      s->strength[static_cast<int32_t>(id)] = strength->Number(text, std::nullopt, 0.0, 100.0);
    }
  }
  r.Finish();
}

// tracker.type, tracker.command, tracker.timeout_s: the rules across them,
// and command[0] found now, so `hcpf validate` rejects a program that
// cannot be started at the line that names it.
void ReadTrackerChoice(YamlReader& r, const std::string& file, TrackerChoice* c) {
  ReadFields(r, *c, TrackerChoice::Fields());
  if (!c->external()) {
    // The command names the program to run, so writing one asks for it: an
    // error here. An empty command is the key not written (a sweep's zip can
    // give particle-filter cells `[]`). timeout_s is an option of the
    // external tracker, and like the options of every component not chosen
    // (the particle filter's with type: external) it is checked, then takes
    // no effect: back to its default, so the resolved YAML and config hash
    // do not depend on it.
    if (!c->command.empty()) {
      r.Child("command").Fail(
          "no tracker.command with tracker.type: particle_filter (it belongs to tracker.type: "
          "external)");
    }
    c->command.clear();
    c->timeout_s = TrackerChoice{}.timeout_s;
    return;
  }
  if (c->command.empty()) {
    YamlReader command = r.Child("command");  // absent: the missing-key error
    command.Fail("a non-empty list: the program to run and its arguments");
  }
  // A NUL ends a C string: the program would run with its name or an
  // argument cut there (a second bad-input audit: exit 0, "a" for "a\0b").
  const std::vector<YamlReader> words = r.Child("command").Items();
  for (size_t i = 0; i < c->command.size() && i < words.size(); ++i) {
    if (c->command[i].find('\0') != std::string::npos) {
      words[i].Fail("a program or argument without a NUL character (\\0 would cut it short)");
    }
  }
  const std::string& program = c->command.front();
  const SourceLocation where = words.front().Where();
  if (program.find('/') == std::string::npos) {
    if (!ExecutableOnPath(program)) {
      throw InputError(where, "a program on PATH, or a path with a '/'",
                       fmt::format("\"{}\", which is not an executable file in any folder of "
                                   "PATH",
                                   program));
    }
    return;
  }
  const bool from_file = !file.empty() && file.rfind("--set", 0) != 0;
  const std::string beside =
      from_file ? std::filesystem::absolute(std::filesystem::path(file)).parent_path().string()
                : std::string();
  std::vector<std::string> looked;
  const auto found = config::FindFile(program, beside, &looked);
  if (!found) {
    throw InputError(where, "the path of an existing executable file",
                     config::NotFoundText(program, looked));
  }
  const std::string resolved = std::filesystem::weakly_canonical(*found).string();
  if (::access(resolved.c_str(), X_OK) != 0) {
    throw InputError(where, "an executable file (chmod +x, or a shebang line and the execute bit)",
                     fmt::format("\"{}\", which is not executable", resolved));
  }
  // A program this user may run but not read (mode 711, as some sites
  // install binaries) has no first bytes to check: the kernel starts a native
  // binary without read permission (a script's interpreter would need it, so
  // an unreadable script fails when the run starts it). It was refused,
  // "cannot read", exit 1, for everyone but root.
  if (::access(resolved.c_str(), R_OK) != 0) {
    c->command.front() = resolved;
    return;
  }
  // What the kernel can start: a script's "#!" line naming an executable
  // interpreter, or a native binary (ELF). A third bad-input audit found a
  // script without "#!", or with a missing interpreter, accepted by validate
  // and failing the run ("Exec format error", exit 1).
  const std::string head = ReadFilePrefix(resolved, 256);
  if (head.rfind("#!", 0) == 0) {
    const size_t start = head.find_first_not_of(" \t", 2);
    const size_t end =
        start == std::string::npos ? std::string::npos : head.find_first_of(" \t\r\n", start);
    const std::string interpreter =
        start == std::string::npos ? std::string() : head.substr(start, end - start);
    std::error_code ec;
    if (interpreter.empty() || !std::filesystem::is_regular_file(interpreter, ec) ||
        ::access(interpreter.c_str(), X_OK) != 0) {
      throw InputError(
          where, "a script whose #! line names an executable interpreter",
          fmt::format("\"{}\", whose #! line names {}", resolved,
                      interpreter.empty()
                          ? std::string("nothing")
                          : "\"" + interpreter + "\", which is not an executable file"));
    }
  } else if (head.rfind("\x7f"
                        "ELF",
                        0) != 0) {
    throw InputError(where,
                     "a program the system can start: a script with a #! line (e.g. "
                     "#!/usr/bin/env python3) or a native binary",
                     fmt::format("\"{}\", which starts with neither", resolved));
  }
  c->command.front() = resolved;
}

void ReadTracker(YamlReader r, Scenario* s) {
  tracker::TrackerOptions* t = &s->tracker;
  r.ExpectMap();
  ReadTrackerChoice(r, s->source_file, &s->tracker_choice);
  ReadFields(r, *t, tracker::TrackerOptions::Fields());
  ReadSection(r, "dynamics", &t->dynamics);
  ReadSection(r, "likelihood", &t->likelihood);
  ReadSection(r, "resampling", &t->resampling);
  ReadSection(r, "interaction", &t->interaction);
  if (auto a = r.Optional("association"); a && a->node().IsScalar()) {
    // Shorthand of DESIGN.md: `association: gnn` sets the method.
    Field<tracker::AssociationOptions> method;
    for (const auto& f : tracker::AssociationOptions::Fields()) {
      if (f.key == "method") method = f;
    }
    method.key = "association";
    ReadFields(r, t->association, std::span<const Field<tracker::AssociationOptions>>(&method, 1));
  } else {
    ReadSection(r, "association", &t->association);
  }
  ReadSection(r, "management", &t->management);
  ReadSection(r, "scene_filter", &t->scene_filter);
  ReadSection(r, "point_tracker", &s->point_tracker);
  ReadSection(r, "ransac", &s->ransac);
  ReadSection(r, "perspective", &s->perspective);
  r.Finish();
  if (s->tracker_choice.external()) {
    // The particle filter's keys were read (so a misspelt key is still an
    // error) but take no effect: back to their defaults, as the resolved
    // YAML, which leaves them out, loads.
    s->tracker = {};
    s->point_tracker = {};
    s->ransac = {};
    s->perspective = {};
  }
}

void ReadMetrics(YamlReader r, MetricsConfig* m) {
  r.ExpectMap();
  ReadFields(r, m->filters, metrics::FilterMetricsOptions::Fields());
  ReadFields(r, m->points, metrics::PointMetricsOptions::Fields());
  r.Finish();
}

Scenario ReadScenario(YamlReader root, const std::string& file, ScenarioUse use) {
  root.ExpectMap();
  if (!root.node().IsDefined() || root.node().IsNull()) root.Fail("a scenario mapping");
  Scenario s;
  s.source_file = file;
  s.name = std::filesystem::path(file).stem().string();
  ReadFields(root, s, ScenarioFields());  // name, seed
  // The name goes into seqinfo.ini, manifests and reports: a newline there
  // would make the run's own files unreadable (issue 15, item 13).
  // NEL (U+0085) and U+2028/9 break lines in editors and browsers too.
  // Nor may it be blank: seqinfo.ini's `name=` and TrackEval's sequence
  // would have none (a bad-input audit: `name: ""` was accepted).
  if (root.Has("name") && s.name.find_first_not_of(" \t") == std::string::npos) {
    root.Child("name").Fail("a name with a visible character (leave the key out for the file's)");
  }
  if (const std::string c = FirstControlCharacter(s.name); !c.empty()) {
    if (root.Has("name"))
      root.Child("name").Fail("a name without control characters (newline, tab, U+0085, U+2028)",
                              "it holds " + c);
    throw InputError(SourceLocation{file, 0, 0, "name"},
                     "a file name without control characters (the default name)",
                     fmt::format("\"{}\", which holds {}", s.name, c));
  }
  DeriveSeeds(&s);
  if (auto seeds = root.Optional("seeds")) {
    seeds->ExpectMap();
    const std::span<const Field<Seeds>> fields = SeedFields();
    for (size_t i = 0; i < fields.size(); ++i) {  // bit i: kPinnedWorld, ..., kPinnedRenderer
      if (seeds->Has(std::string(fields[i].key))) s.pinned_seeds |= static_cast<uint8_t>(1u << i);
    }
    ReadFields(*seeds, s.seeds, fields);
    seeds->Finish();
  }
  // A run holds every frame's truth, observations and reports until it writes
  // its files (about 5 KB + 3.4 KB per target per frame, EstimateRunCost), so
  // the bound is what runs on a workstation: 100,000 frames (55 min at 30 fps).
  ReadFields(root, s.world, WorldFields());  // frames, fps
  const int frames = s.world.frames;

  if (auto world = root.Optional("world")) {
    world->ExpectMap();
    if (auto t = world->Optional("terrain")) ReadTerrain(*t, &s.world.terrain);
    if (auto sun = world->Optional("sun")) ReadSun(*sun, &s.world.sun);
    if (auto occ = world->Optional("occluders")) {
      for (YamlReader o : occ->Items()) s.world.occluders.push_back(ReadOccluder(o, file));
    }
    world->Finish();
  }
  s.world.terrain.seed = s.seeds.world;
  ReadCamera(root.Child("camera"), frames, &s.world.camera);
  s.world.camera.shake_seed = s.seeds.world;
  CheckCameraPath(root.Child("camera").Child("path"), s.world);

  YamlReader targets = root.Child("targets");
  std::set<int32_t> ids;
  for (YamlReader t : targets.Items()) {
    TargetSpec target = ReadTarget(t, frames, file);
    if (!ids.insert(Value(target.id)).second) {
      t.Child("id").Fail("an id used by no other target");
    }
    s.world.targets.push_back(std::move(target));
  }
  if (s.world.targets.empty()) targets.Fail("a list of at least one target");

  if (auto sensor = root.Optional("sensor")) {
    sensor->ExpectMap();
    ReadFields(*sensor, s.sensor, SensorOptions::Fields());
    sensor->Finish();
  }
  if (auto obs = root.Optional("observation")) {
    obs->ExpectMap();
    // `detectors: [sks, prca]` alone means detector: fusion.
    const bool fusion_implied = obs->Has("detectors") && !obs->Has("detector");
    ReadFields(*obs, s.observation, ObservationOptions::Fields());
    if (fusion_implied) s.observation.detector = "fusion";
    if (auto sim = obs->Optional("simulated")) ReadSimulated(*sim, ids, &s.observation.simulated);
    s.observation.detectors.ForEach(
        [&](const char* name, auto& options) { ReadSection(*obs, name, &options); });
    if (auto f = obs->Optional("file")) {
      f->ExpectMap();
      ReadFields(*f, s.observation.file, DetectionFileOptions::Fields(),
                 [&file](const std::string& text, const SourceLocation& where) {
                   if (where.key.ends_with(".rendering")) {
                     return internal::ResolveRenderingFolder(text, file, where);
                   }
                   return ResolveModelPath(text, file, where, "the path of an existing det.txt");
                 });
      f->Finish();
    }
    obs->Finish();
  }
  if (auto r = root.Optional("renderer")) {
    r->ExpectMap();
    ReadFields(*r, s.renderer, RendererConfig::Fields());
    r->Finish();
  }
  if (auto t = root.Optional("tracker")) ReadTracker(*t, &s);
  if (auto m = root.Optional("metrics")) ReadMetrics(*m, &s.metrics);
  root.Finish();
  // What the renderer can draw, checked at load when the run renders (a
  // rendered source, or frames written beside a detection-level run) and for
  // `hcpf render`, so `hcpf validate` refuses what `hcpf run` would (a scale
  // audit: 256 targets validated, then every run failed after its GL
  // context, at no line; `hcpf render` failed so too).
  const bool renders = s.observation.source == ObservationSource::kRendered ||
                       s.renderer.write_frames || s.renderer.write_depth ||
                       s.renderer.write_instance_ids;
  if ((renders || use == ScenarioUse::kRender) &&
      s.world.targets.size() > static_cast<size_t>(renderer::kMaxRenderedTargets)) {
    targets.Fail(
        use == ScenarioUse::kRender && !renders
            ? fmt::format("at most {} targets for hcpf render: the renderer marks each pixel's "
                          "target in 8 bits",
                          renderer::kMaxRenderedTargets)
            : fmt::format("at most {} targets where the run renders (observation.source: "
                          "rendered, or renderer.write_frames, write_depth or "
                          "write_instance_ids): the renderer marks each pixel's target in 8 bits",
                          renderer::kMaxRenderedTargets));
  }
  // A 16-bit instance image holds ids up to 65534 (id + 1; ids up to 10^9
  // were clamped to 65535, two targets then one value: a scale audit).
  if (s.renderer.write_instance_ids) {
    size_t k = 0;  // targets.Items() in the order they were read
    for (YamlReader t : targets.Items()) {
      const int32_t id = Value(s.world.targets[k++].id);
      if (id <= renderer::kMaxInstanceImageId) continue;
      (t.Has("id") ? t.Child("id") : t)
          .Fail(fmt::format("an id of at most {} with renderer.write_instance_ids (its 16-bit "
                            "_ids.png holds id + 1)",
                            renderer::kMaxInstanceImageId),
                std::to_string(id));
    }
  }

  // Every module's own checks (ranges and cross-field rules), run at load
  // time so `hcpf validate` and `hcpf run` accept the same scenarios; an error
  // is reported at the line of the key it names.
  root.Relocate([&s] {
    RendererOptionsOf(s);  // renderer and sensor options (validates)
    s.tracker.Validate();
    s.point_tracker.Validate();
    s.ransac.Validate();
    s.perspective.Validate();
    if (s.perspective.enabled && !s.tracker_choice.external()) {
      if (s.tracker.camera_motion != tracker::CameraMotionMode::kSceneFilter) {
        FailOption("tracker.perspective", "enabled",
                   "false, or true with tracker.camera_motion: scene_filter (the perspective "
                   "stage belongs to the scene filter)",
                   std::string("true with camera_motion: ") +
                       std::string(NameOf(s.tracker.camera_motion)));
      }
      if (s.tracker.scene_filter.evidence == tracker::SceneEvidenceKind::kOracle) {
        FailOption("tracker.perspective", "enabled",
                   "false, or true with scene_filter.evidence simulated or image (it fits point "
                   "tracks)",
                   "true with scene_filter.evidence: oracle");
      }
    }
    s.observation.Validate(s.tracker);
    if (s.tracker_choice.external() && s.observation.search == SearchMode::kWindow) {
      FailOption("observation", "search",
                 "frame with tracker.type: external (windows follow the particle filters)",
                 "window");
    }
    s.metrics.filters.Validate();
    s.metrics.points.Validate();
  });
  if (s.observation.from_file()) {
    ReadDetectionFile(root, &s);
    root.Relocate([&s] { internal::CheckRendering(&s); });
  } else {
    // Checked (the path resolved), then of no effect: not part of the run's
    // identity, like the options of a detector not chosen.
    s.observation.file = DetectionFileOptions{};
  }
  return s;
}

// A file named anew by an override drops the digest the scenario pinned for
// the file it named before, unless an override sets that digest too: `--set
// targets.0.model=...car.glb` on a run's scenario.resolved.yaml loads the
// car, where the tank's model_digest would refuse it. Paths as
// YamlContext::overrides keys them ("targets[0].model").
void DropDigestsOfRenamedFiles(YAML::Node root, const YamlContext& context) {
  const auto overridden = [&](const std::string& path) {
    return context.overrides.count(path) > 0;
  };
  // Const lookups (a missing key reads as undefined, none is added).
  const auto child = [](const YAML::Node& map, const char* key) {
    return map.IsDefined() && map.IsMap() ? map[key] : YAML::Node(YAML::NodeType::Undefined);
  };
  const auto drop = [&](YAML::Node map, const char* key) {
    if (child(map, key).IsDefined()) map.remove(key);
  };
  const YAML::Node top = root;
  for (const auto& [path, origin] : context.overrides) {
    for (const std::string list : {"targets", "world.occluders"}) {
      const std::string head = list + "[";
      const std::string tail = "].model";
      if (path.size() <= head.size() + tail.size() || path.rfind(head, 0) != 0 ||
          path.compare(path.size() - tail.size(), tail.size(), tail) != 0) {
        continue;
      }
      const std::string digits = path.substr(head.size(), path.size() - head.size() - tail.size());
      if (!std::all_of(digits.begin(), digits.end(), ::isdigit) || digits.size() > 9) continue;
      if (overridden(path + "_digest")) continue;
      const YAML::Node items =
          list == "targets" ? child(top, "targets") : child(child(top, "world"), "occluders");
      const size_t index = std::stoul(digits);
      if (items.IsDefined() && items.IsSequence() && index < items.size()) {
        drop(items[index], "model_digest");
      }
    }
    if (path == "observation.file.path" && !overridden("observation.file.digest")) {
      drop(child(child(top, "observation"), "file"), "digest");
    }
  }
}

Scenario LoadFromNode(YAML::Node root, const std::string& file,
                      const std::vector<Override>& overrides, ScenarioUse use) {
  auto context = std::make_shared<YamlContext>();
  context->file = file;
  if ((!root.IsDefined() || root.IsNull()) && overrides.empty()) {
    throw InputError(SourceLocation{file, 1, 1, ""},
                     "a scenario: a mapping with at least frames, camera and targets",
                     config::DescribeNullRoot(root), "start from a file in scenarios/library/");
  }
  if (!root.IsDefined() || root.IsNull()) root = YAML::Node(YAML::NodeType::Map);
  if (!root.IsMap()) {
    throw InputError(SourceLocation{file, 1, 1, ""}, "a scenario mapping (key: value lines)",
                     "a " + std::string(root.IsSequence() ? "list" : "single value"));
  }
  // A sweep file (base:, grid: or zip: at the top, as hcpf validate tells
  // them apart) given where a scenario goes: say so, instead of failing at
  // its first key that a scenario reads differently (`seeds: 2`).
  {
    const YamlReader r(root, "", context);
    for (auto it = root.begin(); it != root.end(); ++it) {
      const std::string key = it->first.IsScalar() ? it->first.Scalar() : "";
      if (std::find(kSweepFileKeys.begin(), kSweepFileKeys.end(), key) == kSweepFileKeys.end()) {
        continue;
      }
      throw InputError(r.Key(it->first).Where(), "a scenario file",
                       fmt::format("a sweep file (it has `{}:` at the top)", key),
                       "hcpf sweep FILE --out DIR runs a sweep; a sweep's base and a regress "
                       "suite's scenes are scenario files");
    }
    // A regression suite or baseline likewise (a bad-input audit: "required
    // key frames missing", never saying what the file was).
    for (auto it = root.begin(); it != root.end(); ++it) {
      if (!it->first.IsScalar() || it->first.Scalar() != "scenes") continue;
      throw InputError(r.Key(it->first).Where(), "a scenario file",
                       "a regression suite or baseline (it has `scenes:` at the top)",
                       "hcpf regress SUITE.yaml --baseline BASELINE.json runs a suite; its "
                       "scenes name scenario files");
    }
  }
  ApplyOverrides(root, overrides, context.get());
  DropDigestsOfRenamedFiles(root, *context);
  return ReadScenario(YamlReader(root, "", context), file, use);
}

}  // namespace

Scenario LoadScenarioText(const std::string& text, const std::string& file_name,
                          const std::vector<Override>& overrides, ScenarioUse use) {
  return LoadFromNode(YamlReader::Parse(text, file_name), file_name, overrides, use);
}

Scenario LoadScenarioFile(const std::string& path, const std::vector<Override>& overrides,
                          ScenarioUse use) {
  if (std::filesystem::is_directory(path)) {
    throw InputError(SourceLocation{path, 0, 0, ""}, "a scenario YAML file", "a directory");
  }
  return LoadFromNode(YamlReader::ParseFile(path), path, overrides, use);
}

Scenario LoadScenarioFromCommandLine(const std::string& path,
                                     const std::vector<Override>& overrides, ScenarioUse use) {
  try {
    return LoadScenarioFile(path, overrides, use);
  } catch (const InputError& e) {
    // At an override's own value the error already names it (--set k=v).
    if (overrides.empty() || e.where().override_index >= 0) throw;
    // An error of the file itself, which it makes without the overrides, as it is.
    try {
      LoadScenarioFile(path, {}, use);
    } catch (const InputError&) {
      throw e;
    }
    std::vector<std::string> labels;
    for (const Override& o : overrides) labels.push_back(o.Label());
    const std::string with = fmt::format("with {}", fmt::join(labels, ", "));
    throw InputError(e.where(), e.expected(), e.found(),
                     e.hint().empty() ? with : e.hint() + "; " + with);
  }
}

CameraTurn StrongestCameraTurn(const Scenario& scenario) {
  const CameraSpec& camera = scenario.world.camera;
  CameraTurn worst;
  Eigen::Matrix3d previous = Eigen::Matrix3d::Identity();
  for (int frame = 0; frame < scenario.world.frames; ++frame) {
    const Eigen::Matrix3d r = EvaluateCamera(camera, frame).pose.world_from_camera;
    if (frame > 0) {
      // The previous right axis carried by the smallest rotation from the
      // previous view to this one: what is left is the image's own turn.
      const Eigen::Vector3d carried =
          Eigen::Quaterniond::FromTwoVectors(previous.col(2), r.col(2)) * previous.col(0);
      const double turn_deg =
          std::abs(std::atan2(carried.cross(r.col(0)).dot(r.col(2)), carried.dot(r.col(0)))) *
          180.0 / std::numbers::pi;
      if (turn_deg > worst.degrees) worst = {turn_deg, frame};
    }
    previous = r;
  }
  return worst;
}

std::string CameraTurnReason() {
  return "a view near straight down turns the image as its heading swings, and most of all near "
         "the view 6 degrees south of straight down (the camera north of what it looks at), where "
         "the image's up is undefined (docs/scenario.md); trackers and camera-motion estimators "
         "see that turn at once";
}

std::string CameraTurnNote(const Scenario& scenario) {
  const CameraTurn worst = StrongestCameraTurn(scenario);
  if (!(worst.degrees > kCameraTurnNoteDeg)) return "";
  return fmt::format(
      "the image turns by {:.1f} degrees about its centre from frame {} to {} "
      "(camera.path): {}",
      worst.degrees, worst.frame - 1, worst.frame, CameraTurnReason());
}

Scenario Reseeded(const Scenario& scenario, uint64_t seed) {
  Scenario s = scenario;
  s.seed = seed;
  DeriveSeeds(&s);
  return s;
}

}  // namespace hcpf::scenarios
