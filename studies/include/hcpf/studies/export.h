#pragma once
// `hcpf export DIR --trackeval OUT`: lays a sweep's runs out in TrackEval's
// MotChallenge2DBox folder layout, so TrackEval's own scripts (and
// `hcpf score --trackeval-root OUT`) score them unchanged (docs/sweeps.md,
// "Export to TrackEval").
//
//   OUT/gt/mot_challenge/<B>-<S>/<seq>/gt/gt.txt, .../<seq>/seqinfo.ini
//   OUT/gt/mot_challenge/seqmaps/<B>-<S>.txt        ("name", then one sequence a line)
//   OUT/trackers/mot_challenge/<B>-<S>/<tracker>/data/<seq>.txt
//   OUT/export.csv                                  (sequence, tracker -> run)
//
// A sequence is one ground truth: the runs that share the values of every
// swept key that is not a `tracker.*` key, and the seed index. A tracker is
// one combination of the swept `tracker.*` values. Only ok runs are exported;
// a sequence lacking an ok run of some tracker is left out (TrackEval needs
// every tracker on every sequence of the seqmap).

#include <cstdint>
#include <string>

namespace hcpf::studies {

struct TrackEvalExportOptions {
  std::string dir;                 // a sweep folder (results.sqlite + runs/)
  std::string out;                 // a new or empty folder
  std::string benchmark = "HCPF";  // TrackEval's BENCHMARK; [A-Za-z0-9_]+
  std::string split = "train";     // TrackEval's SPLIT_TO_EVAL; [A-Za-z0-9_]+
  // InputError naming the option when a name is empty or has another character.
  void Validate() const;
};

struct TrackEvalExportResult {
  int sequences = 0;
  int trackers = 0;
  int runs = 0;         // run folders exported (sequences × trackers)
  int skipped = 0;      // ok runs left out: their sequence lacks some tracker's run
  int not_ok = 0;       // failed runs, or ok runs whose folder lacks a file
  int64_t missing = 0;  // runs of the sweep not in the store (MissingRunsSentence)
  std::string bench;    // "<benchmark>-<split>"
};

// Throws InputError when DIR holds no results store, OUT exists and is not an
// empty folder, or no sequence has an ok run of every tracker; RunError when
// runs grouped into one sequence disagree on their ground truth (a broken
// assumption, never expected) or a file cannot be written. OUT appears whole
// or not at all: everything is written into OUT.partial-<pid> and renamed.
TrackEvalExportResult ExportTrackEval(const TrackEvalExportOptions& options);

}  // namespace hcpf::studies
