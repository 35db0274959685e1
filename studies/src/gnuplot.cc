#include "gnuplot.h"

#include <fmt/format.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

#include "hcpf/core/error.h"
#include "hcpf/core/subprocess.h"
#include "hcpf/core/text_file.h"
#include "hcpf/scenarios/output_folder.h"

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

std::string SvgTerminal(int width, const std::string& height) {
  return fmt::format("set terminal svg size {},{} dynamic font 'sans,11' background rgb 'white'\n",
                     width, height);
}

std::string FitCanvasToBox(int width, int trial_height, int box_px, const fs::path& svg,
                           const fs::path& box_file) {
  std::string gp =
      fmt::format("hcpf_height = int({} - (GPVAL_TERM_YMAX - GPVAL_TERM_YMIN) + {} + 0.5)\n",
                  trial_height, box_px);
  gp += SvgTerminal(width, "hcpf_height");
  gp += fmt::format("set output {}\nreplot\n", GpString(svg.string()));
  // The box, in px from the left and from the bottom, and the height.
  gp += fmt::format(
      "set print {}\nprint GPVAL_TERM_XMIN, GPVAL_TERM_XMAX, GPVAL_TERM_YMIN, "
      "GPVAL_TERM_YMAX, hcpf_height\nunset print\n",
      GpString(box_file.string()));
  return gp;
}

std::optional<PlotBox> ReadPlotBox(const fs::path& box_file, int width) {
  std::error_code ec;
  if (!fs::is_regular_file(box_file, ec)) return std::nullopt;
  std::istringstream in(ReadWholeFile(box_file));
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0;
  int height = 0;
  if (!(in >> x0 >> x1 >> y0 >> y1 >> height) || !(x0 >= 0 && x0 < x1 && x1 <= width) ||
      !(y0 >= 0 && y0 < y1 && y1 <= height)) {
    return std::nullopt;
  }
  return PlotBox{
      .left = x0, .right = x1, .top = height - y1, .bottom = height - y0, .height = height};
}

std::string RunGnuplotToSvg(const std::string& gnuplot, const fs::path& script,
                            const std::string& gp, const fs::path& svg) {
  WriteTextFile(script.string(), gp);
  RunGnuplot(gnuplot, script);
  // A program that exits 0 without writing the plot (a wrapper, a gnuplot
  // whose svg terminal failed quietly) gave a report of empty plots, exit 0
  // (a bad-input audit): a failure as gnuplot's own.
  const std::string text = ReadWholeFile(svg);
  if (text.find("<svg") == std::string::npos) {
    throw RunError(fmt::format("gnuplot (\"{}\") exited 0 but wrote no SVG to {}{}", gnuplot,
                               svg.string(), fs::exists(svg) ? " (the file holds none)" : ""));
  }
  return InlineSvg(text);
}

void CheckGnuplot(const std::string& gnuplot) {
  const SourceLocation where{"command line", 0, 0, "--gnuplot"};
  const std::string hint =
      "install Debian gnuplot-nox (scripts/setup.sh does), or pass --gnuplot PATH";
  if (gnuplot.find('/') == std::string::npos) {
    if (!ExecutableOnPath(gnuplot)) {
      throw InputError(
          where, "gnuplot on PATH, or a path with a '/'",
          fmt::format("\"{}\", which is not an executable file in any folder of PATH", gnuplot),
          hint);
    }
    return;
  }
  std::error_code ec;
  const fs::file_status st = fs::status(gnuplot, ec);
  std::string found;
  if (!fs::exists(st)) {
    found = fmt::format("\"{}\", which does not exist", gnuplot);
  } else if (fs::is_directory(st)) {
    found = fmt::format("\"{}\", which is a folder", gnuplot);
  } else if (!fs::is_regular_file(st) || ::access(gnuplot.c_str(), X_OK) != 0) {
    found = fmt::format("\"{}\", which is not an executable file", gnuplot);
  }
  if (!found.empty()) throw InputError(where, "the path of the gnuplot executable", found, hint);
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
  // What an earlier report killed while writing its files left.
  RemoveStaleTempFiles(out);
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

void PublishReportFiles(const std::filesystem::path& work, const std::filesystem::path& out,
                        const std::vector<std::pair<std::string, std::string>>& files,
                        const std::vector<std::string>& stale) {
  namespace fs = std::filesystem;
  const fs::path staged = work / "publish";
  std::error_code ec;
  fs::create_directories(staged, ec);
  if (ec) throw RunError(fmt::format("cannot create {}: {}", staged.string(), ec.message()));
  for (const auto& [name, text] : files) WriteTextFile((staged / name).string(), text);
  for (const auto& [name, text] : files) {
    const fs::path target = out / name;
    const fs::file_status status = fs::symlink_status(target, ec);
    if (fs::exists(status) && !fs::is_regular_file(status)) {
      WriteTextFile(target.string(), text);
      continue;
    }
    if (fs::is_regular_file(status)) fs::permissions(staged / name, status.permissions(), ec);
    fs::rename(staged / name, target, ec);
    if (ec) {
      throw RunError(fmt::format("replacing {} failed: {}", target.string(), ec.message()));
    }
  }
  for (const std::string& name : stale) fs::remove(out / name, ec);
}

void CheckReportOut(const std::string& out_dir) {
  namespace fs = std::filesystem;
  scenarios::CheckFolderArgument(out_dir, "--out");
  const SourceLocation where{out_dir, 0, 0, "--out"};
  const std::string expected =
      "a new or empty folder, or one holding only an earlier report (report.html, summary.csv, "
      "paired.csv, findings.md, replication.csv, replication_cells.csv)";
  std::error_code ec;
  if (fs::is_symlink(fs::symlink_status(out_dir, ec))) {
    throw InputError(where, expected, "a symbolic link", "nothing was changed; name a folder");
  }
  // A second bad-input audit: a sweep's report written over another
  // sweep's, into a run folder (which hcpf run then refused), or into a
  // TrackEval export.
  const std::string foreign =
      scenarios::FirstForeignEntry(out_dir, [](const fs::directory_entry& entry) {
        std::error_code ec;
        const std::string name = entry.path().filename().string();
        // A report killed while writing leaves WriteTextFile's temporary file.
        const std::string target = TempFileTarget(name);
        const std::string& file = target.empty() ? name : target;
        const bool report_file = file == "report.html" || file == "summary.csv" ||
                                 file == "paired.csv" || file == "findings.md" ||
                                 file == "replication.csv" || file == "replication_cells.csv";
        return (report_file && entry.is_regular_file(ec)) ||
               (name == ".report-work" && entry.is_directory(ec));
      });
  if (foreign.empty()) return;
  throw InputError(where, expected,
                   fmt::format("a folder with other files in it (\"{}\")", foreign),
                   "nothing was changed; name another folder");
}

}  // namespace hcpf::studies
