#pragma once
// Renders a WorldSpec off-screen into 8-bit RGB frames with pixel-exact ground
// truth (OpenGL core profile on Mesa's llvmpipe through OSMesa or EGL).
//
// Camera model: exactly hcpf::CameraState (core/camera.h): OpenCV intrinsics,
// including the per-frame shaken principal point, pixel (0,0) covering
// [0,1)x[0,1). The GL projection is built from K, so a world point projects to
// the same pixel here as in CameraState::Project(); pixel (u, v) of a frame is
// covered by a triangle when its centre (u + 0.5, v + 0.5) is (GL rasterisation).
//
// Ground truth per present target (hcpf::GroundTruthObject), from an
// instance-id pass in the same frame:
//   pixels_visible   pixels whose id is the target in the full render;
//   pixels_total     pixels the target covers rendered alone (no occluders, no
//                    other targets, same rasterisation), inside the image;
//   visible_fraction pixels_visible / pixels_total (0 when pixels_total = 0);
//   visible_box      pixel bounding box of the visible pixels [u0, u1+1) x [v0, v1+1);
//   amodal_box       pixel bounding box of the unoccluded render, extended by
//                    the projected mesh vertices where the target leaves the
//                    image (so it is unclipped and contains visible_box);
//   truncation       fraction of the amodal box's area outside the image;
//   in_frame         some of the amodal box is inside the image.
// Up to 255 targets per scene (the id is stored in the colour buffer's alpha).

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "hcpf/core/fields.h"
#include "hcpf/core/ground_truth.h"
#include "hcpf/core/image.h"
#include "hcpf/core/rng.h"
#include "hcpf/core/world.h"
#include "hcpf/renderer/gl_context.h"

namespace hcpf::renderer {

// The most targets one scene renders: the colour pass carries each pixel's
// target in its 8-bit alpha channel, 0 for none.
inline constexpr int kMaxRenderedTargets = 255;
// The largest target id a 16-bit instance image (`_ids.png`: id + 1, 0 for
// none) holds.
inline constexpr int32_t kMaxInstanceImageId = 65534;

// Effects applied to the rendered 8-bit image, in this order: exposure,
// blur, noise, JPEG. Randomness from Rng::Fork("renderer/sensor", frame).
struct SensorOptions {
  double exposure = 1.0;     // gain on pixel values, (0, 16]
  double blur_px = 0.0;      // Gaussian blur sigma in pixels, [0, 20]; 0 = off
  double noise_sigma = 0.0;  // additive Gaussian noise std. dev. in grey levels, [0, 100]
  int jpeg_quality = 0;      // JPEG encode/decode round trip quality, 1..100; 0 = off
  // The fields with their ranges (core/fields.h); the scenario's `sensor.*`
  // keys take their ranges from here.
  static std::span<const Field<SensorOptions>> Fields();
  // Throws hcpf::InputError naming the field ("sensor.<field>") and the constraint.
  void Validate() const;
  bool active() const {
    return exposure != 1.0 || blur_px > 0.0 || noise_sigma > 0.0 || jpeg_quality > 0;
  }
};

struct RendererOptions {
  GlBackend backend = GlBackend::kAuto;
  bool shadows = true;         // also needs world.sun.shadows
  int shadow_map_size = 1024;  // texels per side, [64, 8192]
  // Shadow filter: a (2r+1)^2-texel footprint sampled by (2r)^2 bilinear
  // comparison taps (r = 0: one tap), [0, 4].
  int pcf_radius = 1;
  // Height-field cells per side when relief > 0, [1, 1024]. Vehicles stand on
  // the drawn mesh; the default (400 m / 48 = 8.3 m cells) stays within
  // ~0.1 x relief of the analytic field and keeps the terrain ~4.6k triangles.
  int terrain_grid = 48;
  int texture_size = 256;            // procedural texture size (power of two, [16, 2048])
  double texture_tile_m = 12.0;      // ground texture repeat length (m), > 0
  double road_width_m = 7.0;         // width of roads along target paths (terrain.roads), > 0
  bool ground_truth = true;          // run the instance-id / count passes
  bool output_depth = false;         // fill RenderedFrame::depth
  bool output_instance_ids = false;  // fill RenderedFrame::instance_ids
  // Draw terrain cells the road mask cannot touch with a shader variant that
  // skips the two road lookups, and cells no shadow can reach in the frame
  // (the vehicles placed at that frame's poses) without the shadow lookups:
  // ~35 % of a frame. Changes no pixel (tested), so it is not part of the
  // frame-cache key; false exists for that test.
  bool split_road_cells = true;
  // The range-checked fields (core/fields.h); the scenario's `renderer.*`
  // keys take their ranges from here.
  static std::span<const Field<RendererOptions>> Fields();
  SensorOptions sensor;
  // Throws hcpf::InputError naming the field ("renderer.<field>").
  void Validate() const;
};

// Camera-frame depth (z along the optical axis) in metres; +inf where nothing
// was drawn.
struct DepthImage {
  int width = 0;
  int height = 0;
  std::vector<float> depth_m;
};

// Per pixel the ObjectId value of the visible target, or -1.
struct InstanceImage {
  int width = 0;
  int height = 0;
  std::vector<int32_t> ids;
};

struct RenderedFrame {
  int frame = 0;
  RgbImage rgb;
  std::optional<DepthImage> depth;
  std::optional<InstanceImage> instance_ids;
  FrameGroundTruth ground_truth;
};

class SceneRenderer {
 public:
  virtual ~SceneRenderer();

