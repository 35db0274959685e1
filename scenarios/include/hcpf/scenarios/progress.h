#pragma once
// Progress of long work on stderr. On a terminal: one line redrawn in place
// (done/total, percent, failures, elapsed, ETA) at most 10 times a second. When
// stderr is not a terminal (CI, logs): a plain log line at most every 5 s.
// Quiet work (under a second) prints nothing.

#include <spdlog/common.h>

#include <chrono>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace hcpf::scenarios {

class Progress {
 public:
  // `enabled` = false prints nothing (work inside a sweep, which shows its own).
  Progress(std::string label, int64_t total, bool enabled = true);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  void Advance(int64_t done = 1, int64_t failed = 0);
  // Prints the final state (if anything was printed before) and ends the line.
  void Finish();

  // The line as shown, e.g. "sweep 12/40 (30%) 1 failed, 0:12 elapsed, ETA 0:28";
  // `eta_s` NaN: from the mean rate since the start.
  static std::string Format(const std::string& label, int64_t done, int64_t total, int64_t failed,
                            double elapsed_s,
                            double eta_s = std::numeric_limits<double>::quiet_NaN());

  // The time left for `total` items at the rate of the later half of those
  // done: `finished_s[i]` is when item i + 1 finished, `now_s` the time now
  // (both from the start). NaN when nothing is done or all is. A rendered
  // sweep's first runs render what the rest read from the cache: at the
  // mean rate since the start its ETA said 16 minutes for a sweep that took
  // one (an audit).
  static double EtaSeconds(const std::vector<double>& finished_s, int64_t total, double now_s);

 private:
  void Print(bool final);

  std::string label_;
  int64_t total_;
  int64_t done_ = 0;
  int64_t failed_ = 0;
  bool enabled_;
  bool tty_;
  bool printed_ = false;
  bool finished_ = false;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_print_;
  std::vector<double> finished_s_;  // when each item finished, seconds from the start
};

// The log level of a run's own summary lines (its detection scores, the
// frames it read from the cache): info for a run by itself, debug inside a
// sweep (`show_progress` false), where one such line per run wrote over the
// sweep's progress line (an audit: 140 times in a 140-run sweep).
spdlog::level::level_enum RunSummaryLevel(bool show_progress);

}  // namespace hcpf::scenarios
