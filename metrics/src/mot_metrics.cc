#include "hcpf/metrics/mot_metrics.h"

#include <fmt/compile.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <unordered_map>

#include "hcpf/core/check.h"
#include "hcpf/metrics/assignment.h"

namespace hcpf::metrics {
namespace {

// TrackEval compares against thresholds with numpy's float64 epsilon.
constexpr double kIouEps = std::numeric_limits<double>::epsilon();

// A gt/hyp pair of one frame with IoU > 0.
struct Overlap {
  int gl = 0;    // index of the gt box within the frame
  int hl = 0;    // index of the hyp box within the frame
  int pair = 0;  // index of the (gt id, hyp id) pair over the sequence
  double iou = 0.0;
};

// The sequence with ids relabelled to 0..n-1 and the IoUs of all overlapping
// pairs computed once, in flat arrays (one allocation per array, not per frame).
struct Prepared {
  int num_frames = 0;        // frames[] entries (not empty ones left out of a sparse sequence)
  std::vector<int> numbers;  // Sequence::numbers (frame numbers of a sparse sequence)
  int num_gt_ids = 0;
  int num_hyp_ids = 0;
  std::vector<int64_t> gt_original, hyp_original;  // relabelled id -> original id
  std::vector<int> gt_begin, hyp_begin, ov_begin;  // per frame offsets, size num_frames + 1
  std::vector<int> gt_id, hyp_id;                  // relabelled id per box
  std::vector<Overlap> overlaps;
  std::vector<int> pair_gt, pair_hyp;  // pair -> relabelled ids
  int64_t num_gt_dets() const { return static_cast<int64_t>(gt_id.size()); }
  int64_t num_hyp_dets() const { return static_cast<int64_t>(hyp_id.size()); }
};

// Relabels the gt (or hyp) ids of every box, in frame order, to their rank
// among the distinct ids (`original` = the distinct ids, sorted). A small
// open-addressing hash of the distinct ids gives one probe per box instead of
// sorting every box's id and binary-searching it again.
void RelabelIds(const Sequence& seq, bool gt, std::vector<int64_t>* original,
                std::vector<int>* relabelled) {
  std::vector<int64_t> keys;  // distinct ids in order of first appearance
  std::vector<int> slots(1024, -1);
  int shift = 64 - 10;
  auto slot_of = [&](int64_t id) {
    size_t s = static_cast<size_t>((static_cast<uint64_t>(id) * 0x9E3779B97F4A7C15ull) >> shift);
    while (slots[s] >= 0 && keys[slots[s]] != id) s = (s + 1) & (slots.size() - 1);
    return s;
  };
  relabelled->clear();
  size_t total = 0;
  for (const SequenceFrame& f : seq.frames) total += (gt ? f.gt : f.hyp).size();
  relabelled->reserve(total);
  for (const SequenceFrame& f : seq.frames) {
    for (const LabelledBox& b : gt ? f.gt : f.hyp) {
      size_t s = slot_of(b.id);
      if (slots[s] < 0) {
        if (2 * (keys.size() + 1) > slots.size()) {
          slots.assign(slots.size() * 2, -1);
          --shift;
          for (size_t k = 0; k < keys.size(); ++k) slots[slot_of(keys[k])] = static_cast<int>(k);
          s = slot_of(b.id);
        }
        slots[s] = static_cast<int>(keys.size());
        keys.push_back(b.id);
      }
      relabelled->push_back(slots[s]);
    }
  }
  std::vector<int> order(keys.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = static_cast<int>(k);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return keys[a] < keys[b]; });
  std::vector<int> rank(keys.size());
  original->resize(keys.size());
  for (size_t r = 0; r < order.size(); ++r) {
    rank[order[r]] = static_cast<int>(r);
    (*original)[r] = keys[order[r]];
  }
  for (int& id : *relabelled) id = rank[id];
}

Prepared Prepare(const Sequence& seq) {
  Prepared p;
  p.num_frames = static_cast<int>(seq.frames.size());
  p.numbers = seq.numbers;
  RelabelIds(seq, true, &p.gt_original, &p.gt_id);
  RelabelIds(seq, false, &p.hyp_original, &p.hyp_id);
  p.num_gt_ids = static_cast<int>(p.gt_original.size());
  p.num_hyp_ids = static_cast<int>(p.hyp_original.size());
  p.gt_begin.reserve(p.num_frames + 1);
  p.hyp_begin.reserve(p.num_frames + 1);
  p.ov_begin.reserve(p.num_frames + 1);
  // Pair index: dense table when small, hash map otherwise (huge id sets).
  const int64_t table_size = static_cast<int64_t>(p.num_gt_ids) * p.num_hyp_ids;
  const bool dense = table_size <= (int64_t{1} << 22);
  std::vector<int> dense_pairs(dense ? table_size : 0, -1);
  std::unordered_map<int64_t, int> sparse_pairs;
  auto pair_of = [&](int g, int h) {
    const int64_t key = static_cast<int64_t>(g) * p.num_hyp_ids + h;
    int* slot = nullptr;
    if (dense) {
      slot = &dense_pairs[key];
    } else {
      slot = &sparse_pairs.try_emplace(key, -1).first->second;
    }
    if (*slot < 0) {
      *slot = static_cast<int>(p.pair_gt.size());
      p.pair_gt.push_back(g);
      p.pair_hyp.push_back(h);
    }
    return *slot;
  };
  std::vector<double> hyp_edges;
  int next_gt0 = 0;  // offset of the frame's first box in gt_id / hyp_id
  int next_hyp0 = 0;
  for (const SequenceFrame& f : seq.frames) {
    const int gt0 = next_gt0;
    const int hyp0 = next_hyp0;
    next_gt0 += static_cast<int>(f.gt.size());
    next_hyp0 += static_cast<int>(f.hyp.size());
    p.gt_begin.push_back(gt0);
    p.hyp_begin.push_back(hyp0);
    p.ov_begin.push_back(static_cast<int>(p.overlaps.size()));
    // Edges of the frame's hyp boxes in one flat array: the overlap test below
    // reads only these (MotIou is 0 whenever its x or y overlap
    // min(right) - max(left) is <= 0, the same expressions as here).
    const size_t nh = f.hyp.size();
    hyp_edges.resize(4 * nh);
    double* const edge = hyp_edges.data();  // left, right, top, bottom of hyp j at 4j
    for (size_t j = 0; j < nh; ++j) {
      const BoxPx& b = f.hyp[j].box;
      edge[4 * j] = b.left;
      edge[4 * j + 1] = b.left + b.width;
      edge[4 * j + 2] = b.top;
      edge[4 * j + 3] = b.top + b.height;
    }
    for (size_t i = 0; i < f.gt.size(); ++i) {
      const BoxPx& a = f.gt[i].box;
      const double ax2 = a.left + a.width;
      const double ay2 = a.top + a.height;
      for (size_t j = 0; j < nh; ++j) {
        const double* e = edge + 4 * j;
        if (std::min(ax2, e[1]) - std::max(a.left, e[0]) <= 0.0 ||
            std::min(ay2, e[3]) - std::max(a.top, e[2]) <= 0.0) {
          continue;
        }
        const double iou = MotIou(a, f.hyp[j].box);
        if (iou <= 0.0) continue;
        const int pair = pair_of(p.gt_id[gt0 + i], p.hyp_id[hyp0 + j]);
        p.overlaps.push_back({static_cast<int>(i), static_cast<int>(j), pair, iou});
      }
    }
  }
  p.gt_begin.push_back(static_cast<int>(p.gt_id.size()));
  p.hyp_begin.push_back(static_cast<int>(p.hyp_id.size()));
  p.ov_begin.push_back(static_cast<int>(p.overlaps.size()));
  return p;
}

ClearMetrics ClearOf(const Prepared& p, std::vector<MotEvent>* events) {
  ClearMetrics r;
  const int G = p.num_gt_ids;
  std::vector<int> prev_id(G, -1), prev_t(G, -1), matched_count(G, 0), id_count(G, 0),
      frag_start(G, 0);
  std::vector<int> last_gt_of_hyp(p.num_hyp_ids, -1);
  std::vector<char> hyp_ever_matched(p.num_hyp_ids, 0);
  std::vector<int> prev_matched_gts, now_matched_gts;
  std::vector<WeightedEdge> edges;
  std::vector<int> edge_overlap, chosen;
  std::vector<char> gt_matched, hyp_matched;
  SparseMatcher matcher;
  for (int t = 0; t < p.num_frames; ++t) {
    const int gt0 = p.gt_begin[t], ng = p.gt_begin[t + 1] - gt0;
    const int hyp0 = p.hyp_begin[t], nh = p.hyp_begin[t + 1] - hyp0;
    const int frame = p.numbers.empty() ? t + 1 : p.numbers[t];
    if (ng == 0) {
      r.fp += nh;
      if (events) {
        for (int j = 0; j < nh; ++j) {
          events->push_back(
              {frame, MotEventType::kFp, -1, p.hyp_original[p.hyp_id[hyp0 + j]], 0.0});
        }
      }
      continue;
    }
    if (nh == 0) {
      r.fn += ng;
      for (int i = 0; i < ng; ++i) {
        ++id_count[p.gt_id[gt0 + i]];
        if (events) {
          events->push_back({frame, MotEventType::kMiss, p.gt_original[p.gt_id[gt0 + i]], -1, 0.0});
        }
      }
      continue;
    }
    edges.clear();
    edge_overlap.clear();
    for (int k = p.ov_begin[t]; k < p.ov_begin[t + 1]; ++k) {
      const Overlap& o = p.overlaps[k];
      if (o.iou < kMotIouThreshold - kIouEps) continue;
      const int g = p.gt_id[gt0 + o.gl];
      const int h = p.hyp_id[hyp0 + o.hl];
      // Continuing last frame's pair has priority over any IoU gain.
      const double score = (prev_t[g] == h ? 1000.0 : 0.0) + o.iou;
      edges.push_back({o.gl, o.hl, score});
      edge_overlap.push_back(k);
    }
    matcher.Solve(edges, ng, nh, &chosen);
    gt_matched.assign(ng, 0);
    hyp_matched.assign(nh, 0);
    now_matched_gts.clear();
    int64_t matches = 0;
    // Events in gt order of the frame.
    std::sort(chosen.begin(), chosen.end(),
              [&](int a, int b) { return edges[a].row < edges[b].row; });
    for (int k : chosen) {
      if (!(edges[k].weight > kIouEps)) continue;
      const Overlap& o = p.overlaps[edge_overlap[k]];
      const int g = p.gt_id[gt0 + o.gl];
      const int h = p.hyp_id[hyp0 + o.hl];
      gt_matched[o.gl] = 1;
      hyp_matched[o.hl] = 1;
      ++matches;
      r.motp_sum += o.iou;
      const bool is_switch = prev_id[g] >= 0 && prev_id[g] != h;
      if (is_switch) ++r.idsw;
      if (events) {
        const int64_t go = p.gt_original[g];
        const int64_t ho = p.hyp_original[h];
        events->push_back(
            {frame, is_switch ? MotEventType::kSwitch : MotEventType::kMatch, go, ho, o.iou});
        if (is_switch && !hyp_ever_matched[h]) {
          events->push_back({frame, MotEventType::kAscend, go, ho, o.iou});
        }
        if (last_gt_of_hyp[h] >= 0 && last_gt_of_hyp[h] != g) {
          events->push_back({frame, MotEventType::kTransfer, go, ho, o.iou});
          if (prev_id[g] < 0) events->push_back({frame, MotEventType::kMigrate, go, ho, o.iou});
        }
      }
      prev_id[g] = h;
      last_gt_of_hyp[h] = g;
      hyp_ever_matched[h] = 1;
      ++matched_count[g];
      // Fragmentation: matched now, not matched in the previous evaluated frame.
      if (prev_t[g] < 0) ++frag_start[g];
      now_matched_gts.push_back(g);
    }
    // prev_t holds this frame's matches only (TrackEval resets it to NaN).
    for (int g : prev_matched_gts) prev_t[g] = -1;
    for (int k : chosen) {
      if (!(edges[k].weight > kIouEps)) continue;
      const Overlap& o = p.overlaps[edge_overlap[k]];
      prev_t[p.gt_id[gt0 + o.gl]] = p.hyp_id[hyp0 + o.hl];
    }
    std::swap(prev_matched_gts, now_matched_gts);
    for (int i = 0; i < ng; ++i) ++id_count[p.gt_id[gt0 + i]];
    r.tp += matches;
    r.fn += ng - matches;
    r.fp += nh - matches;
    if (events) {
      for (int i = 0; i < ng; ++i) {
        if (!gt_matched[i]) {
          events->push_back({frame, MotEventType::kMiss, p.gt_original[p.gt_id[gt0 + i]], -1, 0.0});
        }
      }
      for (int j = 0; j < nh; ++j) {
        if (!hyp_matched[j]) {
          events->push_back(
              {frame, MotEventType::kFp, -1, p.hyp_original[p.hyp_id[hyp0 + j]], 0.0});
        }
      }
    }
  }
  for (int g = 0; g < G; ++g) {
    if (id_count[g] == 0) continue;
    const double ratio = static_cast<double>(matched_count[g]) / id_count[g];
    if (ratio > 0.8) {
      ++r.mt;
    } else if (ratio >= 0.2) {
      ++r.pt;
    }
    if (frag_start[g] > 0) r.frag += frag_start[g] - 1;
  }
  r.ml = G - r.mt - r.pt;
  r.Finalize(p.num_gt_dets() == 0, p.num_hyp_dets() == 0);
  return r;
}

IdentityMetrics IdentityOf(const Prepared& p, double threshold = kMotIouThreshold,
                           std::vector<std::pair<int64_t, int64_t>>* matching = nullptr) {
  IdentityMetrics r;
  std::vector<int> count(p.pair_gt.size(), 0);
  for (const Overlap& o : p.overlaps) {
    if (o.iou >= threshold) ++count[o.pair];  // exact >= 0.5 (no epsilon)
  }
  std::vector<WeightedEdge> edges;
  for (size_t k = 0; k < count.size(); ++k) {
    if (count[k] > 0) edges.push_back({p.pair_gt[k], p.pair_hyp[k], static_cast<double>(count[k])});
  }
  SparseMatcher matcher;
  std::vector<int> chosen;
  matcher.Solve(edges, p.num_gt_ids, p.num_hyp_ids, &chosen);
  for (int k : chosen) {
    r.idtp += static_cast<int64_t>(edges[k].weight);
    if (matching) matching->emplace_back(p.gt_original[edges[k].row], p.hyp_original[edges[k].col]);
  }
  if (matching) std::sort(matching->begin(), matching->end());
  r.idfn = p.num_gt_dets() - r.idtp;
  r.idfp = p.num_hyp_dets() - r.idtp;
  r.Finalize();
  return r;
}

HotaMetrics HotaOf(const Prepared& p) {
  HotaMetrics r;
  const auto& alphas = HotaAlphas();
  const size_t num_pairs = p.pair_gt.size();
  std::vector<double> potential(num_pairs, 0.0);
  std::vector<int> gt_count(p.num_gt_ids, 0), hyp_count(p.num_hyp_ids, 0);
  for (int id : p.gt_id) ++gt_count[id];
  for (int id : p.hyp_id) ++hyp_count[id];
  std::vector<double> row_sum, col_sum;
  for (int t = 0; t < p.num_frames; ++t) {
    const int ng = p.gt_begin[t + 1] - p.gt_begin[t];
    const int nh = p.hyp_begin[t + 1] - p.hyp_begin[t];
    row_sum.assign(ng, 0.0);
    col_sum.assign(nh, 0.0);
    for (int k = p.ov_begin[t]; k < p.ov_begin[t + 1]; ++k) {
      row_sum[p.overlaps[k].gl] += p.overlaps[k].iou;
      col_sum[p.overlaps[k].hl] += p.overlaps[k].iou;
    }
    for (int k = p.ov_begin[t]; k < p.ov_begin[t + 1]; ++k) {
      const Overlap& o = p.overlaps[k];
      const double denom = row_sum[o.gl] + col_sum[o.hl] - o.iou;
      if (denom > kIouEps) potential[o.pair] += o.iou / denom;
    }
  }
  std::vector<double> alignment(num_pairs, 0.0);
  for (size_t k = 0; k < num_pairs; ++k) {
    alignment[k] =
        potential[k] / (gt_count[p.pair_gt[k]] + hyp_count[p.pair_hyp[k]] - potential[k]);
  }
  std::vector<int32_t> matches(num_pairs * kNumHotaAlphas, 0);  // pair-major
  std::array<double, kNumHotaAlphas> loca_sum{};
  std::vector<WeightedEdge> edges;
  std::vector<int> edge_overlap, chosen;
  SparseMatcher matcher;
  for (int t = 0; t < p.num_frames; ++t) {
    const int ng = p.gt_begin[t + 1] - p.gt_begin[t];
    const int nh = p.hyp_begin[t + 1] - p.hyp_begin[t];
    if (ng == 0 || nh == 0) {
      for (int a = 0; a < kNumHotaAlphas; ++a) {
        r.fp[a] += nh;
        r.fn[a] += ng;
      }
      continue;
    }
    edges.clear();
    edge_overlap.clear();
    for (int k = p.ov_begin[t]; k < p.ov_begin[t + 1]; ++k) {
      const Overlap& o = p.overlaps[k];
      const double w = alignment[o.pair] * o.iou;
      if (w > 0.0) {
        edges.push_back({o.gl, o.hl, w});
        edge_overlap.push_back(k);
      }
    }
    matcher.Solve(edges, ng, nh, &chosen);
    std::array<int, kNumHotaAlphas> tp_frame{};
    for (int k : chosen) {
      const Overlap& o = p.overlaps[edge_overlap[k]];
      int32_t* counts = &matches[static_cast<size_t>(o.pair) * kNumHotaAlphas];
      for (int a = 0; a < kNumHotaAlphas && o.iou >= alphas[a] - kIouEps; ++a) {
        ++tp_frame[a];
        loca_sum[a] += o.iou;
        ++counts[a];
      }
    }
    for (int a = 0; a < kNumHotaAlphas; ++a) {
      r.tp[a] += tp_frame[a];
      r.fn[a] += ng - tp_frame[a];
      r.fp[a] += nh - tp_frame[a];
    }
  }
  std::array<double, kNumHotaAlphas> assa{}, assre{}, asspr{};
  for (size_t k = 0; k < num_pairs; ++k) {
    const double ng = gt_count[p.pair_gt[k]];
    const double nh = hyp_count[p.pair_hyp[k]];
    const int32_t* counts = &matches[k * kNumHotaAlphas];
    for (int a = 0; a < kNumHotaAlphas; ++a) {
      const double c = counts[a];
      if (c == 0.0) continue;
      assa[a] += c * (c / std::max(1.0, ng + nh - c));
      assre[a] += c * (c / std::max(1.0, ng));
      asspr[a] += c * (c / std::max(1.0, nh));
    }
  }
  for (int a = 0; a < kNumHotaAlphas; ++a) {
    const double tp = std::max<double>(1.0, static_cast<double>(r.tp[a]));
    r.assa[a] = assa[a] / tp;
    r.assre[a] = assre[a] / tp;
    r.asspr[a] = asspr[a] / tp;
    r.loca[a] = std::max(1e-10, loca_sum[a]) / std::max(1e-10, static_cast<double>(r.tp[a]));
  }
  r.Finalize();
  return r;
}

}  // namespace

