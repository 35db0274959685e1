#include <fmt/format.h>

#include "hcpf/core/error.h"
#include "hcpf/renderer/renderer.h"

namespace hcpf::renderer {
namespace {

[[noreturn]] void Bad(const std::string& key, const std::string& expected,
                      const std::string& found) {
  throw InputError(SourceLocation{.key = key}, expected, found);
}

}  // namespace

void SensorOptions::Validate() const {
  if (!(exposure > 0.0 && exposure <= 16.0)) {
    Bad("sensor.exposure", "a gain in (0, 16]", fmt::format("{}", exposure));
  }
  if (!(blur_px >= 0.0 && blur_px <= 20.0)) {
    Bad("sensor.blur_px", "a sigma in [0, 20] pixels", fmt::format("{}", blur_px));
  }
  if (!(noise_sigma >= 0.0 && noise_sigma <= 100.0)) {
    Bad("sensor.noise_sigma", "a std. dev. in [0, 100] grey levels", fmt::format("{}", noise_sigma));
  }
  if (jpeg_quality < 0 || jpeg_quality > 100) {
    Bad("sensor.jpeg_quality", "0 (off) or a quality in 1..100", fmt::format("{}", jpeg_quality));
  }
}

void RendererOptions::Validate() const {
  if (shadow_map_size < 64 || shadow_map_size > 8192) {
    Bad("renderer.shadow_map_size", "an integer in [64, 8192]", fmt::format("{}", shadow_map_size));
  }
  if (pcf_radius < 0 || pcf_radius > 4) {
    Bad("renderer.pcf_radius", "an integer in [0, 4]", fmt::format("{}", pcf_radius));
  }
  if (terrain_grid < 1 || terrain_grid > 1024) {
    Bad("renderer.terrain_grid", "an integer in [1, 1024]", fmt::format("{}", terrain_grid));
  }
  if (texture_size < 16 || texture_size > 2048 || (texture_size & (texture_size - 1)) != 0) {
    Bad("renderer.texture_size", "a power of two in [16, 2048]", fmt::format("{}", texture_size));
  }
  if (!(texture_tile_m > 0.0)) {
    Bad("renderer.texture_tile_m", "a length > 0 m", fmt::format("{}", texture_tile_m));
  }
  if (!(road_width_m > 0.0)) {
    Bad("renderer.road_width_m", "a width > 0 m", fmt::format("{}", road_width_m));
  }
  if (lp_num_threads < 0 || lp_num_threads > 256) {
    Bad("renderer.lp_num_threads", "0 (leave) or a thread count in 1..256",
        fmt::format("{}", lp_num_threads));
  }
  sensor.Validate();
}

}  // namespace hcpf::renderer
