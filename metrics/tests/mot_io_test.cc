#include "hcpf/metrics/mot_io.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "hcpf/core/error.h"

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
  const MotFile f = ParseMotText("1,5,10.5,20,30,40,1,7,0.25\n", "gt.txt", MotFileKind::kGroundTruth, 3);
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
  const MotFile f = ParseMotText("\n2 3 1 2 3 4\n", "gt.txt", MotFileKind::kGroundTruth, std::nullopt);
  ASSERT_EQ(f.rows.size(), 1u);
  EXPECT_EQ(f.rows[0].line, 2);
  EXPECT_EQ(f.rows[0].conf, 1.0);  // no column 7: considered
  EXPECT_EQ(ResolveBenchmark(Benchmark::kAuto, f), Benchmark::kMot15);
}

TEST(MotIo, BadRowsNameFileLineAndColumn) {
  ExpectInputError("1,1,1,1,1,1\n1,2,x,1,1,1\n", MotFileKind::kTracks, 5,
                   {"f.txt:2:3", "column 3 (x)", "a finite number", "\"x\""});
  ExpectInputError("1,1,1,1,1\n", MotFileKind::kTracks, 5, {"f.txt:1", "at least 6", "5 columns"});
  ExpectInputError("1,1,1,1,1,1,1,1,1,1,1\n", MotFileKind::kTracks, 5, {"f.txt:1", "at most 10"});
  ExpectInputError("6,1,1,1,1,1\n", MotFileKind::kTracks, 5, {"f.txt:1:1", "1..5", "found 6"});
  ExpectInputError("0,1,1,1,1,1\n", MotFileKind::kGroundTruth, 5, {"f.txt:1:1", "found 0"});
  ExpectInputError("1,1,1,1,1,1\n2,1,1,1,1,1\n1,1,5,5,1,1\n", MotFileKind::kTracks, 5,
                   {"f.txt:3:2", "unique within frame 1", "first on line 1"});
  ExpectInputError("1,1,1,1,1,1,0.9,2,-1,-1\n", MotFileKind::kTracks, 5, {"f.txt:1:8", "found 2"});
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
}

// MOT17 preprocessing, worked by hand on one frame:
//   gt a: id 1, class 1, consider 1 at (1,1,10,10)     -> kept
//   gt b: id 2, class 7 (static person) at (101,1,10,10) -> dropped (class)
//   gt c: id 3, class 1, consider 0 at (201,1,10,10)    -> dropped (zero-marked)
//   hyp 10 on a, hyp 20 on b (IoU 1 with a distractor -> removed), hyp 30 on c
//   (not a distractor class -> kept, becomes an FP later).
TEST(MotIo, Mot17PreprocessingRemovesDistractorMatches) {
  const MotFile gt = ParseMotText(
      "1,1,1,1,10,10,1,1,1\n1,2,101,1,10,10,1,7,1\n1,3,201,1,10,10,0,1,1\n", "gt.txt",
      MotFileKind::kGroundTruth, 1);
  const MotFile hyp = ParseMotText(
      "1,10,1,1,10,10,1,-1,-1,-1\n1,20,101,1,10,10,1,-1,-1,-1\n1,30,201,1,10,10,1,-1,-1,-1\n",
      "hyp.txt", MotFileKind::kTracks, 1);
  int64_t removed_gt = 0, removed_hyp = 0;
  const Sequence seq = BuildSequence(gt, hyp, 1, Benchmark::kMot17, {}, "s", &removed_gt, &removed_hyp);
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
  std::vector<MotRow> rows = {{.frame = 1, .id = 4, .box = {1.5, 2, 3.25, 4}, .conf = 1, .col8 = 1, .col9 = 0.5},
                              {.frame = 2, .id = 9007199254740993, .box = {0.1, 0.2, 0.3, 0.4}, .conf = 0, .col8 = 7, .col9 = 1}};
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
  const auto dir = std::filesystem::temp_directory_path() / "hcpf_metrics_io_test";
  std::filesystem::create_directories(dir);
  WriteSeqInfo((dir / "seqinfo.ini").string(), {.name = "x", .seq_length = 7});
  EXPECT_EQ(ReadSeqInfo((dir / "seqinfo.ini").string()).seq_length, 7);
  WriteMotTracks((dir / "t.txt").string(), rows);
  EXPECT_EQ(ReadMotFile((dir / "t.txt").string(), MotFileKind::kTracks, 2).rows.size(), 2u);
  EXPECT_THROW(ReadMotFile((dir / "missing.txt").string(), MotFileKind::kTracks), InputError);
}

}  // namespace
}  // namespace hcpf::metrics
