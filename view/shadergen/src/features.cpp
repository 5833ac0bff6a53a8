// Feature sets: validation, canonical form and the program-cache key (the names are the
// vocabulary's, view/bridge/src/program_names.cpp).
#include "features.hpp"

#include <bit>
#include <stdexcept>
#include <string>

namespace meter::shadergen {

namespace detail {

bool has_texture(const MaterialFeatures& f, TextureSlot slot) {
  switch (slot) {
    case TextureSlot::BaseColor: return f.base_color_texture;
    case TextureSlot::MetallicRoughness: return f.metallic_roughness_texture;
    case TextureSlot::Normal: return f.normal_texture;
    case TextureSlot::Emissive: return f.emissive_texture;
    case TextureSlot::Occlusion: return f.occlusion_texture;
    case TextureSlot::Environment: return f.environment_map_2d;
    case TextureSlot::ShadowMap: return f.lights.shadows != 0;
  }
  return false;
}

bool uses_texcoord1(const MaterialFeatures& f, TextureSlot slot) {
  return (f.texcoord1_slots & (1u << static_cast<unsigned>(slot))) != 0;
}

bool any_material_texture(const MaterialFeatures& f) {
  return f.base_color_texture || f.metallic_roughness_texture || f.normal_texture ||
         f.emissive_texture || f.occlusion_texture;
}

bool is_lit(ShadingModel m) { return m != ShadingModel::Unlit; }

bool per_pixel_normal(ShadingModel m) {
  return m == ShadingModel::BlinnPhong || m == ShadingModel::PbrMetallicRoughness;
}

int attribute_count(const MaterialFeatures& f) {
  int n = 1;  // POSITION
  const bool normals = f.shading != ShadingModel::Unlit && f.shading != ShadingModel::Flat;
  if (normals) ++n;
  if (f.normal_texture && f.has_tangents) ++n;
  bool uv0 = false, uv1 = false;
  for (int s = 0; s <= static_cast<int>(TextureSlot::Occlusion); ++s) {
    const auto slot = static_cast<TextureSlot>(s);
    if (!has_texture(f, slot)) continue;
    (uses_texcoord1(f, slot) ? uv1 : uv0) = true;
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
    if (uses_texcoord1(f, slot) && !has_texture(f, slot))
      fail(std::string("texcoord1_slots names the ") + to_string(slot) +
           " texture, which the material does not have");
  }
  if (attribute_count(f) > 16)
    fail("needs " + std::to_string(attribute_count(f)) +
         " vertex attributes, GLES 3.0 guarantees 16 (reduce morph targets)");
}

}  // namespace detail

MaterialFeatures canonical(const MaterialFeatures& features) {
  detail::validate(features);
  MaterialFeatures c = features;
  // Data the shading model never reads does not change the program: drop it so equal programs
  // share one key (and one cache entry).
  if (c.shading == ShadingModel::Unlit) c.lights = {};
  // Shadow lookups exist in per-pixel light loops only (Gouraud lights per vertex: a cheaper
  // quality level that drops shadows with the rest of the per-pixel work).
  if (!detail::per_pixel_normal(c.shading) && c.shading != ShadingModel::Flat) c.lights.shadows = 0;
  if (!c.normal_texture) c.has_tangents = false;
  if (c.shading == ShadingModel::Unlit || c.shading == ShadingModel::Flat) c.morph_normals = false;
  return c;
}

std::string program_key(const MaterialFeatures& features) {
  const MaterialFeatures c = canonical(features);
  std::string k = to_string(c.shading);
  k += '|';
  k += to_string(c.alpha);
  k += c.precision == Precision::Highp ? "|highp" : "|mediump";
  k += "|tex:";
  const char* tex_codes[] = {"b", "m", "n", "e", "o", "env"};
  for (int s = 0; s <= static_cast<int>(TextureSlot::Environment); ++s) {
    const auto slot = static_cast<TextureSlot>(s);
    if (!detail::has_texture(c, slot)) continue;
    k += tex_codes[s];
    if (detail::uses_texcoord1(c, slot)) k += '1';
  }
  if (c.texture_transform) k += "|tt";
  if (c.vertex_colors) k += "|vc";
  if (c.vertex_alpha) k += "|va";
  if (c.double_sided) k += "|ds";
  if (c.skin_joints) k += "|skin" + std::to_string(c.skin_joints);
  if (c.morph_targets) k += "|morph" + std::to_string(c.morph_targets) + (c.morph_normals ? "n" : "");
  if (c.lights.total())
    k += "|L" + std::to_string(c.lights.directional) + "." + std::to_string(c.lights.point) + "." +
         std::to_string(c.lights.spot);
  if (c.lights.shadows) k += "|S" + std::to_string(c.lights.shadows);
  if (c.has_tangents) k += "|tan";
  return k;
}

}  // namespace meter::shadergen
