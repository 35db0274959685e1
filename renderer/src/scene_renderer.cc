// The GL scene renderer: terrain, occluders and vehicles; a sun shadow map
// with PCF; a colour pass whose alpha channel carries the instance id; a
// per-target count pass for the unoccluded pixel totals.

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <map>
#include <numbers>
#include <optional>

#include "gl_api.h"
#include "gl_texture.h"
#include "hcpf/core/check.h"
#include "hcpf/core/error.h"
#include "hcpf/renderer/mesh.h"
#include "hcpf/renderer/renderer.h"
#include "logging.h"
#include "rgba_split.h"
#include "shaders.h"
#include "textures.h"

namespace hcpf::renderer {

SceneRenderer::~SceneRenderer() = default;

RenderedFrame SceneRenderer::Render(int frame) {
  HCPF_CHECK(in_flight() == 0) << "Render with " << in_flight() << " submitted frame(s)";
  Submit(frame);
  return Collect();
}

RenderedFrame SceneRenderer::Collect() {
  RenderedFrame frame = CollectClean();
  ApplySensor(frame);
  return frame;
}

namespace {

using internal::GlApi;

constexpr double kDegToRad = std::numbers::pi / 180.0;
constexpr double kNearM = 0.5;
constexpr int kMaxTargets = kMaxRenderedTargets;
// Lighting (linear units; albedo * (ambient + sun * N.L * lit)).
const Eigen::Vector3f kSunColor{0.95f, 0.92f, 0.85f};
const Eigen::Vector3f kSkyAmbient{0.36f, 0.40f, 0.46f};
const Eigen::Vector3f kGroundAmbient{0.22f, 0.21f, 0.18f};
const Eigen::Vector3f kSkyClear{0.62f, 0.72f, 0.85f};
// Occluder colours.
const Eigen::Vector3f kConcrete{0.62f, 0.61f, 0.58f};
const Eigen::Vector3f kBuilding{0.72f, 0.66f, 0.56f};
const Eigen::Vector3f kTrunk{0.35f, 0.25f, 0.16f};
const Eigen::Vector3f kCanopy{0.16f, 0.32f, 0.12f};
// Shadow depth bias in metres along the light direction, on top of the
// slope-scaled polygon offset: removes acne on sunlit faces of occluders
// without visibly detaching shadows from their casters (~1 texel).
constexpr double kShadowBiasM = 0.12;

struct GpuMesh {
  GLuint vao = 0;
  GLuint vbo = 0;
  GLuint ibo = 0;
  GLsizei index_count = 0;
  bool closed = false;  // MeshData::IsClosed: the shadow pass may cull its back faces
};

// A block of terrain cells culled together: cells [i0, i1) x [j0, j1) and
// the bounding box of their vertices.
struct TerrainTile {
  int i0 = 0, i1 = 0, j0 = 0, j1 = 0;
  Eigen::Vector3f lo;
  Eigen::Vector3f hi;
};

// The terrain's shader variants, one per part of a frame's cells (see
// GlSceneRenderer::PrepareTerrain): every lookup, road lookups only, shadow
// lookups only, neither.
enum TerrainPart { kTerrainFull = 0, kTerrainRoad, kTerrainShadow, kTerrainPlain, kTerrainParts };

constexpr int kTerrainTileCells = 8;

struct VehicleModel {
  GpuMesh gpu;
  std::vector<Eigen::Vector3f> positions;  // base-centred model frame
  Eigen::Vector3f dims = Eigen::Vector3f::Ones();
};

// Moves a mesh so that its base centre is at the origin; returns its size.
Eigen::Vector3f BaseCentre(MeshData& mesh) {
  const Eigen::AlignedBox3f b = mesh.Bounds();
  mesh.Transform(Eigen::Vector3f::Ones(),
                 Eigen::Vector3f(-0.5f * (b.min().x() + b.max().x()),
                                 -0.5f * (b.min().y() + b.max().y()), -b.min().z()));
  return (b.max() - b.min()).cwiseMax(Eigen::Vector3f::Constant(1e-4f));
}

Eigen::Matrix3f RotZ(double yaw_rad) {
  return Eigen::AngleAxisf(static_cast<float>(yaw_rad), Eigen::Vector3f::UnitZ())
      .toRotationMatrix();
}

class GlSceneRenderer final : public SceneRenderer {
 public:
  GlSceneRenderer(const WorldSpec& world, const RendererOptions& options, Rng rng,
                  std::shared_ptr<GlContext> context)
      : world_(world),
        options_(options),
        rng_(rng),
        context_(std::move(context)),
        gl_(context_->api()) {
    if (world_.targets.size() > static_cast<size_t>(kMaxTargets)) {
      throw InputError(SourceLocation{.key = "targets"},
                       fmt::format("at most {} targets for the renderer", kMaxTargets),
                       fmt::format("{}", world_.targets.size()));
    }
    HCPF_CHECK(!world_.camera.path.empty());
    width_ = world_.camera.width_px;
    height_ = world_.camera.height_px;
    shadows_ = options_.shadows && world_.sun.shadows;
    context_->MakeCurrent();
    BuildPrograms();
    BuildFramebuffers();
    const internal::Texture8 road_mask =
        internal::RoadMask(world_, world_.terrain.roads ? 1024 : 1, options_.road_width_m);
    BuildTextures(road_mask);
    BuildTerrain();
    BuildOccluders();
    BuildVehicles();
    BuildTerrainCells(road_mask);
    gl_.CheckError("scene upload");
  }

  ~GlSceneRenderer() override {
    try {
      context_->MakeCurrent();
    } catch (const std::exception&) {
      return;  // the context is gone; its objects went with it
    }
    const auto drop = [&](GpuMesh& m) {
      gl_.DeleteVertexArrays(1, &m.vao);
      gl_.DeleteBuffers(1, &m.vbo);
      gl_.DeleteBuffers(1, &m.ibo);
    };
    drop(terrain_);
    drop(occluders_);
    for (VehicleModel& v : models_) drop(v.gpu);
    const GLuint textures[] = {shadow_tex_, ground_tex_, road_tex_, mask_tex_};
    gl_.DeleteTextures(4, textures);
    gl_.DeleteFramebuffers(1, &shadow_fbo_);
    gl_.DeleteFramebuffers(1, &main_fbo_);
    const GLuint rbs[] = {color_rb_, depth_rb_};
    gl_.DeleteRenderbuffers(2, rbs);
    gl_.DeleteProgram(object_program_.id);
    gl_.DeleteProgram(terrain_program_.id);
    if (terrain_road_program_.id != 0) gl_.DeleteProgram(terrain_road_program_.id);
    if (terrain_shadow_program_.id != 0) gl_.DeleteProgram(terrain_shadow_program_.id);
    if (terrain_plain_program_.id != 0) gl_.DeleteProgram(terrain_plain_program_.id);
    gl_.DeleteProgram(id_program_.id);
    gl_.DeleteProgram(shadow_program_);
    for (InFlight& slot : slots_) {
      if (slot.fence != nullptr) gl_.DeleteSync(slot.fence);
      const GLuint buffers[] = {slot.colour_pbo, slot.depth_pbo, slot.count_pbo};
      gl_.DeleteBuffers(3, buffers);  // zeros are ignored
    }
  }

  const GlInfo& gl_info() const override { return context_->info(); }

  void Submit(int frame) override;
  RenderedFrame CollectClean() override;
  void ApplySensor(RenderedFrame& frame) const override;
  int in_flight() const override { return in_flight_; }

 private:
  struct TargetInstance {
    size_t slot = 0;  // index in world.targets
    TargetPose pose;
    Eigen::Matrix4f model = Eigen::Matrix4f::Identity();
  };

