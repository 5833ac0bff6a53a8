// GLSL building blocks pasted into generated programs only when the feature that needs them is on.
#pragma once

namespace meter::shadergen::detail {

// Blender's glTF exporter writes photometric units: a sun of S W/m^2 becomes S*683 lux, a point or
// spot light of P W becomes P*683/(4*pi) cd (KHR_lights_punctual). Dividing by 683 lm/W gives back
// Blender's radiometric irradiance, so a white Lambert surface under a sun of strength S renders
// S/pi, as in EEVEE/Cycles with the 'Standard' view transform and exposure 0.
inline constexpr const char* kLightConstants = R"(const float PI = 3.14159265358979;
const float kWattsPerLumen = 1.0 / 683.0;
const float kMinLightDistance2 = 1e-4;
)";

// KHR_lights_punctual: smooth window to zero at `range`, range <= 0 (absent) means infinite.
inline constexpr const char* kRangeAttenuation = R"(float range_attenuation(float d, float range) {
  if (range <= 0.0) return 1.0;
  float x = d / range;
  x *= x;
  return clamp(1.0 - x * x, 0.0, 1.0);
}
)";

// Spot cone as Blender draws it (EEVEE and Cycles: smoothstep over a blend band of
// (1 - cos(size/2)) * spot_blend in cos), from the cone angles Blender's glTF exporter writes:
// outer = size/2, inner = outer * (1 - spot_blend). The glTF spec's non-normative example (linear
// in cos from outer to inner, squared) spreads the edge over the whole inner..outer band.
inline constexpr const char* kSpotAttenuation =
    R"(float spot_attenuation(float cos_angle, float inner_cos, float outer_cos) {
  float outer = acos(outer_cos);
  float blend = (outer - acos(inner_cos)) / max(outer, 1e-4);
  float t = (cos_angle - outer_cos) / max((1.0 - outer_cos) * blend, 1e-6);
  return smoothstep(0.0, 1.0, t);
}
)";

// Fraction of a light that reaches `position` past its shadow map (`shadow_matrix`: world ->
// the map's [0,1]^3): one depth-compared lookup, which the map's linear filtering makes a blend of
// the four nearest texels' comparisons (a one-texel soft edge, as EEVEE's jittered samples soften
// its map's). Four such lookups half a texel apart were measured too: 0.57 dB further from EEVEE
// and 1.4x the lookup cost (docs/engine.md, "Shadows"). Outside the light's frustum the point is
// lit (the map covers everything the light can reach in the scene).
inline constexpr const char* kShadowVisibility =
    R"(float shadow_visibility(highp sampler2DShadow map, highp mat4 shadow_matrix, highp vec3 position) {
  highp vec4 c = shadow_matrix * vec4(position, 1.0);
  if (c.w <= 0.0) return 1.0;
  highp vec3 p = c.xyz / c.w;
  if (p.x < 0.0 || p.x > 1.0 || p.y < 0.0 || p.y > 1.0 || p.z >= 1.0) return 1.0;
  return texture(map, p);
}
)";

// Normalised Blinn-Phong lobe ((s + 8) / 8pi keeps the reflected energy roughly constant).
inline constexpr const char* kBlinnPhongSpecular =
    R"(float blinn_phong_specular(vec3 n, vec3 v, vec3 l, float shininess) {
  vec3 h = normalize(l + v);
  return (shininess + 8.0) / (8.0 * PI) * pow(max(dot(n, h), 0.0), shininess);
}
)";

