#include "hcpf/scenarios/cache.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <chrono>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <ctime>
#include <exception>
#include <map>
#include <nlohmann/json.hpp>
#include <set>
#include <string>
#include <string_view>
#include <system_error>

#include "hcpf/core/error.h"
#include "hcpf/core/text_file.h"

namespace hcpf::scenarios {
namespace fs = std::filesystem;
namespace {

// A scene folder's name: renderer::PixelHash, 32 lower-case hex digits.
bool IsSceneName(const std::string& name) {
  return name.size() == 32 && std::all_of(name.begin(), name.end(), [](char c) {
           return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
         });
}

// A file a scene folder holds: NNNNNN.frame and NNNNNN.json
// (renderer::FrameCache), scene.json (NoteScene), or their temporary names
// while being written (".NNNNNN.frame.tmp-<pid>-<n>", WriteTextFile's; before
// it, "NNNNNN.<writer>.frame.tmp").
bool IsSceneFile(const std::string& name) {
  if (name == "renderers.txt") return true;  // FrameCache::NoteRenderer
  if (name == kSceneNoteFile) return true;
  if (const std::string target = TempFileTarget(name); !target.empty()) {
    return IsSceneFile(target);
  }
  if (name.size() < 11 ||
      !std::all_of(name.begin(), name.begin() + 6, [](char c) { return c >= '0' && c <= '9'; })) {
    return false;
  }
  const std::string_view rest = std::string_view(name).substr(6);
  if (rest == ".frame" || rest == ".json") return true;
  return rest.front() == '.' && (rest.ends_with(".frame.tmp") || rest.ends_with(".json.tmp"));
}

// A detector's name as a label holds it: "sks", "sks+prca" (letters,
// digits, '+', '_', '-').
bool IsDetectorName(std::string_view name) {
  return !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '+' || c == '_' || c == '-';
  });
}

// Reads a detector output's head into `entry`: whether it is one of ours (it
// starts with "HCPFDET", then the format version, detection_cache.cc), and
// from format 3 its label (DetectionLabel: the byte count, then the scene's
// folder name and the detector), left "" when it does not read as one.
bool ReadDetectionHead(CacheEntry* entry) {
  const std::string head = ReadFilePrefix(entry->path.string(), 9 + kMaxDetectionLabelBytes);
  if (!head.starts_with("HCPFDET")) return false;
  if (head.size() < 9 || head[7] != '3') return true;
  const std::string_view label = std::string_view(head).substr(9, static_cast<uint8_t>(head[8]));
  const size_t space = label.find(' ');
  if (label.size() != static_cast<uint8_t>(head[8]) || space == std::string_view::npos ||
      !IsSceneName(std::string(label.substr(0, space))) ||
      !IsDetectorName(label.substr(space + 1))) {
    return true;
  }
  entry->scene = std::string(label.substr(0, space));
  entry->detector = std::string(label.substr(space + 1));
  return true;
}

// A frame's file of a scene folder: six digits and `extension` (".frame",
// ".json").
bool IsCachedFrameFile(const std::string& name, std::string_view extension) {
  return name.size() == 6 + extension.size() && name.ends_with(extension) &&
         std::all_of(name.begin(), name.begin() + 6, [](char c) { return c >= '0' && c <= '9'; });
}

// A positive int under `key` of a JSON object, or nullopt.
std::optional<int> PositiveInt(const nlohmann::json& object, const char* key) {
  const auto it = object.find(key);
  if (it == object.end() || !it->is_number_unsigned()) return std::nullopt;
  const uint64_t v = it->get<uint64_t>();
  if (v == 0 || v > INT_MAX) return std::nullopt;
  return static_cast<int>(v);
}

// scene.json's note, or why it cannot be read (`problem`). No file of ours
// is near 64 KiB.
std::optional<SceneNote> ReadSceneNote(const fs::path& path, std::string* problem) {
  std::string text;
  try {
    text = ReadInputFile(path.string(), "a scene note", uint64_t{1} << 16);
  } catch (const std::exception& e) {
    *problem = fmt::format("{} cannot be read ({})", kSceneNoteFile, e.what());
    return std::nullopt;
  }
  const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) {
    *problem = fmt::format("{} is not a JSON object", kSceneNoteFile);
    return std::nullopt;
  }
  SceneNote note;
  const auto scenario = j.find("scenario");
  const auto seed = j.find("seed");
  const std::optional<int> frames = PositiveInt(j, "frames");
  const std::optional<int> width = PositiveInt(j, "width_px");
  const std::optional<int> height = PositiveInt(j, "height_px");
  if (scenario == j.end() || !scenario->is_string() || seed == j.end() ||
      !seed->is_number_unsigned() || !frames || !width || !height) {
    *problem = fmt::format(
        "{} lacks its scenario, seed, frames, width_px or height_px (or one is of another type)",
        kSceneNoteFile);
    return std::nullopt;
  }
  note.scenario = scenario->get<std::string>();
  note.seed = seed->get<uint64_t>();
  note.frames = *frames;
  note.width_px = *width;
  note.height_px = *height;
  return note;
}

