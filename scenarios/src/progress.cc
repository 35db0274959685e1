#include "hcpf/scenarios/progress.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace hcpf::scenarios {
namespace {

std::string ClockText(double seconds) {
  const auto s = static_cast<int64_t>(seconds + 0.5);
  if (s >= 3600) return fmt::format("{}:{:02}:{:02}", s / 3600, s / 60 % 60, s % 60);
  return fmt::format("{}:{:02}", s / 60, s % 60);
}

}  // namespace

Progress::Progress(std::string label, int64_t total, bool enabled)
    : label_(std::move(label)),
      total_(total),
      enabled_(enabled),
      tty_(::isatty(STDERR_FILENO) == 1),
      start_(std::chrono::steady_clock::now()),
      last_print_(start_) {}

Progress::~Progress() {
  if (!finished_ && printed_ && tty_) std::fputc('\n', stderr);
}

std::string Progress::Format(const std::string& label, int64_t done, int64_t total, int64_t failed,
                             double elapsed_s, double eta_s) {
  const double fraction = total > 0 ? static_cast<double>(done) / total : 1.0;
  std::string line = fmt::format("{} {}/{} ({:.0f}%)", label, done, total, 100.0 * fraction);
  if (failed > 0) line += fmt::format(" {} failed,", failed);
  line += fmt::format(" {} elapsed", ClockText(elapsed_s));
  if (done > 0 && done < total) {
    const double eta = std::isfinite(eta_s) ? eta_s : elapsed_s * (total - done) / done;
    line += fmt::format(", ETA {}", ClockText(eta));
  }
  return line;
}

double Progress::EtaSeconds(const std::vector<double>& finished_s, int64_t total, double now_s) {
  const auto done = static_cast<int64_t>(finished_s.size());
  if (done == 0 || done >= total) return std::numeric_limits<double>::quiet_NaN();
  // The later half: the items after the first done / 2, timed from when
  // the last of those finished (from the start for one item).
  const int64_t recent = (done + 1) / 2;
  const int64_t before = done - recent;
  const double from = before == 0 ? 0.0 : finished_s[static_cast<size_t>(before - 1)];
  return (now_s - from) / static_cast<double>(recent) * static_cast<double>(total - done);
}

void Progress::Advance(int64_t done, int64_t failed) {
  done_ += done;
  failed_ += failed;
  const auto now = std::chrono::steady_clock::now();
  const double since_start = std::chrono::duration<double>(now - start_).count();
  finished_s_.resize(static_cast<size_t>(std::max<int64_t>(done_, 0)), since_start);
  const double since_print = std::chrono::duration<double>(now - last_print_).count();
  if (!enabled_ || since_start < 1.0) return;
  if ((tty_ && since_print >= 0.1) || (!tty_ && since_print >= 5.0)) {
    last_print_ = now;
    Print(false);
  }
}

void Progress::Finish() {
  if (finished_) return;
  finished_ = true;
  if (printed_) Print(true);
}

void Progress::Print(bool final) {
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const std::string line =
      Format(label_, done_, total_, failed_, elapsed, EtaSeconds(finished_s_, total_, elapsed));
  printed_ = true;
  if (tty_) {
    std::fprintf(stderr, "\r\033[K%s%s", line.c_str(), final ? "\n" : "");
    std::fflush(stderr);
  } else {
    spdlog::info("{}", line);
  }
}

spdlog::level::level_enum RunSummaryLevel(bool show_progress) {
  return show_progress ? spdlog::level::info : spdlog::level::debug;
}

}  // namespace hcpf::scenarios
