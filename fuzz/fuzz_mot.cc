// libFuzzer target `mot`: MOTChallenge ground-truth and tracker text
// (ParseMotText) and the TrackEval preprocessing (BuildSequence).
//
// Input: two header bytes, then the text.
//   byte 0, bit 0: the file kind (0 ground truth, 1 tracks) when there is one file
//           bit 1: the reader knows seqLength (frames must lie in 1..seqLength)
//           bit 2: BuildSequence preprocesses (else keeps every row)
//           bits 3-4: benchmark for BuildSequence (MOT15, MOT17, else auto)
//   byte 1: seqLength - 1
// A text with a '|' is a pair: ground truth before it, tracks after it, and
// when both parse they become a Sequence. Every text is also read by the
// straightforward reference reader, which must agree with the fast one on
// every row, bit for bit, and on every error message (metrics/src/mot_io_internal.h).

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>

#include "fuzz_support.h"
#include "hcpf/metrics/mot_io.h"
#include "mot_io_internal.h"

namespace {

using hcpf::InputError;
using hcpf::fuzz::Fail;
namespace metrics = hcpf::metrics;

bool SameBits(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

bool SameRow(const metrics::MotRow& a, const metrics::MotRow& b) {
  return a.frame == b.frame && a.id == b.id && a.line == b.line &&
         SameBits(a.box.left, b.box.left) && SameBits(a.box.top, b.box.top) &&
         SameBits(a.box.width, b.box.width) && SameBits(a.box.height, b.box.height) &&
         SameBits(a.conf, b.conf) && SameBits(a.col8, b.col8) && SameBits(a.col9, b.col9) &&
         SameBits(a.col10, b.col10) && a.id_whole == b.id_whole;
}

// ParseMotText, checked against the reference reader. nullopt when the text is rejected.
std::optional<metrics::MotFile> Parse(const std::string& text, metrics::MotFileKind kind,
                                      std::optional<int> seq_length) {
  std::optional<metrics::MotFile> fast;
  std::string fast_error;
  try {
    fast = metrics::ParseMotText(text, "fuzz.txt", kind, seq_length);
  } catch (const InputError& e) {
    fast_error = e.what();
  }
  std::optional<metrics::MotFile> reference;
  std::string reference_error;
  try {
    reference = metrics::internal::ParseMotTextReference(text, "fuzz.txt", kind, seq_length);
  } catch (const InputError& e) {
    reference_error = e.what();
  }
  if (fast.has_value() != reference.has_value() || fast_error != reference_error) {
    Fail("ParseMotText and the reference reader disagree: \"" +
         (fast ? std::string("accepted") : fast_error) + "\" vs \"" +
         (reference ? std::string("accepted") : reference_error) + "\"");
  }
  if (!fast) return std::nullopt;
  if (fast->num_columns != reference->num_columns || fast->rows.size() != reference->rows.size()) {
    Fail("ParseMotText and the reference reader disagree on the columns or the row count");
  }
  for (size_t i = 0; i < fast->rows.size(); ++i) {
    if (!SameRow(fast->rows[i], reference->rows[i])) {
      Fail("ParseMotText and the reference reader disagree on the row of line " +
           std::to_string(reference->rows[i].line));
    }
  }
  return fast;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  const uint8_t flags = data[0];
  const int seq_length = 1 + data[1];
  const std::optional<int> known_length =
      (flags & 2) != 0 ? std::optional<int>(seq_length) : std::nullopt;
  const std::string text(reinterpret_cast<const char*>(data) + 2, size - 2);
  const size_t bar = text.find('|');
  hcpf::fuzz::ExpectInputErrorOnly([&] {
    if (bar == std::string::npos) {
      const auto kind =
          (flags & 1) != 0 ? metrics::MotFileKind::kTracks : metrics::MotFileKind::kGroundTruth;
      Parse(text, kind, known_length);
      return;
    }
    const auto gt = Parse(text.substr(0, bar), metrics::MotFileKind::kGroundTruth, known_length);
    const auto tracks = Parse(text.substr(bar + 1), metrics::MotFileKind::kTracks, known_length);
    if (!gt || !tracks) return;
    metrics::PreprocessOptions options;
    options.preprocess = (flags & 4) != 0;
    const int benchmark_bits = (flags >> 3) & 3;
    const metrics::Benchmark benchmark =
        metrics::ResolveBenchmark(benchmark_bits == 0   ? metrics::Benchmark::kMot15
                                  : benchmark_bits == 1 ? metrics::Benchmark::kMot17
                                                        : metrics::Benchmark::kAuto,
                                  *gt);
    int64_t removed_gt = 0;
    int64_t removed_tracks = 0;
    const metrics::Sequence sequence = metrics::BuildSequence(
        *gt, *tracks, seq_length, benchmark, options, "fuzz", &removed_gt, &removed_tracks);
    if (static_cast<int>(sequence.frames.size()) != seq_length || removed_gt < 0 ||
        removed_tracks < 0 || removed_gt > static_cast<int64_t>(gt->rows.size()) ||
        removed_tracks > static_cast<int64_t>(tracks->rows.size())) {
      Fail("BuildSequence: wrong frame count or removed-row counts");
    }
  });
  return 0;
}
