// The one list of MaterialFeatures' terms. It drives everything that spells the features out:
// the package writer and reader, the record dump, the program cache's key, and the generator's
// canonical form and program key (shadergen::canonical, shadergen::program_key). A new material
// term is one member in program.hpp and one line here (plus what the generator does with it).
//
// Each line names the term and says two things about it:
//   key   its part of the program key, written from the canonical features in list order (so the
//         list order is the key's order; the key text is part of every generated source);
//   kept  whether the canonical form keeps it: false = data the shading model never reads, reset
//         to MaterialFeatures{}'s value so equal programs share one key and one cache entry.
#pragma once

#include <concepts>
#include <string>
#include <type_traits>

#include "meter/bridge/program.hpp"

namespace meter::bridge {

struct FeatureField {
  const char* name;
  void (*key)(std::string& out, const MaterialFeatures& canonical);
  bool (*kept)(const MaterialFeatures& f);
};

namespace feature_terms {

inline bool has(const MaterialFeatures& f, TextureSlot slot) {
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
inline bool texcoord1(const MaterialFeatures& f, TextureSlot slot) {
  return (f.texcoord1_slots & (1u << static_cast<unsigned>(slot))) != 0;
}
// A texture's code in the key's "tex:" list, with '1' when it reads TEXCOORD_1.
inline void texture(std::string& k, const MaterialFeatures& f, TextureSlot slot, const char* code) {
  if (!has(f, slot)) return;
  k += code;
  if (texcoord1(f, slot)) k += '1';
}
inline void flag(std::string& k, bool on, const char* code) {
  if (on) k += code;
}
inline void none(std::string&, const MaterialFeatures&) {}
inline bool always(const MaterialFeatures&) { return true; }
inline bool lit(const MaterialFeatures& f) { return f.shading != ShadingModel::Unlit; }
// Shadow lookups exist in per-pixel light loops only: Gouraud and Flat light per vertex, cheaper
// quality levels that drop shadows with the rest of the per-pixel work.
inline bool shadowed(const MaterialFeatures& f) {
  return f.shading == ShadingModel::BlinnPhong || f.shading == ShadingModel::PbrMetallicRoughness;
}
// The vertex normal is interpolated (Flat reads only the face normal at the provoking vertex, so
// morph targets' normal deltas are not applied there).
inline bool smooth_normals(const MaterialFeatures& f) {
  return f.shading != ShadingModel::Unlit && f.shading != ShadingModel::Flat;
}

}  // namespace feature_terms

// Calls `visit(FeatureField, member...)` for each term, with the term of every `features` given
// (one for the writer / reader / dump, two for canonical's reset to the default).
template <class V, class... F>
  requires(std::same_as<std::remove_const_t<F>, MaterialFeatures> && ...)
void feature_fields(V&& visit, F&... f) {
  namespace t = feature_terms;
  using M = MaterialFeatures;
  using S = TextureSlot;
  visit(FeatureField{"shading", [](std::string& k, const M& c) { k += to_string(c.shading); }, t::always}, f.shading...);
  visit(FeatureField{"alpha", [](std::string& k, const M& c) { (k += '|') += to_string(c.alpha); }, t::always}, f.alpha...);
  visit(FeatureField{"precision", [](std::string& k, const M& c) { k += c.precision == Precision::Highp ? "|highp" : "|mediump"; },
                     t::always}, f.precision...);
  // The textures, as one "|tex:" list (the environment map with them; the shadow maps are lights').
  visit(FeatureField{"base_color_texture", [](std::string& k, const M& c) { k += "|tex:", t::texture(k, c, S::BaseColor, "b"); },
                     t::always}, f.base_color_texture...);
  visit(FeatureField{"metallic_roughness_texture", [](std::string& k, const M& c) { t::texture(k, c, S::MetallicRoughness, "m"); },
                     t::always}, f.metallic_roughness_texture...);
  visit(FeatureField{"normal_texture", [](std::string& k, const M& c) { t::texture(k, c, S::Normal, "n"); }, t::always},
        f.normal_texture...);
  visit(FeatureField{"emissive_texture", [](std::string& k, const M& c) { t::texture(k, c, S::Emissive, "e"); }, t::always},
        f.emissive_texture...);
  visit(FeatureField{"occlusion_texture", [](std::string& k, const M& c) { t::texture(k, c, S::Occlusion, "o"); }, t::always},
        f.occlusion_texture...);
  visit(FeatureField{"environment_map_2d", [](std::string& k, const M& c) { t::texture(k, c, S::Environment, "env"); },
                     t::always}, f.environment_map_2d...);
  visit(FeatureField{"texcoord1_slots", t::none, t::always}, f.texcoord1_slots...);  // in the texture codes
  visit(FeatureField{"texture_transform", [](std::string& k, const M& c) { t::flag(k, c.texture_transform, "|tt"); }, t::always},
        f.texture_transform...);
  visit(FeatureField{"vertex_colors", [](std::string& k, const M& c) { t::flag(k, c.vertex_colors, "|vc"); }, t::always},
        f.vertex_colors...);
  visit(FeatureField{"vertex_alpha", [](std::string& k, const M& c) { t::flag(k, c.vertex_alpha, "|va"); }, t::always},
        f.vertex_alpha...);
  visit(FeatureField{"double_sided", [](std::string& k, const M& c) { t::flag(k, c.double_sided, "|ds"); }, t::always},
        f.double_sided...);
  visit(FeatureField{"skin_joints", [](std::string& k, const M& c) { if (c.skin_joints) k += "|skin" + std::to_string(c.skin_joints); },
                     t::always}, f.skin_joints...);
  visit(FeatureField{"morph_targets",
                     [](std::string& k, const M& c) {
                       if (c.morph_targets) k += "|morph" + std::to_string(c.morph_targets) + (c.morph_normals ? "n" : "");
                     },
                     t::always}, f.morph_targets...);
  visit(FeatureField{"morph_normals", t::none, t::smooth_normals}, f.morph_normals...);  // in the morph code
  visit(FeatureField{"lights.directional",
                     [](std::string& k, const M& c) {
                       if (c.lights.total())
                         k += "|L" + std::to_string(c.lights.directional) + "." + std::to_string(c.lights.point) + "." +
                              std::to_string(c.lights.spot);
                     },
                     t::lit}, f.lights.directional...);
  visit(FeatureField{"lights.point", t::none, t::lit}, f.lights.point...);  // in the light code
  visit(FeatureField{"lights.spot", t::none, t::lit}, f.lights.spot...);
  visit(FeatureField{"lights.shadows", [](std::string& k, const M& c) { if (c.lights.shadows) k += "|S" + std::to_string(c.lights.shadows); },
                     t::shadowed}, f.lights.shadows...);
  visit(FeatureField{"has_tangents", [](std::string& k, const M& c) { t::flag(k, c.has_tangents, "|tan"); },
                     [](const M& c) { return c.normal_texture; }}, f.has_tangents...);
}

// The record form every package visitor uses: `visit(FeatureField, member)`.
template <class R, class V>
  requires std::same_as<std::remove_const_t<R>, MaterialFeatures>
void fields(R& f, V&& visit) {
  feature_fields(visit, f);
}

}  // namespace meter::bridge