  // Loads models, builds and uploads the scene, generates textures (seeded
  // from rng.Fork("renderer/textures")). Uses `context` when given (it must
  // outlive the renderer and be used from this thread), else creates one for
  // options.backend. Throws hcpf::InputError for bad options, missing or
  // unreadable models, more than 255 targets, or no GL context.
  static std::unique_ptr<SceneRenderer> Create(const WorldSpec& world,
                                               const RendererOptions& options, Rng rng,
                                               std::shared_ptr<GlContext> context = nullptr);

  // Renders frame `frame` (0-based) of the world. Deterministic: the same
  // world, options, seed and driver give byte-identical frames.
  // Renders one frame and waits for it: Submit(frame) then Collect().
  RenderedFrame Render(int frame);

  // Pipelined rendering. Submit queues a frame's GL work (shadow, colour and
  // ground-truth passes) with its readbacks into pixel-buffer objects and
  // returns without waiting; Collect waits for the oldest submitted frame,
  // maps its buffers and finishes it on the CPU (ground-truth counts, depth,
  // sensor effects). With two frames submitted, the GPU renders frame t+1
  // while the CPU finishes frame t. At most kMaxInFlight frames may be
  // submitted and not yet collected; frames come back in submission order and
  // byte-identical to Render's. Submit past the limit and Collect with
  // nothing submitted are programming errors (HCPF_CHECK).
  static constexpr int kMaxInFlight = 2;
  virtual void Submit(int frame) = 0;
  RenderedFrame Collect();
  virtual int in_flight() const = 0;

  // Collect in two steps: Collect() is CollectClean() then ApplySensor() on
  // its frame. ApplySensor uses no GL and nothing Submit or Collect change,
  // so it may run on another thread while this one renders the next frame
  // (scenarios' ProduceFrames does: on llvmpipe, whose readback waits for
  // the frame, it is the only overlap there is). The frames equal Collect's.
  virtual RenderedFrame CollectClean() = 0;
  virtual void ApplySensor(RenderedFrame& frame) const = 0;

  virtual const GlInfo& gl_info() const = 0;