const std::array<double, kNumHotaAlphas>& HotaAlphas() {
  // numpy.arange(start, stop, step) computes start + i * step.
  static const std::array<double, kNumHotaAlphas> kAlphas = [] {
    std::array<double, kNumHotaAlphas> a{};
    for (int i = 0; i < kNumHotaAlphas; ++i) a[i] = 0.05 + i * 0.05;
    return a;
  }();
  return kAlphas;
}

void ClearMetrics::Finalize(bool empty_gt, bool empty_hyp) {
  const double num_gt = static_cast<double>(tp + fn);
  if (empty_gt) {
    // TrackEval returns before computing ratios when there is no ground truth.
    mota = motp = motp_distance = moda = smota = recall = precision = 0.0;
    return;
  }
  (void)empty_hyp;  // the formulas below already give 0 for every ratio
  mota = (static_cast<double>(tp) - fp - idsw) / std::max(1.0, num_gt);
  moda = (static_cast<double>(tp) - fp) / std::max(1.0, num_gt);
  motp = motp_sum / std::max<double>(1.0, static_cast<double>(tp));
  motp_distance = tp > 0 ? 1.0 - motp : 0.0;
  smota = (motp_sum - fp - idsw) / std::max(1.0, num_gt);
  recall = tp / std::max(1.0, num_gt);
  precision = tp / std::max<double>(1.0, static_cast<double>(tp + fp));
}

