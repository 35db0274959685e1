#pragma once
// MOTChallenge text files: ground truth, tracker output, seqinfo.ini, and the
// preprocessing that turns them into a metrics::Sequence the way TrackEval does.
//
// Formats (comma separated; a line without commas is split on whitespace):
//   ground truth, MOT15   frame,id,x,y,w,h,conf[,wx,wy,wz]   (6, 7 or 10 columns)
//   ground truth, MOT16/17 frame,id,x,y,w,h,consider,class,visibility (9 columns)
//   tracker output        frame,id,x,y,w,h,conf,-1,-1,-1     (6 to 10 columns)
// Boxes are kept exactly as written (1-based MOT pixel coordinates, top-left
// corner); every metric here is translation invariant, and keeping the file's
// numbers reproduces TrackEval bit for bit. Use MotBoxToPx / PxToMotBox to move
// between MOT and hcpf's 0-based BoxPx convention.
//
// Every reader throws hcpf::InputError naming file:line and the column for: a
// non-numeric field, too few or too many columns, a frame outside 1..seq_length,
// an id used twice in one frame, a missing or bad seqLength.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "hcpf/core/types.h"
#include "hcpf/metrics/sequence.h"

namespace hcpf::metrics {

// One row of a MOT file, numbers as written.
struct MotRow {
  int frame = 0;  // 1-based
  int64_t id = 0;
  BoxPx box;            // as in the file (1-based left/top)
  double conf = 1.0;    // column 7: MOT15 conf / MOT17 consider flag / tracker score
  double col8 = -1.0;   // MOT17 gt: class; MOT15 gt: world x; tracker: -1
  double col9 = -1.0;   // MOT17 gt: visibility; MOT15 gt: world y
  double col10 = -1.0;  // MOT15 gt: world z
  int line = 0;         // 1-based line in the file it came from (0 = not read from a file)
  // Column 2 is a whole number ("7", "7.0", "7e0"); false for "1.5", whose
  // `id` is the truncation TrackEval reads (int(float(text))).
  bool id_whole = true;
  friend bool operator==(const MotRow&, const MotRow&) = default;
};

// kDetections: a detector's output (MOTChallenge det.txt, `frame,-1,left,
// top,w,h,score,...`): ids are not identities, so they need not be unique
// within a frame.
enum class MotFileKind { kGroundTruth, kTracks, kDetections };

struct MotFile {
  std::string path;
  MotFileKind kind = MotFileKind::kGroundTruth;
  int num_columns = 0;  // largest column count seen (0 for an empty file)
  // The first row's column count, and the first row whose count differs
  // from it (line 0: none): the automatic benchmark needs one count.
  int first_row_columns = 0;
  int mixed_line = 0;
  int mixed_columns = 0;
  std::vector<MotRow> rows;
};

// Reads a MOT file. When `seq_length` is given, frames must lie in 1..seq_length;
// otherwise they must be >= 1. Tracker rows whose column 8 is present and > 1
// are rejected (TrackEval evaluates one class, pedestrians; trackers write -1).
MotFile ReadMotFile(const std::string& path, MotFileKind kind,
                    std::optional<int> seq_length = std::nullopt);
// Same, from text already in memory; `path` is used in error messages only.
MotFile ParseMotText(const std::string& text, const std::string& path, MotFileKind kind,
                     std::optional<int> seq_length = std::nullopt);

// [Sequence] section of a seqinfo.ini.
struct SeqInfo {
  std::string name;
  int seq_length = 0;       // required, >= 1
  int seq_length_line = 0;  // the line it was read from (1-based; 0 when not from a file)
  double frame_rate = 30.0;
  int im_width = 0;
  int im_height = 0;
  std::string im_dir = "img1";
  std::string im_ext = ".jpg";
};
SeqInfo ReadSeqInfo(const std::string& path);
SeqInfo ParseSeqInfo(const std::string& text, const std::string& path);
void WriteSeqInfo(const std::string& path, const SeqInfo& info);

// Which preprocessing applies. kAuto picks MOT17 for 9-column ground truth
// (MOT16/17/20 layout) and MOT15 otherwise.
enum class Benchmark { kMot15, kMot17, kAuto };
Benchmark ResolveBenchmark(Benchmark requested, const MotFile& gt);
const char* BenchmarkName(Benchmark benchmark);
// "MOT15", "MOT16", "MOT17", "MOT20" (MOT16/20 as MOT17) or "auto"; nullopt otherwise.
std::optional<Benchmark> ParseBenchmark(const std::string& text);

struct PreprocessOptions {
  // MOT17: remove tracker boxes matched (IoU >= 0.5, Hungarian) to distractor
  // gt (classes 2, 7, 8, 12), keep gt rows with consider != 0 and class 1.
  // MOT15: keep gt rows with int(conf) != 0, keep every tracker row.
  // false: keep every row of both files (no filtering at all).
  bool preprocess = true;
  int evaluated_class = 1;  // pedestrian
  std::vector<int> distractor_classes = {2, 7, 8, 12};
  // Build the sparse form of the Sequence (frames with no box on either side
  // left out; see sequence.h). Not a filtering rule: a storage choice that
  // leaves the MOT metrics unchanged and keeps memory proportional to the rows.
  bool sparse = false;
};

// Turns a gt file and a tracker file into a Sequence of `seq_length` frames.
// `benchmark` must be resolved (not kAuto). Counts of removed rows go to
// `removed_tracker_rows` / `removed_gt_rows` when given.
Sequence BuildSequence(const MotFile& gt, const MotFile& tracks, int seq_length,
                       Benchmark benchmark, const PreprocessOptions& options = {},
                       std::string name = {}, int64_t* removed_gt_rows = nullptr,
                       int64_t* removed_tracker_rows = nullptr);

// Writers (numbers in shortest round-trip form). Ground truth is written in
// the MOT17 layout (9 columns: frame,id,x,y,w,h,consider,class,visibility),
// tracks in the 10-column layout (frame,id,x,y,w,h,conf,-1,-1,-1). Rows are
// written in the order given. Throws hcpf::RunError when the file cannot be written.
void WriteMotGroundTruth(const std::string& path, const std::vector<MotRow>& rows);
void WriteMotTracks(const std::string& path, const std::vector<MotRow>& rows);
std::string FormatMotGroundTruth(const std::vector<MotRow>& rows);
std::string FormatMotTracks(const std::vector<MotRow>& rows);

// MOT files are 1-based: MOT left = BoxPx left + 1 (see hcpf::BoxPx).
inline BoxPx MotBoxToPx(const BoxPx& mot) {
  return {mot.left - 1.0, mot.top - 1.0, mot.width, mot.height};
}
inline BoxPx PxToMotBox(const BoxPx& px) {
  return {px.left + 1.0, px.top + 1.0, px.width, px.height};
}

}  // namespace hcpf::metrics