  GLuint Compile(GLenum type, const char* source);
  GLuint Link(const char* vs, const char* fs);
  void BuildPrograms();
  void BuildFramebuffers();
  void BuildTextures(const internal::Texture8& road_mask);
  void BuildTerrain();
  // The terrain's tiles and the cells a road may touch (BuildTerrain has
  // placed the vertices).
  void BuildTerrainCells(const internal::Texture8& road_mask);
  // Marks in shadow_cells_ the cells on which a shadow may fall in this
  // frame: every occluder's box and every present vehicle's box at its pose,
  // swept along the sun to the terrain, plus the shadow filter's footprint
  // for the frame's shadow-map texel (`texel_m`, metres). Every cell when the
  // sun is too low to bound the shadows.
  void MarkShadowCells(const std::vector<TargetInstance>& targets, double texel_m);
  // Sorts the cells of the tiles in view into the TerrainParts (cells a road
  // may touch or not, x cells marked by MarkShadowCells or not; every cell is
  // kTerrainFull without split_road_cells) and uploads their indices, part
  // after part, into the terrain's index buffer. Returns each part's first
  // index and count.
  std::array<std::pair<size_t, GLsizei>, kTerrainParts> PrepareTerrain(
      const Eigen::Matrix4f& view_proj, const std::vector<TargetInstance>& targets, double texel_m);
  // Height of the rendered terrain mesh (the triangles, not the analytic
  // field) at (x, y): vehicles stand on what is drawn.
  double MeshHeightAt(double x_m, double y_m) const;
  void BuildOccluders();
  void BuildVehicles();
  GpuMesh Upload(const MeshData& mesh);
  void Draw(const GpuMesh& mesh) const {
    gl_.BindVertexArray(mesh.vao);
    gl_.DrawElements(GL_TRIANGLES, mesh.index_count, GL_UNSIGNED_INT, nullptr);
  }
  void SetModel(const Eigen::Matrix4f& model) const;
  // The sun's view-projection for the frame's shadow map; its depth range and
  // the size of one shadow-map texel (metres, the larger side).
  Eigen::Matrix4f LightViewProj(const CameraState& camera, double* depth_range_m,
                                double* texel_m) const;
  Eigen::Matrix4f ViewProj(const CameraState& camera, double* far_m) const;
  // The count pass's bookkeeping for one target of a submitted frame.
  // count[i] belongs to targets[i].
  struct CountTarget {
    double u_lo = 0.0, v_lo = 0.0, u_hi = 0.0, v_hi = 0.0;
    bool behind = false;
    bool any_in_front = false;
    int sx0 = 0, sy0 = 0, sx1 = 0, sy1 = 0;  // scissor [sx0, sx1) x [sy0, sy1)
    int64_t total = 0;
    int ax0 = std::numeric_limits<int>::max(), ay0 = std::numeric_limits<int>::max();
    int ax1 = -1, ay1 = -1;
  };
  // Targets with disjoint scissors drawn together and read back as one
  // rectangle, at `offset` bytes into the count buffer.
  struct CountLayer {
    int x0 = 0, y0 = 0, w = 0, h = 0;
    size_t offset = 0;
    std::vector<size_t> members;  // indices in InFlight::count
  };
  // A frame between Submit and Collect, with its own pixel-buffer objects
  // (kMaxInFlight slots, used round robin).
  struct InFlight {
    int frame = 0;
    CameraState camera;
    double far_m = 0.0;
    std::vector<TargetInstance> targets;
    std::vector<CountTarget> count;
    std::vector<CountLayer> layers;  // packed one after the other in count_pbo
    GLuint colour_pbo = 0, depth_pbo = 0, count_pbo = 0;
    size_t colour_capacity = 0, depth_capacity = 0, count_capacity = 0;
    GLsync fence = nullptr;
  };
  void SubmitCountPass(InFlight& s, const Eigen::Matrix4f& view_proj);
  FrameGroundTruth GroundTruth(InFlight& s, const internal::VisibleIds& visible);
  // Binds `buffer` (created on first use) to GL_PIXEL_PACK_BUFFER with room
  // for `bytes`.
  void EnsurePackBuffer(GLuint& buffer, size_t& capacity, size_t bytes);
  // The first `bytes` of a pack buffer mapped for reading (mapping waits for
  // its writes), bound to GL_PIXEL_PACK_BUFFER until unmapped at the end of
  // the scope. Readers take the pixels straight from the mapping.
  class MappedPackBuffer {
   public:
    MappedPackBuffer(const GlApi& gl, GLuint buffer, size_t bytes);
    ~MappedPackBuffer();
    MappedPackBuffer(const MappedPackBuffer&) = delete;
    MappedPackBuffer& operator=(const MappedPackBuffer&) = delete;
    const uint8_t* data() const { return data_; }

   private:
    const GlApi& gl_;
    const uint8_t* data_ = nullptr;
  };
  // Copies the first `bytes` of a pack buffer to `out`.
  void ReadPackBuffer(GLuint buffer, size_t bytes, void* out) const {
    const MappedPackBuffer mapped(gl_, buffer, bytes);
    std::memcpy(out, mapped.data(), bytes);
  }

  std::array<InFlight, kMaxInFlight> slots_;
  int head_ = 0;  // the oldest submitted slot
  int in_flight_ = 0;

  WorldSpec world_;
  RendererOptions options_;
  Rng rng_;
  std::shared_ptr<GlContext> context_;
  const GlApi& gl_;
  int width_ = 0;
  int height_ = 0;
  bool shadows_ = true;
  double scene_top_m_ = 0.0;  // highest point of anything drawn
  double scene_bottom_m_ = 0.0;

  struct Program {
    GLuint id = 0;
    std::map<std::string, GLint> locations;
  };
  // Colour-pass variants (see shaders.h) and the count-pass program.
  Program object_program_;
  // Terrain variants for the TerrainParts: all features on; without the
  // shadow lookups (built only with roads and shadows: otherwise
  // terrain_program_ is that variant); without the road lookups; without
  // road and shadow lookups. Ids are 0 when not built (split_road_cells off).
  Program terrain_program_;
  Program terrain_road_program_;
  Program terrain_shadow_program_;
  Program terrain_plain_program_;
  Program id_program_;
  const Program* current_ = nullptr;
  GLuint shadow_program_ = 0;
  Program MakeProgram(const std::string& defines);
  void Use(const Program& program) {
    gl_.UseProgram(program.id);
    current_ = &program;
  }
  // Sets the per-frame uniforms shared by the colour-pass programs.
  void SetFrameUniforms(const Eigen::Matrix4f& view_proj, const Eigen::Matrix4f& light_view_proj,
                        double light_depth_m);
  GLint shadow_model_loc_ = -1;
  GLint shadow_vp_loc_ = -1;
  GLuint shadow_fbo_ = 0;
  GLuint shadow_tex_ = 0;
  int shadow_size_ = 1;
  GLuint main_fbo_ = 0;
  GLuint color_rb_ = 0;
  GLuint depth_rb_ = 0;
  GLuint ground_tex_ = 0;
  GLuint road_tex_ = 0;
  GLuint mask_tex_ = 0;
  GpuMesh terrain_;
  std::vector<TerrainTile> tiles_;
  int terrain_cells_ = 1;
  std::vector<uint8_t> road_cells_;    // per cell (row-major): a road may touch it
  std::vector<uint8_t> shadow_cells_;  // per cell: MarkShadowCells' marks for this frame
  std::array<std::vector<uint32_t>, kTerrainParts> part_indices_;  // PrepareTerrain's scratch
  std::vector<uint32_t> terrain_indices_;                          // the parts, concatenated
  std::vector<float> terrain_heights_;  // (cells+1)^2 vertex heights, row-major

  GpuMesh occluders_;
  std::vector<VehicleModel> models_;
  std::vector<size_t> target_model_;  // per target: index into models_
  std::vector<uint8_t> region_;
  // World boxes of the occluders, for the cells their shadows may reach.
  std::vector<Eigen::AlignedBox3d> occluder_boxes_;