void IdentityMetrics::Finalize() {
  idr = idtp / std::max<double>(1.0, static_cast<double>(idtp + idfn));
  idp = idtp / std::max<double>(1.0, static_cast<double>(idtp + idfp));
  idf1 = idtp / std::max(1.0, idtp + 0.5 * idfp + 0.5 * idfn);
}

void HotaMetrics::Finalize() {
  auto mean = [](const PerAlpha<double>& v) {
    double s = 0.0;
    for (double x : v) s += x;
    return s / kNumHotaAlphas;
  };
  for (int a = 0; a < kNumHotaAlphas; ++a) {
    const double t = static_cast<double>(tp[a]);
    detre[a] = t / std::max(1.0, t + fn[a]);
    detpr[a] = t / std::max(1.0, t + fp[a]);
    deta[a] = t / std::max(1.0, t + fn[a] + fp[a]);
    hota[a] = std::sqrt(deta[a] * assa[a]);
  }
  hota_mean = mean(hota);
  deta_mean = mean(deta);
  assa_mean = mean(assa);
  loca_mean = mean(loca);
  detre_mean = mean(detre);
  detpr_mean = mean(detpr);
  assre_mean = mean(assre);
  asspr_mean = mean(asspr);
  hota0 = hota[0];
  loca0 = loca[0];
  hotaloca0 = hota0 * loca0;
}

