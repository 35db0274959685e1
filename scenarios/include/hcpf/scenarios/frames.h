#pragma once
// Where a run's ground truth (and pixels) come from: the analytic world model
// (detection level, `observation.source: simulated`) or the renderer
// (`observation.source: rendered`, pixel-exact visibility). Rendered frames are
// cached on disk under a hash of everything that affects pixels
// (renderer::PixelHash), so runs that differ only in tracker or observation
// settings render once.

#include <atomic>
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "hcpf/core/ground_truth.h"
#include "hcpf/renderer/renderer.h"
#include "hcpf/scenarios/scenario.h"

namespace hcpf::scenarios {

// The renderer's options from the scenario's `renderer.*` and `sensor.*` keys.
renderer::RendererOptions RendererOptionsOf(const Scenario& scenario);

// The identity of the scenario's frames: renderer::PixelHash of its world,
// its RendererOptionsOf and its renderer seed (the frame cache's folder, a
// rendered run's `pixel_hash`).
std::string PixelHashOf(const Scenario& scenario);

// $HCPF_CACHE_DIR, else $XDG_CACHE_HOME/hcpf/frames, else $HOME/.cache/hcpf/frames.
std::string DefaultFrameCacheDir();
// Where DefaultFrameCacheDir() came from, as an error names it:
// "HCPF_CACHE_DIR (environment)", "XDG_CACHE_HOME (environment)", "HOME
// (environment)", or "the default" (the current folder's .hcpf-cache).
std::string DefaultFrameCacheSource();

// Creates a frame cache folder (and its parents), or throws RunError naming
// it and the ways to another (--cache DIR, HCPF_CACHE_DIR, --no-cache): the
// default's $HOME may be absent or read-only, as for a service user.
void MakeFrameCacheFolder(const std::filesystem::path& dir);

struct FrameSourceOptions {
  bool render = false;  // render even when the scenario is at detection level
  // Rendered frames: keep them where a FrameReader reads them back later
  // (an overlay video) without holding them in memory. The frame cache holds
  // them when there is one; else they are stored here, compressed as the
  // cache stores them (a frame cache of the run's own, which the caller
  // removes). "" = neither.
  std::string spool_dir;
  std::string cache_dir;  // "" = no cache
  bool show_progress = true;
  // Rendered frames: called with every frame, rendered or read from the cache,
  // in frame order (to write images without keeping them all).
  std::function<void(const renderer::RenderedFrame&)> on_frame;
  // Rendered frames: called with every frame on one of the `workers` threads,
  // several frames at once in no set order, after its sensor effects and
  // before on_frame sees it (which sees what it wrote). It must touch only
  // the frame and what belongs to that frame alone: its image files.
  std::function<void(const renderer::RenderedFrame&)> on_frame_work;
  // With `render`: return the analytic ground truth even though frames are
  // rendered (a detection-level `hcpf run` that writes its frames keeps the
  // truth its observations come from).
  bool analytic_truth = false;
  // Rendered frames: threads that apply the sensor effects (several frames at
  // once) and threads that store frames in the cache; on_frame still sees
  // every frame in order. The frames are the same for any value (each frame's
  // noise has its own stream). `hcpf run --threads`.
  int workers = 1;
};

struct SceneFrames {
  std::vector<FrameGroundTruth> truth;  // one per frame
  bool rendered = false;                // pixel-exact ground truth
  // When frames were rendered (or read from the cache): renderer::PixelHash
  // of the scene, the frames' identity (manifest `pixel_hash`).
  std::string pixel_hash;
  int frames_rendered = 0;
  int frames_from_cache = 0;
  std::optional<renderer::GlInfo> gl;  // when a GL context was created
  // With frames from the cache: the GL renderers noted there
  // (FrameCache::Renderers; empty for a cache from before they were noted).
  std::vector<std::string> cache_renderers;
  // When rendered: each frame's XXH3-128 of its size and colour pixels after
  // the sensor effects (32 hex digits), in frame order: the pixels
  // themselves, where pixel_hash is what shapes them (manifest
  // `frame_digests`; a det.txt's run compares them with its rendering's).
  std::vector<std::string> frame_digests;
  // With FrameSourceOptions::spool_dir: the frame cache root that holds every
  // frame under pixel_hash (the run's frame cache, or the spool), and which.
  std::string readback_root;
  bool readback_is_spool = false;
};

SceneFrames ProduceFrames(const Scenario& scenario, const FrameSourceOptions& options);

// Frames produced with FrameSourceOptions::spool_dir, read back one at a time
// from `frames.readback_root` (the frame cache, or the run's spool): frame
// f's colour image, checked against frames.frame_digests[f]. A frame the
// folder no longer holds, or holds with other pixels (a frame cache pruned
// or rewritten while the run ran), is rendered again; Finish() then warns
// once, with how many were and how many of those still differ. It must not
// outlive `scenario`.
class FrameReader {
 public:
  FrameReader(const Scenario& scenario, const SceneFrames& frames);
  ~FrameReader();
  FrameReader(const FrameReader&) = delete;
  FrameReader& operator=(const FrameReader&) = delete;

  RgbImage Read(int frame);
  int rendered_again() const { return rendered_again_; }
  // The warning (spdlog) when any frame was rendered again.
  void Finish() const;

 private:
  const Scenario& scenario_;
  renderer::FrameCache store_;
  std::vector<std::string> digests_;
  std::string source_;                                 // "the frame cache DIR" or "the spool DIR"
  std::unique_ptr<renderer::SceneRenderer> renderer_;  // created on the first miss
  int rendered_again_ = 0;
  int differing_ = 0;
};
// A frame's entry of SceneFrames::frame_digests (the manifests'
// `frame_digests`): XXH3-128 of its width, height and RGB pixels, as 32
// lowercase hex digits.
std::string FrameDigest(const RgbImage& image);

// Writes a rendered frame's images into `frames_dir` as NNNNNN.png (when
// `colour`), NNNNNN_depth.png (in units of `depth_unit_mm`) and
// NNNNNN_ids.png (when the frame has them), NNNNNN = frame + 1: the layout
// of `hcpf render` and of `hcpf run` with renderer.write_frames /
// write_depth / write_instance_ids. Adds to `*saturated` (any thread) the
// depth pixels beyond the PNG's 65535 units.
void WriteFrameImages(const renderer::RenderedFrame& frame, const std::string& frames_dir,
                      bool colour, double depth_unit_mm, std::atomic<int64_t>* saturated);

// The warning for `saturated` depth pixels written 65535 (WriteFrameImages);
// "" for none.
std::string DepthSaturationNote(int64_t saturated, double depth_unit_mm);

}  // namespace hcpf::scenarios
