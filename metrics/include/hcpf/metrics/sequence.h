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

// frames[t] holds frame t + 1 of a MOT file (frame index t when built in memory);
// metrics run over frames in increasing order. A frame may be empty on either side.
struct Sequence {
  std::string name;
  std::vector<SequenceFrame> frames;
};

// IoU exactly as TrackEval computes it (corners x + w, areas from corners,
// 0 when an area or the union is <= machine epsilon).
double MotIou(const BoxPx& a, const BoxPx& b);

}  // namespace hcpf::metrics
