#include "external_tracker.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <nlohmann/json.hpp>
#include <set>

#include "hcpf/core/error.h"
#include "hcpf/core/names.h"

extern char** environ;

namespace hcpf::scenarios::internal {
namespace {

// What a failure message keeps of the child's stderr: its last 20 lines, at
// most 4 KiB (enough for a Python traceback's last frames).
constexpr size_t kStderrTail = 4096;
constexpr int kStderrLines = 20;
// A reply line longer than this is refused: a frame's tracks are a few
// hundred bytes per track, so 16 MiB is a program that writes without end.
constexpr size_t kMaxLine = size_t{16} << 20;
// How much of an offending line a message quotes.
constexpr size_t kQuote = 200;

// `text` as printed: control characters (ESC, BEL, CR, ...) become '?', so a
// program's output cannot clear the terminal or overwrite the diagnosis (a
// third bad-input audit); tabs stay when `keep_tabs`.
std::string Printable(const std::string& text, bool keep_tabs) {
  std::string out;
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    out += (!(keep_tabs && c == '\t') && (u < 0x20 || u == 0x7f)) ? '?' : c;
  }
  return out;
}

// An offending line as quoted in a message: its first kQuote bytes, printable.
std::string Quote(const std::string& line) {
  std::string out = Printable(line.substr(0, kQuote), /*keep_tabs=*/false);
  if (line.size() > kQuote) out += fmt::format("... ({} bytes)", line.size());
  return out;
}

// The last kStderrLines lines of `text`.
std::string LastLines(const std::string& text) {
  size_t end = text.size();
  while (end > 0 && text[end - 1] == '\n') --end;
  size_t begin = end;
  for (int n = 0; n < kStderrLines && begin > 0; ++n) {
    const size_t eol = text.rfind('\n', begin - 1);
    begin = eol == std::string::npos ? 0 : eol;
    if (eol == std::string::npos) break;
  }
  if (begin < end && text[begin] == '\n') ++begin;
  return text.substr(begin, end - begin);
}

void SetNonBlocking(int fd) { ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) | O_NONBLOCK); }

void CloseFd(int& fd) {
  if (fd >= 0) ::close(fd);
  fd = -1;
}

double Finite(const nlohmann::json& j, const char* what) {
  if (!j.is_number()) throw std::invalid_argument(fmt::format("{} is not a number", what));
  const double v = j.get<double>();
  if (!std::isfinite(v)) throw std::invalid_argument(fmt::format("{} is not finite", what));
  return v;
}

// A reply object's tracks; std::invalid_argument saying what is wrong.
std::vector<ExternalTrack> ParseTracks(const nlohmann::json& tracks) {
  if (!tracks.is_array()) throw std::invalid_argument("\"tracks\" is not a list");
  std::vector<ExternalTrack> out;
  std::set<int32_t> ids;
  for (size_t i = 0; i < tracks.size(); ++i) {
    const nlohmann::json& t = tracks[i];
    const std::string at = fmt::format("tracks[{}]", i);
    if (!t.is_object()) throw std::invalid_argument(at + " is not an object");
    for (const auto& item : t.items()) {
      if (item.key() != "id" && item.key() != "box" && item.key() != "score") {
        throw std::invalid_argument(fmt::format("{} has an unknown key \"{}\"", at, item.key()));
      }
    }
    if (!t.contains("id") || !t["id"].is_number_integer()) {
      throw std::invalid_argument(at + ".id is not an integer");
    }
    const int64_t id = t["id"].get<int64_t>();
    if (id < 1 || id > 1'000'000'000) {
      throw std::invalid_argument(fmt::format("{}.id {} is not in [1, 1000000000]", at, id));
    }
    if (!ids.insert(static_cast<int32_t>(id)).second) {
      throw std::invalid_argument(fmt::format("{}.id {} is used twice in the frame", at, id));
    }
    if (!t.contains("box") || !t["box"].is_array() || t["box"].size() != 4) {
      throw std::invalid_argument(at + ".box is not a list of 4 numbers [left, top, w, h]");
    }
    ExternalTrack track;
    track.id = static_cast<int32_t>(id);
    const std::string box = at + ".box";
    track.box = {Finite(t["box"][0], box.c_str()), Finite(t["box"][1], box.c_str()),
                 Finite(t["box"][2], box.c_str()), Finite(t["box"][3], box.c_str())};
    if (!(track.box.width > 0.0 && track.box.height > 0.0)) {
      throw std::invalid_argument(at + ".box has a width or height <= 0");
    }
    const std::string score = at + ".score";
    track.score = t.contains("score") ? Finite(t["score"], score.c_str()) : 1.0;
    out.push_back(track);
  }
  return out;
}

