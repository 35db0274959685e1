#include "hcpf/metrics/mot_io.h"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string_view>
#include <unordered_set>

#include "hcpf/core/check.h"
#include "hcpf/core/error.h"
#include "hcpf/metrics/assignment.h"

namespace hcpf::metrics {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

std::string ReadWholeFile(const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) {
    throw InputError(SourceLocation{path, 0, 0, {}}, "a readable file", "none (cannot open)");
  }
  std::string text;
  char buffer[1 << 16];
  size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof(buffer), f)) > 0) text.append(buffer, n);
  std::fclose(f);
  return text;
}

void WriteWholeFile(const std::string& path, const std::string& text) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) throw RunError(fmt::format("cannot write {}", path));
  const size_t written = std::fwrite(text.data(), 1, text.size(), f);
  const bool ok = written == text.size() && std::fclose(f) == 0;
  if (!ok) throw RunError(fmt::format("error while writing {}", path));
}

// ASCII whitespace without the locale lookup of std::isspace (hot in parsing).
inline bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f'; }

std::string_view Trim(std::string_view s) {
  while (!s.empty() && IsSpace(s.front())) s.remove_prefix(1);
  while (!s.empty() && IsSpace(s.back())) s.remove_suffix(1);
  return s;
}

const char* ColumnName(MotFileKind kind, int column) {
  static const char* kGt[] = {"frame", "id", "x", "y", "w", "h", "conf/consider", "class/world x",
                              "visibility/world y", "world z"};
  static const char* kHyp[] = {"frame", "id", "x", "y", "w", "h", "conf", "-1", "-1", "-1"};
  if (column < 1 || column > 10) return "extra";
  return kind == MotFileKind::kGroundTruth ? kGt[column - 1] : kHyp[column - 1];
}

// Splits one line into at most kMaxFields fields; returns the number found
// (which may exceed kMaxFields: the caller reports it).
constexpr int kMaxFields = 10;
int SplitFields(std::string_view line, std::string_view* fields) {
  const bool commas = line.find(',') != std::string_view::npos;
  int count = 0;
  if (commas) {
    size_t start = 0;
    bool last_empty = false;
    while (true) {
      const size_t pos = line.find(',', start);
      const std::string_view field =
          Trim(line.substr(start, pos == std::string_view::npos ? std::string_view::npos : pos - start));
      if (count < kMaxFields) fields[count] = field;
      ++count;
      last_empty = field.empty();
      if (pos == std::string_view::npos) break;
      start = pos + 1;
    }
    // A trailing comma ("1,2,...,-1,") leaves one empty last field: ignore it.
    if (count > 1 && last_empty) --count;
  } else {
    size_t i = 0;
    while (i < line.size()) {
      while (i < line.size() && IsSpace(line[i])) ++i;
      if (i >= line.size()) break;
      size_t j = i;
      while (j < line.size() && !IsSpace(line[j])) ++j;
      if (count < kMaxFields) fields[count] = line.substr(i, j - i);
      ++count;
      i = j;
    }
  }
  return count;
}

double ParseNumber(std::string_view field, const std::string& path, int line, int column,
                   MotFileKind kind) {
  double value = 0.0;
  const char* begin = field.data();
  const char* end = field.data() + field.size();
  if (!field.empty() && *begin == '+') ++begin;
  const auto [ptr, ec] = std::from_chars(begin, end, value);
  if (field.empty() || ec != std::errc() || ptr != end || !std::isfinite(value)) {
    throw InputError(SourceLocation{path, line, column,
                                    fmt::format("column {} ({})", column, ColumnName(kind, column))},
                     "a finite number", fmt::format("\"{}\"", field));
  }
  return value;
}

}  // namespace

double MotIou(const BoxPx& a, const BoxPx& b) {
  const double ax2 = a.left + a.width;
  const double ay2 = a.top + a.height;
  const double bx2 = b.left + b.width;
  const double by2 = b.top + b.height;
  const double area_a = (ax2 - a.left) * (ay2 - a.top);
  const double area_b = (bx2 - b.left) * (by2 - b.top);
  const double iw = std::min(ax2, bx2) - std::max(a.left, b.left);
  const double ih = std::min(ay2, by2) - std::max(a.top, b.top);
  if (iw <= 0.0 || ih <= 0.0) return 0.0;
  const double inter = iw * ih;
  if (area_a <= kEps || area_b <= kEps) return 0.0;
  const double uni = area_a + area_b - inter;
  if (uni <= kEps) return 0.0;
  return inter / uni;
}

