// hcpf score GT HYP [--seqinfo FILE] [--benchmark MOT15|MOT17|auto] [--json FILE] [--events FILE]
// hcpf score --trackeval-root DIR [--benchmark ...] [--json FILE]
//
// Scores MOTChallenge files with CLEAR MOT, Identity and HOTA (TrackEval's
// rules, see docs/metrics.md): a table on stdout, every value with --json.

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <vector>

#include "command.h"
#include "hcpf/core/error.h"
#include "hcpf/core/text_file.h"
#include "hcpf/metrics/report.h"

namespace hcpf::cli {

namespace fs = std::filesystem;

Command AddScoreCommand(CLI::App& parent) {
  struct Options {
    std::string gt;
    std::string hyp;
    std::string seqinfo;
    std::string benchmark = "auto";
    std::string json;
    std::string events;
    std::string trackeval_root;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand(
      "score",
      "Score tracker output against ground truth (MOTChallenge files): HOTA, CLEAR MOT, IDF1");
  app->add_option("gt", options->gt, "Ground-truth file (MOT15 6/10 or MOT16/17 9 columns)");
  app->add_option("hyp", options->hyp, "Tracker output (MOT 10 columns)");
  app->add_option("--seqinfo", options->seqinfo,
                  "seqinfo.ini giving seqLength (default: next to GT or in its parent folder)");
  app->add_option(
         "--benchmark", options->benchmark,
         "Preprocessing rules: MOT15, MOT17 (also MOT16/MOT20) or auto (9-column gt = MOT17)")
      ->check(CLI::IsMember({"MOT15", "MOT16", "MOT17", "MOT20", "auto"}))
      ->capture_default_str();
  app->add_option("--json", options->json, "Write every metric value to this JSON file");
  app->add_option("--events", options->events,
                  "Write the per-frame event log (MATCH, SWITCH, ...) as JSON lines to this file");
  app->add_option("--trackeval-root", options->trackeval_root,
                  "Score a TrackEval folder (gt/mot_challenge/<bench>/<seq>, "
                  "trackers/mot_challenge/<bench>/<tracker>/data; the sequences of "
                  "gt/mot_challenge/seqmaps/<bench>.txt when there is one) instead of GT HYP");
  return {app, [options]() -> int {
            using namespace hcpf::metrics;
            const Benchmark benchmark = *ParseBenchmark(options->benchmark);
            if (!options->trackeval_root.empty()) {
              if (!options->gt.empty() || !options->hyp.empty()) {
                throw InputError(SourceLocation{{}, 0, 0, "score"},
                                 "either GT HYP or --trackeval-root DIR", "both");
              }
              // What only GT HYP takes (a third bad-input audit: ignored).
              for (const auto& [value, option] :
                   {std::pair{&options->events, "--events"}, {&options->seqinfo, "--seqinfo"}}) {
                if (value->empty()) continue;
                throw InputError(
                    SourceLocation{"command line", 0, 0, option},
                    "no " + std::string(option) + " with --trackeval-root (it goes with GT HYP)",
                    *value);
              }
              // --json checked before anything is read (a third bad-input
              // audit: a folder or a missing parent failed after the table).
              if (!options->json.empty()) {
                const fs::path root(options->trackeval_root);
                CheckFilesToWrite({{options->json, "--json"}}, {}, {root / "gt", root / "trackers"},
                                  "score", "nothing was written");
              }
              const auto results = ScoreTrackEvalRoot(options->trackeval_root, benchmark);
              std::string json = "[\n";
              for (size_t i = 0; i < results.size(); ++i) {
                const TrackEvalResult& r = results[i];
                std::vector<MotSummary> rows = r.sequences;
                rows.push_back(r.combined);
                std::cout << r.bench << " / " << r.tracker << "\n" << FormatMotTable(rows) << "\n";
                json += "{\"bench\":" + nlohmann::json(r.bench).dump() +
                        ",\"tracker\":" + nlohmann::json(r.tracker).dump() +
                        ",\"metrics\":" + MotSummariesToJson(r.sequences, &r.combined) + "}" +
                        (i + 1 < results.size() ? ",\n" : "\n");
              }
              json += "]\n";
              if (results.empty())
                spdlog::warn("{}: no tracker folders found", options->trackeval_root);
              if (!options->json.empty()) WriteTextFile(options->json, json);
              return 0;
            }
            if (options->gt.empty() || options->hyp.empty()) {
              throw InputError(SourceLocation{{}, 0, 0, "score"},
                               "GT and HYP files (or --trackeval-root DIR)", "missing arguments");
            }
            // --json and --events checked before anything is read (a third
            // bad-input audit: --json naming the tracker file replaced it,
            // exit 0; both naming one file lost the JSON).
            std::vector<FileToWrite> writes;
            if (!options->json.empty()) writes.push_back({options->json, "--json"});
            if (!options->events.empty()) writes.push_back({options->events, "--events"});
            CheckFilesToWrite(writes,
                              {{options->gt, "the ground truth (GT)"},
                               {options->hyp, "the tracker output (HYP)"},
                               {options->seqinfo, "the --seqinfo file"}},
                              {}, "score", "nothing was written");
            ScoreFilesOptions o;
            o.gt_path = options->gt;
            o.hyp_path = options->hyp;
            o.seqinfo_path = options->seqinfo;
            o.benchmark = benchmark;
            o.keep_events = !options->events.empty();
            const ScoredSequence s = ScoreFiles(o);
            std::cout << FormatMotTable({&s.summary, 1});
            if (!options->json.empty())
              WriteTextFile(options->json, MotSummariesToJson({&s.summary, 1}, nullptr));
            if (!options->events.empty()) {
              std::ostringstream events;
              WriteEventsJsonLines(events, s.events);
              WriteTextFile(options->events, events.str());
            }
            return 0;
          }};
}

}  // namespace hcpf::cli
