#pragma once
// A scenario: everything one run needs, validated, with every default and
// every seed filled in. Loaded from YAML (docs/scenario.md is the schema).

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hcpf/config/overrides.h"
#include "hcpf/core/fields.h"
#include "hcpf/core/world.h"
#include "hcpf/metrics/filter_metrics.h"
#include "hcpf/metrics/point_metrics.h"
#include "hcpf/tracker/tracker.h"
#include "hcpf/vision/detectors.h"
#include "hcpf/vision/point_tracks.h"

namespace hcpf::scenarios {

// Seeds of the named sub-streams. Each defaults to a value derived from the
// scenario seed and its name, and may be pinned in YAML (`seeds.<name>`), so a
// sweep can vary the tracker's randomness while keeping the observations fixed.
struct Seeds {
  uint64_t world = 0;        // terrain relief, camera shake
  uint64_t observation = 0;  // simulated detections and clutter
  uint64_t tracker = 0;      // particle filters
  uint64_t renderer = 0;     // sensor noise, procedural textures
};

// The seed of stream `name` ("world", "observation", "tracker", "renderer")
// that a scenario's `seed` gives it where `seeds:` does not pin it.
uint64_t DeriveSeed(uint64_t seed, const char* name);

// The simulated (oracle) detector of detection-level mode.
struct SimulatedObservationOptions {
  double sigma_px = 2.0;               // std. dev. of the detected centre, pixels
  double size_sigma = 0.05;            // std. dev. of log box size (relative)
  double p_detect = 0.95;              // detection probability of a fully visible target
  double visibility_exponent = 1.0;    // p = p_detect * visible_fraction^exponent
  double min_visible = 0.05;           // no detection below this visible fraction
  double clutter_per_frame = 1.0;      // Poisson mean of false detections per frame
  std::map<int32_t, double> strength;  // per target id; absent = 1.0
  bool likelihood_map = false;         // also produce a likelihood map
  double map_cell_px = 4.0;            // map resolution: image pixels per cell
  double map_blob_scale = 0.5;         // blob std. dev. = scale * mean(box w, h) / 2
  double map_noise = 0.05;             // noise floor: max of uniform noise per cell

  // The declared fields (core/fields.h), all but `strength` (a map by id).
  static std::span<const Field<SimulatedObservationOptions>> Fields();

  double StrengthOf(int32_t id) const {
    const auto it = strength.find(id);
    return it == strength.end() ? 1.0 : it->second;
  }
};

enum class ObservationSource { kSimulated, kRendered };
// Where a model-based detector looks for each target: the whole frame, or a
// window around its filter's estimate of the previous frame.
enum class SearchMode { kFrame, kWindow };

}  // namespace hcpf::scenarios

template <>
struct hcpf::EnumNames<hcpf::scenarios::ObservationSource> {
  static constexpr std::array kNames = {
      std::pair{hcpf::scenarios::ObservationSource::kSimulated, std::string_view("simulated")},
      std::pair{hcpf::scenarios::ObservationSource::kRendered, std::string_view("rendered")}};
};

template <>
struct hcpf::EnumNames<hcpf::scenarios::SearchMode> {
  static constexpr std::array kNames = {
      std::pair{hcpf::scenarios::SearchMode::kFrame, std::string_view("frame")},
      std::pair{hcpf::scenarios::SearchMode::kWindow, std::string_view("window")}};
};

