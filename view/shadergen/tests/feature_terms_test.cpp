// The one list of material terms (meter/bridge/material_feature_fields.hpp) drives the program key,
// the canonical form and the program cache's key: the key text is exactly the one generated
// sources carry, and every term reaches the cache key.
#include <gtest/gtest.h>

#include <set>
#include <string>
#include <type_traits>

#include "meter/bridge/material_feature_fields.hpp"
#include "meter/shadergen/program_cache.hpp"
#include "meter/shadergen/shadergen.hpp"

using namespace meter::shadergen;

namespace {
MaterialFeatures rich() {
  MaterialFeatures f;
  f.base_color_texture = f.normal_texture = f.occlusion_texture = f.emissive_texture = true;
  f.metallic_roughness_texture = true;
  f.texcoord1_slots = 1u << int(TextureSlot::Occlusion);
  f.environment_map_2d = true;
  f.texture_transform = f.vertex_colors = f.double_sided = f.has_tangents = true;
  f.morph_targets = 2;
  f.morph_normals = true;
  f.lights = {1, 1, 1, 1u | 4u};
  return f;
}
}  // namespace

// The key text is part of every generated source ("meter shadergen: KEY"), so it must not change
// when the list does.
TEST(FeatureTerms, TheKeyTextIsTheGeneratorsOwn) {
  EXPECT_EQ(program_key(rich()), "pbr|opaque|highp|tex:bmneo1env|tt|vc|ds|morph2n|L1.1.1|S5|tan");
  MaterialFeatures unlit;
  unlit.shading = ShadingModel::Unlit;
  unlit.precision = Precision::Mediump;
  unlit.vertex_alpha = true;
  unlit.skin_joints = 4;
  EXPECT_EQ(program_key(unlit), "unlit|opaque|mediump|tex:|va|skin4");
}

TEST(FeatureTerms, CanonicalResetsWhatTheModelNeverReadsToTheDefault) {
  MaterialFeatures g = rich();
  g.shading = ShadingModel::Gouraud;
  g.metallic_roughness_texture = g.normal_texture = g.environment_map_2d = false;
  const MaterialFeatures c = canonical(g);
  EXPECT_EQ(c.lights.shadows, 0u);      // per-vertex lighting has no shadow lookups
  EXPECT_FALSE(c.has_tangents);         // no normal map
  EXPECT_TRUE(c.morph_normals);         // Gouraud lights the morphed normals
  EXPECT_EQ(c.lights.directional, 1);
  MaterialFeatures u = g;
  u.shading = ShadingModel::Unlit;
  u.occlusion_texture = u.emissive_texture = false;
  u.texcoord1_slots = 0;
  const MaterialFeatures cu = canonical(u);
  EXPECT_EQ(cu.lights, LightCounts{});
  EXPECT_FALSE(cu.morph_normals);
}

// Every term of the list changes the program cache's description of a program.
TEST(FeatureTerms, EveryTermReachesTheCacheKey) {
  std::set<std::string> names, keys;
  const Program base{};
  keys.insert(describe(base));
  meter::bridge::feature_fields([&](const meter::bridge::FeatureField& term, const auto&) { names.insert(term.name); },
                                base.features);
  int n = 0;
  Program p = base;
  meter::bridge::feature_fields([&](const meter::bridge::FeatureField&, auto& value, const auto& initial) {
    value = std::remove_cvref_t<decltype(value)>(static_cast<int>(initial) == 0 ? 1 : 0);
    EXPECT_TRUE(keys.insert(describe(p)).second) << "term " << n << " leaves the cache key unchanged";
    value = initial;
    ++n;
  }, p.features, base.features);
  EXPECT_EQ(names.size(), std::size_t(n));  // every term named once
}
