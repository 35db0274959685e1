// hcpf merge OUT DIR...

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <memory>

#include "command.h"
#include "hcpf/studies/results_store.h"

namespace hcpf::cli {

Command AddMergeCommand(CLI::App& parent) {
  struct Options {
    std::string out;
    std::vector<std::string> inputs;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand(
      "merge", "Merge the results stores (and run folders) of sweep shards into OUT");
  app->add_option("out", options->out,
                  "Output folder (created; an existing store of the same sweep is extended)")
      ->required();
  app->add_option("dirs", options->inputs, "Shard folders (each with results.sqlite)")->required();
  return {app, [options] {
            const studies::MergeResult r = studies::MergeStores(options->out, options->inputs);
            spdlog::info(
                "merged {} store(s) into {}/results.sqlite: {} runs added, {} duplicates "
                "skipped{}{}",
                options->inputs.size(), options->out, r.added, r.duplicates,
                r.damaged > 0 ? fmt::format(", {} with a missing or damaged run folder merged as "
                                            "failed (resume the sweep on {} to recompute them)",
                                            r.damaged, options->out)
                              : std::string(),
                r.contact_sheet ? "; the scene's contact_sheet.png copied" : "");
            return 0;
          }};
}

}  // namespace hcpf::cli