namespace hcpf::scenarios {

// `observation.file.*`: detector `file` reads the detections another program
// made on this scenario's rendered frames (`hcpf render`), a MOTChallenge
// det.txt (docs/vision.md "A detector of one's own in the tracker").
struct DetectionFileOptions {
  // The det.txt, found like a model file (next to the scenario file, the
  // current folder, the project folder) and held as an absolute path.
  std::string path;
  // Rows scoring below this are left out (neither tracked nor scored); the
  // run says how many. 0 keeps every row of a detector whose scores are
  // confidences in [0, 1].
  double min_score = 0.0;
  // Whether column 2 (MOTChallenge's id, -1 in a det.txt) names the target
  // each detection is of, as a target-specific detector's output does (the
  // det/det.txt of a model-based detector's run): a target id of the
  // scenario, or -1 for a detection of none. Each filter then sees only its
  // own target's detections (tracker.init: ground_truth numbers filters by
  // target).
  bool labels = false;
  // XXH3-128 of the file's content, 32 hex digits: the resolved YAML writes
  // it, so the run's identity (config hash) changes with the file's content;
  // written in a scenario, the file must still have it.
  std::string digest;
  // The folder of `hcpf render` (or of a rendered `hcpf run`) whose frames
  // the det.txt was made on, held as an absolute path: its manifest's
  // pixel_hash must be this scenario's, so a det.txt of another scene, seed
  // or renderer setting is refused at load time.
  std::string rendering;
  // renderer::PixelHash of the frames the det.txt was made on (32 hex
  // digits): written, or read from `rendering`'s manifest; this scenario
  // must render those frames. The resolved YAML writes it.
  std::string pixel_hash;
  // The file's detections kept (score >= min_score), by 0-based frame: read
  // at load time with detector: file, so `hcpf validate` checks every row.
  std::shared_ptr<const std::vector<std::vector<Detection>>> frames;
  int rows = 0;      // the file's rows
  int left_out = 0;  // of them, scoring below min_score

  // path, min_score, labels, digest, rendering, pixel_hash
  static std::span<const Field<DetectionFileOptions>> Fields();
};

struct ObservationOptions {
  ObservationSource source = ObservationSource::kSimulated;
  // "oracle" (noisy ground truth, both sources), a vision/ detector on the
  // rendered frames (vision::DetectorNames()), "fusion": the detectors
  // listed in `fused` (key `detectors`), run on every frame and fused, or
  // "file": another program's detections (`file`).
  std::string detector = "oracle";
  std::vector<std::string> fused;  // `observation.detectors`, with detector: fusion
  SearchMode search = SearchMode::kFrame;
  SimulatedObservationOptions simulated;
  vision::DetectorOptions detectors;  // `observation.<detector>.*`
  DetectionFileOptions file;          // `observation.file.*`

  // source, detector, detectors
  static std::span<const Field<ObservationOptions>> Fields();
  static std::vector<std::string_view> DetectorNames();  // oracle, vision's, fusion, file
  bool oracle() const { return detector == "oracle"; }
  bool from_file() const { return detector == "file"; }
  // Whether the detector labels its detections with their target (a
  // model-based vision/ detector, or a fusion of them); false for the
  // oracle and the file.
  bool model_based() const;
  // Whether the detections carry their target: model_based(), or the file
  // with file.labels.
  bool labelled() const { return model_based() || (from_file() && file.labels); }
  // The vision/ detector's name as vision::MakeDetector takes it: `detector`,
  // or the fused names joined by '+' ("sks+prca"); "oracle" for the oracle,
  // "file" for the file.
  std::string DetectorName() const;
  // Whether the vision/ detector `name` runs in this scenario.
  bool Uses(std::string_view name) const;
  // The rules across keys: a detector needs rendered frames; a detector with
  // target models needs filters born from ground truth (`tracker.init`),
  // which is where its models come from. Throws InputError naming the key.
  void Validate(const tracker::TrackerOptions& tracker) const;
};

struct SensorOptions {
  double noise_sigma = 0.0;  // Gaussian noise, 8-bit grey levels
  double blur_px = 0.0;      // Gaussian blur std. dev., pixels
  int jpeg_quality = 100;    // 100 = no JPEG round trip
  double exposure = 1.0;     // multiplies linear intensity

  // The declared fields; ranges are the renderer's (renderer::SensorOptions).
  static std::span<const Field<SensorOptions>> Fields();
};

struct RendererConfig {
  std::string backend = "auto";  // auto | osmesa | egl
  int shadow_map_size = 1024;
  // Shadow filter radius: 0 = one bilinear depth-comparison tap (2x2 PCF, the
  // default: 64 fps at 640x480 on one llvmpipe core), r > 0 = (2r)^2 such taps.
  int pcf_radius = 0;
  bool write_frames = false;  // `hcpf run`: also write frames/*.png
  bool write_depth = false;
  // write_depth: the depth PNG's unit; its 16 bits hold 65535 of them.
  double depth_unit_mm = 1.0;
  bool write_instance_ids = false;

