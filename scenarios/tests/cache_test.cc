// hcpf/scenarios/cache.h: scanning a cache folder, the order of pruning,
// sizes on the command line. The folder is built by hand: its sizes and
// times are the test's, not the code's.

#include "hcpf/scenarios/cache.h"

#include <dlfcn.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <opencv2/imgproc.hpp>
#include <optional>
#include <string>
#include <vector>

#include "detection_cache.h"
#include "hcpf/core/error.h"
#include "support/process.h"

namespace hcpf::scenarios {
namespace {

namespace fs = std::filesystem;
using std::chrono::hours;

fs::path FreshCacheDir(const std::string& name) { return hcpf::testing::FreshDir("cache-" + name); }

void WriteBytes(const fs::path& path, size_t n) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << std::string(n, 'x');
}

// A detector output as the detection cache starts one: "HCPFDET" and its
// format version, then (here) filler to n bytes.
void WriteDetection(const fs::path& path, size_t n) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << "HCPFDET2" << std::string(n - 8, 'x');
}

// One of format 3, labelled (DetectionLabel) with `scene` and `detector`,
// padded to `n` bytes.
void WriteLabelledDetection(const fs::path& path, const std::string& scene,
                            const std::string& detector, size_t n) {
  fs::create_directories(path.parent_path());
  const std::string label = DetectionLabel(scene, detector);
  const std::string head = "HCPFDET3" + std::string(1, static_cast<char>(label.size())) + label;
  std::ofstream(path, std::ios::binary) << head << std::string(n - head.size(), 'x');
}

// Two scenes (a: 300 + 100 bytes, used 30 h ago; b: 500 bytes, 10 h ago),
// three detector outputs (d1 50 bytes 40 h ago, d2 70 bytes 20 h ago, d3 80
// bytes now) and what the cache never touches: a folder whose name is not a
// scene hash, a file at the top, a detections/ file that is not .det.
struct HandCache {
  fs::path root;
  fs::path a, b, d1, d2, d3;
};

HandCache MakeHandCache(const std::string& name) {
  HandCache c;
  c.root = FreshCacheDir(name);
  const auto now = fs::file_time_type::clock::now();
  c.a = c.root / "0123456789abcdef0123456789abcdef";
  c.b = c.root / "fedcba9876543210fedcba9876543210";
  WriteBytes(c.a / "000000.frame", 300);
  WriteBytes(c.a / "000000.json", 100);
  WriteBytes(c.b / "000000.frame", 500);
  fs::last_write_time(c.a, now - hours(30));
  fs::last_write_time(c.b, now - hours(10));
  c.d1 = c.root / "detections" / "k1.det";
  c.d2 = c.root / "detections" / "k2.det";
  c.d3 = c.root / "detections" / "k3.det";
  WriteDetection(c.d1, 50);
  WriteDetection(c.d2, 70);
  WriteDetection(c.d3, 80);
  fs::last_write_time(c.d1, now - hours(40));
  fs::last_write_time(c.d2, now - hours(20));
  WriteBytes(c.root / "not-a-scene" / "000000.frame", 1000);
  WriteBytes(c.root / "notes.txt", 1000);
  WriteBytes(c.root / "detections" / "k4.det.tmp", 1000);
  return c;
}

TEST(Cache, ScanCountsScenesAndDetectionsLeastRecentlyUsedFirst) {
  const HandCache c = MakeHandCache("scan");
  const CacheContents contents = ScanCache(c.root);
  EXPECT_EQ(contents.scenes, 2);
  EXPECT_EQ(contents.detections, 3);
  EXPECT_EQ(contents.scene_bytes, 900u);
  EXPECT_EQ(contents.detection_bytes, 200u);
  EXPECT_EQ(contents.bytes(), 1100u);
  ASSERT_EQ(contents.entries.size(), 5u);
  const std::vector<fs::path> order = {c.d1, c.a, c.d2, c.b, c.d3};
  for (size_t i = 0; i < order.size(); ++i) EXPECT_EQ(contents.entries[i].path, order[i]) << i;
  EXPECT_EQ(contents.entries[1].kind, CacheEntry::Kind::kScene);
  EXPECT_EQ(contents.entries[1].bytes, 400u);
  // An absent folder holds nothing.
  EXPECT_EQ(ScanCache(c.root / "absent").entries.size(), 0u);
}

