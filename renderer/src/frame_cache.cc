// Frame cache and the pixel hash that keys it.

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>
#include <zstd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <system_error>
#include <vector>

#include "hcpf/core/error.h"
#include "hcpf/core/ground_truth_json.h"
#include "hcpf/core/parallel.h"
#include "hcpf/core/text_file.h"
#include "hcpf/renderer/renderer.h"

namespace hcpf::renderer {
namespace {

// Bump when shading, geometry or ground-truth rules change, so old caches
// are not reused.
// 2: shader variants, border-lit shadow map; 3: ground truth records in the
// gt.json frame encoding (core/ground_truth_json.h); 4: sensor noise from the
// ziggurat generator (core/normal.h) instead of Box-Muller; 5: sensor noise
// drawn as rounded integers (src/rounded_gaussian.h), same distribution; 6:
// terrain lit and its texture and shadow coordinates computed per vertex
// (shaders.h); 7: sensor noise words from eight interleaved generator lanes
// (sensor.cc), same distribution; 8: the shadow pass culls the back faces of
// closed casters (a few texels at shadow silhouettes move); 9: texture mipmaps
// computed by the renderer (textures.h, HalveTexture) instead of
// glGenerateMipmap (the far terrain ~1-2 levels darker on Mesa); 10: the
// camera's roll between 8.1 and 2 degrees from straight down blends the two
// rules smoothly (core/camera.cc, CameraPose::LookAt; climb's frames from
// 11 on turn by up to 0.74 degrees).
constexpr int kRendererVersion = 10;

// A file's bytes, or nullopt when it cannot be read.
std::optional<std::string> FileBytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::ostringstream bytes;
  bytes << in.rdbuf();
  return bytes.str();
}

// A glTF URI as tinygltf reads it (dlib's urldecode: %XX is a byte, + a space).
std::string UrlDecode(const std::string& uri) {
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '+') {
      out += ' ';
    } else if (uri[i] == '%' && i + 2 < uri.size() &&
               std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
               std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
      out += static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

// A model file by its name and content, not its folder: the same scene
// rendered from another clone or machine (whose model paths are absolute
// elsewhere) has the same hash, so `observation.file.rendering` can tell
// frames apart by what they show, wherever they were rendered. The name stays
// (its extension picks the loader). Then each side file's name and bytes (a
// glTF whose .bin changed, or an .obj whose .mtl did, draws other pixels).
std::string ModelKey(const std::string& path) {
  std::string key = std::filesystem::path(path).filename().string();
  key += '#';
  const std::optional<std::string> bytes = FileBytes(path);
  if (!bytes) return key + "missing";
  key += fmt::format("{:016x}", HashName(*bytes));
  for (const std::filesystem::path& side : ModelSideFiles(path, *bytes)) {
    const std::optional<std::string> side_bytes = FileBytes(side);
    key += fmt::format("+{}#{}", side.filename().string(),
                       side_bytes ? fmt::format("{:016x}", HashName(*side_bytes)) : "missing");
  }
  return key;
}

void AppendVec(std::string& s, const Eigen::Vector2d& v) {
  s += fmt::format("[{:.17g},{:.17g}]", v.x(), v.y());
}
void AppendVec(std::string& s, const Eigen::Vector3d& v) {
  s += fmt::format("[{:.17g},{:.17g},{:.17g}]", v.x(), v.y(), v.z());
}

}  // namespace

// A glTF's buffers named by URI (its geometry; a .glb's JSON chunk may name
// some too), an .obj's material libraries (their colours). Images are not
// read (the renderer shades by base colour).
std::vector<std::filesystem::path> ModelSideFiles(const std::filesystem::path& path,
                                                  const std::string& bytes) {
  std::vector<std::filesystem::path> files;
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  const std::filesystem::path folder = path.parent_path();
  if (extension == ".gltf" || extension == ".glb") {
    std::string json_text = bytes;
    if (extension == ".glb") {
      // 12-byte header, then the JSON chunk: its length and type ("JSON").
      if (bytes.size() < 20 || bytes.compare(16, 4, "JSON") != 0) return files;
      uint32_t length = 0;
      std::memcpy(&length, bytes.data() + 12, 4);
      if (length > bytes.size() - 20) return files;
      json_text = bytes.substr(20, length);
    }
    const nlohmann::json gltf =
        nlohmann::json::parse(json_text, nullptr, /*allow_exceptions=*/false);
    if (!gltf.is_object() || !gltf.contains("buffers") || !gltf["buffers"].is_array()) return files;
    for (const nlohmann::json& buffer : gltf["buffers"]) {
      if (!buffer.is_object() || !buffer.contains("uri") || !buffer["uri"].is_string()) continue;
      const std::string uri = buffer["uri"].get<std::string>();
      if (uri.rfind("data:", 0) == 0) continue;  // embedded: in the model's own bytes
      files.push_back(folder / UrlDecode(uri));
    }
  } else if (extension == ".obj") {
    std::istringstream lines(bytes);
    std::string line;
    while (std::getline(lines, line)) {
      const size_t start = line.find_first_not_of(" \t");
      if (start == std::string::npos || line.compare(start, 6, "mtllib") != 0 ||
          line.find_first_of(" \t", start + 6) != start + 6) {
        continue;
      }
      const size_t begin = line.find_first_not_of(" \t", start + 6);
      const size_t end = line.find_last_not_of(" \t\r");
      if (begin != std::string::npos && end >= begin)
        files.push_back(folder / line.substr(begin, end - begin + 1));
    }
  }
  return files;
}

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
    s +=
        fmt::format(",{:.17g},{:.17g},{:.17g},{:.17g},", o.width_m, o.height_m, o.yaw_deg, o.scale);
    if (o.kind == OccluderKind::kMesh) s += ModelKey(o.model);
    s += ";";
  }
  for (const TargetSpec& tg : world.targets) {
    s += fmt::format("tgt={},{},", Value(tg.id), tg.model.empty() ? "box" : ModelKey(tg.model));
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

namespace {

// The .frame layout, little-endian: "HCPFRAME", u32 format version, u32
// width, u32 height, u32 channels (3), u64 payload bytes, then one zstd frame
// of the filtered planes (R rows, then G, then B; each byte minus its left
// neighbour in the same row, mod 256) with zstd's content checksum.
constexpr char kMagic[8] = {'H', 'C', 'P', 'F', 'R', 'A', 'M', 'E'};
constexpr size_t kHeaderBytes = 32;
constexpr int kMaxSide = 1 << 15;

void Put32(std::string& out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}
void Put64(std::string& out, uint64_t v) {
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<char>((v >> (8 * i)) & 0xFF));
}
uint64_t Get(const std::string& in, size_t at, int bytes) {
  uint64_t v = 0;
  for (int i = bytes - 1; i >= 0; --i) v = (v << 8) | static_cast<unsigned char>(in[at + i]);
  return v;
}

std::string EncodeFrame(const RgbImage& image) {
  const size_t w = static_cast<size_t>(image.width);
  const size_t h = static_cast<size_t>(image.height);
  std::vector<uint8_t> planes(w * h * 3);
  for (size_t y = 0; y < h; ++y) {
    const uint8_t* row = image.pixels.data() + y * w * 3;
    for (size_t c = 0; c < 3; ++c) {
      uint8_t* d = planes.data() + c * w * h + y * w;
      uint8_t previous = 0;
      for (size_t x = 0; x < w; ++x) {
        const uint8_t v = row[x * 3 + c];
        d[x] = static_cast<uint8_t>(v - previous);
        previous = v;
      }
    }
  }
  std::string out;
  out.append(kMagic, sizeof(kMagic));
  Put32(out, FrameCache::kFormatVersion);
  Put32(out, static_cast<uint32_t>(w));
  Put32(out, static_cast<uint32_t>(h));
  Put32(out, 3);
  const size_t bound = ZSTD_compressBound(planes.size());
  std::string payload(bound, '\0');
  // Level 1 with zstd's content checksum (XXH64 of the planes): a damaged
  // file fails decompression instead of decoding to other pixels.
  std::unique_ptr<ZSTD_CCtx, decltype(&ZSTD_freeCCtx)> context(ZSTD_createCCtx(), &ZSTD_freeCCtx);
  if (!context) throw RunError("zstd: cannot create a compression context");
  ZSTD_CCtx_setParameter(context.get(), ZSTD_c_compressionLevel, 1);
  ZSTD_CCtx_setParameter(context.get(), ZSTD_c_checksumFlag, 1);
  const size_t n =
      ZSTD_compress2(context.get(), payload.data(), bound, planes.data(), planes.size());
  if (ZSTD_isError(n)) throw RunError(fmt::format("zstd: {}", ZSTD_getErrorName(n)));
  payload.resize(n);
  Put64(out, n);
  out += payload;
  return out;
}

// nullopt for anything but a well-formed file of this format version.
std::optional<RgbImage> DecodeFrame(const std::string& in) {
  if (in.size() < kHeaderBytes || in.compare(0, sizeof(kMagic), kMagic, sizeof(kMagic)) != 0) {
    return std::nullopt;
  }
  const uint64_t version = Get(in, 8, 4);
  const uint64_t w = Get(in, 12, 4);
  const uint64_t h = Get(in, 16, 4);
  const uint64_t channels = Get(in, 20, 4);
  const uint64_t payload = Get(in, 24, 8);
  if (version != FrameCache::kFormatVersion || w == 0 || h == 0 || w > kMaxSide || h > kMaxSide ||
      channels != 3 || payload != in.size() - kHeaderBytes) {
    return std::nullopt;
  }
  const size_t raw = static_cast<size_t>(w * h * 3);
  const unsigned long long content = ZSTD_getFrameContentSize(in.data() + kHeaderBytes, payload);
  if (content != raw) return std::nullopt;
  std::vector<uint8_t> planes(raw);
  const size_t n = ZSTD_decompress(planes.data(), raw, in.data() + kHeaderBytes, payload);
  if (ZSTD_isError(n) || n != raw) return std::nullopt;
  RgbImage image;
  image.width = static_cast<int>(w);
  image.height = static_cast<int>(h);
  image.pixels.resize(raw);
  for (size_t y = 0; y < h; ++y) {
    uint8_t* row = image.pixels.data() + y * w * 3;
    for (size_t c = 0; c < 3; ++c) {
      const uint8_t* d = planes.data() + c * w * h + y * w;
      uint8_t v = 0;
      for (size_t x = 0; x < w; ++x) {
        v = static_cast<uint8_t>(v + d[x]);
        row[x * 3 + c] = v;
      }
    }
  }
  return image;
}

}  // namespace

