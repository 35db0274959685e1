#include "rendering_check.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>

#include "detection_cache.h"
#include "hcpf/config/file_lookup.h"
#include "hcpf/config/yaml_leaves.h"
#include "hcpf/core/fields.h"
#include "hcpf/core/text_file.h"
#include "hcpf/renderer/renderer.h"
#include "hcpf/scenarios/frames.h"
#include "hcpf/scenarios/models.h"

namespace hcpf::scenarios::internal {

namespace fs = std::filesystem;

namespace {

constexpr const char* kRenderingNeeds =
    "a folder of `hcpf render` or of a rendered `hcpf run` (holding manifest.json)";

// Keys that cannot change what the frames show: the detector's and the
// tracker's side, names, and the renderer's output switches.
bool ShapesNoPixel(const std::string& key) {
  for (const char* prefix : {"observation.", "tracker.", "metrics.", "seeds.observation",
                             "seeds.tracker", "renderer.write_", "renderer.backend"}) {
    if (key.rfind(prefix, 0) == 0) return true;
  }
  return key == "name" || key == "description";
}

// ", where the scenarios differ: a (there x, here y), ..." from the
// rendering's scenario.resolved.yaml, or why the keys do not tell.
std::string WhereTheyDiffer(const fs::path& folder, const Scenario& s,
                            const nlohmann::json& manifest) {
  const fs::path resolved = folder / "scenario.resolved.yaml";
  std::error_code ec;
  if (!fs::is_regular_file(resolved, ec)) {
    return "; that folder has no scenario.resolved.yaml to compare keys with";
  }
  std::vector<config::LeafDifference> differ;
  try {
    differ = config::DifferingLeaves(
        ReadInputFile(resolved.string(), "a resolved scenario", 1u << 26), ToResolvedYaml(s));
  } catch (const std::exception& e) {
    return fmt::format("; its scenario.resolved.yaml could not be compared ({})", e.what());
  }
  std::erase_if(differ, [](const config::LeafDifference& d) { return ShapesNoPixel(d.key); });
  if (differ.empty()) {
    const std::string version =
        manifest.contains("hcpf_version") && manifest["hcpf_version"].is_string()
            ? manifest["hcpf_version"].get<std::string>()
            : "unknown";
    return fmt::format(
        "; the scenarios are alike in every key that shapes pixels, so a model file's content "
        "or the renderer differs (that folder: hcpf {})",
        version);
  }
  constexpr size_t kShown = 6;
  std::string text = "; the scenarios differ at ";
  for (size_t i = 0; i < std::min(differ.size(), kShown); ++i) {
    const config::LeafDifference& d = differ[i];
    if (i > 0) text += ", ";
    text += fmt::format("{} (there {}, here {})", d.key, d.first.value_or("absent"),
                        d.second.value_or("absent"));
  }
  if (differ.size() > kShown) text += fmt::format(" and {} more keys", differ.size() - kShown);
  return text;
}

// The manifest.json of a rendering folder; throws InputError.
nlohmann::json ReadManifest(const fs::path& folder) {
  const std::string path = (folder / "manifest.json").string();
  try {
    return nlohmann::json::parse(
        ReadInputFile(path, "a manifest.json (observation.file.rendering)", 1u << 26));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(SourceLocation{path, 1, 1, ""}, "a manifest.json in JSON", e.what());
  }
}

}  // namespace

std::string ResolveRenderingFolder(const std::string& written, const std::string& scenario_file,
                                   const SourceLocation& where) {
  const bool manifest = fs::path(written).filename() == "manifest.json";
  const std::string file = manifest ? written : (fs::path(written) / "manifest.json").string();
  try {
    return fs::path(ResolveModelPath(file, scenario_file, where, kRenderingNeeds))
        .parent_path()
        .string();
  } catch (const InputError&) {
    // No folder of that name holds a manifest: a file of that name is said
    // to be one (a bad-input audit: "found "afile/manifest.json", which
    // does not exist"). Only then: a file of the name elsewhere on the
    // search path must not hide a folder that is found (a review).
    if (!manifest) {
      if (const auto found =
              config::FindFile(written, fs::path(scenario_file).parent_path().string(), nullptr)) {
        throw InputError(where, kRenderingNeeds,
                         fmt::format("\"{}\", a file ({}), not a folder", written, *found));
      }
    }
    throw;
  }
}

void CheckRendering(Scenario* s) {
  DetectionFileOptions& f = s->observation.file;
  if (f.rendering.empty() && f.pixel_hash.empty()) return;
  const std::string ours = PixelHashOf(*s);
  const std::string expected = fmt::format(
      "this scenario's frames, whose pixel hash is {} (a det.txt made on the frames of `hcpf "
      "render` of this scenario)",
      ours);
  if (!f.rendering.empty()) {
    const fs::path folder(f.rendering);
    const nlohmann::json manifest = ReadManifest(folder);
    if (!manifest.is_object() || !manifest.contains("pixel_hash") ||
        !manifest["pixel_hash"].is_string()) {
      FailOption("observation.file", "rendering",
                 "a folder whose manifest.json names its frames' pixel_hash (written by `hcpf "
                 "render` and rendered runs of this version: render again)",
                 fmt::format("{}, whose manifest has no pixel_hash", f.rendering));
    }
    const std::string theirs = manifest["pixel_hash"].get<std::string>();
    if (theirs != ours) {
      FailOption("observation.file", "rendering", expected,
                 fmt::format("the frames of another rendering: {} has pixel hash {}{}", f.rendering,
                             theirs, WhereTheyDiffer(folder, *s, manifest)));
    }
  }
  // A hash that is none (a bad-input audit: "zz" was "the frames of another
  // rendering").
  if (!f.pixel_hash.empty() && !internal::IsDigestHex(f.pixel_hash)) {
    FailOption("observation.file", "pixel_hash",
               "a pixel hash: 32 lowercase hexadecimal digits, as a manifest.json's pixel_hash",
               "\"" + f.pixel_hash + "\"");
  }
  if (!f.pixel_hash.empty() && f.pixel_hash != ours) {
    FailOption("observation.file", "pixel_hash", expected,
               fmt::format("\"{}\", the frames of another rendering", f.pixel_hash));
  }
  f.pixel_hash = ours;
}

std::string RendererDifference(const std::string& rendering, const SceneFrames& scene) {
  nlohmann::json manifest;
  try {
    manifest = ReadManifest(rendering);
  } catch (const Error& e) {
    return fmt::format("the GL renderer of {} is unknown: {}", rendering, e.what());
  }
  // RendererLine's "<platform>; <vendor>; <renderer>; <version>" of each side.
  std::vector<std::string> there;
  if (manifest.is_object()) {
    const auto gl = manifest.find("gl_renderer");
    if (gl != manifest.end() && gl->is_object()) {
      renderer::GlInfo info;
      info.platform = gl->value("platform", "");
      info.vendor = gl->value("vendor", "");
      info.renderer = gl->value("renderer", "");
      info.version = gl->value("version", "");
      there.push_back(renderer::RendererLine(info));
    }
    const auto cached = manifest.find("frame_cache_renderers");
    if (cached != manifest.end() && cached->is_array()) {
      for (const auto& line : *cached) {
        if (line.is_string()) there.push_back(line.get<std::string>());
      }
    }
  }
  std::vector<std::string> here = scene.cache_renderers;
  if (scene.gl) here.push_back(renderer::RendererLine(*scene.gl));
  std::vector<std::string> unseen;
  for (const std::string& line : here) {
    const bool known = std::find(there.begin(), there.end(), line) != there.end();
    if (!known && std::find(unseen.begin(), unseen.end(), line) == unseen.end()) {
      unseen.push_back(line);
    }
  }
  if (there.empty() || unseen.empty()) return "";
  return fmt::format(
      "the det.txt's frames ({}) were rendered by {}, this run's by {}: the pixel hash leaves "
      "the GL renderer out, so the pixels the detections were made on may differ slightly from "
      "those tracked and scored here",
      rendering, fmt::join(there, " | "), fmt::join(unseen, " | "));
}

std::optional<PixelComparison> ComparePixels(const std::string& rendering,
                                             const SceneFrames& scene) {
  if (scene.frame_digests.empty()) return std::nullopt;
  nlohmann::json manifest;
  try {
    manifest = ReadManifest(rendering);
  } catch (const Error&) {
    return std::nullopt;  // RendererDifference says why
  }
  if (!manifest.is_object()) return std::nullopt;
  const auto there = manifest.find("frame_digests");
  if (there == manifest.end() || !there->is_array() || there->empty()) return std::nullopt;
  const std::vector<std::string>& here = scene.frame_digests;
  PixelComparison c;
  c.frames = static_cast<int>(std::max(here.size(), there->size()));
  for (int f = 0; f < c.frames; ++f) {
    const auto i = static_cast<size_t>(f);
    const bool same = i < here.size() && i < there->size() && (*there)[i].is_string() &&
                      (*there)[i].get<std::string>() == here[i];
    if (!same) c.differing.push_back(f);
  }
  return c;
}

}  // namespace hcpf::scenarios::internal
