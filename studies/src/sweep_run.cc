// Running a sweep: a worker pool over the runs of one shard, each finished
// run committed to the results store as it completes (docs/sweeps.md).

#include <fcntl.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <ctime>
#include <exception>
#include <filesystem>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <set>

#include "hcpf/core/check.h"
#include "hcpf/core/parallel.h"
#include "hcpf/core/text_file.h"
#include "hcpf/renderer/image_io.h"
#include "hcpf/renderer/renderer.h"
#include "hcpf/scenarios/frames.h"
#include "hcpf/scenarios/models.h"
#include "hcpf/scenarios/output_folder.h"
#include "hcpf/scenarios/overlay.h"
#include "hcpf/scenarios/progress.h"
#include "hcpf/scenarios/run.h"
#include "hcpf/scenarios/version.h"
#include "hcpf/studies/results_store.h"
#include "hcpf/studies/run_queue.h"
#include "hcpf/studies/sweep.h"
#include "sweep_plan.h"

namespace hcpf::studies {

using scenarios::LoadScenarioFile;
using scenarios::ObservationSource;
using scenarios::Progress;
using scenarios::RemoveStaleStagingFolders;
using scenarios::RunOptions;
using scenarios::RunScenario;
using scenarios::Scenario;
using scenarios::ToResolvedYaml;

namespace fs = std::filesystem;

namespace internal {

// The sweep's picture of its scene: the first rendered run's frames, sampled
// from the sweep's own frame cache into DIR/contact_sheet.png for the report
// (which never renders). Nothing is written when no run is rendered or the
// frames are not cached (--no-cache, or another shard rendered them).
void WriteContactSheet(const fs::path& out, const std::vector<SweepRun>& runs,
                       const std::string& cache_dir) {
  if (cache_dir.empty()) return;
  for (const SweepRun& run : runs) {
    const Scenario scenario = run.scenario();
    if (scenario.observation.source != ObservationSource::kRendered) continue;
    const renderer::FrameCache cache(cache_dir, scenarios::PixelHashOf(scenario));
    constexpr int kSheetFrames = 8;
    const int frames = scenario.world.frames;
    std::vector<renderer::RenderedFrame> sheet;
    for (int f = 0; f < frames && static_cast<int>(sheet.size()) < kSheetFrames;
         f += std::max(1, frames / kSheetFrames)) {
      std::optional<renderer::RenderedFrame> frame = cache.Load(f);
      if (!frame) {
        spdlog::info(
            "sweep: no contact_sheet.png (frame {} of the first rendered run is not in the frame "
            "cache: its runs were copied or rendered into another cache)",
            f + 1);
        return;
      }
      sheet.push_back(std::move(*frame));
    }
    // Written beside its name and renamed, as WriteTextFile writes, so a sweep
    // killed while writing it leaves the earlier sheet or none, never a cut
    // one (and a temporary file a later report removes).
    const fs::path temp = TempFileFor(out / "contact_sheet.png");
    std::error_code ec;
    try {
      renderer::WritePng(renderer::MakeContactSheet(sheet), temp.string());
    } catch (const RunError&) {
      fs::remove(temp, ec);
      throw;
    }
    fs::rename(temp, out / "contact_sheet.png", ec);
    if (ec) {
      fs::remove(temp, ec);
      throw RunError(
          fmt::format("cannot write {}: {}", (out / "contact_sheet.png").string(), ec.message()));
    }
    return;
  }
}

FolderLock::FolderLock(const fs::path& out, const std::string& out_argument,
                       const std::string& option) {
  // One sweep process per folder: an advisory lock, released by the kernel
  // when the process ends however it ends (SIGKILL included).
  const std::string lock_path = (out / "sweep.lock").string();
  fd_ = ::open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd_ < 0) throw RunError(fmt::format("cannot open {}: {}", lock_path, std::strerror(errno)));
  if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(fd_);
    fd_ = -1;
    throw InputError(SourceLocation{out_argument, 0, 0, option},
                     "a folder no other hcpf sweep or merge is writing to",
                     "a sweep already running there");
  }
}

