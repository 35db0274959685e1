#pragma once
// The project's one way to run another program: fork + exec, no shell (so
// paths need no quoting), output captured in a log file.

#include <string>
#include <string_view>
#include <vector>

namespace hcpf {

struct ProcessStatus {
  bool started = false;  // false: fork failed (`error` says why)
  int exit_code = -1;    // when the program exited; 127: it could not be executed
  int signal = 0;        // when a signal ended it (0 otherwise)
  std::string error;

  bool ok() const { return started && signal == 0 && exit_code == 0; }
};

// Runs argv[0] (looked up on PATH when it holds no '/') with arguments
// argv[1..], its stdout and stderr written to `log_path` (truncated), and
// waits for it. Between fork and exec the child makes only async-signal-safe
// calls, so this is safe to call from a threaded process. The child gets
// SIGTERM when this process ends first (PR_SET_PDEATHSIG): a killed sweep
// leaves no run behind it.
ProcessStatus RunProcess(const std::vector<std::string>& argv, const std::string& log_path);

// Whether `name` (no '/') names an executable file in a folder of PATH, as
// RunProcess would look it up.
bool ExecutableOnPath(const std::string& name);

// Whether `pid_digits` (decimal digits only, as a process id appears in a
// file or folder name this project leaves behind: "<name>.partial-<pid>",
// ".<name>.tmp-<pid>-<n>", "hcpf-regress.partial-<pid>") names a process that no
// longer runs on this machine: none has that id, or it is a zombie (ended,
// its exit status not yet collected). False for anything else, and for a
// process that runs, even one of another user: only what is surely left
// over may be removed.
bool ProcessIsGone(std::string_view pid_digits);

}  // namespace hcpf
