#include "interrupt.h"

#include <signal.h>
#include <unistd.h>

#include <array>
#include <cstring>
#include <string>

#include "hcpf/scenarios/output_folder.h"

namespace hcpf::cli {

namespace {

constexpr std::array<int, 3> kSignals = {SIGINT, SIGTERM, SIGHUP};

// Filled before any handler is installed and never changed afterwards, so
// the handler only reads finished text.
std::array<std::string, 3> g_messages;
// The actions AnnounceInterrupts replaced, for StopAnnouncingInterrupts.
std::array<struct sigaction, 3> g_previous;
std::array<bool, 3> g_installed = {false, false, false};

void OnSignal(int signal_number) {
  for (size_t i = 0; i < kSignals.size(); ++i) {
    if (kSignals[i] != signal_number) continue;
    const std::string& text = g_messages[i];
    size_t written = 0;
    while (written < text.size()) {
      const ssize_t n = ::write(STDERR_FILENO, text.data() + written, text.size() - written);
      if (n <= 0) break;
      written += static_cast<size_t>(n);
    }
  }
  // The default action, delivered when this handler returns (the signal is
  // blocked while it runs): the process ends by the signal, as it would have.
  ::signal(signal_number, SIG_DFL);
  ::raise(signal_number);
}

}  // namespace

void AnnounceInterrupts(const std::string& message) {
  for (size_t i = 0; i < kSignals.size(); ++i) {
    // sigabbrev_np: "INT" for SIGINT (glibc).
    g_messages[i] = message + " (SIG" + ::sigabbrev_np(kSignals[i]) + ")\n";
  }
  for (size_t i = 0; i < kSignals.size(); ++i) {
    struct sigaction old_action {};
    if (::sigaction(kSignals[i], nullptr, &old_action) != 0) continue;
    if (old_action.sa_handler == SIG_IGN) continue;
    struct sigaction action {};
    action.sa_handler = OnSignal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;
    if (::sigaction(kSignals[i], &action, nullptr) != 0) continue;
    g_previous[i] = old_action;
    g_installed[i] = true;
  }
}

void StopAnnouncingInterrupts() {
  for (size_t i = 0; i < kSignals.size(); ++i) {
    if (g_installed[i]) ::sigaction(kSignals[i], &g_previous[i], nullptr);
    g_installed[i] = false;
  }
}

std::string InterruptedMessage(const std::string& command, const std::string& out,
                               const std::string& cache) {
  // What was written so far stays in the staging folder until the next
  // command into `out` removes it (a docs audit: 36 MB left unnamed after a
  // rendered run).
  const std::string partial = scenarios::StagingFolderFor(out).string();
  std::string message = "hcpf " + command + ": interrupted; nothing was written to " + out +
                        " (an earlier output there is kept; what was written so far, in " +
                        partial + ", is removed by the next hcpf run or hcpf render into it)";
  if (!cache.empty()) {
    message += "; the frames rendered so far are kept in the frame cache " + cache +
               ", so the same command again starts from them";
  }
  return message;
}

}  // namespace hcpf::cli