// glTF 2.0 spec appendix B: Lambert diffuse + GGX (Trowbridge-Reitz) D, separable Smith-GGX
// visibility, Schlick Fresnel; returns outgoing radiance for irradiance e from direction l.
// One deviation, to match the authoring tool: the diffuse lobe is NOT scaled by (1 - F). Blender
// 3.x's Principled BSDF (EEVEE, Cycles) adds the specular layer on top of the full Lambert
// diffuse; the spec's energy split made every lit dielectric ~4 % darker than Blender (measured:
// 1.2-2.4 dB lower PSNR on diffuse, specular, spot, omni; docs/fidelity.md).
inline constexpr const char* kPbrBrdf =
    R"(vec3 pbr_light(vec3 n, vec3 v, vec3 l, vec3 e, vec3 c_diff, vec3 f0, float alpha) {
  float n_dot_l = dot(n, l);
  if (n_dot_l <= 0.0) return vec3(0.0);
  vec3 h = normalize(l + v);
  float n_dot_v = max(dot(n, v), 1e-4);
  float n_dot_h = max(dot(n, h), 0.0);
  float v_dot_h = max(dot(v, h), 0.0);
  vec3 fresnel = f0 + (1.0 - f0) * pow(1.0 - v_dot_h, 5.0);
  float a2 = alpha * alpha;
  float dd = n_dot_h * n_dot_h * (a2 - 1.0) + 1.0;
  float distribution = a2 / (PI * dd * dd);
  float visibility = 1.0 / ((n_dot_l + sqrt(a2 + (1.0 - a2) * n_dot_l * n_dot_l)) *
                            (n_dot_v + sqrt(a2 + (1.0 - a2) * n_dot_v * n_dot_v)));
  vec3 diffuse = c_diff / PI;
  vec3 specular = fresnel * (distribution * visibility);
  return (diffuse + specular) * e * n_dot_l;
}
)";

// Directional-albedo of the specular lobe under uniform light (Karis' analytic fit of the split-sum
// DFG term): weights the ambient / environment radiance so metals reflect the world.
inline constexpr const char* kEnvBrdfApprox =
    R"(vec3 env_brdf_approx(vec3 f0, float roughness, float n_dot_v) {
  const vec4 c0 = vec4(-1.0, -0.0275, -0.572, 0.022);
  const vec4 c1 = vec4(1.0, 0.0425, 1.04, -0.04);
  vec4 r = roughness * c0 + c1;
  float a004 = min(r.x * r.x, exp2(-9.28 * n_dot_v)) * r.x + r.y;
  vec2 ab = vec2(-1.04, 1.04) * a004 + r.zw;
  return f0 * ab.x + ab.y;
}
)";

// Tangent frame from screen-space derivatives when the mesh has no TANGENT attribute.
inline constexpr const char* kCotangentFrame = R"(mat3 cotangent_frame(vec3 n, vec3 p, vec2 uv) {
  vec3 dp1 = dFdx(p);
  vec3 dp2 = dFdy(p);
  vec2 duv1 = dFdx(uv);
  vec2 duv2 = dFdy(uv);
  vec3 dp2perp = cross(dp2, n);
  vec3 dp1perp = cross(n, dp1);
  vec3 t = dp2perp * duv1.x + dp1perp * duv2.x;
  vec3 b = dp2perp * duv1.y + dp1perp * duv2.y;
  // Degenerate UVs give t = b = 0: keep the frame finite instead of dividing by zero.
  float inv_max = inversesqrt(max(max(dot(t, t), dot(b, b)), 1e-12));
  return mat3(t * inv_max, b * inv_max, n);
}
)";

// EEVEE's (Blender 2.8-3.x) world diffuse lighting, the "HL2" ambient cube: six colours, one per
// signed axis, blended by the squared normal components (they sum to 1). Each colour is the
// cosine-weighted mean radiance of the map around its axis (the converter integrates it), so a
// Lambert surface gets albedo * ambient_cube(n), as EEVEE's diffuse does with its world probe.
inline constexpr const char* kAmbientCube =
    R"(vec3 ambient_cube(vec3 n, vec3 px, vec3 nx, vec3 py, vec3 ny, vec3 pz, vec3 nz) {
  vec3 n2 = n * n;
  return n2.x * (n.x >= 0.0 ? px : nx) + n2.y * (n.y >= 0.0 ? py : ny) + n2.z * (n.z >= 0.0 ? pz : nz);
}
)";

}  // namespace meter::shadergen::detail
