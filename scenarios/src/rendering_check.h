#pragma once
// observation.file.rendering / pixel_hash: a det.txt belongs to one rendering
// (renderer::PixelHash), checked at load time so `hcpf validate` refuses what
// `hcpf run` would, before a tracker reads boxes of another scene.

#include <optional>
#include <string>
#include <vector>

#include "hcpf/core/error.h"
#include "hcpf/scenarios/frames.h"
#include "hcpf/scenarios/scenario.h"

namespace hcpf::scenarios::internal {

// The folder `written` names (`hcpf render`'s or a rendered run's), found like
// a model file through its manifest.json; `written` may name the manifest
// itself. Returns the folder's canonical absolute path; throws InputError at
// `where` when no such manifest exists.
std::string ResolveRenderingFolder(const std::string& written, const std::string& scenario_file,
                                   const SourceLocation& where);

// With `rendering` or `pixel_hash` set in s->observation.file: compares the
// frames the det.txt was made on with those `s` renders; throws InputError at
// the key whose hash differs (thrown by FailOption: relocate it), naming both
// hashes and, from the rendering's scenario.resolved.yaml, the keys that
// differ. Sets pixel_hash (the resolved YAML writes it).
void CheckRendering(Scenario* s);

// After the run's frames are made: a warning when they came from a GL
// renderer that made none of `rendering`'s frames (its manifest's
// gl_renderer and frame_cache_renderers), whose pixels may differ slightly
// though the pixel hash (which leaves the GL renderer out) is the same; ""
// when they agree, or when either side does not say.
std::string RendererDifference(const std::string& rendering, const SceneFrames& scene);

// The run's frames against `rendering`'s, pixel by pixel: its manifest's
// frame_digests against scene.frame_digests, frame by frame. nullopt when
// either side has none (a rendering written before they were), so nothing
// was compared. A frame only one side has counts as differing.
struct PixelComparison {
  int frames = 0;              // frames compared: the larger count
  std::vector<int> differing;  // 0-based frames whose pixels differ
};
std::optional<PixelComparison> ComparePixels(const std::string& rendering,
                                             const SceneFrames& scene);

}  // namespace hcpf::scenarios::internal