// What DescribeScene found, as a line's words: "crossing, seed 7, 240
// frames, 640 x 480", or "scene unknown: <why>; 12 frames, 640 x 480".
std::string SceneText(const SceneDescription& d) {
  const std::string size =
      d.width_px > 0 ? fmt::format(", {} x {}", d.width_px, d.height_px) : std::string();
  if (d.note) {
    // The folder is the world's (renderer::PixelHash), not the frame
    // count's: a longer run of the same world adds frames past the note's.
    const std::string frames =
        d.frames_cached >= d.note->frames
            ? fmt::format("{} frame(s)", d.frames_cached)
            : fmt::format("{} of {} frame(s) cached", d.frames_cached, d.note->frames);
    return fmt::format("{}, seed {}, {}{}", d.note->scenario, d.note->seed, frames, size);
  }
  return fmt::format("scene unknown: {}; {} frame(s) cached{}", d.no_note, d.frames_cached, size);
}

[[noreturn]] void CannotRead(const fs::path& path, const std::error_code& ec) {
  throw RunError(fmt::format("cannot read the cache folder {}: {}", path.string(), ec.message()));
}

}  // namespace

CacheContents ScanCache(const fs::path& root) {
  CacheContents out;
  std::error_code ec;
  if (!fs::is_directory(root, ec)) return out;
  for (fs::directory_iterator it(root, ec), end; !ec && it != end; it.increment(ec)) {
    const fs::directory_entry& e = *it;
    if (!IsSceneName(e.path().filename().string())) continue;
    // A third bad-input audit: any folder with a 32-hex-digit name in any
    // folder given as --cache was pruned. A scene is a real folder holding
    // only frame files; anything else of that name is the user's.
    if (e.is_symlink(ec) || !e.is_directory(ec)) {
      out.foreign.push_back(e.path());
      continue;
    }
    CacheEntry scene{.kind = CacheEntry::Kind::kScene, .path = e.path()};
    scene.last_used = fs::last_write_time(e.path(), ec);
    if (ec) CannotRead(e.path(), ec);
    bool ours = true;
    for (fs::directory_iterator f(e.path(), ec); !ec && f != end; f.increment(ec)) {
      if (f->is_symlink(ec) || !f->is_regular_file(ec) ||
          !IsSceneFile(f->path().filename().string())) {
        ours = false;
        out.foreign.push_back(f->path());
        break;
      }
      scene.bytes += f->file_size(ec);
    }
    if (ec) CannotRead(e.path(), ec);
    if (!ours) continue;
    out.scene_bytes += scene.bytes;
    ++out.scenes;
    out.entries.push_back(std::move(scene));
  }
  if (ec) CannotRead(root, ec);
  const fs::path detections = root / "detections";
  if (fs::is_directory(detections, ec)) {
    for (fs::directory_iterator it(detections, ec), end; !ec && it != end; it.increment(ec)) {
      if (it->path().extension() != ".det") continue;
      CacheEntry d{.kind = CacheEntry::Kind::kDetection, .path = it->path()};
      if (it->is_symlink(ec) || !it->is_regular_file(ec) || !ReadDetectionHead(&d)) {
        out.foreign.push_back(it->path());
        continue;
      }
      d.bytes = it->file_size(ec);
      if (!ec) d.last_used = it->last_write_time(ec);
      if (ec) CannotRead(it->path(), ec);
      out.detection_bytes += d.bytes;
      ++out.detections;
      out.entries.push_back(std::move(d));
    }
    if (ec) CannotRead(detections, ec);
  }
  std::sort(out.entries.begin(), out.entries.end(), [](const CacheEntry& a, const CacheEntry& b) {
    return a.last_used != b.last_used ? a.last_used < b.last_used : a.path < b.path;
  });
  return out;
}

