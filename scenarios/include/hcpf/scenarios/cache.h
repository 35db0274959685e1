#pragma once
// What the on-disk caches hold, and pruning them to a size (`hcpf cache`).
// The cache folder (DefaultFrameCacheDir(), or --cache) holds one folder of
// rendered frames per scene, named by its 32-hex-digit pixel hash
// (renderer::FrameCache), and detections/*.det, one detector output per
// frame and detector setting (the detection cache, docs/vision.md; each
// labelled with its scene's folder name and its detector). Both
// only grow: every rebuild of the detectors keys new entries, and every
// scene or seed renders a new folder. Each use marks its entry (MarkUsed:
// the file's or folder's modification time), so that pruning removes what
// was used least recently. Nothing else in the folder is ever touched.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace hcpf::scenarios {

struct CacheEntry {
  enum class Kind { kScene, kDetection };
  Kind kind = Kind::kScene;
  std::filesystem::path path;  // a scene's folder or a .det file
  uint64_t bytes = 0;          // a scene: every file in its folder
  std::filesystem::file_time_type last_used;
  // A detector output's label (DetectionLabel): the folder name of the scene
  // whose frame it was detected in, and the detector; both "" when the file
  // has none (written by an hcpf before labels, 2026-12-06) or it does not
  // read as one.
  std::string scene;
  std::string detector;
};

// The label a detector output is stored with (the detection cache's format
// 3, docs/vision.md): the name of its scene's frame folder (the scene's
// renderer::PixelHash, 32 hex digits: the folder exists while the frames
// are cached) and the detector's name (`observation.detector`, "sks+prca"
// when fused), joined by a space. At most kMaxDetectionLabelBytes.
inline constexpr size_t kMaxDetectionLabelBytes = 255;
std::string DetectionLabel(std::string_view scene, std::string_view detector);

struct CacheContents {
  std::vector<CacheEntry> entries;  // least recently used first (ties by path)
  uint64_t scene_bytes = 0;
  uint64_t detection_bytes = 0;
  int scenes = 0;
  int detections = 0;
  uint64_t bytes() const { return scene_bytes + detection_bytes; }
  // What has a cache entry's name but not its content: a 32-hex-digit name
  // that is a link, a file, or a folder holding anything but frame files,
  // renderers.txt and scene.json (the first such file is listed), a
  // detections/*.det that is not ours.
  // Never counted, never removed; pruning a folder holding any is refused.
  std::vector<std::filesystem::path> foreign;
};

// The scene folders (32 hex digits) and detection entries (detections/*.det)
// under `root`; an absent root holds nothing. Throws hcpf::RunError when a
// folder cannot be read.
CacheContents ScanCache(const std::filesystem::path& root);

// The entries to remove, least recently used first, so that what stays is
// at most `max_bytes`: a prefix of contents.entries. With `spare_from`, the
// prefix stops at the first entry used at or after it (what stays may then
// be over `max_bytes`).
std::vector<CacheEntry> PruneOrder(const CacheContents& contents, uint64_t max_bytes,
                                   std::optional<std::filesystem::file_time_type> spare_from = {});

// Removes `entries` (a scene's folder with its files); throws hcpf::RunError
// naming the first that cannot be removed.
void RemoveCacheEntries(const std::vector<CacheEntry>& entries);

// The environment variable that bounds the cache after each command that
// uses it (hcpf run, render, sweep): a size as ParseSize reads it.
inline constexpr const char* kCacheMaxSizeVariable = "HCPF_CACHE_MAX_SIZE";

// The limit when the variable is unset: a cache of every frame of every
// scene rendered grows without end otherwise (a rendered 640 x 480 frame is
// ~0.45 MB; 20 GiB holds ~45,000 of them).
inline constexpr uint64_t kDefaultCacheMaxBytes = 20ull << 30;
inline constexpr const char* kDefaultCacheMaxText = "20G";

// $HCPF_CACHE_MAX_SIZE as bytes: unset, kDefaultCacheMaxBytes; `off` (or
// empty): nullopt, no limit. Throws hcpf::InputError naming the variable,
// what is expected and what was found.
std::optional<uint64_t> CacheMaxSizeFromEnvironment();
// The limit as messages say it, after the variable's name: the variable's
// value ("8G"), or "20G (the default: the variable is unset)".
std::string CacheMaxSizeText();