std::string RendererLine(const GlInfo& gl) {
  std::string line = fmt::format("{}; {}; {}; {}", gl.platform, gl.vendor, gl.renderer, gl.version);
  std::replace(line.begin(), line.end(), '\n', ' ');
  return line;
}

std::vector<std::string> FrameCache::Renderers() const {
  std::vector<std::string> lines;
  std::ifstream in(dir_ / "renderers.txt");
  for (std::string line; std::getline(in, line);) {
    if (!line.empty() && std::find(lines.begin(), lines.end(), line) == lines.end()) {
      lines.push_back(line);
    }
  }
  return lines;
}

void FrameCache::NoteRenderer(const GlInfo& gl) const {
  const std::string line = RendererLine(gl);
  const std::vector<std::string> known = Renderers();
  if (std::find(known.begin(), known.end(), line) != known.end()) return;
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec)
    throw RunError(fmt::format("cannot create frame cache {}: {}", dir_.string(), ec.message()));
  const std::filesystem::path path = dir_ / "renderers.txt";
  // One write() with O_APPEND: two processes noting at once add two whole
  // lines (a duplicate is read once).
  const std::string text = line + "\n";
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  const bool ok =
      fd >= 0 && ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  const int error = errno;
  if (fd >= 0) ::close(fd);
  if (!ok) throw RunError(fmt::format("cannot write {}: {}", path.string(), std::strerror(error)));
}