std::vector<CacheEntry> PruneOrder(const CacheContents& contents, uint64_t max_bytes,
                                   std::optional<fs::file_time_type> spare_from) {
  std::vector<CacheEntry> out;
  uint64_t kept = contents.bytes();
  for (const CacheEntry& e : contents.entries) {  // least recently used first
    if (kept <= max_bytes || (spare_from && e.last_used >= *spare_from)) break;
    out.push_back(e);
    kept -= e.bytes;
  }
  return out;
}

void RemoveCacheEntries(const std::vector<CacheEntry>& entries) {
  for (const CacheEntry& e : entries) {
    std::error_code ec;
    fs::remove_all(e.path, ec);
    if (ec) {
      throw RunError(
          fmt::format("cannot remove the cache entry {}: {}", e.path.string(), ec.message()));
    }
  }
}

std::optional<uint64_t> CacheMaxSizeFromEnvironment() {
  const char* text = std::getenv(kCacheMaxSizeVariable);
  if (text == nullptr) return kDefaultCacheMaxBytes;
  if (*text == '\0' || std::string_view(text) == "off") return std::nullopt;
  try {
    return ParseSize(text, kCacheMaxSizeVariable);
  } catch (const InputError& e) {
    throw InputError(SourceLocation{.file = "environment", .key = kCacheMaxSizeVariable},
                     e.expected(), e.found(),
                     fmt::format("the most the frame cache may hold after each hcpf run, render "
                                 "or sweep (unset: {}); off keeps everything",
                                 kDefaultCacheMaxText));
  }
}

std::string CacheMaxSizeText() {
  const char* text = std::getenv(kCacheMaxSizeVariable);
  if (text == nullptr) {
    return fmt::format("{} (the default: the variable is unset)", kDefaultCacheMaxText);
  }
  return text;
}

AutoPrune PruneAfterCommand(const fs::path& root, uint64_t max_bytes, fs::file_time_type since) {
  const CacheContents contents = ScanCache(root);
  AutoPrune out;
  out.left = contents.bytes();
  if (!contents.foreign.empty()) {
    out.foreign = contents.foreign.front();
    return out;
  }
  const std::vector<CacheEntry> remove = PruneOrder(contents, max_bytes, since);
  for (const CacheEntry& e : remove) {
    out.left -= e.bytes;
    out.freed += e.bytes;
    (e.kind == CacheEntry::Kind::kScene ? out.scenes : out.detections) += 1;
  }
  RemoveCacheEntries(remove);
  return out;
}

std::string DescribeAutoPrune(const fs::path& root, const AutoPrune& result, uint64_t max_bytes,
                              const std::string& max_text) {
  const std::string limit = fmt::format("{} {}", kCacheMaxSizeVariable, max_text);
  if (!result.foreign.empty()) {
    return fmt::format(
        "frame cache {}: not pruned to {}: it holds {}, which is not a cache entry (hcpf cache "
        "--cache {} says more)",
        root.string(), limit, result.foreign.string(), root.string());
  }
  const std::string removed =
      result.scenes + result.detections == 0
          ? std::string("nothing removed")
          : fmt::format("removed {} scene(s) and {} detector output(s) used least recently, {}",
                        result.scenes, result.detections, FormatSize(result.freed));
  if (result.left <= max_bytes) {
    return fmt::format("frame cache {}: {}; {} left ({})", root.string(), removed,
                       FormatSize(result.left), limit);
  }
  return fmt::format(
      "frame cache {}: {}; {} left, over {}: the rest was used since this command started, by it "
      "or by a command beside it, and stays",
      root.string(), removed, FormatSize(result.left), limit);
}

void MarkUsed(const fs::path& path) {
  std::error_code ec;
  fs::last_write_time(path, fs::file_time_type::clock::now(), ec);
}