// 1100 bytes; to keep at most 600: d1 (50) leaves 1050, a (400) 650, d2
// (70) 580. At most 1100: nothing. At most 0: everything.
TEST(Cache, PruneRemovesTheLeastRecentlyUsedUntilTheRestFits) {
  const HandCache c = MakeHandCache("prune");
  const CacheContents contents = ScanCache(c.root);
  const std::vector<CacheEntry> remove = PruneOrder(contents, 600);
  ASSERT_EQ(remove.size(), 3u);
  EXPECT_EQ(remove[0].path, c.d1);
  EXPECT_EQ(remove[1].path, c.a);
  EXPECT_EQ(remove[2].path, c.d2);
  EXPECT_TRUE(PruneOrder(contents, 1100).empty());
  EXPECT_EQ(PruneOrder(contents, 0).size(), 5u);

  RemoveCacheEntries(remove);
  EXPECT_FALSE(fs::exists(c.a));
  EXPECT_FALSE(fs::exists(c.d1));
  EXPECT_FALSE(fs::exists(c.d2));
  EXPECT_TRUE(fs::exists(c.b / "000000.frame"));
  EXPECT_TRUE(fs::exists(c.d3));
  // What is not a cache entry stays.
  EXPECT_TRUE(fs::exists(c.root / "not-a-scene" / "000000.frame"));
  EXPECT_TRUE(fs::exists(c.root / "notes.txt"));
  EXPECT_TRUE(fs::exists(c.root / "detections" / "k4.det.tmp"));
  EXPECT_EQ(ScanCache(c.root).bytes(), 580u);
}

// What has an entry's name without its content is the user's, not the
// cache's (a third bad-input audit: every 32-hex-digit folder of any folder
// given as --cache was pruned): a folder holding another file, a link to a
// folder, a file of that name, a .det that is not a detector output of
// ours. Listed as foreign, never counted or removed; a scene being written
// (temporary names) is a scene.
TEST(Cache, EntriesWithoutTheCachesContentAreForeign) {
  const HandCache c = MakeHandCache("foreign");
  const fs::path mixed = c.root / "00000000000000000000000000000001";
  WriteBytes(mixed / "000000.frame", 10);
  WriteBytes(mixed / "important.txt", 10);
  const fs::path linked = c.root / "00000000000000000000000000000002";
  fs::create_directory_symlink(c.b, linked);
  const fs::path file = c.root / "00000000000000000000000000000003";
  WriteBytes(file, 10);
  const fs::path other_det = c.root / "detections" / "run.det";
  WriteBytes(other_det, 10);
  // Temporary files of a write (WriteTextFile's names, and those of before
  // it) belong to the scene; a temporary name of a file no scene holds does not.
  WriteBytes(c.b / "000001.4242-77.frame.tmp", 5);
  WriteBytes(c.b / ".000001.frame.tmp-4242-0", 5);
  WriteBytes(c.b / ".000001.json.tmp-4242-1", 5);
  const fs::path odd_temp = c.root / "00000000000000000000000000000004";
  WriteBytes(odd_temp / ".notes.txt.tmp-4242-2", 5);
  const CacheContents contents = ScanCache(c.root);
  EXPECT_EQ(contents.scenes, 2);
  EXPECT_EQ(contents.detections, 3);
  EXPECT_EQ(contents.bytes(), 1115u);
  std::vector<fs::path> foreign = contents.foreign;
  std::sort(foreign.begin(), foreign.end());
  EXPECT_EQ(foreign, (std::vector<fs::path>{mixed / "important.txt", linked, file,
                                            odd_temp / ".notes.txt.tmp-4242-2", other_det}));
  for (const CacheEntry& e : PruneOrder(contents, 0)) {
    EXPECT_NE(e.path, mixed);
    EXPECT_NE(e.path, linked);
    EXPECT_NE(e.path, other_det);
  }
}

// A use moves an entry to the back of the order.
TEST(Cache, MarkUsedMakesAnEntryTheMostRecent) {
  const HandCache c = MakeHandCache("mark");
  MarkUsed(c.d1);
  MarkUsed(c.a);
  const CacheContents contents = ScanCache(c.root);
  EXPECT_EQ(contents.entries[0].path, c.d2);
  EXPECT_EQ(contents.entries[1].path, c.b);
  MarkUsed(c.root / "absent");  // ignored
}

