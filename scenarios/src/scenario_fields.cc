// The declared fields of the scenario-level Options structs (scenario.h).
// Where a quantity is also checked by a library module (the sensor and
// renderer options), the range is taken from that module's declaration, so
// each range is written once.

#include <fmt/format.h>

#include <algorithm>

#include "hcpf/renderer/renderer.h"
#include "hcpf/scenarios/models.h"
#include "hcpf/scenarios/scenario.h"

namespace hcpf::scenarios {
namespace {

constexpr double kBig = 1e6;  // generous bound for world coordinates, metres
const FieldRange kWorld = Closed(-kBig, kBig);
// Frame numbers are declared in [0, kMaxFrames - 1]; the reader also checks
// them against the scenario's own `frames` (a rule across keys).

// A file the scenario names (`Member`): resolved by the reader (models.h),
// written relative to the project folder, left out when unset.
template <auto Member>
Field<typename hcpf::internal::MemberOf<decltype(Member)>::Object> FileField(std::string_view key,
                                                                             std::string_view doc) {
  using O = typename hcpf::internal::MemberOf<decltype(Member)>::Object;
  Field<O> f;
  f.key = key;
  f.type = FieldType::kPath;
  f.doc = doc;
  f.get_text = [](const O& o) {
    const std::string& path = o.*Member;
    return path.empty() ? path : PortableModelPath(path);
  };
  f.set_text = [](O& o, std::string v) { o.*Member = std::move(v); };
  return f;
}

// The `model` file of a target or a mesh occluder.
template <class O>
Field<O> ModelField(std::string_view doc) {
  return FileField<&O::model>("model", doc);
}

// Its content, pinned by the resolved YAML (models.h, ModelDigest).
template <class O>
Field<O> ModelDigestField() {
  Field<O> f = DefaultDoc(
      TextField<&O::model_digest>(
          "model_digest",
          "XXH3-128 of the `model` file's content and of the files beside it that it names "
          "(a glTF's buffers, an .obj's material libraries), 32 hex digits, written by the "
          "resolved YAML; when given, the files must still have it (a `--set` of `model` "
          "alone drops it)"),
      "none (a model only)");
  f.omitted_when_empty = true;
  return f;
}

}  // namespace

std::span<const Field<Scenario>> ScenarioFields() {
  using O = Scenario;
  static const std::vector<Field<O>> fields = {
      DefaultDoc(TextField<&O::name>(
                     "name",
                     "no control characters, NEL or U+2028/9 (it is written into seqinfo.ini "
                     "and manifests)"),
                 "file name without extension"),
      SeedField("seed", &O::seed, "drives every random stream"),
  };
  return fields;
}

std::span<const Field<Seeds>> SeedFields() {
  using O = Seeds;
  static const std::vector<Field<O>> fields = {
      DefaultDoc(SeedField("world", &O::world, "terrain relief, camera shake"),
                 "derived from `seed`"),
      DefaultDoc(SeedField("observation", &O::observation,
                           "simulated detections, clutter, likelihood-map noise"),
                 "derived from `seed`"),
      DefaultDoc(
          SeedField("tracker", &O::tracker, "particle filters (`tracker/filter/<id>` below it)"),
          "derived from `seed`"),
      DefaultDoc(SeedField("renderer", &O::renderer, "sensor noise, procedural textures"),
                 "derived from `seed`"),
  };
  return fields;
}

std::span<const Field<WorldSpec>> WorldFields() {
  using O = WorldSpec;
  static const std::vector<Field<O>> fields = {
      Required(IntegerField("frames", &O::frames, 1, kMaxFrames, "frames",
                            "length of the run (see Large scenarios)")),
      NumberField("fps", &O::fps, Closed(0.1, 10000), "frames/s", "frame rate"),
  };
  return fields;
}

std::span<const Field<OccluderSpec>> OccluderKindFields() {
  static const std::vector<Field<OccluderSpec>> fields = {
      Required(ChoiceField<&OccluderSpec::kind>("kind", "selects the other keys")),
  };
  return fields;
}

std::span<const Field<OccluderSpec>> OccluderFields(OccluderKind kind) {
  using O = OccluderSpec;
  const auto at = [] {
    return Required(VectorField<&O::at_m>("at", "x, y", kWorld, "m", "position on the ground"));
  };
  const auto yaw = [] {
    return NumberField("yaw_deg", &O::yaw_deg, Closed(-360, 360), "deg",
                       "counter-clockwise from +x");
  };
  static const std::vector<Field<O>> bridge = {
      Required(VectorField<&O::from_m>("from", "x, y", kWorld, "m", "one end of the deck")),
      Required(VectorField<&O::to_m>("to", "x, y", kWorld, "m",
                                     "the other end, at least 0.1 m from `from`")),
      NumberField("width_m", &O::width_m, Closed(0.1, 1000), "m", "deck width"),
      NumberField("height_m", &O::height_m, Closed(1.5, 1000), "m",
                  "deck top above the ground (a 1 m deck plus a pier at each end)"),
  };
  static const std::vector<Field<O>> building = {
      at(),
      VectorField<&O::size_m>("size_m", "x, y, z", Closed(0.1, 10000), "m", "box size"),
      yaw(),
  };
  static const std::vector<Field<O>> tree = {
      at(),
      NumberField("height_m", &O::height_m, Closed(0.5, 200), "m", "trunk + canopy boxes"),
  };
  static const std::vector<Field<O>> mesh = {
      Required(ModelField<O>(
          "a model file, found as for `targets[i].model`; occludes as its bounding box")),
      ModelDigestField<O>(),
      at(),
      yaw(),
      NumberField("scale", &O::scale, Closed(1e-3, 1e3), "", "uniform scale"),
  };
  switch (kind) {
    case OccluderKind::kBridge:
      return bridge;
    case OccluderKind::kBuilding:
      return building;
    case OccluderKind::kTree:
      return tree;
    case OccluderKind::kMesh:
      return mesh;
  }
  return building;
}

OccluderSpec OccluderDefaults(OccluderKind kind) {
  OccluderSpec o;
  o.kind = kind;
  if (kind == OccluderKind::kTree) o.height_m = 9.0;
  return o;
}

std::span<const Field<CameraSpec>> CameraFields() {
  using O = CameraSpec;
  static const std::vector<Field<O>> fields = [] {
    Field<O> resolution;
    resolution.key = "resolution";
    resolution.type = FieldType::kVector;
    resolution.unit = "px";
    resolution.range = Closed(16, 8192);
    resolution.doc = "image size";
    resolution.size = 2;
    resolution.whole = true;
    resolution.elements = "width, height";
    resolution.required = true;
    resolution.get_vector = [](const O& c) {
      return std::vector<double>{static_cast<double>(c.width_px), static_cast<double>(c.height_px)};
    };
    resolution.set_vector = [](O& c, const std::vector<double>& v) {
      c.width_px = static_cast<int>(v[0]);
      c.height_px = static_cast<int>(v[1]);
    };
    return std::vector<Field<O>>{
        resolution,
        NumberField("fov_deg", &O::hfov_deg, Closed(1, 170), "deg",
                    "horizontal field of view; square pixels"),
        NumberField("shake_px", &O::shake_px, Closed(0, 100), "px",
                    "std. dev. of a per-frame jitter of the optical centre (`seeds.world`)"),
    };
  }();
  return fields;
}

std::span<const Field<CameraKeyframe>> KeyframeFields() {
  using O = CameraKeyframe;
  static const std::vector<Field<O>> fields = {
      Required(IntegerField("frame", &O::frame, 0, kMaxFrames - 1, "frame",
                            "at most frames − 1; strictly increasing along the list")),
      Required(VectorField<&O::position_m>("position", "x, y, z", kWorld, "m", "camera centre")),
      Required(VectorField<&O::look_at_m>("look_at", "x, y, z", kWorld, "m",
                                          "a point on the optical axis, ≠ position")),
  };
  return fields;
}

std::span<const Field<TargetSpec>> TargetFields() {
  using O = TargetSpec;
  static const std::vector<Field<O>> fields = [] {
    Field<O> id = IntegerField<O>("id", nullptr, 1, 1'000'000'000, "", "unique; the MOT id");
    id.required = true;
    id.get_integer = [](const O& t) { return static_cast<int64_t>(Value(t.id)); };
    id.set_integer = [](O& t, int64_t v) { t.id = ObjectId{static_cast<int32_t>(v)}; };
    const Field<O> model = DefaultDoc(
        ModelField<O>("`.glb`/`.gltf`/`.obj`/`.fbx`/`.dae`/`.stl` (`.ply` is refused, "
                      "docs/fuzzing.md); looked for next to the scenario file, then in the "
                      "current folder, then in the project folder"),
        "none (a box)");
    return std::vector<Field<O>>{
        id,
        model,
        ModelDigestField<O>(),
        DefaultDoc(VectorField<&O::dimensions_m>("dimensions_m", "length, width, height",
                                                 Closed(0.05, 1000), "m", "box size"),
                   "from `model`'s bounds; required without a model"),
        VectorField<&O::tint>("tint", "r, g, b", Closed(0, 1), "", "colour"),
    };
  }();
  return fields;
}

std::span<const Field<TargetPathSpec>> PathFields() {
  using O = TargetPathSpec;
  static const std::vector<Field<O>> fields = {
      ChoiceField<&O::kind>("type", "selects the keys of the path's type (tables below)"),
      IntegerField("start_frame", &O::start_frame, 0, kMaxFrames - 1, "frame",
                   "first frame the target exists; at most frames − 1"),
      IntegerField("end_frame", &O::end_frame, -1, kMaxFrames - 1, "frame",
                   "last frame it exists: −1 (to the end) or start_frame … frames − 1"),
      NumberField("speed_mps", &O::speed_mps, Closed(0, 1000), "m/s", "> 0 for several waypoints"),
      NumberField("heading_deg", &O::heading_deg, Closed(-360, 360), "deg",
                  "counter-clockwise from +x (east); static targets and the start of a turn"),
  };
  return fields;
}

std::span<const Field<TargetPathSpec>> PathFields(PathKind kind) {
  using O = TargetPathSpec;
  static const std::vector<Field<O>> waypoints = [] {
    Field<O> at_end;
    at_end.key = "at_end";
    at_end.type = FieldType::kChoice;
    at_end.doc = "stay: stop at the last waypoint; vanish: leave the scene there";
    at_end.get_choice = [](const O& p) {
      return std::string_view(p.vanish_at_end ? "vanish" : "stay");
    };
    at_end.set_choice = [](O& p, std::string_view name) {
      if (name != "stay" && name != "vanish") return false;
      p.vanish_at_end = name == "vanish";
      return true;
    };
    at_end.choices = [] { return std::vector<std::string_view>{"stay", "vanish"}; };
    return std::vector<Field<O>>{
        Required(
            PointsField("waypoints", &O::waypoints_m, kWorld, "m", "one point = a static target")),
        at_end,
    };
  }();
  static const std::vector<Field<O>> constant_turn = {
      Required(VectorField<&O::start_m>("start", "x, y", kWorld, "m", "start position")),
      NumberField("turn_rate_deg_s", &O::turn_rate_deg_s, Closed(-360, 360), "deg/s",
                  "positive = left turn"),
  };
  return kind == PathKind::kWaypoints ? waypoints : constant_turn;
}

std::span<const Field<PathStop>> StopFields() {
  using O = PathStop;
  static const std::vector<Field<O>> fields = {
      Required(NumberField("at_m", &O::at_m, Closed(0, kBig), "m",
                           "distance travelled; increasing along the list")),
      Required(NumberField("duration_s", &O::duration_s, Closed(0, 1e5), "s", "wait")),
  };
  return fields;
}

std::span<const Field<SimulatedObservationOptions>> SimulatedObservationOptions::Fields() {
  using O = SimulatedObservationOptions;
  static const std::vector<Field<O>> fields = {
      NumberField("sigma_px", &O::sigma_px, Closed(0, 1000), "px",
                  "std. dev. of the detected centre"),
      NumberField("size_sigma", &O::size_sigma, Closed(0, 2), "",
                  "std. dev. of the log of width and height"),
      NumberField("p_detect", &O::p_detect, Closed(0, 1), "",
                  "detection probability of a fully visible target"),
      NumberField("visibility_exponent", &O::visibility_exponent, Closed(0, 10), "",
                  "p = p_detect · visible^exponent"),
      NumberField("min_visible", &O::min_visible, Closed(0, 1), "",
                  "never detected below this visible fraction"),
      NumberField("clutter_per_frame", &O::clutter_per_frame, Closed(0, 1000), "",
                  "Poisson mean of false detections"),
      FlagField("likelihood_map", &O::likelihood_map, "also produce a likelihood map"),
      NumberField("map_cell_px", &O::map_cell_px, Closed(1, 64), "px", "map cell size"),
      NumberField("map_blob_scale", &O::map_blob_scale, Closed(0.01, 10), "",
                  "blob σ = scale · (w + h) / 4"),
      NumberField("map_noise", &O::map_noise, Closed(0, 10), "", "uniform noise floor per cell"),
  };
  return fields;
}

std::vector<std::string_view> ObservationOptions::DetectorNames() {
  std::vector<std::string_view> names = {"oracle"};
  for (std::string_view n : vision::DetectorNames()) names.push_back(n);
  names.push_back("fusion");
  names.push_back("file");
  return names;
}

bool ObservationOptions::model_based() const {
  if (oracle() || from_file()) return false;
  const auto made = vision::MakeDetector(DetectorName(), detectors);
  return made != nullptr && made->uses_models();
}

std::span<const Field<DetectionFileOptions>> DetectionFileOptions::Fields() {
  using O = DetectionFileOptions;
  static const std::vector<Field<O>> fields = {
      DefaultDoc(FileField<&O::path>(
                     "path",
                     "detector file only (checked, no effect otherwise): a MOTChallenge det.txt "
                     "made on the frames of `hcpf render` of this scenario (frame, id, left, top, "
                     "width, height, score; 1-based), found like `targets[i].model`"),
                 "none (required with detector: file)"),
      // Scores are the program's own: any finite number may be a threshold.
      NumberField("min_score", &O::min_score, Closed(-1e9, 1e9), "",
                  "rows scoring below it are left out (neither tracked nor scored)"),
      FlagField("labels", &O::labels,
                "column 2 names the target each detection is of (a target id, or -1 for "
                "none), as in the det/det.txt of a model-based detector's run: each filter "
                "sees only its own target's detections, and is born at its target's first "
                "labelled row (needs tracker.init: ground_truth)"),
      DefaultDoc(TextField<&O::digest>(
                     "digest",
                     "XXH3-128 of the file's content (32 hex digits), written by the resolved "
                     "YAML; when given, the file must still have it (a `--set` of `path` alone "
                     "drops it)"),
                 "none"),
      DefaultDoc(FileField<&O::rendering>(
                     "rendering",
                     "the folder of `hcpf render` (or of a rendered `hcpf run`) whose frames the "
                     "det.txt was made on: its manifest.json's pixel_hash must be this "
                     "scenario's, else the run is refused naming the keys that differ"),
                 "none (not checked)"),
      DefaultDoc(TextField<&O::pixel_hash>(
                     "pixel_hash",
                     "the pixel hash of the frames the det.txt was made on (32 hex digits, "
                     "`pixel_hash` in the manifest of `hcpf render`): this scenario must render "
                     "those frames; the resolved YAML writes it when `rendering` is given"),
                 "none (not checked)"),
  };
  return fields;
}

std::string ObservationOptions::DetectorName() const {
  if (detector != "fusion") return detector;
  std::string name;
  for (const std::string& d : fused) name += (name.empty() ? "" : "+") + d;
  return name;
}

std::span<const Field<TrackerChoice>> TrackerChoice::Fields() {
  using O = TrackerChoice;
  static const std::vector<Field<O>> fields = {
      ChoiceField<&O::type>("type",
                            "particle_filter: the built-in filters (the keys below); external: "
                            "the program `command` (docs/external-trackers.md), the other "
                            "`tracker.*` keys then taking no effect"),
      DefaultDoc(StringsField<&O::command>(
                     "command", 1,
                     "type external only: the program and its arguments, no shell; a first word "
                     "with a `/` is found like `targets[i].model`, else on PATH"),
                 "none (required with type external)"),
      // 1 ms up to an hour: the program answers each frame, and a reply that
      // takes an hour is a hung program, not a slow one.
      NumberField("timeout_s", &O::timeout_s, Closed(0.001, 3600), "s",
                  "type external only (checked, no effect otherwise): how long to wait for each "
                  "reply (the hello's too) "
                  "before the run fails"),
  };
  return fields;
}

bool UsesPointTracker(const Scenario& scenario) {
  const tracker::CameraMotionMode mode = scenario.tracker.camera_motion;
  return scenario.tracker.scene_filter.evidence == tracker::SceneEvidenceKind::kImage &&
         (mode == tracker::CameraMotionMode::kSceneFilter ||
          mode == tracker::CameraMotionMode::kRansac);
}

bool UsesPerspective(const Scenario& scenario) {
  return scenario.perspective.enabled &&
         scenario.tracker.camera_motion == tracker::CameraMotionMode::kSceneFilter;
}

namespace {

// The points each scene particle is weighed on a frame, and what sets them.
struct ScenePoints {
  int64_t count = 0;
  const char* source = "";
};
ScenePoints SceneFilterPoints(const Scenario& scenario) {
  switch (scenario.tracker.scene_filter.evidence) {
    case tracker::SceneEvidenceKind::kSimulated:
      return {scenario.tracker.scene_filter.points, "tracker.scene_filter.points"};
    case tracker::SceneEvidenceKind::kImage:
      return {scenario.point_tracker.max_corners, "tracker.point_tracker.max_corners"};
    case tracker::SceneEvidenceKind::kOracle:
      return {int64_t{tracker::HomographyEvidence::kGrid} * tracker::HomographyEvidence::kGrid,
              "the oracle's 10 x 10 grid"};
  }
  return {};
}

// The hypotheses the Laplace proposal's Newton search weighs a frame
// (SceneMotionFilter::FindMode), whatever the particles: the 33-point
// stencil at the start and after each of typically four iterations, and a
// trial step each. A typical frame's count, so a lower bound: a frame whose
// search restarts from its best particle weighs them twice (and its
// particles twice), and up to 30 iterations of up to 30 trial steps. Left out, 10 particles x 10^6
// points counted 10^7 terms, 0.1 s, for a run that took 2.0 s a frame (a scale audit; crossing, 20
// frames, 39.5 s; 179 x 10^6 terms at 10 ns are 1.8 s).
constexpr int64_t kLaplaceHypotheses = 33 * 5 + 4;

int64_t SceneFilterHypotheses(const Scenario& scenario) {
  const tracker::SceneMotionOptions& o = scenario.tracker.scene_filter;
  return int64_t{o.particles} +
         (o.proposal == tracker::SceneProposal::kLaplace ? kLaplaceHypotheses : 0);
}

}  // namespace

int64_t SceneFilterEvaluationsPerFrame(const Scenario& scenario) {
  if (scenario.tracker.camera_motion != tracker::CameraMotionMode::kSceneFilter) return 0;
  return SceneFilterHypotheses(scenario) * SceneFilterPoints(scenario).count;
}

std::string SceneFilterCostWarning(const Scenario& scenario) {
  constexpr double kSecondsPerEvaluation = 10e-9;  // BM_SceneFilterStep/1000/200: 2.0 ms
  const int64_t evaluations = SceneFilterEvaluationsPerFrame(scenario);
  const double per_frame = static_cast<double>(evaluations) * kSecondsPerEvaluation;
  if (per_frame <= 1.0) return "";
  const ScenePoints points = SceneFilterPoints(scenario);
  const bool laplace = scenario.tracker.scene_filter.proposal == tracker::SceneProposal::kLaplace;
  return fmt::format(
      "the scene filter weighs (tracker.scene_filter.particles ({}){}) x {} ({}) = {:.3g} "
      "evidence terms a frame: about {:.3g} s a frame at ~10 ns each (BM_SceneFilterStep), "
      "{:.3g} h for {} frames; fewer particles or points make it faster{}",
      scenario.tracker.scene_filter.particles,
      laplace ? fmt::format(" + at least ~{} of the laplace proposal's Newton search",
                            kLaplaceHypotheses)
              : std::string(),
      points.source, points.count, static_cast<double>(evaluations), per_frame,
      per_frame * scenario.world.frames / 3600.0, scenario.world.frames,
      laplace ? ", as does tracker.scene_filter.proposal: dynamics (no Newton search)" : "");
}

bool UsesRansac(const Scenario& scenario) {
  return scenario.tracker.camera_motion == tracker::CameraMotionMode::kRansac ||
         UsesPerspective(scenario);
}

bool ObservationOptions::Uses(std::string_view name) const {
  if (detector == "fusion") return std::find(fused.begin(), fused.end(), name) != fused.end();
  return detector == name;
}

void ObservationOptions::Validate(const tracker::TrackerOptions& tracker) const {
  CheckFields(*this, Fields(), "observation");
  detectors.ForEach([](const char* name, const auto& options) {
    options.Validate(fmt::format("observation.{}", name));
  });
  if (detector == "fusion" && fused.size() < 2) {
    FailOption("observation", "detectors",
               WordsExpectation(2, vision::DetectorNames()) + " (detector: fusion fuses them)",
               "not written");
  }
  if (detector != "fusion" && !fused.empty()) {
    FailOption("observation", "detector",
               "fusion, or no observation.detector key (observation.detectors lists detectors "
               "to fuse)",
               "\"" + detector + "\" with observation.detectors");
  }
  if (search == SearchMode::kWindow && oracle()) {
    FailOption("observation", "search",
               "frame, or a model-based observation.detector (windows belong to target models)",
               "window with observation.detector: oracle");
  }
  if (tracker.scene_filter.evidence == tracker::SceneEvidenceKind::kImage &&
      source != ObservationSource::kRendered &&
      (tracker.camera_motion == tracker::CameraMotionMode::kSceneFilter ||
       tracker.camera_motion == tracker::CameraMotionMode::kRansac)) {
    FailOption("tracker.scene_filter", "evidence",
               "simulated or oracle (image evidence needs observation.source: rendered)", "image");
  }
  const bool reacquire = tracker.management.reacquire != tracker::ReacquireMode::kNone;
  constexpr std::string_view kReacquireNeeds =
      "none, or a model-based observation.detector or a detection file with labels: true (a "
      "filter is found again from its own target's detections, which only labelled detections "
      "name)";
  if (reacquire && oracle()) {
    FailOption("tracker.management", "reacquire", kReacquireNeeds,
               "own_detections with observation.detector: oracle");
  }
  // A map likelihood without maps leaves every filter unsupported: each one
  // coasts on its dynamics alone until it is deleted (a bad-input audit).
  const bool map_likelihood = tracker.likelihood.model == tracker::LikelihoodModel::kMap;
  const auto map_needs = [this] {
    std::vector<std::string> model_based;
    for (std::string_view d : vision::DetectorNames()) {
      if (vision::MakeDetector(d, detectors)->uses_models()) model_based.emplace_back(d);
    }
    return fmt::format(
        "a likelihood with a map to read: observation.simulated.likelihood_map: true with the "
        "oracle, or a model-based observation.detector ({})",
        fmt::join(model_based, ", "));
  };
  if (map_likelihood && oracle() && !simulated.likelihood_map) {
    FailOption("tracker.likelihood", "model", map_needs(),
               "map with the oracle and observation.simulated.likelihood_map: false");
  }
  if (oracle()) return;
  if (detector == "fusion") {
    const bool first = vision::MakeDetector(fused.front(), detectors)->uses_models();
    for (const std::string& d : fused) {
      if (vision::MakeDetector(d, detectors)->uses_models() != first) {
        FailOption("observation", "detectors",
                   "detectors that all use target models, or none that does (their "
                   "detections could not be fused per target)",
                   "\"" + fused.front() + "\" with \"" + d + "\"");
      }
    }
  }
  const std::string name = DetectorName();
  if (source != ObservationSource::kRendered) {
    FailOption("observation", "detector",
               "oracle, or observation.source: rendered (a detector needs rendered frames)",
               "\"" + name + "\" with observation.source: simulated");
  }
  if (from_file() && file.path.empty()) {
    FailOption("observation.file", "path",
               "the det.txt to read (detector: file reads another program's detections)",
               "not written");
  }
  const bool uses_models = model_based();
  if (search == SearchMode::kWindow && !uses_models) {
    FailOption("observation", "search",
               "frame, or a model-based observation.detector (windows belong to target models)",
               "window with observation.detector: " + name);
  }
  if (map_likelihood && !uses_models) {
    FailOption("tracker.likelihood", "model", map_needs(),
               "map with observation.detector: " + name + ", which makes no maps");
  }
  if (reacquire && !labelled()) {
    FailOption("tracker.management", "reacquire", kReacquireNeeds,
               "own_detections with observation.detector: " + name +
                   (from_file() ? " and file.labels: false" : ""));
  }
  if (from_file() && file.labels && tracker.init != tracker::InitMode::kGroundTruth) {
    FailOption("observation.file", "labels",
               "false, or true with tracker.init: ground_truth (a label names a target, and "
               "filters carry their target's id only when born from ground truth)",
               "true with tracker.init: " + std::string(NameOf(tracker.init)));
  }
  if (uses_models && tracker.init != tracker::InitMode::kGroundTruth) {
    FailOption("observation", "detector",
               "a detector without target models, or tracker.init: ground_truth (the \"" + name +
                   "\" models are cut where filters are born from ground truth)",
               "\"" + name + "\" with tracker.init: " + std::string(NameOf(tracker.init)));
  }
}

std::span<const Field<ObservationOptions>> ObservationOptions::Fields() {
  using O = ObservationOptions;
  static const std::vector<Field<O>> fields = {
      ChoiceField<&O::source>("source",
                              "simulated: detection level, no pixels; rendered: frames are "
                              "rendered with pixel-exact ground truth"),
      WordField<&O::detector, &ObservationOptions::DetectorNames>(
          "detector",
          "oracle: noisy ground truth, labelled as oracle in results; else a detector on the "
          "rendered frames (docs/vision.md); fusion: the `detectors` fused; file: another "
          "program's detections, read from `file.path`"),
      ChoiceField<&O::search>(
          "search",
          "frame: a model-based detector searches the whole frame; window: around each "
          "filter's estimate of the previous frame (side: the detector's window_scale x the "
          "box), the tracker stepping frame by frame with the detector"),
      WordsField<&O::fused, &vision::DetectorNames>(
          "detectors", 2,
          "detectors to run together and fuse (thesis ch. 10); writing it alone implies "
          "detector: fusion"),
  };
  return fields;
}

std::span<const Field<SensorOptions>> SensorOptions::Fields() {
  using O = SensorOptions;
  const auto renderer = renderer::SensorOptions::Fields();
  static const std::vector<Field<O>> fields = {
      NumberField("noise_sigma", &O::noise_sigma, RangeOf(renderer, "noise_sigma"), "grey levels",
                  "std. dev. of additive Gaussian noise"),
      NumberField("blur_px", &O::blur_px, RangeOf(renderer, "blur_px"), "px",
                  "Gaussian blur σ; 0 = off"),
      IntegerField("jpeg_quality", &O::jpeg_quality, 1, 100, "",
                   "JPEG round trip quality; 100 = no round trip"),
      NumberField("exposure", &O::exposure, RangeOf(renderer, "exposure"), "",
                  "gain on pixel values"),
  };
  return fields;
}

std::vector<std::string_view> RendererConfig::BackendNames() { return {"auto", "osmesa", "egl"}; }

std::span<const Field<RendererConfig>> RendererConfig::Fields() {
  using O = RendererConfig;
  const auto renderer = renderer::RendererOptions::Fields();
  const auto integer = [&renderer](const char* key, int O::*member, const char* unit,
                                   const char* doc) {
    const FieldRange& r = RangeOf(renderer, key);
    return IntegerField(key, member, static_cast<int>(r.lo), static_cast<int>(r.hi), unit, doc);
  };
  static const std::vector<Field<O>> fields = {
      WordField<&O::backend, &RendererConfig::BackendNames>(
          "backend", "auto: a hardware EGL device (GPU), else OSMesa, else EGL surfaceless"),
      integer("shadow_map_size", &O::shadow_map_size, "texels", "shadow map size per side"),
      integer("pcf_radius", &O::pcf_radius, "texels",
              "0 = one bilinear depth-comparison tap (2×2 PCF), r > 0 = (2r)² taps"),
      FlagField("write_frames", &O::write_frames,
                "hcpf run: also write frames/NNNNNN.png (rendered even at detection level)"),
      FlagField("write_depth", &O::write_depth,
                "hcpf run and render: also write frames/NNNNNN_depth.png (16-bit, in "
                "depth_unit_mm)"),
      NumberField("depth_unit_mm", &O::depth_unit_mm, AboveUpTo(0, 1e6), "mm",
                  "write_depth: the depth PNG's unit; its 16 bits hold 65535 of them (65.5 m "
                  "at 1, 655 m at 10), farther is written 65535 and the run says how many"),
      FlagField("write_instance_ids", &O::write_instance_ids,
                "hcpf run and render: also write frames/NNNNNN_ids.png (16-bit, id + 1)"),
  };
  return fields;
}

}  // namespace hcpf::scenarios
