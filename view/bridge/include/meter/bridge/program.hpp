// The program vocabulary shared by the offline shader generator (meter::shadergen, inside
// meter-convert) and the runtime (meter::engine, inside meter-view): what a generated program
// needs from its draw (attributes, uniforms with their semantics, samplers, blend state) and the
// feature set it was generated from. Plain data only. The runtime reads programs from the scene
// package through these types and never includes, or links, the generator.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace meter::bridge {

enum class ShadingModel { Unlit, Flat, Gouraud, BlinnPhong, PbrMetallicRoughness };
enum class AlphaMode { Opaque, Mask, Blend };
enum class Precision { Mediump, Highp };

// How many KHR_lights_punctual lights of each type the program evaluates (scene-wide), and which
// of them cast shadows: bit i of `shadows` = light i of the program's light list (directionals,
// then points, then spots) has a shadow map. Only the lights the scene says cast shadows
// (Blender's use_shadow, exported as the light's extras) get one.
struct LightCounts {
  int directional = 0, point = 0, spot = 0;
  unsigned shadows = 0;
  int total() const { return directional + point + spot; }
  bool casts_shadow(int light) const { return light >= 0 && light < 32 && (shadows >> light) & 1u; }
  bool operator==(const LightCounts&) const = default;
};

// Environment: the world's reflection probe, a cube map (samplerCube, scene.hpp EnvironmentProbe).
// ShadowMap: a light's depth map (SamplerInfo::index = the light's place in the light list),
// sampled with depth comparison (sampler2DShadow).
enum class TextureSlot { BaseColor, MetallicRoughness, Normal, Emissive, Occlusion, Environment, ShadowMap };

// The reflection probe's smallest level is 2^3 = 8 texels per face (EEVEE's MIN_CUBE_LOD_LEVEL):
// the converter bakes levels down to it and the programs read level sqrt(roughness) *
// (log2(face size) - 3), the last one.
inline constexpr int kProbeSmallestFaceLog2 = 3;

// Limits that keep every generated program inside the GLES 3.0 minimums
// (16 vertex attributes, 256 vertex uniform vectors, 16 texture units).
inline constexpr int kMaxSkinJoints = 48;   // 48 mat4 = 192 vectors, leaves room for the rest
inline constexpr int kMaxMorphTargets = 8;  // further bounded by the 16-attribute limit
inline constexpr int kMaxLights = 8;        // directional + point + spot
inline constexpr int kMaxShadowMaps = 4;    // lights with a shadow map (one texture unit each)

// Everything that changes the generated code. Values that only change uniform contents
// (factors, light colours, ...) are NOT here: they are uniforms, or constants after optimize().
struct MaterialFeatures {
  ShadingModel shading = ShadingModel::PbrMetallicRoughness;
  AlphaMode alpha = AlphaMode::Opaque;
  Precision precision = Precision::Highp;
  bool base_color_texture = false;
  bool metallic_roughness_texture = false;  // PBR only
  bool normal_texture = false;              // per-pixel models only (Flat, BlinnPhong, PBR)
  bool emissive_texture = false;
  bool occlusion_texture = false;
  // Bit (1 << int(TextureSlot::X)) set when texture X samples TEXCOORD_1 instead of TEXCOORD_0.
  unsigned texcoord1_slots = 0;
  bool texture_transform = false;  // KHR_texture_transform: one mat3 uniform per used texture
  bool vertex_colors = false;      // COLOR_0 (vec4) multiplies base colour
  bool vertex_alpha = false;       // mesh concatenation visibility (float attribute), multiplies alpha
  bool double_sided = false;       // no culling; back faces flip their normal
  int skin_joints = 0;             // 0 = no skinning; else size of the joint-matrix array
  int morph_targets = 0;           // 0 = no morphing; else number of POSITION targets/weights
  bool morph_normals = false;      // targets also carry NORMAL deltas
  LightCounts lights;
  // Equirectangular world image (lit per-pixel models): specular reflection from the texture,
  // diffuse from its ambient cube (EnvironmentIrradiance) instead of the uniform AmbientLight.
  bool environment_map_2d = false;
  bool has_tangents = false;        // TANGENT attribute present (else derived from derivatives)

  // The canonical form and the program key are the generator's: shadergen::canonical(),
  // shadergen::program_key().
  bool operator==(const MaterialFeatures&) const = default;
};

