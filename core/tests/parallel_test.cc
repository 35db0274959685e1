#include "hcpf/core/parallel.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <future>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "hcpf/core/subprocess.h"
#include "support/process.h"

namespace hcpf {
namespace {

TEST(ParallelFor, EveryItemExactlyOnceForAnyWorkerCount) {
  for (int workers : {0, 1, 2, 3, 8, 100}) {
    std::vector<std::atomic<int>> hits(57);
    ParallelFor(hits.size(), workers, [&](size_t i) { hits[i].fetch_add(1); });
    for (size_t i = 0; i < hits.size(); ++i) EXPECT_EQ(hits[i].load(), 1) << workers << " " << i;
  }
  int calls = 0;
  ParallelFor(0, 4, [&](size_t) { ++calls; });
  EXPECT_EQ(calls, 0);
}

TEST(ParallelFor, AnExceptionIsRethrownAndStopsTheLoop) {
  // One worker: items run in order, so the loop stops right after item 3.
  int started = 0;
  EXPECT_THROW(ParallelFor(1000, 1,
                           [&](size_t i) {
                             ++started;
                             if (i == 3) throw std::runtime_error("item 3");
                           }),
               std::runtime_error);
  EXPECT_EQ(started, 4);
  // Several workers: the exception of the throwing item reaches the caller
  // (how many other items ran before the others saw it depends on timing).
  try {
    ParallelFor(1000, 4, [](size_t i) {
      if (i == 500) throw std::runtime_error("item 500");
    });
    FAIL() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "item 500");
  }
}

TEST(RunProcess, ExitCodesSignalsAndOutputInTheLog) {
  const std::string log = (hcpf::testing::FreshDir("run-process") / "run.log").string();
  ProcessStatus s = RunProcess({"sh", "-c", "echo hello; exit 3"}, log);
  EXPECT_TRUE(s.started);
  EXPECT_EQ(s.exit_code, 3);
  EXPECT_FALSE(s.ok());
  std::FILE* f = std::fopen(log.c_str(), "r");
  ASSERT_NE(f, nullptr);
  char buffer[16] = {};
  ASSERT_NE(std::fgets(buffer, sizeof buffer, f), nullptr);
  std::fclose(f);
  EXPECT_STREQ(buffer, "hello\n");
  s = RunProcess({"sh", "-c", "kill -9 $$"}, log);
  EXPECT_EQ(s.signal, 9);
  s = RunProcess({"/nonexistent/program"}, log);
  EXPECT_EQ(s.exit_code, 127);
  EXPECT_TRUE(RunProcess({"true"}, log).ok());
}

TEST(ProcessIsGone, OnlyForTheDigitsOfAProcessThatEnded) {
  // A child that has ended and been reaped: its pid names no process (until
  // the kernel reuses it, which takes a full cycle of pid_max).
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) ::_exit(0);
  // Ended but not yet collected (a zombie, as MPI ranks that mpirun left
  // wait for init): gone. WNOWAIT waits for the exit and leaves the zombie.
  siginfo_t info{};
  ASSERT_EQ(::waitid(P_PID, static_cast<id_t>(child), &info, WEXITED | WNOWAIT), 0);
  EXPECT_TRUE(ProcessIsGone(std::to_string(child)));
  // Collected: no such process.
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  EXPECT_TRUE(ProcessIsGone(std::to_string(child)));
  // Running processes: this one, and init (another user's for a non-root
  // test run: EPERM, which is not "gone").
  EXPECT_FALSE(ProcessIsGone(std::to_string(::getpid())));
  EXPECT_FALSE(ProcessIsGone("1"));
  // Not a pid: nothing may be removed on its account.
  for (const char* text : {"", "0", "-5", "+5", "12a", "a12", " 12", "99999999999999999999"}) {
    EXPECT_FALSE(ProcessIsGone(text)) << '"' << text << '"';
  }
}

TEST(SerialWorker, RunsJobsInPostOrderOnOneOtherThread) {
  std::vector<int> order;
  std::vector<std::thread::id> threads;
  {
    SerialWorker worker(2);
    for (int i = 0; i < 50; ++i) {
      worker.Post([&, i] {
        order.push_back(i);
        threads.push_back(std::this_thread::get_id());
      });
    }
    worker.Wait();
    ASSERT_EQ(order.size(), 50u);
    for (int i = 0; i < 50; ++i) EXPECT_EQ(order[i], i);
    for (const std::thread::id& t : threads) {
      EXPECT_EQ(t, threads.front());
      EXPECT_NE(t, std::this_thread::get_id());
    }
    worker.Post([&] { order.push_back(50); });
  }  // the destructor waits for the last job
  EXPECT_EQ(order.size(), 51u);
}

