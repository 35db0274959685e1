#include "detection_cache.h"

#include <fmt/format.h>
#include <link.h>
#include <zstd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <mutex>
#include <opencv2/core/utility.hpp>
#include <set>
#include <system_error>
#include <vector>

#include "hcpf/core/check.h"
#include "hcpf/core/error.h"
#include "hcpf/core/text_file.h"
#include "hcpf/scenarios/cache.h"

namespace hcpf::scenarios::internal {
namespace {

// "HCPFDET" + format version. Bump the version when the layout or the
// meaning of a stored output changes: entries of another version are misses.
// Version 2: the payload compressed by zstd (version 1 stored it raw; the
// maps, mostly zeros and smooth, shrink to a fifth, docs/vision.md).
// Version 3: a label after the magic, the scene and the detector
// (DetectionLabel), which `hcpf cache` lists the entry under.
constexpr char kMagic[8] = {'H', 'C', 'P', 'F', 'D', 'E', 'T', '3'};
// zstd level 1: fast to write, and higher levels gain little on the maps.
constexpr int kZstdLevel = 1;
// No stored output is anywhere near this; a larger size read from a damaged
// header is a miss, not an allocation.
constexpr uint64_t kMaxPayloadBytes = uint64_t{1} << 30;

class Writer {
 public:
  template <class T>
  void Put(const T& v) {
    const auto* p = reinterpret_cast<const char*>(&v);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  void PutFloats(const std::vector<float>& v) {
    const auto* p = reinterpret_cast<const char*>(v.data());
    bytes_.insert(bytes_.end(), p, p + v.size() * sizeof(float));
  }
  std::vector<char>& bytes() { return bytes_; }

 private:
  std::vector<char> bytes_;
};

class Reader {
 public:
  Reader(const char* data, size_t size) : data_(data), size_(size) {}
  template <class T>
  bool Get(T* v) {
    if (size_ - at_ < sizeof(T)) return false;
    std::memcpy(v, data_ + at_, sizeof(T));
    at_ += sizeof(T);
    return true;
  }
  bool GetFloats(size_t n, std::vector<float>* v) {
    if ((size_ - at_) / sizeof(float) < n) return false;
    v->resize(n);
    std::memcpy(v->data(), data_ + at_, n * sizeof(float));
    at_ += n * sizeof(float);
    return true;
  }
  bool done() const { return at_ == size_; }