uint64_t ParseSize(std::string_view text, std::string_view option) {
  const auto refuse = [&](const std::string& expected, const std::string& found) -> uint64_t {
    throw InputError(SourceLocation{.file = "command line", .key = std::string(option)}, expected,
                     found);
  };
  const std::string quoted = fmt::format("\"{}\"", text);
  const auto fail = [&] {
    return refuse(
        "a size: bytes (1048576) or a number with K, M, G or T (powers of 1024: 500M, 1.5G)",
        quoted);
  };
  std::string s(text);
  if (s.empty()) return fail();
  double unit = 1.0;
  const char last = static_cast<char>(std::toupper(static_cast<unsigned char>(s.back())));
  const std::string units = "KMGT";
  if (const size_t at = units.find(last); at != std::string::npos) {
    unit = std::pow(1024.0, static_cast<double>(at + 1));
    s.pop_back();
  }
  if (s.empty() ||
      !std::all_of(s.begin(), s.end(), [](char c) { return (c >= '0' && c <= '9') || c == '.'; }) ||
      std::count(s.begin(), s.end(), '.') > 1 || s == ".") {
    return fail();
  }
  // from_chars, not stod: a number too long for a double threw out_of_range
  // (a third bad-input audit: exit 1, "cache failed: stod").
  double number = 0.0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), number);
  if (ec != std::errc() || ptr != s.data() + s.size()) return fail();
  const double value = number * unit;
  // Within llround's range, and said so (an audit: 8388607T was refused as
  // if it were no size).
  constexpr double kLargest = 8.0e6 * 1024.0 * 1024.0 * 1024.0 * 1024.0;
  if (!std::isfinite(value) || value > kLargest) return refuse("a size up to 8000000T", quoted);
  // Whole bytes: a byte count with a fraction (1.5), or a size that rounds
  // to no byte but is not 0 (0.0001K), is no size (an audit: they were
  // rounded to 2 and 0 without a word). A fraction of K, M, G or T is kept
  // to the nearest byte (1.5G).
  const double bytes = std::round(value);
  if ((unit == 1.0 && bytes != value) || (bytes == 0.0 && value > 0.0)) {
    return refuse("a size of whole bytes (a fraction only with K, M, G or T: 1.5G)",
                  fmt::format("{}, {} bytes", quoted, value));
  }
  return static_cast<uint64_t>(bytes);
}

std::string FormatSize(uint64_t bytes) {
  static const char* const kUnits[] = {"B", "KiB", "MiB", "GiB", "TiB"};
  double v = static_cast<double>(bytes);
  int u = 0;
  while (v >= 1024.0 && u < 4) {
    v /= 1024.0;
    ++u;
  }
  return u == 0 ? fmt::format("{} B", bytes) : fmt::format("{:.1f} {}", v, kUnits[u]);
}

std::string FormatLastUsed(fs::file_time_type time) {
  const std::time_t seconds = std::chrono::system_clock::to_time_t(
      std::chrono::time_point_cast<std::chrono::system_clock::duration>(
          std::chrono::file_clock::to_sys(time)));
  std::tm utc{};
  gmtime_r(&seconds, &utc);
  return fmt::format("{:04}-{:02}-{:02} {:02}:{:02}", utc.tm_year + 1900, utc.tm_mon + 1,
                     utc.tm_mday, utc.tm_hour, utc.tm_min);
}

void NoteScene(const fs::path& folder, const SceneNote& note) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec) || fs::exists(folder / kSceneNoteFile, ec) || ec) return;
  const nlohmann::json j = {{"scenario", note.scenario},
                            {"seed", note.seed},
                            {"frames", note.frames},
                            {"width_px", note.width_px},
                            {"height_px", note.height_px}};
  try {
    WriteTextFile((folder / kSceneNoteFile).string(), j.dump() + "\n");
  } catch (const RunError&) {
    // Only a description: the frames are cached without it.
  }
}

SceneDescription DescribeScene(const fs::path& folder) {
  SceneDescription out;
  std::string first_truth;  // the first frame's NNNNNN.json
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    if (IsCachedFrameFile(name, ".frame")) ++out.frames_cached;
    if (IsCachedFrameFile(name, ".json") && (first_truth.empty() || name < first_truth)) {
      first_truth = name;
    }
  }
  if (!fs::exists(folder / kSceneNoteFile, ec)) {
    out.no_note = fmt::format("no {} (cached before hcpf noted its scenes)", kSceneNoteFile);
  } else {
    out.note = ReadSceneNote(folder / kSceneNoteFile, &out.no_note);
  }
  if (out.note) {
    out.width_px = out.note->width_px;
    out.height_px = out.note->height_px;
  } else if (!first_truth.empty()) {
    // The camera of the frame's truth (core/ground_truth_json.h's encoding).
    try {
      const nlohmann::json truth = nlohmann::json::parse(
          ReadInputFile((folder / first_truth).string(), "a cached frame's truth", 1 << 26),
          nullptr, false);
      if (truth.is_object() && truth.contains("camera") && truth["camera"].is_object()) {
        const std::optional<int> width = PositiveInt(truth["camera"], "width_px");
        const std::optional<int> height = PositiveInt(truth["camera"], "height_px");
        if (width && height) {
          out.width_px = *width;
          out.height_px = *height;
        }
      }
    } catch (const std::exception&) {
      // The size stays unknown (0): the line says none.
    }
  }
  return out;
}

std::string DetectionLabel(std::string_view scene, std::string_view detector) {
  return fmt::format("{} {}", scene, detector);
}

