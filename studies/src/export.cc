// `hcpf export DIR --trackeval OUT`: a sweep's runs in TrackEval's layout.

#include "hcpf/studies/export.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <vector>

#include "hcpf/core/error.h"
#include "hcpf/core/rng.h"
#include "hcpf/core/text_file.h"
#include "hcpf/metrics/mot_io.h"
#include "hcpf/scenarios/output_folder.h"
#include "hcpf/studies/results_store.h"
#include "text.h"

namespace hcpf::studies {

namespace fs = std::filesystem;

namespace {

// A run's MOT files are read whole; this bounds what one may hold (a
// 100,000-frame sequence with 100 boxes a frame is about 0.4 GB of text).
constexpr uint64_t kMaxMotFileBytes = uint64_t{1} << 30;

bool NameChar(char c) {
  return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_';
}

void CheckName(const std::string& value, const std::string& option) {
  if (value.empty() || value.size() > 100 || !std::all_of(value.begin(), value.end(), NameChar)) {
    throw InputError(SourceLocation{"hcpf export", 0, 0, option},
                     "a name of 1 to 100 letters, digits and _", value.empty() ? "nothing" : value);
  }
}

// Keeps [A-Za-z0-9._-]; any other run of characters becomes one '_', and '_'
// at either end is dropped ("[320, 240]" -> "320_240"). Leading dots are
// dropped too (no hidden or "." / ".." folder names).
std::string Sanitise(const std::string& text) {
  std::string out;
  for (char c : text) {
    const bool keep = NameChar(c) || c == '.' || c == '-';
    if (keep) {
      out += c;
    } else if (out.empty() || out.back() != '_') {
      out += '_';
    }
  }
  const size_t first = out.find_first_not_of("._");
  const size_t last = out.find_last_not_of('_');
  out = first == std::string::npos ? std::string() : out.substr(first, last - first + 1);
  return out.empty() ? "_" : out;
}

// The label of one group of runs: "<key>-<value>" parts joined by '_'.
std::string Label(const std::vector<std::string>& keys, const std::vector<std::string>& values,
                  const std::string& strip_prefix) {
  std::string out;
  for (size_t i = 0; i < keys.size(); ++i) {
    std::string key = keys[i];
    if (key.rfind(strip_prefix, 0) == 0) key = key.substr(strip_prefix.size());
    // A base scenario is named by its file's stem, not its path.
    const std::string value = keys[i] == "base" ? fs::path(values[i]).stem().string() : values[i];
    if (!out.empty()) out += '_';
    out += Sanitise(key) + "-" + Sanitise(value);
  }
  return out;
}

// A folder or file name may hold 255 bytes (NAME_MAX); a label longer than
// kMaxLabelBytes keeps its first bytes and ends in a hash of the whole, so
// two long labels that share their start still differ (a second bad-input
// audit: long swept values failed the export with "File name too long").
// What each name stands for is in runs.csv.
constexpr size_t kMaxLabelBytes = 200;

std::string Bounded(const std::string& label) {
  if (label.size() <= kMaxLabelBytes) return label;
  const std::string tail = fmt::format("-{:016x}", HashName(label));
  return label.substr(0, kMaxLabelBytes - tail.size()) + tail;
}

// Names for distinct groups, in the order first seen: `label`, and `label-2`,
// `label-3`, ... when sanitising made two groups' labels equal.
class Namer {
 public:
  std::string NameOf(const std::vector<std::string>& group, const std::string& label) {
    auto it = names_.find(group);
    if (it != names_.end()) return it->second;
    const std::string bounded = Bounded(label);
    std::string name = bounded;
    for (int k = 2; used_.count(name) > 0; ++k) name = fmt::format("{}-{}", bounded, k);
    used_.insert(name);
    names_[group] = name;
    return name;
  }

