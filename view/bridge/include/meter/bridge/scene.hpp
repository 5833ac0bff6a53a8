// The scene model shared by the converter (glTF -> Scene -> package) and the runtime
// (package -> Scene -> GPU). Plain data only: everything the runtime needs is decided at
// conversion time (vertex layouts, which program each draw uses, decoded textures), so loading a
// package is a bounds-checked copy and nothing about the glTF file survives into the runtime.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "meter/bridge/draw_levels.hpp"
#include "meter/bridge/integrity.hpp"
#include "meter/bridge/program.hpp"
#include "meter/bridge/scene_config.hpp"

namespace meter::bridge {

// Every conversion / load failure. The message names the file and the element
// ("nodes[3].rotation: quaternion not unit length (|q| = 1.2)").
struct SceneError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class Interpolation : std::uint8_t { Linear = 0, Step = 1, CubicSpline = 2 };
enum class TargetPath : std::uint8_t { Translation = 0, Rotation = 1, Scale = 2, Weights = 3 };

// One glTF animation sampler, already converted to float. `components` floats per key
// (3 T/S, 4 R as x,y,z,w, N for weights). CUBICSPLINE stores (in-tangent, value, out-tangent) per key,
// i.e. 3 * components floats per key, exactly as glTF does.
struct AnimSampler {
  Interpolation interpolation = Interpolation::Linear;
  int components = 0;
  std::vector<float> input;   // key times, seconds, strictly increasing after conversion
  std::vector<float> output;
};

struct AnimChannel {
  int sampler = -1;
  int node = -1;
  TargetPath path = TargetPath::Translation;
};

struct Animation {
  std::string name;
  std::vector<AnimSampler> samplers;
  std::vector<AnimChannel> channels;
  float start = 0.0f, end = 0.0f;  // min / max key time over all samplers
};

struct Node {
  std::string name;
  int parent = -1;
  std::vector<int> children;
  glm::vec3 translation{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};  // glm order w, x, y, z
  glm::vec3 scale{1.0f};
  int mesh = -1, camera = -1, light = -1, skin = -1;
  std::vector<float> weights;  // morph weights (node's, else the mesh's defaults)
};

// Where one attribute sits inside a primitive's interleaved vertex record (offsets in floats).
struct VertexAttribute {
  AttributeSemantic semantic{};
  int index = -1;  // morph target index for MorphPosition / MorphNormal
  int components = 0;
  int offset = 0;
};

struct Primitive {
  int material = -1;  // -1 = glTF default material (converter always assigns one)
  std::uint32_t vertex_count = 0;
  int stride = 0;  // floats per vertex
  std::vector<VertexAttribute> layout;
  std::vector<float> vertices;          // vertex_count * stride
  std::vector<std::uint32_t> indices;   // triangles; always present (generated when absent)
  glm::vec3 bounds_min{0.0f}, bounds_max{0.0f};  // POSITION bounds (no morph)
  int morph_targets = 0;
  std::vector<LodLevel> lods;  // cheaper index lists, most detailed first (draw_levels.hpp)
  // The triangles of `indices` as a Flat program draws them: each rotated (winding kept) so that
  // its last, provoking vertex carries the face normal, on a copy of a corner appended to the
  // vertices where no corner's own normal is the face's. Empty: no Flat program draws the
  // primitive (or it is skinned: its normals follow the pose), and Flat draws `indices`.
  std::vector<std::uint32_t> flat_indices{};
};

struct Mesh {
  std::string name;
  std::vector<Primitive> primitives;
  std::vector<float> weights;  // default morph weights
};

// glTF metallic-roughness material, plus the shading model the scene config picked.
struct Material {
  std::string name;
  ShadingModel shading = ShadingModel::PbrMetallicRoughness;
  AlphaMode alpha = AlphaMode::Opaque;
  bool double_sided = false;
  glm::vec4 base_color{1.0f};
  glm::vec3 emissive{0.0f};  // already multiplied by KHR_materials_emissive_strength
  float metallic = 1.0f, roughness = 1.0f, normal_scale = 1.0f, occlusion_strength = 1.0f;
  float alpha_cutoff = 0.5f;
  glm::vec3 specular_color{0.5f};  // Blinn-Phong / Gouraud
  float shininess = 32.0f;
  // Per TextureSlot (BaseColor .. Occlusion; Environment unused: it is scene-wide,
  // Scene::environment): texture index or -1, texcoord set, KHR_texture_transform matrix
  // (identity when absent).
  std::array<int, 6> texture{-1, -1, -1, -1, -1, -1};
  std::array<int, 6> texcoord{0, 0, 0, 0, 0, 0};
  std::array<glm::mat3, 6> uv_transform{glm::mat3(1.0f), glm::mat3(1.0f), glm::mat3(1.0f),
                                        glm::mat3(1.0f), glm::mat3(1.0f), glm::mat3(1.0f)};
  bool has_uv_transform = false;
};

// Decoded RGBA8 image plus its sampler state (GL enums). `srgb` = the data is sRGB-encoded colour
// (base colour, emissive) and must be uploaded as SRGB8_ALPHA8 so sampling returns linear values.
struct Texture {
  std::string name;
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgba;
  bool srgb = false;
  int min_filter = 0x2703 /*LINEAR_MIPMAP_LINEAR*/, mag_filter = 0x2601 /*LINEAR*/;
  int wrap_s = 0x2901 /*REPEAT*/, wrap_t = 0x2901;
  // EXT_texture_filter_anisotropic degree; 1 = off. 2 by default: what EEVEE samples image
  // textures with (Blender's factory preference, Viewport > Textures > Anisotropic Filtering 2x;
  // the references are rendered with it). The quality ladder sets another at load time; not
  // stored in packages (a runtime choice like MSAA). The scene's environment map is never
  // filtered anisotropically (GpuScene): it is read at explicit LODs (the reflection footprint).
  float max_anisotropy = 2.0f;
};

struct Camera {
  std::string name;
  bool perspective = true;
  float yfov = 0.8f, znear = 0.05f, zfar = 1000.0f;  // zfar <= 0: infinite
  float xmag = 1.0f, ymag = 1.0f;                      // orthographic
};

enum class LightType : std::uint8_t { Directional = 0, Point = 1, Spot = 2 };

struct Light {
  std::string name;
  LightType type = LightType::Directional;
  glm::vec3 color{1.0f};
  float intensity = 1.0f;
  float range = 0.0f;  // 0 = infinite
  float inner_cone = 0.0f, outer_cone = 0.7853982f;
  // Casts shadows (Blender's use_shadow; glTF light extras `meter_cast_shadow`): the light gets a
  // shadow map and its pass, lit programs a shadow lookup for it. Directional and spot lights.
  bool cast_shadow = false;
};

struct Skin {
  std::string name;
  std::vector<int> joints;
  std::vector<glm::mat4> inverse_bind;
};

// One generated program and the draws that use it.
struct ProgramEntry {
  Program program;
  OptimizeReport optimize_report;  // all zero when --optimize=off
};

// One draw: a primitive of the mesh on `node`, drawn with `program`. Programs depend on the node
// (skin, scene lights) as well as on the material, so the converter resolves them per draw.
struct DrawItem {
  int node = -1, mesh = -1, primitive = -1, program = -1;
};

// Mesh concatenation (the DENSO engine's draw-call reduction): draws merged into one draw at runtime.
// `draws` index Scene::draws in draw order; draws[0] (the first in traversal order) is the
// representative whose place in the sorted draw list the merged draw takes. All members share one
// program, which has the vertex_alpha feature (visibility), no skin and no morph targets.
struct MergedGroup {
  std::string name;
  std::vector<int> draws;
};

// EEVEE's world reflection probe (Blender 3.x): a cube map rendered from the world and
// GGX-prefiltered per mip level. The converter bakes it from the equirectangular image
// (meter/convert/environment_probe.hpp); the runtime uploads it as a cube map and reads it at
// level sqrt(roughness) * (levels - 1), as EEVEE's probe_evaluate_world_spec does.
//   Level L (face face_size >> L) holds the radiance around each texel's direction filtered by a
// GGX lobe of alpha (L / (levels - 1))^4 (Disney alpha = roughness^2 at that level's lookup): level
// 0 is the world as seen, the last level is lit by the whole hemisphere. The smallest face is 8
// texels (kProbeSmallestFaceLog2), so levels = log2(face_size) - 2.
struct EnvironmentProbe {
  static constexpr int levels_for(int face_size) {
    int log2 = 0;
    while ((1 << (log2 + 1)) <= face_size) ++log2;
    return log2 - kProbeSmallestFaceLog2 + 1;
  }
  int face_size = 0;  // level 0, texels per side (a power of two >= 8); 0 = no probe
  int levels = 0;     // levels_for(face_size)
  // sRGB-encoded RGB, 3 bytes per texel: level 0 first; in each level the faces +X, -X, +Y, -Y,
  // +Z, -Z (glTF axes; GL's cube-face order and texel orientation), each face row by row.
  std::vector<std::uint8_t> rgb;
  static std::size_t byte_size(int face_size, int levels) {
    std::size_t n = 0;
    for (int l = 0; l < levels; ++l) n += 6u * 3u * std::size_t(face_size >> l) * std::size_t(face_size >> l);
    return n;
  }
};

// The world's environment (glTF scene extras `meter_environment`, the equirectangular image
// Blender's world shader samples; docs/engine.md, "Environment"). Only scenes that name one have
// it; programs then get the environment_map_2d feature (and only then).
struct Environment {
  EnvironmentProbe probe;  // specular: the image baked into EEVEE's prefiltered cube probe
  float strength = 1.0f;   // Blender's Background strength (`meter_environment_strength`)
  // Diffuse light from the map as EEVEE stores it for the world (an "ambient cube"): the
  // cosine-weighted mean linear radiance (times strength) around +X, -X, +Y, -Y, +Z, -Z (glTF axes),
  // i.e. irradiance / pi. A normal n receives sum(n_i^2 * side(sign n_i, i)).
  std::array<glm::vec3, 6> irradiance{};
  bool present() const { return probe.levels > 0; }
};

// The font the scene's texts are drawn with, carried in the package (chunk FONT) so that the view
// opens no font file: the TrueType / OpenType file the converter found (the config's "font", else
// DejaVu Sans), byte for byte, read by FreeType from memory. Empty for a scene that draws no text.
struct SceneFont {
  std::string name;                // the file's name, for messages ("DejaVuSans.ttf")
  std::vector<std::uint8_t> data;  // the whole font file
  bool present() const { return !data.empty(); }
};

struct Scene {
  std::vector<Node> nodes;
  std::vector<int> roots;
  std::vector<Mesh> meshes;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<Camera> cameras;
  std::vector<Light> lights;
  std::vector<Skin> skins;
  std::vector<Animation> animations;
  std::vector<ProgramEntry> programs;
  std::vector<DrawItem> draws;
  std::vector<MergedGroup> groups;  // planned by the converter (meter/convert/concat_plan.hpp), checked on load (meter/engine/merged_draws.hpp)
  SceneConfig config;            // validated against this scene at conversion time
  std::string source_name;       // input file name, for messages
  glm::vec3 ambient{0.0f};       // config "ambient" (linear)
  Environment environment;       // from the glTF scene extras; absent for most scenes
  IntegrityTable integrity;      // safety regions measured by the converter (integrity.hpp); empty without telltale / needle / readout bindings
  std::vector<DrawLevels> draw_levels;  // per draw, or empty: every draw at level 0 (draw_levels.hpp)
  SceneFont font;                // the texts' font (config_draws_text), embedded by the converter

  int find_node(std::string_view name) const;       // -1 when absent
  int find_material(std::string_view name) const;
  int find_animation(std::string_view name) const;
};

// The scene's one traversal order: depth first from each root in turn, every node before its
// children, children in their glTF order (the order draws, lights and merged groups are listed in).
// Nodes no root reaches are left out.
std::vector<int> node_preorder(const Scene& scene);

// The light nodes in the order the programs index their light uniforms: node_preorder, then
// stably grouped by type (directional, point, spot). The converter generates programs for this
// order and the runtime sets light uniforms in it.
std::vector<int> light_order(const Scene& scene);

// Which lights of `light_nodes` (light_order) have a shadow map: bit i = light_nodes[i]. The first
// kMaxShadowMaps directional or spot lights that cast shadows, in that order. The converter gives
// programs their shadow lookups by this mask and the runtime draws exactly these maps.
unsigned shadow_map_lights(const Scene& scene, const std::vector<int>& light_nodes);

}  // namespace meter::bridge