// $HCPF_CACHE_MAX_SIZE after a command that started 25 h ago, at most 600
// of the 1100 bytes: d1 (50, 40 h ago) and a (400, 30 h ago) go, leaving 650;
// d2 (20 h ago) was used since the command started and stays though the
// rest is over the limit. A command started later removes d2 too (580 left);
// a limit over the contents removes nothing; a folder holding something not
// the cache's is left whole.
TEST(Cache, AfterACommandThePruneSparesWhatWasUsedSinceItStarted) {
  const HandCache c = MakeHandCache("after-command");
  const auto now = fs::file_time_type::clock::now();
  AutoPrune r = PruneAfterCommand(c.root, 600, now - hours(25));
  EXPECT_EQ(r.scenes, 1);
  EXPECT_EQ(r.detections, 1);
  EXPECT_EQ(r.freed, 450u);
  EXPECT_EQ(r.left, 650u);
  EXPECT_TRUE(r.foreign.empty());
  EXPECT_FALSE(fs::exists(c.a));
  EXPECT_FALSE(fs::exists(c.d1));
  EXPECT_TRUE(fs::exists(c.d2));
  EXPECT_EQ(DescribeAutoPrune(c.root, r, 600, "600"),
            "frame cache " + c.root.string() +
                ": removed 1 scene(s) and 1 detector output(s) used least recently, 450 B; 650 B "
                "left, over HCPF_CACHE_MAX_SIZE 600: the rest was used since this command "
                "started, by it or by a command beside it, and stays");
  r = PruneAfterCommand(c.root, 600, now + hours(1));
  EXPECT_EQ(r.detections, 1);
  EXPECT_EQ(r.left, 580u);
  EXPECT_FALSE(fs::exists(c.d2));
  EXPECT_TRUE(fs::exists(c.b / "000000.frame"));
  EXPECT_EQ(DescribeAutoPrune(c.root, r, 600, "600"),
            "frame cache " + c.root.string() +
                ": removed 0 scene(s) and 1 detector output(s) used least recently, 70 B; 580 B "
                "left (HCPF_CACHE_MAX_SIZE 600)");
  r = PruneAfterCommand(c.root, 2000, now + hours(1));
  EXPECT_EQ(r.scenes + r.detections, 0);
  EXPECT_EQ(DescribeAutoPrune(c.root, r, 2000, "2K"),
            "frame cache " + c.root.string() +
                ": nothing removed; 580 B left (HCPF_CACHE_MAX_SIZE "
                "2K)");
  const fs::path mixed = c.root / "00000000000000000000000000000001";
  WriteBytes(mixed / "000000.frame", 10);
  WriteBytes(mixed / "important.txt", 10);
  r = PruneAfterCommand(c.root, 0, now + hours(1));
  EXPECT_EQ(r.foreign, mixed / "important.txt");
  EXPECT_EQ(r.scenes + r.detections, 0);
  EXPECT_TRUE(fs::exists(c.b / "000000.frame"));
  EXPECT_NE(DescribeAutoPrune(c.root, r, 0, "0")
                .find("not pruned to HCPF_CACHE_MAX_SIZE 0: it holds " +
                      (mixed / "important.txt").string()),
            std::string::npos);
}

// A file time at minute `minute` and 30 s of an hour of a day, UTC.
fs::file_time_type UtcTime(int year, unsigned month, unsigned day, int hour, int minute) {
  using namespace std::chrono;
  return file_clock::from_sys(sys_days{std::chrono::year{year} / month / day} + hours(hour) +
                              minutes(minute) + seconds(30));
}

// `text` padded with spaces (which JSON reads past) to `n` bytes.
void WritePadded(const fs::path& path, const std::string& text, size_t n) {
  fs::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text << std::string(n - text.size(), ' ');
}