const char* MotEventName(MotEventType type) {
  switch (type) {
    case MotEventType::kMatch:
      return "MATCH";
    case MotEventType::kSwitch:
      return "SWITCH";
    case MotEventType::kTransfer:
      return "TRANSFER";
    case MotEventType::kAscend:
      return "ASCEND";
    case MotEventType::kMigrate:
      return "MIGRATE";
    case MotEventType::kFp:
      return "FP";
    case MotEventType::kMiss:
      return "MISS";
  }
  return "?";
}

ClearMetrics ComputeClear(const Sequence& seq, std::vector<MotEvent>* events) {
  if (events) events->clear();
  return ClearOf(Prepare(seq), events);
}

IdentityMetrics ComputeIdentity(const Sequence& seq) { return IdentityOf(Prepare(seq)); }

HotaMetrics ComputeHota(const Sequence& seq) { return HotaOf(Prepare(seq)); }

std::vector<std::pair<int64_t, int64_t>> IdentityMatching(const Sequence& seq,
                                                          double iou_threshold) {
  std::vector<std::pair<int64_t, int64_t>> matching;
  IdentityOf(Prepare(seq), iou_threshold, &matching);
  return matching;
}

MotSummary ComputeAll(const Sequence& seq, std::vector<MotEvent>* events) {
  if (events) events->clear();
  const Prepared p = Prepare(seq);
  MotSummary s;
  s.name = seq.name;
  s.num_frames = seq.NumFrames();
  s.num_objects = p.num_gt_dets();
  s.num_predictions = p.num_hyp_dets();
  s.num_gt_ids = p.num_gt_ids;
  s.num_tracker_ids = p.num_hyp_ids;
  s.clear = ClearOf(p, events);
  s.identity = IdentityOf(p);
  s.hota = HotaOf(p);
  return s;
}