TEST(SerialWorker, AFailedJobDropsTheQueuedOnesAndTheNextPostRethrows) {
  SerialWorker worker(1);
  std::promise<void> gate;
  std::shared_future<void> opened = gate.get_future().share();
  int ran = 0;
  worker.Post([opened] {
    opened.wait();
    throw std::runtime_error("job 1 failed");
  });
  worker.Post([&] { ++ran; });  // queued behind job 1: the queue is full
  gate.set_value();
  // Room in the queue comes only when job 1 ends, and job 1 ends by
  // throwing: this Post sees the failure instead of queuing.
  EXPECT_THROW(worker.Post([&] { ++ran; }), std::runtime_error);
  worker.Wait();  // rethrown once only
  EXPECT_EQ(ran, 0);
  // The worker goes on after a failure.
  worker.Post([&] { ++ran; });
  worker.Wait();
  EXPECT_EQ(ran, 1);
  worker.Post([] { throw std::logic_error("job 4 failed"); });
  EXPECT_THROW(worker.Wait(), std::logic_error);
}

// Works overlap on several threads, each job's on thread i % workers, and
// the thens run one at a time, in post order, each after its own work.
TEST(OrderedWorkers, ThensRunInPostOrderAfterTheirWorksWhichOverlap) {
  constexpr int kJobs = 40;
  std::vector<int> order;
  std::vector<int> work_done(kJobs, 0);
  std::vector<std::thread::id> work_thread(kJobs);
  std::atomic<int> running{0};
  std::atomic<int> most{0};
  std::thread::id then_thread;
  {
    OrderedWorkers workers(3);
    EXPECT_EQ(workers.workers(), 3);
    for (int i = 0; i < kJobs; ++i) {
      workers.Post(
          [&, i] {
            const int now = ++running;
            most = std::max(most.load(), now);
            // Later jobs finish their work sooner: order comes from Post.
            std::this_thread::sleep_for(std::chrono::microseconds(200 * (kJobs - i) % 3000));
            work_done[i] = 1;
            work_thread[i] = std::this_thread::get_id();
            --running;
          },
          [&, i] {
            EXPECT_EQ(work_done[i], 1) << "then before its work, job " << i;
            if (order.empty()) then_thread = std::this_thread::get_id();
            EXPECT_EQ(std::this_thread::get_id(), then_thread);
            order.push_back(i);
          });
    }
    workers.Wait();
  }
  ASSERT_EQ(order.size(), static_cast<size_t>(kJobs));
  for (int i = 0; i < kJobs; ++i) EXPECT_EQ(order[i], i);
  EXPECT_GT(most.load(), 1) << "the works never overlapped";
  for (int i = 3; i < kJobs; ++i) EXPECT_EQ(work_thread[i], work_thread[i % 3]) << i;
  EXPECT_NE(work_thread[0], work_thread[1]);
  EXPECT_NE(then_thread, std::this_thread::get_id());
}

// A work that throws skips its then; Wait rethrows it once, and the jobs
// queued behind it do not run their thens. (Job 2's work waits for the gate
// until all six are posted: two work threads hold jobs 0-5, the ordered
// queue 3-5, so no Post blocks.)
TEST(OrderedWorkers, AFailedWorkSkipsItsThenAndReachesWait) {
  OrderedWorkers workers(2);
  std::promise<void> gate;
  std::shared_future<void> opened = gate.get_future().share();
  std::vector<int> thens;
  for (int i = 0; i < 6; ++i) {
    workers.Post(
        [i, opened] {
          if (i != 2) return;
          opened.wait();
          throw std::runtime_error("work 2 failed");
        },
        [&, i] { thens.push_back(i); });
  }
  gate.set_value();
  try {
    workers.Wait();
    ADD_FAILURE() << "Wait did not rethrow";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "work 2 failed");
  }
  EXPECT_EQ(thens, (std::vector<int>{0, 1}));
  EXPECT_NO_THROW(workers.Wait());  // once
  // The workers go on after a failure.
  workers.Post([] {}, [&] { thens.push_back(6); });
  workers.Wait();
  EXPECT_EQ(thens, (std::vector<int>{0, 1, 6}));
}

}  // namespace
}  // namespace hcpf
