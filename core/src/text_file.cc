#include "hcpf/core/text_file.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "hcpf/core/error.h"
#include "hcpf/core/subprocess.h"

namespace hcpf {
namespace {

// Closes a file descriptor on every path out of a function.
class Fd {
 public:
  explicit Fd(int fd) : fd_(fd) {}
  ~Fd() {
    if (fd_ >= 0) ::close(fd_);
  }
  Fd(const Fd&) = delete;
  Fd& operator=(const Fd&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

const char* KindOf(mode_t mode) {
  if (S_ISDIR(mode)) return "a directory";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

std::string SizeText(uint64_t bytes) {
  if (bytes >= (uint64_t{1} << 20)) return fmt::format("{:.1f} MiB", bytes / 1048576.0);
  return fmt::format("{} bytes", bytes);
}

// A file that exists but may not be read is an I/O problem (exit 1) to fix
// with permissions, not bad input; a missing one is bad input.
[[noreturn]] void ThrowCannotOpen(const std::string& path, const std::string& what, int error) {
  if (error == EACCES || error == EPERM) {
    throw RunError(fmt::format("cannot read {} ({}): check its permissions and its folder's", path,
                               std::strerror(error)));
  }
  throw InputError(SourceLocation{path, 0, 0, ""}, what,
                   fmt::format("it cannot be opened ({})", std::strerror(error)));
}

// Opens `path` without blocking (a FIFO with no writer would block open()),
// and checks it is a regular file. Returns the descriptor and its size.
int OpenRegular(const std::string& path, const std::string& what, uint64_t* size) {
  struct stat st {};
  // stat first: opening a FIFO, even non-blocking, is not needed to refuse it.
  if (::stat(path.c_str(), &st) != 0) ThrowCannotOpen(path, what, errno);
  if (!S_ISREG(st.st_mode)) {
    throw InputError(SourceLocation{path, 0, 0, ""}, fmt::format("{} (a regular file)", what),
                     KindOf(st.st_mode));
  }
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
  if (fd < 0) ThrowCannotOpen(path, what, errno);
  // Check the opened file too: the path may have been replaced in between.
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    throw InputError(SourceLocation{path, 0, 0, ""}, fmt::format("{} (a regular file)", what),
                     KindOf(st.st_mode));
  }
  *size = static_cast<uint64_t>(st.st_size);
  return fd;
}

// Reads up to `count` bytes from `fd` into `out` (resized to what was read).
void ReadUpTo(int fd, const std::string& path, size_t count, std::string* out) {
  out->resize(count);
  size_t done = 0;
  while (done < count) {
    const ssize_t n = ::read(fd, out->data() + done, count - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      throw RunError(fmt::format("reading {} failed: {}", path, std::strerror(errno)));
    }
    if (n == 0) break;
    done += static_cast<size_t>(n);
  }
  out->resize(done);
}

}  // namespace

std::filesystem::path TempFileFor(const std::filesystem::path& path) {
  // The counter keeps two threads apart.
  static std::atomic<uint64_t> counter{0};
  return path.parent_path() /
         fmt::format(".{}.tmp-{}-{}", path.filename().string(), ::getpid(), counter.fetch_add(1));
}

bool IsStandardOutput(const std::string& path) {
  struct stat out {};
  struct stat at {};
  // A device (a terminal, /dev/null) takes two writers in turn without
  // offsets to clash or a reader to confuse: only a file, a pipe or a socket
  // counts (a review: `--json /dev/null > /dev/null` sent the table to stderr).
  return ::fstat(STDOUT_FILENO, &out) == 0 && ::stat(path.c_str(), &at) == 0 &&
         out.st_dev == at.st_dev && out.st_ino == at.st_ino &&
         (S_ISREG(out.st_mode) || S_ISFIFO(out.st_mode) || S_ISSOCK(out.st_mode));
}

void WriteTextFile(const std::string& path, const std::string& text) {
  if (IsStandardOutput(path)) {
    // After what was printed there (std::cout is synced with stdio's buffer).
    std::cout.flush();
    errno = 0;
    if (std::fwrite(text.data(), 1, text.size(), stdout) != text.size() ||
        std::fflush(stdout) != 0) {
      throw RunError(fmt::format("writing {} (standard output) failed: {}", path,
                                 std::strerror(errno != 0 ? errno : EIO)));
    }
    return;
  }
  struct stat st {};
  const bool exists = ::lstat(path.c_str(), &st) == 0;
  if (exists && !S_ISREG(st.st_mode)) {
    // A device (/dev/stdout), a FIFO or a symbolic link is written through,
    // in place: there is no file of ours to replace.
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    if (!out) throw RunError(fmt::format("cannot write {}: {}", path, std::strerror(errno)));
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out) throw RunError(fmt::format("writing {} failed: {}", path, std::strerror(errno)));
    return;
  }
  // A file is written whole beside its final name, then renamed over it, so a
  // write that fails (a full disk) or is killed part-way leaves the earlier
  // file as it was instead of a truncated one that looks complete (a report a
  // browser shows without complaint).
  const std::string temp = TempFileFor(path).string();
  const int fd = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) throw RunError(fmt::format("cannot write {}: {}", path, std::strerror(errno)));
  int open_fd = fd;
  const auto fail = [&](const char* what, int error) {
    if (open_fd >= 0) ::close(open_fd);
    ::unlink(temp.c_str());
    throw RunError(fmt::format("{} {} failed: {}", what, path, std::strerror(error)));
  };
  // An existing file keeps its permissions, as when it was truncated in place.
  if (exists && ::fchmod(fd, st.st_mode & 07777) != 0) fail("writing", errno);
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t n = ::write(fd, text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) fail("writing", errno);
    done += static_cast<size_t>(n);
  }
  open_fd = -1;
  if (::close(fd) != 0) fail("writing", errno);
  if (::rename(temp.c_str(), path.c_str()) != 0) fail("replacing", errno);
}