bool FolderLockHeld(const fs::path& dir) {
  const std::string lock_path = (dir / "sweep.lock").string();
  const int fd = ::open(lock_path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool held = ::flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK;
  ::close(fd);
  return held;
}

FolderLock::~FolderLock() {
  if (fd_ >= 0) ::close(fd_);
}

FolderLock::FolderLock(FolderLock&& other) noexcept : fd_(other.fd_) { other.fd_ = -1; }

namespace {

// One --reuse folder: its finished runs by key, and a shared lock on its
// sweep.lock while they are copied (a sweep or merge cannot start writing
// there meanwhile).
struct Donor {
  fs::path dir;
  std::map<std::string, RunRecord> finished;
  int lock_fd = -1;
  Donor() = default;
  Donor(const Donor&) = delete;
  Donor& operator=(const Donor&) = delete;
  ~Donor() {
    if (lock_fd >= 0) ::close(lock_fd);
  }
};

// The --reuse folders, each checked and its store read, before anything is
// written; InputError at --reuse for a folder that is no sweep's, --out
// itself, or one a sweep is writing to.
std::vector<std::unique_ptr<Donor>> OpenDonors(const SweepOptions& options) {
  const SourceLocation where{"hcpf sweep", 0, 0, "--reuse"};
  const std::string expected =
      "another sweep folder (holding results.sqlite) whose finished runs may be copied";
  std::vector<std::unique_ptr<Donor>> donors;
  std::error_code ec;
  for (const std::string& dir : options.reuse_dirs) {
    if (!fs::is_directory(dir, ec)) {
      throw InputError(
          where, expected,
          fmt::format("\"{}\": {}", dir, fs::exists(dir, ec) ? "a file" : "no such folder"));
    }
    if (!fs::is_regular_file(fs::path(dir) / "results.sqlite", ec)) {
      throw InputError(where, expected, fmt::format("{}, a folder without results.sqlite", dir));
    }
    if (fs::exists(options.out_dir, ec) && fs::equivalent(dir, options.out_dir, ec)) {
      throw InputError(where, expected,
                       fmt::format("{}, the --out folder itself (its finished runs are reused "
                                   "without --reuse)",
                                   dir));
    }
    auto donor = std::make_unique<Donor>();
    donor->dir = dir;
    // Held until the copies are made; a folder without sweep.lock (read-only
    // media) is only read.
    donor->lock_fd = ::open((fs::path(dir) / "sweep.lock").c_str(), O_RDONLY | O_CLOEXEC);
    if (donor->lock_fd >= 0 && ::flock(donor->lock_fd, LOCK_SH | LOCK_NB) != 0) {
      throw InputError(where, expected,
                       fmt::format("{}, where a sweep or merge is running (its sweep.lock is "
                                   "held): reuse it when that ends",
                                   dir));
    }
    const auto store =
        ResultsStore::Open((fs::path(dir) / "results.sqlite").string(), StoreAccess::kReadOnly);
    // Matched by key alone: its labels are the donor sweep's.
    for (RunRecord& r : store->RunsAsStored()) {
      if (r.ok) donor->finished.emplace(r.key, std::move(r));
    }
    donors.push_back(std::move(donor));
  }
  return donors;
}

// Copies a finished run folder: its manifest.json and the files it lists
// under "files" (what the run wrote: not a report.html written there later),
// or the whole folder when the manifest lists none (runs written before the
// list), through a staging folder renamed into place (CopyWhole).
void CopyRunFolder(const fs::path& from, const fs::path& to) {
  nlohmann::json manifest;
  try {
    manifest = nlohmann::json::parse(ReadInputFile(
        (from / "manifest.json").string(), "a run manifest (JSON)", std::uint64_t{64} << 20));
  } catch (const std::exception&) {
  }
  std::vector<std::string> files;
  if (manifest.is_object() && manifest.contains("files") && manifest["files"].is_object()) {
    files.push_back("manifest.json");
    for (const auto& [name, size] : manifest["files"].items()) files.push_back(name);
  }
  CopyWhole(from, to, files);
}

// Copies into `plan` the runs of `todo` that a --reuse folder holds finished
// with their folders intact (and, under --video, with the video the run
// needs), records them, and returns the runs left to compute.
std::vector<const SweepRun*> CopyFromDonors(const std::vector<std::unique_ptr<Donor>>& donors,
                                            const std::vector<const SweepRun*>& todo,
                                            const SweepOptions& options, SweepPlan& plan) {
  if (donors.empty() || todo.empty()) return todo;
  // Per run: the first folder whose copy of it is whole (checked in
  // parallel). An external tracker's run is computed again: its program is
  // named by path in the run's key, not by content, so a copy could be of
  // another program's tracks.
  std::vector<const Donor*> source(todo.size(), nullptr);
  std::vector<const RunRecord*> record(todo.size(), nullptr);
  std::vector<char> external(todo.size(), 0);
  ParallelFor(todo.size(), options.jobs, [&](size_t i) {
    const SweepRun& run = *todo[i];
    if (run.cell->tracker_choice.external()) {
      external[i] = 1;
      return;
    }
    for (const auto& donor : donors) {
      const Donor& d = *donor;
      const auto it = d.finished.find(run.key);
      if (it == d.finished.end()) continue;
      const fs::path from = d.dir / it->second.run_dir;
      std::error_code ec;
      const bool video_ok =
          !(options.video && run.seed_index == 0) || fs::is_regular_file(from / "overlay.mp4", ec);
      if (video_ok && RunFolderIntact(from.string(), it->second)) {
        source[i] = &d;
        record[i] = &it->second;
        return;
      }
    }
  });
  std::vector<const SweepRun*> left;
  std::set<std::string> used, builds;
  int64_t other_builds = 0;
  const std::string here = scenarios::BuildName();
  for (size_t i = 0; i < todo.size(); ++i) {
    if (source[i] == nullptr) {
      left.push_back(todo[i]);
      continue;
    }
    RunRecord copy = NewRecord(*todo[i]);
    const fs::path to = plan.out / copy.run_dir;
    CopyRunFolder(source[i]->dir / record[i]->run_dir, to);
    ReadRunFolderInto(to.string(), copy);  // every metric of this build's catalogue
    copy.ok = true;
    plan.store->Put(copy);
    ++plan.result.copied;
    used.insert(source[i]->dir.string());
    if (*copy.build != here) {
      ++other_builds;
      builds.insert(copy.build->empty() ? std::string("a build its manifest does not name")
                                        : "hcpf " + *copy.build);
    }
  }
  plan.result.reused += plan.result.copied;
  if (plan.result.copied > 0) {
    spdlog::info(
        "sweep: {} runs copied from {} (each the same resolved scenario as the run it stands "
        "for, so the same files: docs/outputs.md)",
        plan.result.copied, fmt::join(used, ", "));
  }
  const auto externals = std::count(external.begin(), external.end(), 1);
  if (externals > 0) {
    spdlog::info(
        "sweep: {} run(s) of an external tracker are computed, not copied: the program is part "
        "of a run's key by its path, not its content",
        externals);
  }
  if (other_builds > 0) {
    spdlog::warn(
        "sweep: {} of the copied runs were made by {}, this is hcpf {}: their results are those "
        "builds'",
        other_builds, fmt::join(builds, ", "), here);
  }
  return left;
}

// --move-aside: an --out folder holding another sweep's store is renamed
// DIR.before-<UTC time> (the first free name) under its lock, so a sweep
// writing there is refused as without the option. Returns the new name, or
// "" when DIR holds no store or this sweep's.
// `mine`: this sweep's hash and root seed.
std::string MoveOtherSweepAside(const StoreMeta& mine, const std::string& out_dir) {
  fs::path out = fs::path(out_dir).lexically_normal();
  if (!out.has_filename()) out = out.parent_path();  // "DIR/"
  std::error_code ec;
  if (!fs::is_regular_file(out / "results.sqlite", ec)) return "";
  StoreMeta held;
  {
    const auto store =
        ResultsStore::Open((out / "results.sqlite").string(), StoreAccess::kReadOnly);
    held = store->meta();
  }
  if (held.sweep_hash == mine.sweep_hash) return "";
  const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
  std::tm utc{};
  gmtime_r(&now, &utc);
  char stamp[32];
  std::strftime(stamp, sizeof(stamp), "%Y%m%dT%H%M%SZ", &utc);
  fs::path aside;
  for (int k = 1;; ++k) {
    aside = out.string() + ".before-" + stamp + (k > 1 ? fmt::format("-{}", k) : "");
    if (!fs::exists(aside, ec)) break;
  }
  {
    const FolderLock lock(out, out_dir);
    fs::rename(out, aside, ec);
  }
  if (ec) {
    throw RunError(fmt::format("--move-aside: cannot rename {} to {}: {}", out.string(),
                               aside.string(), ec.message()));
  }
  // Another root seed is said as the refusal says it; else what can change
  // a sweep's runs without its file's keys.
  const std::string why =
      OfOtherRootSeeds(held, mine)
          ? fmt::format("root seed {}, this sweep's {}", held.root_seed, mine.root_seed)
          : "its runs keyed by another hcpf, or the sweep file, a scenario or a model it names "
            "edited since";
  spdlog::warn(
      "sweep: {} held the store of another sweep ({}; its hash {}, from {}, this sweep's {}): "
      "moved to {} (--move-aside); its runs that are still this sweep's are copied from there",
      out_dir, why, held.sweep_hash, held.sweep_file, mine.sweep_hash, aside.string());
  return aside.string();
}

}  // namespace

SweepPlan PrepareSweep(const SweepSpec& spec, const std::vector<SweepRun>& runs,
                       const SweepOptions& options, const std::string& workers) {
  options.Validate();
  SweepPlan plan;
  plan.out = fs::path(options.out_dir);
  const fs::path& out = plan.out;
  CheckSweepFolder(options.out_dir, "--out");
  if (options.video) {
    for (const SweepRun& run : runs) scenarios::CheckVideoFits(*run.cell, "--video");
  }
  StoreMeta meta;
  meta.sweep_hash = SweepHash(runs);
  SetRootSeedMeta(spec, meta);
  // Moved aside first: it then gives its runs as a --reuse folder.
  SweepOptions with_aside = options;
  if (options.move_aside) {
    if (std::string aside = MoveOtherSweepAside(meta, options.out_dir); !aside.empty())
      with_aside.reuse_dirs.insert(with_aside.reuse_dirs.begin(), std::move(aside));
  }
  const std::vector<std::unique_ptr<Donor>> donors = OpenDonors(with_aside);
  std::error_code ec;
  fs::create_directories(out / "runs", ec);
  if (ec)
    throw RunError(fmt::format("cannot create {}: {}", (out / "runs").string(), ec.message()));
  plan.lock = std::make_unique<FolderLock>(out, options.out_dir);
  // Staging folders of runs whose process was killed.
  RemoveStaleStagingFolders(out / "runs", "");

  // Relative to the project's folder when the file is inside it, else its
  // absolute path: the same file started from another folder (or a shard
  // started elsewhere) records the same name, so a merge does not take the
  // first shard's spelling and a resume does not rewrite it (a determinism
  // audit: the path was stored as typed).
  meta.sweep_file = scenarios::ProjectRelativePath(spec.file);
  meta.swept_keys = spec.SweptKeys();
  meta.report = spec.report;
  if (spec.base_paths.size() > 1) {
    // grid.base: every base scenario, each headed by the value that names it.
    const SweepAxis* base_axis = nullptr;
    for (const SweepAxis& a : spec.grid) {
      if (a.key == kSweptBaseKey) base_axis = &a;
    }
    HCPF_CHECK(base_axis != nullptr && base_axis->values.size() == spec.base_paths.size());
    for (size_t b = 0; b < spec.base_paths.size(); ++b) {
      meta.base_resolved += internal::BaseResolvedHead(base_axis->values[b]) +
                            ToResolvedYaml(LoadScenarioFile(spec.base_paths[b])) +
                            (b + 1 < spec.base_paths.size() ? "\n" : "");
    }
  } else {
    meta.base_resolved = ToResolvedYaml(LoadScenarioFile(spec.base_path));
  }
  meta.run_count = static_cast<int64_t>(runs.size());
  meta.expansion = ExpansionOf(spec);
  // A run's key is its resolved scenario, so a row of a key says which run
  // it is (the store's reader holds its folder to runs/<key>); its index,
  // seeds and swept values are labels, which must say what the sweep's
  // expansion says of that run. A row whose labels differ (edited by hand:
  // the report drew a cell of a swept value the sweep does not have, and
  // resume kept it, a bad-input audit; or a value written otherwise in the
  // sweep file, 0.10 for 0.1, which is the same run) is rewritten from the
  // expansion, keeping its run; a row of a key the sweep has no run of is
  // refused, before the store is written to (a review: the refusal came
  // after the store had taken this sweep file's name and report: block).
  std::map<std::string, const SweepRun*> planned;
  for (const SweepRun& run : runs) planned.emplace(run.key, &run);
  const std::string store_path = (out / "results.sqlite").string();
  const auto refuse_foreign_rows = [&](const std::vector<RunRecord>& rows) {
    for (const RunRecord& r : rows) {
      if (planned.count(r.key) > 0) continue;
      throw InputError(SourceLocation{store_path, 0, 0, fmt::format("runs[{}]", r.key)},
                       "a row of a run of this sweep (its key a configuration hash of the "
                       "sweep's expansion)",
                       fmt::format("run {}, whose key no run of the sweep has", r.index),
                       "the store was edited; delete the row, or the store to compute every run "
                       "again");
    }
  };
  plan.store = ResultsStore::OpenOrCreate(store_path, meta, [&](const ResultsStore& existing) {
    refuse_foreign_rows(existing.RunsAsStored());
  });

  // Finished runs are reused only while their folders still hold what the
  // store records (a deleted or damaged folder is computed again).
  std::vector<RunRecord> stored = plan.store->RunsAsStored();
  // Read again: the folder lock keeps other sweeps out, not a hand edit
  // between the two reads (refused then after the store took this sweep's
  // descriptive meta, the one write before this point).
  refuse_foreign_rows(stored);
  std::vector<char> relabelled(stored.size(), 0);
  std::string first_relabelled;
  for (size_t i = 0; i < stored.size(); ++i) {
    RunRecord& r = stored[i];
    const auto it = planned.find(r.key);
    RunRecord want = NewRecord(*it->second);
    if (r.index == want.index && r.seed_index == want.seed_index && r.seed == want.seed &&
        r.values == want.values) {
      continue;
    }
    if (first_relabelled.empty()) {
      first_relabelled = fmt::format(
          "run {} ({}): the row said index {}, seed {} (seed index {}), swept values [{}]; the "
          "sweep says index {}, seed {} (seed index {}), swept values [{}]",
          want.index, r.key, r.index, r.seed, r.seed_index, fmt::join(r.values, ", "), want.index,
          want.seed, want.seed_index, fmt::join(want.values, ", "));
    }
    want.ok = r.ok;
    want.error = std::move(r.error);
    want.metrics = std::move(r.metrics);
    want.build = std::move(r.build);
    r = std::move(want);
    relabelled[i] = 1;
  }
  std::vector<char> intact(stored.size(), 0);
  ParallelFor(stored.size(), options.jobs, [&](size_t i) {
    const RunRecord& r = stored[i];
    intact[i] = r.ok && RunFolderIntact((out / r.run_dir).string(), r);
  });
  if (const auto count = std::count(relabelled.begin(), relabelled.end(), 1); count > 0) {
    // Rewritten now when the run is reused; a run computed again rewrites it.
    for (size_t i = 0; i < stored.size(); ++i) {
      if (relabelled[i] && intact[i]) plan.store->Put(stored[i]);
    }
    spdlog::warn(
        "sweep: {} row(s) of {} did not say what the sweep says of their run (edited by hand, "
        "or a swept value written otherwise in the sweep file); rewritten from the sweep, the "
        "runs kept where their folders are whole. First: {}",
        count, store_path, first_relabelled);
  }
  std::map<std::string, bool> finished;  // key -> ok and intact
  // The video is not part of a run's key: a finished run that --video asks a
  // video of (its first seed's) but that was computed without one is computed
  // again to write it (the run's other files come out the same).
  std::set<std::string> lacks_video;
  for (size_t i = 0; i < stored.size(); ++i) {
    finished[stored[i].key] = intact[i] != 0;
    if (intact[i] && options.video && stored[i].seed_index == 0 &&
        !fs::is_regular_file(out / stored[i].run_dir / "overlay.mp4", ec)) {
      lacks_video.insert(stored[i].key);
    }
    if (stored[i].ok && !intact[i]) {
      spdlog::warn(
          "sweep: run {} ({}) is recorded as done but its folder {} is missing or "
          "damaged: computing it again",
          stored[i].index, stored[i].key, (out / stored[i].run_dir).string());
    }
  }

  SweepResult& result = plan.result;
  std::vector<const SweepRun*> todo;
  for (const SweepRun& run : runs) {
    if (run.index % options.shard_count != options.shard_index) continue;
    ++result.total;
    const auto it = finished.find(run.key);
    if (it != finished.end() && it->second && !lacks_video.count(run.key)) {
      ++result.reused;
    } else {
      todo.push_back(&run);
    }
  }
  todo = CopyFromDonors(donors, todo, options, plan);
  const auto without_video = std::count_if(todo.begin(), todo.end(), [&](const SweepRun* run) {
    return lacks_video.count(run->key) > 0;
  });
  if (without_video > 0) {
    spdlog::info(
        "sweep: --video: {} finished run(s) have no overlay.mp4; computing them again to "
        "write it",
        without_video);
  }
  spdlog::info(
      "sweep: {} runs{}, {} already in {}{}, {} to compute with {}", result.total,
      options.shard_count > 1
          ? fmt::format(" in shard {}/{}", options.shard_index, options.shard_count)
          : "",
      result.reused, (out / "results.sqlite").string(),
      result.copied > 0 ? fmt::format(" ({} of them copied)", result.copied) : std::string(),
      todo.size(), workers);
  plan.todo = static_cast<int64_t>(todo.size());
  // The frame cache's folder, made before any run: one that cannot be made
  // failed every rendered run of the sweep, each after making its GL context.
  if (!options.frame_cache_dir.empty() &&
      std::any_of(todo.begin(), todo.end(), [](const SweepRun* run) { return run->rendered(); })) {
    scenarios::MakeFrameCacheFolder(options.frame_cache_dir);
  }
  plan.waves = RunWaves(todo, options.frame_cache_dir);
  return plan;
}

RunExecutors::RunExecutors(const SweepOptions& options) : options_(options) {
  if (!options.ChildExe().empty()) {
    child_ = std::make_unique<ChildProcessExecutor>(options.ChildExe(),
                                                    (fs::path(options.out_dir) / "runs").string());
  }
}

const RunExecutor& RunExecutors::For(const SweepRun& run) const {
  if (child_ && options_.InChildProcess(run)) {
    if (run.rendered()) ++rendered_in_children_;
    return *child_;
  }
  if (child_ && !options_.render_exe.empty() && options_.isolate_exe.empty() && run.rendered() &&
      options_.jobs > 1) {
    ++cached_in_threads_;  // InChildProcess kept it here: FramesAllCached
  }
  return in_process_;
}

RunRecord NewRecord(const SweepRun& run) {
  RunRecord record;
  record.key = run.key;
  record.index = run.index;
  record.seed_index = run.seed_index;
  record.seed = run.seed;
  record.values = run.values;
  record.run_dir = "runs/" + run.key;
  return record;
}

RunRecord ExecuteRun(const SweepRun& run, const SweepOptions& options,
                     const RunExecutor& executor) {
  RunRecord record = NewRecord(run);
  try {
    RunOptions run_options;
    run_options.out_dir = (fs::path(options.out_dir) / record.run_dir).string();
    run_options.threads = options.run_threads;
    run_options.show_progress = false;
    run_options.frame_cache_dir = options.frame_cache_dir;
    run_options.video = options.video && run.seed_index == 0;
    // PrepareSweep removed the staging folders of dead processes in runs/,
    // and the folder lock keeps others out: not listed again per run.
    run_options.remove_stale_siblings = false;
    executor.Execute(run, run_options);
    ReadRunFolderInto(run_options.out_dir, record);
    record.ok = true;
  } catch (const std::exception& e) {
    record.ok = false;
    record.error = e.what();
  }
  return record;
}

}  // namespace internal