// `hcpf cache` lists a scene a line, by what its scene.json says, the
// time of its last use to the minute (an audit: 1,440 detector outputs were
// listed a line each, then scenes named only by their hash, all with one
// date); the detector outputs under their scene. Three scenes, least
// recently used first: c (a scene.json that is not JSON, 100 + 1 bytes), a
// (noted: crossing, seed 7, 2 of 240 frames cached; 2 x 1000 + 2 x 100 +
// 200 bytes), b (cached before notes: its size from its frame's truth; 500
// + 300 bytes); two unlabelled detector outputs (50 and 70 bytes) used on
// the 1st and the 3rd, and five labelled ones.
TEST(Cache, ListsEachSceneByItsNoteAndItsDetectorOutputs) {
  const fs::path root = FreshCacheDir("list");
  const fs::path a = root / "0123456789abcdef0123456789abcdef";
  const fs::path b = root / "fedcba9876543210fedcba9876543210";
  const fs::path c = root / "00000000000000000000000000000001";
  WriteBytes(a / "000000.frame", 1000);
  WriteBytes(a / "000001.frame", 1000);
  WriteBytes(a / "000000.json", 100);
  WriteBytes(a / "000001.json", 100);
  WritePadded(a / "scene.json",
              R"({"scenario": "crossing", "seed": 7, "frames": 240, "width_px": 640, )"
              R"("height_px": 480})",
              200);
  WriteBytes(b / "000000.frame", 500);
  WritePadded(b / "000000.json", R"({"frame": 0, "camera": {"width_px": 320, "height_px": 240}})",
              300);
  WriteBytes(c / "000000.frame", 100);
  WritePadded(c / "scene.json", "{", 1);
  const fs::path d1 = root / "detections" / "k1.det";
  const fs::path d2 = root / "detections" / "k2.det";
  WriteDetection(d1, 50);
  WriteDetection(d2, 70);
  // Labelled outputs: two SKS and one fused of scene a, one NCC of a scene
  // whose frames are gone, and one whose label names no scene folder (read
  // as unlabelled).
  const std::string gone = "abcdefabcdefabcdefabcdefabcdefab";
  const fs::path l1 = root / "detections" / "l1.det";
  const fs::path l2 = root / "detections" / "l2.det";
  const fs::path l3 = root / "detections" / "l3.det";
  const fs::path l4 = root / "detections" / "l4.det";
  const fs::path l5 = root / "detections" / "l5.det";
  WriteLabelledDetection(l1, a.filename().string(), "sks", 100);
  WriteLabelledDetection(l2, a.filename().string(), "sks+prca", 200);
  WriteLabelledDetection(l3, a.filename().string(), "sks", 300);
  WriteLabelledDetection(l4, gone, "ncc", 400);
  WriteLabelledDetection(l5, "not-a-scene", "ncc", 80);
  fs::last_write_time(c, UtcTime(2026, 1, 1, 23, 59));
  fs::last_write_time(a, UtcTime(2026, 1, 2, 3, 4));
  fs::last_write_time(b, UtcTime(2026, 1, 2, 5, 6));
  fs::last_write_time(d1, UtcTime(2026, 1, 1, 10, 0));
  fs::last_write_time(d2, UtcTime(2026, 1, 3, 11, 12));
  fs::last_write_time(l1, UtcTime(2026, 1, 2, 3, 0));
  fs::last_write_time(l2, UtcTime(2026, 1, 2, 3, 1));
  fs::last_write_time(l3, UtcTime(2026, 1, 2, 3, 5));
  fs::last_write_time(l4, UtcTime(2026, 1, 1, 9, 0));
  fs::last_write_time(l5, UtcTime(2026, 1, 1, 9, 30));

  const CacheContents contents = ScanCache(root);
  EXPECT_TRUE(contents.foreign.empty()) << "scene.json is a scene's file";
  EXPECT_EQ(contents.scenes, 3);
  const std::vector<std::string> lines = ListCacheEntries(contents.entries, false, "  ");
  // Each labelled output under its scene, by detector; those of a scene
  // whose frames are gone a line of their own; the unlabelled together (an
  // audit: every output was one line apart from the scenes).
  EXPECT_EQ(lines,
            (std::vector<std::string>{
                "  2026-01-01 23:59       101 B  scene unknown: scene.json is not a JSON object; 1 "
                "frame(s) cached  00000000000000000000000000000001",
                "  2026-01-02 03:04     2.3 KiB  crossing, seed 7, 2 of 240 frame(s) cached, 640 x "
                "480  0123456789abcdef0123456789abcdef",
                "    and its detector outputs: sks 2 (400 B), sks+prca 1 (200 B); last used "
                "2026-01-02 03:05",
                "  2026-01-02 05:06       800 B  scene unknown: no scene.json (cached before hcpf "
                "noted its scenes); 1 frame(s) cached, 320 x 240  "
                "fedcba9876543210fedcba9876543210",
                "  1 detector output(s), 400 B, used from 2026-01-01 09:00 to 2026-01-01 09:00, of "
                "scene abcdefabcdefabcdefabcdefabcdefab (its frames no longer cached): ncc 1 (400 "
                "B)",
                "  3 detector output(s), 200 B, used from 2026-01-01 09:30 to 2026-01-03 11:12, of "
                "no known scene (written by an hcpf before 2026-12-06, which did not record the "
                "scene)"}));
  // --verbose: a line per detector output too, after each group's.
  const std::vector<std::string> verbose = ListCacheEntries(contents.entries, true, "  ");
  ASSERT_EQ(verbose.size(), 13u);
  EXPECT_EQ(verbose[3], "      2026-01-02 03:00       100 B  detections/l1.det  sks");
  EXPECT_EQ(verbose[4], "      2026-01-02 03:01       200 B  detections/l2.det  sks+prca");
  EXPECT_EQ(verbose[5], "      2026-01-02 03:05       300 B  detections/l3.det  sks");
  EXPECT_EQ(verbose[10], "      2026-01-01 09:30        80 B  detections/l5.det");
  EXPECT_EQ(verbose[11], "      2026-01-01 10:00        50 B  detections/k1.det");
  EXPECT_EQ(verbose[12], "      2026-01-03 11:12        70 B  detections/k2.det");
  // What PruneOrder returns is listed alike: at most 1800 of the 4501 bytes
  // takes l4, l5, d1, c, l1, l2 and a (l3, a's third output, stays), and
  // a's line lists l1 and l2 alone.
  const std::vector<std::string> pruned = ListCacheEntries(PruneOrder(contents, 1800), false, "");
  EXPECT_EQ(pruned.size(), 5u);
  EXPECT_EQ(pruned[2],
            "  and its detector outputs: sks 1 (100 B), sks+prca 1 (200 B); last used "
            "2026-01-02 03:01");
  EXPECT_EQ(pruned.back(),
            "2 detector output(s), 130 B, used from 2026-01-01 09:30 to 2026-01-01 10:00, of no "
            "known scene (written by an hcpf before 2026-12-06, which did not record the scene)");
  EXPECT_EQ(FormatLastUsed(UtcTime(2026, 12, 5, 14, 2)), "2026-12-05 14:02");
  // The folder is the world's, not the frame count's: a note of 1 frame
  // (the first run's) beside 2 cached frames (a longer run's) says 2.
  const fs::path longer = FreshCacheDir("list-longer");
  const fs::path e = longer / "0123456789abcdef0123456789abcdef";
  WriteBytes(e / "000000.frame", 10);
  WriteBytes(e / "000001.frame", 10);
  WritePadded(e / "scene.json",
              R"({"scenario": "crossing", "seed": 7, "frames": 1, "width_px": 64, )"
              R"("height_px": 48})",
              100);
  const std::vector<std::string> one = ListCacheEntries(ScanCache(longer).entries, false, "");
  ASSERT_EQ(one.size(), 1u);
  EXPECT_NE(one[0].find("crossing, seed 7, 2 frame(s), 64 x 48"), std::string::npos) << one[0];
}

