// Frame cache and the pixel hash that keys it.

#include <fmt/format.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>
#include <system_error>
#include <thread>

#include "hcpf/core/error.h"
#include "hcpf/core/ground_truth_json.h"
#include "hcpf/renderer/renderer.h"

namespace hcpf::renderer {
namespace {

// Bump when shading, geometry or ground-truth rules change, so old caches
// are not reused.
// 2: shader variants, border-lit shadow map; 3: ground truth records in the
// gt.json frame encoding (core/ground_truth_json.h); 4: sensor noise from the
// ziggurat generator (core/normal.h) instead of Box-Muller.
constexpr int kRendererVersion = 4;

std::string FileDigest(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return "missing";
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return fmt::format("{:016x}", HashName(bytes.str()));
}

void AppendVec(std::string& s, const Eigen::Vector2d& v) {
  s += fmt::format("[{:.17g},{:.17g}]", v.x(), v.y());
}
void AppendVec(std::string& s, const Eigen::Vector3d& v) {
  s += fmt::format("[{:.17g},{:.17g},{:.17g}]", v.x(), v.y(), v.z());
}

}  // namespace

std::string PixelHash(const WorldSpec& world, const RendererOptions& options, uint64_t seed) {
  std::string s = fmt::format("hcpf-renderer-v{};seed={};", kRendererVersion, seed);
  s += fmt::format("frames={};fps={:.17g};", world.frames, world.fps);
  const TerrainSpec& t = world.terrain;
  s += "terrain=";
  AppendVec(s, t.size_m);
  s += fmt::format(",{:.17g},{},{},{};", t.relief_m, t.texture, t.roads, t.seed);
  const SunSpec& sun = world.sun;
  s += fmt::format("sun={:.17g},{:.17g},{};", sun.azimuth_deg, sun.elevation_deg, sun.shadows);
  for (const OccluderSpec& o : world.occluders) {
    s += fmt::format("occ={},", static_cast<int>(o.kind));
    AppendVec(s, o.from_m);
    AppendVec(s, o.to_m);
    AppendVec(s, o.at_m);
    AppendVec(s, o.size_m);
    s += fmt::format(",{:.17g},{:.17g},{:.17g},{:.17g},{}", o.width_m, o.height_m, o.yaw_deg,
                     o.scale, o.model);
    if (o.kind == OccluderKind::kMesh) {
      s += '#';  // (not "#" + ...: GCC 12 -O3 warns falsely, -Wrestrict)
      s += FileDigest(o.model);
    }
    s += ";";
  }
  for (const TargetSpec& tg : world.targets) {
    s += fmt::format("tgt={},{}#{},", Value(tg.id), tg.model,
                     tg.model.empty() ? "box" : FileDigest(tg.model));
    AppendVec(s, tg.tint);
    AppendVec(s, tg.dimensions_m);
    const TargetPathSpec& p = tg.path;
    s += fmt::format(",{},{:.17g},", static_cast<int>(p.kind), p.speed_mps);
    for (const auto& w : p.waypoints_m) AppendVec(s, w);
    for (const PathStop& st : p.stops) s += fmt::format("s{:.17g}/{:.17g}", st.at_m, st.duration_s);
    AppendVec(s, p.start_m);
    s += fmt::format(",{:.17g},{:.17g},{},{},{};", p.heading_deg, p.turn_rate_deg_s, p.start_frame,
                     p.end_frame, p.vanish_at_end);
  }
  const CameraSpec& c = world.camera;
  s += fmt::format("camera={},{},{:.17g},{:.17g},{},", c.width_px, c.height_px, c.hfov_deg,
                   c.shake_px, c.shake_seed);
  for (const CameraKeyframe& k : c.path) {
    s += fmt::format("k{}", k.frame);
    AppendVec(s, k.position_m);
    AppendVec(s, k.look_at_m);
  }
  const RendererOptions& o = options;
  s += fmt::format(";opts={},{},{},{},{},{:.17g},{:.17g},{};", o.shadows, o.shadow_map_size,
                   o.pcf_radius, o.terrain_grid, o.texture_size, o.texture_tile_m, o.road_width_m,
                   o.ground_truth);
  s += fmt::format("sensor={:.17g},{:.17g},{:.17g},{}", o.sensor.exposure, o.sensor.blur_px,
                   o.sensor.noise_sigma, o.sensor.jpeg_quality);
  // Two independent 64-bit digests (FNV-1a of the text and of its reverse,
  // each mixed) make an accidental collision negligible.
  const std::string reversed(s.rbegin(), s.rend());
  return fmt::format("{:016x}{:016x}", Mix64(HashName(s)), Mix64(HashName(reversed)));
}

FrameCache::FrameCache(std::filesystem::path root, std::string hash)
    : dir_(std::move(root) / std::move(hash)) {}

std::optional<RenderedFrame> FrameCache::Load(int frame) const {
  const auto png = dir_ / fmt::format("{:06d}.png", frame);
  const auto json = dir_ / fmt::format("{:06d}.json", frame);
  std::error_code ec;
  if (!std::filesystem::exists(png, ec) || !std::filesystem::exists(json, ec)) return std::nullopt;
  try {
    RenderedFrame out;
    out.frame = frame;
    out.rgb = ReadPng(png.string());
    std::ifstream in(json);
    out.ground_truth = GroundTruthFromJson(nlohmann::json::parse(in));
    return out;
  } catch (const std::exception&) {
    return std::nullopt;  // a damaged entry is re-rendered
  }
}

void FrameCache::Store(const RenderedFrame& frame) const {
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec)
    throw RunError(fmt::format("cannot create frame cache {}: {}", dir_.string(), ec.message()));
  const auto png = dir_ / fmt::format("{:06d}.png", frame.frame);
  const auto json = dir_ / fmt::format("{:06d}.json", frame.frame);
  // Temporary names unique to this process and thread: concurrent runs that
  // render the same scene each write their own and the last rename wins (the
  // contents are identical).
  const std::string unique =
      fmt::format("{}-{}", ::getpid(), std::hash<std::thread::id>{}(std::this_thread::get_id()));
  const auto png_tmp = dir_ / fmt::format("{:06d}.{}.tmp.png", frame.frame, unique);
  const auto json_tmp = dir_ / fmt::format("{:06d}.{}.json.tmp", frame.frame, unique);
  WritePng(frame.rgb, png_tmp.string());
  {
    std::ofstream out(json_tmp);
    out << GroundTruthToJson(frame.ground_truth).dump();
    if (!out) throw RunError(fmt::format("cannot write {}", json_tmp.string()));
  }
  // The JSON is renamed last: Load() needs both, so a crash in between
  // leaves a miss, never a frame without its ground truth.
  std::filesystem::rename(png_tmp, png, ec);
  if (!ec) std::filesystem::rename(json_tmp, json, ec);
  if (ec) throw RunError(fmt::format("cannot store frame in {}: {}", dir_.string(), ec.message()));
}

}  // namespace hcpf::renderer
