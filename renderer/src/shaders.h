#pragma once
// Private: GLSL sources (3.3 core, so any 3.3+ core context runs them).

namespace hcpf::renderer::internal {

// Vertex shader body, compiled with the same #defines as the fragment
// shader it is linked with (see kSceneFragmentBody). The colour pass's
// object program and the count pass's id-only program share this stage (and
// `invariant gl_Position`), so both passes rasterise a target to identical
// pixels.
//
// With TERRAIN the stage also computes, per vertex, everything the terrain's
// fragments need that is linear (or very nearly so) across a triangle: the
// lighting without the shadow (ambient and N.L from the vertex's unit
// normal: Gouraud shading, where the other materials shade per fragment),
// the texture coordinates, and the shadow-map coordinate (the sun's
// projection is orthographic, so it is exactly linear). Per fragment that
// leaves the texture and shadow lookups and one multiply-add: the
// normalisation, N.L and the ambient blend per fragment cost ~11 % of a
// frame on llvmpipe (docs/performance.md). The terrain's normals come from a
// smooth height field with 8 m cells, so the interpolated lighting differs
// from per-fragment lighting by well under a grey level.
inline constexpr const char* kSceneVertexBody = R"(
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
#ifdef TERRAIN
uniform vec3 u_sun_dir;
uniform vec3 u_sky_color;
uniform vec3 u_ground_color;
uniform float u_shadow_bias;
uniform vec2 u_terrain_min;
uniform vec2 u_terrain_size;
uniform float u_tile_m;
out vec3 v_ambient;    // hemispheric ambient
out float v_sun;       // max(N.L, 0)
out vec2 v_tex;        // ground and road texture coordinate
out vec2 v_mask;       // road-mask coordinate
out vec3 v_shadow;     // shadow-map coordinate, depth biased
#endif
invariant gl_Position;
void main() {
  vec4 world = u_model * vec4(a_position, 1.0);
  v_world = world.xyz;
  v_normal = u_normal_matrix * a_normal;
  v_color = a_color;
  v_light = u_light_view_proj * world;
  gl_Position = u_view_proj * world;
#ifdef TERRAIN
  vec3 n = normalize(v_normal);
  v_ambient = mix(u_ground_color, u_sky_color, 0.5 + 0.5 * n.z);
  v_sun = max(dot(n, u_sun_dir), 0.0);
  v_tex = world.xy / u_tile_m;
  v_mask = (world.xy - u_terrain_min) / u_terrain_size;
  v_shadow = v_light.xyz * 0.5 + 0.5;  // w = 1: orthographic
  v_shadow.z -= u_shadow_bias;
#endif
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
#ifdef TERRAIN
in vec3 v_ambient;
in float v_sun;
in vec2 v_tex;
in vec2 v_mask;
in vec3 v_shadow;
#endif
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
#ifdef TERRAIN
  vec3 p = v_shadow;
  float z = p.z;
#else
  vec3 p = v_light.xyz / v_light.w * 0.5 + 0.5;
  float z = p.z - u_shadow_bias;
#endif
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
#elif defined(TERRAIN)
  vec3 albedo = texture(u_ground_tex, v_tex).rgb;
#ifdef ROADS
  float r = texture(u_road_mask, v_mask).r;
  albedo = mix(albedo, texture(u_road_tex, v_tex).rgb, r);
#endif
  float ndl = v_sun;
#ifdef SHADOWS
  ndl *= Lit();
#endif
  o_color = vec4(albedo * (v_ambient + u_sun_color * ndl), u_id);
#else
  vec3 n = normalize(v_normal);
  vec3 albedo = v_color * u_tint;
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
