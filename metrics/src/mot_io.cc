#include "hcpf/metrics/mot_io.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cfloat>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <map>
#include <span>
#include <string_view>
#include <unordered_set>

#include "hcpf/core/check.h"
#include "hcpf/core/error.h"
#include "hcpf/core/text_file.h"
#include "hcpf/metrics/assignment.h"
#include "mot_io_internal.h"

namespace hcpf::metrics {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

// ASCII whitespace without the locale lookup of std::isspace (hot in parsing).
inline bool IsSpace(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

std::string_view Trim(std::string_view s) {
  while (!s.empty() && IsSpace(s.front())) s.remove_prefix(1);
  while (!s.empty() && IsSpace(s.back())) s.remove_suffix(1);
  return s;
}

const char* ColumnName(MotFileKind kind, int column) {
  static const char* kGt[] = {
      "frame",  "id", "x", "y", "w", "h", "conf/consider", "class/world x", "visibility/world y",
      "world z"};
  static const char* kHyp[] = {"frame", "id", "x", "y", "w", "h", "conf", "-1", "-1", "-1"};
  static const char* kDet[] = {"frame", "id", "x", "y", "w", "h", "score", "-1", "-1", "-1"};
  if (column < 1 || column > 10) return "extra";
  switch (kind) {
    case MotFileKind::kGroundTruth:
      return kGt[column - 1];
    case MotFileKind::kTracks:
      return kHyp[column - 1];
    case MotFileKind::kDetections:
      return kDet[column - 1];
  }
  return "extra";
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
      const std::string_view field = Trim(
          line.substr(start, pos == std::string_view::npos ? std::string_view::npos : pos - start));
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
  if (field.empty() || StartsWithTwoSigns(field) || ec != std::errc() || ptr != end ||
      !std::isfinite(value)) {
    // A byte-order mark (a file saved as "UTF-8 with BOM") does not show in
    // a terminal: named (it was printed raw, "found "1"").
    const size_t bom = ByteOrderMarkLength(field);
    throw InputError(
        SourceLocation{path, line, column,
                       fmt::format("column {} ({})", column, ColumnName(kind, column))},
        "a finite number",
        bom ? fmt::format("\"\\uFEFF{}\" (a byte-order mark, U+FEFF, starts the file: save it "
                          "without one)",
                          field.substr(bom))
            : fmt::format("\"{}\"", field));
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

namespace {

// The numbers of one row as parsed, before the per-row checks.
struct RowValues {
  double v[kMaxFields];
  int count = 0;
  bool has_exact_id = false;  // column 2 is an integer literal within 64 bits
  int64_t exact_id = 0;
};

// Whether a frame field is written as TrackEval compares it: the decimal
// digits of a positive integer, no sign, no leading zero.
inline bool IsFrameText(std::string_view f) {
  if (f.empty() || f.front() < '1' || f.front() > '9') return false;
  return std::all_of(f.begin(), f.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// General path for one trimmed, non-empty line: splits it (commas or
// whitespace), reports column-count and number errors with file:line:column.
void ParseLineGeneral(std::string_view line, const std::string& path, int line_no, MotFileKind kind,
                      RowValues* out) {
  std::string_view fields[kMaxFields];
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
  for (int c = 0; c < count; ++c) out->v[c] = ParseNumber(fields[c], path, line_no, c + 1, kind);
  // TrackEval keys its frames by the text of column 1 and refuses any key
  // other than "1".."seqLength" ("invalid timesteps"): "4.0", "04", "+4" or
  // "4e0" is refused there, so here too. (A number that is no frame at all,
  // 0 or past seqLength, gets the range message of AppendRow.)
  if (!IsFrameText(fields[0]) && out->v[0] >= 1.0 && out->v[0] <= 1e9) {
    throw InputError(SourceLocation{path, line_no, 1, "column 1 (frame)"},
                     "a frame written as TrackEval reads it: decimal digits without a sign, "
                     "fraction, exponent or leading zero",
                     fmt::format("\"{}\"", fields[0]));
  }
  out->count = count;
  // Integer literals are taken exactly (ids above 2^53 stay distinct).
  const std::string_view f = fields[1];
  int64_t exact = 0;
  const auto [ptr, ec] = std::from_chars(f.data(), f.data() + f.size(), exact);
  out->has_exact_id = ec == std::errc() && ptr == f.data() + f.size();
  out->exact_id = exact;
}

// A plain decimal number ("-12", "0.9", "1359.25", ".5", "5.", and the
// 17-digit shortest forms hcpf writes): at most 18 digits, no exponent, so the
// value is m / 10^k with integers m < 10^18 and k <= 18. Up to 15 digits, m and
// 10^k are exact doubles and one IEEE division gives the correctly rounded
// value (Clinger's fast path). With 16 to 18 digits the division is done in
// x87 extended precision (m and 10^k exact in its 64-bit significand): the
// quotient q is x rounded to 64 bits, and rounding q to a double gives x
// rounded to a double unless q lies exactly halfway between two doubles (a
// halfway point that separated x from q would be a 64-bit number nearer to x
// than q); that case goes to std::from_chars. Either way the result is the
// double std::from_chars returns. Returns the end of the number, or nullptr
// when the text is anything else (more digits, an exponent, no digit at all):
// the caller then uses std::from_chars. A number followed by other characters
// is left to the caller exactly as std::from_chars would leave it.
#if defined(__x86_64__) && LDBL_MANT_DIG == 64
#define HCPF_METRICS_X87_DECIMALS 1
#else
#define HCPF_METRICS_X87_DECIMALS 0
#endif
// If the 8 bytes at p are all ASCII digits, sets *value to their decimal
// value and returns true. SWAR: each byte minus '0' must be below 10 (checked
// on all lanes at once: no byte has a high nibble other than 3, and adding 6
// carries none of them out of the low nibble); then adjacent lanes are merged
// pairwise (x 10), the pairs into fours (x 100) and the fours into eight
// (x 10^4) with multiplications that keep every partial sum in its own lane.
inline bool SwarEightDigits(const char* p, uint32_t* value) {
  uint64_t v = 0;
  std::memcpy(&v, p, sizeof(v));  // little-endian: p[0] is the low byte
  constexpr uint64_t kHigh = 0xF0F0F0F0F0F0F0F0ULL;
  constexpr uint64_t kZeros = 0x3030303030303030ULL;
  if ((v & kHigh) != kZeros || ((v + 0x0606060606060606ULL) & kHigh) != kZeros) return false;
  v -= kZeros;  // lanes d0..d7, d0 the most significant digit
  // Pairs: byte 2k becomes 10 d_{2k} + d_{2k+1} (at most 99: no carry).
  v = (v * 10 + (v >> 8)) & 0x00FF00FF00FF00FFULL;
  // Fours: 100 * pair_{k} + pair_{k+1} in 16-bit lanes 0 and 2.
  v = (v * 100 + (v >> 16)) & 0x0000FFFF0000FFFFULL;
  // Eight: 10^4 * four_0 + four_1.
  v = (v * 10000 + (v >> 32)) & 0xFFFFFFFFULL;
  *value = static_cast<uint32_t>(v);
  return true;
}

struct ShortDecimal {
  double value = 0.0;
  bool is_integer = false;  // no '.': `integer` holds the exact value
  int64_t integer = 0;
};
inline const char* ParseShortDecimal(const char* p, const char* end, ShortDecimal* out) {
  static constexpr double kPow10[] = {1e0, 1e1, 1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                      1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15};
#if HCPF_METRICS_X87_DECIMALS
  static constexpr int kMaxDigits = 18;
  static constexpr long double kPow10Long[] = {1e0L,  1e1L,  1e2L,  1e3L,  1e4L,  1e5L,  1e6L,
                                               1e7L,  1e8L,  1e9L,  1e10L, 1e11L, 1e12L, 1e13L,
                                               1e14L, 1e15L, 1e16L, 1e17L, 1e18L};
#else
  static constexpr int kMaxDigits = 15;
#endif
  const char* q = p;
  const bool negative = q < end && *q == '-';
  if (negative) ++q;
  uint64_t m = 0;
  int digits = 0;
  // Appends a run of digits to m, eight at a time while they fit
  // (SwarEightDigits), then one by one; false when there are too many.
  auto eat_digits = [&]() -> bool {
    uint32_t eight = 0;
    while (digits + 8 <= kMaxDigits && end - q >= 8 && SwarEightDigits(q, &eight)) {
      m = m * 100000000u + eight;
      digits += 8;
      q += 8;
    }
    while (q < end && static_cast<unsigned>(*q - '0') < 10u) {
      if (++digits > kMaxDigits) return false;
      m = m * 10 + static_cast<unsigned>(*q - '0');
      ++q;
    }
    return true;
  };
  if (!eat_digits()) return nullptr;
  const int integer_digits = digits;
  int fraction = 0;
  const bool dot = q < end && *q == '.';
  if (dot) {
    ++q;
    if (!eat_digits()) return nullptr;
    fraction = digits - integer_digits;
  }
  if (digits == 0) return nullptr;
  if (q < end && (*q == 'e' || *q == 'E')) return nullptr;
  double v = 0.0;
  if (digits <= 15) {
    v = static_cast<double>(m);
    if (fraction > 0) v /= kPow10[fraction];
  } else {
#if HCPF_METRICS_X87_DECIMALS
    const long double quotient =
        static_cast<long double>(static_cast<int64_t>(m)) / kPow10Long[fraction];
    uint64_t significand = 0;  // the low 8 bytes of the x87 format: the explicit 64-bit significand
    std::memcpy(&significand, &quotient, sizeof(significand));
    if ((significand & 0x7FF) == 0x400) return nullptr;  // halfway between two doubles
    v = static_cast<double>(quotient);
#else
    return nullptr;
#endif
  }
  out->value = negative ? -v : v;
  out->is_integer = !dot;
  out->integer = negative ? -static_cast<int64_t>(m) : static_cast<int64_t>(m);
  return q;
}

// Fast path for the common well-formed line: comma separated, 6..10 finite
// numbers, optional blanks around fields, optional trailing comma. Parses in
// place (no splitting) and returns false for anything else, which then goes
// through ParseLineGeneral: that path accepts exactly the same lines with the
// same values (each field is the same characters, converted by std::from_chars
// there and by ParseShortDecimal or std::from_chars here, which agree) and
// produces the error messages.
bool ParseLineFast(const char* p, const char* end, RowValues* out) {
  int count = 0;
  while (true) {
    while (p < end && IsSpace(*p)) ++p;
    if (count == kMaxFields) return false;
    double& value = out->v[count];
    ShortDecimal d;
    const char* ptr = ParseShortDecimal(p, end, &d);
    // A frame not written as plain digits (no sign, point, exponent or
    // leading zero) goes to the general path, which refuses it.
    if (ptr != nullptr) {
      value = d.value;
      if (count <= 1) [[unlikely]] {
        if (count == 1) {
          out->has_exact_id = d.is_integer;
          out->exact_id = d.integer;
        } else if (!d.is_integer || *p < '1' || *p > '9') {
          return false;
        }
      }
    } else {
      if (count == 0) return false;
      const auto [fptr, ec] = std::from_chars(p, end, value);
      if (ec != std::errc() || !std::isfinite(value)) return false;
      ptr = fptr;
      if (count == 1) {
        int64_t exact = 0;
        const auto [iptr, iec] = std::from_chars(p, ptr, exact);
        out->has_exact_id = iec == std::errc() && iptr == ptr;
        out->exact_id = exact;
      }
    }
    ++count;
    p = ptr;
    while (p < end && IsSpace(*p)) ++p;
    if (p == end) break;
    if (*p != ',') return false;
    ++p;
    const char* q = p;
    while (q < end && IsSpace(*q)) ++q;
    if (q == end) break;  // trailing comma: the empty last field is ignored
  }
  if (count < 6) return false;
  out->count = count;
  return true;
}

// The errors of AppendRow, out of line (cold).
[[noreturn]] [[gnu::noinline]] void ThrowBadFrame(const std::string& path, int line_no,
                                                  std::optional<int> seq_length, double frame) {
  throw InputError(SourceLocation{path, line_no, 1, "column 1 (frame)"},
                   seq_length ? fmt::format("a frame in 1..{} (seqLength)", *seq_length)
                              : std::string("a frame >= 1"),
                   fmt::format("{}", frame));
}
[[noreturn]] [[gnu::noinline]] void ThrowBadId(const std::string& path, int line_no, double id) {
  throw InputError(SourceLocation{path, line_no, 2, "column 2 (id)"},
                   "an integer id within 64 bits", fmt::format("{}", id));
}
[[noreturn]] [[gnu::noinline]] void ThrowBadClass(const std::string& path, int line_no,
                                                  double col8) {
  throw InputError(SourceLocation{path, line_no, 8, "column 8"},
                   "a class of at most 1 (only the pedestrian class is evaluated; TrackEval "
                   "truncates the class to an integer and refuses any above 1)",
                   fmt::format("{}", col8));
}

// The per-row checks and conversion shared by both paths.
inline void AppendRow(const RowValues& r, const std::string& path, int line_no, MotFileKind kind,
                      std::optional<int> seq_length, MotFile* file) {
  const double* v = r.v;
  const int count = r.count;
  // The frame is an integer here (its text checked by the parsers); TrackEval
  // reads the id as int(float(text)): truncation.
  if (v[0] < 1.0 || (seq_length && std::trunc(v[0]) > *seq_length) || v[0] > 1e9) [[unlikely]] {
    ThrowBadFrame(path, line_no, seq_length, v[0]);
  }
  // An integer literal is exact whatever its size (from_chars into int64_t);
  // only a non-integer spelling ("1e3", "7.0") goes through the double.
  if (!r.has_exact_id && !(std::fabs(v[1]) <= 9.0e18)) [[unlikely]]
    ThrowBadId(path, line_no, v[1]);
  // TrackEval: classes astype(int) (truncation), refused when above 1; so
  // 1.5 is class 1, and 2 is refused.
  if (kind == MotFileKind::kTracks && count >= 8 && v[7] >= 2.0) [[unlikely]] {
    ThrowBadClass(path, line_no, v[7]);
  }
  MotRow& row = file->rows.emplace_back();
  row.line = line_no;
  row.frame = static_cast<int>(std::trunc(v[0]));
  row.id = r.has_exact_id ? r.exact_id : static_cast<int64_t>(std::trunc(v[1]));
  row.id_whole = r.has_exact_id || v[1] == std::trunc(v[1]);
  row.box = BoxPx{v[2], v[3], v[4], v[5]};
  if (count >= 7) row.conf = v[6];
  if (count >= 8) row.col8 = v[7];
  if (count >= 9) row.col9 = v[8];
  if (count >= 10) row.col10 = v[9];
  file->num_columns = std::max(file->num_columns, count);
  if (file->rows.size() == 1) {
    file->first_row_columns = count;
  } else if (count != file->first_row_columns && file->mixed_line == 0) [[unlikely]] {
    file->mixed_line = line_no;
    file->mixed_columns = count;
  }
}

[[noreturn]] void ThrowDuplicateId(const std::string& path, const MotRow& first,
                                   const MotRow& again) {
  throw InputError(SourceLocation{path, again.line, 2, "column 2 (id)"},
                   fmt::format("ids unique within frame {}", again.frame),
                   fmt::format("id {} again (first on line {})", again.id, first.line));
}

// Ids must be unique within a frame (TrackEval raises on a duplicate). The
// error names the smallest (frame, id) that repeats, at its second line, like
// a scan of the rows sorted by (frame, id, line).
void CheckUniqueIds(const MotFile& file) {
  if (file.kind == MotFileKind::kDetections) return;  // ids are not identities
  const std::vector<MotRow>& rows = file.rows;
  const size_t n = rows.size();
  if (n < 2) return;
  // Group row indices by frame, keeping file order within a frame.
  std::vector<int> order;
  bool sorted = true;
  int max_frame = rows[0].frame;
  for (size_t i = 1; i < n; ++i) {
    sorted = sorted && rows[i - 1].frame <= rows[i].frame;
    max_frame = std::max(max_frame, rows[i].frame);
  }
  if (!sorted) {
    order.resize(n);
    if (static_cast<size_t>(max_frame) <= 4 * n + 100000) {
      std::vector<int> start(static_cast<size_t>(max_frame) + 2, 0);
      for (const MotRow& r : rows) ++start[r.frame + 1];
      for (size_t f = 1; f < start.size(); ++f) start[f] += start[f - 1];
      for (size_t i = 0; i < n; ++i) order[start[rows[i].frame]++] = static_cast<int>(i);
    } else {
      for (size_t i = 0; i < n; ++i) order[i] = static_cast<int>(i);
      std::stable_sort(order.begin(), order.end(),
                       [&](int a, int b) { return rows[a].frame < rows[b].frame; });
    }
  }
  auto at = [&](size_t k) -> const MotRow& { return sorted ? rows[k] : rows[order[k]]; };
  std::vector<int64_t> ids;
  std::vector<std::pair<int64_t, int>> id_rows;  // (id, index into rows)
  size_t begin = 0;
  while (begin < n) {
    const int frame = at(begin).frame;
    size_t end = begin + 1;
    while (end < n && at(end).frame == frame) ++end;
    const size_t size = end - begin;
    bool duplicate = false;
    if (size > 1) {
      ids.clear();
      for (size_t k = begin; k < end; ++k) ids.push_back(at(k).id);
      if (size <= 48) {
        for (size_t a = 1; a < size && !duplicate; ++a) {
          for (size_t b = 0; b < a; ++b) duplicate = duplicate || ids[a] == ids[b];
        }
      } else {
        std::sort(ids.begin(), ids.end());
        duplicate = std::adjacent_find(ids.begin(), ids.end()) != ids.end();
      }
    }
    if (duplicate) {
      // Rows of a frame are in file order, so (id, position) sorts by (id, line).
      id_rows.clear();
      for (size_t k = begin; k < end; ++k) {
        id_rows.emplace_back(at(k).id, sorted ? static_cast<int>(k) : order[k]);
      }
      std::sort(id_rows.begin(), id_rows.end());
      for (size_t k = 1; k < id_rows.size(); ++k) {
        if (id_rows[k].first == id_rows[k - 1].first) {
          ThrowDuplicateId(file.path, rows[id_rows[k - 1].second], rows[id_rows[k].second]);
        }
      }
      HCPF_CHECK(false) << "duplicate id detected but not found";
    }
    begin = end;
  }
}

}  // namespace

namespace {

MotFile ParseMotView(std::string_view text, const std::string& path, MotFileKind kind,
                     std::optional<int> seq_length) {
  MotFile file;
  file.path = path;
  file.kind = kind;
  {
    // Exact capacity: one row per line at most (memchr is vectorised, a byte loop is not).
    size_t lines = 1;
    const char* q = text.data();
    const char* const q_end = q + text.size();
    while ((q = static_cast<const char*>(std::memchr(q, '\n', static_cast<size_t>(q_end - q)))) !=
           nullptr) {
      ++lines;
      ++q;
    }
    file.rows.reserve(lines);
  }
  const char* p = text.data();
  const char* const text_end = p + text.size();
  int line_no = 0;
  RowValues values;
  // Duplicates are found while streaming when a row repeats the (frame, id) of
  // the row before it (a file of one repeated line). From then on a row is kept
  // only if it could take part in a smaller duplicate (an earlier frame, or the
  // same frame and a smaller id), so memory stays bounded; every line is still
  // parsed (a later syntax error is reported first, as before), and
  // CheckUniqueIds below reports exactly the duplicate it would have.
  bool have_duplicate = false;
  int duplicate_frame = 0;
  int64_t duplicate_id = 0;
  int previous_frame = 0;
  int64_t previous_id = 0;
  while (p < text_end) {
    const char* nl =
        static_cast<const char*>(std::memchr(p, '\n', static_cast<size_t>(text_end - p)));
    const char* line_end = nl == nullptr ? text_end : nl;
    const char* line_begin = p;
    p = nl == nullptr ? text_end : nl + 1;
    ++line_no;
    while (line_begin < line_end && IsSpace(*line_begin)) ++line_begin;
    while (line_end > line_begin && IsSpace(line_end[-1])) --line_end;
    if (line_begin == line_end) continue;
    if (!ParseLineFast(line_begin, line_end, &values)) {
      ParseLineGeneral(std::string_view(line_begin, static_cast<size_t>(line_end - line_begin)),
                       path, line_no, kind, &values);
    }
    AppendRow(values, path, line_no, kind, seq_length, &file);
    if (kind == MotFileKind::kDetections) continue;  // ids are not identities
    const int frame = file.rows.back().frame;
    const int64_t id = file.rows.back().id;
    if (have_duplicate && (frame > duplicate_frame ||
                           (frame == duplicate_frame && id >= duplicate_id))) [[unlikely]] {
      file.rows.pop_back();
    } else if (file.rows.size() > 1 && frame == previous_frame && id == previous_id) [[unlikely]] {
      have_duplicate = true;
      duplicate_frame = frame;
      duplicate_id = id;
    }
    previous_frame = frame;
    previous_id = id;
  }
  CheckUniqueIds(file);
  HCPF_CHECK(!have_duplicate) << "a duplicate id was seen but not reported";
  return file;
}

// A read-only view of a whole file: mapped when possible (no copy, no zeroed
// buffer), else read into memory.
class FileText {
 public:
  explicit FileText(const std::string& path) {
    // A directory, FIFO or device is refused before anything is read.
    const uint64_t size = CheckRegularFile(path, "a MOT file");
    if (size == 0) return;
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd >= 0) {
      void* map = ::mmap(nullptr, static_cast<size_t>(size), PROT_READ, MAP_PRIVATE, fd, 0);
      if (map != MAP_FAILED) {
        map_ = map;
        map_size_ = static_cast<size_t>(size);
        ::madvise(map_, map_size_, MADV_SEQUENTIAL | MADV_WILLNEED);
      }
      ::close(fd);
    }
    if (map_ == nullptr) {
      copy_ = ReadInputFile(path, "a MOT file", std::numeric_limits<uint64_t>::max() - 1);
    }
  }
  ~FileText() {
    if (map_ != nullptr) ::munmap(map_, map_size_);
  }
  FileText(const FileText&) = delete;
  FileText& operator=(const FileText&) = delete;
  std::string_view view() const {
    return map_ != nullptr ? std::string_view(static_cast<const char*>(map_), map_size_)
                           : std::string_view(copy_);
  }

 private:
  void* map_ = nullptr;
  size_t map_size_ = 0;
  std::string copy_;
};

}  // namespace

MotFile ParseMotText(const std::string& text, const std::string& path, MotFileKind kind,
                     std::optional<int> seq_length) {
  return ParseMotView(text, path, kind, seq_length);
}

namespace internal {

MotFile ParseMotTextReference(const std::string& text, const std::string& path, MotFileKind kind,
                              std::optional<int> seq_length) {
  MotFile file;
  file.path = path;
  file.kind = kind;
  std::string_view rest(text);
  int line_no = 0;
  RowValues values;
  while (!rest.empty()) {
    const size_t nl = rest.find('\n');
    std::string_view line = rest.substr(0, nl);
    rest = nl == std::string_view::npos ? std::string_view() : rest.substr(nl + 1);
    ++line_no;
    line = Trim(line);
    if (line.empty()) continue;
    ParseLineGeneral(line, path, line_no, kind, &values);
    AppendRow(values, path, line_no, kind, seq_length, &file);
  }
  std::vector<int> order(file.rows.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    const MotRow& ra = file.rows[a];
    const MotRow& rb = file.rows[b];
    if (ra.frame != rb.frame) return ra.frame < rb.frame;
    if (ra.id != rb.id) return ra.id < rb.id;
    return ra.line < rb.line;
  });
  for (size_t i = 1; i < order.size() && kind != MotFileKind::kDetections; ++i) {
    const MotRow& a = file.rows[order[i - 1]];
    const MotRow& b = file.rows[order[i]];
    if (a.frame == b.frame && a.id == b.id) ThrowDuplicateId(path, a, b);
  }
  return file;
}

}  // namespace internal

MotFile ReadMotFile(const std::string& path, MotFileKind kind, std::optional<int> seq_length) {
  const FileText text(path);
  return ParseMotView(text.view(), path, kind, seq_length);
}

SeqInfo ParseSeqInfo(const std::string& text, const std::string& path) {
  // Read as TrackEval's configparser reads it: option names without regard
  // to case (seqlength is seqLength), '=' or ':' between name and value, a
  // section or an option given twice refused, and no option before the first
  // section header. Section names keep their case ([sequence] is another
  // section, which TrackEval does not read).
  SeqInfo info;
  bool have_length = false;
  bool in_sequence = false;
  bool any_section = false;
  std::map<std::string, int> first_line;  // lower-case key -> line
  std::map<std::string, int> sections;    // section name -> line
  std::string_view rest(text);
  int line_no = 0;
  const auto lower = [](std::string_view v) {
    std::string out(v);
    for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    return out;
  };
  while (!rest.empty()) {
    const size_t nl = rest.find('\n');
    std::string_view line = Trim(rest.substr(0, nl));
    rest = nl == std::string_view::npos ? std::string_view() : rest.substr(nl + 1);
    ++line_no;
    if (line.empty() || line.front() == ';' || line.front() == '#') continue;
    if (line.front() == '[' && line.find(']') != std::string_view::npos) {
      const std::string name(line.substr(1, line.find(']') - 1));
      if (const auto [at, fresh] = sections.emplace(name, line_no); !fresh) {
        throw InputError(SourceLocation{path, line_no, 0, {}}, "each section once",
                         fmt::format("[{}] again (first at line {})", name, at->second));
      }
      in_sequence = name == "Sequence";
      any_section = true;
      continue;
    }
    if (!any_section) {
      throw InputError(SourceLocation{path, line_no, 0, {}},
                       "a section header ([Sequence]) before the first key",
                       fmt::format("\"{}\"", line));
    }
    if (!in_sequence) continue;
    const size_t eq = line.find_first_of("=:");
    if (eq == std::string_view::npos) {
      throw InputError(SourceLocation{path, line_no, 0, {}}, "key=value",
                       fmt::format("\"{}\"", line));
    }
    const std::string key(Trim(line.substr(0, eq)));
    const std::string_view value = Trim(line.substr(eq + 1));
    const std::string name = lower(key);
    // TrackEval's configparser refuses a key given twice (in any case);
    // taking the last silently would score another sequence length than the
    // reader meant.
    if (const auto [at, fresh] = first_line.emplace(name, line_no); !fresh) {
      throw InputError(SourceLocation{path, line_no, 0, "Sequence." + key},
                       "each key once in [Sequence] (names without regard to case)",
                       fmt::format("{} again (first at line {})", key, at->second));
    }
    auto parse_int = [&](int minimum) {
      int out = 0;
      const auto [ptr, ec] = std::from_chars(value.data(), value.data() + value.size(), out);
      if (value.empty() || ec != std::errc() || ptr != value.data() + value.size() ||
          out < minimum) {
        throw InputError(SourceLocation{path, line_no, 0, "Sequence." + key},
                         fmt::format("an integer >= {}", minimum), fmt::format("\"{}\"", value));
      }
      return out;
    };
    if (name == "seqlength") {
      info.seq_length = parse_int(1);
      info.seq_length_line = line_no;
      have_length = true;
    } else if (name == "name") {
      info.name = std::string(value);
    } else if (name == "imwidth") {
      info.im_width = parse_int(0);
    } else if (name == "imheight") {
      info.im_height = parse_int(0);
    } else if (name == "framerate") {
      double out = 0.0;
      const auto [ptr, ec] = std::from_chars(value.data(), value.data() + value.size(), out);
      if (value.empty() || ec != std::errc() || ptr != value.data() + value.size() ||
          !(out > 0.0)) {
        throw InputError(SourceLocation{path, line_no, 0, "Sequence." + key}, "a number > 0",
                         fmt::format("\"{}\"", value));
      }
      info.frame_rate = out;
    } else if (name == "imdir") {
      info.im_dir = std::string(value);
    } else if (name == "imext") {
      info.im_ext = std::string(value);
    }
  }
  if (!have_length) {
    throw InputError(SourceLocation{path, 0, 0, "Sequence.seqLength"},
                     "a [Sequence] section with seqLength=N", "none");
  }
  return info;
}

SeqInfo ReadSeqInfo(const std::string& path) {
  // A seqinfo.ini is a few hundred bytes.
  return ParseSeqInfo(ReadInputFile(path, "a seqinfo.ini file", uint64_t{1} << 20), path);
}

void WriteSeqInfo(const std::string& path, const SeqInfo& info) {
  HCPF_CHECK(info.seq_length >= 1);
  WriteTextFile(path, fmt::format("[Sequence]\nname={}\nimDir={}\nframeRate={}\nseqLength={}\n"
                                  "imWidth={}\nimHeight={}\nimExt={}\n",
                                  info.name, info.im_dir, info.frame_rate, info.seq_length,
                                  info.im_width, info.im_height, info.im_ext));
}

Benchmark ResolveBenchmark(Benchmark requested, const MotFile& gt) {
  if (requested != Benchmark::kAuto) return requested;
  // A third bad-input audit: one 10-column row made a 9-column MOT17 file
  // MOT15 (static persons and distractors scored as pedestrians), exit 0.
  if (gt.mixed_line > 0) {
    throw InputError(SourceLocation{gt.path, gt.mixed_line, 0, "--benchmark auto"},
                     "ground-truth rows of one column count (9: MOT17 rules; 6 or 10: MOT15 rules)",
                     fmt::format("a row of {} columns where the first row has {}", gt.mixed_columns,
                                 gt.first_row_columns),
                     "pass --benchmark MOT17 or MOT15, or mend the file");
  }
  return gt.num_columns == 9 ? Benchmark::kMot17 : Benchmark::kMot15;
}

const char* BenchmarkName(Benchmark benchmark) {
  switch (benchmark) {
    case Benchmark::kMot15:
      return "MOT15";
    case Benchmark::kMot17:
      return "MOT17";
    case Benchmark::kAuto:
      return "auto";
  }
  return "?";
}

std::optional<Benchmark> ParseBenchmark(const std::string& text) {
  if (text == "MOT15") return Benchmark::kMot15;
  if (text == "MOT16" || text == "MOT17" || text == "MOT20") return Benchmark::kMot17;
  if (text == "auto") return Benchmark::kAuto;
  return std::nullopt;
}

namespace {

// Rows of one file in frame order (file order within a frame), one group per
// distinct frame. Memory is proportional to the rows whatever the frame
// numbers (a row at frame 10^9 costs what any row costs): a counting sort when
// the frames span little more than the rows, else a stable sort.
struct FrameGroups {
  std::vector<const MotRow*> rows;
  std::vector<int> frames;  // distinct frames, increasing
  std::vector<int> begin;   // rows of frames[k] are rows[begin[k] .. begin[k + 1])
  std::span<const MotRow* const> Rows(size_t k) const {
    return {rows.data() + begin[k], static_cast<size_t>(begin[k + 1] - begin[k])};
  }
};

// Rows out of range were rejected by the reader when it knew seq_length; check
// again here (first offending row in file order) because callers may build MotFiles.
FrameGroups GroupByFrame(const MotFile& file, int seq_length) {
  int max_frame = 0;
  for (const MotRow& row : file.rows) {
    if (row.frame < 1 || row.frame > seq_length) {
      throw InputError(SourceLocation{file.path, row.line, 1, "column 1 (frame)"},
                       fmt::format("a frame in 1..{} (seqLength)", seq_length),
                       fmt::format("{}", row.frame));
    }
    max_frame = std::max(max_frame, row.frame);
  }
  FrameGroups g;
  const size_t n = file.rows.size();
  g.rows.resize(n);
  if (static_cast<size_t>(max_frame) <= 4 * n + 100000) {
    std::vector<int> start(static_cast<size_t>(max_frame) + 2, 0);
    for (const MotRow& row : file.rows) ++start[row.frame + 1];
    for (size_t f = 1; f < start.size(); ++f) start[f] += start[f - 1];
    for (const MotRow& row : file.rows) g.rows[start[row.frame]++] = &row;
  } else {
    for (size_t i = 0; i < n; ++i) g.rows[i] = &file.rows[i];
    std::stable_sort(g.rows.begin(), g.rows.end(),
                     [](const MotRow* a, const MotRow* b) { return a->frame < b->frame; });
  }
  for (size_t i = 0; i < n; ++i) {
    if (i == 0 || g.rows[i]->frame != g.rows[i - 1]->frame) {
      g.frames.push_back(g.rows[i]->frame);
      g.begin.push_back(static_cast<int>(i));
    }
  }
  g.begin.push_back(static_cast<int>(n));
  return g;
}

}  // namespace

// TrackEval's MOTChallenge classes: pedestrian (1) to crowd (13).
constexpr int kFirstMotClass = 1;
constexpr int kLastMotClass = 13;

Sequence BuildSequence(const MotFile& gt, const MotFile& tracks, int seq_length,
                       Benchmark benchmark, const PreprocessOptions& options, std::string name,
                       int64_t* removed_gt_rows, int64_t* removed_tracker_rows) {
  HCPF_CHECK(benchmark != Benchmark::kAuto) << "resolve the benchmark first";
  HCPF_CHECK(seq_length >= 0);
  Sequence seq;
  seq.name = std::move(name);
  const FrameGroups gt_rows = GroupByFrame(gt, seq_length);
  const FrameGroups hyp_rows = GroupByFrame(tracks, seq_length);
  if (options.sparse) {
    seq.length = seq_length;
  } else {
    seq.frames.resize(seq_length);
  }
  const bool mot17 = options.preprocess && benchmark == Benchmark::kMot17;
  if (mot17 && gt.num_columns > 0 && gt.num_columns < 8) {
    throw InputError(SourceLocation{gt.path, 0, 0, {}},
                     "MOT17 ground truth with at least 8 columns (class in column 8)",
                     fmt::format("{} columns", gt.num_columns));
  }
  // Classes compare as truncated doubles (TrackEval: astype(int)); a value
  // outside int's range is no class at all (converting it would be undefined).
  auto class_is = [](const MotRow* row, int cls) {
    return std::trunc(row->col8) == static_cast<double>(cls);
  };
  auto is_distractor = [&](const MotRow* row) {
    return std::any_of(options.distractor_classes.begin(), options.distractor_classes.end(),
                       [&](int cls) { return class_is(row, cls); });
  };
  int64_t removed_gt = 0;
  int64_t removed_hyp = 0;
  SparseMatcher matcher;
  std::vector<WeightedEdge> edges;
  std::vector<int> chosen;
  std::vector<char> remove_hyp;
  // Walk the frames that hold a row on either side, in increasing order; the
  // others are empty on both sides and need nothing.
  constexpr int kNone = std::numeric_limits<int>::max();
  size_t gk = 0;
  size_t hk = 0;
  while (gk < gt_rows.frames.size() || hk < hyp_rows.frames.size()) {
    const int gt_frame = gk < gt_rows.frames.size() ? gt_rows.frames[gk] : kNone;
    const int hyp_frame = hk < hyp_rows.frames.size() ? hyp_rows.frames[hk] : kNone;
    const int number = std::min(gt_frame, hyp_frame);
    const std::span<const MotRow* const> g =
        gt_frame == number ? gt_rows.Rows(gk++) : std::span<const MotRow* const>();
    const std::span<const MotRow* const> h =
        hyp_frame == number ? hyp_rows.Rows(hk++) : std::span<const MotRow* const>();
    SequenceFrame* frame_ptr = nullptr;
    if (options.sparse) {
      seq.numbers.push_back(number);
      frame_ptr = &seq.frames.emplace_back();
    } else {
      frame_ptr = &seq.frames[static_cast<size_t>(number) - 1];
    }
    SequenceFrame& frame = *frame_ptr;
    remove_hyp.assign(h.size(), 0);
    // TrackEval refuses a gt class outside its 13 MOTChallenge classes in a
    // frame it preprocesses (MOT16/17/20, gt and tracker boxes both present)
    // instead of dropping the row as a non-pedestrian; so does this.
    if (mot17 && !h.empty()) {
      for (const MotRow* row : g) {
        const double cls = std::trunc(row->col8);
        if (!(cls >= kFirstMotClass && cls <= kLastMotClass)) {
          throw InputError(
              SourceLocation{gt.path, row->line, 8, "column 8 (class)"},
              fmt::format("a MOTChallenge class {}..{} (TrackEval refuses any other in a frame "
                          "with tracker boxes)",
                          kFirstMotClass, kLastMotClass),
              fmt::format("{}", row->col8),
              "check the ground truth, or pass --benchmark MOT15 to score it without classes");
        }
      }
    }
    // Only a tracker box matched to a distractor gt box is removed, so a frame
    // without distractor gt needs no matching (the result would remove nothing).
    if (mot17 && !h.empty() && std::any_of(g.begin(), g.end(), is_distractor)) {
      edges.clear();
      for (size_t i = 0; i < g.size(); ++i) {
        const BoxPx& a = g[i]->box;
        for (size_t j = 0; j < h.size(); ++j) {
          const BoxPx& b = h[j]->box;
          // Boxes that do not overlap have IoU 0 (MotIou's own first test): skip them cheaply.
          if (std::min(a.left + a.width, b.left + b.width) - std::max(a.left, b.left) <= 0.0 ||
              std::min(a.top + a.height, b.top + b.height) - std::max(a.top, b.top) <= 0.0) {
            continue;
          }
          const double iou = MotIou(a, b);
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
        if (is_distractor(g[e.row])) remove_hyp[e.col] = 1;
      }
    }
    frame.gt.reserve(g.size());
    for (const MotRow* row : g) {
      bool keep = true;
      if (options.preprocess) {
        // int(conf) == 0 drops the row (TrackEval: astype(int), truncation).
        keep = std::trunc(row->conf) != 0.0;
        if (mot17) keep = keep && class_is(row, options.evaluated_class);
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
  WriteTextFile(path, FormatMotGroundTruth(rows));
}
void WriteMotTracks(const std::string& path, const std::vector<MotRow>& rows) {
  WriteTextFile(path, FormatMotTracks(rows));
}

}  // namespace hcpf::metrics