 protected:
  SceneRenderer() = default;
};

// Applies the sensor effects to `image` in place (no GL needed).
void ApplySensorEffects(const SensorOptions& options, Rng rng, RgbImage& image);

// Hex digest of everything that affects the pixels and ground truth of a
// rendered frame: the world (model files by name and content, not by the
// folder they are in), the options that change pixels (not backend, threads
// or output flags), the seed and the renderer's shading version. The same
// scene has the same hash in any clone, on any machine.
std::string PixelHash(const WorldSpec& world, const RendererOptions& options, uint64_t seed);

// The files beside the model file `path` (whose content is `bytes`) that its
// loader reads and that change its pixels: a glTF's buffers, an .obj's
// material libraries. In the order the model names them; a model that cannot
// be parsed names none (its loader says why). PixelHash keys a model by its
// bytes and theirs, as does the scenario's `targets[i].model_digest`.
std::vector<std::filesystem::path> ModelSideFiles(const std::filesystem::path& path,
                                                  const std::string& bytes);

// "<platform>; <vendor>; <renderer>; <version>" of a GL context, e.g.
// "osmesa; Mesa; llvmpipe (LLVM 15.0.6, 256 bits); 4.5 (Core Profile) Mesa
// 22.3.6" (FrameCache::NoteRenderer).
std::string RendererLine(const GlInfo& gl);

// Frames + ground truth on disk under DIR/<hash>/: a second run of the same
// scene with other tracker settings reads frames instead of rendering. Depth
// and instance images are not cached. A frame is NNNNNN.frame (a versioned
// header, then the colour planes, each row left-differenced, compressed by
// zstd level 1 with a checksum: ~6x less CPU to write and ~4x less to read
// than PNG, about the same bytes, bench/frame_cache_bench.cc and
// docs/renderer.md) and NNNNNN.json (its truth).
class FrameCache {
 public:
  // Bump when the .frame layout changes: a file of another version is a miss
  // (re-rendered and overwritten), never misread.
  static constexpr uint32_t kFormatVersion = 1;

  FrameCache(std::filesystem::path root, std::string hash);
  // The frame if it is cached (and readable, of this format version), else
  // nullopt.
  std::optional<RenderedFrame> Load(int frame) const;
  // Whether the cache holds a file for `frame` (Load may still reject it).
  bool Contains(int frame) const;
  // Writes the frame atomically (temp file + rename); throws hcpf::RunError.
  void Store(const RenderedFrame& frame) const;
  // The key leaves the GL renderer out, so a cache shared by machines whose
  // renderers differ (a GPU and llvmpipe, two Mesa versions) could mix their
  // pixels unseen. Each process that renders into the cache first notes its
  // renderer, one line of renderers.txt in the scene's folder
  // (RendererLine), added once with a single O_APPEND write; throws
  // hcpf::RunError when it cannot.
  void NoteRenderer(const GlInfo& gl) const;
  // The lines noted, in the order first noted (none for frames cached before
  // renderers were noted).
  std::vector<std::string> Renderers() const;
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
};

// FrameCache::Store on worker threads, so encoding and writing frame t
// overlap the rendering of frame t + 1 (SerialWorkers, core/parallel.h):
// `workers` of them take the frames in turn (frame files are independent).
// Submit copies nothing more than the frame it is given and blocks while
// `queue_depth` frames wait for its worker (bounded memory). Once a store has
// failed, the frames queued after it on that worker are not stored, and a
// later Submit to it or Finish throws RunError naming the cache and the
// failure; Finish waits for every submitted frame first. The destructor waits
// too (and drops errors: call Finish). The files written are those Store
// writes, whatever the timing and the number of workers.
class FrameCacheWriter {
 public:
  explicit FrameCacheWriter(FrameCache cache, int queue_depth = 4, int workers = 1);
  ~FrameCacheWriter();
  FrameCacheWriter(const FrameCacheWriter&) = delete;
  FrameCacheWriter& operator=(const FrameCacheWriter&) = delete;

  void Submit(RenderedFrame frame);
  void Finish();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// PNG I/O for RGB images (OpenCV inside). ReadPng throws hcpf::InputError.
void WritePng(const RgbImage& image, const std::string& path);
RgbImage ReadPng(const std::string& path);

}  // namespace hcpf::renderer
