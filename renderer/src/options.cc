#include <fmt/format.h>

#include <limits>

#include "hcpf/core/error.h"
#include "hcpf/renderer/renderer.h"

namespace hcpf::renderer {

std::span<const Field<SensorOptions>> SensorOptions::Fields() {
  using O = SensorOptions;
  static const std::vector<Field<O>> fields = {
      NumberField("exposure", &O::exposure, AboveUpTo(0, 16), "", "gain on pixel values"),
      NumberField("blur_px", &O::blur_px, Closed(0, 20), "px", "Gaussian blur σ; 0 = off"),
      NumberField("noise_sigma", &O::noise_sigma, Closed(0, 100), "grey levels",
                  "std. dev. of additive Gaussian noise"),
      IntegerField("jpeg_quality", &O::jpeg_quality, 0, 100, "",
                   "JPEG encode/decode round trip quality; 0 = off"),
  };
  return fields;
}

void SensorOptions::Validate() const { CheckFields(*this, Fields(), "sensor"); }

std::span<const Field<RendererOptions>> RendererOptions::Fields() {
  using O = RendererOptions;
  static const std::vector<Field<O>> fields = {
      IntegerField("shadow_map_size", &O::shadow_map_size, 64, 8192, "texels",
                   "shadow map size per side"),
      IntegerField("pcf_radius", &O::pcf_radius, 0, 4, "texels", "shadow filter radius"),
      IntegerField("terrain_grid", &O::terrain_grid, 1, 1024, "cells",
                   "height-field cells per side"),
      IntegerField("texture_size", &O::texture_size, 16, 2048, "texels",
                   "procedural texture size (a power of two)"),
      NumberField("texture_tile_m", &O::texture_tile_m,
                  AboveUpTo(0, std::numeric_limits<double>::infinity()), "m",
                  "ground texture repeat length"),
      NumberField("road_width_m", &O::road_width_m,
                  AboveUpTo(0, std::numeric_limits<double>::infinity()), "m",
                  "width of roads along target paths"),
  };
  return fields;
}

void RendererOptions::Validate() const {
  CheckFields(*this, Fields(), "renderer");
  if ((texture_size & (texture_size - 1)) != 0) {
    FailOption("renderer", "texture_size", "a power of two in [16, 2048]", texture_size);
  }
  sensor.Validate();
}

}  // namespace hcpf::renderer
