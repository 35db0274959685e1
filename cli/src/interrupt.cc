#include "interrupt.h"

#include <signal.h>
#include <unistd.h>

#include <array>
#include <string>

namespace hcpf::cli {

namespace {

constexpr std::array<int, 3> kSignals = {SIGINT, SIGTERM, SIGHUP};
constexpr std::array<const char*, 3> kNames = {"SIGINT", "SIGTERM", "SIGHUP"};

// Filled before any handler is installed and never changed afterwards, so
// the handler only reads finished text.
std::array<std::string, 3> g_messages;

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
    g_messages[i] = message + " (" + kNames[i] + ")\n";
  }
  for (const int signal_number : kSignals) {
    struct sigaction old_action {};
    if (::sigaction(signal_number, nullptr, &old_action) != 0) continue;
    if (old_action.sa_handler == SIG_IGN) continue;
    struct sigaction action {};
    action.sa_handler = OnSignal;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESTART;
    ::sigaction(signal_number, &action, nullptr);
  }
}

}  // namespace hcpf::cli