MotFile ParseMotText(const std::string& text, const std::string& path, MotFileKind kind,
                     std::optional<int> seq_length) {
  MotFile file;
  file.path = path;
  file.kind = kind;
  file.rows.reserve(text.size() / 40);
  std::string_view rest(text);
  int line_no = 0;
  std::string_view fields[kMaxFields];
  while (!rest.empty()) {
    const size_t nl = rest.find('\n');
    std::string_view line = rest.substr(0, nl);
    rest = nl == std::string_view::npos ? std::string_view() : rest.substr(nl + 1);
    ++line_no;
    line = Trim(line);
    if (line.empty()) continue;
    const int count = SplitFields(line, fields);
    if (count < 6) {
      throw InputError(SourceLocation{path, line_no, 0, {}},
                       "at least 6 comma-separated columns (frame,id,x,y,w,h,...)",
                       fmt::format("{} column{}", count, count == 1 ? "" : "s"));
    }
    if (count > kMaxFields) {
      throw InputError(SourceLocation{path, line_no, 0, {}}, "at most 10 columns",
                       fmt::format("{} columns", count));
    }
    double v[kMaxFields];
    for (int c = 0; c < count; ++c) v[c] = ParseNumber(fields[c], path, line_no, c + 1, kind);
    MotRow row;
    row.line = line_no;
    // TrackEval reads frame and id as int(float(text)): truncation.
    if (v[0] < 1.0 || (seq_length && std::trunc(v[0]) > *seq_length) || v[0] > 1e9) {
      throw InputError(
          SourceLocation{path, line_no, 1, "column 1 (frame)"},
          seq_length ? fmt::format("a frame in 1..{} (seqLength)", *seq_length)
                     : std::string("a frame >= 1"),
          fmt::format("{}", v[0]));
    }
    row.frame = static_cast<int>(std::trunc(v[0]));
    if (std::fabs(v[1]) > 9.0e18) {
      throw InputError(SourceLocation{path, line_no, 2, "column 2 (id)"},
                       "an integer id within 64 bits", fmt::format("{}", v[1]));
    }
    row.id = static_cast<int64_t>(std::trunc(v[1]));
    {
      // Integer literals are taken exactly (ids above 2^53 stay distinct).
      int64_t exact = 0;
      const std::string_view f = fields[1];
      const auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), exact);
      if (ec == std::errc() && ptr == f.data() + f.size()) row.id = exact;
    }
    row.box = BoxPx{v[2], v[3], v[4], v[5]};
    if (count >= 7) row.conf = v[6];
    if (count >= 8) row.col8 = v[7];
    if (count >= 9) row.col9 = v[8];
    if (count >= 10) row.col10 = v[9];
    if (kind == MotFileKind::kTracks && count >= 8 && row.col8 > 1.0) {
      throw InputError(SourceLocation{path, line_no, 8, "column 8"},
                       "-1 or 1 (only the pedestrian class is evaluated)",
                       fmt::format("{}", row.col8));
    }
    file.num_columns = std::max(file.num_columns, count);
    file.rows.push_back(row);
  }
  // Ids must be unique within a frame (TrackEval raises on a duplicate).
  std::vector<int> order(file.rows.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const MotRow& ra = file.rows[a];
    const MotRow& rb = file.rows[b];
    if (ra.frame != rb.frame) return ra.frame < rb.frame;
    if (ra.id != rb.id) return ra.id < rb.id;
    return ra.line < rb.line;
  });
  for (size_t i = 1; i < order.size(); ++i) {
    const MotRow& a = file.rows[order[i - 1]];
    const MotRow& b = file.rows[order[i]];
    if (a.frame == b.frame && a.id == b.id) {
      throw InputError(SourceLocation{path, b.line, 2, "column 2 (id)"},
                       fmt::format("ids unique within frame {}", b.frame),
                       fmt::format("id {} again (first on line {})", b.id, a.line));
    }
  }
  return file;
}

MotFile ReadMotFile(const std::string& path, MotFileKind kind, std::optional<int> seq_length) {
  return ParseMotText(ReadWholeFile(path), path, kind, seq_length);
}

