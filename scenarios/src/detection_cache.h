#pragma once
// Private: the detection cache. A detector's output for one frame, stored on
// disk under a key that covers everything the output depends on: the
// frame's pixels, the earlier frames it reads, the target models (their
// pixels, boxes and frames), the detector's name and options, and its random
// stream. A tracker sweep over one scene then detects once: every run after
// the first reads the detections (docs/vision.md, "Detection cache").

#include <xxhash.h>

#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "hcpf/core/image.h"
#include "hcpf/vision/detector.h"

namespace hcpf::scenarios::internal {

// A digest as 32 lowercase hex digits (high 64 bits first).
std::string DigestHex(const XXH128_hash_t& digest);
// Whether `text` is written as DigestHex writes (32 lowercase hex digits):
// what observation.file.digest and pixel_hash must be.
bool IsDigestHex(std::string_view text);

// XXH3-128 of an image's size and pixels.
XXH128_hash_t PixelDigest(const ImageView& image);

// A loaded object of the code that detects: the path it was loaded from, and
// its GNU build ID (lowercase hex, from its notes in memory; "" when it has
// none).
struct CodeObject {
  std::string path;
  std::string build_id;
};

// The objects of the code that detects, in the order ProgramDigest hashes
// them: first the loaded object that holds the detection code (this
// module's): the running executable when it is linked in (the tests;
// "/proc/self/exe"), or the shared library that holds it (the `hcpf`
// launcher loads libhcpf_cli.so, which links every module); then every
// loaded OpenCV library (libopencv_*) and the C maths library (libm.so.*),
// in order of their file names (not paths: the same install reached through
// /lib or /usr/lib hashes alike).
std::vector<CodeObject> CodeObjects();

// OpenCV's line of the CPU's instruction sets and which of them its kernels
// dispatch to (cv::getCPUFeaturesLine: "SSE SSE2 *SSE4.1 ... *AVX2", with
// "?" after those OPENCV_CPU_DISABLE turns off).
std::string CpuFeatures();

// XXH3-128 of each of CodeObjects() (its build ID as the text "build-id:"
// + hex; for one without, its file's contents followed by their length) and
// CpuFeatures(), computed once: part of every key, so a rebuilt detector
// (any code change relinks the first object, whose linker-made build ID is a
// hash of its contents: the modules are static libraries), another OpenCV or
// libm, or another CPU's OpenCV kernels never read outputs made by other
// code. The build ID is that of the code loaded, so a file rebuilt while the
// process runs does not speak for it; and nothing is read from disk (the
// `ci` build's libhcpf_cli.so is 166 MB). nullopt when a file that must be
// read cannot be: then no detection is cached.
const std::optional<XXH128_hash_t>& ProgramDigest();
// ProgramDigest's computation, of `objects` (frame_cache_bench times it with
// and without their build IDs).
std::optional<XXH128_hash_t> ComputeProgramDigest(const std::vector<CodeObject>& objects);

// Builds a key: feed every input, then Finish().
class DetectionKey {
 public:
  DetectionKey();
  ~DetectionKey();
  DetectionKey(const DetectionKey&) = delete;
  DetectionKey& operator=(const DetectionKey&) = delete;
  void Add(std::string_view text);
  void Add(uint64_t value);
  void Add(double value);
  void Add(const XXH128_hash_t& digest);
  // 32 hex digits.
  std::string Finish() const;

 private:
  XXH3_state_t* state_;
};

class DetectionCache {
 public:
  // Entries live in `root`/detections/ (root: the frame cache's folder);
  // each written with `label` (DetectionLabel: what `hcpf cache` lists it
  // under; at most kMaxDetectionLabelBytes).
  DetectionCache(const std::filesystem::path& root, std::string label);
  // The output stored under `key`, or nullopt when absent, of another format
  // version or damaged (its checksum does not match): then it is recomputed.
  std::optional<vision::DetectorOutput> Load(const std::string& key) const;
  // Writes atomically (a temporary file renamed); throws hcpf::RunError.
  void Store(const std::string& key, const vision::DetectorOutput& output) const;
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
  std::string label_;
};

}  // namespace hcpf::scenarios::internal
