// The MPI executor of a sweep (mpi_sweep.h, docs/sweeps.md). Compiled with
// MPI when CMake found it (HCPF_HAVE_MPI); without, only the launcher check.
//
// Protocol (MPI_COMM_WORLD, rank 0 the coordinator):
//   1. Rank 0 broadcasts its sweep hash; every rank compares its own
//      expansion's; all agree (Allreduce) or all throw.
//   2. Rank 0 prepares the sweep (lock, store, reuse, waves) and broadcasts
//      whether it could; if not, every rank stops cleanly and rank 0 throws.
//   3. A worker sends kTagReady (empty the first time, then the record of the
//      run it finished, as JSON); rank 0 stores the record and answers
//      kTagRun with the next run index, or kTagStop when no run is left. A
//      worker that asks while the current wave's last runs are still in
//      flight waits until they are back: the next wave reads their frames.
// The run index suffices one way because every rank expanded the same run
// list; the record carries only what the worker computed (ok, error,
// metrics) and rank 0 fills in the rest from its own run list.

#include "hcpf/studies/mpi_sweep.h"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <charconv>
#include <cstring>
#include <string>

#include "hcpf/core/error.h"

#ifdef HCPF_HAVE_MPI
#include <dlfcn.h>
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <deque>
#include <exception>
#include <limits>
#include <nlohmann/json.hpp>
#include <thread>

#include "hcpf/core/check.h"
#include "hcpf/scenarios/progress.h"
#include "hcpf/studies/results_store.h"
#include "sweep_plan.h"
#endif

namespace hcpf::studies {

namespace {

// A positive int in `text`, or 0.
int PositiveInt(const char* text) {
  if (text == nullptr) return 0;
  const char* end = text + std::strlen(text);
  int n = 0;
  const auto [ptr, ec] = std::from_chars(text, end, n);
  return ec == std::errc() && ptr == end && n > 0 ? n : 0;
}

}  // namespace

int LaunchedRankCount(const std::function<const char*(const char*)>& getenv) {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    if (const int n = PositiveInt(getenv(name)); n > 0) return n;
  }
  if (getenv("PMIX_RANK") != nullptr) {
    if (const int n = PositiveInt(getenv("SLURM_STEP_NUM_TASKS")); n > 0) return n;
  }
  return 1;
}

bool IsFirstLaunchedRank(const std::function<const char*(const char*)>& getenv) {
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMI_RANK", "PMIX_RANK"}) {
    if (const char* rank = getenv(name)) return PositiveInt(rank) == 0;
  }
  return true;
}

#ifndef HCPF_HAVE_MPI

bool MpiExecutorBuilt() { return false; }

std::optional<SweepResult> RunSweepMpi(const SweepSpec& spec, const std::vector<SweepRun>& runs,
                                       const SweepOptions& options) {
  const int ranks = LaunchedRankCount();
  if (ranks > 1) {
    throw RunError(fmt::format(
        "hcpf sweep was started as {} processes by an MPI launcher (mpirun, srun), but this hcpf "
        "was built without MPI, so each would run the whole sweep into the same folder. Install "
        "libopenmpi-dev and openmpi-bin (scripts/setup.sh) and rebuild, or start one process "
        "(--jobs N uses the cores of one machine; --shard i/n splits a sweep into jobs)",
        ranks));
  }
  return RunSweep(spec, runs, options);
}

#else  // HCPF_HAVE_MPI

bool MpiExecutorBuilt() { return true; }

