#pragma once
// A sketch of a run's scene from above, drawn from its gt.json alone (no
// rendering): each target's path on the ground with a dot every 10th frame,
// the frames where it is less than 0.75 visible ringed, and the ground the
// camera sees at its first, middle and last frame. A detection-level sweep
// has no contact sheet, and an audit found its report had no picture of what
// "crossing with a dominant target" looks like; the sweep report and the
// run report both show it.

#include <filesystem>
#include <string>
#include <vector>

#include "hcpf/metrics/detection_truth.h"

namespace hcpf::studies {

struct SketchPoint {
  int frame = 0;  // 0-based
  double x_m = 0.0, y_m = 0.0;
  double visible_fraction = 1.0;
  bool in_frame = false;  // some of its box is inside the image
};

struct SketchPath {
  int id = 0;
  std::vector<SketchPoint> points;  // frames where the target is present, in order
};

// The ground the image covers: its four corners (top left, top right,
// bottom right, bottom left) on the ground plane z = 0.
struct SketchFootprint {
  int frame = 0;  // 0-based
  std::vector<std::pair<double, double>> corners;
};

// Two targets whose boxes overlap in the image (amodal boxes, both in the
// frame): the frames (0-based) where they do.
struct SketchEncounter {
  int a = 0, b = 0;  // ids, a < b
  std::vector<int> frames;
};

struct SceneSketch {
  std::vector<SketchPath> paths;            // in order of first appearance
  std::vector<SketchFootprint> footprints;  // first, middle, last (those that differ)
  std::vector<SketchEncounter> encounters;
  int frames = 0;
};

// The sketch of `gt`. A footprint is left out when a corner's ray does not
// reach the ground (a camera looking at the horizon), and a middle or last
// one when it is within 0.5 m of the one before (a still camera: one).
SceneSketch SketchOf(const metrics::GroundTruthFile& gt);

// "targets 1 and 2: boxes overlap in the image in frames 61–95" per
// encounter (frames 1-based, as gt/gt.txt and the timeline count them), or
// "no two targets' boxes overlap in the image".
std::string EncounterText(const SceneSketch& sketch);

// The sketch as an inline SVG (gnuplot on files in `work`, named
// sketch_<name>.*), titled `title`.
std::string SceneSketchSvg(const SceneSketch& sketch, const std::string& title,
                           const std::filesystem::path& work, const std::string& gnuplot,
                           const std::string& name);

}  // namespace hcpf::studies
