#pragma once
// The project's worker threads: a parallel loop over independent items, a
// serial worker for a two-stage pipeline, and ordered workers for a pipeline
// whose middle stage runs on several threads.

#include <cstddef>
#include <functional>
#include <memory>
#include <vector>

namespace hcpf {

// Calls body(i) once for every i in [0, count) on min(workers, count)
// threads, the calling thread among them. Items are handed out one at a time
// from a shared counter, so items whose run times differ 100x still keep every
// thread busy; which thread runs an item is not fixed, so a body must touch
// only item i's own state (results are then the same for any `workers`).
// If a body throws, no further item is started and the first exception is
// rethrown once every thread has finished. workers <= 1 runs in order on the
// calling thread.
void ParallelFor(size_t count, int workers, const std::function<void(size_t)>& body);

// One thread that runs posted jobs one at a time, in the order they were
// posted: the second stage of a pipeline whose first stage is the posting
// thread (ProduceFrames renders frame t + 1 while it finishes frame t). A job
// may touch state that later jobs touch too (they never overlap); the poster
// must not touch it until Wait() returns.
class SerialWorker {
 public:
  // `queue_depth` (at least 1): how many jobs may wait besides the running
  // one before Post blocks, which bounds the memory jobs hold.
  explicit SerialWorker(int queue_depth = 1);
  // Waits for the posted jobs; an exception one of them threw is dropped
  // (call Wait to see it).
  ~SerialWorker();
  SerialWorker(const SerialWorker&) = delete;
  SerialWorker& operator=(const SerialWorker&) = delete;

  // Queues `job`, blocking while queue_depth jobs wait. Once a job has
  // thrown, the jobs queued after it are dropped unrun, and the next Post or
  // Wait rethrows that exception (once) instead of queuing: the poster learns
  // of a failure at its next step, not at the end.
  void Post(std::function<void()> job);
  // Returns when every posted job has run or been dropped; rethrows a job's
  // exception not yet rethrown.
  void Wait();

 private:
  struct State;
  std::unique_ptr<State> state_;
};

// Jobs in two parts: `work` on one of `workers` threads, several jobs' work
// at once, then `then` on one more thread, one job at a time in the order
// the jobs were posted, after that job's work has returned (and seeing what
// it wrote). ProduceFrames applies frame t's sensor effects beside frame
// t + 1's while frame t - 1 goes to the detector: the work of a job must
// touch only its own state; `then` may touch state shared by every job.
// Job i's work runs on thread i % workers (a fixed assignment: what a job
// computes cannot depend on the thread count unless its work reads another
// job's state, which it must not). workers <= 1 is one work thread.
//
// Errors: a work that throws skips its `then`; that exception, or one a
// `then` threw, is rethrown by the next Post or by Wait, once, and the jobs
// queued behind it then do not run their `then` (their work may still run),
// as SerialWorker drops its queue. A caller that stops at the exception
// finishes no frame after the failed one.
class OrderedWorkers {
 public:
  // `queue_depth` (at least 1) jobs may wait per work thread besides the
  // running one before Post blocks.
  explicit OrderedWorkers(int workers, int queue_depth = 1);
  ~OrderedWorkers();  // waits for the posted jobs; drops their errors (call Wait)
  OrderedWorkers(const OrderedWorkers&) = delete;
  OrderedWorkers& operator=(const OrderedWorkers&) = delete;

  void Post(std::function<void()> work, std::function<void()> then);
  void Wait();
  int workers() const { return static_cast<int>(work_.size()); }

 private:
  std::vector<std::unique_ptr<SerialWorker>> work_;
  std::unique_ptr<SerialWorker> ordered_;  // destroyed first: it waits on the work threads
  size_t posted_ = 0;
};

}  // namespace hcpf
