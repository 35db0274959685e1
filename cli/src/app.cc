// hcpf: the HCPF Bench command line. Parses arguments, dispatches to the
// subcommand, maps errors to exit codes (0 ok, 1 run failed, 2 bad input).

#include "app.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <CLI/CLI.hpp>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <iostream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "hcpf/core/did_you_mean.h"
#include "hcpf/core/error.h"
#include "hcpf/core/text_file.h"

namespace hcpf::cli {

namespace {

// CLI11's own messages in the house form (a bad-input audit: "--jobs: Value
// -1 not in range 0 to 1024" and "Run with --help for more information.",
// no "expected ... found ..."): `command line: --jobs: expected ..., found
// ...`, with where the options are listed. A message of another shape keeps
// CLI11's words after the prefix.
std::string CommandLineMessage(const std::string& what, const std::string& command,
                               const std::vector<std::string>& options) {
  const std::string where =
      fmt::format(" (hcpf {}--help lists the options)", command.empty() ? "" : command + " ");
  // std::regex recurses once a character: a message of thousands (`hcpf
  // report runs/*`, a pasted argument) overflowed the stack (a review).
  // CLI11's own words then, cut to a readable length.
  if (what.size() > 400) return "command line: " + what.substr(0, 400) + " ..." + where;
  static const std::regex kRange(R"(^(--[\w-]+): Value (.*) not in range (.*) to (.*)$)");
  static const std::regex kMissing(R"(^(--[\w-]+): \d+ required .* missing$)");
  static const std::regex kChoice(R"(^(--[\w-]+): (.*) not in \{(.*)\}$)");
  static const std::regex kRequired(R"(^(--[\w-]+|[A-Za-z]\w*) is required$)");
  static const std::regex kExtra(R"(^The following arguments? (?:was|were) not expected: (.*)$)");
  static const std::regex kOurs(R"(^(--[\w-]+): (expected .*)$)");
  static const std::regex kAtMost(R"(^(--[\w-]+): At Most (\d+) required but received (\d+)$)");
  std::smatch m;
  std::string text;
  if (std::regex_match(what, m, kRange)) {
    // CLI11 writes a number range's bounds as "0.000000": the shortest form.
    const auto bound = [](const std::string& b) {
      char* end = nullptr;
      const double value = std::strtod(b.c_str(), &end);
      return end == b.c_str() + b.size() ? fmt::format("{}", value) : b;
    };
    text = fmt::format("{}: expected a value in [{}, {}], found \"{}\"", m.str(1), bound(m.str(3)),
                       bound(m.str(4)), m.str(2));
  } else if (std::regex_match(what, m, kMissing)) {
    text = fmt::format("{}: expected a value after it, found none", m.str(1));
  } else if (std::regex_match(what, m, kChoice)) {
    std::vector<std::string> choices;
    std::stringstream list(m.str(3));
    for (std::string c; std::getline(list, c, ',');) choices.push_back(c);
    const std::string near = ClosestMatch(m.str(2), choices);
    text = fmt::format("{}: expected one of {}, found \"{}\"{}", m.str(1), fmt::join(choices, ", "),
                       m.str(2), near.empty() ? "" : " (did you mean \"" + near + "\"?)");
  } else if (std::regex_match(what, m, kRequired)) {
    const bool option = m.str(1).rfind("--", 0) == 0;
    text = fmt::format("{}: expected the {} {} (it is required), found nothing", m.str(1),
                       option ? "option" : "argument", m.str(1));
  } else if (std::regex_match(what, m, kExtra)) {
    // CLI11 lists them space-separated, last first: each is quoted, in the
    // order given.
    std::vector<std::string> extras;
    std::stringstream words(m.str(1));
    for (std::string word; words >> word;) extras.insert(extras.begin(), word);
    std::vector<std::string> quoted;
    for (const std::string& extra : extras) quoted.push_back("\"" + extra + "\"");
    // An option misspelt is among them ("--no-cahce"): the nearest.
    std::string near;
    for (const std::string& extra : extras) {
      if (extra == kLogLevelOption) {
        return fmt::format(
            "command line: {}: expected it before the command (hcpf {} LEVEL {} "
            "...), found it after",
            kLogLevelOption, kLogLevelOption, command);
      }
      if (near.empty() && extra.rfind("--", 0) == 0) near = ClosestMatch(extra, options);
    }
    text = fmt::format("expected no more arguments, found {}{}", fmt::join(quoted, ", "),
                       near.empty() ? "" : " (did you mean \"" + near + "\"?)");
  } else if (std::regex_match(what, m, kAtMost)) {
    // A fourth bad-input audit: CLI11's "At Most 1 required but received 2".
    text = fmt::format("{}: expected it {}, found it {} times", m.str(1),
                       m.str(2) == "1" ? std::string("once") : "at most " + m.str(2) + " times",
                       m.str(3));
  } else if (std::regex_match(what, m, kOurs)) {
    text = fmt::format("{}: {}", m.str(1), m.str(2));
  } else {
    text = what;
  }
  return "command line: " + text + where;
}

int ParseAndRun(int argc, char** argv, std::span<const AddCommandFn> adders,
                const std::function<std::string()>& version) {
  // Logging goes to stderr; stdout is reserved for requested machine output.
  auto logger = spdlog::stderr_color_mt("hcpf");
  spdlog::set_default_logger(logger);
  spdlog::set_pattern("[%H:%M:%S.%e] [%^%l%$] %v");

  CLI::App app{"HCPF Bench: synthetic-scene evaluation harness for multi-target tracking"};
  if (version) app.set_version_flag("--version", version);
  app.require_subcommand(1);
  std::string log_level = "info";
  app.add_option(kLogLevelOption, log_level, "trace, debug, info, warn, error or off")
      ->check(CLI::IsMember({"trace", "debug", "info", "warn", "error", "off"}))
      ->capture_default_str();

  std::vector<Command> commands;
  for (const AddCommandFn add : adders) commands.push_back(add(app));
  // Integer options take decimal digits only, checked before their range: a
  // second bad-input audit found --jobs 0x2 read as 2 (CLI11 reads 0x, 0o
  // and 0b prefixes) and --jobs 1.5 refused as "not in range".
  const CLI::Validator decimal(
      [](std::string& text) -> std::string {
        const size_t digits = text.size() > 1 && (text[0] == '-' || text[0] == '+') ? 1 : 0;
        if (digits < text.size() &&
            text.find_first_not_of("0123456789", digits) == std::string::npos) {
          return {};
        }
        return fmt::format("expected a decimal integer, found \"{}\"", text);
      },
      "", "decimal");
  // Number options likewise take a finite decimal number: CLI::Range let
  // --min-visible nan through (NaN fails both of its comparisons) and CLI11
  // reads hexadecimal floats (0x0.8p0) and inf (a third bad-input audit).
  const CLI::Validator finite_decimal(
      [](std::string& text) -> std::string {
        static const std::regex kNumber(R"([+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?)");
        if (std::regex_match(text, kNumber) && std::isfinite(std::strtod(text.c_str(), nullptr))) {
          return {};
        }
        return fmt::format("expected a finite decimal number, found \"{}\"", text);
      },
      "", "finite decimal");
  for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
    for (CLI::Option* option : sub->get_options()) {
      const std::string type = option->get_type_name();
      if (type.rfind("INT", 0) == 0) option->transform(decimal);
      if (type.rfind("FLOAT", 0) == 0) option->transform(finite_decimal);
    }
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    // An unknown command: CLI11 says only that a subcommand is required.
    const std::vector<std::string> rest = app.remaining();
    if (!rest.empty() && app.get_subcommands().empty()) {
      std::vector<std::string> names;
      for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
        names.push_back(sub->get_name());
      }
      const std::string near = ClosestMatch(rest.front(), names);
      spdlog::error("expected a command ({}), found \"{}\"{}",
                    fmt::format("{}", fmt::join(names, ", ")), rest.front(),
                    near.empty() ? "" : " (did you mean \"" + near + "\"?)");
      return 2;
    }
    // An unknown option before the command (`hcpf -v validate F`): CLI11
    // blames the command's arguments (a fourth bad-input audit).
    for (int i = 1; i < argc; ++i) {
      const std::string word = argv[i];
      if (word == kLogLevelOption) {
        ++i;  // its value
        continue;
      }
      if (word.rfind(std::string(kLogLevelOption) + "=", 0) == 0 || word == "--version" ||
          word == "--help" || word == "-h") {
        continue;
      }
      if (word.empty() || word[0] != '-') break;  // the command
      const std::string near = ClosestMatch(word, {kLogLevelOption, "--version", "--help"});
      spdlog::error(
          "command line: expected an option of hcpf before the command ({} LEVEL, --version, "
          "--help), found \"{}\"{}",
          kLogLevelOption, word, near.empty() ? "" : " (did you mean \"" + near + "\"?)");
      return 2;
    }
    // The command given (its options are the ones to list), if any.
    // (The top level's options are listed by `hcpf --help`, and are near
    // misses too: --log-levle.)
    std::string command;
    std::vector<std::string> options = {kLogLevelOption, "--version"};
    const std::string message = e.what();
    for (const CLI::App* sub : app.get_subcommands()) {
      if (message.rfind(kLogLevelOption, 0) != 0) command = sub->get_name();
      for (const CLI::Option* option : sub->get_options()) {
        for (const std::string& name : option->get_lnames()) options.push_back("--" + name);
      }
    }
    spdlog::error("{}", CommandLineMessage(e.what(), command, options));
    return 2;
  }
  spdlog::set_level(spdlog::level::from_str(log_level));