// A run notes its scene in the folder once: the first note stays, and no
// folder is made for it.
TEST(Cache, NoteSceneWritesOnceIntoAnExistingFolder) {
  const fs::path root = FreshCacheDir("note");
  const fs::path scene = root / "0123456789abcdef0123456789abcdef";
  NoteScene(scene,
            {.scenario = "crossing", .seed = 7, .frames = 3, .width_px = 64, .height_px = 48});
  EXPECT_FALSE(fs::exists(scene));
  fs::create_directories(scene);
  NoteScene(scene,
            {.scenario = "crossing", .seed = 7, .frames = 3, .width_px = 64, .height_px = 48});
  NoteScene(scene, {.scenario = "other", .seed = 8, .frames = 3, .width_px = 64, .height_px = 48});
  const SceneDescription d = DescribeScene(scene);
  ASSERT_TRUE(d.note.has_value()) << d.no_note;
  EXPECT_EQ(d.note->scenario, "crossing");
  EXPECT_EQ(d.note->seed, 7u);
  EXPECT_EQ(d.note->frames, 3);
  EXPECT_EQ(d.width_px, 64);
  EXPECT_EQ(d.height_px, 48);
  EXPECT_EQ(d.frames_cached, 0);
}

// The variable: unset or empty is no limit; a size as the command line
// writes it; anything else is bad input naming the variable.
// Unset, the cache is held to 20 GiB (it grew without end: every frame of
// every scene rendered); `off`, or empty, keeps everything.
TEST(Cache, TheLimitComesFromTheEnvironment) {
  ::unsetenv("HCPF_CACHE_MAX_SIZE");
  EXPECT_EQ(CacheMaxSizeFromEnvironment(), std::optional<uint64_t>(20ull << 30));
  EXPECT_EQ(CacheMaxSizeText(), "20G (the default: the variable is unset)");
  ::setenv("HCPF_CACHE_MAX_SIZE", "off", 1);
  EXPECT_EQ(CacheMaxSizeFromEnvironment(), std::nullopt);
  ::setenv("HCPF_CACHE_MAX_SIZE", "", 1);
  EXPECT_EQ(CacheMaxSizeFromEnvironment(), std::nullopt);
  ::setenv("HCPF_CACHE_MAX_SIZE", "1.5G", 1);
  EXPECT_EQ(CacheMaxSizeFromEnvironment(), std::optional<uint64_t>(1536ull << 20));
  EXPECT_EQ(CacheMaxSizeText(), "1.5G");
  ::setenv("HCPF_CACHE_MAX_SIZE", "lots", 1);
  try {
    CacheMaxSizeFromEnvironment();
    ADD_FAILURE() << "accepted \"lots\"";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().file, "environment");
    EXPECT_EQ(e.where().key, "HCPF_CACHE_MAX_SIZE");
    EXPECT_EQ(e.found(), "\"lots\"");
  }
  ::unsetenv("HCPF_CACHE_MAX_SIZE");
}

