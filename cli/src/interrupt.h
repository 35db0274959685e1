#pragma once
// What a long command says when it is interrupted (Ctrl-C, SIGTERM from a
// batch system, a closed terminal).

#include <string>

namespace hcpf::cli {

// From now on SIGINT, SIGTERM and SIGHUP write "<message> (<signal>)\n" to
// stderr, then end the process by that signal as before (its default action,
// so the exit status a shell or a batch system sees is unchanged). A signal
// this process was started with ignored (a background job of a script,
// nohup) stays ignored. The message is copied once; the handler only
// write()s it. Call once, from the main thread, before the work starts.
void AnnounceInterrupts(const std::string& message);

// Puts back the actions AnnounceInterrupts replaced: from now on the message
// would be wrong (the command's output is complete).
void StopAnnouncingInterrupts();

// The message of `hcpf <command>` (run, render), which writes `out` through a
// staging folder renamed into place at the end: nothing was written to it,
// the staging folder (named) is removed by the next command into it, and
// with a frame cache `cache` (empty: none) the frames rendered so far are
// kept there for the same command to start from.
std::string InterruptedMessage(const std::string& command, const std::string& out,
                               const std::string& cache);

}  // namespace hcpf::cli