enum class UniformSemantic {
  ModelMatrix,         // mat4 object -> world
  ViewProjection,      // mat4 world -> clip
  NormalMatrix,        // mat3 inverse-transpose of the model matrix's upper 3x3
  CameraPosition,      // vec3 world-space eye
  BaseColorFactor,     // vec4 linear RGBA
  EmissiveFactor,      // vec3 linear (times KHR_materials_emissive_strength)
  MetallicFactor,      // float
  RoughnessFactor,     // float
  NormalScale,         // float
  OcclusionStrength,   // float
  AlphaCutoff,         // float (AlphaMode::Mask)
  SpecularColor,       // vec3 Blinn-Phong / Gouraud specular colour
  Shininess,           // float Blinn-Phong exponent
  AmbientLight,        // vec3 linear radiance of the world (Blender world colour * strength)
  // Light uniforms: index = the light's position in the program's light list, directionals
  // first, then points, then spots (lights.directional + lights.point + i for spot i).
  LightColor,          // vec3 linear
  LightIntensity,      // float, glTF units: lux (directional) or candela (point, spot)
  LightPosition,       // vec3 world (point, spot)
  LightDirection,      // vec3 world, direction the light travels (directional, spot)
  LightRange,          // float, <= 0 means infinite (glTF "range" absent)
  LightInnerConeCos,   // float cos(innerConeAngle)
  LightOuterConeCos,   // float cos(outerConeAngle)
  JointMatrices,       // mat4[N] joint world * inverse bind (relative to the mesh node)
  MorphWeights,        // float[N]
  TextureTransform,    // mat3, index = int(TextureSlot)
  EnvironmentIntensity,// float multiplier of the environment texture
  // vec3 diffuse light of the environment around one axis (index 0..5 = +X, -X, +Y, -Y, +Z, -Z):
  // cosine-weighted mean linear radiance, EEVEE's world "ambient cube" (environment_map_2d only)
  EnvironmentIrradiance,
  Exposure,            // float linear scale 2^exposure applied to the final colour (Blender: 0 -> 1)
  UberSwitches,        // ivec4 runtime switches of generate_uber() only (see docs/shaders.md)
  UberLightCounts,     // ivec3 directional/point/spot counts in use, generate_uber() only
  // mat4 world -> the light's shadow-map texture space ([0,1]^3 inside its frustum; index = the
  // light's place in the light list, as LightColor)
  LightShadowMatrix,
};

struct UniformInfo {
  std::string name;
  std::string glsl_type;  // "vec4", "mat4", "float", ...
  UniformSemantic semantic{};
  int index = -1;       // light list index / int(TextureSlot), -1 when not applicable
  int array_size = 1;   // element count of JointMatrices / MorphWeights (may be 1)

  // JointMatrices and MorphWeights are always declared as GLSL arrays, even with one element:
  // the shader indexes them (`u_morph_weights[0]`), so `float u_morph_weights;` would not compile.
  bool is_array() const {
    return array_size > 1 || semantic == UniformSemantic::JointMatrices ||
           semantic == UniformSemantic::MorphWeights;
  }
};

enum class AttributeSemantic {
  Position, Normal, Tangent, TexCoord0, TexCoord1, Color0, Joints0, Weights0,
  MorphPosition, MorphNormal, VertexAlpha
};

struct AttributeInfo {
  std::string name;
  AttributeSemantic semantic{};
  int index = -1;      // morph target index, -1 otherwise
  int location = 0;    // explicit layout(location) in the vertex shader
  int components = 0;  // float components (Joints0 is a float vec4 of joint indices)
};

struct SamplerInfo {
  std::string name;
  TextureSlot slot{};
  int unit = 0;    // texture unit the runtime binds (glUniform1i(name, unit))
  int index = -1;  // ShadowMap: the light's place in the light list; -1 otherwise
};

struct Program {
  std::string vertex_source, fragment_source;  // "#version 300 es": runs on EGL GLES3 and OSMesa
  std::vector<AttributeInfo> attributes;
  std::vector<UniformInfo> uniforms;  // only uniforms the runtime must set
  std::vector<SamplerInfo> samplers;
  MaterialFeatures features;  // canonical features this program was generated from
  bool blend = false;         // enable GL_BLEND (SRC_ALPHA, ONE_MINUS_SRC_ALPHA), no depth write
  bool cull_back_faces = true;
  bool optimized = false;     // went through optimize()
  bool uber = false;          // generate_uber() baseline

  // Lookups by semantic, as the runtime binds a draw.
  const UniformInfo* find_uniform(UniformSemantic semantic, int index = -1) const {
    for (const auto& u : uniforms)
      if (u.semantic == semantic && u.index == index) return &u;
    return nullptr;
  }
  const AttributeInfo* find_attribute(AttributeSemantic semantic, int index = -1) const {
    for (const auto& a : attributes)
      if (a.semantic == semantic && a.index == index) return &a;
    return nullptr;
  }
};

struct OptimizeReport {
  std::size_t source_bytes_before = 0, source_bytes_after = 0;
  std::size_t spirv_instructions_before = 0, spirv_instructions_after = 0;  // vertex + fragment
  std::size_t uniforms_before = 0, uniforms_after = 0;  // Program::uniforms (samplers excluded)
  std::size_t varyings_before = 0, varyings_after = 0;  // fragment-shader inputs
  std::size_t samplers_before = 0, samplers_after = 0;
  std::vector<std::string> folded;  // names of uniforms replaced by constants
};

// Human-readable names, used in program keys, tools and error messages.
const char* to_string(ShadingModel m);
const char* to_string(AlphaMode m);
const char* to_string(UniformSemantic s);
const char* to_string(AttributeSemantic s);
const char* to_string(TextureSlot s);

}  // namespace meter::bridge