std::vector<std::string> ListCacheEntries(const std::vector<CacheEntry>& entries, bool verbose,
                                          std::string_view indent) {
  std::vector<std::string> lines;
  // The detector outputs by scene ("" for those without a label), each in
  // the entries' order (least recently used first).
  std::map<std::string, std::vector<const CacheEntry*>> by_scene;
  std::set<std::string> scenes_listed;
  for (const CacheEntry& e : entries) {
    if (e.kind == CacheEntry::Kind::kDetection) {
      by_scene[e.scene].push_back(&e);
    } else {
      scenes_listed.insert(e.path.filename().string());
    }
  }
  const auto used = [](const std::vector<const CacheEntry*>& list) {
    const auto [first, last] = std::minmax_element(
        list.begin(), list.end(),
        [](const CacheEntry* a, const CacheEntry* b) { return a->last_used < b->last_used; });
    return std::pair((*first)->last_used, (*last)->last_used);
  };
  const auto size_of = [](const std::vector<const CacheEntry*>& list) {
    uint64_t bytes = 0;
    for (const CacheEntry* d : list) bytes += d->bytes;
    return bytes;
  };
  // "sks 30 (612.0 KiB), ncc 30 (600.0 KiB)": each detector's outputs, in
  // the order of their first (least recent) entry.
  const auto detectors = [&](const std::vector<const CacheEntry*>& list) {
    std::vector<std::pair<std::string, std::pair<int, uint64_t>>> counts;
    for (const CacheEntry* d : list) {
      auto it = std::find_if(counts.begin(), counts.end(),
                             [&](const auto& c) { return c.first == d->detector; });
      if (it == counts.end()) it = counts.insert(counts.end(), {d->detector, {0, 0}});
      ++it->second.first;
      it->second.second += d->bytes;
    }
    std::string text;
    for (const auto& [name, count] : counts) {
      text += fmt::format("{}{} {} ({})", text.empty() ? "" : ", ", name, count.first,
                          FormatSize(count.second));
    }
    return text;
  };
  const auto each_output = [&](const std::vector<const CacheEntry*>& list) {
    if (!verbose) return;
    for (const CacheEntry* d : list) {
      lines.push_back(fmt::format("{}    {}  {:>10}  detections/{}{}", indent,
                                  FormatLastUsed(d->last_used), FormatSize(d->bytes),
                                  d->path.filename().string(),
                                  d->detector.empty() ? "" : "  " + d->detector));
    }
  };
  for (const CacheEntry& e : entries) {
    if (e.kind == CacheEntry::Kind::kDetection) continue;
    lines.push_back(fmt::format("{}{}  {:>10}  {}  {}", indent, FormatLastUsed(e.last_used),
                                FormatSize(e.bytes), SceneText(DescribeScene(e.path)),
                                e.path.filename().string()));
    const auto outputs = by_scene.find(e.path.filename().string());
    if (outputs == by_scene.end()) continue;
    lines.push_back(fmt::format("{}  and its detector outputs: {}; last used {}", indent,
                                detectors(outputs->second),
                                FormatLastUsed(used(outputs->second).second)));
    each_output(outputs->second);
  }
  // Outputs of scenes not listed: the folder beside them, or none.
  for (const auto& [scene, list] : by_scene) {
    if (scene.empty() || scenes_listed.contains(scene)) continue;
    const fs::path folder = list.front()->path.parent_path().parent_path() / scene;
    std::error_code ec;
    const std::string what = fs::is_directory(folder, ec)
                                 ? SceneText(DescribeScene(folder)) + ", its frames kept"
                                 : std::string("its frames no longer cached");
    const auto [first, last] = used(list);
    lines.push_back(
        fmt::format("{}{} detector output(s), {}, used from {} to {}, of scene {} ({}): {}", indent,
                    list.size(), FormatSize(size_of(list)), FormatLastUsed(first),
                    FormatLastUsed(last), scene, what, detectors(list)));
    each_output(list);
  }
  if (const auto unlabelled = by_scene.find(""); unlabelled != by_scene.end()) {
    const auto [first, last] = used(unlabelled->second);
    lines.push_back(fmt::format(
        "{}{} detector output(s), {}, used from {} to {}, of no known scene (written by an hcpf "
        "before 2026-12-06, which did not record the scene)",
        indent, unlabelled->second.size(), FormatSize(size_of(unlabelled->second)),
        FormatLastUsed(first), FormatLastUsed(last)));
    each_output(unlabelled->second);
  }
  return lines;
}

}  // namespace hcpf::scenarios
