#pragma once
// An external tracker: a child program that tracks over a line protocol of
// JSON objects on its stdin and stdout (docs/external-trackers.md, protocol
// version kExternalProtocolVersion). The run pipeline sends it a hello, then
// each frame's detections (and the path of the frame's image when the run
// writes one), and reads back the frame's tracks.
//
// Failure contract: anything that is not the protocol — the program cannot be
// started, exits or closes its stdout early, answers with a line that is not
// the expected JSON object, a wrong frame number, or no answer within
// `timeout_s` — throws RunError whose message names the command, the frame,
// what was wrong, the offending line (cut to 200 characters) and the last
// lines the program wrote to stderr. The child is then killed (SIGKILL to its
// process group, so a shell script's children go too) and reaped; the
// destructor does the same for a run that fails elsewhere. Nothing here
// blocks without a deadline: stdin, stdout and stderr are polled together, so
// a child that writes a lot to stderr, or stops reading its stdin, cannot
// stall the run beyond `timeout_s`.
//
// Not thread-safe (one instance per run); several instances in one process
// (a sweep's threads) are independent. SIGPIPE is blocked in the calling
// thread around each write, never ignored process-wide.

#include <sys/types.h>

#include <chrono>
#include <string>
#include <vector>

#include "hcpf/core/types.h"

namespace hcpf::scenarios::internal {

inline constexpr int kExternalProtocolVersion = 1;

// What the hello tells the program about the run.
struct ExternalHello {
  std::string scenario;
  int frames = 0;
  double fps = 0.0;
  int width_px = 0;
  int height_px = 0;
  double hfov_deg = 0.0;
  bool images = false;  // whether frames carry an image path
};

// One track of a reply: a positive id, a box (left, top, width, height in
// 0-based pixels, width and height > 0) and a score.
struct ExternalTrack {
  int32_t id = 0;
  BoxPx box;
  double score = 0.0;
};

class ExternalTracker {
 public:
  // Starts `command` (argv; argv[0] a path, or a name looked up on PATH),
  // sends the hello and waits for the ready reply. Throws RunError.
  ExternalTracker(const std::vector<std::string>& command, double timeout_s,
                  const ExternalHello& hello);
  ~ExternalTracker();
  ExternalTracker(const ExternalTracker&) = delete;
  ExternalTracker& operator=(const ExternalTracker&) = delete;

  // Sends frame `frame` (0-based) and returns the program's tracks for it.
  // `image_path` empty: null in the message. Throws RunError.
  std::vector<ExternalTrack> Step(int frame, const std::string& image_path,
                                  const Observation& observation);
  // Sends the end message, closes the program's stdin and waits (timeout_s)
  // for it to exit with status 0. Throws RunError.
  void Finish();

  // The program's name and protocol for the manifest.
  const std::vector<std::string>& command() const { return command_; }
  // The "name" of the ready reply ("" when it gave none).
  const std::string& name() const { return name_; }

 private:
  using Clock = std::chrono::steady_clock;

  [[noreturn]] void Fail(const std::string& what, const std::string& line = {});
  void Send(const std::string& line, Clock::time_point deadline, const std::string& context);
  // The next stdout line; Fail()s on timeout or end of output.
  std::string ReadLine(Clock::time_point deadline, const std::string& context);
  // One poll over the open pipes until `deadline`; false on timeout.
  bool Pump(Clock::time_point deadline);
  void ReadStderr();
  void Kill();
  // Reaps the child if it has ended (killing what it left in its group).
  bool TryReap();
  std::string ExitText();  // "exited with status 3" / "killed by signal 9" (reaps)
  Clock::time_point Deadline() const;

  std::vector<std::string> command_;
  double timeout_s_ = 10.0;
  pid_t pid_ = -1;
  bool reaped_ = false;
  int wait_status_ = 0;
  int in_fd_ = -1;        // the child's stdin (ours to write)
  int out_fd_ = -1;       // the child's stdout
  int err_fd_ = -1;       // the child's stderr
  std::string pending_;   // bytes still to write to stdin
  std::string out_buf_;   // stdout bytes not yet returned as lines
  std::string err_tail_;  // the last kStderrTail bytes of stderr
  std::string name_;
  int frame_ = -1;  // the frame being answered (-1: the hello)
};

}  // namespace hcpf::scenarios::internal
