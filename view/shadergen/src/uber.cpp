// The uber-shader: ONE program with runtime switches, the way an engine without a generator would
// do it. It exists only as the baseline of bench/shadergen and the engine's frame-time benchmark,
// so the generated programs can be compared against it side by side.
#include <string>

#include "features.hpp"
#include "glsl_builder.hpp"
#include "glsl_snippets.hpp"

namespace meter::shadergen {

namespace {

using detail::GlslBuilder;
using detail::Stage;

constexpr int kUberLightsPerType = 2;

// Every attribute, transform and varying any material could use: the vertex stage reads them all.
void declare_vertex_interface(GlslBuilder& b) {
  b.attribute("a_position", "vec3", AttributeSemantic::Position, 3);
  b.attribute("a_normal", "vec3", AttributeSemantic::Normal, 3);
  b.attribute("a_tangent", "vec4", AttributeSemantic::Tangent, 4);
  b.attribute("a_texcoord0", "vec2", AttributeSemantic::TexCoord0, 2);
  b.attribute("a_texcoord1", "vec2", AttributeSemantic::TexCoord1, 2);
  b.attribute("a_color0", "vec4", AttributeSemantic::Color0, 4);
  b.attribute("a_joints0", "vec4", AttributeSemantic::Joints0, 4);
  b.attribute("a_weights0", "vec4", AttributeSemantic::Weights0, 4);

  b.uniform(Stage::Vertex, "u_model_matrix", "mat4", UniformSemantic::ModelMatrix);
  b.uniform(Stage::Vertex, "u_view_projection", "mat4", UniformSemantic::ViewProjection);
  b.uniform(Stage::Vertex, "u_normal_matrix", "mat3", UniformSemantic::NormalMatrix);
  b.uniform(Stage::Vertex, "u_joint_matrices", "mat4", UniformSemantic::JointMatrices, -1,
            kMaxSkinJoints);
  b.uniform(Stage::Vertex, "u_uber_vertex_switches", "ivec4", UniformSemantic::UberSwitches, 0);

  b.varying("v_world_position", "vec3", true);
  b.varying("v_normal", "vec3");
  b.varying("v_tangent", "vec4");
  b.varying("v_texcoord0", "vec2", true);
  b.varying("v_texcoord1", "vec2", true);
  b.varying("v_color0", "vec4");
}

// Skinning behind a switch, then every varying written unconditionally.
std::string vertex_body() {
  const std::string last_joint = std::to_string(kMaxSkinJoints - 1);
  return R"(  vec3 position = a_position;
  vec3 normal = a_normal;
  vec3 tangent = a_tangent.xyz;
  if ((u_uber_vertex_switches.z & 2) != 0) {
    ivec4 joints = clamp(ivec4(a_joints0), ivec4(0), ivec4()" + last_joint + R"());
    mat4 skin = a_weights0.x * u_joint_matrices[joints.x] + a_weights0.y * u_joint_matrices[joints.y] +
                a_weights0.z * u_joint_matrices[joints.z] + a_weights0.w * u_joint_matrices[joints.w];
    position = (skin * vec4(position, 1.0)).xyz;
    normal = mat3(skin) * normal;
    tangent = mat3(skin) * tangent;
  }
  vec4 world = u_model_matrix * vec4(position, 1.0);
  v_world_position = world.xyz;
  v_normal = normalize(u_normal_matrix * normal);
  v_tangent = vec4(normalize(mat3(u_model_matrix) * tangent), a_tangent.w);
  v_texcoord0 = a_texcoord0;
  v_texcoord1 = a_texcoord1;
  v_color0 = (u_uber_vertex_switches.z & 1) != 0 ? a_color0 : vec4(1.0);
  gl_Position = u_view_projection * world;
)";
}

// The switches, every texture with its transform, and every material factor.
void declare_material_uniforms(GlslBuilder& b) {
  // Fragment: every texture, both lighting models, up to 2 lights per type, all switched at run time.
  b.uniform(Stage::Fragment, "u_uber_switches", "ivec4", UniformSemantic::UberSwitches, 1);
  b.uniform(Stage::Fragment, "u_uber_light_counts", "ivec3", UniformSemantic::UberLightCounts);
  const char* slots[] = {"base_color", "metallic_roughness", "normal", "emissive", "occlusion"};
  for (int s = 0; s < 5; ++s) {
    b.sampler(std::string("u_") + slots[s] + "_texture", static_cast<TextureSlot>(s));
    b.uniform(Stage::Fragment, std::string("u_") + slots[s] + "_uv_transform", "mat3",
              UniformSemantic::TextureTransform, s);
  }
  b.uniform(Stage::Fragment, "u_camera_position", "vec3", UniformSemantic::CameraPosition);
  b.uniform(Stage::Fragment, "u_base_color_factor", "vec4", UniformSemantic::BaseColorFactor);
  b.uniform(Stage::Fragment, "u_emissive_factor", "vec3", UniformSemantic::EmissiveFactor);
  b.uniform(Stage::Fragment, "u_metallic_factor", "float", UniformSemantic::MetallicFactor);
  b.uniform(Stage::Fragment, "u_roughness_factor", "float", UniformSemantic::RoughnessFactor);
  b.uniform(Stage::Fragment, "u_normal_scale", "float", UniformSemantic::NormalScale);
  b.uniform(Stage::Fragment, "u_occlusion_strength", "float", UniformSemantic::OcclusionStrength);
  b.uniform(Stage::Fragment, "u_alpha_cutoff", "float", UniformSemantic::AlphaCutoff);
  b.uniform(Stage::Fragment, "u_specular_color", "vec3", UniformSemantic::SpecularColor);
  b.uniform(Stage::Fragment, "u_shininess", "float", UniformSemantic::Shininess);
  b.uniform(Stage::Fragment, "u_ambient_light", "vec3", UniformSemantic::AmbientLight);
  b.uniform(Stage::Fragment, "u_exposure", "float", UniformSemantic::Exposure);
}

// One uniform array per light type and property, kUberLightsPerType long.
void declare_light_arrays(GlslBuilder& b) {
  // Light arrays: index = first light-list index of the type (directional 0, point 2, spot 4).
  const struct {
    const char* prefix;
    int base;
    bool positional, spot;
  } types[] = {{"u_directional", 0, false, false},
               {"u_point", kUberLightsPerType, true, false},
               {"u_spot", 2 * kUberLightsPerType, true, true}};
  for (const auto& t : types) {
    const std::string p = t.prefix;
    b.uniform(Stage::Fragment, p + "_color", "vec3", UniformSemantic::LightColor, t.base,
              kUberLightsPerType);
    b.uniform(Stage::Fragment, p + "_intensity", "float", UniformSemantic::LightIntensity, t.base,
              kUberLightsPerType);
    if (t.positional) {
      b.uniform(Stage::Fragment, p + "_position", "vec3", UniformSemantic::LightPosition, t.base,
                kUberLightsPerType);
      b.uniform(Stage::Fragment, p + "_range", "float", UniformSemantic::LightRange, t.base,
                kUberLightsPerType);
    }
    if (!t.positional || t.spot)
      b.uniform(Stage::Fragment, p + "_direction", "vec3", UniformSemantic::LightDirection, t.base,
                kUberLightsPerType);
    if (t.spot) {
      b.uniform(Stage::Fragment, p + "_inner_cone_cos", "float",
                UniformSemantic::LightInnerConeCos, t.base, kUberLightsPerType);
      b.uniform(Stage::Fragment, p + "_outer_cone_cos", "float",
                UniformSemantic::LightOuterConeCos, t.base, kUberLightsPerType);
    }
  }
}

// Every helper, plus the switch readers and the per-light shading of both lit models.
std::string fragment_functions() {
  return std::string(detail::kLightConstants) + detail::kRangeAttenuation +
                   detail::kSpotAttenuation + detail::kBlinnPhongSpecular + detail::kPbrBrdf +
                   detail::kEnvBrdfApprox + detail::kCotangentFrame + R"(vec2 uber_uv(int slot, mat3 transform) {
  // switches.w bits 4..8: texture `slot` reads TEXCOORD_1; switches.z & 16: KHR_texture_transform
  vec2 uv = ((u_uber_switches.w >> (4 + slot)) & 1) != 0 ? v_texcoord1 : v_texcoord0;
  return (u_uber_switches.z & 16) != 0 ? (transform * vec3(uv, 1.0)).xy : uv;
}
bool has_texture(int slot) { return ((u_uber_switches.y >> slot) & 1) != 0; }
vec3 shade(int model, vec3 n, vec3 v, vec3 l, vec3 e, vec3 base, vec3 c_diff, vec3 f0, float alpha) {
  if (model == 2) return pbr_light(n, v, l, e, c_diff, f0, alpha);
  float n_dot_l = max(dot(n, l), 0.0);
  return e * n_dot_l * (base / PI + u_specular_color * blinn_phong_specular(n, v, l, u_shininess));
}
)";
}