size_t ByteOrderMarkLength(std::string_view text) {
  return text.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;
}

bool StartsWithTwoSigns(std::string_view text) {
  return text.size() >= 2 && text[0] == '+' && (text[1] == '+' || text[1] == '-');
}

TextPosition PositionOf(std::string_view text, size_t offset) {
  offset = std::min(offset, text.size());
  const size_t newline = offset == 0 ? std::string_view::npos : text.rfind('\n', offset - 1);
  const size_t line_start = newline == std::string_view::npos ? 0 : newline + 1;
  const size_t first_column = line_start == 0 ? ByteOrderMarkLength(text) : line_start;
  return {.line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + offset, '\n')),
          .column = static_cast<int>(offset - std::min(offset, first_column)) + 1};
}

std::string TempFileTarget(std::string_view entry) {
  const size_t at = entry.rfind(".tmp-");
  if (entry.size() < 2 || entry[0] != '.' || at == std::string_view::npos || at < 2) return "";
  const std::string_view numbers = entry.substr(at + 5);  // "<pid>-<n>"
  const size_t dash = numbers.find('-');
  const auto digits = [](std::string_view text) {
    return !text.empty() &&
           std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
  };
  if (dash == std::string_view::npos || !digits(numbers.substr(0, dash)) ||
      !digits(numbers.substr(dash + 1))) {
    return "";
  }
  return std::string(entry.substr(1, at - 1));
}

void RemoveStaleTempFiles(const std::filesystem::path& dir) {
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    const std::string target = TempFileTarget(name);
    if (target.empty() || !entry.is_regular_file(ec)) continue;
    // ".<target>.tmp-<pid>-<n>": the pid's digits were checked by TempFileTarget.
    const std::string_view numbers = std::string_view(name).substr(target.size() + 6);
    if (ProcessIsGone(numbers.substr(0, numbers.find('-')))) {
      std::filesystem::remove(entry.path(), ec);
    }
  }
}

uint64_t CheckRegularFile(const std::string& path, const std::string& what) {
  uint64_t size = 0;
  const Fd fd(OpenRegular(path, what, &size));
  return size;
}

std::string ReadInputFile(const std::string& path, const std::string& what, uint64_t max_bytes) {
  uint64_t size = 0;
  const Fd fd(OpenRegular(path, what, &size));
  if (size > max_bytes) {
    throw InputError(SourceLocation{path, 0, 0, ""},
                     fmt::format("{} of at most {}", what, SizeText(max_bytes)), SizeText(size));
  }
  std::string text;
  // One byte more than the size: a file that grew since fstat is caught.
  ReadUpTo(fd.get(), path, static_cast<size_t>(size) + 1, &text);
  if (text.size() > size) {
    throw InputError(SourceLocation{path, 0, 0, ""}, what, "a file that grows while it is read");
  }
  return text;
}

std::string ReadFilePrefix(const std::string& path, size_t count) {
  uint64_t size = 0;
  const Fd fd(OpenRegular(path, "a file", &size));
  std::string text;
  ReadUpTo(fd.get(), path, count, &text);
  return text;
}

void CheckFilesToWrite(const std::vector<FileToWrite>& writes, const std::vector<FileRead>& reads,
                       const std::vector<std::filesystem::path>& reads_under,
                       const std::string& command, const std::string& consequence) {
  namespace fs = std::filesystem;
  std::error_code ec;
  for (size_t i = 0; i < writes.size(); ++i) {
    const auto& [path, option] = writes[i];
    const SourceLocation where{path, 0, 0, option};
    if (fs::is_directory(path, ec)) throw InputError(where, "a file to write", "a folder");
    const fs::path parent = fs::path(path).parent_path();
    if (!parent.empty() && !fs::is_directory(parent, ec)) {
      throw InputError(where, "a file in an existing folder",
                       fmt::format("no folder {}", parent.string()));
    }
    // equivalent() needs both to exist; an output not there yet is no input.
    if (fs::exists(path, ec)) {
      for (const auto& [read, what] : reads) {
        if (!read.empty() && fs::equivalent(path, read, ec)) {
          throw InputError(where, fmt::format("a file {} does not read", command), what,
                           consequence);
        }
      }
    }
    const fs::path mine = fs::weakly_canonical(path, ec);
    for (size_t k = 0; k < i; ++k) {
      if (fs::weakly_canonical(writes[k].path, ec) == mine) {
        throw InputError(where, "a file of its own",
                         fmt::format("the file {} writes too", writes[k].option), consequence);
      }
    }
    for (const fs::path& folder : reads_under) {
      const fs::path root = fs::weakly_canonical(folder, ec);
      const auto [end, unused] = std::mismatch(root.begin(), root.end(), mine.begin(), mine.end());
      if (end == root.end()) {
        throw InputError(where, fmt::format("a file outside the folders {} reads", command),
                         fmt::format("a file in {}", folder.string()), consequence);
      }
    }
  }
}

}  // namespace hcpf