  // Location of a uniform in the current program (-1 when the variant does
  // not use it: glUniform* ignores -1).
  GLint U(const char* name) const {
    HCPF_CHECK(current_ != nullptr);
    const auto it = current_->locations.find(name);
    HCPF_CHECK(it != current_->locations.end()) << "uniform " << name;
    return it->second;
  }
};

GLuint GlSceneRenderer::Compile(GLenum type, const char* source) {
  const GLuint shader = gl_.CreateShader(type);
  gl_.ShaderSource(shader, 1, &source, nullptr);
  gl_.CompileShader(shader);
  GLint ok = 0;
  gl_.GetShaderiv(shader, GL_COMPILE_STATUS, &ok);
  if (ok == 0) {
    char log[4096] = {};
    gl_.GetShaderInfoLog(shader, sizeof(log), nullptr, log);
    throw RunError(fmt::format("renderer: shader compilation failed: {}", log));
  }
  return shader;
}

GLuint GlSceneRenderer::Link(const char* vs, const char* fs) {
  const GLuint v = Compile(GL_VERTEX_SHADER, vs);
  const GLuint f = Compile(GL_FRAGMENT_SHADER, fs);
  const GLuint program = gl_.CreateProgram();
  gl_.AttachShader(program, v);
  gl_.AttachShader(program, f);
  gl_.LinkProgram(program);
  gl_.DeleteShader(v);
  gl_.DeleteShader(f);
  GLint ok = 0;
  gl_.GetProgramiv(program, GL_LINK_STATUS, &ok);
  if (ok == 0) {
    char log[4096] = {};
    gl_.GetProgramInfoLog(program, sizeof(log), nullptr, log);
    throw RunError(fmt::format("renderer: program link failed: {}", log));
  }
  return program;
}

GlSceneRenderer::Program GlSceneRenderer::MakeProgram(const std::string& defines) {
  const std::string vs = "#version 330 core\n" + defines + internal::kSceneVertexBody;
  const std::string fs = "#version 330 core\n" + defines + internal::kSceneFragmentBody;
  Program program;
  program.id = Link(vs.c_str(), fs.c_str());
  for (const char* name :
       {"u_model", "u_normal_matrix", "u_view_proj", "u_light_view_proj", "u_id", "u_tint",
        "u_sun_dir", "u_sun_color", "u_sky_color", "u_ground_color", "u_shadow_texel",
        "u_shadow_bias", "u_shadow_map", "u_ground_tex", "u_road_tex", "u_road_mask",
        "u_terrain_min", "u_terrain_size", "u_tile_m"}) {
    program.locations[name] = gl_.GetUniformLocation(program.id, name);
  }
  Use(program);
  gl_.Uniform1i(U("u_shadow_map"), 0);
  gl_.Uniform1i(U("u_ground_tex"), 1);
  gl_.Uniform1i(U("u_road_tex"), 2);
  gl_.Uniform1i(U("u_road_mask"), 3);
  current_ = nullptr;
  return program;
}

void GlSceneRenderer::BuildPrograms() {
  std::string common;
  if (shadows_)
    common += fmt::format("#define SHADOWS\n#define PCF_RADIUS {}\n", options_.pcf_radius);
  object_program_ = MakeProgram(common);
  terrain_program_ =
      MakeProgram(common + "#define TERRAIN\n" + (world_.terrain.roads ? "#define ROADS\n" : ""));
  if (options_.split_road_cells) {
    if (shadows_ && world_.terrain.roads) {
      terrain_road_program_ = MakeProgram("#define TERRAIN\n#define ROADS\n");
    }
    terrain_shadow_program_ = MakeProgram(common + "#define TERRAIN\n");
    terrain_plain_program_ = MakeProgram("#define TERRAIN\n");
  }
  id_program_ = MakeProgram("#define ID_ONLY\n");
  shadow_program_ = Link(internal::kShadowVertexShader, internal::kShadowFragmentShader);
  shadow_model_loc_ = gl_.GetUniformLocation(shadow_program_, "u_model");
  shadow_vp_loc_ = gl_.GetUniformLocation(shadow_program_, "u_light_view_proj");
  gl_.CheckError("program setup");
}

void GlSceneRenderer::SetFrameUniforms(const Eigen::Matrix4f& view_proj,
                                       const Eigen::Matrix4f& light_view_proj,
                                       double light_depth_m) {
  gl_.UniformMatrix4fv(U("u_view_proj"), 1, GL_FALSE, view_proj.data());
  gl_.UniformMatrix4fv(U("u_light_view_proj"), 1, GL_FALSE, light_view_proj.data());
  const Eigen::Vector3f sun = world_.sun.Direction().normalized().cast<float>();
  gl_.Uniform3f(U("u_sun_dir"), sun.x(), sun.y(), sun.z());
  // Below the horizon the sun contributes nothing (N.L clamps per face, but
  // the terrain would still be lit from below the horizon otherwise).
  const float sun_scale = world_.sun.elevation_deg > 0.0 ? 1.0f : 0.0f;
  gl_.Uniform3f(U("u_sun_color"), sun_scale * kSunColor.x(), sun_scale * kSunColor.y(),
                sun_scale * kSunColor.z());
  gl_.Uniform3f(U("u_sky_color"), kSkyAmbient.x(), kSkyAmbient.y(), kSkyAmbient.z());
  gl_.Uniform3f(U("u_ground_color"), kGroundAmbient.x(), kGroundAmbient.y(), kGroundAmbient.z());
  const float texel = 1.0f / static_cast<float>(shadow_size_);
  gl_.Uniform2f(U("u_shadow_texel"), texel, texel);
  gl_.Uniform1f(U("u_shadow_bias"), static_cast<float>(kShadowBiasM / light_depth_m));
  gl_.Uniform2f(U("u_terrain_min"), static_cast<float>(-0.5 * world_.terrain.size_m.x()),
                static_cast<float>(-0.5 * world_.terrain.size_m.y()));
  gl_.Uniform2f(U("u_terrain_size"), static_cast<float>(world_.terrain.size_m.x()),
                static_cast<float>(world_.terrain.size_m.y()));
  gl_.Uniform1f(U("u_tile_m"), static_cast<float>(options_.texture_tile_m));
  gl_.Uniform1f(U("u_id"), 0.0f);
  gl_.Uniform3f(U("u_tint"), 1.0f, 1.0f, 1.0f);
}

void GlSceneRenderer::BuildFramebuffers() {
  // Shadow map: depth texture with hardware comparison (bilinear PCF taps).
  shadow_size_ = shadows_ ? options_.shadow_map_size : 1;
  gl_.GenTextures(1, &shadow_tex_);
  gl_.ActiveTexture(GL_TEXTURE0);
  gl_.BindTexture(GL_TEXTURE_2D, shadow_tex_);
  gl_.TexImage2D(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT24, shadow_size_, shadow_size_, 0,
                 GL_DEPTH_COMPONENT, GL_UNSIGNED_INT, nullptr);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  // Outside the map nothing casts: the border compares as depth 1 (lit).
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_BORDER);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_BORDER);
  const GLfloat border[4] = {1.0f, 1.0f, 1.0f, 1.0f};
  gl_.TexParameterfv(GL_TEXTURE_2D, GL_TEXTURE_BORDER_COLOR, border);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
  gl_.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
  gl_.GenFramebuffers(1, &shadow_fbo_);
  gl_.BindFramebuffer(GL_FRAMEBUFFER, shadow_fbo_);
  gl_.FramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, shadow_tex_, 0);
  gl_.DrawBuffer(GL_NONE);
  gl_.ReadBuffer(GL_NONE);
  if (gl_.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    throw RunError("renderer: shadow framebuffer incomplete");
  }
  // Colour pass: RGBA8 (alpha = instance id) + 32-bit float depth.
  gl_.GenRenderbuffers(1, &color_rb_);
  gl_.BindRenderbuffer(GL_RENDERBUFFER, color_rb_);
  gl_.RenderbufferStorage(GL_RENDERBUFFER, GL_RGBA8, width_, height_);
  gl_.GenRenderbuffers(1, &depth_rb_);
  gl_.BindRenderbuffer(GL_RENDERBUFFER, depth_rb_);
  gl_.RenderbufferStorage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT32F, width_, height_);
  gl_.GenFramebuffers(1, &main_fbo_);
  gl_.BindFramebuffer(GL_FRAMEBUFFER, main_fbo_);
  gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, color_rb_);
  gl_.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, depth_rb_);
  if (gl_.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    throw RunError("renderer: colour framebuffer incomplete");
  }
  gl_.CheckError("framebuffers");
}

void GlSceneRenderer::BuildTextures(const internal::Texture8& road_mask) {
  Rng tex_rng = rng_.Fork("renderer/textures");
  gl_.ActiveTexture(GL_TEXTURE1);
  ground_tex_ =
      internal::UploadTexture(gl_,
                              internal::GroundTexture(world_.terrain.texture, options_.texture_size,
                                                      tex_rng.Fork("ground")),
                              true);
  gl_.ActiveTexture(GL_TEXTURE2);
  road_tex_ = internal::UploadTexture(
      gl_, internal::GroundTexture("asphalt", options_.texture_size, tex_rng.Fork("road")), true);
  gl_.ActiveTexture(GL_TEXTURE3);
  mask_tex_ = internal::UploadTexture(gl_, road_mask, false);

  gl_.ActiveTexture(GL_TEXTURE0);
  gl_.CheckError("textures");
}

GpuMesh GlSceneRenderer::Upload(const MeshData& mesh) {
  GpuMesh gpu;
  std::vector<float> interleaved;
  interleaved.reserve(mesh.vertex_count() * 11);
  for (size_t i = 0; i < mesh.vertex_count(); ++i) {
    const auto& p = mesh.positions[i];
    const auto& n = mesh.normals[i];
    const auto& t = mesh.uvs[i];
    const auto& c = mesh.colors[i];
    interleaved.insert(interleaved.end(), {p.x(), p.y(), p.z(), n.x(), n.y(), n.z(), t.x(), t.y(),
                                           c.x(), c.y(), c.z()});
  }
  gl_.GenVertexArrays(1, &gpu.vao);
  gl_.BindVertexArray(gpu.vao);
  gl_.GenBuffers(1, &gpu.vbo);
  gl_.BindBuffer(GL_ARRAY_BUFFER, gpu.vbo);
  gl_.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(interleaved.size() * sizeof(float)),
                 interleaved.data(), GL_STATIC_DRAW);
  gl_.GenBuffers(1, &gpu.ibo);
  gl_.BindBuffer(GL_ELEMENT_ARRAY_BUFFER, gpu.ibo);
  gl_.BufferData(GL_ELEMENT_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(mesh.indices.size() * sizeof(uint32_t)),
                 mesh.indices.data(), GL_STATIC_DRAW);
  constexpr GLsizei kStride = 11 * sizeof(float);
  const int sizes[4] = {3, 3, 2, 3};
  size_t offset = 0;
  for (GLuint a = 0; a < 4; ++a) {
    gl_.EnableVertexAttribArray(a);
    gl_.VertexAttribPointer(a, sizes[a], GL_FLOAT, GL_FALSE, kStride,
                            reinterpret_cast<const void*>(offset * sizeof(float)));
    offset += static_cast<size_t>(sizes[a]);
  }
  gl_.BindVertexArray(0);
  gpu.index_count = static_cast<GLsizei>(mesh.indices.size());
  gpu.closed = mesh.IsClosed();
  return gpu;
}