// The reply line as a JSON object of `type`; std::invalid_argument otherwise.
nlohmann::json ParseReply(const std::string& line, const char* type) {
  nlohmann::json j = nlohmann::json::parse(line, nullptr, /*allow_exceptions=*/false);
  if (j.is_discarded()) throw std::invalid_argument("not a JSON value");
  if (!j.is_object()) throw std::invalid_argument("not a JSON object");
  if (!j.contains("type") || !j["type"].is_string() || j["type"].get<std::string>() != type) {
    throw std::invalid_argument(fmt::format("not a \"type\": \"{}\" object", type));
  }
  return j;
}

}  // namespace

ExternalTracker::ExternalTracker(const std::vector<std::string>& command, double timeout_s,
                                 const ExternalHello& hello)
    : command_(command), timeout_s_(timeout_s) {
  if (command_.empty()) throw RunError("external tracker: an empty command");
  int in[2] = {-1, -1}, out[2] = {-1, -1}, err[2] = {-1, -1};
  if (::pipe2(in, O_CLOEXEC) != 0 || ::pipe2(out, O_CLOEXEC) != 0 || ::pipe2(err, O_CLOEXEC) != 0) {
    const int e = errno;
    for (int fd : {in[0], in[1], out[0], out[1], err[0], err[1]}) {
      if (fd >= 0) ::close(fd);
    }
    throw RunError(fmt::format("external tracker: cannot create pipes: {}", std::strerror(e)));
  }
  // posix_spawn, not fork: safe in a threaded process (a sweep's workers),
  // and glibc reports a failed exec as its return value. Every pipe end is
  // close-on-exec; dup2 gives the child its three ends without the flag.
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, in[0], 0);
  posix_spawn_file_actions_adddup2(&actions, out[1], 1);
  posix_spawn_file_actions_adddup2(&actions, err[1], 2);
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  // Its own process group: a kill reaches the children of a script too.
  // Default SIGPIPE in the child whatever ours is.
  sigset_t default_signals;
  sigemptyset(&default_signals);
  sigaddset(&default_signals, SIGPIPE);
  posix_spawnattr_setsigdefault(&attr, &default_signals);
  sigset_t no_signals;
  sigemptyset(&no_signals);
  posix_spawnattr_setsigmask(&attr, &no_signals);
  posix_spawnattr_setpgroup(&attr, 0);
  posix_spawnattr_setflags(&attr,
                           POSIX_SPAWN_SETPGROUP | POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETSIGMASK);
  std::vector<char*> argv;
  for (const std::string& a : command_) argv.push_back(const_cast<char*>(a.c_str()));
  argv.push_back(nullptr);
  const int rc = ::posix_spawnp(&pid_, argv[0], &actions, &attr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  posix_spawnattr_destroy(&attr);
  ::close(in[0]);
  ::close(out[1]);
  ::close(err[1]);
  in_fd_ = in[1];
  out_fd_ = out[0];
  err_fd_ = err[0];
  if (rc != 0) {
    pid_ = -1;
    CloseFd(in_fd_);
    CloseFd(out_fd_);
    CloseFd(err_fd_);
    throw RunError(fmt::format("external tracker: cannot start \"{}\": {}", command_.front(),
                               std::strerror(rc)));
  }
  SetNonBlocking(in_fd_);
  SetNonBlocking(out_fd_);
  SetNonBlocking(err_fd_);

  nlohmann::json h = {{"type", "hello"},
                      {"protocol", kExternalProtocolVersion},
                      {"scenario", hello.scenario},
                      {"frames", hello.frames},
                      {"fps", hello.fps},
                      {"image", {{"width", hello.width_px}, {"height", hello.height_px}}},
                      {"camera", {{"hfov_deg", hello.hfov_deg}}},
                      {"images", hello.images}};
  const auto deadline = Deadline();
  Send(h.dump() + "\n", deadline, "the hello");
  const std::string line = ReadLine(deadline, "the ready reply to the hello");
  try {
    const nlohmann::json j = ParseReply(line, "ready");
    if (!j.contains("protocol") || !j["protocol"].is_number_integer() ||
        j["protocol"].get<int64_t>() != kExternalProtocolVersion) {
      throw std::invalid_argument(fmt::format("\"protocol\" is not {} (the version hcpf speaks)",
                                              kExternalProtocolVersion));
    }
    if (j.contains("name")) {
      if (!j["name"].is_string()) throw std::invalid_argument("\"name\" is not a string");
      name_ = j["name"].get<std::string>();
      // The name goes into manifest.json and the logs: one printable line,
      // as a scenario's name (a third bad-input audit stored ESC and CR).
      if (const std::string c = FirstControlCharacter(name_); !c.empty()) {
        throw std::invalid_argument(fmt::format("\"name\" holds the control character {}", c));
      }
    }
  } catch (const std::invalid_argument& e) {
    Fail(fmt::format("a malformed ready reply to the hello ({})", e.what()), line);
  }
}