MotSummary Pool(std::span<const MotSummary> sequences, std::string name) {
  MotSummary out;
  out.name = std::move(name);
  std::array<double, kNumHotaAlphas> assa{}, assre{}, asspr{}, loca{};
  for (const MotSummary& s : sequences) {
    out.num_frames += s.num_frames;
    out.num_objects += s.num_objects;
    out.num_predictions += s.num_predictions;
    out.num_gt_ids += s.num_gt_ids;
    out.num_tracker_ids += s.num_tracker_ids;
    ClearMetrics& c = out.clear;
    c.tp += s.clear.tp;
    c.fp += s.clear.fp;
    c.fn += s.clear.fn;
    c.idsw += s.clear.idsw;
    c.frag += s.clear.frag;
    c.mt += s.clear.mt;
    c.pt += s.clear.pt;
    c.ml += s.clear.ml;
    c.motp_sum += s.clear.motp_sum;
    out.identity.idtp += s.identity.idtp;
    out.identity.idfp += s.identity.idfp;
    out.identity.idfn += s.identity.idfn;
    for (int a = 0; a < kNumHotaAlphas; ++a) {
      const double tp = static_cast<double>(s.hota.tp[a]);
      out.hota.tp[a] += s.hota.tp[a];
      out.hota.fn[a] += s.hota.fn[a];
      out.hota.fp[a] += s.hota.fp[a];
      assa[a] += s.hota.assa[a] * tp;
      assre[a] += s.hota.assre[a] * tp;
      asspr[a] += s.hota.asspr[a] * tp;
      loca[a] += s.hota.loca[a] * tp;
    }
  }
  out.clear.Finalize();
  out.identity.Finalize();
  for (int a = 0; a < kNumHotaAlphas; ++a) {
    const double tp = static_cast<double>(out.hota.tp[a]);
    out.hota.assa[a] = assa[a] / std::max(1.0, tp);
    out.hota.assre[a] = assre[a] / std::max(1.0, tp);
    out.hota.asspr[a] = asspr[a] / std::max(1.0, tp);
    out.hota.loca[a] = std::max(1e-10, loca[a]) / std::max(1e-10, tp);
  }
  out.hota.Finalize();
  return out;
}