void GlSceneRenderer::BuildTerrain() {
  const TerrainSpec& t = world_.terrain;
  const int grid = t.relief_m > 0.0 ? options_.terrain_grid : 1;
  terrain_cells_ = grid;
  MeshData mesh;
  const double sx = t.size_m.x();
  const double sy = t.size_m.y();
  // Normals from central differences of the analytic height field; 0.5 m is
  // well below the shortest wavelength (10 m).
  constexpr double kEps = 0.5;
  for (int j = 0; j <= grid; ++j) {
    for (int i = 0; i <= grid; ++i) {
      const double x = -0.5 * sx + sx * i / grid;
      const double y = -0.5 * sy + sy * j / grid;
      mesh.positions.emplace_back(static_cast<float>(x), static_cast<float>(y),
                                  static_cast<float>(t.HeightAt(x, y)));
      terrain_heights_.push_back(mesh.positions.back().z());
      const double dx = (t.HeightAt(x + kEps, y) - t.HeightAt(x - kEps, y)) / (2 * kEps);
      const double dy = (t.HeightAt(x, y + kEps) - t.HeightAt(x, y - kEps)) / (2 * kEps);
      mesh.normals.push_back(Eigen::Vector3d(-dx, -dy, 1.0).normalized().cast<float>());
      mesh.uvs.emplace_back(static_cast<float>(i) / grid, static_cast<float>(j) / grid);
      mesh.colors.emplace_back(1.0f, 1.0f, 1.0f);
    }
  }
  terrain_ = Upload(mesh);
  scene_bottom_m_ = -0.5 * t.relief_m;
  scene_top_m_ = 0.5 * t.relief_m;
}

void GlSceneRenderer::BuildTerrainCells(const internal::Texture8& road_mask) {
  const int grid = terrain_cells_;
  const TerrainSpec& t = world_.terrain;
  const auto cell = [&](int i, int j) { return static_cast<size_t>(j) * grid + i; };
  road_cells_.assign(static_cast<size_t>(grid) * grid, options_.split_road_cells ? 0 : 1);
  if (options_.split_road_cells && t.roads) {
    // A cell is a road cell when the mask may be non-zero anywhere the shader
    // samples it: the cell spans [i, i+1] x [j, j+1] / grid in mask
    // coordinates ((xy - min) / size in the shader), and a bilinear lookup at
    // u reads texels floor(u M - 0.5) and the next one, clamped to the edge.
    // Two texels of margin cover float rounding in the shader.
    const int m = road_mask.size;
    const auto texel_range = [&](int c) {
      const int lo = static_cast<int>(std::floor(static_cast<double>(c) / grid * m - 0.5)) - 2;
      const int hi = static_cast<int>(std::floor(static_cast<double>(c + 1) / grid * m - 0.5)) + 3;
      return std::pair(std::clamp(lo, 0, m - 1), std::clamp(hi, 0, m - 1));
    };
    const auto road_may_touch = [&](int i, int j) {
      const auto [x0, x1] = texel_range(i);
      const auto [y0, y1] = texel_range(j);
      for (int y = y0; y <= y1; ++y) {
        for (int x = x0; x <= x1; ++x) {
          if (road_mask.texels[static_cast<size_t>(y) * m + x] != 0) return true;
        }
      }
      return false;
    };
    for (int j = 0; j < grid; ++j) {
      for (int i = 0; i < grid; ++i) road_cells_[cell(i, j)] = road_may_touch(i, j) ? 1 : 0;
    }
  }
  // Tiles of cells, culled together against the view (llvmpipe's geometry
  // stage is single-threaded: unseen triangles cost). Their boxes hold the
  // vertices as BuildTerrain placed them.
  const auto vertex = [&](int i, int j) {
    return Eigen::Vector3f(static_cast<float>(-0.5 * t.size_m.x() + t.size_m.x() * i / grid),
                           static_cast<float>(-0.5 * t.size_m.y() + t.size_m.y() * j / grid),
                           terrain_heights_[static_cast<size_t>(j) * (grid + 1) + i]);
  };
  for (int tj = 0; tj < grid; tj += kTerrainTileCells) {
    for (int ti = 0; ti < grid; ti += kTerrainTileCells) {
      TerrainTile tile;
      tile.i0 = ti;
      tile.i1 = std::min(grid, ti + kTerrainTileCells);
      tile.j0 = tj;
      tile.j1 = std::min(grid, tj + kTerrainTileCells);
      tile.lo = Eigen::Vector3f::Constant(std::numeric_limits<float>::max());
      tile.hi = -tile.lo;
      for (int j = tile.j0; j <= tile.j1; ++j) {
        for (int i = tile.i0; i <= tile.i1; ++i) {
          tile.lo = tile.lo.cwiseMin(vertex(i, j));
          tile.hi = tile.hi.cwiseMax(vertex(i, j));
        }
      }
      tiles_.push_back(tile);
    }
  }
  shadow_cells_.assign(road_cells_.size(), 0);
}

void GlSceneRenderer::MarkShadowCells(const std::vector<TargetInstance>& targets, double texel_m) {
  const TerrainSpec& t = world_.terrain;
  const int grid = terrain_cells_;
  const Eigen::Vector3d sun = world_.sun.Direction().normalized();
  // Below ~3 degrees shadows run for kilometres: no bound worth having.
  if (sun.z() < 0.05) {
    std::fill(shadow_cells_.begin(), shadow_cells_.end(), 1);
    return;
  }
  std::fill(shadow_cells_.begin(), shadow_cells_.end(), 0);
  // The filter reads pcf_radius + 1 texels either side of a point, and a
  // texel seen obliquely covers 1 / sin(elevation) of its size on the
  // ground; one more texel and a metre cover rounding.
  const double bottom = scene_bottom_m_ - 1.0;
  const double top = 0.5 * t.relief_m + 1.0;  // highest terrain point, + 1 m
  const double margin = (options_.pcf_radius + 2) * texel_m / sun.z() + 1.0;
  const auto cell_range = [&](double lo, double hi, double size) {
    const double c0 = std::floor((lo + 0.5 * size) / size * grid);
    const double c1 = std::floor((hi + 0.5 * size) / size * grid);
    return std::pair(static_cast<int>(std::clamp(c0, 0.0, grid - 1.0)),
                     static_cast<int>(std::clamp(c1, 0.0, grid - 1.0)));
  };
  const auto mark = [&](const Eigen::AlignedBox3d& box) {
    // The ground rectangle of the box and of where the rays from its corners
    // away from the sun meet the lowest and the highest terrain: the box's
    // shadow lies inside.
    Eigen::AlignedBox2d f;
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d p = box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c));
      f.extend(p.head<2>());
      for (const double z : {bottom, top}) {
        if (p.z() <= z) continue;
        f.extend((p - (p.z() - z) / sun.z() * sun).head<2>());
      }
    }
    // Cost: the cells covered, not cells x boxes.
    const auto [i0, i1] = cell_range(f.min().x() - margin, f.max().x() + margin, t.size_m.x());
    const auto [j0, j1] = cell_range(f.min().y() - margin, f.max().y() + margin, t.size_m.y());
    for (int j = j0; j <= j1; ++j) {
      std::fill_n(shadow_cells_.begin() + static_cast<ptrdiff_t>(j) * grid + i0, i1 - i0 + 1, 1);
    }
  };
  for (const Eigen::AlignedBox3d& box : occluder_boxes_) mark(box);
  // A vehicle's mesh fills its dimensions (BuildVehicles scales it so),
  // standing on the drawn terrain at its pose: any heading stays within half
  // its footprint's diagonal of the position. Half a metre of slack.
  for (const TargetInstance& target : targets) {
    const Eigen::Vector3d& dims = world_.targets[target.slot].dimensions_m;
    const Eigen::Vector3d at(target.model(0, 3), target.model(1, 3), target.model(2, 3));
    const double r = 0.5 * dims.head<2>().norm() + 0.5;
    mark(Eigen::AlignedBox3d(at - Eigen::Vector3d(r, r, 0.5),
                             at + Eigen::Vector3d(r, r, dims.z() + 0.5)));
  }
}

