// hcpf schema [SECTION ...] [--update FILE]

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include "command.h"
#include "hcpf/core/did_you_mean.h"
#include "hcpf/core/error.h"
#include "hcpf/core/text_file.h"
#include "hcpf/scenarios/schema.h"
#include "hcpf/studies/file_keys.h"

namespace hcpf::cli {
namespace {

std::vector<std::string> AllSections() {
  std::vector<std::string> sections = scenarios::SchemaSections();
  for (std::string_view s : studies::FileKeySections()) sections.emplace_back(s);
  return sections;
}

// A scenario section (scenarios/schema.h) or a sweep-file / suite section
// (studies/file_keys.h); an unknown one is an InputError listing both kinds.
std::string AnyMarkdown(const std::string& section) {
  const std::string table = studies::FileKeysMarkdown(section);
  if (!table.empty()) return table;
  try {
    return scenarios::SchemaMarkdown(section);
  } catch (const InputError&) {
    const std::vector<std::string> all = AllSections();
    const std::string close = ClosestMatch(section, all);
    throw InputError(SourceLocation{"hcpf schema", 0, 0, "section"},
                     fmt::format("one of {}", fmt::join(all, " | ")),
                     fmt::format("\"{}\"", section),
                     close.empty() ? "" : "did you mean \"" + close + "\"?");
  }
}

}  // namespace

Command AddSchemaCommand(CLI::App& parent) {
  struct Options {
    std::vector<std::string> sections;
    std::string update;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand(
      "schema",
      "Print the scenario keys declared by the modules (key, type, unit, default, range, "
      "meaning) as markdown tables, or rewrite the generated tables of a document");
  app->add_option("sections", options->sections,
                  "Sections to print (default: all): scenario, world, \"world.occluders[i] "
                  "kind=bridge\", camera, \"camera.path[i]\", \"targets[i]\", "
                  "\"targets[i].path\", ..., sensor, observation, renderer, tracker, metrics, "
                  "sweep, suite");
  app->add_option("--update", options->update,
                  "Rewrite the generated tables of this markdown file in place "
                  "(docs/scenario.md, docs/sweeps.md)");
  return {app, [options] {
            if (!options->update.empty()) {
              // A folder or a missing file said as such (an audit: "found
              // none" for a folder, "found No such file or directory").
              std::error_code ec;
              const auto status = std::filesystem::status(options->update, ec);
              if (status.type() == std::filesystem::file_type::not_found) {
                throw InputError(SourceLocation{options->update, 0, 0, "--update"},
                                 "a markdown file with generated tables", "no such file");
              }
              if (status.type() == std::filesystem::file_type::directory) {
                throw InputError(SourceLocation{options->update, 0, 0, "--update"},
                                 "a markdown file with generated tables", "a folder");
              }
              std::ifstream in(options->update, std::ios::binary);
              if (!in) {
                throw InputError(
                    SourceLocation{options->update, 0, 0, "--update"}, "a readable markdown file",
                    fmt::format("a file that cannot be read ({})", std::strerror(errno)));
              }
              std::stringstream text;
              text << in.rdbuf();
              const std::string updated =
                  scenarios::UpdateGeneratedTables(text.str(), options->update, AnyMarkdown);
              if (updated == text.str()) {
                spdlog::info("{}: generated tables are up to date", options->update);
                return 0;
              }
              // Whole or not at all: truncated in place, a full disk left the
              // user's document cut short (and the failure was seen only at
              // a close nobody checked).
              WriteTextFile(options->update, updated);
              spdlog::info("{}: generated tables rewritten", options->update);
              return 0;
            }
            const std::vector<std::string> sections =
                options->sections.empty() ? AllSections() : options->sections;
            // Every table first: an unknown section prints nothing at all.
            std::string text;
            for (const std::string& section : sections) {
              text += "## `" + section + "`\n\n" + AnyMarkdown(section) + "\n";
            }
            std::cout << text;
            return 0;
          }};
}

}  // namespace hcpf::cli
