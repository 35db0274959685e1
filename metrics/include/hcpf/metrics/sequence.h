#pragma once
// The input of the standard (box) metrics: ground-truth and hypothesis boxes
// per frame. Plain data; ids are arbitrary 64-bit integers (unique within a
// frame on each side), relabelled internally.

#include <cstdint>
#include <string>
#include <vector>

#include "hcpf/core/types.h"

namespace hcpf::metrics {

struct LabelledBox {
  int64_t id = 0;
  BoxPx box;
  friend bool operator==(const LabelledBox&, const LabelledBox&) = default;
};

struct SequenceFrame {
  std::vector<LabelledBox> gt;
  std::vector<LabelledBox> hyp;
};

// Dense form: frames[t] holds frame t + 1 of a MOT file (frame index t when
// built in memory); a frame may be empty on either side. Sparse form (what
// `hcpf score` builds, so a sequence of 10^9 frames costs what its rows cost):
// `numbers` is not empty, frames[t] is frame numbers[t] (increasing), and the
// other frames of the `length` are empty on both sides. The MOT metrics give
// the same results for both forms (like TrackEval they skip a frame with no
// box); the point metrics need the dense form (GOSPA switches and per-frame
// series see every frame). Metrics run over frames in increasing order.
struct Sequence {
  std::string name;
  std::vector<SequenceFrame> frames;
  // Sparse form only (length >= 0): frame numbers of frames[], and the number
  // of frames in the sequence.
  std::vector<int> numbers;
  int length = -1;

  bool sparse() const { return length >= 0; }
  // The 1-based frame number of frames[t].
  int FrameNumber(size_t t) const { return sparse() ? numbers[t] : static_cast<int>(t) + 1; }
  // Frames in the sequence, empty ones included.
  int NumFrames() const { return sparse() ? length : static_cast<int>(frames.size()); }
};

// IoU exactly as TrackEval computes it (corners x + w, areas from corners,
// 0 when an area or the union is <= machine epsilon).
double MotIou(const BoxPx& a, const BoxPx& b);

}  // namespace hcpf::metrics