namespace {

using nlohmann::json;

constexpr int kCoordinator = 0;
constexpr int kTagReady = 1;  // worker -> 0: "" or a finished run's record (JSON)
constexpr int kTagRun = 2;    // 0 -> worker: the index of the run to compute (int64)
constexpr int kTagStop = 3;   // 0 -> worker: no run left (empty)

// Open MPI's blocking receive polls in a loop that keeps a core busy; rank 0
// waits for most of a sweep, and a worker waits between waves, on cores the
// other ranks' runs need (the 2-core CI machine runs 3 ranks). So waits probe
// and sleep, backing off to at most kMaxPollSleep: a run takes 10 ms to
// minutes, and 2 ms of extra latency per run is lost in that.
constexpr auto kMaxPollSleep = std::chrono::microseconds(2000);

MPI_Status WaitForMessage(int source, int tag) {
  auto sleep = std::chrono::microseconds(20);
  for (;;) {
    int flag = 0;
    MPI_Status status;
    MPI_Iprobe(source, tag, MPI_COMM_WORLD, &flag, &status);
    if (flag != 0) return status;
    std::this_thread::sleep_for(sleep);
    sleep = std::min(sleep * 2, kMaxPollSleep);
  }
}

// Receives the probed message as bytes.
std::string ReceiveText(const MPI_Status& probed) {
  int count = 0;
  MPI_Get_count(&probed, MPI_CHAR, &count);
  std::string text(static_cast<size_t>(count), '\0');
  MPI_Recv(text.data(), count, MPI_CHAR, probed.MPI_SOURCE, probed.MPI_TAG, MPI_COMM_WORLD,
           MPI_STATUS_IGNORE);
  return text;
}

void SendText(const std::string& text, int destination, int tag) {
  HCPF_CHECK(text.size() <= static_cast<size_t>(std::numeric_limits<int>::max()));
  MPI_Send(text.data(), static_cast<int>(text.size()), MPI_CHAR, destination, tag, MPI_COMM_WORLD);
}

// What a worker sends back: the run's index and key (checked by rank 0),
// ok, error, metrics and build. JSON numbers are written with 17 significant digits
// and read back to the same double; non-finite values, which JSON lacks, are
// written as the strings "nan", "inf" and "-inf".
std::string RecordToJson(const RunRecord& record) {
  json metrics = json::object();
  for (const auto& [name, value] : record.metrics) {
    if (std::isnan(value)) {
      metrics[name] = "nan";
    } else if (std::isinf(value)) {
      metrics[name] = value > 0 ? "inf" : "-inf";
    } else {
      metrics[name] = value;
    }
  }
  const json j = {
      {"index", record.index}, {"key", record.key},
      {"ok", record.ok},       {"error", record.error},
      {"metrics", metrics},    {"build", record.build ? json(*record.build) : json(nullptr)}};
  // An error message may quote bytes that are not UTF-8 (a file's content).
  return j.dump(-1, ' ', false, json::error_handler_t::replace);
}

// Fills ok, error, metrics and build of `record` (made by NewRecord for the run the
// worker was given) from a worker's message. Throws RunError when the message
// is not the record of that run.
void ReadRecordJson(const std::string& text, int worker, RunRecord& record) {
  try {
    const json j = json::parse(text);
    if (j.at("index").get<int64_t>() != record.index ||
        j.at("key").get<std::string>() != record.key)
      throw RunError("the record is of another run");
    record.ok = j.at("ok").get<bool>();
    record.error = j.at("error").get<std::string>();
    if (!j.at("build").is_null()) record.build = j.at("build").get<std::string>();
    for (const auto& [name, value] : j.at("metrics").items()) {
      if (value.is_string()) {
        const std::string s = value.get<std::string>();
        double v = std::numeric_limits<double>::quiet_NaN();
        if (s == "inf") v = std::numeric_limits<double>::infinity();
        if (s == "-inf") v = -std::numeric_limits<double>::infinity();
        record.metrics[name] = v;
      } else {
        record.metrics[name] = value.get<double>();
      }
    }
  } catch (const std::exception& e) {
    throw RunError(fmt::format("sweep: rank {} sent a malformed record for run {} ({}): {}", worker,
                               record.index, record.key, e.what()));
  }
}

// Rank 0 from PrepareSweep on: hands out the waves' runs, stores what comes
// back, stops every worker at the end.
SweepResult Coordinate(internal::SweepPlan& plan, const std::vector<SweepRun>& runs,
                       const SweepOptions& options, int ranks) {
  SweepResult& result = plan.result;
  scenarios::Progress progress("sweep", plan.todo);
  std::vector<int64_t> assigned(static_cast<size_t>(ranks), -1);  // per rank, -1 = none
  std::deque<int> idle;                                           // ranks waiting for the next wave
  size_t wave = 0;                                                // the wave being handed out
  size_t next = 0;                                                // its next run
  int in_flight = 0;
  int running = ranks - 1;  // workers not yet stopped
  while (running > 0) {
    const MPI_Status probed = WaitForMessage(MPI_ANY_SOURCE, kTagReady);
    const int worker = probed.MPI_SOURCE;
    const std::string text = ReceiveText(probed);
    const int64_t index = assigned[static_cast<size_t>(worker)];
    if (index >= 0) {
      RunRecord record = internal::NewRecord(runs[static_cast<size_t>(index)]);
      ReadRecordJson(text, worker, record);
      if (!record.ok) {
        spdlog::warn("sweep: run {} ({}) failed on rank {}: {}", record.index, record.key, worker,
                     record.error);
      }
      plan.store->Put(record);
      ++(record.ok ? result.computed : result.failed);
      if (options.progress) progress.Advance(1, record.ok ? 0 : 1);
      assigned[static_cast<size_t>(worker)] = -1;
      --in_flight;
    } else if (!text.empty()) {
      throw RunError(fmt::format("sweep: rank {} sent a record for no run it was given", worker));
    }
    idle.push_back(worker);
    // A wave ends when all its runs are back; empty waves are skipped.
    while (wave < plan.waves.size() && next == plan.waves[wave].size() && in_flight == 0) {
      ++wave;
      next = 0;
    }
    while (!idle.empty() && wave < plan.waves.size() && next < plan.waves[wave].size()) {
      const int w = idle.front();
      idle.pop_front();
      const int64_t run_index = plan.waves[wave][next++]->index;
      assigned[static_cast<size_t>(w)] = run_index;
      ++in_flight;
      MPI_Send(&run_index, 1, MPI_INT64_T, w, kTagRun, MPI_COMM_WORLD);
    }
    if (wave == plan.waves.size()) {
      for (const int w : idle) SendText("", w, kTagStop);
      running -= static_cast<int>(idle.size());
      idle.clear();
    }
  }
  if (options.progress) progress.Finish();
  return result;
}

// Ranks 1..R-1: ask, compute, send the record back, until told to stop.
void Work(const std::vector<SweepRun>& runs, const SweepOptions& options) {
  const internal::RunExecutors executors(options);
  std::string record;  // the previous run's, "" before the first
  for (;;) {
    SendText(record, kCoordinator, kTagReady);
    const MPI_Status probed = WaitForMessage(kCoordinator, MPI_ANY_TAG);
    if (probed.MPI_TAG == kTagStop) {
      ReceiveText(probed);
      return;
    }
    HCPF_CHECK(probed.MPI_TAG == kTagRun) << "tag " << probed.MPI_TAG;
    int64_t index = -1;
    MPI_Recv(&index, 1, MPI_INT64_T, kCoordinator, kTagRun, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    HCPF_CHECK(index >= 0 && static_cast<size_t>(index) < runs.size()) << "run " << index;
    const SweepRun& run = runs[static_cast<size_t>(index)];
    HCPF_CHECK(run.index == index);
    record = RecordToJson(internal::ExecuteRun(run, options, executors.For(run)));
  }
}

// libhcpf_cli.so, which holds this code and links libmpi, is loaded with
// RTLD_LOCAL (cli/src/main.cc), so libmpi's symbols are not global; Open
// MPI's plugins (mca_*.so, loaded by MPI_Init) do not link libmpi and
// libopen-pal themselves and expect their symbols to be. Promote libmpi and
// its dependencies to the global scope before MPI_Init (what mpi4py does).
void MakeMpiSymbolsGlobal() {
  Dl_info info{};
  // NOLINTNEXTLINE(cppcoreguidelines-pro-type-reinterpret-cast)
  if (::dladdr(reinterpret_cast<void*>(&MPI_Init), &info) == 0 || info.dli_fname == nullptr) return;
  // The handle is left open on purpose: libmpi stays loaded until exit.
  if (::dlopen(info.dli_fname, RTLD_NOW | RTLD_GLOBAL | RTLD_NOLOAD) == nullptr) {
    spdlog::debug("sweep: cannot make {} global: {}", info.dli_fname, ::dlerror());
  }
}

}  // namespace

std::optional<SweepResult> RunSweepMpi(const SweepSpec& spec, const std::vector<SweepRun>& runs,
                                       const SweepOptions& options) {
  if (LaunchedRankCount() <= 1) return RunSweep(spec, runs, options);
  options.Validate();
  MakeMpiSymbolsGlobal();
  int provided = 0;
  // Only the main thread calls MPI; runs and the reuse check use threads.
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_ARE_FATAL);
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  if (ranks == 1) {
    // Each process alone in its MPI world: the launcher is another MPI's
    // (MPICH's mpiexec for an Open MPI build), and every process would run
    // the whole sweep.
    char library[MPI_MAX_LIBRARY_VERSION_STRING] = {};
    int length = 0;
    MPI_Get_library_version(library, &length);
    std::string name(library, static_cast<size_t>(std::max(0, length)));
    name = name.substr(0, name.find_first_of(",\n"));
    MPI_Finalize();
    throw RunError(fmt::format(
        "hcpf sweep was started as {} processes by an MPI launcher, but each is alone in its MPI "
        "world: launch it with the mpirun of the MPI this hcpf was built with ({})",
        LaunchedRankCount(), name));
  }
  for (size_t i = 0; i < runs.size(); ++i) HCPF_CHECK(runs[i].index == static_cast<int64_t>(i));