// What PruneAfterCommand did.
struct AutoPrune {
  int scenes = 0;      // scene folders removed
  int detections = 0;  // detector outputs removed
  uint64_t freed = 0;
  uint64_t left = 0;  // bytes the cache holds after
  // Nothing was removed because the folder holds what is not the cache's
  // (CacheContents::foreign): its first such path, else empty.
  std::filesystem::path foreign;
};

// After a command that used the cache at `root`: removes the entries used
// least recently until the rest is at most `max_bytes` (PruneOrder), but
// never one used at or after `since` (the command's start): what the command
// used, and what commands running beside it use, stays, so the cache may be
// left over `max_bytes` (AutoPrune::left says). Nothing is removed from a
// folder holding foreign entries. Throws hcpf::RunError when an entry cannot
// be removed or the folder cannot be read.
AutoPrune PruneAfterCommand(const std::filesystem::path& root, uint64_t max_bytes,
                            std::filesystem::file_time_type since);

// A line for the log: what PruneAfterCommand removed and left, naming the
// variable and its value (`max_text`, as written), and why what is left is
// over the limit when it is (used since the command started; foreign
// entries).
std::string DescribeAutoPrune(const std::filesystem::path& root, const AutoPrune& result,
                              uint64_t max_bytes, const std::string& max_text);

// Marks a cache entry used now (its modification time); errors are ignored:
// a read-only cache is still a cache.
void MarkUsed(const std::filesystem::path& path);

// A size as written on the command line: bytes ("1048576") or a number with
// the suffix K, M, G or T (powers of 1024, "500M", "1.5G"). Throws
// hcpf::InputError naming `option`, what is expected and what was found.
uint64_t ParseSize(std::string_view text, std::string_view option);

// "1.4 GiB", "512 KiB", "300 B".
std::string FormatSize(uint64_t bytes);

// "2026-12-05 14:02": an entry's last use, UTC, to the minute (the order of
// use shows within a day).
std::string FormatLastUsed(std::filesystem::file_time_type time);

// What a scene folder's name (a hash of everything that shapes its pixels)
// does not say: the scenario and seed of the run that first rendered into it,
// its frames and their size. Kept in the folder as scene.json
// ({"scenario": "crossing", "seed": 7, "frames": 240, "width_px": 640,
// "height_px": 480}) for `hcpf cache` to list.
struct SceneNote {
  std::string scenario;
  uint64_t seed = 0;
  int frames = 0;
  int width_px = 0, height_px = 0;
};
inline constexpr const char* kSceneNoteFile = "scene.json";

// Writes `folder`/scene.json when the folder exists and has none (the first
// run's note stays; a folder cached before notes were kept gains one when a
// run opens it). Errors are ignored: the note only describes, and a
// read-only cache is still a cache.
void NoteScene(const std::filesystem::path& folder, const SceneNote& note);

// What `hcpf cache` says of a scene folder: its note, when it can be read
// (else why not), and what the folder itself shows.
struct SceneDescription {
  std::optional<SceneNote> note;
  std::string no_note;    // why there is no note ("no scene.json: ..."), else ""
  int frames_cached = 0;  // its NNNNNN.frame files
  // The note's; without one, the camera of the first frame's truth
  // (NNNNNN.json); 0 when neither can be read.
  int width_px = 0, height_px = 0;
};
SceneDescription DescribeScene(const std::filesystem::path& folder);

// The lines `hcpf cache` lists `entries` with (a CacheContents' or
// PruneOrder's, least recently used first), each starting with `indent`: one
// per scene, in that order (most recently used last): when it was last used,
// its size, what it is (DescribeScene) and its folder's name, followed by a
// line of the detector outputs of that scene among `entries`, if any (each
// detector's count and size, the last use); then a line per scene whose
// outputs are among `entries` but not the scene (its folder removed, or not
// being pruned: what the folder holds, or that it is gone); then one line
// for the outputs without a label (how many, their size, when first and last
// used). With `verbose`, after each of those lines one more per detector
// output (its file, detector, size and last use).
std::vector<std::string> ListCacheEntries(const std::vector<CacheEntry>& entries, bool verbose,
                                          std::string_view indent);

}  // namespace hcpf::scenarios