  // The declared fields; ranges are the renderer's (renderer::RendererOptions).
  static std::span<const Field<RendererConfig>> Fields();
  static std::vector<std::string_view> BackendNames();
};

// Which tracker a run uses: the built-in particle filters (`tracker.*`), or
// an external program speaking the line protocol of docs/external-trackers.md.
enum class TrackerType { kParticleFilter, kExternal };

}  // namespace hcpf::scenarios

template <>
struct hcpf::EnumNames<hcpf::scenarios::TrackerType> {
  static constexpr std::array kNames = {
      std::pair{hcpf::scenarios::TrackerType::kParticleFilter, std::string_view("particle_filter")},
      std::pair{hcpf::scenarios::TrackerType::kExternal, std::string_view("external")}};
};

namespace hcpf::scenarios {

// `tracker.type`, `tracker.command`, `tracker.timeout_s`. With type external
// the particle filter's `tracker.*` keys do not take effect: the reader
// accepts them and resets them to their defaults, and the resolved YAML
// (so the config hash) holds only these three keys of `tracker`.
struct TrackerChoice {
  TrackerType type = TrackerType::kParticleFilter;
  // The program and its arguments (no shell). command[0] with a '/' is a
  // file found like a model (next to the scenario file, the current folder,
  // the project folder) and held as an absolute path; a bare name is looked
  // up on PATH at load time and kept as written.
  std::vector<std::string> command;
  // Seconds to wait for each reply of the program (the hello's included).
  double timeout_s = 10.0;