std::array<std::pair<size_t, GLsizei>, kTerrainParts> GlSceneRenderer::PrepareTerrain(
    const Eigen::Matrix4f& view_proj, const std::vector<TargetInstance>& targets, double texel_m) {
  const int grid = terrain_cells_;
  const bool split = options_.split_road_cells;
  if (split && shadows_) MarkShadowCells(targets, texel_m);
  for (std::vector<uint32_t>& part : part_indices_) part.clear();
  const auto v = [&](int i, int j) { return static_cast<uint32_t>(j * (grid + 1) + i); };
  for (const TerrainTile& tile : tiles_) {
    // Clip-space test of the tile's box: culled when all 8 corners lie
    // outside the same frustum plane.
    int outside[6] = {0, 0, 0, 0, 0, 0};
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector4f p((c & 1) ? tile.hi.x() : tile.lo.x(),
                              (c & 2) ? tile.hi.y() : tile.lo.y(),
                              (c & 4) ? tile.hi.z() : tile.lo.z(), 1.0f);
      const Eigen::Vector4f q = view_proj * p;
      outside[0] += q.x() < -q.w();
      outside[1] += q.x() > q.w();
      outside[2] += q.y() < -q.w();
      outside[3] += q.y() > q.w();
      outside[4] += q.z() < -q.w();
      outside[5] += q.z() > q.w();
    }
    if (std::any_of(std::begin(outside), std::end(outside), [](int n) { return n == 8; })) {
      continue;
    }
    for (int j = tile.j0; j < tile.j1; ++j) {
      for (int i = tile.i0; i < tile.i1; ++i) {
        const size_t c = static_cast<size_t>(j) * grid + i;
        int part = kTerrainFull;
        if (split) {
          const bool road = road_cells_[c] != 0;
          const bool shadow = shadow_cells_[c] != 0;
          part = road ? (shadow ? kTerrainFull : kTerrainRoad)
                      : (shadow ? kTerrainShadow : kTerrainPlain);
        }
        part_indices_[static_cast<size_t>(part)].insert(
            part_indices_[static_cast<size_t>(part)].end(),
            {v(i, j), v(i + 1, j), v(i + 1, j + 1), v(i, j), v(i + 1, j + 1), v(i, j + 1)});
      }
    }
  }
  std::array<std::pair<size_t, GLsizei>, kTerrainParts> ranges{};
  terrain_indices_.clear();
  for (size_t k = 0; k < part_indices_.size(); ++k) {
    ranges[k] = {terrain_indices_.size(), static_cast<GLsizei>(part_indices_[k].size())};
    terrain_indices_.insert(terrain_indices_.end(), part_indices_[k].begin(),
                            part_indices_[k].end());
  }
  // New storage each frame: a frame still queued keeps the indices it was
  // submitted with, and nothing waits for it.
  gl_.BindVertexArray(terrain_.vao);
  gl_.BufferData(GL_ELEMENT_ARRAY_BUFFER,
                 static_cast<GLsizeiptr>(terrain_indices_.size() * sizeof(uint32_t)),
                 terrain_indices_.data(), GL_STREAM_DRAW);
  return ranges;
}

void GlSceneRenderer::BuildOccluders() {
  MeshBuilder builder;
  MeshData mesh;
  for (size_t k = 0; k < world_.occluders.size(); ++k) {
    const OccluderSpec& o = world_.occluders[k];
    if (o.kind == OccluderKind::kMesh) {
      MeshData m = LoadMesh(o.model);
      BaseCentre(m);
      const Eigen::Matrix3f r = RotZ(o.yaw_deg * kDegToRad);
      const auto s = static_cast<float>(o.scale);
      const Eigen::Vector3f at(static_cast<float>(o.at_m.x()), static_cast<float>(o.at_m.y()),
                               static_cast<float>(world_.terrain.HeightAt(o.at_m.x(), o.at_m.y())));
      for (auto& p : m.positions) p = r * (s * p) + at;
      for (auto& n : m.normals) n = r * n;
      mesh.Append(m);
      const Eigen::AlignedBox3f bounds = m.Bounds();
      occluder_boxes_.push_back(bounds.cast<double>());
      scene_top_m_ = std::max(scene_top_m_, double{bounds.max().z()});
      continue;
    }
    // Primitive occluders are drawn as exactly the boxes the analytic ground
    // truth uses (world.h OccluderSpec::Boxes).
    std::vector<OrientedBox> boxes = o.Boxes(world_.terrain);
    if (world_.terrain.relief_m > 0.0) {
      // Boxes standing on the ground (building, trunk, bridge piers) reach
      // 1 m below it, so the mesh's interpolation never shows a gap under them.
      for (size_t b = 0; b < boxes.size(); ++b) {
        const bool grounded = o.kind == OccluderKind::kBridge ? b > 0 : b == 0;
        if (!grounded) continue;
        boxes[b].centre_m.z() -= 0.5;
        boxes[b].half_size_m.z() += 0.5;
      }
    }
    for (size_t b = 0; b < boxes.size(); ++b) {
      Eigen::Vector3f color = kBuilding;
      if (o.kind == OccluderKind::kBridge) color = kConcrete;
      if (o.kind == OccluderKind::kTree) color = b == 0 ? kTrunk : kCanopy;
      builder.AddOrientedBox(boxes[b].centre_m.cast<float>(), boxes[b].half_size_m.cast<float>(),
                             static_cast<float>(boxes[b].yaw_deg * kDegToRad), color);
      scene_top_m_ = std::max(scene_top_m_, boxes[b].centre_m.z() + boxes[b].half_size_m.z());
      Eigen::AlignedBox3d world_box;
      for (const Eigen::Vector3d& c : boxes[b].Corners()) world_box.extend(c);
      occluder_boxes_.push_back(world_box);
    }
  }
  mesh.Append(builder.mesh());
  if (!mesh.empty()) occluders_ = Upload(mesh);
}

void GlSceneRenderer::BuildVehicles() {
  std::map<std::string, size_t> by_path;
  for (const TargetSpec& target : world_.targets) {
    auto it = by_path.find(target.model);
    if (it == by_path.end()) {
      MeshData mesh =
          target.model.empty()
              ? MeshBuilder().AddBox({-0.5f, -0.5f, 0.0f}, {0.5f, 0.5f, 1.0f}, {1, 1, 1}).Take()
              : LoadMesh(target.model);
      VehicleModel model;
      model.dims = BaseCentre(mesh);
      model.positions = mesh.positions;
      model.gpu = Upload(mesh);
      models_.push_back(std::move(model));
      it = by_path.emplace(target.model, models_.size() - 1).first;
    }
    target_model_.push_back(it->second);
    scene_top_m_ = std::max(scene_top_m_, 0.5 * world_.terrain.relief_m + target.dimensions_m.z());
  }
}

void GlSceneRenderer::SetModel(const Eigen::Matrix4f& model) const {
  gl_.UniformMatrix4fv(U("u_model"), 1, GL_FALSE, model.data());
  const Eigen::Matrix3f normal = model.topLeftCorner<3, 3>().inverse().transpose();
  gl_.UniformMatrix3fv(U("u_normal_matrix"), 1, GL_FALSE, normal.data());
}

Eigen::Matrix4f GlSceneRenderer::ViewProj(const CameraState& camera, double* far_m) const {
  const CameraIntrinsics& k = camera.intrinsics;
  // Far plane: beyond the farthest corner of the scene's bounding box.
  double far = 10.0;
  const Eigen::Vector2d half = 0.5 * world_.terrain.size_m;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d corner((i & 1) ? half.x() : -half.x(), (i & 2) ? half.y() : -half.y(),
                                 (i & 4) ? scene_top_m_ : scene_bottom_m_);
    far = std::max(far, camera.ToCamera(corner).z() + 10.0);
  }
  *far_m = far;
  const double n = kNearM;
  const double f = far;
  // Maps camera (OpenCV) coordinates to clip space so that window x = u and
  // window y = v: glReadPixels row v is image row v, no flip needed.
  Eigen::Matrix4d p = Eigen::Matrix4d::Zero();
  p(0, 0) = 2.0 * k.fx_px / k.width_px;
  p(0, 2) = 2.0 * k.cx_px / k.width_px - 1.0;
  p(1, 1) = 2.0 * k.fy_px / k.height_px;
  p(1, 2) = 2.0 * k.cy_px / k.height_px - 1.0;
  p(2, 2) = (f + n) / (f - n);
  p(2, 3) = -2.0 * f * n / (f - n);
  p(3, 2) = 1.0;
  Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
  view.topLeftCorner<3, 3>() = camera.pose.camera_from_world();
  view.topRightCorner<3, 1>() = -camera.pose.camera_from_world() * camera.pose.position_m;
  return (p * view).cast<float>();
}