// The material and every light, each behind its runtime switch.
std::string fragment_body() {
  const std::string n_lights = std::to_string(kUberLightsPerType);
  return R"(  int model = u_uber_switches.x;  // 0 unlit, 1 Blinn-Phong, 2 PBR
  int alpha_mode = u_uber_switches.w & 3;
  vec4 base_color = u_base_color_factor * v_color0;
  if (has_texture(0)) base_color *= texture(u_base_color_texture, uber_uv(0, u_base_color_uv_transform));
  if (alpha_mode == 1 && base_color.a < u_alpha_cutoff) discard;
  vec3 color = base_color.rgb;
  if (model != 0) {
    vec3 n = normalize(v_normal);
    if ((u_uber_switches.z & 4) != 0 && !gl_FrontFacing) n = -n;
    if (has_texture(2)) {
      vec2 uv_normal = uber_uv(2, u_normal_uv_transform);
      vec3 t;
      vec3 bt;
      if ((u_uber_switches.z & 8) != 0) {
        t = normalize(v_tangent.xyz - n * dot(n, v_tangent.xyz));
        bt = cross(n, t) * v_tangent.w;
      } else {
        mat3 f = cotangent_frame(n, v_world_position, uv_normal);
        t = f[0];
        bt = f[1];
      }
      vec3 tn = texture(u_normal_texture, uv_normal).xyz * 2.0 - 1.0;
      tn.xy *= u_normal_scale;
      n = normalize(mat3(t, bt, n) * tn);
    }
    vec3 v = normalize(u_camera_position - v_world_position);
    float metallic = u_metallic_factor;
    float roughness = u_roughness_factor;
    if (has_texture(1)) {
      vec4 mr = texture(u_metallic_roughness_texture, uber_uv(1, u_metallic_roughness_uv_transform));
      roughness *= mr.g;
      metallic *= mr.b;
    }
    roughness = clamp(roughness, 0.045, 1.0);
    metallic = clamp(metallic, 0.0, 1.0);
    vec3 c_diff = model == 2 ? mix(base_color.rgb, vec3(0.0), metallic) : base_color.rgb;
    vec3 f0 = mix(vec3(0.04), base_color.rgb, metallic);
    float alpha = roughness * roughness;
    color = vec3(0.0);
    for (int i = 0; i < )" + n_lights + R"(; ++i) {
      if (i >= u_uber_light_counts.x) break;
      vec3 l = -normalize(u_directional_direction[i]);
      vec3 e = u_directional_color[i] * (u_directional_intensity[i] * kWattsPerLumen);
      color += shade(model, n, v, l, e, base_color.rgb, c_diff, f0, alpha);
    }
    for (int i = 0; i < )" + n_lights + R"(; ++i) {
      if (i >= u_uber_light_counts.y) break;
      vec3 to_light = u_point_position[i] - v_world_position;
      float d2 = max(dot(to_light, to_light), kMinLightDistance2);
      float d = sqrt(d2);
      vec3 l = to_light / d;
      vec3 e = u_point_color[i] * (u_point_intensity[i] * kWattsPerLumen * range_attenuation(d, u_point_range[i]) / d2);
      color += shade(model, n, v, l, e, base_color.rgb, c_diff, f0, alpha);
    }
    for (int i = 0; i < )" + n_lights + R"(; ++i) {
      if (i >= u_uber_light_counts.z) break;
      vec3 to_light = u_spot_position[i] - v_world_position;
      float d2 = max(dot(to_light, to_light), kMinLightDistance2);
      float d = sqrt(d2);
      vec3 l = to_light / d;
      float attenuation = range_attenuation(d, u_spot_range[i]) / d2 *
          spot_attenuation(dot(normalize(u_spot_direction[i]), -l), u_spot_inner_cone_cos[i], u_spot_outer_cone_cos[i]);
      vec3 e = u_spot_color[i] * (u_spot_intensity[i] * kWattsPerLumen * attenuation);
      color += shade(model, n, v, l, e, base_color.rgb, c_diff, f0, alpha);
    }
    float ao = 1.0;
    if (has_texture(4)) ao += u_occlusion_strength * (texture(u_occlusion_texture, uber_uv(4, u_occlusion_uv_transform)).r - 1.0);
    vec3 ambient_weight = model == 2 ? c_diff + env_brdf_approx(f0, roughness, max(dot(n, v), 1e-4)) : base_color.rgb;
    color += ambient_weight * u_ambient_light * ao;
    vec3 emissive = u_emissive_factor;
    if (has_texture(3)) emissive *= texture(u_emissive_texture, uber_uv(3, u_emissive_uv_transform)).rgb;
    color += emissive;
  }
  o_color = vec4(color * u_exposure, alpha_mode == 2 ? base_color.a : 1.0);
)";
}

}  // namespace

Program generate_uber() {
  GlslBuilder b(Precision::Highp);
  declare_vertex_interface(b);
  b.vs_body = vertex_body();
  declare_material_uniforms(b);
  declare_light_arrays(b);
  b.fs_functions = fragment_functions();
  b.fs_body = fragment_body();

  Program& p = b.program();
  p.uber = true;
  p.blend = false;  // the runtime sets blending per draw from the material when using the uber shader
  p.cull_back_faces = true;
  p.features.shading = ShadingModel::PbrMetallicRoughness;
  return b.finish("meter shadergen: uber-shader (benchmark baseline, runtime switches)");
}

}  // namespace meter::shadergen