SeqInfo ParseSeqInfo(const std::string& text, const std::string& path) {
  SeqInfo info;
  bool have_length = false;
  bool in_sequence = false;
  std::string_view rest(text);
  int line_no = 0;
  while (!rest.empty()) {
    const size_t nl = rest.find('\n');
    std::string_view line = Trim(rest.substr(0, nl));
    rest = nl == std::string_view::npos ? std::string_view() : rest.substr(nl + 1);
    ++line_no;
    if (line.empty() || line.front() == ';' || line.front() == '#') continue;
    if (line.front() == '[') {
      in_sequence = line == "[Sequence]";
      continue;
    }
    if (!in_sequence) continue;
    const size_t eq = line.find('=');
    if (eq == std::string_view::npos) {
      throw InputError(SourceLocation{path, line_no, 0, {}}, "key=value", fmt::format("\"{}\"", line));
    }
    const std::string key(Trim(line.substr(0, eq)));
    const std::string_view value = Trim(line.substr(eq + 1));
    auto parse_int = [&](int minimum) {
      int out = 0;
      const auto [ptr, ec] = std::from_chars(value.data(), value.data() + value.size(), out);
      if (value.empty() || ec != std::errc() || ptr != value.data() + value.size() || out < minimum) {
        throw InputError(SourceLocation{path, line_no, 0, "Sequence." + key},
                         fmt::format("an integer >= {}", minimum), fmt::format("\"{}\"", value));
      }
      return out;
    };
    if (key == "seqLength") {
      info.seq_length = parse_int(1);
      have_length = true;
    } else if (key == "name") {
      info.name = std::string(value);
    } else if (key == "imWidth") {
      info.im_width = parse_int(0);
    } else if (key == "imHeight") {
      info.im_height = parse_int(0);
    } else if (key == "frameRate") {
      double out = 0.0;
      const auto [ptr, ec] = std::from_chars(value.data(), value.data() + value.size(), out);
      if (value.empty() || ec != std::errc() || ptr != value.data() + value.size() || !(out > 0.0)) {
        throw InputError(SourceLocation{path, line_no, 0, "Sequence.frameRate"}, "a number > 0",
                         fmt::format("\"{}\"", value));
      }
      info.frame_rate = out;
    } else if (key == "imDir") {
      info.im_dir = std::string(value);
    } else if (key == "imExt") {
      info.im_ext = std::string(value);
    }
  }
  if (!have_length) {
    throw InputError(SourceLocation{path, 0, 0, "Sequence.seqLength"},
                     "a [Sequence] section with seqLength=N", "none");
  }
  return info;
}

SeqInfo ReadSeqInfo(const std::string& path) { return ParseSeqInfo(ReadWholeFile(path), path); }

void WriteSeqInfo(const std::string& path, const SeqInfo& info) {
  HCPF_CHECK(info.seq_length >= 1);
  WriteWholeFile(path, fmt::format("[Sequence]\nname={}\nimDir={}\nframeRate={}\nseqLength={}\n"
                                   "imWidth={}\nimHeight={}\nimExt={}\n",
                                   info.name, info.im_dir, info.frame_rate, info.seq_length,
                                   info.im_width, info.im_height, info.im_ext));
}

Benchmark ResolveBenchmark(Benchmark requested, const MotFile& gt) {
  if (requested != Benchmark::kAuto) return requested;
  return gt.num_columns == 9 ? Benchmark::kMot17 : Benchmark::kMot15;
}

const char* BenchmarkName(Benchmark benchmark) {
  switch (benchmark) {
    case Benchmark::kMot15: return "MOT15";
    case Benchmark::kMot17: return "MOT17";
    case Benchmark::kAuto: return "auto";
  }
  return "?";
}

std::optional<Benchmark> ParseBenchmark(const std::string& text) {
  if (text == "MOT15") return Benchmark::kMot15;
  if (text == "MOT16" || text == "MOT17" || text == "MOT20") return Benchmark::kMot17;
  if (text == "auto") return Benchmark::kAuto;
  return std::nullopt;
}

