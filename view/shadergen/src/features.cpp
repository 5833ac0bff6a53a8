// Feature sets: validation, canonical form and the program key, the last two from the list of
// material terms (meter/bridge/material_feature_fields.hpp; the names are the vocabulary's,
// view/bridge/src/program_names.cpp).
#include "features.hpp"

#include "meter/bridge/material_feature_fields.hpp"

#include <bit>
#include <stdexcept>
#include <string>

namespace meter::shadergen {

namespace detail {

bool any_material_texture(const MaterialFeatures& f) {
  return f.base_color_texture || f.metallic_roughness_texture || f.normal_texture ||
         f.emissive_texture || f.occlusion_texture;
}

bool per_pixel_normal(ShadingModel m) {
  return m == ShadingModel::BlinnPhong || m == ShadingModel::PbrMetallicRoughness;
}

int attribute_count(const MaterialFeatures& f) {
  int n = 1;  // POSITION
  const bool normals = bridge::feature_terms::smooth_normals(f);
  if (f.shading != ShadingModel::Unlit) ++n;  // NORMAL (Flat's: the face's, at the provoking vertex)
  if (f.normal_texture && f.has_tangents) ++n;
  bool uv0 = false, uv1 = false;
  for (int s = 0; s <= static_cast<int>(TextureSlot::Occlusion); ++s) {
    const auto slot = static_cast<TextureSlot>(s);
    if (!bridge::feature_terms::has(f, slot)) continue;
    (bridge::feature_terms::texcoord1(f, slot) ? uv1 : uv0) = true;
  }
  n += int(uv0) + int(uv1);
  if (f.vertex_colors) ++n;
  if (f.vertex_alpha) ++n;
  if (f.skin_joints > 0) n += 2;
  n += f.morph_targets;
  if (f.morph_normals && normals) n += f.morph_targets;
  return n;
}

void validate(const MaterialFeatures& f) {
  auto fail = [](const std::string& what) {
    throw std::invalid_argument("shadergen: invalid material features: " + what);
  };
  const char* model = to_string(f.shading);
  if (f.skin_joints < 0 || f.skin_joints > kMaxSkinJoints)
    fail("skin_joints = " + std::to_string(f.skin_joints) + ", expected 0.." +
         std::to_string(kMaxSkinJoints));
  if (f.morph_targets < 0 || f.morph_targets > kMaxMorphTargets)
    fail("morph_targets = " + std::to_string(f.morph_targets) + ", expected 0.." +
         std::to_string(kMaxMorphTargets));
  if (f.morph_normals && f.morph_targets == 0)
    fail("morph_normals is set but morph_targets = 0");
  if (f.lights.directional < 0 || f.lights.point < 0 || f.lights.spot < 0)
    fail("light counts must not be negative");
  if (f.lights.total() > kMaxLights)
    fail("lights = " + std::to_string(f.lights.total()) + ", expected at most " +
         std::to_string(kMaxLights));
  if (f.lights.total() < 32 && (f.lights.shadows >> f.lights.total()) != 0)
    fail("shadows names light bits beyond the " + std::to_string(f.lights.total()) + " lights");
  if (std::popcount(f.lights.shadows) > kMaxShadowMaps)
    fail("shadows = " + std::to_string(std::popcount(f.lights.shadows)) + " shadow maps, expected at most " +
         std::to_string(kMaxShadowMaps));
  for (int i = f.lights.directional; i < f.lights.directional + f.lights.point; ++i)
    if (f.lights.casts_shadow(i)) fail("shadows names point light " + std::to_string(i) + " (only directional and spot lights have shadow maps)");
  if (f.metallic_roughness_texture && f.shading != ShadingModel::PbrMetallicRoughness)
    fail(std::string("metallic_roughness_texture needs shading = pbr, got ") + model);
  if (f.normal_texture && !per_pixel_normal(f.shading))
    fail(std::string("normal_texture needs per-pixel shading (blinn-phong or pbr), got ") + model);
  if (f.environment_map_2d && !per_pixel_normal(f.shading))
    fail(std::string("environment_map_2d needs per-pixel shading (blinn-phong or pbr), got ") +
         model);
  if (f.occlusion_texture && f.shading == ShadingModel::Unlit)
    fail("occlusion_texture has no effect on unlit shading (it only scales ambient light)");
  if (f.emissive_texture && f.shading == ShadingModel::Unlit)
    fail("emissive_texture has no effect on unlit shading (KHR_materials_unlit ignores emission)");
  if (f.texture_transform && !any_material_texture(f))
    fail("texture_transform is set but the material has no texture");
  constexpr unsigned kEnvBit = 1u << static_cast<unsigned>(TextureSlot::Environment);
  if (f.texcoord1_slots & ~((kEnvBit << 1) - 1))
    fail("texcoord1_slots has bits beyond the known texture slots");
  if (f.texcoord1_slots & kEnvBit)
    fail("texcoord1_slots: the environment map is addressed by direction, not by TEXCOORD_1");
  for (int s = 0; s <= static_cast<int>(TextureSlot::Occlusion); ++s) {
    const auto slot = static_cast<TextureSlot>(s);
    if (bridge::feature_terms::texcoord1(f, slot) && !bridge::feature_terms::has(f, slot))
      fail(std::string("texcoord1_slots names the ") + to_string(slot) +
           " texture, which the material does not have");
  }
  if (attribute_count(f) > 16)
    fail("needs " + std::to_string(attribute_count(f)) +
         " vertex attributes, GLES 3.0 guarantees 16 (reduce morph targets)");
}

}  // namespace detail

// The canonical form and the key follow the one list of material terms
// (meter/bridge/material_feature_fields.hpp): each term says whether the canonical form keeps it
// and what it adds to the key.
MaterialFeatures canonical(const MaterialFeatures& features) {
  detail::validate(features);
  MaterialFeatures c = features;
  const MaterialFeatures defaults{};
  bridge::feature_fields([&](const bridge::FeatureField& term, auto& value, const auto& initial) {
    if (!term.kept(c)) value = initial;
  }, c, defaults);
  return c;
}

std::string program_key(const MaterialFeatures& features) {
  const MaterialFeatures c = canonical(features);
  std::string k;
  bridge::feature_fields([&](const bridge::FeatureField& term, const auto&) { term.key(k, c); }, c);
  return k;
}

}  // namespace meter::shadergen