Eigen::Matrix4f GlSceneRenderer::LightViewProj(const CameraState& camera, double* depth_range_m,
                                               double* texel_m) const {
  const Eigen::Vector3d sun = world_.sun.Direction().normalized();
  const Eigen::Vector3d forward = -sun;
  const Eigen::Vector3d up_hint =
      std::abs(sun.z()) > 0.99 ? Eigen::Vector3d::UnitY() : Eigen::Vector3d::UnitZ();
  const Eigen::Vector3d right = forward.cross(up_hint).normalized();
  const Eigen::Vector3d up = right.cross(forward);
  Eigen::Matrix3d rows;
  rows.row(0) = right;
  rows.row(1) = up;
  rows.row(2) = sun;  // GL eye space looks down -z
  const Eigen::Vector2d half = 0.5 * world_.terrain.size_m;
  const auto clamp_xy = [&](Eigen::Vector3d p) {
    p.x() = std::clamp(p.x(), -half.x(), half.x());
    p.y() = std::clamp(p.y(), -half.y(), half.y());
    return p;
  };
  // Receivers: the part of the terrain the camera sees (rays through a 5x5
  // lattice of image points hitting the bottom and top planes of the scene),
  // clamped to the terrain. Fitting the map to the view instead of the whole
  // terrain keeps shadow texels small when the camera sees a small area.
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::max());
  Eigen::Vector2d hi = -lo;
  const int w = camera.intrinsics.width_px;
  const int h = camera.intrinsics.height_px;
  for (int a = 0; a <= 4; ++a) {
    for (int b = 0; b <= 4; ++b) {
      const Eigen::Vector3d d = camera.RayDirection(w * a / 4.0, h * b / 4.0).normalized();
      for (double z : {scene_bottom_m_, scene_top_m_}) {
        Eigen::Vector3d p;
        const double t = d.z() < -1e-9 ? (z - camera.pose.position_m.z()) / d.z() : -1.0;
        if (t > 0.0) {
          p = camera.pose.position_m + t * d;
        } else {
          p = camera.pose.position_m + 1e6 * Eigen::Vector3d(d.x(), d.y(), 0.0);
          p.z() = z;
        }
        const Eigen::Vector3d e = rows * clamp_xy(p);
        lo = lo.cwiseMin(e.head<2>());
        hi = hi.cwiseMax(e.head<2>());
      }
    }
  }
  lo.array() -= 1.0;
  hi.array() += 1.0;
  *texel_m = (hi - lo).maxCoeff() / shadow_size_;
  // Depth: every caster in the scene box, so casters outside the view still
  // shadow what is seen.
  double zmin = std::numeric_limits<double>::max();
  double zmax = -zmin;
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d corner((i & 1) ? half.x() : -half.x(), (i & 2) ? half.y() : -half.y(),
                                 (i & 4) ? scene_top_m_ + 1.0 : scene_bottom_m_ - 1.0);
    const double z = (rows * corner).z();
    zmin = std::min(zmin, z);
    zmax = std::max(zmax, z);
  }
  const double near = -zmax;
  const double far = -zmin;
  *depth_range_m = far - near;
  Eigen::Matrix4d ortho = Eigen::Matrix4d::Identity();
  ortho(0, 0) = 2.0 / (hi.x() - lo.x());
  ortho(0, 3) = -(hi.x() + lo.x()) / (hi.x() - lo.x());
  ortho(1, 1) = 2.0 / (hi.y() - lo.y());
  ortho(1, 3) = -(hi.y() + lo.y()) / (hi.y() - lo.y());
  ortho(2, 2) = -2.0 / (far - near);
  ortho(2, 3) = -(far + near) / (far - near);
  Eigen::Matrix4d view = Eigen::Matrix4d::Identity();
  view.topLeftCorner<3, 3>() = rows;
  return (ortho * view).cast<float>();
}

double GlSceneRenderer::MeshHeightAt(double x_m, double y_m) const {
  const int g = terrain_cells_;
  const double fx_all = (x_m / world_.terrain.size_m.x() + 0.5) * g;
  const double fy_all = (y_m / world_.terrain.size_m.y() + 0.5) * g;
  const int i = std::clamp(static_cast<int>(std::floor(fx_all)), 0, g - 1);
  const int j = std::clamp(static_cast<int>(std::floor(fy_all)), 0, g - 1);
  const double fx = std::clamp(fx_all - i, 0.0, 1.0);
  const double fy = std::clamp(fy_all - j, 0.0, 1.0);
  const auto h = [&](int a, int b) {
    return double{terrain_heights_[static_cast<size_t>(b) * (g + 1) + static_cast<size_t>(a)]};
  };
  // Cells are split along the (i, j)-(i+1, j+1) diagonal (BuildTerrain).
  if (fx >= fy)
    return h(i, j) + fx * (h(i + 1, j) - h(i, j)) + fy * (h(i + 1, j + 1) - h(i + 1, j));
  return h(i, j) + fy * (h(i, j + 1) - h(i, j)) + fx * (h(i + 1, j + 1) - h(i, j + 1));
}

void GlSceneRenderer::EnsurePackBuffer(GLuint& buffer, size_t& capacity, size_t bytes) {
  if (buffer == 0) gl_.GenBuffers(1, &buffer);
  gl_.BindBuffer(GL_PIXEL_PACK_BUFFER, buffer);
  if (capacity < bytes) {
    // Only between frames: the slot's previous contents were read by Collect.
    gl_.BufferData(GL_PIXEL_PACK_BUFFER, static_cast<GLsizeiptr>(bytes), nullptr, GL_STREAM_READ);
    capacity = bytes;
  }
}

GlSceneRenderer::MappedPackBuffer::MappedPackBuffer(const GlApi& gl, GLuint buffer, size_t bytes)
    : gl_(gl) {
  gl_.BindBuffer(GL_PIXEL_PACK_BUFFER, buffer);
  data_ = static_cast<const uint8_t*>(
      gl_.MapBufferRange(GL_PIXEL_PACK_BUFFER, 0, static_cast<GLsizeiptr>(bytes), GL_MAP_READ_BIT));
  if (data_ == nullptr) {
    gl_.BindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    gl_.CheckError("mapping a pixel-buffer object");
    throw RunError("renderer: mapping a pixel-buffer object failed");
  }
}

GlSceneRenderer::MappedPackBuffer::~MappedPackBuffer() {
  gl_.UnmapBuffer(GL_PIXEL_PACK_BUFFER);
  gl_.BindBuffer(GL_PIXEL_PACK_BUFFER, 0);
}