bool FrameCache::Contains(int frame) const {
  std::error_code ec;
  return std::filesystem::is_regular_file(dir_ / fmt::format("{:06d}.frame", frame), ec);
}

std::optional<RenderedFrame> FrameCache::Load(int frame) const {
  const auto pixels = dir_ / fmt::format("{:06d}.frame", frame);
  const auto json = dir_ / fmt::format("{:06d}.json", frame);
  std::error_code ec;
  if (!std::filesystem::exists(pixels, ec) || !std::filesystem::exists(json, ec)) {
    return std::nullopt;
  }
  try {
    // The largest file DecodeFrame accepts; an unreadable or larger one
    // throws, which is a miss below.
    const uint64_t max_bytes =
        kHeaderBytes + ZSTD_compressBound(size_t{kMaxSide} * size_t{kMaxSide} * 3);
    std::optional<RgbImage> image =
        DecodeFrame(ReadInputFile(pixels.string(), "a cached frame", max_bytes));
    if (!image) return std::nullopt;  // another format version or a damaged file
    RenderedFrame out;
    out.frame = frame;
    out.rgb = std::move(*image);
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
  // Each file is written whole under a temporary name unique to this process
  // and write, then renamed (WriteTextFile): concurrent runs that render the
  // same scene each write their own and the last rename wins (the contents
  // are identical); a failed write (a full disk) removes its temporary file
  // and says why. The JSON is renamed last: Load() needs both, so a failure
  // or a crash in between leaves a miss, never a frame without its ground
  // truth. (The temporary files were named here and kept on a failed write:
  // a full disk left a partial .frame.tmp in the cache for good, and the
  // error had no reason.)
  WriteTextFile((dir_ / fmt::format("{:06d}.frame", frame.frame)).string(), EncodeFrame(frame.rgb));
  WriteTextFile((dir_ / fmt::format("{:06d}.json", frame.frame)).string(),
                GroundTruthToJson(frame.ground_truth).dump());
}

struct FrameCacheWriter::State {
  State(FrameCache c, int depth, int workers) : cache(std::move(c)) {
    for (int i = 0; i < std::max(1, workers); ++i) {
      this->workers.push_back(std::make_unique<SerialWorker>(depth));
    }
  }
  FrameCache cache;
  std::vector<std::unique_ptr<SerialWorker>> workers;
  size_t submitted = 0;

  // A store's failure, rethrown by a worker, named after the cache.
  [[noreturn]] void Rethrow(const std::exception& e) const {
    throw RunError(fmt::format("frame cache {}: {}", cache.dir().string(), e.what()));
  }
};

FrameCacheWriter::FrameCacheWriter(FrameCache cache, int queue_depth, int workers)
    : state_(std::make_unique<State>(std::move(cache), queue_depth, workers)) {}

FrameCacheWriter::~FrameCacheWriter() = default;  // the workers wait for their stores

void FrameCacheWriter::Submit(RenderedFrame frame) {
  try {
    SerialWorker& worker = *state_->workers[state_->submitted++ % state_->workers.size()];
    worker.Post([s = state_.get(), f = std::move(frame)] { s->cache.Store(f); });
  } catch (const std::exception& e) {
    state_->Rethrow(e);
  }
}

void FrameCacheWriter::Finish() {
  std::exception_ptr first;
  for (auto& worker : state_->workers) {
    try {
      worker->Wait();
    } catch (...) {
      if (!first) first = std::current_exception();
    }
  }
  if (!first) return;
  try {
    std::rethrow_exception(first);
  } catch (const std::exception& e) {
    state_->Rethrow(e);
  }
}

}  // namespace hcpf::renderer