Sequence BuildSequence(const MotFile& gt, const MotFile& tracks, int seq_length,
                       Benchmark benchmark, const PreprocessOptions& options, std::string name,
                       int64_t* removed_gt_rows, int64_t* removed_tracker_rows) {
  HCPF_CHECK(benchmark != Benchmark::kAuto) << "resolve the benchmark first";
  HCPF_CHECK(seq_length >= 0);
  Sequence seq;
  seq.name = std::move(name);
  seq.frames.resize(seq_length);
  // Bucket rows per frame (rows out of range were rejected by the reader when
  // it knew seq_length; check again here because callers may build MotFiles).
  std::vector<std::vector<const MotRow*>> gt_rows(seq_length), hyp_rows(seq_length);
  auto bucket = [&](const MotFile& file, std::vector<std::vector<const MotRow*>>* out) {
    for (const MotRow& row : file.rows) {
      if (row.frame < 1 || row.frame > seq_length) {
        throw InputError(SourceLocation{file.path, row.line, 1, "column 1 (frame)"},
                         fmt::format("a frame in 1..{} (seqLength)", seq_length),
                         fmt::format("{}", row.frame));
      }
      (*out)[row.frame - 1].push_back(&row);
    }
  };
  bucket(gt, &gt_rows);
  bucket(tracks, &hyp_rows);
  const bool mot17 = options.preprocess && benchmark == Benchmark::kMot17;
  if (mot17 && gt.num_columns > 0 && gt.num_columns < 8) {
    throw InputError(SourceLocation{gt.path, 0, 0, {}},
                     "MOT17 ground truth with at least 8 columns (class in column 8)",
                     fmt::format("{} columns", gt.num_columns));
  }
  int64_t removed_gt = 0;
  int64_t removed_hyp = 0;
  SparseMatcher matcher;
  std::vector<WeightedEdge> edges;
  std::vector<int> chosen;
  std::vector<char> remove_hyp;
  for (int t = 0; t < seq_length; ++t) {
    SequenceFrame& frame = seq.frames[t];
    const auto& g = gt_rows[t];
    const auto& h = hyp_rows[t];
    remove_hyp.assign(h.size(), 0);
    if (mot17 && !g.empty() && !h.empty()) {
      edges.clear();
      for (size_t i = 0; i < g.size(); ++i) {
        for (size_t j = 0; j < h.size(); ++j) {
          const double iou = MotIou(g[i]->box, h[j]->box);
          // TrackEval zeroes scores below 0.5 - eps before its Hungarian step.
          if (iou >= 0.5 - kEps) {
            edges.push_back({static_cast<int>(i), static_cast<int>(j), iou});
          }
        }
      }
      matcher.Solve(edges, static_cast<int>(g.size()), static_cast<int>(h.size()), &chosen);
      for (int k : chosen) {
        const WeightedEdge& e = edges[k];
        if (!(e.weight > kEps)) continue;
        const int cls = static_cast<int>(g[e.row]->col8);
        if (std::find(options.distractor_classes.begin(), options.distractor_classes.end(), cls) !=
            options.distractor_classes.end()) {
          remove_hyp[e.col] = 1;
        }
      }
    }
    frame.gt.reserve(g.size());
    for (const MotRow* row : g) {
      bool keep = true;
      if (options.preprocess) {
        // int(conf) == 0 drops the row (TrackEval: astype(int), truncation).
        keep = static_cast<int64_t>(std::trunc(row->conf)) != 0;
        if (mot17) keep = keep && static_cast<int>(row->col8) == options.evaluated_class;
      }
      if (keep) {
        frame.gt.push_back({row->id, row->box});
      } else {
        ++removed_gt;
      }
    }
    frame.hyp.reserve(h.size());
    for (size_t j = 0; j < h.size(); ++j) {
      if (remove_hyp[j]) {
        ++removed_hyp;
        continue;
      }
      frame.hyp.push_back({h[j]->id, h[j]->box});
    }
  }
  if (removed_gt_rows) *removed_gt_rows = removed_gt;
  if (removed_tracker_rows) *removed_tracker_rows = removed_hyp;
  return seq;
}

namespace {
std::string FormatRows(const std::vector<MotRow>& rows, bool gt) {
  std::string out;
  out.reserve(rows.size() * 48);
  for (const MotRow& r : rows) {
    if (gt) {
      fmt::format_to(std::back_inserter(out), "{},{},{},{},{},{},{},{},{}\n", r.frame, r.id,
                     r.box.left, r.box.top, r.box.width, r.box.height, r.conf, r.col8, r.col9);
    } else {
      fmt::format_to(std::back_inserter(out), "{},{},{},{},{},{},{},-1,-1,-1\n", r.frame, r.id,
                     r.box.left, r.box.top, r.box.width, r.box.height, r.conf);
    }
  }
  return out;
}
}  // namespace

std::string FormatMotGroundTruth(const std::vector<MotRow>& rows) { return FormatRows(rows, true); }
std::string FormatMotTracks(const std::vector<MotRow>& rows) { return FormatRows(rows, false); }
void WriteMotGroundTruth(const std::string& path, const std::vector<MotRow>& rows) {
  WriteWholeFile(path, FormatMotGroundTruth(rows));
}
void WriteMotTracks(const std::string& path, const std::vector<MotRow>& rows) {
  WriteWholeFile(path, FormatMotTracks(rows));
}

}  // namespace hcpf::metrics