const double* NamedMetrics::Scalar(const std::string& name) const {
  for (const auto& [key, value] : scalars) {
    if (key == name) return &value;
  }
  return nullptr;
}

const std::vector<double>* NamedMetrics::Array(const std::string& name) const {
  for (const auto& [key, value] : arrays) {
    if (key == name) return &value;
  }
  return nullptr;
}

NamedMetrics ToNamedMetrics(const MotSummary& s) {
  NamedMetrics n;
  auto d = [](int64_t v) { return static_cast<double>(v); };
  const ClearMetrics& c = s.clear;
  const IdentityMetrics& i = s.identity;
  const HotaMetrics& h = s.hota;
  n.scalars = {
      {"MOTA", c.mota},
      {"MOTP", c.motp},
      {"MOTP_distance", c.motp_distance},
      {"MODA", c.moda},
      {"sMOTA", c.smota},
      {"MOTP_sum", c.motp_sum},
      {"IDF1", i.idf1},
      {"IDP", i.idp},
      {"IDR", i.idr},
      {"IDTP", d(i.idtp)},
      {"IDFP", d(i.idfp)},
      {"IDFN", d(i.idfn)},
      {"IDSW", d(c.idsw)},
      {"FP", d(c.fp)},
      {"FN", d(c.fn)},
      {"TP", d(c.tp)},
      {"Frag", d(c.frag)},
      {"MT", d(c.mt)},
      {"PT", d(c.pt)},
      {"ML", d(c.ml)},
      {"recall", c.recall},
      {"precision", c.precision},
      {"num_objects", d(s.num_objects)},
      {"num_predictions", d(s.num_predictions)},
      {"num_gt_ids", d(s.num_gt_ids)},
      {"num_tracker_ids", d(s.num_tracker_ids)},
      {"num_frames", d(s.num_frames)},
      {"HOTA", h.hota_mean},
      {"DetA", h.deta_mean},
      {"AssA", h.assa_mean},
      {"LocA", h.loca_mean},
      {"DetRe", h.detre_mean},
      {"DetPr", h.detpr_mean},
      {"AssRe", h.assre_mean},
      {"AssPr", h.asspr_mean},
      {"HOTA(0)", h.hota0},
      {"LocA(0)", h.loca0},
      {"HOTALocA(0)", h.hotaloca0},
  };
  auto arr = [](const auto& a) {
    std::vector<double> v;
    for (auto x : a) v.push_back(static_cast<double>(x));
    return v;
  };
  n.arrays = {
      {"HOTA_alpha", arr(h.hota)},   {"DetA_alpha", arr(h.deta)},   {"AssA_alpha", arr(h.assa)},
      {"LocA_alpha", arr(h.loca)},   {"DetRe_alpha", arr(h.detre)}, {"DetPr_alpha", arr(h.detpr)},
      {"AssRe_alpha", arr(h.assre)}, {"AssPr_alpha", arr(h.asspr)}, {"HOTA_TP_alpha", arr(h.tp)},
      {"HOTA_FN_alpha", arr(h.fn)},  {"HOTA_FP_alpha", arr(h.fp)},
  };
  return n;
}

