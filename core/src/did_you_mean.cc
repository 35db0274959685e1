#include "hcpf/core/did_you_mean.h"

#include <algorithm>
#include <vector>

namespace hcpf {

int EditDistance(const std::string& a, const std::string& b) {
  // Optimal string alignment: Levenshtein plus the swap of two adjacent
  // letters as one edit ("paht" is 1 from "path", was 2: a bad-input audit
  // found no "did you mean" for it). Rows i-2, i-1 and i of the table.
  std::vector<int> before(b.size() + 1);
  std::vector<int> prev(b.size() + 1);
  std::vector<int> cur(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) prev[j] = static_cast<int>(j);
  for (size_t i = 1; i <= a.size(); ++i) {
    cur[0] = static_cast<int>(i);
    for (size_t j = 1; j <= b.size(); ++j) {
      const int cost = a[i - 1] == b[j - 1] ? 0 : 1;
      cur[j] = std::min({prev[j] + 1, cur[j - 1] + 1, prev[j - 1] + cost});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
        cur[j] = std::min(cur[j], before[j - 2] + 1);
      }
    }
    std::swap(before, prev);
    std::swap(prev, cur);
  }
  return prev[b.size()];
}

std::string ClosestMatch(const std::string& word, const std::vector<std::string>& candidates) {
  std::string best;
  // Up to a third of the word's length may differ (at least 1, at most 3 edits):
  // enough for a transposition or a dropped letter, not for an unrelated key.
  const int limit = std::clamp(static_cast<int>(word.size()) / 3, 1, 3);
  int best_distance = limit + 1;
  for (const std::string& c : candidates) {
    const int d = EditDistance(word, c);
    if (d < best_distance) {
      best_distance = d;
      best = c;
    }
  }
  if (!best.empty()) return best;
  // A dropped suffix ("azimuth" for "azimuth_deg", "max_missed" for
  // "max_missed_frames"): the shortest candidate that extends the word at an
  // underscore (most often the word plus its unit); none when two tie.
  std::string extended;
  bool tie = false;
  for (const std::string& c : candidates) {
    if (c.size() <= word.size() + 1 || c.rfind(word + "_", 0) != 0) continue;
    if (extended.empty() || c.size() < extended.size()) {
      extended = c;
      tie = false;
    } else if (c.size() == extended.size()) {
      tie = true;
    }
  }
  return tie ? "" : extended;
}

}  // namespace hcpf
