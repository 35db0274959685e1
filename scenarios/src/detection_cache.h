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

// The files of the code that detects, in the order ProgramDigest hashes
// them: first the loaded object that holds the detection code (this
// module's): the running executable when it is linked in (the tests;
// "/proc/self/exe"), or the shared library that holds it (the `hcpf`
// launcher loads libhcpf_cli.so, which links every module); then every
// loaded OpenCV library (libopencv_*) and the C maths library (libm.so.*),
// in order of their file names (not paths: the same install reached through
// /lib or /usr/lib hashes alike).
std::vector<std::string> CodeFiles();

// OpenCV's line of the CPU's instruction sets and which of them its kernels
// dispatch to (cv::getCPUFeaturesLine: "SSE SSE2 *SSE4.1 ... *AVX2", with
// "?" after those OPENCV_CPU_DISABLE turns off).
std::string CpuFeatures();

// XXH3-128 of the contents of CodeFiles() (each followed by its length) and
// CpuFeatures(), computed once: part of every key, so a rebuilt detector
// (any code change relinks the first file: the modules are static
// libraries), another OpenCV or libm, or another CPU's OpenCV kernels never
// read outputs made by other code. nullopt when a file cannot be read: then
// no detection is cached.
const std::optional<XXH128_hash_t>& ProgramDigest();

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