ExternalTracker::~ExternalTracker() {
  if (pid_ > 0 && !reaped_) Kill();
  CloseFd(in_fd_);
  CloseFd(out_fd_);
  CloseFd(err_fd_);
}

ExternalTracker::Clock::time_point ExternalTracker::Deadline() const {
  return Clock::now() +
         std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(timeout_s_));
}

std::vector<ExternalTrack> ExternalTracker::Step(int frame, const std::string& image_path,
                                                 const Observation& observation) {
  frame_ = frame;
  nlohmann::json detections = nlohmann::json::array();
  for (const Detection& d : observation.detections) {
    nlohmann::json det = {{"box", {d.box.left, d.box.top, d.box.width, d.box.height}},
                          {"score", d.score}};
    // A target-specific detector's target (a detector output, not ground
    // truth: the simulated detector's `source` is never sent).
    if (d.target) det["target"] = Value(*d.target);
    detections.push_back(std::move(det));
  }
  nlohmann::json message = {
      {"type", "frame"},
      {"frame", frame},
      {"image", image_path.empty() ? nlohmann::json() : nlohmann::json(image_path)},
      {"detections", std::move(detections)}};
  const auto deadline = Deadline();
  Send(message.dump() + "\n", deadline, fmt::format("frame {}", frame));
  const std::string line = ReadLine(deadline, fmt::format("the tracks of frame {}", frame));
  try {
    const nlohmann::json j = ParseReply(line, "tracks");
    if (!j.contains("frame") || !j["frame"].is_number_integer()) {
      throw std::invalid_argument("\"frame\" is not an integer");
    }
    if (j["frame"].get<int64_t>() != frame) {
      throw std::invalid_argument(
          fmt::format("\"frame\" is {}, the frame sent was {}", j["frame"].get<int64_t>(), frame));
    }
    if (!j.contains("tracks")) throw std::invalid_argument("no \"tracks\"");
    return ParseTracks(j["tracks"]);
  } catch (const std::invalid_argument& e) {
    Fail(fmt::format("a malformed reply to frame {} ({})", frame, e.what()), line);
  }
}

void ExternalTracker::Finish() {
  frame_ = -2;
  const auto deadline = Deadline();
  Send("{\"type\":\"end\"}\n", deadline, "the end message");
  CloseFd(in_fd_);
  // Its stdout to its end: anything more than blank lines is an error. Read
  // in short slices, reaping between them: once the program has ended,
  // TryReap kills the rest of its process group, so a child it left holding
  // the pipe (a shell script's background job) cannot keep the run waiting
  // until timeout_s and then be reported as a program that did not exit.
  while (out_fd_ >= 0) {
    const auto slice = std::min(deadline, Clock::now() + std::chrono::milliseconds(50));
    if (Pump(slice)) continue;
    if (Clock::now() < deadline) {
      TryReap();
      continue;
    }
    if (reaped_) {
      Fail(
          fmt::format("its standard output still open timeout_s = {} s after the end message, "
                      "though the program {}: a process it started outside its process group "
                      "(setsid, a daemon) holds it",
                      timeout_s_, ExitText()));
    }
    Fail(fmt::format("no exit within timeout_s = {} s of the end message", timeout_s_));
  }
  const size_t text = out_buf_.find_first_not_of(" \t\r\n");
  if (text != std::string::npos) {
    const size_t eol = out_buf_.find('\n', text);
    Fail("output after the end message",
         out_buf_.substr(text, eol == std::string::npos ? std::string::npos : eol - text));
  }
  // Then its exit, polled (waitpid has no timeout).
  while (!TryReap()) {
    if (Clock::now() >= deadline) {
      Fail(fmt::format("no exit within timeout_s = {} s of the end message", timeout_s_));
    }
    if (err_fd_ >= 0) {
      Pump(std::min(deadline, Clock::now() + std::chrono::milliseconds(5)));
    } else {
      ::usleep(2000);
    }
  }
  if (!WIFEXITED(wait_status_) || WEXITSTATUS(wait_status_) != 0) {
    Fail(fmt::format("the program {} after the end message (expected: status 0)", ExitText()));
  }
}