TEST(Cache, SizesAreBytesOrPowersOf1024) {
  EXPECT_EQ(ParseSize("1048576", "--max-size"), 1048576u);
  EXPECT_EQ(ParseSize("500K", "--max-size"), 500u * 1024u);
  EXPECT_EQ(ParseSize("500m", "--max-size"), 500u * 1024u * 1024u);
  EXPECT_EQ(ParseSize("1.5G", "--max-size"), 1536u * 1024u * 1024u);
  EXPECT_EQ(ParseSize("2T", "--max-size"), 2ull << 40);
  EXPECT_EQ(ParseSize("0", "--max-size"), 0u);
  EXPECT_EQ(ParseSize("0.0K", "--max-size"), 0u);
  EXPECT_EQ(ParseSize("8000000T", "--max-size"), 8000000ull << 40);
  // Above the largest size, and sizes that are no whole bytes, are refused
  // saying so (an audit: the first with the generic message, the others
  // rounded to 2 and 0 bytes).
  const auto found_and_expected = [](const std::string& text) {
    try {
      ParseSize(text, "--max-size");
      return std::string("accepted");
    } catch (const InputError& e) {
      return e.expected() + " / " + e.found();
    }
  };
  EXPECT_EQ(found_and_expected("8000001T"), "a size up to 8000000T / \"8000001T\"");
  EXPECT_EQ(found_and_expected("18446744073709551615"),
            "a size up to 8000000T / \"18446744073709551615\"");
  EXPECT_EQ(found_and_expected("1.5"),
            "a size of whole bytes (a fraction only with K, M, G or T: 1.5G) / \"1.5\", 1.5 bytes");
  EXPECT_EQ(found_and_expected("0.0001K"),
            "a size of whole bytes (a fraction only with K, M, G or T: 1.5G) / \"0.0001K\", "
            "0.1024 bytes");
  // A number too long for a double was exit 1 ("stod", a third bad-input
  // audit).
  const std::string long_number(400, '1');
  const std::string tiny = "0." + std::string(400, '0') + "1";
  for (const std::string& bad :
       {std::string(), std::string("G"), std::string("1.2.3G"), std::string("-5M"),
        std::string("5 M"), std::string("5MB"), std::string("ten"), std::string("."),
        std::string("1e3"), long_number, tiny}) {
    SCOPED_TRACE(bad);
    try {
      ParseSize(bad, "--max-size");
      ADD_FAILURE() << "accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.where().key, "--max-size");
    }
  }
  EXPECT_EQ(FormatSize(300), "300 B");
  EXPECT_EQ(FormatSize(512 * 1024), "512.0 KiB");
  EXPECT_EQ(FormatSize(3u * 1024u * 1024u * 1024u / 2u), "1.5 GiB");
}

