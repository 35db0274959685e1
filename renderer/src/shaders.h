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

inline constexpr const char* kSceneFragmentShader = R"(#version 330 core
in vec3 v_world;
in vec3 v_normal;
in vec3 v_color;
in vec4 v_light;
uniform int u_id_only;       // 1: write only the id (count pass)
uniform float u_id;          // target slot / 255, 0 for scenery
uniform int u_material;      // 0: vertex colour * tint, 1: textured terrain
uniform vec3 u_tint;
uniform vec3 u_sun_dir;      // unit, towards the sun
uniform vec3 u_sun_color;
uniform vec3 u_sky_color;
uniform vec3 u_ground_color;
uniform int u_shadows;
uniform int u_pcf;
uniform vec2 u_shadow_texel;
uniform float u_shadow_bias;
uniform sampler2DShadow u_shadow_map;
uniform sampler2D u_ground_tex;
uniform sampler2D u_road_tex;
uniform sampler2D u_road_mask;
uniform sampler2D u_occupancy;   // 128 x 128, nearest: 0 = no caster can shadow here
uniform vec2 u_terrain_min;
uniform vec2 u_terrain_size;
uniform float u_tile_m;
uniform int u_roads;
out vec4 o_color;

float Lit() {
  vec3 p = v_light.xyz / v_light.w * 0.5 + 0.5;
  if (p.z >= 1.0 || p.x <= 0.0 || p.y <= 0.0 || p.x >= 1.0 || p.y >= 1.0) return 1.0;
  if (texelFetch(u_occupancy, ivec2(p.xy * 128.0), 0).r == 0.0) return 1.0;
  if (u_pcf == 0) return texture(u_shadow_map, vec3(p.xy, p.z - u_shadow_bias));
  // (2r)^2 hardware-bilinear comparison taps at half-texel offsets: a
  // (2r+1)^2-texel tent-weighted footprint for (2r)^2 instead of (2r+1)^2
  // lookups (shadow lookups dominate llvmpipe's fragment cost).
  float sum = 0.0;
  for (int i = -u_pcf; i < u_pcf; ++i) {
    for (int j = -u_pcf; j < u_pcf; ++j) {
      sum += texture(u_shadow_map,
                     vec3(p.xy + (vec2(i, j) + 0.5) * u_shadow_texel, p.z - u_shadow_bias));
    }
  }
  float n = float(2 * u_pcf);
  return sum / (n * n);
}

void main() {
  if (u_id_only == 1) {
    o_color = vec4(0.0, 0.0, 0.0, u_id);
    return;
  }
  vec3 n = normalize(v_normal);
  vec3 albedo;
  if (u_material == 1) {
    vec2 t = v_world.xy / u_tile_m;
    albedo = texture(u_ground_tex, t).rgb;
    if (u_roads == 1) {
      float r = texture(u_road_mask, (v_world.xy - u_terrain_min) / u_terrain_size).r;
      if (r > 0.0) albedo = mix(albedo, texture(u_road_tex, t).rgb, r);
    }
  } else {
    albedo = v_color * u_tint;
  }
  float ndl = max(dot(n, u_sun_dir), 0.0);
  float lit = (u_shadows == 1 && ndl > 0.0) ? Lit() : 1.0;
  vec3 ambient = mix(u_ground_color, u_sky_color, 0.5 + 0.5 * n.z);
  o_color = vec4(albedo * (ambient + u_sun_color * (ndl * lit)), u_id);
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
