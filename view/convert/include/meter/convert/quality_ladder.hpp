// The quality ladder: settings an integrator trades against frame time, applied to a
// converted Scene before the Renderer is built (at load), globally or per object.
//
//   shading model   programs regenerated with another shadergen::ShadingModel (unlit .. PBR);
//   precision       programs regenerated with mediump or highp float precision;
//   LOD             meshoptimizer's meshopt_simplify keeps a fraction of each primitive's triangles;
//   texture filter  nearest / bilinear / trilinear / anisotropic (trilinear + 16x anisotropy)
//                   sampler state (global: textures are shared); unset: the glTF sampler with 2x
//                   anisotropy, as EEVEE samples image textures (Texture::max_anisotropy);
//   MSAA            1 / 2 / 4 / 8 samples: a RendererOptions value, carried here so one settings
//                   object describes a whole ladder point (the target clamps it to GL_MAX_SAMPLES,
//                   4 on llvmpipe, and says so);
//   interpolation   affine: varyings interpolated in screen space, without perspective
//                   correction (the EClay paper's trade), through GLES 3's
//                   NV_shader_noperspective_interpolation (Mesa has it; a driver without it
//                   fails to compile and says so). Global: every program is patched;
//   environment     off: drop the scene's environment map (programs regenerated without it; the
//                   config's uniform ambient lights the scene instead), as the engine drew before it
//                   supported environment maps. Only scenes that have one are affected;
//   resolve         box / blackman-harris: the MSAA resolve (the scene config's "resolve" filter;
//                   its width stays the config's), a RendererOptions-free setting: the Renderer
//                   reads it from the scene;
//   sample_shading  off / normal-maps / mirrors / normal-maps+mirrors: which materials are shaded
//                   once per MSAA sample (normal-mapped ones, sharp environment reflections), the
//                   others once per pixel (the scene config's "sample_shading"), read from the
//                   scene like the resolve.
//
// Why after conversion and not inside convert_gltf: the ladder is a runtime choice (the frame-rate
// governor picks a level on the target), and a Scene already holds the features
// every program was generated from, so nothing about the glTF is needed again.
// Regenerated programs are NOT constant-folded by shadergen::optimize() (the converter owns the
// folding constants): compare ladder points on a scene converted with optimize = false.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "meter/convert/vocabulary.hpp"
#include "meter/shadergen/shadergen.hpp"

namespace meter::convert {

enum class TextureFilter { Nearest, Bilinear, Trilinear, Anisotropic };

// One object's (or the global) choice; unset fields keep what the converter produced.
struct QualityOverride {
  std::optional<shadergen::ShadingModel> shading;
  std::optional<shadergen::Precision> precision;
  std::optional<float> lod;  // fraction of triangles kept, in (0, 1]; 1 = the original mesh
  bool operator==(const QualityOverride&) const = default;
};

struct QualitySettings {
  QualityOverride global;
  std::map<std::string, QualityOverride> objects;  // node name -> override; wins over global per field
  std::optional<TextureFilter> filter;             // all textures
  std::optional<int> msaa;                         // 1, 2, 4 or 8: give to RendererOptions::msaa
  std::optional<bool> environment;                 // false: no environment map (global)
  std::optional<bool> shadows;                     // false: no light casts shadows (global)
  std::optional<bool> affine;                      // true: no perspective correction (global)
  std::optional<bridge::ResolveConfig::Filter> resolve;  // the MSAA resolve filter (global)
  std::optional<bridge::ResolveConfig::SampleFormat> sample_format;  // the MSAA samples' storage (global)
  std::optional<bridge::SampleShading> sample_shading;   // per-sample shading of normal maps / mirrors (global)
};

struct QualityReport {
  int programs_regenerated = 0;
  int primitives_simplified = 0;
  std::size_t triangles_before = 0, triangles_after = 0;  // over the primitives that were simplified
  float max_simplify_error = 0.0f;  // meshoptimizer's relative error (fraction of the mesh extent)
  int groups_dropped = 0;           // merged groups whose members no longer share one program
  int textures_changed = 0;
  bool environment_dropped = false;  // the scene had an environment map and settings turned it off
  int shadow_maps_dropped = 0;       // lights that cast shadows in the scene and settings turned off
  int programs_made_affine = 0;
};

// Applies `settings` to `scene`. Throws SceneError for an unknown node name, a LOD outside (0, 1],
// an MSAA count other than 1/2/4/8, or a feature set shadergen rejects (message names the node).
QualityReport apply_quality(Scene& scene, const QualitySettings& settings);

// "pbr" | "blinn-phong" | "gouraud" | "flat" | "unlit" (the scene-config spelling); nullopt otherwise.
std::optional<shadergen::ShadingModel> parse_shading_model(const std::string& text);
const char* filter_name(TextureFilter f);  // "nearest" | "bilinear" | "trilinear" | "anisotropic"

// Parses a ladder point written as comma-separated key=value pairs, e.g.
// "shading=gouraud,precision=mediump,lod=0.5,filter=nearest,msaa=2,environment=off,interpolation=affine,
// resolve=blackman-harris,sample_shading=off"
// (every key optional; "" = no change). Throws SceneError naming the pair and what was expected.
QualitySettings parse_quality(const std::string& text);
// The canonical text of the global part ("shading=..,msaa=.." in a fixed order; "default" if empty).
std::string describe_quality(const QualitySettings& settings);

}  // namespace meter::convert
