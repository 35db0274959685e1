#include "hcpf/scenarios/frames.h"

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <spdlog/spdlog.h>

#include <algorithm>
#include <cstdlib>
#include <memory>

#include "detection_cache.h"
#include "hcpf/core/check.h"
#include "hcpf/core/error.h"
#include "hcpf/core/parallel.h"
#include "hcpf/core/text_file.h"
#include "hcpf/renderer/image_io.h"
#include "hcpf/scenarios/cache.h"
#include "hcpf/scenarios/progress.h"

namespace hcpf::scenarios {

renderer::RendererOptions RendererOptionsOf(const Scenario& s) {
  renderer::RendererOptions o;
  o.backend = renderer::ParseGlBackend(s.renderer.backend);
  o.shadows = s.world.sun.shadows;
  o.shadow_map_size = s.renderer.shadow_map_size;
  o.pcf_radius = s.renderer.pcf_radius;
  o.output_depth = s.renderer.write_depth;
  o.output_instance_ids = s.renderer.write_instance_ids;
  o.sensor.noise_sigma = s.sensor.noise_sigma;
  o.sensor.blur_px = s.sensor.blur_px;
  // The scenario's 100 means "no JPEG round trip"; the renderer's "off" is 0.
  o.sensor.jpeg_quality = s.sensor.jpeg_quality >= 100 ? 0 : s.sensor.jpeg_quality;
  o.sensor.exposure = s.sensor.exposure;
  o.Validate();
  return o;
}

std::string PixelHashOf(const Scenario& scenario) {
  return renderer::PixelHash(scenario.world, RendererOptionsOf(scenario), scenario.seeds.renderer);
}

namespace {

// The default frame cache folder and where it came from, in one order for
// both (a review: the order was written twice).
std::pair<std::string, std::string> DefaultFrameCache() {
  if (const char* dir = std::getenv("HCPF_CACHE_DIR"); dir != nullptr && *dir != '\0') {
    return {dir, "HCPF_CACHE_DIR (environment)"};
  }
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg != nullptr && *xdg != '\0') {
    return {std::string(xdg) + "/hcpf/frames", "XDG_CACHE_HOME (environment)"};
  }
  if (const char* home = std::getenv("HOME"); home != nullptr && *home != '\0') {
    return {std::string(home) + "/.cache/hcpf/frames", "HOME (environment)"};
  }
  return {".hcpf-cache/frames", "the default"};
}

}  // namespace

std::string DefaultFrameCacheDir() { return DefaultFrameCache().first; }

std::string DefaultFrameCacheSource() { return DefaultFrameCache().second; }

void MakeFrameCacheFolder(const std::filesystem::path& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    throw RunError(fmt::format(
        "cannot create frame cache {}: {} (give a writable frame cache folder with --cache DIR or "
        "HCPF_CACHE_DIR, or render without one: --no-cache)",
        dir.string(), ec.message()));
  }
}