SweepResult RunSweep(const SweepSpec& spec, const std::vector<SweepRun>& runs,
                     const SweepOptions& options) {
  internal::SweepPlan plan =
      internal::PrepareSweep(spec, runs, options, fmt::format("{} worker(s)", options.jobs));
  SweepResult& result = plan.result;
  std::mutex mutex;  // guards result and progress
  Progress progress("sweep", plan.todo);
  const internal::RunExecutors executors(options);
  // One run: compute it (a failure is recorded, not thrown), then store it. A
  // failure to store stops the sweep: ParallelFor starts no further run and
  // rethrows it once the runs in flight are done.
  const auto run_one = [&](const SweepRun& run) {
    const RunRecord record = internal::ExecuteRun(run, options, executors.For(run));
    if (!record.ok) spdlog::warn("sweep: run {} ({}) failed: {}", run.index, run.key, record.error);
    plan.store->Put(record);
    std::lock_guard lock(mutex);
    if (record.ok) {
      ++result.computed;
    } else {
      ++result.failed;
    }
    if (options.progress) progress.Advance(1, record.ok ? 0 : 1);
  };
  for (const std::vector<const SweepRun*>& wave : plan.waves) {
    ParallelFor(wave.size(), options.jobs, [&](size_t i) { run_one(*wave[i]); });
  }
  if (options.progress) progress.Finish();
  if (executors.cached_in_threads() > 0) {
    spdlog::info(
        "sweep: {} rendered run(s) in processes of their own, {} in worker threads (every frame "
        "in the frame cache: nothing to render)",
        executors.rendered_in_children(), executors.cached_in_threads());
  }
  internal::WriteContactSheet(plan.out, runs, options.frame_cache_dir);
  return result;
}

}  // namespace hcpf::studies
