#pragma once
// The plotting machinery shared by the sweep report (report.cc) and the run
// report (run_report.cc): gnuplot run as a subprocess on a script that writes
// an SVG file, and that file's <svg> element inlined into the page.

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace hcpf::studies {

// A gnuplot string literal (single quotes; '' escapes a quote).
std::string GpString(const std::string& text);

// Runs `gnuplot script`; throws RunError with gnuplot's messages when it
// fails, and one that names Debian gnuplot-nox and --gnuplot when the
// executable cannot be run.
void RunGnuplot(const std::string& gnuplot, const std::filesystem::path& script);

// Checks --gnuplot before a report writes anything: a path with a '/' must
// name an executable file, a bare name one on PATH. InputError naming
// --gnuplot otherwise (a second bad-input audit: a folder given as gnuplot
// failed the report midway and left its --out folder behind, empty).
void CheckGnuplot(const std::string& gnuplot);

// Writes the gnuplot script `gp` to `script`, runs it (RunGnuplot) and
// returns the SVG it wrote to `svg`, inlined (InlineSvg): every plot of the
// reports ends so.
std::string RunGnuplotToSvg(const std::string& gnuplot, const std::filesystem::path& script,
                            const std::string& gp, const std::filesystem::path& svg);

// The whole of a file the report wrote itself ("" when it cannot be read).
std::string ReadWholeFile(const std::filesystem::path& path);

// The SVG element of a gnuplot SVG file (no XML prolog or doctype).
std::string InlineSvg(const std::string& svg);

// Creates `out`/.report-work afresh (removed first) for the plots' scripts and
// data, and returns it; throws RunError naming the folder, and suggesting
// --out when the report writes into the folder it reads (`out_is_input`).
std::filesystem::path MakePlotWorkDir(const std::filesystem::path& out, bool out_is_input);

// Writes a report's files (file name in `out` -> contents) as one set: each
// is first written whole into `work` (MakePlotWorkDir), and only when all of
// them are there are they renamed into `out`, in the order given (report.html
// last). A report that fails on the way (a full disk) leaves the earlier
// report in `out` as it was, not a mix of two reports; a kill can leave a mix
// only inside the renames, microseconds. A name that is a symbolic link,
// device or FIFO in `out` is written through in place (WriteTextFile), and an
// existing file keeps its mode. Then the names in `stale` (files of an
// earlier report that this one does not write) are removed from `out`.
void PublishReportFiles(const std::filesystem::path& work, const std::filesystem::path& out,
                        const std::vector<std::pair<std::string, std::string>>& files,
                        const std::vector<std::string>& stale);

// Checks a report's --out folder: new, empty, or holding only what a report
// writes (report.html, summary.csv, paired.csv, findings.md, .report-work);
// anything else, another sweep, a run folder or a symbolic link, is an
// InputError naming what it holds, before anything is written.
void CheckReportOut(const std::string& out_dir);

// A plot's canvas that fits its key. The end of a gnuplot script whose
// `plot` was drawn on a canvas `trial_height` tall: it reads where gnuplot
// put the plot's box (GPVAL_TERM_YMIN / YMAX), sets the terminal to `width`
// by the height that makes the box `box_px` tall, whatever the title, axis
// labels and key take, and plots again into `svg`; then writes the box and
// that height to `box_file` (ReadPlotBox). On a canvas of fixed height a key
// of many entries took the plot's place (an audit: 18 targets' centre-error
// lines left their plot 200 of 440 px; the timeline's key ran off its
// canvas).
std::string FitCanvasToBox(int width, int trial_height, int box_px,
                           const std::filesystem::path& svg, const std::filesystem::path& box_file);

// The terminal line of every plot: `width` by `height` px ("hcpf_height", the
// gnuplot variable FitCanvasToBox sets, is taken as written).
std::string SvgTerminal(int width, const std::string& height);

// Where gnuplot drew a plot's box, in the SVG's own units (its viewBox: x
// from the left, y from the top), and the canvas height, as FitCanvasToBox
// wrote them to `box_file`; nullopt when the file is missing or does not fit
// a canvas `width` wide.
struct PlotBox {
  double left = 0, right = 0, top = 0, bottom = 0;
  int height = 0;
};
std::optional<PlotBox> ReadPlotBox(const std::filesystem::path& box_file, int width);

// Line colours of every plot, in order (tab10).
inline constexpr const char* kPlotColours[] = {"#1f77b4", "#d62728", "#2ca02c", "#ff7f0e",
                                               "#9467bd", "#8c564b", "#e377c2", "#7f7f7f",
                                               "#bcbd22", "#17becf"};

}  // namespace hcpf::studies
