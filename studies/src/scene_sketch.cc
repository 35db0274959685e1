#include "scene_sketch.h"

#include <fmt/format.h>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gnuplot.h"
#include "hcpf/core/text_file.h"
#include "hcpf/core/types.h"
#include "text.h"

namespace hcpf::studies {
namespace fs = std::filesystem;

namespace {

// The ground point (z = 0) seen at pixel (u, v): the inverse of the frame's
// image-from-ground homography; nullopt when the ray does not reach the
// ground in front of the camera.
std::optional<std::pair<double, double>> GroundAt(const Eigen::Matrix3d& ground_from_image,
                                                  double u, double v) {
  const Eigen::Vector3d p = ground_from_image * Eigen::Vector3d(u, v, 1.0);
  if (!(p.z() > 0.0) || !std::isfinite(p.x() / p.z()) || !std::isfinite(p.y() / p.z())) {
    return std::nullopt;
  }
  return std::pair{p.x() / p.z(), p.y() / p.z()};
}

std::optional<SketchFootprint> FootprintOf(const FrameGroundTruth& frame) {
  const Eigen::Matrix3d& h = frame.image_from_ground;
  if (std::abs(h.determinant()) < 1e-12) return std::nullopt;
  const Eigen::Matrix3d g = h.inverse();
  const double w = frame.camera.intrinsics.width_px;
  const double ht = frame.camera.intrinsics.height_px;
  SketchFootprint out{.frame = frame.frame, .corners = {}};
  for (const auto& [u, v] : {std::pair{0.0, 0.0}, {w, 0.0}, {w, ht}, {0.0, ht}}) {
    const auto at = GroundAt(g, u, v);
    if (!at) return std::nullopt;
    out.corners.push_back(*at);
  }
  return out;
}

// The largest distance between corresponding corners, metres.
double CornerDistance(const SketchFootprint& a, const SketchFootprint& b) {
  double d = 0.0;
  for (size_t i = 0; i < a.corners.size(); ++i) {
    d = std::max(d, std::hypot(a.corners[i].first - b.corners[i].first,
                               a.corners[i].second - b.corners[i].second));
  }
  return d;
}

// "61–95", or "12 frames between 61 and 120" when not every frame between.
std::string FramesText(const std::vector<int>& frames) {
  const int first = frames.front() + 1, last = frames.back() + 1;
  if (frames.size() == 1) return fmt::format("frame {}", first);
  if (static_cast<int>(frames.size()) == last - first + 1) {
    return fmt::format("frames {}\u2013{}", first, last);
  }
  return fmt::format("{} frames between {} and {}", frames.size(), first, last);
}

}  // namespace

SceneSketch SketchOf(const metrics::GroundTruthFile& gt) {
  SceneSketch out;
  out.frames = static_cast<int>(gt.frames.size());
  std::map<int, size_t> path_of;  // id -> index in out.paths
  std::map<std::pair<int, int>, std::vector<int>> overlaps;
  for (const FrameGroundTruth& frame : gt.frames) {
    for (const GroundTruthObject& o : frame.objects) {
      const int id = static_cast<int>(o.id);
      auto [it, added] = path_of.emplace(id, out.paths.size());
      if (added) out.paths.push_back({.id = id, .points = {}});
      out.paths[it->second].points.push_back({.frame = frame.frame,
                                              .x_m = o.position_m.x(),
                                              .y_m = o.position_m.y(),
                                              .visible_fraction = o.visible_fraction,
                                              .in_frame = o.in_frame});
    }
    for (size_t i = 0; i < frame.objects.size(); ++i) {
      for (size_t j = i + 1; j < frame.objects.size(); ++j) {
        const GroundTruthObject& a = frame.objects[i];
        const GroundTruthObject& b = frame.objects[j];
        if (!a.in_frame || !b.in_frame || Intersect(a.amodal_box, b.amodal_box).empty()) continue;
        const int ia = static_cast<int>(a.id), ib = static_cast<int>(b.id);
        overlaps[{std::min(ia, ib), std::max(ia, ib)}].push_back(frame.frame);
      }
    }
  }
  for (const auto& [pair, frames] : overlaps) {
    out.encounters.push_back({.a = pair.first, .b = pair.second, .frames = frames});
  }
  if (!gt.frames.empty()) {
    const size_t n = gt.frames.size();
    for (const size_t f : {size_t{0}, n / 2, n - 1}) {
      std::optional<SketchFootprint> fp = FootprintOf(gt.frames[f]);
      if (!fp) continue;
      if (!out.footprints.empty() && (out.footprints.back().frame == fp->frame ||
                                      CornerDistance(out.footprints.back(), *fp) <= 0.5)) {
        continue;
      }
      out.footprints.push_back(std::move(*fp));
    }
  }
  return out;
}

std::string EncounterText(const SceneSketch& sketch) {
  if (sketch.encounters.empty()) return "no two targets' boxes overlap in the image";
  std::vector<std::string> parts;
  for (const SketchEncounter& e : sketch.encounters) {
    parts.push_back(fmt::format("targets {} and {}: boxes overlap in the image in {}", e.a, e.b,
                                FramesText(e.frames)));
  }
  return fmt::format("{}", fmt::join(parts, "; "));
}

std::string SceneSketchSvg(const SceneSketch& sketch, const std::string& title,
                           const fs::path& work, const std::string& gnuplot,
                           const std::string& name) {
  const fs::path data = work / fmt::format("sketch_{}.dat", name);
  const fs::path svg = work / fmt::format("sketch_{}.svg", name);
  const fs::path script = work / fmt::format("sketch_{}.gp", name);
  // Blocks: per path its line (index 3p), its every-10th-frame dots (3p+1)
  // and its frames less than 0.75 visible in the image (3p+2); then per
  // footprint a closed polygon; labels are set in the script.
  std::string text;
  const auto block_end = [&](bool any) {
    if (!any) text += "nan nan\n";
    text += "\n\n";
  };
  for (const SketchPath& p : sketch.paths) {
    for (const SketchPoint& q : p.points)
      text += fmt::format("{} {}\n", Number(q.x_m), Number(q.y_m));
    block_end(!p.points.empty());
    bool any = false;
    for (const SketchPoint& q : p.points) {
      if (q.frame % 10 != 0) continue;
      text += fmt::format("{} {}\n", Number(q.x_m), Number(q.y_m));
      any = true;
    }
    block_end(any);
    any = false;
    for (const SketchPoint& q : p.points) {
      if (!q.in_frame || q.visible_fraction >= 0.75) continue;
      text += fmt::format("{} {}\n", Number(q.x_m), Number(q.y_m));
      any = true;
    }
    block_end(any);
  }
  for (const SketchFootprint& f : sketch.footprints) {
    for (size_t i = 0; i <= f.corners.size(); ++i) {
      const auto& [x, y] = f.corners[i % f.corners.size()];
      text += fmt::format("{} {}\n", Number(x), Number(y));
    }
    block_end(true);
  }
  WriteTextFile(data.string(), text);

  std::string gp;
  gp += SvgTerminal(820, "560");
  gp += fmt::format("set output {}\n", GpString(svg.string()));
  gp += fmt::format("set title {} noenhanced\n", GpString(title));
  gp += "set xlabel 'east, m'\nset ylabel 'north, m'\nset size ratio -1\nset grid\n";
  gp += "set key outside right top noenhanced\n";
  // Each path's start: its id; every 50th frame: the frame number (1-based).
  int label = 1;
  for (size_t p = 0; p < sketch.paths.size(); ++p) {
    const SketchPath& path = sketch.paths[p];
    if (path.points.empty()) continue;
    const SketchPoint& first = path.points.front();
    gp += fmt::format("set label {} {} at {},{} offset -1.5,0.8 front tc rgb '{}' noenhanced\n",
                      label++, GpString(fmt::format("{}", path.id)), Number(first.x_m),
                      Number(first.y_m), kPlotColours[p % std::size(kPlotColours)]);
    for (const SketchPoint& q : path.points) {
      if (q.frame == 0 || (q.frame + 1) % 50 != 0) continue;
      gp += fmt::format(
          "set label {} {} at {},{} offset 0.6,-0.6 front font 'sans,8' tc rgb '#555555'\n",
          label++, GpString(fmt::format("{}", q.frame + 1)), Number(q.x_m), Number(q.y_m));
    }
  }
  std::vector<std::string> plots;
  const std::string file = GpString(data.string());
  int index = 0;
  for (size_t p = 0; p < sketch.paths.size(); ++p, index += 3) {
    const char* colour = kPlotColours[p % std::size(kPlotColours)];
    plots.push_back(fmt::format("{} index {} using 1:2 with lines lw 2 lc rgb '{}' title {}", file,
                                index, colour,
                                GpString(fmt::format("target {}", sketch.paths[p].id))));
    plots.push_back(fmt::format("{} index {} using 1:2 with points pt 7 ps 0.45 lc rgb '{}' {}",
                                file, index + 1, colour,
                                p == 0 ? "title 'every 10th frame'" : "notitle"));
    plots.push_back(fmt::format("{} index {} using 1:2 with points pt 6 ps 1.1 lc rgb '#222222' {}",
                                file, index + 2, p == 0 ? "title 'visible < 0.75'" : "notitle"));
  }
  for (size_t f = 0; f < sketch.footprints.size(); ++f, ++index) {
    plots.push_back(fmt::format(
        "{} index {} using 1:2 with lines lw 1 dt {} lc rgb '#777777' title {}", file, index, f + 2,
        GpString(fmt::format("camera view, frame {}", sketch.footprints[f].frame + 1))));
  }
  if (plots.empty()) {
    gp +=
        "set label 1 'no target in the ground truth' at graph 0.5, 0.5 center\n"
        "plot [0:1] [0:1] NaN notitle\n";
  } else {
    gp += "plot " + fmt::format("{}", fmt::join(plots, ", \\\n     ")) + "\n";
  }
  return RunGnuplotToSvg(gnuplot, script, gp, svg);
}

}  // namespace hcpf::studies