 private:
  std::map<std::vector<std::string>, std::string> names_;
  std::set<std::string> used_;
};

struct ExportRun {
  const RunRecord* record = nullptr;
  std::string sequence;
  std::string tracker;
  fs::path dir;
};

void CheckOutFolder(const fs::path& out) {
  scenarios::CheckFolderArgument(out.string(), "--trackeval");
  std::error_code ec;
  const fs::file_status status = fs::symlink_status(out, ec);
  if (!fs::exists(status)) return;
  if (!fs::is_directory(status)) {
    throw InputError(SourceLocation{out.string(), 0, 0, "--trackeval"},
                     "a new or empty folder for the export", "a file");
  }
  if (!fs::is_empty(out, ec) || ec) {
    throw InputError(SourceLocation{out.string(), 0, 0, "--trackeval"},
                     "a new or empty folder for the export", "a folder that is not empty",
                     "choose another folder or delete this one");
  }
}

// The files of a run that the export copies: all a run folder written
// before manifests listed their files is asked for.
constexpr std::array<const char*, 3> kExportedFiles = {"gt/gt.txt", "tracks.txt", "seqinfo.ini"};

void MakeDirs(const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw RunError(fmt::format("cannot create {}: {}", dir.string(), ec.message()));
}

}  // namespace

void TrackEvalExportOptions::Validate() const {
  if (dir.empty())
    throw InputError(SourceLocation{"hcpf export", 0, 0, "DIR"}, "a sweep folder", "nothing");
  if (out.empty()) {
    throw InputError(SourceLocation{"hcpf export", 0, 0, "--trackeval"}, "an output folder",
                     "nothing");
  }
  CheckName(benchmark, "--benchmark");
  CheckName(split, "--split");
}

TrackEvalExportResult ExportTrackEval(const TrackEvalExportOptions& options) {
  options.Validate();
  const fs::path dir(options.dir);
  // "OUT/" names OUT: the staging folder goes beside it, not inside.
  fs::path out = fs::path(options.out).lexically_normal();
  if (!out.has_filename()) out = out.parent_path();
  CheckOutFolder(out);
  auto store = ResultsStore::Open((dir / "results.sqlite").string(), StoreAccess::kReadOnly);
  if (const std::string unchecked = UncheckedLabelsSentence(*store); !unchecked.empty()) {
    spdlog::warn("export: {}", unchecked);
  }
  const StoreMeta& meta = store->meta();
  const std::vector<RunRecord> records = store->Runs();

  // Which swept keys describe the tracker; the others (and the seed) the
  // sequence. The scenario `name` swept beside tracker keys labels the
  // trackers (the shipped external-sort sweep zips it with them): a third
  // bad-input audit found such a sweep split into one sequence per tracker,
  // so that it could never be exported. The name changes no pixel and no
  // ground-truth box.
  const bool tracker_swept =
      std::any_of(meta.swept_keys.begin(), meta.swept_keys.end(),
                  [](const std::string& key) { return key.rfind("tracker.", 0) == 0; });
  std::vector<size_t> tracker_keys, sequence_keys;
  for (size_t k = 0; k < meta.swept_keys.size(); ++k) {
    const std::string& key = meta.swept_keys[k];
    const bool describes_tracker =
        key.rfind("tracker.", 0) == 0 || (key == "name" && tracker_swept);
    (describes_tracker ? tracker_keys : sequence_keys).push_back(k);
  }

  TrackEvalExportResult result;
  result.bench = options.benchmark + "-" + options.split;
  if (const std::string missing = MissingRunsSentence(meta, records.size()); !missing.empty()) {
    spdlog::warn("export: {}", missing);
    result.missing = meta.run_count - static_cast<int64_t>(records.size());
  }
  Namer sequence_names, tracker_names;
  std::vector<ExportRun> runs;
  // Every tracker of the sweep, from every run, failed ones too: a tracker
  // whose runs all failed is one that every sequence lacks (a third bad-input
  // audit found it silently absent from a complete-looking export).
  std::set<std::string> trackers;
  std::vector<std::string> damaged;  // ok in the store, not whole on disk
  for (const RunRecord& r : records) {
    std::vector<std::string> seq_group, seq_keys, tracker_group, trk_keys;
    for (size_t k : sequence_keys) {
      seq_group.push_back(r.values[k]);
      seq_keys.push_back(meta.swept_keys[k]);
    }
    for (size_t k : tracker_keys) {
      tracker_group.push_back(r.values[k]);
      trk_keys.push_back(meta.swept_keys[k]);
    }
    const std::string tracker_label =
        trk_keys.empty() ? std::string("hcpf") : Label(trk_keys, tracker_group, "tracker.");
    const std::string tracker = tracker_names.NameOf(tracker_group, tracker_label);
    trackers.insert(tracker);
    const fs::path run_dir = dir / r.run_dir;
    // Whole as resume, --reuse and merge ask (RunFolderIntact: every file
    // of the manifest's list at the size written, the metrics the store
    // holds): a bad-input audit found an emptied tracks.txt exported as a
    // tracker that found nothing, exit 0. A run written before manifests
    // listed their files (2026-11-23) is asked only for the three files the
    // export copies (a review: its older runs lack camera_motion.csv, which
    // RunFolderIntact asks of them by default, and were all left out).
    if (!r.ok || !RunFolderIntact(run_dir.string(), r, kExportedFiles)) {
      ++result.not_ok;
      if (r.ok) damaged.push_back(r.run_dir);
      continue;
    }
    seq_group.push_back(std::to_string(r.seed_index));
    std::string seq_label = Label(seq_keys, seq_group, "");
    seq_label += fmt::format("{}seed{}", seq_label.empty() ? "" : "_", r.seed_index);
    runs.push_back({&r, sequence_names.NameOf(seq_group, seq_label), tracker, run_dir});
  }
  if (result.not_ok > 0) {
    spdlog::warn(
        "export: {} run(s) left out: failed, or their run folder lacks a file it wrote or "
        "holds one of another size (damaged){}",
        result.not_ok,
        damaged.empty()
            ? std::string()
            : fmt::format(
                  "; damaged: {}{}",
                  fmt::join(damaged.begin(),
                            damaged.begin() + std::min<ptrdiff_t>(std::ssize(damaged), 5), ", "),
                  damaged.size() > 5 ? fmt::format(" and {} more", damaged.size() - 5)
                                     : std::string()));
  }

  // Keep the sequences with a run of every tracker.
  std::map<std::string, std::map<std::string, const ExportRun*>> by_sequence;
  std::set<std::string> trackers_with_runs;
  for (const ExportRun& run : runs) {
    trackers_with_runs.insert(run.tracker);
    auto [it, inserted] = by_sequence[run.sequence].emplace(run.tracker, &run);
    if (!inserted) {
      throw RunError(fmt::format("export: runs {} and {} both map to sequence {}, tracker {}",
                                 it->second->record->key, run.record->key, run.sequence,
                                 run.tracker));
    }
  }
  std::vector<std::string> sequences;
  for (const auto& [sequence, by_tracker] : by_sequence) {
    if (by_tracker.size() == trackers.size()) {
      sequences.push_back(sequence);
    } else {
      result.skipped += static_cast<int>(by_tracker.size());
      spdlog::warn(
          "export: sequence {} left out: only {} of the {} trackers have an ok run on it (the "
          "others failed, lost a file, or the sweep did not run them on it)",
          sequence, by_tracker.size(), trackers.size());
    }
  }
  if (sequences.empty()) {
    std::string without;
    for (const std::string& t : trackers) {
      if (trackers_with_runs.count(t) == 0) without += (without.empty() ? "" : ", ") + t;
    }
    throw InputError(
        SourceLocation{(dir / "results.sqlite").string(), 0, 0, "runs"},
        "a sequence with an ok run of every tracker",
        runs.empty() ? std::string("no ok run with its files")
        : without.empty()
            // Every tracker ran, each on other sequences (an
            // audit: a tracker key zipped with a scene key read
            // as if runs had failed).
            ? std::string("none: every tracker has ok runs, but on other sequences (a "
                          "tracker key zipped with a scene key runs each tracker on its own "
                          "sequences; TrackEval's layout needs every tracker on every "
                          "sequence: sweep the tracker keys in grid:)")
            : fmt::format("none: no ok run of the tracker(s) {}", without));
  }

  // Write everything into a staging folder, then rename it into place.
  const fs::path staging = out.string() + fmt::format(".partial-{}", ::getpid());
  std::error_code ec;
  // And remove what exports into OUT that were killed left.
  scenarios::RemoveStaleStagingFolders(out.parent_path(), out.filename().string());
  fs::remove_all(staging, ec);
  try {
    const fs::path gt_root = staging / "gt" / "mot_challenge";
    const fs::path trackers_root = staging / "trackers" / "mot_challenge" / result.bench;
    std::string seqmap = "name\n";
    std::string csv = "sequence,tracker,run_key,run_index,seed_index,seed,run_dir";
    // Appended piecewise: GCC 12's -Wrestrict misfires on "," + string&&
    // (a known false positive) and command (1)'s release build shows it.
    for (const std::string& key : meta.swept_keys) {
      csv += ',';
      // A swept `seed` has the store's column name: the run's seed is `seed`.
      csv += Csv(key == "seed" ? "swept.seed" : key);
    }
    csv += "\n";
    for (const std::string& sequence : sequences) {
      seqmap += sequence + "\n";
      const auto& by_tracker = by_sequence.at(sequence);
      // One ground truth: every run of the sequence must have written the same.
      const ExportRun& first = *by_tracker.begin()->second;
      const std::string gt = ReadInputFile((first.dir / "gt" / "gt.txt").string(),
                                           "a MOT ground-truth file", kMaxMotFileBytes);
      metrics::SeqInfo info = metrics::ReadSeqInfo((first.dir / "seqinfo.ini").string());
      const metrics::SeqInfo first_info = info;
      for (const auto& [tracker, run] : by_tracker) {
        const metrics::SeqInfo other = metrics::ReadSeqInfo((run->dir / "seqinfo.ini").string());
        if (ReadInputFile((run->dir / "gt" / "gt.txt").string(), "a MOT ground-truth file",
                          kMaxMotFileBytes) != gt ||
            other.seq_length != first_info.seq_length || other.im_width != first_info.im_width ||
            other.im_height != first_info.im_height) {
          throw RunError(fmt::format(
              "export: runs {} and {} share sequence {} (the same non-tracker values and seed) "
              "but not their ground truth",
              first.record->key, run->record->key, sequence));
        }
      }
      const fs::path seq_dir = gt_root / result.bench / sequence;
      MakeDirs(seq_dir / "gt");
      WriteTextFile((seq_dir / "gt" / "gt.txt").string(), gt);
      info.name = sequence;
      metrics::WriteSeqInfo((seq_dir / "seqinfo.ini").string(), info);
      for (const auto& [tracker, run] : by_tracker) {
        const fs::path data = trackers_root / tracker / "data";
        MakeDirs(data);
        WriteTextFile((data / (sequence + ".txt")).string(),
                      ReadInputFile((run->dir / "tracks.txt").string(), "a MOT tracker file",
                                    kMaxMotFileBytes));
        const RunRecord& r = *run->record;
        csv += fmt::format("{},{},{},{},{},{},{}", Csv(sequence), Csv(tracker), r.key, r.index,
                           r.seed_index, r.seed, Csv(r.run_dir));
        for (const std::string& v : r.values) {
          csv += ',';
          csv += Csv(v);
        }
        csv += "\n";
        ++result.runs;
      }
    }
    MakeDirs(gt_root / "seqmaps");
    WriteTextFile((gt_root / "seqmaps" / (result.bench + ".txt")).string(), seqmap);
    WriteTextFile((staging / "export.csv").string(), csv);
    // An empty OUT is replaced (rename(2) replaces an empty directory).
    fs::rename(staging, out, ec);
    if (ec) {
      throw RunError(
          fmt::format("cannot rename {} to {}: {}", staging.string(), out.string(), ec.message()));
    }
  } catch (...) {
    std::error_code ignored;
    fs::remove_all(staging, ignored);
    throw;
  }
  result.sequences = static_cast<int>(sequences.size());
  result.trackers = static_cast<int>(trackers.size());
  return result;
}

}  // namespace hcpf::studies