SceneFrames ProduceFrames(const Scenario& scenario, const FrameSourceOptions& options) {
  SceneFrames out;
  const int frames = scenario.world.frames;
  out.truth.reserve(frames);
  const bool render = options.render || scenario.observation.source == ObservationSource::kRendered;
  if (!render) {
    // Seconds for hundreds of packed targets over thousands of frames.
    Progress progress("ground truth", frames, options.show_progress);
    for (int f = 0; f < frames; ++f) {
      out.truth.push_back(ComputeGroundTruth(scenario.world, f));
      progress.Advance();
    }
    progress.Finish();
    return out;
  }
  out.rendered = !options.analytic_truth;
  const renderer::RendererOptions ropts = RendererOptionsOf(scenario);
  out.pixel_hash = PixelHashOf(scenario);
  // Depth and instance images are not cached (FrameCache holds colour + truth).
  std::unique_ptr<renderer::FrameCache> cache;
  if (!options.cache_dir.empty() && !ropts.output_depth && !ropts.output_instance_ids) {
    cache = std::make_unique<renderer::FrameCache>(options.cache_dir, out.pixel_hash);
    MarkUsed(cache->dir());  // `hcpf cache --max-size` prunes the scenes used least recently
  }
  // What the folder holds, for `hcpf cache` to list (its name says none of it).
  const SceneNote note{.scenario = scenario.name,
                       .seed = scenario.seed,
                       .frames = frames,
                       .width_px = scenario.world.camera.width_px,
                       .height_px = scenario.world.camera.height_px};
  if (cache) NoteScene(cache->dir(), note);  // a folder cached before notes were kept
  // Misses are stored on a worker thread while the next frame renders.
  std::unique_ptr<renderer::FrameCacheWriter> cache_writer;
  const int workers = std::max(1, options.workers);
  // Four frames may wait for one writer; with several, one each (memory: an
  // 800 x 600 frame is 1.4 MB).
  const auto writer_of = [workers](renderer::FrameCache store) {
    return std::make_unique<renderer::FrameCacheWriter>(std::move(store), workers > 1 ? 1 : 4,
                                                        workers);
  };
  // The spool (FrameSourceOptions::spool_dir): every frame stored on a worker
  // thread as the cache stores its misses, where no frame cache keeps them.
  std::unique_ptr<renderer::FrameCacheWriter> spool_writer;
  if (!options.spool_dir.empty()) {
    out.readback_root = cache ? options.cache_dir : options.spool_dir;
    out.readback_is_spool = !cache;
    if (!cache) spool_writer = writer_of(renderer::FrameCache(options.spool_dir, out.pixel_hash));
  }
  // A spool's failure names the run's folder, not a frame cache.
  const auto spool_failed = [&options](const RunError& e) {
    return RunError(fmt::format("cannot spool the video's frames in {} (the run's folder): {}",
                                options.spool_dir, e.what()));
  };
  std::unique_ptr<renderer::SceneRenderer> scene;  // created on the first cache miss
  // "frames", not "render": from a warm cache nothing is rendered (an audit
  // saw "render 240/240" for frames read from the cache).
  Progress progress("frames", frames, options.show_progress);
  // Three stages: this thread renders frame f + 1 (or reads it from the
  // cache) while `finisher` applies the sensor effects and on_frame_work to
  // frame f (and, with several workers, to the frames before it, each on its
  // own thread) and then, one frame at a time in frame order, finishes it:
  // the cache write, on_frame, the truth and the image. On llvmpipe, whose readback waits for
  // the frame, this is the overlap there is (the sensor effects and a
  // detector's work run beside the rasteriser); on a GPU the GL work runs
  // beside all of them. Each frame's noise has its own stream, so the bytes
  // are those of Render(f) frame after frame for any number of workers.
  // Declared last: destroyed first, it waits for its jobs before what they
  // use goes.
  OrderedWorkers finisher(workers);
  const auto finish = [&](renderer::RenderedFrame frame, bool rendered) {
    auto shared = std::make_shared<renderer::RenderedFrame>(std::move(frame));
    finisher.Post(
        [&, shared, rendered] {
          if (rendered) scene->ApplySensor(*shared);
          if (options.on_frame_work) options.on_frame_work(*shared);
        },
        [&, shared, rendered] {
          renderer::RenderedFrame& frame = *shared;
          if (rendered && cache) {
            if (!cache_writer) cache_writer = writer_of(*cache);
            cache_writer->Submit(frame);  // a copy: the frame is used below
          }
          if (spool_writer) {
            // The colour and truth alone (what a cache file holds): a frame
            // spooled here may carry depth and instance images too.
            renderer::RenderedFrame colour;
            colour.frame = frame.frame;
            colour.rgb = frame.rgb;
            colour.ground_truth = frame.ground_truth;
            try {
              spool_writer->Submit(std::move(colour));
            } catch (const RunError& e) {
              throw spool_failed(e);
            }
          }
          if (options.on_frame) options.on_frame(frame);
          out.frame_digests.push_back(FrameDigest(frame.rgb));
          out.truth.push_back(options.analytic_truth
                                  ? ComputeGroundTruth(scenario.world, frame.frame)
                                  : std::move(frame.ground_truth));
          progress.Advance();
        });
  };
  const auto submit = [&](int f) {
    if (!scene) {
      scene = renderer::SceneRenderer::Create(scenario.world, ropts, Rng(scenario.seeds.renderer));
      out.gl = scene->gl_info();
      if (cache) {
        MakeFrameCacheFolder(cache->dir());  // its first write
        NoteScene(cache->dir(), note);
        RemoveStaleTempFiles(cache->dir());  // what killed writes left there
        cache->NoteRenderer(*out.gl);        // before any frame of it is stored
      }
    }
    scene->Submit(f);
  };
  bool submitted = false;  // frame f was submitted by the previous step
  for (int f = 0; f < frames; ++f) {
    std::optional<renderer::RenderedFrame> frame;
    if (cache && !submitted) frame = cache->Load(f);
    const bool rendered = !frame;
    if (frame) {
      ++out.frames_from_cache;
    } else {
      if (!submitted) submit(f);
      frame = scene->CollectClean();
      HCPF_CHECK(frame->frame == f) << "collected frame " << frame->frame << ", expected " << f;
      ++out.frames_rendered;
    }
    finish(std::move(*frame), rendered);
    submitted = f + 1 < frames && !(cache && cache->Contains(f + 1));
    if (submitted) submit(f + 1);
  }
  finisher.Wait();
  if (cache_writer) cache_writer->Finish();
  if (spool_writer) {
    try {
      spool_writer->Finish();
    } catch (const RunError& e) {
      throw spool_failed(e);
    }
  }
  progress.Finish();
  if (out.frames_from_cache > 0) {
    spdlog::log(RunSummaryLevel(options.show_progress),
                "{} of {} frames read from the frame cache {}", out.frames_from_cache, frames,
                cache->dir().string());
    out.cache_renderers = cache->Renderers();
    if (out.cache_renderers.size() > 1) {
      spdlog::warn(
          "the frame cache {} holds frames of {} GL renderers ({}), whose pixels may differ: "
          "this run's frames may mix them. Keep each machine's frames apart with --cache, or "
          "delete that folder to render them again",
          cache->dir().string(), out.cache_renderers.size(), fmt::join(out.cache_renderers, " | "));
    }
  }
  return out;
}