 private:
  const char* data_;
  size_t size_;
  size_t at_ = 0;
};

std::vector<char> Encode(const vision::DetectorOutput& output) {
  Writer w;
  w.Put(static_cast<uint64_t>(output.detections.size()));
  for (const Detection& d : output.detections) {
    w.Put(d.box.left);
    w.Put(d.box.top);
    w.Put(d.box.width);
    w.Put(d.box.height);
    w.Put(d.score);
    w.Put(static_cast<uint8_t>(d.target.has_value()));
    w.Put(static_cast<int64_t>(d.target ? Value(*d.target) : 0));
  }
  w.Put(static_cast<uint64_t>(output.maps.size()));
  for (const TargetMap& m : output.maps) {
    w.Put(static_cast<int64_t>(Value(m.target)));
    w.Put(static_cast<int32_t>(m.map.width));
    w.Put(static_cast<int32_t>(m.map.height));
    w.Put(m.map.cell_px);
    HCPF_CHECK(m.map.values.size() == static_cast<size_t>(m.map.width) * m.map.height)
        << "map of " << m.map.width << " x " << m.map.height << " cells";
    w.PutFloats(m.map.values);
  }
  return std::move(w.bytes());
}

std::optional<vision::DetectorOutput> Decode(const char* data, size_t size) {
  Reader r(data, size);
  vision::DetectorOutput out;
  uint64_t n = 0;
  if (!r.Get(&n) || n > size) return std::nullopt;
  for (uint64_t i = 0; i < n; ++i) {
    Detection d;
    uint8_t has_target = 0;
    int64_t target = 0;
    if (!r.Get(&d.box.left) || !r.Get(&d.box.top) || !r.Get(&d.box.width) ||
        !r.Get(&d.box.height) || !r.Get(&d.score) || !r.Get(&has_target) || !r.Get(&target)) {
      return std::nullopt;
    }
    if (has_target) d.target = ObjectId{static_cast<int32_t>(target)};
    out.detections.push_back(d);
  }
  if (!r.Get(&n) || n > size) return std::nullopt;
  for (uint64_t i = 0; i < n; ++i) {
    TargetMap m;
    int64_t target = 0;
    int32_t width = 0;
    int32_t height = 0;
    if (!r.Get(&target) || !r.Get(&width) || !r.Get(&height) || !r.Get(&m.map.cell_px) ||
        width < 0 || height < 0) {
      return std::nullopt;
    }
    m.target = ObjectId{static_cast<int32_t>(target)};
    m.map.width = width;
    m.map.height = height;
    if (!r.GetFloats(static_cast<size_t>(width) * height, &m.map.values)) return std::nullopt;
    out.maps.push_back(std::move(m));
  }
  if (!r.done()) return std::nullopt;
  return out;
}

// The entry's checksum: XXH3-64 of its label followed by its payload, so
// that a damaged label, which `hcpf cache` lists, is a miss too.
uint64_t Checksum(std::string_view label, const std::vector<char>& payload) {
  XXH3_state_t* state = XXH3_createState();
  HCPF_CHECK(state != nullptr) << "XXH3_createState";
  XXH3_64bits_reset(state);
  XXH3_64bits_update(state, label.data(), label.size());
  XXH3_64bits_update(state, payload.data(), payload.size());
  const uint64_t sum = XXH3_64bits_digest(state);
  XXH3_freeState(state);
  return sum;
}

}  // namespace

std::string DigestHex(const XXH128_hash_t& digest) {
  return fmt::format("{:016x}{:016x}", digest.high64, digest.low64);
}

bool IsDigestHex(std::string_view text) {
  return text.size() == 32 && std::all_of(text.begin(), text.end(), [](char c) {
           return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
         });
}

XXH128_hash_t PixelDigest(const ImageView& image) {
  XXH3_state_t* state = XXH3_createState();
  HCPF_CHECK(state != nullptr) << "XXH3_createState";
  XXH3_128bits_reset(state);
  const int32_t size[2] = {image.width, image.height};
  XXH3_128bits_update(state, size, sizeof(size));
  for (int y = 0; y < image.height; ++y) {
    XXH3_128bits_update(state, image.at(0, y), 3 * static_cast<size_t>(image.width));
  }
  const XXH128_hash_t digest = XXH3_128bits_digest(state);
  XXH3_freeState(state);
  return digest;
}

std::string CpuFeatures() { return cv::getCPUFeaturesLine(); }

namespace {

// The GNU build ID of a loaded object, read from its PT_NOTE segments in
// memory (the linker's hash of the object's contents, 20 bytes of SHA-1 by
// default): as lowercase hex, "" when it has none.
std::string BuildIdOf(const dl_phdr_info& info) {
  for (int i = 0; i < info.dlpi_phnum; ++i) {
    const ElfW(Phdr)& ph = info.dlpi_phdr[i];
    if (ph.p_type != PT_NOTE) continue;
    const size_t align = ph.p_align >= 8 ? 8 : 4;
    const auto pad = [align](size_t n) { return (n + align - 1) / align * align; };
    const auto* at = reinterpret_cast<const unsigned char*>(info.dlpi_addr + ph.p_vaddr);
    const unsigned char* end = at + ph.p_memsz;
    while (at + sizeof(ElfW(Nhdr)) <= end) {
      ElfW(Nhdr) note;
      std::memcpy(&note, at, sizeof(note));
      const unsigned char* name = at + sizeof(note);
      const unsigned char* desc = name + pad(note.n_namesz);
      if (desc + note.n_descsz > end) break;
      if (note.n_type == NT_GNU_BUILD_ID && note.n_namesz == 4 &&
          std::memcmp(name, "GNU", 4) == 0 && note.n_descsz > 0) {
        std::string hex;
        for (uint32_t k = 0; k < note.n_descsz; ++k) hex += fmt::format("{:02x}", desc[k]);
        return hex;
      }
      at = desc + pad(note.n_descsz);
    }
  }
  return "";
}

}  // namespace

std::vector<CodeObject> CodeObjects() {
  // The loaded object whose segments hold this function: the executable
  // (dl_iterate_phdr names it "") or a shared library, by the path it was
  // loaded from. The `hcpf` launcher loads libhcpf_cli.so, which holds the
  // detectors: hashing the launcher alone would let a rebuilt detector read
  // the outputs of the build before it. Beside it, the shared libraries
  // whose arithmetic the detectors call: OpenCV's and the C maths library
  // (another OpenCV build, or another libm's exp, can move a detection).
  struct Search {
    uintptr_t address = 0;
    CodeObject code;
    bool found = false;
    std::map<std::string, CodeObject> libraries;  // by file name, in name order
  } search{.address = reinterpret_cast<uintptr_t>(&CodeObjects)};
  dl_iterate_phdr(
      [](dl_phdr_info* info, size_t, void* data) -> int {
        auto* s = static_cast<Search*>(data);
        const std::string name = info->dlpi_name != nullptr ? info->dlpi_name : "";
        const std::string base = std::filesystem::path(name).filename().string();
        if (base.rfind("libopencv_", 0) == 0 || base.rfind("libm.so", 0) == 0) {
          s->libraries.emplace(base, CodeObject{name, BuildIdOf(*info)});
        }
        for (int i = 0; !s->found && i < info->dlpi_phnum; ++i) {
          const ElfW(Phdr)& ph = info->dlpi_phdr[i];
          if (ph.p_type != PT_LOAD) continue;
          const uintptr_t start = info->dlpi_addr + ph.p_vaddr;
          if (s->address >= start && s->address < start + ph.p_memsz) {
            s->code = CodeObject{name.empty() ? "/proc/self/exe" : name, BuildIdOf(*info)};
            s->found = true;
          }
        }
        return 0;
      },
      &search);
  if (!search.found) search.code = CodeObject{"/proc/self/exe", ""};
  std::vector<CodeObject> objects{search.code};
  for (const auto& [base, object] : search.libraries) objects.push_back(object);
  return objects;
}

std::optional<XXH128_hash_t> ComputeProgramDigest(const std::vector<CodeObject>& objects) {
  XXH3_state_t* state = XXH3_createState();
  HCPF_CHECK(state != nullptr) << "XXH3_createState";
  XXH3_128bits_reset(state);
  std::vector<char> buffer(1 << 20);
  bool ok = true;
  for (const CodeObject& object : objects) {
    if (!object.build_id.empty()) {
      // Its build ID stands for its contents (nothing read from disk).
      const std::string text = "build-id:" + object.build_id;
      const uint64_t length = text.size();
      XXH3_128bits_update(state, text.data(), text.size());
      XXH3_128bits_update(state, &length, sizeof(length));
      continue;
    }
    std::ifstream in(object.path, std::ios::binary);
    uint64_t bytes = 0;
    while (in) {
      in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
      XXH3_128bits_update(state, buffer.data(), static_cast<size_t>(in.gcount()));
      bytes += static_cast<uint64_t>(in.gcount());
    }
    // Each file's length after it: the concatenation is then unambiguous.
    XXH3_128bits_update(state, &bytes, sizeof(bytes));
    ok = ok && in.eof();
  }
  // The instruction sets OpenCV dispatches its kernels to on this CPU (as
  // OPENCV_CPU_DISABLE leaves them): NCC's matchTemplate and the
  // differencing's corners and optical flow round differently on another
  // CPU, so a cache shared by unlike machines must not mix them.
  const std::string cpu = CpuFeatures();
  XXH3_128bits_update(state, cpu.data(), cpu.size());
  const XXH128_hash_t h = XXH3_128bits_digest(state);
  XXH3_freeState(state);
  if (!ok) return std::nullopt;
  return h;
}

const std::optional<XXH128_hash_t>& ProgramDigest() {
  static const std::optional<XXH128_hash_t> digest = ComputeProgramDigest(CodeObjects());
  return digest;
}

DetectionKey::DetectionKey() : state_(XXH3_createState()) {
  HCPF_CHECK(state_ != nullptr) << "XXH3_createState";
  XXH3_128bits_reset(state_);
}
DetectionKey::~DetectionKey() { XXH3_freeState(state_); }

void DetectionKey::Add(std::string_view text) {
  Add(static_cast<uint64_t>(text.size()));
  XXH3_128bits_update(state_, text.data(), text.size());
}
void DetectionKey::Add(uint64_t value) { XXH3_128bits_update(state_, &value, sizeof(value)); }
void DetectionKey::Add(double value) { XXH3_128bits_update(state_, &value, sizeof(value)); }
void DetectionKey::Add(const XXH128_hash_t& digest) {
  Add(digest.high64);
  Add(digest.low64);
}
std::string DetectionKey::Finish() const {
  return DigestHex(XXH3_128bits_digest(state_));  // state_ is left as it is
}

DetectionCache::DetectionCache(const std::filesystem::path& root, std::string label)
    : dir_(root / "detections"), label_(std::move(label)) {
  HCPF_CHECK(label_.size() <= kMaxDetectionLabelBytes) << label_;
  // What killed writes left (WriteTextFile's temporary files of processes
  // that no longer run), once per folder and process: the folder holds a
  // file per frame and detector, and a sweep makes a cache per run.
  static std::mutex mutex;
  static std::set<std::filesystem::path> cleaned;
  const std::lock_guard<std::mutex> lock(mutex);
  if (cleaned.insert(dir_).second) RemoveStaleTempFiles(dir_);
}

std::optional<vision::DetectorOutput> DetectionCache::Load(const std::string& key) const {
  const auto path = dir_ / (key + ".det");
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  const std::vector<char> bytes((std::istreambuf_iterator<char>(in)),
                                std::istreambuf_iterator<char>());
  // magic, u8 label bytes and the label, u64 payload bytes, the payload
  // compressed by zstd, XXH3-64 of the label and the payload (Checksum).
  if (bytes.size() < sizeof(kMagic) + 1 || std::memcmp(bytes.data(), kMagic, sizeof(kMagic)) != 0) {
    return std::nullopt;
  }
  const size_t header = sizeof(kMagic) + 1 + static_cast<uint8_t>(bytes[sizeof(kMagic)]);
  const size_t overhead = header + 2 * sizeof(uint64_t);
  if (bytes.size() < overhead) return std::nullopt;
  uint64_t payload_size = 0;
  uint64_t checksum = 0;
  std::memcpy(&payload_size, bytes.data() + header, sizeof(payload_size));
  std::memcpy(&checksum, bytes.data() + bytes.size() - sizeof(checksum), sizeof(checksum));
  if (payload_size > kMaxPayloadBytes) return std::nullopt;
  const char* compressed = bytes.data() + header + sizeof(payload_size);
  const size_t compressed_size = bytes.size() - overhead;
  std::vector<char> payload(static_cast<size_t>(payload_size));
  const size_t got = ZSTD_decompress(payload.data(), payload.size(), compressed, compressed_size);
  if (ZSTD_isError(got) || got != payload.size()) return std::nullopt;
  if (checksum !=
      Checksum(std::string_view(bytes.data() + sizeof(kMagic) + 1, header - sizeof(kMagic) - 1),
               payload)) {
    return std::nullopt;
  }
  std::optional<vision::DetectorOutput> out = Decode(payload.data(), payload.size());
  if (out) MarkUsed(path);  // `hcpf cache --max-size` prunes the least used
  return out;
}

void DetectionCache::Store(const std::string& key, const vision::DetectorOutput& output) const {
  std::error_code ec;
  std::filesystem::create_directories(dir_, ec);
  if (ec) {
    throw RunError(
        fmt::format("cannot create detection cache {}: {}", dir_.string(), ec.message()));
  }
  const std::vector<char> payload = Encode(output);
  const uint64_t payload_size = payload.size();
  const uint64_t checksum = Checksum(label_, payload);
  std::vector<char> compressed(ZSTD_compressBound(payload.size()));
  const size_t compressed_size = ZSTD_compress(compressed.data(), compressed.size(), payload.data(),
                                               payload.size(), kZstdLevel);
  HCPF_CHECK(!ZSTD_isError(compressed_size)) << ZSTD_getErrorName(compressed_size);
  std::string bytes(kMagic, sizeof(kMagic));
  bytes += static_cast<char>(static_cast<uint8_t>(label_.size()));
  bytes += label_;
  bytes.append(reinterpret_cast<const char*>(&payload_size), sizeof(payload_size));
  bytes.append(compressed.data(), compressed_size);
  bytes.append(reinterpret_cast<const char*>(&checksum), sizeof(checksum));
  // Written whole under a temporary name unique to this process and write,
  // then renamed (WriteTextFile): concurrent runs storing the same key each
  // write their own and the last rename wins (same contents); a failed write
  // (a full disk) removes its temporary file and says why, where one was kept
  // for good with "cannot write" and no reason.
  WriteTextFile((dir_ / (key + ".det")).string(), bytes);
}

}  // namespace hcpf::scenarios::internal