  static std::span<const Field<TrackerChoice>> Fields();
  bool external() const { return type == TrackerType::kExternal; }
};

// Scoring options of a run (metrics/ Options, filled from `metrics.*`).
struct MetricsConfig {
  metrics::FilterMetricsOptions filters;
  metrics::PointMetricsOptions points;
};

struct Scenario {
  std::string source_file;  // where it was loaded from (for messages)
  std::string name;
  uint64_t seed = 1;
  Seeds seeds;
  WorldSpec world;
  ObservationOptions observation;
  SensorOptions sensor;
  RendererConfig renderer;
  TrackerChoice tracker_choice;     // `tracker.type`, `tracker.command`, `tracker.timeout_s`
  tracker::TrackerOptions tracker;  // `tracker.*` (threads: a run option, not a key)
  // `tracker.point_tracker.*` and `tracker.ransac.*`: the vision/ side of the
  // camera-motion estimate (the image evidence's corners and Lucas-Kanade,
  // shared by scene_filter and ransac; the RANSAC baseline's settings).
  vision::PointTrackerOptions point_tracker;
  vision::RansacOptions ransac;
  // `tracker.perspective.*`: the scene filter's perspective stage.
  vision::PerspectiveOptions perspective;
  MetricsConfig metrics;
  // Which of `seeds` the input gave explicitly (bits kPinned*): Reseeded keeps
  // those and derives the others from the new seed.
  uint8_t pinned_seeds = 0;
  static constexpr uint8_t kPinnedWorld = 1, kPinnedObservation = 2, kPinnedTracker = 4,
                           kPinnedRenderer = 8;
};

// Whether the run tracks background points through the rendered frames
// (tracker.camera_motion scene_filter or ransac with scene_filter.evidence:
// image), so `tracker.point_tracker` takes effect; whether the RANSAC
// baseline runs, so `tracker.ransac` does. The resolved YAML (and so the
// config hash) holds a section only when it takes effect.
bool UsesPointTracker(const Scenario& scenario);
bool UsesRansac(const Scenario& scenario);
// Whether the scene filter's perspective stage runs (tracker.perspective.enabled
// with camera_motion scene_filter; written to the resolved YAML only then,
// so every other scenario's config hash is unchanged). It fits the RANSAC
// similarity for its inliers, so `tracker.ransac` takes effect too.
bool UsesPerspective(const Scenario& scenario);

// The scene filter's evidence evaluations a frame: its hypotheses (its
// particles, and with the laplace proposal the ~169 its Newton search weighs)
// times the points each one is weighed on (scene_filter.points for simulated
// evidence, at most point_tracker.max_corners for image evidence, the 10 x 10
// grid of the oracle); 0 when no scene filter runs (tracker.camera_motion
// other than scene_filter).
int64_t SceneFilterEvaluationsPerFrame(const Scenario& scenario);
// A warning for a scene filter that would take more than a second a frame at
// about 10 ns an evaluation (BM_SceneFilterStep: 2.0 ms for 1000 particles
// x 200 points, docs/tracker.md), naming the keys, the estimate and the whole
// run's; "" otherwise. Both keys' ranges allow 10^13 evaluations a frame.
std::string SceneFilterCostWarning(const Scenario& scenario);

// The declared fields of the scenario's own keys (scenario_fields.cc), from
// which the reader, the resolved-YAML writer and docs/scenario.md are made;
// the modules' Options structs declare theirs next to the struct. A list
// (occluders, camera.path, targets, path.stops) is read item by item with
// the item's table; `kind` / `type` select the table of the kind's keys.
std::span<const Field<Scenario>> ScenarioFields();          // name, seed
std::span<const Field<Seeds>> SeedFields();                 // seeds.world, ...
std::span<const Field<WorldSpec>> WorldFields();            // frames, fps
std::span<const Field<OccluderSpec>> OccluderKindFields();  // kind
std::span<const Field<OccluderSpec>> OccluderFields(OccluderKind kind);
// An occluder of `kind` with that kind's defaults (a tree is 9 m high, a bridge deck 6 m).
OccluderSpec OccluderDefaults(OccluderKind kind);
std::span<const Field<CameraSpec>> CameraFields();
std::span<const Field<CameraKeyframe>> KeyframeFields();
std::span<const Field<TargetSpec>> TargetFields();
std::span<const Field<TargetPathSpec>> PathFields();  // type and the keys of every type
std::span<const Field<TargetPathSpec>> PathFields(PathKind kind);
std::span<const Field<PathStop>> StopFields();

// `--set key=value` overrides (hcpf/config/overrides.h).
using config::Override;
using config::ParseOverride;

// The top-level keys that make a YAML file a sweep file (docs/sweeps.md);
// a scenario has none of them. hcpf validate tells the two apart by them
// (studies::IsSweepFile), and a sweep file given where a scenario goes is
// refused by them.
inline constexpr std::array<std::string_view, 3> kSweepFileKeys = {"base", "grid", "zip"};

// What a scenario is loaded for: a run (`hcpf run`, `hcpf validate`, a
// sweep's cells), which renders when its observation source or renderer
// keys say so, or `hcpf render`, which always renders: what only the
// renderer limits (at most renderer::kMaxRenderedTargets targets) is then
// checked at load, at the line of `targets`, for every scenario.
enum class ScenarioUse { kRun, kRender };

// Loads, applies overrides, validates and resolves a scenario. Throws
// InputError naming file, line, column, key, expected and found.
Scenario LoadScenarioFile(const std::string& path, const std::vector<Override>& overrides = {},
                          ScenarioUse use = ScenarioUse::kRun);
Scenario LoadScenarioText(const std::string& text, const std::string& file_name,
                          const std::vector<Override>& overrides = {},
                          ScenarioUse use = ScenarioUse::kRun);
// LoadScenarioFile for a command's FILE and --set overrides: an error that
// the overrides make at a line of the file valid on its own (another
// target's id, a path frame past the overridden frames) ends with the
// overrides ("with --set frames=10"), as a sweep names a cell's swept
// values (a bad-input audit: the line was blamed, the override unnamed).
Scenario LoadScenarioFromCommandLine(const std::string& path,
                                     const std::vector<Override>& overrides,
                                     ScenarioUse use = ScenarioUse::kRun);

// The resolved scenario as YAML: every key with its value, seeds included.
// Loading this text gives back an identical Scenario (and the same text).
std::string ToResolvedYaml(const Scenario& scenario);

// Stable 64-bit hash (hex) of the resolved YAML: the run's identity.
std::string ConfigHash(const Scenario& scenario);
// The same hash of a resolved YAML text.
std::string HashResolvedYaml(const std::string& resolved_yaml);

// The scenario as loading it with `--set seed=SEED` gives: the top-level seed
// replaced, every seed the input did not pin derived from it again. A sweep
// expands its seeds with it instead of loading the base file once per seed
// (studies/src/sweep.cc checks the two agree for every cell).
Scenario Reseeded(const Scenario& scenario, uint64_t seed);
// ToResolvedYaml(reseeded) from the resolved YAML of the scenario it was
// reseeded from (only the seed lines differ), without emitting it again.
std::string ReseedResolvedYaml(const std::string& resolved_yaml, const Scenario& reseeded);

// The largest `frames` a scenario may have.
inline constexpr int kMaxFrames = 100'000;

// What one `hcpf run` of a scenario costs in peak memory and in bytes written,
// from per-frame costs measured on detection-level runs (docs/scenario.md,
// "Large scenarios"): a guide to within about a factor of two, not a bound.
// A run keeps every frame until it writes its files, so both grow with
// frames × targets.
struct RunCost {
  double memory_bytes = 0.0;
  double output_bytes = 0.0;  // the run folder
  double cache_bytes = 0.0;   // rendered frames written to the frame cache
};
RunCost EstimateRunCost(const Scenario& scenario);

// A one-line note on a scenario's cost when a run needs more than 256 MiB of
// memory or writes more than 256 MiB ("" otherwise); `hcpf validate` and
// `hcpf run` print it.
std::string LargeScenarioNote(const Scenario& scenario);

// The strongest turn of the image about its centre between two frames: the
// camera's right axis against the previous frame's carried by the smallest
// rotation from the previous view to this one. `frame` is the later frame of
// the two (0 with a single frame, where nothing turns).
struct CameraTurn {
  double degrees = 0.0;
  int frame = 0;
};
CameraTurn StrongestCameraTurn(const Scenario& scenario);

// The turn between two frames that CameraTurnNote reports: 150 degrees a
// second at 30 fps, beyond the roll of any path in scenarios/library
// (climb-yaw-dive, the strongest: 1.6).
inline constexpr double kCameraTurnNoteDeg = 5.0;

// A one-line note when the image turns about its centre by more than 5
// degrees between two frames ("" otherwise): a view near straight down
// whose heading swings, or passes near the view where the image's "up" is
// undefined (CameraPose::LookAt). `hcpf validate`, `hcpf run` and `hcpf render`
// print it (for a sweep file, studies::CameraTurnNote).
std::string CameraTurnNote(const Scenario& scenario);

// Why an image turns at once, and what it does to a run: the tail of
// CameraTurnNote, shared with the sweep's note.
std::string CameraTurnReason();

// Two targets whose ground footprints (length x width about the base, turned
// to the heading: TargetSpec::dimensions_m, a model's bounds unless given)
// interpenetrate by more than kTargetOverlapDepthM: vehicles driving through
// each other. The depth is how far one must move to clear the other, the
// least overlap of their projections on the rectangles' four edge normals.
// `first_frame`..`last_frame` is the first stretch of such frames, `frames`
// counts them all, `deepest_m` is the greatest depth.
struct TargetOverlap {
  ObjectId a{}, b{};  // in the order of `targets`
  int first_frame = 0;
  int last_frame = 0;
  int frames = 0;
  double deepest_m = 0.0;
};
// 10 cm: beyond the slack of a model's bounding box (mirrors, wheels), so
// that a convoy bumper to bumper or neighbours in adjacent lanes are not
// reported, while vehicles that cross within a car length of each other are.
inline constexpr double kTargetOverlapDepthM = 0.1;
// Every overlapping pair, ordered by the frame its overlap starts, then by
// the targets' order.
std::vector<TargetOverlap> TargetOverlaps(const WorldSpec& world);
// A one-line note naming the first pair (and how many pairs overlap), or ""
// when none does.
std::string TargetOverlapNote(const Scenario& scenario);

// The notes on the scene itself that `hcpf validate`, `hcpf run` and `hcpf
// render` print as warnings, those that apply: CameraTurnNote,
// TargetOverlapNote.
std::vector<std::string> SceneNotes(const Scenario& scenario);

}  // namespace hcpf::scenarios
