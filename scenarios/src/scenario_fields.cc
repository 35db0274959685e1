// The declared fields of the scenario-level Options structs (scenario.h).
// Where a quantity is also checked by a library module (the sensor and
// renderer options), the range is taken from that module's declaration, so
// each range is written once.

#include "hcpf/renderer/renderer.h"
#include "hcpf/scenarios/scenario.h"

namespace hcpf::scenarios {

std::span<const Field<SimulatedObservationOptions>> SimulatedObservationOptions::Fields() {
  using O = SimulatedObservationOptions;
  static const std::vector<Field<O>> fields = {
      NumberField("sigma_px", &O::sigma_px, Closed(0, 1000), "px",
                  "std. dev. of the detected centre"),
      NumberField("size_sigma", &O::size_sigma, Closed(0, 2), "",
                  "std. dev. of the log of width and height"),
      NumberField("p_detect", &O::p_detect, Closed(0, 1), "",
                  "detection probability of a fully visible target"),
      NumberField("visibility_exponent", &O::visibility_exponent, Closed(0, 10), "",
                  "p = p_detect · visible^exponent"),
      NumberField("min_visible", &O::min_visible, Closed(0, 1), "",
                  "never detected below this visible fraction"),
      NumberField("clutter_per_frame", &O::clutter_per_frame, Closed(0, 1000), "",
                  "Poisson mean of false detections"),
      FlagField("likelihood_map", &O::likelihood_map, "also produce a likelihood map"),
      NumberField("map_cell_px", &O::map_cell_px, Closed(1, 64), "px", "map cell size"),
      NumberField("map_blob_scale", &O::map_blob_scale, Closed(0.01, 10), "",
                  "blob σ = scale · (w + h) / 4"),
      NumberField("map_noise", &O::map_noise, Closed(0, 10), "", "uniform noise floor per cell"),
  };
  return fields;
}

std::vector<std::string_view> ObservationOptions::DetectorNames() { return {"oracle"}; }

std::span<const Field<ObservationOptions>> ObservationOptions::Fields() {
  using O = ObservationOptions;
  static const std::vector<Field<O>> fields = {
      ChoiceField<&O::source>("source",
                              "simulated: detection level, no pixels; rendered: frames are "
                              "rendered with pixel-exact ground truth"),
      WordField<&O::detector, &ObservationOptions::DetectorNames>(
          "detector", "oracle: noisy ground truth, labelled as oracle in results"),
  };
  return fields;
}

std::span<const Field<SensorOptions>> SensorOptions::Fields() {
  using O = SensorOptions;
  const auto renderer = renderer::SensorOptions::Fields();
  static const std::vector<Field<O>> fields = {
      NumberField("noise_sigma", &O::noise_sigma, RangeOf(renderer, "noise_sigma"), "grey levels",
                  "std. dev. of additive Gaussian noise"),
      NumberField("blur_px", &O::blur_px, RangeOf(renderer, "blur_px"), "px",
                  "Gaussian blur σ; 0 = off"),
      IntegerField("jpeg_quality", &O::jpeg_quality, 1, 100, "",
                   "JPEG round trip quality; 100 = no round trip"),
      NumberField("exposure", &O::exposure, RangeOf(renderer, "exposure"), "",
                  "gain on pixel values"),
  };
  return fields;
}

std::vector<std::string_view> RendererConfig::BackendNames() { return {"auto", "osmesa", "egl"}; }

std::span<const Field<RendererConfig>> RendererConfig::Fields() {
  using O = RendererConfig;
  const auto renderer = renderer::RendererOptions::Fields();
  const auto integer = [&renderer](const char* key, int O::*member, const char* unit,
                                   const char* doc) {
    const FieldRange& r = RangeOf(renderer, key);
    return IntegerField(key, member, static_cast<int>(r.lo), static_cast<int>(r.hi), unit, doc);
  };
  static const std::vector<Field<O>> fields = {
      WordField<&O::backend, &RendererConfig::BackendNames>(
          "backend", "auto: EGL when a device answers, else OSMesa"),
      integer("shadow_map_size", &O::shadow_map_size, "texels", "shadow map size per side"),
      integer("pcf_radius", &O::pcf_radius, "texels",
              "0 = one bilinear depth-comparison tap (2×2 PCF), r > 0 = (2r)² taps"),
      FlagField("write_frames", &O::write_frames,
                "hcpf run: also write frames/NNNNNN.png (rendered even at detection level)"),
      FlagField("write_depth", &O::write_depth,
                "hcpf run and render: also write frames/NNNNNN_depth.png (16-bit, mm)"),
      FlagField("write_instance_ids", &O::write_instance_ids,
                "hcpf run and render: also write frames/NNNNNN_ids.png (16-bit, id + 1)"),
  };
  return fields;
}

}  // namespace hcpf::scenarios