bool IsCountMetric(const std::string& name) {
  static const char* kCounts[] = {"IDTP",
                                  "IDFP",
                                  "IDFN",
                                  "IDSW",
                                  "FP",
                                  "FN",
                                  "TP",
                                  "Frag",
                                  "MT",
                                  "PT",
                                  "ML",
                                  "num_objects",
                                  "num_predictions",
                                  "num_gt_ids",
                                  "num_tracker_ids",
                                  "num_frames",
                                  "HOTA_TP_alpha",
                                  "HOTA_FN_alpha",
                                  "HOTA_FP_alpha"};
  for (const char* c : kCounts) {
    if (name == c) return true;
  }
  return false;
}

void WriteEventsJsonLines(std::ostream& out, std::span<const MotEvent> events) {
  // One buffer for many lines, the format compiled once (no parsing per event).
  fmt::memory_buffer buffer;
  for (const MotEvent& e : events) {
    fmt::format_to(
        std::back_inserter(buffer),
        FMT_COMPILE("{{\"frame\":{},\"type\":\"{}\",\"gt\":{},\"hyp\":{},\"iou\":{}}}\n"), e.frame,
        MotEventName(e.type), e.gt, e.hyp, e.iou);
    if (buffer.size() >= (size_t{1} << 16)) {
      out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
      buffer.clear();
    }
  }
  out.write(buffer.data(), static_cast<std::streamsize>(buffer.size()));
}

}  // namespace hcpf::metrics