FrameReader::FrameReader(const Scenario& scenario, const SceneFrames& frames)
    : scenario_(scenario),
      store_(frames.readback_root, frames.pixel_hash),
      digests_(frames.frame_digests),
      source_(fmt::format("the {} {}", frames.readback_is_spool ? "spool" : "frame cache",
                          store_.dir().string())) {
  HCPF_CHECK(!frames.readback_root.empty()) << "frames produced without a spool_dir";
}

FrameReader::~FrameReader() = default;

RgbImage FrameReader::Read(int f) {
  HCPF_CHECK(f >= 0 && static_cast<size_t>(f) < digests_.size())
      << "frame " << f << " of " << digests_.size();
  const std::string& digest = digests_[static_cast<size_t>(f)];
  std::optional<renderer::RenderedFrame> frame = store_.Load(f);
  if (frame && FrameDigest(frame->rgb) == digest) return std::move(frame->rgb);
  if (!renderer_) {
    renderer_ = renderer::SceneRenderer::Create(scenario_.world, RendererOptionsOf(scenario_),
                                                Rng(scenario_.seeds.renderer));
  }
  renderer::RenderedFrame again = renderer_->Render(f);
  ++rendered_again_;
  if (FrameDigest(again.rgb) != digest) ++differing_;
  return std::move(again.rgb);
}

void FrameReader::Finish() const {
  if (rendered_again_ == 0) return;
  spdlog::warn(
      "{} of {} frames were gone from {}, or held other pixels there (pruned or rewritten "
      "while the run ran?): rendered again{}",
      rendered_again_, digests_.size(), source_,
      differing_ == 0 ? std::string(", each the run's pixels")
                      : fmt::format("; {} of them differ from the run's frames (another GL "
                                    "renderer?), and the video shows them as rendered now",
                                    differing_));
}

std::string DepthSaturationNote(int64_t saturated, double depth_unit_mm) {
  if (saturated == 0) return "";
  const double next = depth_unit_mm * 10.0;
  return fmt::format(
      "renderer.write_depth: {} pixel(s) lie beyond the depth PNG's 65535 units of "
      "renderer.depth_unit_mm {:g} ({:g} m) and are written 65535; renderer.depth_unit_mm: {:g} "
      "holds {:g} m",
      saturated, depth_unit_mm, 65.535 * depth_unit_mm, next, 65.535 * next);
}

std::string FrameDigest(const RgbImage& image) {
  return internal::DigestHex(internal::PixelDigest(image));
}

void WriteFrameImages(const renderer::RenderedFrame& frame, const std::string& frames_dir,
                      bool colour, double depth_unit_mm, std::atomic<int64_t>* saturated) {
  const std::string stem = fmt::format("{}/{:06d}", frames_dir, frame.frame + 1);
  if (colour) renderer::WritePng(frame.rgb, stem + ".png");
  if (frame.depth) {
    const int64_t n = renderer::WriteDepthPng(*frame.depth, stem + "_depth.png", depth_unit_mm);
    if (saturated != nullptr) *saturated += n;
  }
  if (frame.instance_ids) renderer::WriteInstancePng(*frame.instance_ids, stem + "_ids.png");
}

}  // namespace hcpf::scenarios
