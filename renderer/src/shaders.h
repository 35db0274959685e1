#pragma once
// Private: GLSL sources (3.3 core, so any 3.3+ core context runs them).

namespace hcpf::renderer::internal {

// One program draws everything in the colour pass and, with u_id_only = 1,
// the per-target count pass: sharing the vertex stage (and `invariant
// gl_Position`) makes both passes rasterise a target to identical pixels.
inline constexpr const char* kSceneVertexShader = R"(#version 330 core
layout(location = 0) in vec3 a_position;
layout(location = 1) in vec3 a_normal;
layout(location = 2) in vec2 a_uv;
layout(location = 3) in vec3 a_color;
uniform mat4 u_model;
uniform mat3 u_normal_matrix;
uniform mat4 u_view_proj;
uniform mat4 u_light_view_proj;
out vec3 v_world;
out vec3 v_normal;
out vec3 v_color;
out vec4 v_light;
invariant gl_Position;
void main() {
  vec4 world = u_model * vec4(a_position, 1.0);
  v_world = world.xyz;
  v_normal = u_normal_matrix * a_normal;
  v_color = a_color;
  v_light = u_light_view_proj * world;
  gl_Position = u_view_proj * world;
}
)";

// Fragment shader body; compiled in variants selected by #defines placed
// after the #version line (see FragmentSource): TERRAIN (textured ground) or
// not (vertex colour x tint), SHADOWS, ROADS, PCF_RADIUS r, and ID_ONLY (the
// count pass). Variants instead of runtime branches because llvmpipe runs
// both sides of a branch under a mask: a disabled feature would still cost.
inline constexpr const char* kSceneFragmentBody = R"(
in vec3 v_world;
in vec3 v_normal;
in vec3 v_color;
in vec4 v_light;
uniform float u_id;          // target slot / 255, 0 for scenery
uniform vec3 u_tint;
uniform vec3 u_sun_dir;      // unit, towards the sun
uniform vec3 u_sun_color;
uniform vec3 u_sky_color;
uniform vec3 u_ground_color;
uniform vec2 u_shadow_texel;
uniform float u_shadow_bias;
uniform sampler2DShadow u_shadow_map;
uniform sampler2D u_ground_tex;
uniform sampler2D u_road_tex;
uniform sampler2D u_road_mask;
uniform vec2 u_terrain_min;
uniform vec2 u_terrain_size;
uniform float u_tile_m;
out vec4 o_color;

#ifdef SHADOWS
float Lit() {
  vec3 p = v_light.xyz / v_light.w * 0.5 + 0.5;
  float z = p.z - u_shadow_bias;
#if PCF_RADIUS == 0
  return texture(u_shadow_map, vec3(p.xy, z));
#else
  // (2r)^2 hardware-bilinear comparison taps at half-texel offsets: a
  // (2r+1)^2-texel tent-weighted footprint for (2r)^2 instead of (2r+1)^2
  // lookups. Outside the map the border (depth 1) compares as lit.
  float sum = 0.0;
  for (int i = -PCF_RADIUS; i < PCF_RADIUS; ++i) {
    for (int j = -PCF_RADIUS; j < PCF_RADIUS; ++j) {
      sum += texture(u_shadow_map, vec3(p.xy + (vec2(i, j) + 0.5) * u_shadow_texel, z));
    }
  }
  return sum / float(4 * PCF_RADIUS * PCF_RADIUS);
#endif
}
#endif

void main() {
#ifdef ID_ONLY
  o_color = vec4(0.0, 0.0, 0.0, u_id);
#else
  vec3 n = normalize(v_normal);
#ifdef TERRAIN
  vec2 t = v_world.xy / u_tile_m;
  vec3 albedo = texture(u_ground_tex, t).rgb;
#ifdef ROADS
  float r = texture(u_road_mask, (v_world.xy - u_terrain_min) / u_terrain_size).r;
  albedo = mix(albedo, texture(u_road_tex, t).rgb, r);
#endif
#else
  vec3 albedo = v_color * u_tint;
#endif
  float ndl = max(dot(n, u_sun_dir), 0.0);
#ifdef SHADOWS
  ndl *= Lit();
#endif
  vec3 ambient = mix(u_ground_color, u_sky_color, 0.5 + 0.5 * n.z);
  o_color = vec4(albedo * (ambient + u_sun_color * ndl), u_id);
#endif
}
)";

inline constexpr const char* kShadowVertexShader = R"(#version 330 core
layout(location = 0) in vec3 a_position;
uniform mat4 u_model;
uniform mat4 u_light_view_proj;
void main() { gl_Position = u_light_view_proj * (u_model * vec4(a_position, 1.0)); }
)";

inline constexpr const char* kShadowFragmentShader = R"(#version 330 core
void main() {}
)";

}  // namespace hcpf::renderer::internal
