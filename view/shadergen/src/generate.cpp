// The generator: instantiates GLSL ES 3.00 for exactly the features of one material + light set.
// Every `if` below decides whether a piece of code exists at all; the output has no #ifdef and no
// runtime feature switch (that is generate_uber(), the benchmark baseline).
#include <string>

#include "features.hpp"
#include "glsl_builder.hpp"
#include "glsl_snippets.hpp"
#include "meter/bridge/material_feature_fields.hpp"

namespace meter::shadergen {

namespace {

using detail::GlslBuilder;
using detail::Stage;

std::string slot_name(TextureSlot s) { return to_string(s); }

struct Needs {
  bool normal_attribute = false;  // vertex normal transformed at all
  bool view_vector = false;       // fragment needs (camera - position)
  bool world_position = false;    // v_world_position varying
  bool normal_varying = false;
  bool tangent = false;
  bool uv0 = false, uv1 = false;
  bool gouraud_light = false;
  bool flat_light = false;        // Flat: the face's light from its provoking vertex
  bool morph_normals = false;     // morph targets move the normal too
};

Needs analyse(const MaterialFeatures& f) {
  Needs n;
  const bool per_pixel = detail::per_pixel_normal(f.shading);
  const int lights = f.lights.total();
  // Flat reads the normal too: the converter gives each face's provoking vertex the face normal
  // (Primitive::flat_indices), and the light computed there is the whole face's.
  n.normal_attribute = f.shading != ShadingModel::Unlit;
  // PBR always needs N.V (Fresnel of the ambient term); Blinn-Phong only for highlights.
  n.view_vector = f.shading == ShadingModel::PbrMetallicRoughness ||
                  (f.shading == ShadingModel::BlinnPhong && (lights > 0 || f.environment_map_2d));
  n.world_position = n.view_vector ||
                     (per_pixel && (f.lights.point + f.lights.spot) > 0) || f.lights.shadows != 0 ||
                     (f.normal_texture && !f.has_tangents);
  n.normal_varying = per_pixel;
  n.tangent = f.normal_texture && f.has_tangents;
  for (int s = 0; s <= static_cast<int>(TextureSlot::Occlusion); ++s) {
    const auto slot = static_cast<TextureSlot>(s);
    if (!bridge::feature_terms::has(f, slot)) continue;
    (bridge::feature_terms::texcoord1(f, slot) ? n.uv1 : n.uv0) = true;
  }
  n.gouraud_light = f.shading == ShadingModel::Gouraud && lights > 0;
  n.flat_light = f.shading == ShadingModel::Flat && lights > 0;
  n.morph_normals = f.morph_normals && n.normal_attribute;
  return n;
}

// Declares the uniforms of every light in `stage` and returns the code that accumulates them:
// for each light `l` (unit vector to the light) and `e` (irradiance, W/m^2 in Blender's units at
// the surface, before N.L, times the shadow map's visibility for a light that casts shadows) are
// computed, then `accumulate` is pasted with them in scope.
std::string light_loop(GlslBuilder& b, Stage stage, const LightCounts& lights,
                       const std::string& position, const std::string& accumulate) {
  std::string code;
  int g = 0;
  auto U = [&](const std::string& field, const char* type, UniformSemantic sem) {
    const std::string name = "u_light" + std::to_string(g) + "_" + field;
    b.uniform(stage, name, type, sem, g);
    return name;
  };
  auto shadow = [&] {
    if (stage != Stage::Fragment || !lights.casts_shadow(g)) return std::string();
    const std::string map = "u_light" + std::to_string(g) + "_shadow_map";
    b.sampler(map, TextureSlot::ShadowMap, g);
    const auto matrix = U("shadow_matrix", "highp mat4", UniformSemantic::LightShadowMatrix);
    return "    e *= shadow_visibility(" + map + ", " + matrix + ", " + position + ");\n";
  };
  for (int i = 0; i < lights.directional; ++i, ++g) {
    const auto color = U("color", "vec3", UniformSemantic::LightColor);
    const auto intensity = U("intensity", "float", UniformSemantic::LightIntensity);
    const auto direction = U("direction", "vec3", UniformSemantic::LightDirection);
    code += "  {  // directional light " + std::to_string(g) + " (intensity in lux)\n";
    code += "    vec3 l = -normalize(" + direction + ");\n";
    code += "    vec3 e = " + color + " * (" + intensity + " * kWattsPerLumen);\n";
    code += shadow();
    code += accumulate + "  }\n";
  }
  for (int i = 0; i < lights.point + lights.spot; ++i, ++g) {
    const bool spot = i >= lights.point;
    const auto color = U("color", "vec3", UniformSemantic::LightColor);
    const auto intensity = U("intensity", "float", UniformSemantic::LightIntensity);
    const auto pos = U("position", "vec3", UniformSemantic::LightPosition);
    const auto range = U("range", "float", UniformSemantic::LightRange);
    code += "  {  // " + std::string(spot ? "spot" : "point") + " light " + std::to_string(g) +
            " (intensity in candela)\n";
    code += "    vec3 to_light = " + pos + " - " + position + ";\n";
    code += "    float d2 = max(dot(to_light, to_light), kMinLightDistance2);\n";
    code += "    float d = sqrt(d2);\n";
    code += "    vec3 l = to_light / d;\n";
    code += "    float attenuation = range_attenuation(d, " + range + ") / d2;\n";
    if (spot) {
      const auto direction = U("direction", "vec3", UniformSemantic::LightDirection);
      const auto inner = U("inner_cone_cos", "float", UniformSemantic::LightInnerConeCos);
      const auto outer = U("outer_cone_cos", "float", UniformSemantic::LightOuterConeCos);
      code += "    attenuation *= spot_attenuation(dot(normalize(" + direction + "), -l), " +
              inner + ", " + outer + ");\n";
    }
    code += "    vec3 e = " + color + " * (" + intensity + " * kWattsPerLumen * attenuation);\n";
    code += shadow();
    code += accumulate + "  }\n";
  }
  return code;
}

std::string light_helpers(const LightCounts& lights) {
  std::string s = detail::kLightConstants;
  if (lights.point + lights.spot > 0) s += detail::kRangeAttenuation;
  if (lights.spot > 0) s += detail::kSpotAttenuation;
  if (lights.shadows != 0) s += detail::kShadowVisibility;
  return s;
}

// ---- vertex stage

// The vertex inputs: the position, then only the attributes the features read, in a fixed order
// (their locations follow it).
void declare_attributes(GlslBuilder& b, const MaterialFeatures& f, const Needs& need) {
  b.attribute("a_position", "vec3", AttributeSemantic::Position, 3);
  if (need.normal_attribute) b.attribute("a_normal", "vec3", AttributeSemantic::Normal, 3);
  if (need.tangent) b.attribute("a_tangent", "vec4", AttributeSemantic::Tangent, 4);
  if (need.uv0) b.attribute("a_texcoord0", "vec2", AttributeSemantic::TexCoord0, 2);
  if (need.uv1) b.attribute("a_texcoord1", "vec2", AttributeSemantic::TexCoord1, 2);
  if (f.vertex_colors) b.attribute("a_color0", "vec4", AttributeSemantic::Color0, 4);
  if (f.vertex_alpha) b.attribute("a_vertex_alpha", "float", AttributeSemantic::VertexAlpha, 1);
  if (f.skin_joints > 0) {
    b.attribute("a_joints0", "vec4", AttributeSemantic::Joints0, 4);
    b.attribute("a_weights0", "vec4", AttributeSemantic::Weights0, 4);
  }
  for (int i = 0; i < f.morph_targets; ++i) {
    b.attribute("a_morph_position" + std::to_string(i), "vec3", AttributeSemantic::MorphPosition, 3,
                i);
    if (need.morph_normals)
      b.attribute("a_morph_normal" + std::to_string(i), "vec3", AttributeSemantic::MorphNormal, 3,
                  i);
  }
}

// The transforms every program has, the normal matrix of lit models, and the joint matrices and
// morph weights of deformed meshes.
void declare_vertex_uniforms(GlslBuilder& b, const MaterialFeatures& f, const Needs& need) {
  b.uniform(Stage::Vertex, "u_model_matrix", "mat4", UniformSemantic::ModelMatrix);
  b.uniform(Stage::Vertex, "u_view_projection", "mat4", UniformSemantic::ViewProjection);
  if (need.normal_attribute)
    b.uniform(Stage::Vertex, "u_normal_matrix", "mat3", UniformSemantic::NormalMatrix);
  if (f.skin_joints > 0)
    b.uniform(Stage::Vertex, "u_joint_matrices", "mat4", UniformSemantic::JointMatrices, -1,
              f.skin_joints);
  if (f.morph_targets > 0)
    b.uniform(Stage::Vertex, "u_morph_weights", "float", UniformSemantic::MorphWeights, -1,
              f.morph_targets);
}

// What the vertex stage hands the fragment stage.
void declare_varyings(GlslBuilder& b, const MaterialFeatures& f, const Needs& need) {
  if (need.world_position) b.varying("v_world_position", "vec3", true);
  if (need.normal_varying) b.varying("v_normal", "vec3");
  if (need.tangent) b.varying("v_tangent", "vec4");
  if (need.uv0) b.varying("v_texcoord0", "vec2", true);
  if (need.uv1) b.varying("v_texcoord1", "vec2", true);
  if (f.vertex_colors) b.varying("v_color0", "vec4");
  if (f.vertex_alpha) b.varying("v_vertex_alpha", "float");
  if (need.gouraud_light) {
    b.varying("v_diffuse_light", "vec3");
    b.varying("v_specular_light", "vec3");
  }
  if (need.flat_light) b.flat_varying("v_flat_light", "vec3");
}

// Morph targets, then skinning, move the model-space position (and normal, tangent).
void deform_vertex(GlslBuilder& b, const MaterialFeatures& f, const Needs& need) {
  std::string& vb = b.vs_body;
  vb += "  vec3 position = a_position;\n";
  if (need.normal_attribute) vb += "  vec3 normal = a_normal;\n";
  if (need.tangent) vb += "  vec3 tangent = a_tangent.xyz;\n";
  for (int i = 0; i < f.morph_targets; ++i) {
    const std::string w = "u_morph_weights[" + std::to_string(i) + "]";
    vb += "  position += " + w + " * a_morph_position" + std::to_string(i) + ";\n";
    if (need.morph_normals)
      vb += "  normal += " + w + " * a_morph_normal" + std::to_string(i) + ";\n";
  }
  if (f.skin_joints > 0) {
    // Clamped indices: an out-of-range joint index must not read outside the uniform array.
    const std::string last = std::to_string(f.skin_joints - 1);
    vb += "  ivec4 joints = clamp(ivec4(a_joints0), ivec4(0), ivec4(" + last + "));\n";
    vb += "  mat4 skin = a_weights0.x * u_joint_matrices[joints.x] + a_weights0.y * "
          "u_joint_matrices[joints.y] +\n"
          "            a_weights0.z * u_joint_matrices[joints.z] + a_weights0.w * "
          "u_joint_matrices[joints.w];\n";
    vb += "  position = (skin * vec4(position, 1.0)).xyz;\n";
    if (need.normal_attribute) vb += "  normal = mat3(skin) * normal;\n";
    if (need.tangent) vb += "  tangent = mat3(skin) * tangent;\n";
  }
}

// The deformed vertex into world space, and the varyings written from it and the attributes.
void write_vertex_outputs(GlslBuilder& b, const MaterialFeatures& f, const Needs& need) {
  std::string& vb = b.vs_body;
  vb += "  vec4 world = u_model_matrix * vec4(position, 1.0);\n";
  if (need.world_position) vb += "  v_world_position = world.xyz;\n";
  if (need.normal_attribute) vb += "  vec3 world_normal = normalize(u_normal_matrix * normal);\n";
  if (need.normal_varying) vb += "  v_normal = world_normal;\n";
  if (need.tangent)
    vb += "  v_tangent = vec4(normalize(mat3(u_model_matrix) * tangent), a_tangent.w);\n";
  if (need.uv0) vb += "  v_texcoord0 = a_texcoord0;\n";
  if (need.uv1) vb += "  v_texcoord1 = a_texcoord1;\n";
  if (f.vertex_colors) vb += "  v_color0 = a_color0;\n";
  if (f.vertex_alpha) vb += "  v_vertex_alpha = a_vertex_alpha;\n";
}

// Gouraud shading: the lights are summed per vertex (diffuse and specular apart, so the fragment
// stage can tint the diffuse part with the base colour).
void light_vertex(GlslBuilder& b, const MaterialFeatures& f) {
  std::string& vb = b.vs_body;
  b.uniform(Stage::Vertex, "u_camera_position", "vec3", UniformSemantic::CameraPosition);
  b.uniform(Stage::Vertex, "u_specular_color", "vec3", UniformSemantic::SpecularColor);
  b.uniform(Stage::Vertex, "u_shininess", "float", UniformSemantic::Shininess);
  b.vs_functions += light_helpers(f.lights);
  b.vs_functions += detail::kBlinnPhongSpecular;
  vb += "  vec3 n = world_normal;\n";
  vb += "  vec3 v = normalize(u_camera_position - world.xyz);\n";
  vb += "  vec3 diffuse_light = vec3(0.0);\n  vec3 specular_light = vec3(0.0);\n";
  vb += light_loop(b, Stage::Vertex, f.lights, "world.xyz",
                   "    float n_dot_l = max(dot(n, l), 0.0);\n"
                   "    diffuse_light += e * (n_dot_l / PI);\n"
                   "    specular_light += e * (n_dot_l * blinn_phong_specular(n, v, l, "
                   "u_shininess));\n");
  vb += "  v_diffuse_light = diffuse_light;\n";
  vb += "  v_specular_light = specular_light * u_specular_color;\n";
}

// Flat shading: Lambert at each vertex, handed on without interpolation, so every fragment of a
// face takes its provoking (last) vertex's light: one lighting per face, no per-fragment work.
void light_vertex_flat(GlslBuilder& b, const MaterialFeatures& f) {
  std::string& vb = b.vs_body;
  b.vs_functions += light_helpers(f.lights);
  vb += "  vec3 n = world_normal;\n  vec3 diffuse_light = vec3(0.0);\n";
  vb += light_loop(b, Stage::Vertex, f.lights, "world.xyz", "    diffuse_light += e * (max(dot(n, l), 0.0) / PI);\n");
  vb += "  v_flat_light = diffuse_light;\n";
}

void write_vertex_stage(GlslBuilder& b, const MaterialFeatures& f, const Needs& need) {
  declare_attributes(b, f, need);
  declare_vertex_uniforms(b, f, need);
  declare_varyings(b, f, need);
  deform_vertex(b, f, need);
  write_vertex_outputs(b, f, need);
  if (need.gouraud_light) light_vertex(b, f);
  if (need.flat_light) light_vertex_flat(b, f);
  b.vs_body += "  gl_Position = u_view_projection * world;\n";
}

// ---- fragment stage

// Texture coordinates per texture (KHR_texture_transform applied here, per texture).
void sample_coordinates(GlslBuilder& b, const MaterialFeatures& f) {
  for (int s = 0; s <= static_cast<int>(TextureSlot::Occlusion); ++s) {
    const auto slot = static_cast<TextureSlot>(s);
    if (!bridge::feature_terms::has(f, slot)) continue;
    b.sampler("u_" + slot_name(slot) + "_texture", slot);
    const std::string uv = bridge::feature_terms::texcoord1(f, slot) ? "v_texcoord1" : "v_texcoord0";
    if (f.texture_transform) {
      const std::string t = "u_" + slot_name(slot) + "_uv_transform";
      b.uniform(Stage::Fragment, t, "mat3", UniformSemantic::TextureTransform, s);
      b.fs_body += "  vec2 uv_" + slot_name(slot) + " = (" + t + " * vec3(" + uv + ", 1.0)).xy;\n";
    } else {
      b.fs_body += "  vec2 uv_" + slot_name(slot) + " = " + uv + ";\n";
    }
  }
}

// The base colour (factor, texture, vertex colour, concatenated-mesh visibility) and the alpha
// test of masked materials.
void base_color(GlslBuilder& b, const MaterialFeatures& f) {
  std::string& fb = b.fs_body;
  b.uniform(Stage::Fragment, "u_base_color_factor", "vec4", UniformSemantic::BaseColorFactor);
  fb += "  vec4 base_color = u_base_color_factor;\n";
  if (f.base_color_texture)
    fb += "  base_color *= texture(u_base_color_texture, uv_base_color);  // sRGB texture -> linear\n";
  if (f.vertex_colors) fb += "  base_color *= v_color0;\n";
  if (f.vertex_alpha) {
    fb += "  base_color.a *= v_vertex_alpha;  // concatenated-mesh visibility\n";
    if (f.alpha != AlphaMode::Blend)
      // Without blending a hidden part must not cover what is behind it.
      fb += "  if (v_vertex_alpha < 0.5) discard;\n";
  }
  if (f.alpha == AlphaMode::Mask) {
    b.uniform(Stage::Fragment, "u_alpha_cutoff", "float", UniformSemantic::AlphaCutoff);
    fb += "  if (base_color.a < u_alpha_cutoff) discard;\n";
  }
}

// The shading normal `n` of per-pixel models: the interpolated one, then the normal map's.
void surface_normal(GlslBuilder& b, const MaterialFeatures& f) {
  std::string& fb = b.fs_body;
  if (detail::per_pixel_normal(f.shading)) {
    fb += "  vec3 n = normalize(v_normal);\n";
    if (f.double_sided) fb += "  if (!gl_FrontFacing) n = -n;\n";
  }
  if (!f.normal_texture) return;
  b.uniform(Stage::Fragment, "u_normal_scale", "float", UniformSemantic::NormalScale);
  if (f.has_tangents) {
    fb += "  vec3 t = normalize(v_tangent.xyz - n * dot(n, v_tangent.xyz));\n";
    fb += "  vec3 bt = cross(n, t) * v_tangent.w;\n";
    if (f.double_sided) fb += "  if (!gl_FrontFacing) { t = -t; bt = -bt; }\n";
  } else {
    b.fs_functions += detail::kCotangentFrame;
    fb += "  mat3 tbn_derived = cotangent_frame(n, v_world_position, uv_normal);\n";
    fb += "  vec3 t = tbn_derived[0];\n  vec3 bt = tbn_derived[1];\n";
  }
  fb += "  vec3 tn = texture(u_normal_texture, uv_normal).xyz * 2.0 - 1.0;\n";
  fb += "  tn.xy *= u_normal_scale;\n";
  fb += "  n = normalize(mat3(t, bt, n) * tn);\n";
}

// The view vector `v` (where the model needs it) and the ambient occlusion `ao`.
void view_and_occlusion(GlslBuilder& b, const MaterialFeatures& f, const Needs& need) {
  std::string& fb = b.fs_body;
  if (need.view_vector) {
    b.uniform(Stage::Fragment, "u_camera_position", "vec3", UniformSemantic::CameraPosition);
    fb += "  vec3 v = normalize(u_camera_position - v_world_position);\n";
  }
  fb += "  float ao = 1.0;\n";
  if (f.occlusion_texture) {
    b.uniform(Stage::Fragment, "u_occlusion_strength", "float",
              UniformSemantic::OcclusionStrength);
    fb += "  ao += u_occlusion_strength * (texture(u_occlusion_texture, uv_occlusion).r - 1.0);\n";
  }
}

// Declares the world's light (the uniform ambient, or the environment's probe and ambient cube)
// and the light helpers of per-pixel models. Returns the expression of the environment's diffuse
// radiance for normal n, empty without an environment map.
std::string world_light(GlslBuilder& b, const MaterialFeatures& f) {
  // With an environment map the world's diffuse light comes from its ambient cube (below), so
  // the uniform ambient exists only in programs without one.
  if (!f.environment_map_2d)
    b.uniform(Stage::Fragment, "u_ambient_light", "vec3", UniformSemantic::AmbientLight);
  std::string env_diffuse;
  if (f.environment_map_2d) {
    b.sampler("u_environment_texture", TextureSlot::Environment);
    b.uniform(Stage::Fragment, "u_environment_intensity", "float",
              UniformSemantic::EnvironmentIntensity);
    static const char* kAxis[6] = {"px", "nx", "py", "ny", "pz", "nz"};
    std::string args;
    for (int i = 0; i < 6; ++i) {
      const std::string name = std::string("u_environment_irradiance_") + kAxis[i];
      b.uniform(Stage::Fragment, name, "vec3", UniformSemantic::EnvironmentIrradiance, i);
      args += ", " + name;
    }
    b.fs_functions += detail::kAmbientCube;
    env_diffuse = "ambient_cube(n" + args + ")";
  }
  if (detail::per_pixel_normal(f.shading) && f.lights.total() > 0) b.fs_functions += light_helpers(f.lights);
  return env_diffuse;
}

// glTF metallic-roughness: the lights through the PBR BRDF, then the world's light split into
// diffuse and specular by the split-sum approximation.
void shade_pbr(GlslBuilder& b, const MaterialFeatures& f, const std::string& env_diffuse) {
  std::string& fb = b.fs_body;
  b.uniform(Stage::Fragment, "u_metallic_factor", "float", UniformSemantic::MetallicFactor);
  b.uniform(Stage::Fragment, "u_roughness_factor", "float", UniformSemantic::RoughnessFactor);
  fb += "  float metallic = u_metallic_factor;\n  float roughness = u_roughness_factor;\n";
  if (f.metallic_roughness_texture) {
    fb += "  vec4 mr = texture(u_metallic_roughness_texture, uv_metallic_roughness);\n";
    fb += "  roughness *= mr.g;\n  metallic *= mr.b;\n";
  }
  fb += std::string("  roughness = clamp(roughness, ") +
        (f.precision == Precision::Highp ? "0.045" : "0.089") +
        ", 1.0);  // keeps GGX finite (and representable in mediump)\n";
  fb += "  metallic = clamp(metallic, 0.0, 1.0);\n";
  fb += "  vec3 c_diff = mix(base_color.rgb, vec3(0.0), metallic);\n";
  fb += "  vec3 f0 = mix(vec3(0.04), base_color.rgb, metallic);\n";
  fb += "  float alpha = roughness * roughness;\n";
  fb += "  float n_dot_v = max(dot(n, v), 1e-4);\n";
  fb += "  vec3 color = vec3(0.0);\n";
  if (f.lights.total() > 0) {
    b.fs_functions += detail::kPbrBrdf;
    fb += light_loop(b, Stage::Fragment, f.lights, "v_world_position",
                     "    color += pbr_light(n, v, l, e, c_diff, f0, alpha);\n");
  }
  b.fs_functions += detail::kEnvBrdfApprox;
  fb += "  vec3 specular_weight = env_brdf_approx(f0, roughness, n_dot_v);\n";
  if (f.environment_map_2d) {
    // EEVEE's world-probe lookup (Blender 3.x probe_evaluate_world_spec): level sqrt(roughness)
    // times the last level, whose lobes the converter prefiltered (bridge::EnvironmentProbe).
    // No footprint term: a level's lobe, not its texel size, sets its blur, so a footprint-chosen
    // level blurs far more than the pixel sees (reflection 19.12 dB object with it, 33.60
    // without); sharp mirrors are shaded per MSAA sample instead (docs/scene-config.md).
    fb += "  vec3 r = reflect(-v, n);\n";
    fb += "  float probe_size = float(textureSize(u_environment_texture, 0).x);\n";
    fb += "  float env_lod = sqrt(roughness) * (log2(probe_size) - " + std::to_string(bridge::kProbeSmallestFaceLog2) + ".0);\n";
    fb += "  vec3 environment = textureLod(u_environment_texture, r, env_lod).rgb * u_environment_intensity;\n";
    fb += "  color += (c_diff * " + env_diffuse + " + specular_weight * environment) * ao;\n";
  } else {
    fb += "  color += (c_diff + specular_weight) * u_ambient_light * ao;\n";
  }
}

// Blinn-Phong per pixel: Lambert plus a specular lobe per light, the environment as a mirror.
void shade_blinn_phong(GlslBuilder& b, const MaterialFeatures& f, const std::string& env_diffuse) {
  std::string& fb = b.fs_body;
  const int lights = f.lights.total();
  fb += "  vec3 color = vec3(0.0);\n";
  const bool specular = lights > 0 || f.environment_map_2d;
  if (specular)
    b.uniform(Stage::Fragment, "u_specular_color", "vec3", UniformSemantic::SpecularColor);
  if (lights > 0) {
    b.uniform(Stage::Fragment, "u_shininess", "float", UniformSemantic::Shininess);
    b.fs_functions += detail::kBlinnPhongSpecular;
    fb += light_loop(b, Stage::Fragment, f.lights, "v_world_position",
                     "    float n_dot_l = max(dot(n, l), 0.0);\n"
                     "    color += e * n_dot_l * (base_color.rgb / PI + u_specular_color * "
                     "blinn_phong_specular(n, v, l, u_shininess));\n");
  }
  if (f.environment_map_2d) {
    fb += "  color += base_color.rgb * " + env_diffuse + " * ao;\n";
    fb += "  vec3 r = reflect(-v, n);\n";
    // No roughness: a mirror, the probe's sharp level 0 (EEVEE's lookup at roughness 0); the
    // scene's "sample_shading": "mirrors" averages it inside the pixel.
    fb += "  color += u_specular_color * textureLod(u_environment_texture, r, 0.0).rgb * "
          "u_environment_intensity * ao;\n";
  } else {
    fb += "  color += base_color.rgb * u_ambient_light * ao;\n";
  }
}

// Flat: Lambert of the face, computed at its provoking vertex (light_vertex_flat).
void shade_flat(GlslBuilder& b, const Needs& need) {
  b.fs_body += need.flat_light ? "  vec3 color = base_color.rgb * (v_flat_light + u_ambient_light * ao);\n"
                               : "  vec3 color = base_color.rgb * u_ambient_light * ao;\n";
}

// Gouraud: the lighting came from the vertex stage.
void shade_gouraud(GlslBuilder& b, const Needs& need) {
  b.fs_body += need.gouraud_light
                   ? "  vec3 color = base_color.rgb * (v_diffuse_light + u_ambient_light * ao) + "
                     "v_specular_light;\n"
                   : "  vec3 color = base_color.rgb * u_ambient_light * ao;\n";
}

// A lit model's colour: its normal, view vector and occlusion, the world's light, then the model.
void shade_lit(GlslBuilder& b, const MaterialFeatures& f, const Needs& need) {
  surface_normal(b, f);
  view_and_occlusion(b, f, need);
  const std::string env_diffuse = world_light(b, f);
  switch (f.shading) {
    case ShadingModel::PbrMetallicRoughness: shade_pbr(b, f, env_diffuse); break;
    case ShadingModel::BlinnPhong: shade_blinn_phong(b, f, env_diffuse); break;
    case ShadingModel::Flat: shade_flat(b, need); break;
    default: shade_gouraud(b, need); break;
  }
}

// Emission (lit models only) and the exposed, linear output colour.
void write_output(GlslBuilder& b, const MaterialFeatures& f) {
  std::string& fb = b.fs_body;
  if (f.shading != ShadingModel::Unlit) {
    b.uniform(Stage::Fragment, "u_emissive_factor", "vec3", UniformSemantic::EmissiveFactor);
    fb += "  vec3 emissive = u_emissive_factor;\n";
    if (f.emissive_texture)
      fb += "  emissive *= texture(u_emissive_texture, uv_emissive).rgb;  // sRGB texture -> linear\n";
    fb += "  color += emissive;\n";
  }
  b.uniform(Stage::Fragment, "u_exposure", "float", UniformSemantic::Exposure);
  // Linear output: the render target encodes sRGB on write.
  fb += std::string("  o_color = vec4(color * u_exposure, ") +
        (f.alpha == AlphaMode::Blend ? "base_color.a" : "1.0") + ");\n";
}

void write_fragment_stage(GlslBuilder& b, const MaterialFeatures& f, const Needs& need) {
  sample_coordinates(b, f);
  base_color(b, f);
  if (f.shading == ShadingModel::Unlit)
    b.fs_body += "  vec3 color = base_color.rgb;\n";
  else
    shade_lit(b, f, need);
  write_output(b, f);
}

}  // namespace

Program generate(const MaterialFeatures& requested) {
  const MaterialFeatures f = canonical(requested);  // validates; throws std::invalid_argument
  const Needs need = analyse(f);
  GlslBuilder b(f.precision);
  write_vertex_stage(b, f, need);
  write_fragment_stage(b, f, need);
  Program& p = b.program();
  p.features = f;
  p.blend = f.alpha == AlphaMode::Blend;
  p.cull_back_faces = !f.double_sided;
  return b.finish("meter shadergen: " + program_key(f));
}

}  // namespace meter::shadergen