void GlSceneRenderer::Submit(int frame) {
  HCPF_CHECK(in_flight_ < kMaxInFlight)
      << "Submit with " << in_flight_ << " frames already submitted";
  context_->MakeCurrent();
  InFlight& s = slots_[(head_ + in_flight_) % kMaxInFlight];
  s.frame = frame;
  s.camera = EvaluateCamera(world_.camera, frame);
  const CameraState& camera = s.camera;
  HCPF_CHECK(camera.intrinsics.width_px == width_ && camera.intrinsics.height_px == height_);

  std::vector<TargetInstance>& targets = s.targets;
  targets.clear();
  for (size_t i = 0; i < world_.targets.size(); ++i) {
    const TargetSpec& spec = world_.targets[i];
    TargetInstance t;
    t.slot = i;
    t.pose = EvaluateTarget(spec, world_.terrain, frame, world_.fps);
    if (!t.pose.present) continue;
    const VehicleModel& model = models_[target_model_[i]];
    Eigen::Affine3f m = Eigen::Affine3f::Identity();
    // On the drawn terrain surface; equals the analytic height when the
    // terrain is flat and differs by the mesh's interpolation error (a few
    // centimetres at the default grid) otherwise.
    const Eigen::Vector3d base(t.pose.position_m.x(), t.pose.position_m.y(),
                               MeshHeightAt(t.pose.position_m.x(), t.pose.position_m.y()));
    m.translate(base.cast<float>());
    m.rotate(RotZ(t.pose.heading_deg * kDegToRad));
    m.scale(spec.dimensions_m.cast<float>().cwiseQuotient(model.dims));
    t.model = m.matrix();
    targets.push_back(t);
  }

  const Eigen::Matrix4f view_proj = ViewProj(camera, &s.far_m);
  Eigen::Matrix4f light_view_proj = Eigen::Matrix4f::Identity();
  double light_depth_m = 1.0;
  double light_texel_m = 0.0;

  // Shadow pass: occluders and vehicles cast; the terrain only receives
  // (its relief is gentle, and skipping it keeps the pass cheap).
  if (shadows_) {
    light_view_proj = LightViewProj(camera, &light_depth_m, &light_texel_m);
    gl_.BindFramebuffer(GL_FRAMEBUFFER, shadow_fbo_);
    gl_.Viewport(0, 0, shadow_size_, shadow_size_);
    gl_.Disable(GL_SCISSOR_TEST);
    gl_.Enable(GL_DEPTH_TEST);
    gl_.DepthFunc(GL_LESS);
    gl_.DepthMask(GL_TRUE);
    gl_.Disable(GL_CULL_FACE);
    gl_.ClearDepth(1.0);
    gl_.Clear(GL_DEPTH_BUFFER_BIT);
    gl_.Enable(GL_POLYGON_OFFSET_FILL);
    gl_.PolygonOffset(1.5f, 2.0f);
    gl_.UseProgram(shadow_program_);
    gl_.UniformMatrix4fv(shadow_vp_loc_, 1, GL_FALSE, light_view_proj.data());
    // A closed mesh's nearest surface seen from the sun faces the sun, so its
    // faces turned away are culled: the same nearest depths for half the
    // fragments. (The sun's projection does not flip, so counter-clockwise
    // is front; the model matrices scale by positive factors only.) Open
    // meshes keep both sides.
    gl_.FrontFace(GL_CCW);
    gl_.CullFace(GL_BACK);
    const auto draw_caster = [&](const GpuMesh& mesh) {
      if (mesh.closed) {
        gl_.Enable(GL_CULL_FACE);
      } else {
        gl_.Disable(GL_CULL_FACE);
      }
      Draw(mesh);
    };
    const Eigen::Matrix4f identity = Eigen::Matrix4f::Identity();
    if (occluders_.index_count > 0) {
      gl_.UniformMatrix4fv(shadow_model_loc_, 1, GL_FALSE, identity.data());
      draw_caster(occluders_);
    }
    for (const TargetInstance& t : targets) {
      gl_.UniformMatrix4fv(shadow_model_loc_, 1, GL_FALSE, t.model.data());
      draw_caster(models_[target_model_[t.slot]].gpu);
    }
    gl_.Disable(GL_POLYGON_OFFSET_FILL);
    gl_.CheckError("shadow pass");
  }

  // Colour pass; alpha = instance id / 255.
  gl_.BindFramebuffer(GL_FRAMEBUFFER, main_fbo_);
  gl_.Viewport(0, 0, width_, height_);
  gl_.Disable(GL_SCISSOR_TEST);
  gl_.Enable(GL_DEPTH_TEST);
  gl_.DepthFunc(GL_LESS);
  gl_.DepthMask(GL_TRUE);
  gl_.Enable(GL_CULL_FACE);
  gl_.CullFace(GL_BACK);
  // The projection maps image rows to window rows top-down (a y flip), so
  // counter-clockwise triangles appear clockwise in window coordinates.
  gl_.FrontFace(GL_CW);
  gl_.ClearColor(kSkyClear.x(), kSkyClear.y(), kSkyClear.z(), 0.0f);
  gl_.ClearDepth(1.0);
  gl_.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  gl_.ActiveTexture(GL_TEXTURE0);
  gl_.BindTexture(GL_TEXTURE_2D, shadow_tex_);
  gl_.ActiveTexture(GL_TEXTURE1);
  gl_.BindTexture(GL_TEXTURE_2D, ground_tex_);
  gl_.ActiveTexture(GL_TEXTURE2);
  gl_.BindTexture(GL_TEXTURE_2D, road_tex_);
  gl_.ActiveTexture(GL_TEXTURE3);
  gl_.BindTexture(GL_TEXTURE_2D, mask_tex_);
  // Front to back-ish: vehicles and occluders first, so that the depth test
  // rejects the terrain fragments they cover before shading them.
  Use(object_program_);
  SetFrameUniforms(view_proj, light_view_proj, light_depth_m);
  for (const TargetInstance& t : targets) {
    const Eigen::Vector3f tint = world_.targets[t.slot].tint.cast<float>();
    gl_.Uniform3f(U("u_tint"), tint.x(), tint.y(), tint.z());
    gl_.Uniform1f(U("u_id"), static_cast<float>(t.slot + 1) / 255.0f);
    SetModel(t.model);
    Draw(models_[target_model_[t.slot]].gpu);
  }
  gl_.Uniform3f(U("u_tint"), 1.0f, 1.0f, 1.0f);
  gl_.Uniform1f(U("u_id"), 0.0f);
  SetModel(Eigen::Matrix4f::Identity());
  if (occluders_.index_count > 0) Draw(occluders_);
  // The terrain, part by part (the cheaper variants change no pixel where
  // they are drawn: see PrepareTerrain and MarkShadowCells).
  const auto ranges = PrepareTerrain(view_proj, targets, light_texel_m);
  const std::array<const Program*, kTerrainParts> programs = {
      &terrain_program_, terrain_road_program_.id != 0 ? &terrain_road_program_ : &terrain_program_,
      &terrain_shadow_program_, &terrain_plain_program_};
  for (size_t k = 0; k < ranges.size(); ++k) {
    const auto [first, count] = ranges[k];
    if (count == 0) continue;
    Use(*programs[k]);
    SetFrameUniforms(view_proj, light_view_proj, light_depth_m);
    SetModel(Eigen::Matrix4f::Identity());
    gl_.DrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT,
                     reinterpret_cast<const void*>(first * sizeof(uint32_t)));
  }
  gl_.CheckError("colour pass");

  // Readbacks into the slot's pixel-buffer objects: queued, not waited for.
  const size_t pixels = static_cast<size_t>(width_) * height_;
  gl_.PixelStorei(GL_PACK_ALIGNMENT, 1);
  gl_.ReadBuffer(GL_COLOR_ATTACHMENT0);
  EnsurePackBuffer(s.colour_pbo, s.colour_capacity, 4 * pixels);
  gl_.ReadPixels(0, 0, width_, height_, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
  if (options_.output_depth) {
    EnsurePackBuffer(s.depth_pbo, s.depth_capacity, sizeof(float) * pixels);
    gl_.ReadPixels(0, 0, width_, height_, GL_DEPTH_COMPONENT, GL_FLOAT, nullptr);
  }
  gl_.BindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  gl_.CheckError("readback");
  s.count.clear();
  s.layers.clear();
  if (options_.ground_truth) SubmitCountPass(s, view_proj);
  s.fence = gl_.FenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
  gl_.Flush();
  gl_.CheckError("submit");
  ++in_flight_;
}

RenderedFrame GlSceneRenderer::CollectClean() {
  HCPF_CHECK(in_flight_ > 0) << "Collect with no submitted frame";
  context_->MakeCurrent();
  InFlight& s = slots_[head_];
  head_ = (head_ + 1) % kMaxInFlight;
  --in_flight_;
  // Mapping waits as well; the fence makes the wait explicit and flushes.
  const GLenum waited = gl_.ClientWaitSync(s.fence, GL_SYNC_FLUSH_COMMANDS_BIT, GL_TIMEOUT_IGNORED);
  gl_.DeleteSync(s.fence);
  s.fence = nullptr;
  if (waited == GL_WAIT_FAILED) {
    gl_.CheckError("waiting for a frame");
    throw RunError("renderer: waiting for a submitted frame failed");
  }

  RenderedFrame out;
  out.frame = s.frame;
  const size_t pixels = static_cast<size_t>(width_) * height_;
  if (options_.output_depth) {
    DepthImage depth;
    depth.width = width_;
    depth.height = height_;
    depth.depth_m.resize(pixels);
    ReadPackBuffer(s.depth_pbo, sizeof(float) * pixels, depth.depth_m.data());
    const double n = kNearM;
    const double f = s.far_m;
    for (float& d : depth.depth_m) {
      if (d >= 1.0f) {
        d = std::numeric_limits<float>::infinity();
      } else {
        const double ndc = 2.0 * d - 1.0;
        d = static_cast<float>(2.0 * f * n / (f + n - ndc * (f - n)));
      }
    }
    out.depth = std::move(depth);
  }

  out.rgb.width = width_;
  out.rgb.height = height_;
  out.rgb.pixels.resize(3 * pixels);
  internal::VisibleIds visible(world_.targets.size() + 1, width_, height_);
  {
    // Split straight from the mapping: one pass over the readback, no copy.
    const MappedPackBuffer rgba(gl_, s.colour_pbo, 4 * pixels);
    internal::SplitRgba(rgba.data(), width_, height_, out.rgb.pixels.data(),
                        options_.ground_truth ? &visible : nullptr);
    if (options_.output_instance_ids) {
      InstanceImage ids;
      ids.width = width_;
      ids.height = height_;
      ids.ids.resize(pixels);
      for (size_t i = 0; i < pixels; ++i) {
        const uint8_t a = rgba.data()[4 * i + 3];
        ids.ids[i] = a == 0 ? -1 : Value(world_.targets[a - 1].id);
      }
      out.instance_ids = std::move(ids);
    }
  }
  if (options_.ground_truth) {
    out.ground_truth = GroundTruth(s, visible);
  } else {
    out.ground_truth.frame = s.frame;
    out.ground_truth.camera = s.camera;
    out.ground_truth.image_from_ground = s.camera.ImageFromGround(0.0);
  }
  gl_.CheckError("collect");
  return out;
}

void GlSceneRenderer::ApplySensor(RenderedFrame& frame) const {
  if (options_.sensor.active()) {
    ApplySensorEffects(options_.sensor, rng_.Fork("renderer/sensor", frame.frame), frame.rgb);
  }
}