  for (const auto& command : commands) {
    if (!command.app->parsed()) continue;
    try {
      // An option given an empty value (`--shard "$TASK"` with TASK unset)
      // is bad input, never "not given": a second bad-input audit found
      // --shard '' running the whole sweep, report --out '' writing into
      // DIR and regress --junit '' writing nothing, each with exit 0.
      for (const CLI::Option* option : command.app->get_options()) {
        if (option->get_expected_max() == 0) continue;  // a flag
        for (const std::string& value : option->results()) {
          if (!value.empty()) continue;
          const std::string name =
              option->get_lnames().empty() ? option->get_name() : "--" + option->get_lnames()[0];
          throw InputError(SourceLocation{"command line", 0, 0, name}, "a value", "an empty value");
        }
      }
      return command.run();
    } catch (const hcpf::InputError& e) {
      spdlog::error("{}", e.what());
      return 2;
    } catch (const std::exception& e) {
      spdlog::error("{} failed: {}", command.app->get_name(), e.what());
      return 1;
    }
  }
  return 2;
}

// Standard output carries what a command was asked for (score's table,
// validate --print, schema, cache, report's path, --help, --version): text
// that could not be written is a failure, never exit 0 (`hcpf schema >
// /dev/full` and `hcpf validate --print` on a full disk exited 0 with the
// text lost). A broken pipe ends the process by SIGPIPE before this, as it
// does for any Unix filter.
int FinishStandardOutput(int code) {
  errno = 0;  // std::cout writes through stdout's buffer (synced with stdio)
  const bool flush_failed = std::fflush(stdout) != 0;
  const int flush_errno = errno;
  std::cout.flush();
  if (!flush_failed && std::ferror(stdout) == 0 && !std::cout.bad()) return code;
  spdlog::error("writing standard output failed{}",
                flush_failed && flush_errno != 0
                    ? fmt::format(": {}", std::strerror(flush_errno))
                    : std::string(": part of it could not be written"));
  return code == 0 ? 1 : code;
}

}  // namespace

std::ostream& TableStream(std::initializer_list<std::string> output_paths) {
  for (const std::string& path : output_paths) {
    if (IsStandardOutput(path)) return std::cerr;
  }
  return std::cout;
}

int RunApp(int argc, char** argv, std::span<const AddCommandFn> adders,
           const std::function<std::string()>& version) {
  return FinishStandardOutput(ParseAndRun(argc, argv, adders, version));
}

}  // namespace hcpf::cli
