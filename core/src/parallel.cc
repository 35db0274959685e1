#include "hcpf/core/parallel.h"

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <deque>
#include <exception>
#include <future>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

namespace hcpf {

void ParallelFor(size_t count, int workers, const std::function<void(size_t)>& body) {
  const size_t threads = std::min(count, static_cast<size_t>(std::max(workers, 1)));
  if (threads <= 1) {
    for (size_t i = 0; i < count; ++i) body(i);
    return;
  }
  std::atomic<size_t> next{0};
  std::atomic<bool> stop{false};
  std::mutex mutex;
  std::exception_ptr first_error;
  const auto work = [&] {
    for (size_t i = next.fetch_add(1); i < count && !stop.load(); i = next.fetch_add(1)) {
      try {
        body(i);
      } catch (...) {
        std::lock_guard lock(mutex);
        if (!first_error) first_error = std::current_exception();
        stop = true;
      }
    }
  };
  {
    std::vector<std::jthread> pool;
    pool.reserve(threads - 1);
    for (size_t t = 1; t < threads; ++t) pool.emplace_back(work);
    work();
  }  // joins
  if (first_error) std::rethrow_exception(first_error);
}

struct SerialWorker::State {
  explicit State(size_t depth) : queue_depth(depth) {}
  size_t queue_depth;
  std::mutex mutex;
  std::condition_variable changed;
  std::deque<std::function<void()>> queue;
  bool busy = false;  // a job is running, outside the queue
  bool closing = false;
  std::exception_ptr error;  // thrown by a job, not yet rethrown
  std::thread thread;

  void Run() {
    std::unique_lock lock(mutex);
    while (true) {
      changed.wait(lock, [&] { return closing || !queue.empty(); });
      if (queue.empty()) return;  // closing and drained
      std::function<void()> job = std::move(queue.front());
      queue.pop_front();
      busy = true;
      changed.notify_all();  // room in the queue
      lock.unlock();
      std::exception_ptr failure;
      try {
        job();
      } catch (...) {
        failure = std::current_exception();
      }
      job = nullptr;  // what the job holds goes before the poster is told
      lock.lock();
      busy = false;
      if (failure) {
        if (!error) error = failure;
        queue.clear();
      }
      changed.notify_all();
    }
  }

  // With `lock` held: rethrows (and forgets) a job's exception.
  void RethrowError() {
    if (!error) return;
    std::exception_ptr e = std::exchange(error, nullptr);
    std::rethrow_exception(e);
  }
};

SerialWorker::SerialWorker(int queue_depth)
    : state_(std::make_unique<State>(static_cast<size_t>(std::max(1, queue_depth)))) {
  state_->thread = std::thread([s = state_.get()] { s->Run(); });
}

SerialWorker::~SerialWorker() {
  {
    std::lock_guard lock(state_->mutex);
    state_->closing = true;
  }
  state_->changed.notify_all();
  if (state_->thread.joinable()) state_->thread.join();
}

void SerialWorker::Post(std::function<void()> job) {
  std::unique_lock lock(state_->mutex);
  state_->changed.wait(
      lock, [&] { return state_->error != nullptr || state_->queue.size() < state_->queue_depth; });
  state_->RethrowError();
  state_->queue.push_back(std::move(job));
  state_->changed.notify_all();
}

void SerialWorker::Wait() {
  std::unique_lock lock(state_->mutex);
  state_->changed.wait(lock, [&] { return state_->queue.empty() && !state_->busy; });
  state_->RethrowError();
}

OrderedWorkers::OrderedWorkers(int workers, int queue_depth) {
  const int n = std::max(1, workers);
  for (int i = 0; i < n; ++i) work_.push_back(std::make_unique<SerialWorker>(queue_depth));
  // Room for every work thread's running and waiting jobs, so the poster can
  // keep them all busy while `then` waits on the oldest.
  ordered_ = std::make_unique<SerialWorker>(n * (std::max(1, queue_depth) + 1));
}

OrderedWorkers::~OrderedWorkers() {
  // The ordered thread first: its jobs wait on work that the work threads,
  // still running, finish.
  ordered_.reset();
  work_.clear();
}

void OrderedWorkers::Post(std::function<void()> work, std::function<void()> then) {
  auto done = std::make_shared<std::promise<void>>();
  std::shared_future<void> finished = done->get_future().share();
  // The ordered job first: a failed `then` (or work) surfaces here, before
  // more work is queued.
  ordered_->Post([finished, then = std::move(then)] {
    finished.get();  // rethrows the work's exception
    then();
  });
  work_[posted_++ % work_.size()]->Post([done, work = std::move(work)] {
    try {
      work();
      done->set_value();
    } catch (...) {
      done->set_exception(std::current_exception());
    }
  });
}

void OrderedWorkers::Wait() {
  for (auto& w : work_) w->Wait();
  ordered_->Wait();
}

}  // namespace hcpf
