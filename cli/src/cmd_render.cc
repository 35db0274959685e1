// hcpf render SCENARIO.yaml --out DIR [--set key=value ...] [--cache DIR]
//
// Renders every frame of a scenario off-screen and writes
//   DIR/frames/000001.png ...      8-bit RGB frames (1-based names, MOT style)
//   DIR/frames/000001_depth.png    16-bit depth in mm   (renderer.write_depth)
//   DIR/frames/000001_ids.png      16-bit id + 1        (renderer.write_instance_ids)
//   DIR/gt.txt                     MOT17, 9 columns; visibility = pixel-exact visible fraction
//   DIR/gt.json                    every ground-truth field per frame, camera K and pose, homography
//   DIR/seqinfo.ini                MOTChallenge sequence info
//   DIR/contact_sheet.png          up to 16 evenly sampled frames with ground-truth boxes

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>

#include "command.h"
#include "hcpf/core/error.h"
#include "hcpf/renderer/image_io.h"
#include "hcpf/renderer/renderer.h"
#include "hcpf/scenarios/scenario.h"

namespace hcpf::cli {
namespace {

renderer::RendererOptions RendererOptionsOf(const scenarios::Scenario& s) {
  renderer::RendererOptions o;
  o.backend = renderer::ParseGlBackend(s.renderer.backend);
  o.shadow_map_size = s.renderer.shadow_map_size;
  o.pcf_radius = s.renderer.pcf_radius;
  o.output_depth = s.renderer.write_depth;
  o.output_instance_ids = s.renderer.write_instance_ids;
  o.sensor.noise_sigma = s.sensor.noise_sigma;
  o.sensor.blur_px = s.sensor.blur_px;
  // The scenario's 100 means "no JPEG round trip"; the renderer's off is 0.
  o.sensor.jpeg_quality = s.sensor.jpeg_quality >= 100 ? 0 : s.sensor.jpeg_quality;
  o.sensor.exposure = s.sensor.exposure;
  o.Validate();
  return o;
}

void WriteText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  out.close();
  if (!out) throw RunError(fmt::format("cannot write {}", path.string()));
}

nlohmann::json BoxJson(const BoxPx& b) { return {b.left, b.top, b.width, b.height}; }
template <typename M>
nlohmann::json MatrixJson(const M& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (int r = 0; r < m.rows(); ++r) {
    nlohmann::json row = nlohmann::json::array();
    for (int c = 0; c < m.cols(); ++c) row.push_back(m(r, c));
    rows.push_back(row);
  }
  return rows;
}
nlohmann::json VecJson(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

nlohmann::json FrameJson(const FrameGroundTruth& f) {
  const CameraIntrinsics& k = f.camera.intrinsics;
  nlohmann::json frame;
  frame["frame"] = f.frame;
  frame["camera"] = {{"width_px", k.width_px},
                     {"height_px", k.height_px},
                     {"K", MatrixJson(k.K())},
                     {"position_m", VecJson(f.camera.pose.position_m)},
                     {"world_from_camera", MatrixJson(f.camera.pose.world_from_camera)}};
  frame["image_from_ground"] = MatrixJson(f.image_from_ground);
  nlohmann::json objects = nlohmann::json::array();
  for (const GroundTruthObject& o : f.objects) {
    objects.push_back({{"id", Value(o.id)},
                       {"in_frame", o.in_frame},
                       {"amodal_box", BoxJson(o.amodal_box)},
                       {"visible_box", BoxJson(o.visible_box)},
                       {"visible_fraction", o.visible_fraction},
                       {"truncation", o.truncation},
                       {"pixels_visible", o.pixels_visible},
                       {"pixels_total", o.pixels_total},
                       {"position_m", VecJson(o.position_m)},
                       {"heading_deg", o.heading_deg},
                       {"dimensions_m", VecJson(o.dimensions_m)}});
  }
  frame["objects"] = std::move(objects);
  return frame;
}

}  // namespace

Command AddRenderCommand(CLI::App& parent) {
  struct Options {
    std::string file;
    std::string out;
    std::vector<std::string> sets;
    std::string cache;
    int sheet_frames = 16;
  };
  auto options = std::make_shared<Options>();
  CLI::App* app = parent.add_subcommand(
      "render", "Render a scenario's frames with pixel-exact ground truth into --out");
  app->add_option("scenario", options->file, "Scenario YAML file")->required();
  app->add_option("--out", options->out, "Output folder (created if missing; files replaced)")
      ->required();
  app->add_option("--set", options->sets,
                  "Override a key, e.g. --set world.sun.azimuth_deg=90 (repeatable)");
  app->add_option("--cache", options->cache,
                  "Frame cache folder: frames already rendered for the same pixels are read, "
                  "new ones stored (keyed by a hash of everything that affects pixels)");
  app->add_option("--sheet-frames", options->sheet_frames,
                  "Frames sampled into contact_sheet.png")
      ->check(CLI::Range(1, 100))
      ->capture_default_str();
  return {app, [options] {
            std::vector<scenarios::Override> overrides;
            for (const auto& s : options->sets) overrides.push_back(scenarios::ParseOverride(s));
            const scenarios::Scenario scenario =
                scenarios::LoadScenarioFile(options->file, overrides);
            const renderer::RendererOptions ropts = RendererOptionsOf(scenario);
            const uint64_t seed = scenario.seeds.renderer;
            const std::filesystem::path out(options->out);
            std::error_code ec;
            std::filesystem::create_directories(out / "frames", ec);
            if (ec) {
              throw InputError(fmt::format("--out {}: cannot create folder: {}", out.string(),
                                           ec.message()));
            }
            // The cache holds colour frames and ground truth only.
            std::unique_ptr<renderer::FrameCache> cache;
            if (!options->cache.empty() && !ropts.output_depth && !ropts.output_instance_ids) {
              cache = std::make_unique<renderer::FrameCache>(
                  options->cache, renderer::PixelHash(scenario.world, ropts, seed));
            }
            std::unique_ptr<renderer::SceneRenderer> scene;  // created on the first miss
            const int frames = scenario.world.frames;
            const int sheet_n = std::min(options->sheet_frames, frames);
            std::vector<int> sheet_frames;
            for (int i = 0; i < sheet_n; ++i) {
              sheet_frames.push_back(sheet_n == 1 ? 0 : i * (frames - 1) / (sheet_n - 1));
            }
            std::vector<renderer::RenderedFrame> sheet;
            std::string mot;
            nlohmann::json json_frames = nlohmann::json::array();
            int cached = 0;
            const auto start = std::chrono::steady_clock::now();
            for (int f = 0; f < frames; ++f) {
              std::optional<renderer::RenderedFrame> frame;
              if (cache) frame = cache->Load(f);
              if (frame) {
                ++cached;
              } else {
                if (!scene) {
                  scene = renderer::SceneRenderer::Create(scenario.world, ropts, Rng(seed));
                }
                frame = scene->Render(f);
                if (cache) cache->Store(*frame);
              }
              const std::string stem = fmt::format("{:06d}", f + 1);
              renderer::WritePng(frame->rgb, (out / "frames" / (stem + ".png")).string());
              if (frame->depth) {
                renderer::WriteDepthPng(*frame->depth,
                                        (out / "frames" / (stem + "_depth.png")).string());
              }
              if (frame->instance_ids) {
                renderer::WriteInstancePng(*frame->instance_ids,
                                           (out / "frames" / (stem + "_ids.png")).string());
              }
              for (const GroundTruthObject& o : frame->ground_truth.objects) {
                if (!o.in_frame) continue;
                const BoxPx& b = o.amodal_box;
                mot += fmt::format("{},{},{:.3f},{:.3f},{:.3f},{:.3f},1,1,{:.4f}\n", f + 1,
                                   Value(o.id), b.left + 1.0, b.top + 1.0, b.width, b.height,
                                   o.visible_fraction);
              }
              json_frames.push_back(FrameJson(frame->ground_truth));
              if (std::find(sheet_frames.begin(), sheet_frames.end(), f) != sheet_frames.end()) {
                frame->depth.reset();
                frame->instance_ids.reset();
                sheet.push_back(std::move(*frame));
              }
            }
            const double seconds =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            WriteText(out / "gt.txt", mot);
            nlohmann::json root;
            root["format"] = "hcpf-gt/1";
            root["scenario"] = scenario.name;
            root["source"] = "rendered";
            root["conventions"] = {
                {"frame", "0-based here; MOT files and frame PNGs are 1-based"},
                {"boxes", "[left, top, width, height] in pixels, pixel (0,0) covers [0,1)x[0,1)"},
                {"visible_fraction",
                 "pixel-exact: pixels_visible / pixels_total from the renderer's instance-id "
                 "pass (not MOTChallenge's box-overlap heuristic); gt.txt's visibility column"},
                {"world", "x east, y north, z up, metres"},
                {"camera", "OpenCV: x right, y down, z forward; world_from_camera columns = camera axes"},
                {"image_from_ground", "homography of the plane z = 0 to homogeneous pixels"},
            };
            if (scene) {
              root["gl"] = {{"backend", scene->gl_info().backend},
                            {"renderer", scene->gl_info().renderer},
                            {"version", scene->gl_info().version}};
            }
            root["frames"] = std::move(json_frames);
            WriteText(out / "gt.json", root.dump(1) + "\n");
            WriteText(out / "seqinfo.ini",
                      fmt::format("[Sequence]\nname={}\nimDir=frames\nframeRate={}\nseqLength={}\n"
                                  "imWidth={}\nimHeight={}\nimExt=.png\n",
                                  scenario.name, scenario.world.fps, frames,
                                  scenario.world.camera.width_px, scenario.world.camera.height_px));
            renderer::WritePng(renderer::MakeContactSheet(sheet),
                               (out / "contact_sheet.png").string());
            spdlog::info("rendered \"{}\": {} frames ({} from cache) in {:.2f} s into {}",
                         scenario.name, frames, cached, seconds, out.string());
            return 0;
          }};
}

}  // namespace hcpf::cli
