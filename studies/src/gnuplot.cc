#include "gnuplot.h"

#include <fmt/format.h>

#include <fstream>
#include <sstream>

#include "hcpf/core/error.h"
#include "hcpf/core/subprocess.h"

namespace hcpf::studies {

namespace fs = std::filesystem;

std::string GpString(const std::string& text) {
  std::string out = "'";
  for (char c : text) out += c == '\'' ? std::string("''") : std::string(1, c);
  return out + "'";
}

void RunGnuplot(const std::string& gnuplot, const fs::path& script) {
  const std::string log = script.string() + ".log";
  const ProcessStatus status = RunProcess({gnuplot, script.string()}, log);
  if (!status.started) throw RunError(fmt::format("cannot start gnuplot: {}", status.error));
  if (status.ok()) return;
  const std::string messages = ReadWholeFile(log);
  if (status.exit_code == 127) {
    throw RunError(fmt::format(
        "cannot run \"{}\" (install Debian gnuplot-nox, or pass --gnuplot PATH)", gnuplot));
  }
  throw RunError(fmt::format(
      "gnuplot failed ({} {}) on {}: {}", status.signal != 0 ? "signal" : "status",
      status.signal != 0 ? status.signal : status.exit_code, script.string(), messages));
}

std::string ReadWholeFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string InlineSvg(const std::string& svg) {
  const size_t start = svg.find("<svg");
  return start == std::string::npos ? svg : svg.substr(start);
}

std::filesystem::path MakePlotWorkDir(const std::filesystem::path& out, bool out_is_input) {
  const std::filesystem::path work = out / ".report-work";
  std::error_code ec;
  std::filesystem::remove_all(work, ec);
  std::filesystem::create_directories(work, ec);
  if (ec) {
    throw RunError(
        fmt::format("cannot create {}: {}{}", work.string(), ec.message(),
                    out_is_input ? " (use --out to write the report to another folder)" : ""));
  }
  return work;
}

}  // namespace hcpf::studies