  // 1. Every rank expanded the same sweep.
  const std::string own_hash = SweepHash(runs);
  std::string hash = own_hash;
  int hash_size = static_cast<int>(hash.size());
  MPI_Bcast(&hash_size, 1, MPI_INT, kCoordinator, MPI_COMM_WORLD);
  hash.resize(static_cast<size_t>(hash_size));
  MPI_Bcast(hash.data(), hash_size, MPI_CHAR, kCoordinator, MPI_COMM_WORLD);
  const int differs = hash == own_hash ? 0 : 1;
  if (differs != 0) {
    spdlog::error("sweep: rank {} expanded {} runs with sweep hash {}, rank 0 hash {}", rank,
                  runs.size(), own_hash, hash);
  }
  int differing = 0;
  MPI_Allreduce(&differs, &differing, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
  if (differing > 0) {
    MPI_Finalize();
    throw RunError(fmt::format(
        "{} of {} MPI ranks expanded {} to another run list than rank 0 (a different sweep hash): "
        "every rank must read the same sweep file and base scenarios",
        differing, ranks, spec.file));
  }

  // 2. Rank 0 prepares the sweep.
  std::optional<internal::SweepPlan> plan;
  std::exception_ptr setup_error;
  if (rank == kCoordinator) {
    try {
      plan = internal::PrepareSweep(
          spec, runs, options,
          fmt::format("{} MPI worker rank(s) (rank 0 coordinates)", ranks - 1));
    } catch (...) {
      setup_error = std::current_exception();
    }
  }
  int prepared = setup_error ? 0 : 1;
  MPI_Bcast(&prepared, 1, MPI_INT, kCoordinator, MPI_COMM_WORLD);
  if (prepared == 0) {
    MPI_Finalize();
    if (setup_error) std::rethrow_exception(setup_error);
    return std::nullopt;  // rank 0 reports why
  }

  // 3. The runs. From here an error on one rank ends the job: the others may
  // be waiting for a message from it.
  std::optional<SweepResult> result;
  try {
    if (rank == kCoordinator) {
      result = Coordinate(*plan, runs, options, ranks);
    } else {
      Work(runs, options);
    }
  } catch (const std::exception& e) {
    spdlog::error("sweep: MPI rank {}: {}; ending the job (rerunning resumes)", rank, e.what());
    MPI_Abort(MPI_COMM_WORLD, dynamic_cast<const InputError*>(&e) != nullptr ? 2 : 1);
  }
  MPI_Finalize();
  if (rank == kCoordinator) internal::WriteContactSheet(plan->out, runs, options.frame_cache_dir);
  return result;
}

#endif  // HCPF_HAVE_MPI

}  // namespace hcpf::studies
