#include "hcpf/core/subprocess.h"

#include <fcntl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string_view>

#include "hcpf/core/check.h"

namespace hcpf {

ProcessStatus RunProcess(const std::vector<std::string>& argv, const std::string& log_path) {
  HCPF_CHECK(!argv.empty()) << "RunProcess needs a program";
  // Everything the child needs is prepared before the fork.
  std::vector<std::string> args = argv;
  std::vector<char*> pointers;
  for (std::string& a : args) pointers.push_back(a.data());
  pointers.push_back(nullptr);
  ProcessStatus status;
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    status.error = std::strerror(errno);
    return status;
  }
  if (pid == 0) {
    // The child ends with this process (SIGTERM when the thread that started
    // it is gone): a sweep killed alone must not leave its runs writing into a
    // folder that the next sweep takes over. A parent already gone before the
    // request was made is caught by getppid().
    if (::prctl(PR_SET_PDEATHSIG, SIGTERM) != 0 || ::getppid() != parent) ::_exit(127);
    const int fd = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      ::dup2(fd, STDOUT_FILENO);
      ::dup2(fd, STDERR_FILENO);
    }
    ::execvp(pointers[0], pointers.data());
    ::_exit(127);
  }
  status.started = true;
  int raw = 0;
  while (::waitpid(pid, &raw, 0) < 0 && errno == EINTR) {
  }
  if (WIFSIGNALED(raw)) {
    status.signal = WTERMSIG(raw);
  } else if (WIFEXITED(raw)) {
    status.exit_code = WEXITSTATUS(raw);
  }
  return status;
}

bool ExecutableOnPath(const std::string& name) {
  const char* path = std::getenv("PATH");
  std::string_view dirs = path != nullptr ? path : "";
  while (true) {
    const size_t colon = dirs.find(':');
    const std::string_view dir = dirs.substr(0, colon);
    const std::filesystem::path candidate =
        std::filesystem::path(dir.empty() ? "." : std::string(dir)) / name;
    std::error_code ec;
    if (std::filesystem::is_regular_file(candidate, ec) && ::access(candidate.c_str(), X_OK) == 0) {
      return true;
    }
    if (colon == std::string_view::npos) return false;
    dirs.remove_prefix(colon + 1);
  }
}

bool ProcessIsGone(std::string_view pid_digits) {
  int pid = 0;
  const char* end = pid_digits.data() + pid_digits.size();
  if (pid_digits.empty() || pid_digits.front() < '0' || pid_digits.front() > '9') return false;
  const auto [ptr, ec] = std::from_chars(pid_digits.data(), end, pid);
  if (ec != std::errc() || ptr != end || pid <= 0) return false;
  // ESRCH: no such process. EPERM means one exists (of another user).
  if (::kill(pid, 0) == -1 && errno == ESRCH) return true;
  // A zombie has ended too: its parent has not collected its exit status
  // yet. An MPI job's ranks that mpirun left behind wait as zombies for init,
  // and a resumed sweep started at once must see their staging folders as
  // left over. The state is the field after the command's closing ')'.
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string line;
  if (!std::getline(stat, line)) return false;
  const size_t close = line.rfind(')');
  if (close == std::string::npos || close + 2 >= line.size()) return false;
  const char state = line[close + 2];
  return state == 'Z' || state == 'X';
}

}  // namespace hcpf