void ExternalTracker::Send(const std::string& line, Clock::time_point deadline,
                           const std::string& context) {
  pending_ += line;
  while (!pending_.empty()) {
    if (in_fd_ < 0) Fail(fmt::format("the program closed its stdin before {}", context));
    if (!Pump(deadline)) {
      Fail(fmt::format("the program did not read {} within timeout_s = {} s", context, timeout_s_));
    }
  }
}

std::string ExternalTracker::ReadLine(Clock::time_point deadline, const std::string& context) {
  while (true) {
    const size_t eol = out_buf_.find('\n');
    if (eol != std::string::npos) {
      std::string line = out_buf_.substr(0, eol);
      out_buf_.erase(0, eol + 1);
      if (!line.empty() && line.back() == '\r') line.pop_back();
      return line;
    }
    if (out_buf_.size() > kMaxLine) {
      Fail(fmt::format("a line longer than {} bytes instead of {}", kMaxLine, context),
           out_buf_.substr(0, kQuote));
    }
    if (out_fd_ < 0) {
      // Give a dying program a moment to be reaped, so the message says how
      // it ended.
      Fail(fmt::format("the program closed its stdout ({}) instead of sending {}", ExitText(),
                       context),
           out_buf_);
    }
    if (!Pump(deadline)) {
      Fail(fmt::format("no reply within timeout_s = {} s: waiting for {}", timeout_s_, context),
           out_buf_);
    }
  }
}

bool ExternalTracker::Pump(Clock::time_point deadline) {
  pollfd fds[3];
  nfds_t n = 0;
  int in_at = -1, out_at = -1, err_at = -1;
  if (in_fd_ >= 0 && !pending_.empty()) {
    in_at = static_cast<int>(n);
    fds[n++] = {in_fd_, POLLOUT, 0};
  }
  if (out_fd_ >= 0) {
    out_at = static_cast<int>(n);
    fds[n++] = {out_fd_, POLLIN, 0};
  }
  if (err_fd_ >= 0) {
    err_at = static_cast<int>(n);
    fds[n++] = {err_fd_, POLLIN, 0};
  }
  // Past the deadline is a timeout even while a chatty child keeps the
  // pipes busy.
  const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now());
  if (left.count() <= 0) return false;
  const int ready = ::poll(fds, n, static_cast<int>(std::max<int64_t>(0, left.count())) + 1);
  if (ready < 0) {
    if (errno == EINTR) return true;
    throw RunError(fmt::format("external tracker: poll: {}", std::strerror(errno)));
  }
  if (ready == 0) return Clock::now() < deadline;
  if (err_at >= 0 && fds[err_at].revents != 0) ReadStderr();
  if (out_at >= 0 && fds[out_at].revents != 0) {
    char buf[65536];
    const ssize_t got = ::read(out_fd_, buf, sizeof buf);
    if (got > 0) {
      out_buf_.append(buf, static_cast<size_t>(got));
    } else if (got == 0 || (errno != EAGAIN && errno != EINTR)) {
      CloseFd(out_fd_);
    }
  }
  if (in_at >= 0 && fds[in_at].revents != 0) {
    // A child that closed its stdin raises SIGPIPE on this write: blocked
    // here and taken back below, so it never reaches the process.
    sigset_t pipe_set, old_set;
    sigemptyset(&pipe_set);
    sigaddset(&pipe_set, SIGPIPE);
    pthread_sigmask(SIG_BLOCK, &pipe_set, &old_set);
    const ssize_t wrote = ::write(in_fd_, pending_.data(), pending_.size());
    const int e = errno;
    if (wrote < 0 && e == EPIPE) {
      const timespec zero{0, 0};
      while (sigtimedwait(&pipe_set, nullptr, &zero) == -1 && errno == EINTR) {
      }
    }
    pthread_sigmask(SIG_SETMASK, &old_set, nullptr);
    if (wrote > 0) {
      pending_.erase(0, static_cast<size_t>(wrote));
    } else if (wrote < 0 && e != EAGAIN && e != EINTR) {
      CloseFd(in_fd_);
    }
  }
  return true;
}