// The detection cache's key covers the code that detects: this test
// executable (where the modules are linked in), then the libraries whose
// arithmetic the detectors call, found independently of CodeObjects: the
// files dladdr says hold cv::GaussianBlur and exp; then the CPU's instruction
// sets as OpenCV dispatches to them. The digest is worked out here from each
// object's build ID as readelf reads it from the file (the text "build-id:"
// and the hex, followed by its length), or for one without, the file's bytes
// (each followed by its length), and the CPU line. (Before 2026-12-05 only the
// first file: two OpenCV builds, or two CPUs, sharing a cache could read each
// other's detections. Before 2026-12-07 every file's bytes: 166 MB read by
// each hcpf process of a `ci` build, where the build IDs are in memory.)
TEST(DetectionCacheKey, CoversTheCodeOpenCvTheMathsLibraryAndTheCpu) {
  const std::vector<internal::CodeObject> objects = internal::CodeObjects();
  ASSERT_FALSE(objects.empty());
  EXPECT_EQ(objects.front().path, "/proc/self/exe");
  std::vector<std::string> files;
  for (const internal::CodeObject& o : objects) files.push_back(o.path);
  Dl_info opencv{}, maths{};
  void (*blur)(cv::InputArray, cv::OutputArray, cv::Size, double, double, int) = &cv::GaussianBlur;
  double (*exponential)(double) = &::exp;
  ASSERT_NE(dladdr(reinterpret_cast<void*>(blur), &opencv), 0);
  ASSERT_NE(dladdr(reinterpret_cast<void*>(exponential), &maths), 0);
  EXPECT_NE(std::string(opencv.dli_fname).find("libopencv_imgproc"), std::string::npos)
      << opencv.dli_fname;
  EXPECT_NE(std::find(files.begin(), files.end(), opencv.dli_fname), files.end())
      << opencv.dli_fname;
  EXPECT_NE(std::find(files.begin(), files.end(), maths.dli_fname), files.end()) << maths.dli_fname;
  const std::string cpu = internal::CpuFeatures();
  EXPECT_NE(cpu.find("SSE2"), std::string::npos) << cpu;

  XXH3_state_t* state = XXH3_createState();
  XXH3_128bits_reset(state);
  int with_build_id = 0;
  for (const std::string& file : files) {
    // readelf of /proc/self/exe would read readelf: this executable's path.
    const std::string build_id = hcpf::testing::ReadelfBuildId(
        file == "/proc/self/exe" ? std::filesystem::read_symlink(file).string() : file);
    if (!build_id.empty()) {
      ++with_build_id;
      const std::string text = "build-id:" + build_id;
      const uint64_t length = text.size();
      XXH3_128bits_update(state, text.data(), text.size());
      XXH3_128bits_update(state, &length, sizeof(length));
      continue;
    }
    std::ifstream in(file, std::ios::binary);
    std::string bytes(static_cast<size_t>(std::filesystem::file_size(file)), '\0');
    in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    ASSERT_EQ(in.gcount(), static_cast<std::streamsize>(bytes.size())) << file;
    XXH3_128bits_update(state, bytes.data(), bytes.size());
    const uint64_t length = bytes.size();
    XXH3_128bits_update(state, &length, sizeof(length));
  }
  XXH3_128bits_update(state, cpu.data(), cpu.size());
  const XXH128_hash_t expected = XXH3_128bits_digest(state);
  XXH3_freeState(state);
  // GCC and Debian's libraries are linked with build IDs: none of them read.
  EXPECT_EQ(with_build_id, static_cast<int>(files.size()));
  ASSERT_TRUE(internal::ProgramDigest().has_value());
  EXPECT_TRUE(XXH128_isEqual(*internal::ProgramDigest(), expected));
}

}  // namespace
}  // namespace hcpf::scenarios
