#include "hcpf/metrics/mot_io.h"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include "../src/mot_io_internal.h"
#include "hcpf/core/error.h"
#include "hcpf/core/rng.h"
#include "hcpf/metrics/mot_metrics.h"
#include "support/process.h"

namespace hcpf::metrics {
namespace {

// Expects an InputError whose message contains every fragment.
void ExpectInputError(const std::string& text, MotFileKind kind, std::optional<int> seq_length,
                      std::initializer_list<const char*> fragments) {
  try {
    ParseMotText(text, "f.txt", kind, seq_length);
    ADD_FAILURE() << "no error for:\n" << text;
  } catch (const InputError& e) {
    const std::string message = e.what();
    for (const char* f : fragments) EXPECT_NE(message.find(f), std::string::npos) << message;
  }
}

TEST(MotIo, ReadsMot17GroundTruthColumns) {
  const MotFile f =
      ParseMotText("1,5,10.5,20,30,40,1,7,0.25\n", "gt.txt", MotFileKind::kGroundTruth, 3);
  ASSERT_EQ(f.rows.size(), 1u);
  EXPECT_EQ(f.num_columns, 9);
  const MotRow& r = f.rows[0];
  EXPECT_EQ(r.frame, 1);
  EXPECT_EQ(r.id, 5);
  EXPECT_EQ(r.box, (BoxPx{10.5, 20, 30, 40}));
  EXPECT_EQ(r.conf, 1.0);
  EXPECT_EQ(r.col8, 7.0);
  EXPECT_EQ(r.col9, 0.25);
  EXPECT_EQ(r.line, 1);
  EXPECT_EQ(ResolveBenchmark(Benchmark::kAuto, f), Benchmark::kMot17);
}

TEST(MotIo, ReadsSixColumnAndWhitespaceRows) {
  const MotFile f =
      ParseMotText("\n2 3 1 2 3 4\n", "gt.txt", MotFileKind::kGroundTruth, std::nullopt);
  ASSERT_EQ(f.rows.size(), 1u);
  EXPECT_EQ(f.rows[0].line, 2);
  EXPECT_EQ(f.rows[0].conf, 1.0);  // no column 7: considered
  EXPECT_EQ(ResolveBenchmark(Benchmark::kAuto, f), Benchmark::kMot15);
}

// The automatic benchmark reads the ground truth's column count: rows of
// two counts are bad input at the first row that differs (a third bad-input
// audit: one 10-column row made a 9-column MOT17 file MOT15, scoring static
// persons and distractors as pedestrians, exit 0). A benchmark given is
// used whatever the counts.
TEST(MotIo, AutoBenchmarkNeedsOneColumnCount) {
  const MotFile f = ParseMotText("1,1,1,1,1,1,1,1,1\n2,1,1,1,1,1,1,1,1\n3,1,1,1,1,1,1,8,1,0\n",
                                 "gt.txt", MotFileKind::kGroundTruth, std::nullopt);
  try {
    ResolveBenchmark(Benchmark::kAuto, f);
    ADD_FAILURE() << "mixed column counts accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()),
              "gt.txt:3: --benchmark auto: expected ground-truth rows of one column count (9: "
              "MOT17 rules; 6 or 10: MOT15 rules), found a row of 10 columns where the first row "
              "has 9 (pass --benchmark MOT17 or MOT15, or mend the file)");
  }
  EXPECT_EQ(ResolveBenchmark(Benchmark::kMot17, f), Benchmark::kMot17);
  EXPECT_EQ(ResolveBenchmark(Benchmark::kMot15, f), Benchmark::kMot15);
}

// The error message of ParseMotText on `text`, or "" when it parses.
std::string ErrorOf(const std::string& text, MotFileKind kind, std::optional<int> seq_length) {
  try {
    ParseMotText(text, "f.txt", kind, seq_length);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(MotIo, BadRowsNameFileLineAndColumn) {
  ExpectInputError("1,1,1,1,1,1\n1,2,x,1,1,1\n", MotFileKind::kTracks, 5,
                   {"f.txt:2:3", "column 3 (x)", "a finite number", "\"x\""});
  ExpectInputError("1,1,1,1,1\n", MotFileKind::kTracks, 5, {"f.txt:1", "at least 6", "5 columns"});
  // Two signs are no number ("+-3" was read as -3), and a byte-order mark is
  // named (it was printed raw, invisible): a bad-input audit.
  ExpectInputError("1,1,+-3,1,1,1\n", MotFileKind::kTracks, 5,
                   {"f.txt:1:3", "a finite number", "\"+-3\""});
  ExpectInputError(
      "\xEF\xBB\xBF"
      "1,1,1,1,1,1\n",
      MotFileKind::kTracks, 5,
      {"f.txt:1:1", "found \"\\uFEFF1\" (a byte-order mark, U+FEFF, starts the file"});
  ExpectInputError("1,1,1,1,1,1,1,1,1,1,1\n", MotFileKind::kTracks, 5, {"f.txt:1", "at most 10"});
  ExpectInputError("6,1,1,1,1,1\n", MotFileKind::kTracks, 5, {"f.txt:1:1", "1..5", "found 6"});
  ExpectInputError("0,1,1,1,1,1\n", MotFileKind::kGroundTruth, 5, {"f.txt:1:1", "found 0"});
  ExpectInputError("1,1,1,1,1,1\n2,1,1,1,1,1\n1,1,5,5,1,1\n", MotFileKind::kTracks, 5,
                   {"f.txt:3:2", "unique within frame 1", "first on line 1"});
  ExpectInputError("1,1,1,1,1,1,0.9,2,-1,-1\n", MotFileKind::kTracks, 5, {"f.txt:1:8", "found 2"});
  // A tracker class is truncated as TrackEval truncates it (astype(int)):
  // 1.5 and 1.99 are class 1 and accepted, as are 0 and -7; 2.0 is refused.
  EXPECT_EQ(ErrorOf("1,1,1,1,1,1,0.9,1.5,-1,-1\n2,1,1,1,1,1,0.9,1.99,-1,-1\n"
                    "3,1,1,1,1,1,0.9,0,-1,-1\n4,1,1,1,1,1,0.9,-7,-1,-1\n",
                    MotFileKind::kTracks, 5),
            "");
  ExpectInputError("1,1,1,1,1,1,0.9,2.0,-1,-1\n", MotFileKind::kTracks, 5,
                   {"f.txt:1:8", "a class of at most 1", "found 2"});
}

// TrackEval keys frames by the text of column 1 and refuses a key other than
// "1".."seqLength" (MotChallenge2DBox._load_raw_file: "invalid timesteps"),
// so a frame written "4.0", "4.5", "04", "+4" or "4e0" is refused at its line
// (it was read as frame 4), by the fast path and the general one alike (the
// second file is whitespace separated); a plain "4" with blanks around it is
// read.
TEST(MotIo, FramesAreWrittenAsTrackEvalComparesThem) {
  for (const char* frame : {"4.0", "4.5", "04", "+4", "4e0", "4."}) {
    for (const char* sep : {",", " "}) {
      std::string row = std::string("1,1,1,1,1,1\n") + frame + ",2,1,1,1,1\n";
      if (std::string(sep) == " ") std::replace(row.begin(), row.end(), ',', ' ');
      const std::string e = ErrorOf(row, MotFileKind::kTracks, 5);
      EXPECT_NE(e.find("f.txt:2:1: column 1 (frame): expected a frame written as TrackEval reads "
                       "it"),
                std::string::npos)
          << frame << " sep '" << sep << "': " << e;
      EXPECT_NE(e.find(std::string("found \"") + frame + "\""), std::string::npos) << e;
    }
  }
  EXPECT_EQ(ErrorOf("  4 ,2,1,1,1,1\n10,3,1,1,1,1\n", MotFileKind::kTracks, 10), "");
  // Out of range keeps its own message.
  EXPECT_NE(ErrorOf("0,1,1,1,1,1\n", MotFileKind::kTracks, 5).find("expected a frame in 1..5"),
            std::string::npos);
}

// Unusual but valid spellings, worked out by hand: blanks and tabs around fields,
// CRLF line ends, a trailing comma, '+' signs, exponents, a leading '.', an
// integer id beyond 2^53 (kept exactly), a fractional id (truncated), a
// whitespace-separated line between comma lines, and a last line without '\n'.
TEST(MotIo, UnusualSpellingsParseAsWritten) {
  const std::string text =
      " 1 , 7 ,\t1.5,2e1, 30 ,40\r\n"           // line 1: 6 columns, blanks, CRLF
      "2,9007199254740993,+3,.5,1E+2,4,0.9,\n"  // line 2: 7 columns + trailing comma
      "\n"                                      // line 3: empty
      "3 8.9 1 2 3 4 1 -1 -1 -1\n"              // line 4: whitespace separated, 10 columns
      "4,-2,1,2,3,4,1,1,0.5";                   // line 5: no final newline
  const MotFile f = ParseMotText(text, "t.txt", MotFileKind::kTracks, 4);
  ASSERT_EQ(f.rows.size(), 4u);
  EXPECT_EQ(f.num_columns, 10);
  EXPECT_EQ(f.rows[0], (MotRow{.frame = 1, .id = 7, .box = {1.5, 20, 30, 40}, .line = 1}));
  EXPECT_EQ(
      f.rows[1],
      (MotRow{
          .frame = 2, .id = 9007199254740993, .box = {3, 0.5, 100, 4}, .conf = 0.9, .line = 2}));
  // 8.9 is read as TrackEval reads it, 8, and marked as no whole number.
  EXPECT_EQ(
      f.rows[2],
      (MotRow{.frame = 3, .id = 8, .box = {1, 2, 3, 4}, .conf = 1, .line = 4, .id_whole = false}));
  EXPECT_EQ(f.rows[3], (MotRow{.frame = 4,
                               .id = -2,
                               .box = {1, 2, 3, 4},
                               .conf = 1,
                               .col8 = 1,
                               .col9 = 0.5,
                               .line = 5}));
}

// Duplicate ids: the error names the smallest repeated (frame, id) at its second
// line, whatever the order of the file. Worked by hand:
//   unsorted rows, frame 3 has id 1 twice (lines 1, 2), frame 2 has id 6 twice (lines 4, 6)
//   and id 5 twice (lines 5, 7): smallest frame 2, smallest id 5 -> line 7, first on line 5.
TEST(MotIo, DuplicateIdErrorIsTheSmallestFrameAndId) {
  const std::string text =
      "3,1,0,0,1,1\n3,1,0,0,1,1\n1,5,0,0,1,1\n2,6,0,0,1,1\n2,5,0,0,1,1\n2,6,0,0,1,1\n2,5,0,0,1,1\n";
  const std::string message = ErrorOf(text, MotFileKind::kTracks, 3);
  EXPECT_NE(message.find("f.txt:7:2"), std::string::npos) << message;
  EXPECT_NE(message.find("unique within frame 2"), std::string::npos) << message;
  EXPECT_NE(message.find("id 5 again (first on line 5)"), std::string::npos) << message;
  // Huge frame numbers (no seq_length): frame 900000000 with ids 4, 4 on lines 2, 3.
  const std::string huge = "5,4,0,0,1,1\n900000000,4,0,0,1,1\n900000000,4,0,0,1,1\n5,3,0,0,1,1\n";
  const std::string m2 = ErrorOf(huge, MotFileKind::kTracks, std::nullopt);
  EXPECT_NE(m2.find("f.txt:3:2"), std::string::npos) << m2;
  EXPECT_NE(m2.find("first on line 2"), std::string::npos) << m2;
  // A frame with 60 rows (ids 0..59) where id 17 comes back on line 61 (first on line 18).
  std::string big;
  for (int i = 0; i < 60; ++i) big += "1," + std::to_string(i) + ",0,0,1,1\n";
  big += "1,17,0,0,1,1\n";
  const std::string m3 = ErrorOf(big, MotFileKind::kTracks, 1);
  EXPECT_NE(m3.find("f.txt:61:2"), std::string::npos) << m3;
  EXPECT_NE(m3.find("first on line 18"), std::string::npos) << m3;
  EXPECT_EQ(ErrorOf(big.substr(0, big.rfind("1,17")), MotFileKind::kTracks, 1), "");
}

// A detector's output (det.txt) writes -1 for every id: ids are not
// identities there, so repeating one in a frame is no error; the same text as
// tracker output is.
TEST(MotIo, DetectionsMayRepeatAnIdInAFrame) {
  const std::string text = "1,-1,0,0,4,4,0.9,-1,-1,-1\n1,-1,8,8,4,4,0.5,-1,-1,-1\n";
  const MotFile det = ParseMotText(text, "det.txt", MotFileKind::kDetections, 1);
  ASSERT_EQ(det.rows.size(), 2u);
  EXPECT_EQ(det.rows[1].conf, 0.5);
  EXPECT_EQ(det.rows[1].line, 2);
  EXPECT_EQ(internal::ParseMotTextReference(text, "det.txt", MotFileKind::kDetections, 1).rows,
            det.rows);
  EXPECT_NE(ErrorOf(text, MotFileKind::kTracks, 1).find("id -1 again (first on line 1)"),
            std::string::npos);
}

// ParseMotText (in-place fast path + grouped duplicate check) against the
// straightforward reference reader on random lines built from valid and invalid
// pieces: both must give the same rows, or the same error message.
TEST(MotIo, AgreesWithReferenceReaderOnRandomText) {
  const char* kNumbers[] = {"1",
                            "2",
                            "3",
                            "0",
                            "-1",
                            "17",
                            "1.5",
                            "2.25e1",
                            ".5",
                            "5.",
                            "+4",
                            "1E2",
                            "9007199254740993",
                            "123456789012345678901",
                            "1e400",
                            "nan",
                            "inf",
                            "0x10",
                            "1e",
                            "-",
                            "",
                            "x",
                            "3.14159265358979",
                            "-0",
                            "2.000000000000001",
                            "-.5",
                            ".",
                            "-5.",
                            "0.1",
                            "123456789012345",
                            "1234567890123456",
                            "000000000000000001",
                            "-9223372036854775808",
                            "1e-5",
                            "4.9e-324",
                            "9.87654321098765",
                            "1.2.3",
                            "--1"};
  const char* kBlanks[] = {"", "", "", " ", "\t", "  "};
  Rng rng(7);
  int parsed = 0;
  int failed = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    std::string text;
    const int lines = 1 + static_cast<int>(rng.UniformInt(6));
    for (int l = 0; l < lines; ++l) {
      if (rng.Bernoulli(0.1)) {
        text += rng.Bernoulli(0.5) ? "\n" : "  \r\n";
        continue;
      }
      const bool spaces = rng.Bernoulli(0.1);
      const int columns = 4 + static_cast<int>(rng.UniformInt(8));
      for (int c = 0; c < columns; ++c) {
        if (c > 0) text += spaces ? " " : ",";
        text += kBlanks[rng.UniformInt(std::size(kBlanks))];
        // Mostly valid numbers so that many texts parse; frames 1..3, ids 1..4.
        if (c == 0 && rng.Bernoulli(0.9)) {
          text += std::to_string(1 + rng.UniformInt(3));
        } else if (c == 1 && rng.Bernoulli(0.8)) {
          text += std::to_string(1 + rng.UniformInt(4));
        } else if (c == 7 && rng.Bernoulli(0.7)) {
          text += "-1";
        } else if (rng.Bernoulli(0.85)) {
          text += kNumbers[rng.UniformInt(13)];
        } else {
          text += kNumbers[rng.UniformInt(std::size(kNumbers))];
        }
        text += kBlanks[rng.UniformInt(std::size(kBlanks))];
      }
      if (rng.Bernoulli(0.1)) text += ",";
      if (rng.Bernoulli(0.2)) text += "\r";
      if (l + 1 < lines || rng.Bernoulli(0.5)) text += "\n";
    }
    const MotFileKind kind = std::array{MotFileKind::kTracks, MotFileKind::kGroundTruth,
                                        MotFileKind::kDetections}[rng.UniformInt(3)];
    const std::optional<int> length = rng.Bernoulli(0.5) ? std::optional<int>(3) : std::nullopt;
    std::string expected_error;
    MotFile expected;
    try {
      expected = internal::ParseMotTextReference(text, "f.txt", kind, length);
    } catch (const InputError& e) {
      expected_error = e.what();
    }
    if (expected_error.empty()) {
      ++parsed;
      const MotFile got = ParseMotText(text, "f.txt", kind, length);
      EXPECT_EQ(got.num_columns, expected.num_columns) << text;
      EXPECT_EQ(got.rows, expected.rows) << text;
    } else {
      ++failed;
      EXPECT_EQ(ErrorOf(text, kind, length), expected_error) << text;
    }
  }
  // Both outcomes must be exercised for the comparison to mean something.
  EXPECT_GT(parsed, 300);
  EXPECT_GT(failed, 300);
}

// Plain decimals of 1..20 digits with the point anywhere (the reader's own
// decimal path up to 18 digits, including its extended-precision branch and the
// halfway cases it hands back, std::from_chars above) must give the same
// doubles as the reference reader, which parses every field with std::from_chars.
// About 2^-11 of the 16-18 digit numbers are halfway cases, so the 240k numbers
// here include dozens of them.
TEST(MotIo, DecimalsMatchFromChars) {
  Rng rng(11);
  std::string text;
  for (int line = 0; line < 60000; ++line) {
    text += "1," + std::to_string(line + 1);
    for (int c = 0; c < 4; ++c) {
      const int digits = 1 + static_cast<int>(rng.UniformInt(20));
      std::string number;
      for (int d = 0; d < digits; ++d) number += static_cast<char>('0' + rng.UniformInt(10));
      const int point = static_cast<int>(rng.UniformInt(static_cast<uint64_t>(digits) + 2)) - 1;
      if (point >= 0) number.insert(static_cast<size_t>(point), ".");
      if (rng.Bernoulli(0.3)) number.insert(0, "-");
      text += "," + number;
    }
    text += "\n";
  }
  const MotFile got = ParseMotText(text, "f.txt", MotFileKind::kTracks, 1);
  const MotFile expected = internal::ParseMotTextReference(text, "f.txt", MotFileKind::kTracks, 1);
  ASSERT_EQ(got.rows.size(), 60000u);
  for (size_t i = 0; i < got.rows.size(); ++i) {
    // Bitwise equality (operator== on doubles would equate 0.0 and -0.0).
    const BoxPx& a = got.rows[i].box;
    const BoxPx& b = expected.rows[i].box;
    ASSERT_EQ(std::memcmp(&a, &b, sizeof(BoxPx)), 0) << "line " << i + 1;
  }
}

TEST(MotIo, SeqInfo) {
  const SeqInfo info = ParseSeqInfo("[Sequence]\nname=A\nseqLength=42\nframeRate=25\n", "s.ini");
  EXPECT_EQ(info.name, "A");
  EXPECT_EQ(info.seq_length, 42);
  EXPECT_EQ(info.frame_rate, 25.0);
  EXPECT_THROW(ParseSeqInfo("[Sequence]\nname=A\n", "s.ini"), InputError);
  try {
    ParseSeqInfo("[Sequence]\nseqLength=abc\n", "s.ini");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("s.ini:2"), std::string::npos) << e.what();
  }
  // A key given twice is refused, as TrackEval's configparser refuses it (a
  // bad-input audit found the last seqLength taken silently).
  try {
    ParseSeqInfo("[Sequence]\nseqLength=40\nname=A\nseqLength=400\n", "s.ini");
    ADD_FAILURE();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("s.ini:4: Sequence.seqLength: expected each key once in "
                                         "[Sequence] (names without regard to case), found "
                                         "seqLength again (first at line 2)"),
              std::string::npos)
        << e.what();
  }
}