void GlSceneRenderer::SubmitCountPass(InFlight& s, const Eigen::Matrix4f& view_proj) {
  // Count pass: each target alone (same program, same vertex stage, so the
  // same pixels as in the colour pass) inside a scissor around its projected
  // vertices. Targets whose scissors do not overlap share one layer: one
  // readback per layer instead of per target. Collect counts the pixels.
  const CameraState& camera = s.camera;
  const Eigen::Matrix3d r = camera.pose.camera_from_world();
  const CameraIntrinsics& k = camera.intrinsics;
  s.count.resize(s.targets.size());
  for (size_t i = 0; i < s.targets.size(); ++i) {
    const TargetInstance& t = s.targets[i];
    CountTarget& p = s.count[i];
    p = CountTarget{};
    p.u_lo = p.v_lo = std::numeric_limits<double>::max();
    p.u_hi = p.v_hi = -std::numeric_limits<double>::max();
    for (const Eigen::Vector3f& q : models_[target_model_[t.slot]].positions) {
      const Eigen::Vector4f w = t.model * Eigen::Vector4f(q.x(), q.y(), q.z(), 1.0f);
      const Eigen::Vector3d c = r * (w.head<3>().cast<double>() - camera.pose.position_m);
      if (c.z() <= kNearM) {
        p.behind = true;
        continue;
      }
      p.any_in_front = true;
      const double u = k.fx_px * c.x() / c.z() + k.cx_px;
      const double v = k.fy_px * c.y() / c.z() + k.cy_px;
      p.u_lo = std::min(p.u_lo, u);
      p.u_hi = std::max(p.u_hi, u);
      p.v_lo = std::min(p.v_lo, v);
      p.v_hi = std::max(p.v_hi, v);
    }
    // The whole image when part of the target is behind the near plane,
    // else the projected bounds grown by a pixel.
    p.sx1 = width_;
    p.sy1 = height_;
    if (!p.behind && p.any_in_front) {
      p.sx0 = std::clamp(static_cast<int>(std::floor(p.u_lo)) - 1, 0, width_);
      p.sy0 = std::clamp(static_cast<int>(std::floor(p.v_lo)) - 1, 0, height_);
      p.sx1 = std::clamp(static_cast<int>(std::ceil(p.u_hi)) + 1, 0, width_);
      p.sy1 = std::clamp(static_cast<int>(std::ceil(p.v_hi)) + 1, 0, height_);
    }
  }
  std::vector<size_t> todo;
  for (size_t i = 0; i < s.count.size(); ++i) {
    const CountTarget& p = s.count[i];
    if (p.any_in_front && p.sx1 > p.sx0 && p.sy1 > p.sy0) todo.push_back(i);
  }
  // Layers first (they depend on the scissors alone), so the count buffer is
  // sized once before any readback lands in it.
  size_t bytes = 0;
  while (!todo.empty()) {
    // Greedy layer: targets in scenario order whose scissors are disjoint.
    CountLayer layer;
    std::vector<size_t> rest;
    for (size_t i : todo) {
      const CountTarget& p = s.count[i];
      bool overlaps = false;
      for (size_t j : layer.members) {
        const CountTarget& q = s.count[j];
        if (p.sx0 < q.sx1 && q.sx0 < p.sx1 && p.sy0 < q.sy1 && q.sy0 < p.sy1) {
          overlaps = true;
          break;
        }
      }
      (overlaps ? rest : layer.members).push_back(i);
    }
    int lx1 = 0, ly1 = 0;
    layer.x0 = width_;
    layer.y0 = height_;
    for (size_t i : layer.members) {
      const CountTarget& p = s.count[i];
      layer.x0 = std::min(layer.x0, p.sx0);
      layer.y0 = std::min(layer.y0, p.sy0);
      lx1 = std::max(lx1, p.sx1);
      ly1 = std::max(ly1, p.sy1);
    }
    layer.w = lx1 - layer.x0;
    layer.h = ly1 - layer.y0;
    layer.offset = bytes;
    bytes += 4 * static_cast<size_t>(layer.w) * layer.h;
    s.layers.push_back(std::move(layer));
    todo = std::move(rest);
  }
  if (s.layers.empty()) return;

  gl_.BindFramebuffer(GL_FRAMEBUFFER, main_fbo_);
  Use(id_program_);
  // The colour pass's view-projection (identical vertex stage).
  gl_.UniformMatrix4fv(U("u_view_proj"), 1, GL_FALSE, view_proj.data());
  gl_.Enable(GL_SCISSOR_TEST);
  gl_.ClearColor(0.0f, 0.0f, 0.0f, 0.0f);
  EnsurePackBuffer(s.count_pbo, s.count_capacity, bytes);
  for (const CountLayer& layer : s.layers) {
    for (size_t i : layer.members) {
      const CountTarget& p = s.count[i];
      const TargetInstance& t = s.targets[i];
      gl_.Scissor(p.sx0, p.sy0, p.sx1 - p.sx0, p.sy1 - p.sy0);
      gl_.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
      gl_.Uniform1f(U("u_id"), static_cast<float>(t.slot + 1) / 255.0f);
      SetModel(t.model);
      Draw(models_[target_model_[t.slot]].gpu);
    }
    gl_.ReadPixels(layer.x0, layer.y0, layer.w, layer.h, GL_RGBA, GL_UNSIGNED_BYTE,
                   reinterpret_cast<void*>(layer.offset));  // NOLINT: a PBO offset
  }
  gl_.BindBuffer(GL_PIXEL_PACK_BUFFER, 0);
  gl_.Disable(GL_SCISSOR_TEST);
  gl_.CheckError("ground-truth pass");
}

FrameGroundTruth GlSceneRenderer::GroundTruth(InFlight& s, const internal::VisibleIds& visible) {
  FrameGroundTruth gt;
  gt.frame = s.frame;
  gt.camera = s.camera;
  gt.image_from_ground = s.camera.ImageFromGround(0.0);

  // Unoccluded totals and amodal bounds from the count pass's layers.
  if (!s.layers.empty()) {
    const CountLayer& last = s.layers.back();
    region_.resize(last.offset + 4 * static_cast<size_t>(last.w) * last.h);
    ReadPackBuffer(s.count_pbo, region_.size(), region_.data());
  }
  for (const CountLayer& layer : s.layers) {
    const uint8_t* base = region_.data() + layer.offset;
    for (size_t i : layer.members) {
      CountTarget& p = s.count[i];
      const auto id = static_cast<uint8_t>(s.targets[i].slot + 1);
      for (int y = p.sy0; y < p.sy1; ++y) {
        const uint8_t* row = base + 4 * (static_cast<size_t>(y - layer.y0) * layer.w);
        for (int x = p.sx0; x < p.sx1; ++x) {
          if (row[4 * (x - layer.x0) + 3] != id) continue;
          ++p.total;
          p.ax0 = std::min(p.ax0, x);
          p.ax1 = std::max(p.ax1, x);
          p.ay0 = std::min(p.ay0, y);
          p.ay1 = std::max(p.ay1, y);
        }
      }
    }
  }
  const BoxPx image{0.0, 0.0, static_cast<double>(width_), static_cast<double>(height_)};
  for (size_t i = 0; i < s.count.size(); ++i) {
    const CountTarget& p = s.count[i];
    const TargetInstance& t = s.targets[i];
    const TargetSpec& spec = world_.targets[t.slot];
    GroundTruthObject obj;
    obj.id = spec.id;
    obj.position_m = t.pose.position_m;
    obj.heading_deg = t.pose.heading_deg;
    obj.dimensions_m = spec.dimensions_m;
    const size_t id = t.slot + 1;
    obj.pixels_total = p.total;
    obj.pixels_visible = visible.count[id];
    obj.visible_fraction = p.total > 0 ? static_cast<double>(visible.count[id]) / p.total : 0.0;
    if (visible.count[id] > 0) {
      obj.visible_box = BoxPx::FromCorners(visible.x0[id], visible.y0[id], visible.x1[id] + 1,
                                           visible.y1[id] + 1);
    }
    BoxPx amodal;
    if (p.total > 0) amodal = BoxPx::FromCorners(p.ax0, p.ay0, p.ax1 + 1, p.ay1 + 1);
    // Extend by the projected vertices where the target leaves the image.
    if (p.any_in_front && !p.behind &&
        (p.u_lo < 0.0 || p.v_lo < 0.0 || p.u_hi > width_ || p.v_hi > height_)) {
      amodal = Union(amodal, BoxPx::FromCorners(p.u_lo, p.v_lo, p.u_hi, p.v_hi));
    }
    obj.amodal_box = amodal;
    const double inside = Intersect(amodal, image).area();
    obj.in_frame = inside > 0.0;
    obj.truncation = amodal.area() > 0.0 ? 1.0 - inside / amodal.area() : 0.0;
    gt.objects.push_back(obj);
  }
  return gt;
}

}  // namespace

std::unique_ptr<SceneRenderer> SceneRenderer::Create(const WorldSpec& world,
                                                     const RendererOptions& options, Rng rng,
                                                     std::shared_ptr<GlContext> context) {
  options.Validate();
  if (world.camera.path.empty()) {
    throw InputError(SourceLocation{.key = "camera.path"}, "at least one keyframe", "none");
  }
  if (!context) context = GlContext::Create(options.backend);
  return std::make_unique<GlSceneRenderer>(world, options, rng, std::move(context));
}

}  // namespace hcpf::renderer