void ExternalTracker::ReadStderr() {
  char buf[8192];
  const ssize_t got = ::read(err_fd_, buf, sizeof buf);
  if (got > 0) {
    err_tail_.append(buf, static_cast<size_t>(got));
    if (err_tail_.size() > 2 * kStderrTail) err_tail_.erase(0, err_tail_.size() - kStderrTail);
  } else if (got == 0 || (errno != EAGAIN && errno != EINTR)) {
    CloseFd(err_fd_);
  }
}

bool ExternalTracker::TryReap() {
  if (reaped_) return true;
  siginfo_t info{};
  if (::waitid(P_PID, static_cast<id_t>(pid_), &info, WEXITED | WNOHANG | WNOWAIT) != 0 ||
      info.si_pid != pid_) {
    return false;
  }
  // It has ended: the children it left in its process group go too. The
  // leader, a zombie until reaped below, still holds the group's id, so the
  // kill cannot reach a process that reused it.
  ::kill(-pid_, SIGKILL);
  while (::waitpid(pid_, &wait_status_, 0) < 0 && errno == EINTR) {
  }
  reaped_ = true;
  return true;
}

void ExternalTracker::Kill() {
  if (pid_ <= 0 || reaped_) return;
  ::kill(-pid_, SIGKILL);
  ::kill(pid_, SIGKILL);
  while (::waitpid(pid_, &wait_status_, 0) < 0 && errno == EINTR) {
  }
  reaped_ = true;
}

std::string ExternalTracker::ExitText() {
  if (!reaped_) {
    // It closed its stdout: it is most likely exiting. Wait up to 200 ms
    // (then kill) so the message can say how it ended.
    const auto until = Clock::now() + std::chrono::milliseconds(200);
    while (!TryReap() && Clock::now() < until) ::usleep(2000);
    if (!reaped_) return "still running";
  }
  if (WIFEXITED(wait_status_))
    return fmt::format("exited with status {}", WEXITSTATUS(wait_status_));
  if (WIFSIGNALED(wait_status_)) {
    return fmt::format("killed by signal {}", WTERMSIG(wait_status_));
  }
  return "ended";
}

void ExternalTracker::Fail(const std::string& what, const std::string& line) {
  // Collect what is left of stderr (a crashing program's traceback) for a
  // short while, then kill the program.
  const auto until = Clock::now() + std::chrono::milliseconds(100);
  while (err_fd_ >= 0 && Clock::now() < until) {
    pollfd p{err_fd_, POLLIN, 0};
    if (::poll(&p, 1, 20) > 0) {
      ReadStderr();
    }
  }
  Kill();
  // A failure in the constructor skips the destructor: close the pipes here.
  CloseFd(in_fd_);
  CloseFd(out_fd_);
  CloseFd(err_fd_);
  std::string where = frame_ == -1   ? "at the hello"
                      : frame_ == -2 ? "at the end"
                                     : fmt::format("at frame {}", frame_);
  std::string message =
      fmt::format("external tracker \"{}\" {}: {}", command_.front(), where, what);
  if (!line.empty()) message += fmt::format("\n  offending line: {}", Quote(line));
  const std::string tail =
      LastLines(err_tail_.size() > kStderrTail ? err_tail_.substr(err_tail_.size() - kStderrTail)
                                               : err_tail_);
  if (tail.empty()) {
    message += "\n  stderr: (nothing)";
  } else {
    message += "\n  stderr (last lines):";
    size_t at = 0;
    while (at < tail.size()) {
      size_t eol = tail.find('\n', at);
      if (eol == std::string::npos) eol = tail.size();
      message += "\n    " + Printable(tail.substr(at, eol - at), /*keep_tabs=*/true);
      at = eol + 1;
    }
  }
  throw RunError(message);
}

}  // namespace hcpf::scenarios::internal