// seqinfo.ini as TrackEval's configparser reads it: option names without
// regard to case, ':' as well as '=', a section or option given twice and
// an option before any section refused; [sequence] is another section.
TEST(MotIo, SeqInfoIsReadAsConfigparserReadsIt) {
  EXPECT_EQ(ParseSeqInfo("[Sequence]\nSEQLENGTH=7\n", "s.ini").seq_length, 7);
  EXPECT_EQ(ParseSeqInfo("; c\n[Other]\nx=1\n[Sequence]\nseqLength : 9\nframerate: 30\n", "s.ini")
                .seq_length,
            9);
  const auto error = [](const std::string& text) {
    try {
      ParseSeqInfo(text, "s.ini");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error("[Sequence]\nseqLength=7\nseqlength=8\n")
                .find("s.ini:3: Sequence.seqlength: expected each key once"),
            std::string::npos);
  EXPECT_NE(error("[Sequence]\nseqLength=7\n[Sequence]\nname=x\n")
                .find("s.ini:3: expected each section once, found [Sequence] again (first at line "
                      "1)"),
            std::string::npos);
  EXPECT_NE(error("seqLength=7\n[Sequence]\nseqLength=7\n")
                .find("s.ini:1: expected a section header ([Sequence]) before the first key"),
            std::string::npos);
  EXPECT_NE(error("[sequence]\nseqLength=7\n").find("expected a [Sequence] section"),
            std::string::npos);
}

// MOT17 preprocessing, worked by hand on one frame:
//   gt a: id 1, class 1, consider 1 at (1,1,10,10)     -> kept
//   gt b: id 2, class 7 (static person) at (101,1,10,10) -> dropped (class)
//   gt c: id 3, class 1, consider 0 at (201,1,10,10)    -> dropped (zero-marked)
//   hyp 10 on a, hyp 20 on b (IoU 1 with a distractor -> removed), hyp 30 on c
//   (not a distractor class -> kept, becomes an FP later).
TEST(MotIo, Mot17PreprocessingRemovesDistractorMatches) {
  const MotFile gt =
      ParseMotText("1,1,1,1,10,10,1,1,1\n1,2,101,1,10,10,1,7,1\n1,3,201,1,10,10,0,1,1\n", "gt.txt",
                   MotFileKind::kGroundTruth, 1);
  const MotFile hyp = ParseMotText(
      "1,10,1,1,10,10,1,-1,-1,-1\n1,20,101,1,10,10,1,-1,-1,-1\n1,30,201,1,10,10,1,-1,-1,-1\n",
      "hyp.txt", MotFileKind::kTracks, 1);
  int64_t removed_gt = 0, removed_hyp = 0;
  const Sequence seq =
      BuildSequence(gt, hyp, 1, Benchmark::kMot17, {}, "s", &removed_gt, &removed_hyp);
  ASSERT_EQ(seq.frames.size(), 1u);
  ASSERT_EQ(seq.frames[0].gt.size(), 1u);
  EXPECT_EQ(seq.frames[0].gt[0].id, 1);
  ASSERT_EQ(seq.frames[0].hyp.size(), 2u);
  EXPECT_EQ(seq.frames[0].hyp[0].id, 10);
  EXPECT_EQ(seq.frames[0].hyp[1].id, 30);
  EXPECT_EQ(removed_gt, 2);
  EXPECT_EQ(removed_hyp, 1);
  // MOT15 rules on the same files keep all hyps and every gt with int(conf) != 0.
  const Sequence seq15 = BuildSequence(gt, hyp, 1, Benchmark::kMot15);
  EXPECT_EQ(seq15.frames[0].gt.size(), 2u);
  EXPECT_EQ(seq15.frames[0].hyp.size(), 3u);
}

TEST(MotIo, WritersRoundTrip) {
  std::vector<MotRow> rows = {
      {.frame = 1, .id = 4, .box = {1.5, 2, 3.25, 4}, .conf = 1, .col8 = 1, .col9 = 0.5},
      {.frame = 2,
       .id = 9007199254740993,
       .box = {0.1, 0.2, 0.3, 0.4},
       .conf = 0,
       .col8 = 7,
       .col9 = 1}};
  const std::string gt_text = FormatMotGroundTruth(rows);
  EXPECT_EQ(gt_text.substr(0, gt_text.find('\n')), "1,4,1.5,2,3.25,4,1,1,0.5");
  const MotFile back = ParseMotText(gt_text, "gt.txt", MotFileKind::kGroundTruth, 2);
  ASSERT_EQ(back.rows.size(), 2u);
  for (size_t i = 0; i < rows.size(); ++i) {
    rows[i].line = static_cast<int>(i + 1);
    rows[i].col10 = -1;
    EXPECT_EQ(back.rows[i], rows[i]);
  }
  const std::string tracks = FormatMotTracks(rows);
  EXPECT_EQ(tracks.substr(0, tracks.find('\n')), "1,4,1.5,2,3.25,4,1,-1,-1,-1");
  const auto dir = hcpf::testing::FreshDir("metrics-io");
  WriteSeqInfo((dir / "seqinfo.ini").string(), {.name = "x", .seq_length = 7});
  EXPECT_EQ(ReadSeqInfo((dir / "seqinfo.ini").string()).seq_length, 7);
  WriteMotTracks((dir / "t.txt").string(), rows);
  EXPECT_EQ(ReadMotFile((dir / "t.txt").string(), MotFileKind::kTracks, 2).rows.size(), 2u);
  EXPECT_THROW(ReadMotFile((dir / "missing.txt").string(), MotFileKind::kTracks), InputError);
  // A file that cannot be written says why (it said only "cannot write" or
  // "error while writing", and a short write leaked the open file).
  try {
    WriteMotTracks((dir / "no" / "t.txt").string(), rows);
    ADD_FAILURE() << "written into a folder that does not exist";
  } catch (const RunError& e) {
    EXPECT_NE(std::string(e.what()).find(std::strerror(ENOENT)), std::string::npos) << e.what();
  }
}

// Issue 15 item 17: an integer id is taken exactly at both ends of int64_t
// (the range check ran on the double, which rounds 2^63 - 1 up to 2^63).
TEST(MotIo, IdsAtTheEndsOfInt64AreExact) {
  const MotFile f = ParseMotText("1,9223372036854775807,0,0,1,1\n1,-9223372036854775808,0,0,1,1\n",
                                 "t.txt", MotFileKind::kTracks, std::nullopt);
  ASSERT_EQ(f.rows.size(), 2u);
  EXPECT_EQ(f.rows[0].id, std::numeric_limits<int64_t>::max());
  EXPECT_EQ(f.rows[1].id, std::numeric_limits<int64_t>::min());
  // A non-integer spelling still goes through the double and its range check.
  ExpectInputError("1,1e19,0,0,1,1\n", MotFileKind::kTracks, std::nullopt,
                   {"f.txt:1:2", "an integer id within 64 bits"});
}

// Issue 15 item 7: a file of one repeated line stops keeping rows at the first
// repeat; the error is still the first duplicate (line 2), and a smaller
// duplicate after it (an earlier frame, or a smaller id of the same frame) is
// still the one reported, as the reference reader would.
TEST(MotIo, RepeatedLinesAreFoundWhileStreaming) {
  std::string repeated;
  for (int i = 0; i < 20000; ++i) repeated += "7,3,0,0,1,1\n";
  EXPECT_EQ(ErrorOf(repeated, MotFileKind::kTracks, std::nullopt),
            "f.txt:2:2: column 2 (id): expected ids unique within frame 7, found id 3 again "
            "(first on line 1)");
  for (const std::string& text :
       {repeated + "7,2,0,0,1,1\n7,2,0,0,1,1\n",
        repeated + "5,9,0,0,1,1\n6,1,0,0,1,1\n5,9,0,0,1,1\n",
        repeated + "7,1,0,0,1,1\n8,1,0,0,1,1\n7,1,0,0,1,1\n", repeated + "7,3,0,0,1,x\n"}) {
    std::string expected;
    try {
      internal::ParseMotTextReference(text, "f.txt", MotFileKind::kTracks, std::nullopt);
    } catch (const InputError& e) {
      expected = e.what();
    }
    EXPECT_FALSE(expected.empty());
    EXPECT_EQ(ErrorOf(text, MotFileKind::kTracks, std::nullopt), expected);
  }
}

// Issue 15 item 7: the sparse form keeps only frames with a box, with their
// numbers; frame numbers near 10^9 cost what their rows cost.
TEST(MotIo, SparseSequenceKeepsFramesWithBoxes) {
  const MotFile gt = ParseMotText("999999999,1,0,0,10,10\n3,1,0,0,10,10\n", "gt.txt",
                                  MotFileKind::kGroundTruth, std::nullopt);
  const MotFile hyp = ParseMotText("5,1,0,0,10,10\n999999999,2,0,0,10,10\n", "t.txt",
                                   MotFileKind::kTracks, std::nullopt);
  PreprocessOptions sparse;
  sparse.sparse = true;
  const Sequence seq = BuildSequence(gt, hyp, 1000000000, Benchmark::kMot15, sparse);
  EXPECT_TRUE(seq.sparse());
  EXPECT_EQ(seq.NumFrames(), 1000000000);
  EXPECT_EQ(seq.numbers, (std::vector<int>{3, 5, 999999999}));
  ASSERT_EQ(seq.frames.size(), 3u);
  EXPECT_EQ(seq.frames[0].gt.size(), 1u);
  EXPECT_EQ(seq.frames[0].hyp.size(), 0u);
  EXPECT_EQ(seq.frames[1].hyp.size(), 1u);
  EXPECT_EQ(seq.frames[2].gt[0].id, 1);
  EXPECT_EQ(seq.frames[2].hyp[0].id, 2);
  EXPECT_EQ(seq.FrameNumber(2), 999999999);
}

// Random sequences with empty stretches: the sparse form gives exactly the
// dense form's MOT metrics and events (frame numbers included).
TEST(MotIo, SparseAndDenseSequencesScoreTheSame) {
  Rng rng(23);
  for (int trial = 0; trial < 40; ++trial) {
    const int length = 30 + static_cast<int>(rng.UniformInt(40));
    std::string gt_text;
    std::string hyp_text;
    for (int t = 1; t <= length; ++t) {
      if (rng.Bernoulli(0.4)) continue;  // an empty frame, or a stretch of them
      for (int id = 1; id <= 4; ++id) {
        const double x = 10.0 * id + rng.Uniform(-3, 3);
        if (rng.Bernoulli(0.7)) gt_text += fmt::format("{},{},{},5,8,8,1,-1,-1,-1\n", t, id, x);
        if (rng.Bernoulli(0.7)) {
          hyp_text += fmt::format("{},{},{},5,8,8,1,-1,-1,-1\n", t,
                                  rng.Bernoulli(0.9) ? id : id + 10, x + rng.Uniform(-2, 2));
        }
      }
    }
    const MotFile gt = ParseMotText(gt_text, "gt.txt", MotFileKind::kGroundTruth, length);
    const MotFile hyp = ParseMotText(hyp_text, "t.txt", MotFileKind::kTracks, length);
    PreprocessOptions sparse_options;
    sparse_options.sparse = true;
    const Sequence dense = BuildSequence(gt, hyp, length, Benchmark::kMot15);
    const Sequence sparse = BuildSequence(gt, hyp, length, Benchmark::kMot15, sparse_options);
    EXPECT_LT(sparse.frames.size(), dense.frames.size());
    std::vector<MotEvent> dense_events;
    std::vector<MotEvent> sparse_events;
    const NamedMetrics a = ToNamedMetrics(ComputeAll(dense, &dense_events));
    const NamedMetrics b = ToNamedMetrics(ComputeAll(sparse, &sparse_events));
    EXPECT_EQ(a.scalars, b.scalars);
    EXPECT_EQ(a.arrays, b.arrays);
    EXPECT_EQ(dense_events, sparse_events);
  }
}

// Issue 15 item 8: a directory or a FIFO is refused before anything is read
// (a directory gave std::bad_alloc, a FIFO hung).
TEST(MotIo, NonRegularFilesAreRefused) {
  const auto dir = hcpf::testing::FreshDir("metrics-nonregular");
  std::filesystem::create_directories(dir / "gt.txt");
  try {
    ReadMotFile((dir / "gt.txt").string(), MotFileKind::kGroundTruth);
    ADD_FAILURE() << "a directory was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("found a directory"), std::string::npos) << e.what();
  }
  const std::string fifo = (dir / "fifo.txt").string();
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  try {
    ReadMotFile(fifo, MotFileKind::kTracks);
    ADD_FAILURE() << "a FIFO was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("found a FIFO"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ReadSeqInfo(fifo), InputError);
  EXPECT_THROW(ReadMotFile("/dev/zero", MotFileKind::kTracks), InputError);
}

// Found by the fuzzer (fuzz/regressions/mot): a class or conf beyond int's
// range was converted to int (undefined behaviour). Such a class is no class;
// a huge conf is non-zero. In a frame without tracker boxes the rows of no
// class are dropped as non-pedestrians; in one with tracker boxes TrackEval
// refuses them (its "invalid gt classes" check), and so does BuildSequence,
// at the first such row.
TEST(MotIo, HugeClassAndConfValuesAreNotConvertedToInt) {
  const MotFile gt =
      ParseMotText("1,1,1,2,3,6,1e30,1,1\n1,2,1,2,3,6,1,1e10,1\n1,3,50,50,3,6,1,-7777777710,1\n",
                   "gt.txt", MotFileKind::kGroundTruth, 1);
  const MotFile no_hyp = ParseMotText("", "t.txt", MotFileKind::kTracks, 1);
  int64_t removed_gt = 0;
  int64_t removed_hyp = 0;
  const Sequence seq =
      BuildSequence(gt, no_hyp, 1, Benchmark::kMot17, {}, "s", &removed_gt, &removed_hyp);
  ASSERT_EQ(seq.frames.size(), 1u);
  ASSERT_EQ(seq.frames[0].gt.size(), 1u);  // only the class-1 row, kept by its conf 1e30
  EXPECT_EQ(seq.frames[0].gt[0].id, 1);
  EXPECT_EQ(removed_gt, 2);
  EXPECT_EQ(removed_hyp, 0);

  const MotFile hyp = ParseMotText("1,9,50,50,3,6,1,-1,-1,-1\n", "t.txt", MotFileKind::kTracks, 1);
  try {
    BuildSequence(gt, hyp, 1, Benchmark::kMot17, {}, "s");
    FAIL() << "a class of 1e10 beside tracker boxes was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where().line, 2) << e.what();
    EXPECT_NE(std::string(e.what()).find("expected a MOTChallenge class 1..13"), std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("found 10000000000"), std::string::npos) << e.what();
  }
}

// TrackEval's check of gt classes (MotChallenge2DBox.get_preprocessed_seq_data)
// runs only when it preprocesses (MOT16/17/20, not MOT15) a frame holding gt
// and tracker boxes; it truncates the class (astype(int)) and accepts its 13
// classes. Class 0 and 14 beside a tracker box are refused at their line;
// 13.9 (class 13, crowd) is accepted; class 14 in a frame without tracker
// boxes is dropped as a non-pedestrian, and MOT15 rules read no class.
TEST(MotIo, GroundTruthClassesOutsideTrackEvalsThirteenAreRefusedWhereItChecks) {
  const MotFile hyp = ParseMotText("1,9,50,50,3,6,1,-1,-1,-1\n", "t.txt", MotFileKind::kTracks, 2);
  for (const char* cls : {"0", "14", "-1"}) {
    const MotFile gt = ParseMotText(std::string("1,1,1,2,3,6,1,1,1\n1,2,1,2,3,6,1,") + cls + ",1\n",
                                    "gt.txt", MotFileKind::kGroundTruth, 2);
    try {
      BuildSequence(gt, hyp, 2, Benchmark::kMot17, {}, "s");
      FAIL() << "class " << cls << " accepted";
    } catch (const InputError& e) {
      EXPECT_EQ(e.where().file, "gt.txt");
      EXPECT_EQ(e.where().line, 2) << e.what();
      EXPECT_EQ(e.where().key, "column 8 (class)");
    }
    // MOT15 rules: no classes, nothing refused.
    EXPECT_NO_THROW(BuildSequence(gt, hyp, 2, Benchmark::kMot15, {}, "s"));
    // Without preprocessing nothing is filtered and nothing checked.
    PreprocessOptions none;
    none.preprocess = false;
    EXPECT_NO_THROW(BuildSequence(gt, hyp, 2, Benchmark::kMot17, none, "s"));
  }
  const MotFile crowd = ParseMotText("1,1,1,2,3,6,1,13.9,1\n2,1,1,2,3,6,1,14,1\n", "gt.txt",
                                     MotFileKind::kGroundTruth, 2);
  int64_t removed_gt = 0;
  const Sequence seq = BuildSequence(crowd, hyp, 2, Benchmark::kMot17, {}, "s", &removed_gt);
  EXPECT_EQ(removed_gt, 2);  // frame 1: a crowd row (not a pedestrian); frame 2: no tracker box
}

}  // namespace
}  // namespace hcpf::metrics
