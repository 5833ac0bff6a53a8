// generate(): every feature flag produces a program that compiles (glslang, ES 3.00 profile) and
// contains exactly the code and metadata of that feature; invalid sets throw; program_key() is canonical.
#include <gtest/gtest.h>

#include <cctype>
#include <functional>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "test_util.hpp"

namespace meter::shadergen {
namespace {

using test::compiles;
using test::contains;
using test::declares_any_uniform;
using test::pbr;

// One row per feature flag: the flag turned on over a plain base material must add these
// uniforms/attributes/code fragments, which the base program must not have.
struct FeatureCase {
  const char* name;
  MaterialFeatures base;
  std::function<void(MaterialFeatures&)> enable;
  std::vector<std::string> new_uniforms;        // declared in a stage + in metadata
  std::vector<AttributeSemantic> new_attributes;
  std::vector<std::string> new_fragment_code;
  std::vector<std::string> new_vertex_code;
};

MaterialFeatures with(ShadingModel m) {
  MaterialFeatures f;
  f.shading = m;
  return f;
}

MaterialFeatures lit_pbr() {
  MaterialFeatures f = pbr();
  f.lights.directional = 1;
  return f;
}

std::vector<FeatureCase> feature_cases() {
  using U = std::vector<std::string>;
  using A = std::vector<AttributeSemantic>;
  return {
      {"base_color_texture", pbr(), [](auto& f) { f.base_color_texture = true; },
       U{}, A{AttributeSemantic::TexCoord0}, {"texture(u_base_color_texture"}, {"v_texcoord0"}},
      {"metallic_roughness_texture", pbr(), [](auto& f) { f.metallic_roughness_texture = true; },
       U{}, A{AttributeSemantic::TexCoord0}, {"texture(u_metallic_roughness_texture", "mr.g"}, {}},
      {"normal_texture", pbr(), [](auto& f) { f.normal_texture = true; }, U{"u_normal_scale"},
       A{AttributeSemantic::TexCoord0}, {"texture(u_normal_texture", "cotangent_frame"}, {}},
      {"normal_texture+tangents", pbr(),
       [](auto& f) { f.normal_texture = true; f.has_tangents = true; }, U{"u_normal_scale"},
       A{AttributeSemantic::Tangent, AttributeSemantic::TexCoord0}, {"v_tangent.w"}, {"a_tangent"}},
      {"emissive_texture", pbr(), [](auto& f) { f.emissive_texture = true; }, U{},
       A{AttributeSemantic::TexCoord0}, {"texture(u_emissive_texture"}, {}},
      {"occlusion_texture", pbr(), [](auto& f) { f.occlusion_texture = true; },
       U{"u_occlusion_strength"}, A{AttributeSemantic::TexCoord0}, {"texture(u_occlusion_texture"}, {}},
      {"occlusion_texture on TEXCOORD_1", pbr(),
       [](auto& f) {
         f.occlusion_texture = true;
         f.texcoord1_slots = 1u << static_cast<unsigned>(TextureSlot::Occlusion);
       },
       U{"u_occlusion_strength"}, A{AttributeSemantic::TexCoord1}, {"uv_occlusion = v_texcoord1"}, {}},
      {"texture_transform", [] { auto f = pbr(); f.base_color_texture = true; return f; }(),
       [](auto& f) { f.texture_transform = true; }, U{"u_base_color_uv_transform"}, A{},
       {"u_base_color_uv_transform * vec3(v_texcoord0, 1.0)"}, {}},
      {"vertex_colors", pbr(), [](auto& f) { f.vertex_colors = true; }, U{},
       A{AttributeSemantic::Color0}, {"base_color *= v_color0"}, {"v_color0 = a_color0"}},
      {"vertex_alpha", pbr(), [](auto& f) { f.vertex_alpha = true; }, U{},
       A{AttributeSemantic::VertexAlpha}, {"v_vertex_alpha", "discard"}, {"a_vertex_alpha"}},
      {"alpha mask", pbr(), [](auto& f) { f.alpha = AlphaMode::Mask; }, U{"u_alpha_cutoff"}, A{},
       {"discard"}, {}},
      {"alpha blend", pbr(), [](auto& f) { f.alpha = AlphaMode::Blend; }, U{}, A{},
       {"base_color.a)"}, {}},
      {"double_sided", pbr(), [](auto& f) { f.double_sided = true; }, U{}, A{}, {"gl_FrontFacing"},
       {}},
      {"skinning", pbr(), [](auto& f) { f.skin_joints = 5; }, U{"u_joint_matrices"},
       A{AttributeSemantic::Joints0, AttributeSemantic::Weights0}, {},
       {"u_joint_matrices[5]", "ivec4(4)", "mat3(skin) * normal"}},
      {"morph targets", pbr(), [](auto& f) { f.morph_targets = 2; }, U{"u_morph_weights"},
       A{AttributeSemantic::MorphPosition}, {}, {"u_morph_weights[1] * a_morph_position1"}},
      {"morph normals", [] { auto f = pbr(); f.morph_targets = 2; return f; }(),
       [](auto& f) { f.morph_normals = true; }, U{}, A{AttributeSemantic::MorphNormal}, {},
       {"normal += u_morph_weights[0] * a_morph_normal0"}},
      {"directional light", pbr(), [](auto& f) { f.lights.directional = 1; },
       U{"u_light0_color", "u_light0_intensity", "u_light0_direction"}, A{},
       {"pbr_light(", "kWattsPerLumen"}, {}},
      {"point light", pbr(), [](auto& f) { f.lights.point = 1; },
       U{"u_light0_position", "u_light0_range"}, A{}, {"range_attenuation("}, {}},
      {"spot light", pbr(), [](auto& f) { f.lights.spot = 1; },
       U{"u_light0_inner_cone_cos", "u_light0_outer_cone_cos", "u_light0_direction"}, A{},
       {"spot_attenuation("}, {}},
      {"environment map", pbr(), [](auto& f) { f.environment_map_2d = true; },
       U{"u_environment_intensity", "u_environment_irradiance_px", "u_environment_irradiance_nz"}, A{},
       {"uniform samplerCube u_environment_texture", "textureLod(u_environment_texture, r, env_lod)", "ambient_cube("}, {}},
      {"blinn-phong environment map", with(ShadingModel::BlinnPhong),
       [](auto& f) { f.environment_map_2d = true; },
       U{"u_environment_intensity", "u_environment_irradiance_py", "u_specular_color"}, A{},
       {"textureLod(u_environment_texture, r, 0.0)", "ambient_cube("}, {}},
      {"blinn-phong lights", with(ShadingModel::BlinnPhong), [](auto& f) { f.lights.point = 2; },
       U{"u_shininess", "u_specular_color", "u_camera_position", "u_light1_position"}, A{},
       {"blinn_phong_specular("}, {}},
      {"gouraud lights", with(ShadingModel::Gouraud), [](auto& f) { f.lights.directional = 1; },
       U{"u_shininess", "u_specular_color", "u_camera_position"}, A{}, {"v_diffuse_light"},
       {"blinn_phong_specular(", "v_specular_light ="}},
      {"flat lights", with(ShadingModel::Flat), [](auto& f) { f.lights.spot = 1; },
       U{"u_light0_position"}, A{}, {"flat in vec3 v_flat_light"}, {"spot_attenuation("}},
  };
}

class FeatureFlag : public ::testing::TestWithParam<std::size_t> {};

TEST_P(FeatureFlag, AddsExactlyItsCodeAndCompiles) {
  const FeatureCase c = feature_cases()[GetParam()];
  SCOPED_TRACE(c.name);
  MaterialFeatures on = c.base;
  c.enable(on);
  const Program base = generate(c.base);
  const Program p = generate(on);
  EXPECT_TRUE(compiles(base));
  EXPECT_TRUE(compiles(p));
  EXPECT_NE(meter::shadergen::program_key(base.features), meter::shadergen::program_key(p.features));
  for (const auto& u : c.new_uniforms) {
    EXPECT_TRUE(declares_any_uniform(p, u)) << u;
    EXPECT_FALSE(declares_any_uniform(base, u)) << u;
    bool in_meta = false;
    for (const auto& info : p.uniforms) in_meta |= info.name == u;
    EXPECT_TRUE(in_meta) << u;
  }
  for (auto a : c.new_attributes) {
    EXPECT_NE(p.find_attribute(a, a == AttributeSemantic::MorphPosition ||
                                          a == AttributeSemantic::MorphNormal ? 0 : -1),
              nullptr)
        << to_string(a);
    EXPECT_EQ(base.find_attribute(a, a == AttributeSemantic::MorphPosition ||
                                             a == AttributeSemantic::MorphNormal ? 0 : -1),
              nullptr)
        << to_string(a);
  }
  for (const auto& code : c.new_fragment_code) {
    EXPECT_TRUE(contains(p.fragment_source, code)) << code << "\n" << p.fragment_source;
    EXPECT_FALSE(contains(base.fragment_source, code)) << code;
  }
  for (const auto& code : c.new_vertex_code) {
    EXPECT_TRUE(contains(p.vertex_source, code)) << code << "\n" << p.vertex_source;
    EXPECT_FALSE(contains(base.vertex_source, code)) << code;
  }
}

INSTANTIATE_TEST_SUITE_P(AllFlags, FeatureFlag,
                         ::testing::Range<std::size_t>(0, feature_cases().size()),
                         [](const auto& info) {
                           std::string n = feature_cases()[info.param].name;
                           for (char& ch : n)
                             if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                           return n;
                         });

// "Simulate only the effects a scene calls for": a program without environment_map_2d has no
// environment sampler, uniform or code at all (no cost for scenes without a world image), and one
// with it lights diffuse from the map's ambient cube instead of the uniform ambient.
TEST(Generate, EnvironmentCodeExistsOnlyWhenTheFeatureIsOn) {
  for (ShadingModel m : {ShadingModel::Unlit, ShadingModel::Flat, ShadingModel::Gouraud,
                         ShadingModel::BlinnPhong, ShadingModel::PbrMetallicRoughness}) {
    SCOPED_TRACE(to_string(m));
    MaterialFeatures f = with(m);
    f.lights.directional = 1;
    f.base_color_texture = true;
    const Program p = generate(f);
    for (const auto& s : p.samplers) EXPECT_NE(s.slot, TextureSlot::Environment) << s.name;
    for (const auto& u : p.uniforms) {
      EXPECT_NE(u.semantic, UniformSemantic::EnvironmentIntensity) << u.name;
      EXPECT_NE(u.semantic, UniformSemantic::EnvironmentIrradiance) << u.name;
    }
    EXPECT_FALSE(contains(p.fragment_source, "environment")) << p.fragment_source;
    EXPECT_FALSE(contains(p.fragment_source, "equirect")) << p.fragment_source;
    if (m != ShadingModel::BlinnPhong && m != ShadingModel::PbrMetallicRoughness) continue;
    f.environment_map_2d = true;
    const Program e = generate(f);
    int env_samplers = 0, irradiance = 0;
    for (const auto& s : e.samplers) env_samplers += s.slot == TextureSlot::Environment;
    for (const auto& u : e.uniforms) irradiance += u.semantic == UniformSemantic::EnvironmentIrradiance;
    EXPECT_EQ(env_samplers, 1);
    EXPECT_EQ(irradiance, 6);  // one colour per signed axis
    EXPECT_EQ(e.find_uniform(UniformSemantic::AmbientLight), nullptr);
    EXPECT_NE(p.find_uniform(UniformSemantic::AmbientLight), nullptr);
    EXPECT_TRUE(compiles(e));
  }
}

// Shadows exist only for the lights that cast them: one depth-compare sampler and one matrix per
// casting light, with that light's index, and no shadow code at all in a program whose lights cast
// none. Gouraud and Flat (per-vertex light) and unlit programs drop shadows in their canonical form.
TEST(Generate, ShadowLookupsExistOnlyForCastingLights) {
  for (ShadingModel m : {ShadingModel::BlinnPhong, ShadingModel::PbrMetallicRoughness}) {
    SCOPED_TRACE(to_string(m));
    MaterialFeatures f = with(m);
    f.lights.directional = 1, f.lights.point = 1, f.lights.spot = 1;
    const Program plain = generate(f);
    EXPECT_FALSE(contains(plain.fragment_source, "shadow")) << plain.fragment_source;
    f.lights.shadows = 0b101;  // the sun (0) and the spot (2); the point light (1) has no map
    const Program p = generate(f);
    std::vector<int> sampler_lights, matrix_lights;
    for (const auto& s : p.samplers)
      if (s.slot == TextureSlot::ShadowMap) sampler_lights.push_back(s.index);
      else EXPECT_EQ(s.index, -1) << s.name;
    for (const auto& u : p.uniforms)
      if (u.semantic == UniformSemantic::LightShadowMatrix) matrix_lights.push_back(u.index);
    EXPECT_EQ(sampler_lights, (std::vector<int>{0, 2}));
    EXPECT_EQ(matrix_lights, (std::vector<int>{0, 2}));
    EXPECT_TRUE(contains(p.fragment_source, "uniform highp sampler2DShadow u_light0_shadow_map;"));
    EXPECT_FALSE(contains(p.fragment_source, "u_light1_shadow"));
    EXPECT_TRUE(compiles(p));
    EXPECT_NE(program_key(f), program_key(with(m)));
  }
  for (ShadingModel m : {ShadingModel::Unlit, ShadingModel::Flat, ShadingModel::Gouraud}) {
    MaterialFeatures f = with(m);
    f.lights.directional = 1, f.lights.shadows = 1;
    EXPECT_EQ(canonical(f).lights.shadows, 0u) << to_string(m);
    EXPECT_FALSE(contains(generate(f).fragment_source, "shadow")) << to_string(m);
  }
}

TEST(Generate, PlainPbrHasNoOptionalCode) {
  const Program p = generate(pbr());
  const std::string all = p.vertex_source + p.fragment_source;
  for (const char* absent :
       {"texture(", "u_joint", "u_morph", "u_light", "discard", "gl_FrontFacing", "#if", "a_color0",
        "v_texcoord", "a_tangent", "uber"})
    EXPECT_FALSE(contains(all, absent)) << absent;
  EXPECT_TRUE(p.samplers.empty());
  ASSERT_EQ(p.attributes.size(), 2u);  // position + normal
  EXPECT_EQ(p.attributes[0].semantic, AttributeSemantic::Position);
  EXPECT_EQ(p.attributes[1].semantic, AttributeSemantic::Normal);
  EXPECT_FALSE(p.blend);
  EXPECT_TRUE(p.cull_back_faces);
  EXPECT_TRUE(compiles(p));
}

TEST(Generate, UnlitHasNoLightingAndNoNormals) {
  MaterialFeatures f = with(ShadingModel::Unlit);
  f.base_color_texture = true;
  const Program p = generate(f);
  EXPECT_EQ(p.find_attribute(AttributeSemantic::Normal), nullptr);
  EXPECT_EQ(p.find_uniform(UniformSemantic::NormalMatrix), nullptr);
  EXPECT_EQ(p.find_uniform(UniformSemantic::AmbientLight), nullptr);
  EXPECT_EQ(p.find_uniform(UniformSemantic::EmissiveFactor), nullptr);
  EXPECT_FALSE(contains(p.fragment_source, "PI"));
  EXPECT_TRUE(compiles(p));
}

// Flat lights once per face: in the vertex stage, at the normal the converter put on the face's
// provoking vertex, handed to the fragments without interpolation; no per-fragment lighting.
TEST(Generate, FlatLightsOncePerFaceAtTheProvokingVertex) {
  MaterialFeatures f = with(ShadingModel::Flat);
  f.lights.directional = 1;
  const Program p = generate(f);
  EXPECT_NE(p.find_attribute(AttributeSemantic::Normal), nullptr);
  EXPECT_TRUE(contains(p.vertex_source, "flat out vec3 v_flat_light;"));
  EXPECT_TRUE(contains(p.fragment_source, "flat in vec3 v_flat_light;"));
  EXPECT_TRUE(test::declares_uniform(p.vertex_source, "u_light0_color"));
  EXPECT_FALSE(test::declares_uniform(p.fragment_source, "u_light0_color"));
  for (const char* absent : {"dFdx", "v_world_position", "v_normal", "blinn_phong_specular"})
    EXPECT_FALSE(contains(p.vertex_source + p.fragment_source, absent)) << absent;
  EXPECT_TRUE(compiles(p));
}

TEST(Generate, GouraudLightsInVertexStageOnly) {
  MaterialFeatures f = with(ShadingModel::Gouraud);
  f.lights = {1, 1, 1};
  const Program p = generate(f);
  EXPECT_TRUE(test::declares_uniform(p.vertex_source, "u_light0_color"));
  EXPECT_FALSE(test::declares_uniform(p.fragment_source, "u_light0_color"));
  EXPECT_FALSE(contains(p.fragment_source, "v_normal"));
  EXPECT_TRUE(compiles(p));
}

TEST(Generate, LightIndicesListDirectionalsThenPointsThenSpots) {
  MaterialFeatures f = pbr();
  f.lights = {2, 1, 2};
  const Program p = generate(f);
  for (int i = 0; i < 5; ++i) {
    const UniformInfo* color = p.find_uniform(UniformSemantic::LightColor, i);
    ASSERT_NE(color, nullptr) << i;
    EXPECT_EQ(color->name, "u_light" + std::to_string(i) + "_color");
  }
  EXPECT_NE(p.find_uniform(UniformSemantic::LightDirection, 1), nullptr);   // directional
  EXPECT_EQ(p.find_uniform(UniformSemantic::LightPosition, 1), nullptr);
  EXPECT_NE(p.find_uniform(UniformSemantic::LightPosition, 2), nullptr);    // point
  EXPECT_EQ(p.find_uniform(UniformSemantic::LightDirection, 2), nullptr);
  EXPECT_NE(p.find_uniform(UniformSemantic::LightOuterConeCos, 4), nullptr);  // spot
  EXPECT_EQ(p.find_uniform(UniformSemantic::LightOuterConeCos, 2), nullptr);
  EXPECT_TRUE(compiles(p));
}

TEST(Generate, MetadataMatchesDeclarations) {
  MaterialFeatures f = lit_pbr();
  f.base_color_texture = f.normal_texture = f.emissive_texture = f.occlusion_texture =
      f.metallic_roughness_texture = f.environment_map_2d = true;
  f.texture_transform = f.vertex_colors = true;
  f.skin_joints = 3;
  f.morph_targets = 2;
  f.lights = {1, 1, 1};
  const Program p = generate(f);
  // Every uniform in the metadata is declared exactly once (in one stage)...
  for (const auto& u : p.uniforms) {
    const int n = int(test::declares_uniform(p.vertex_source, u.name)) +
                  int(test::declares_uniform(p.fragment_source, u.name));
    EXPECT_EQ(n, 1) << u.name;
  }
  // ...and every declared uniform is in the metadata (as uniform or sampler).
  std::set<std::string> meta;
  for (const auto& u : p.uniforms) meta.insert(u.name);
  for (const auto& s : p.samplers) meta.insert(s.name);
  const std::regex decl("uniform\\s+(?:\\w+\\s+)*\\w+\\s+(\\w+)");
  for (const std::string* src : {&p.vertex_source, &p.fragment_source})
    for (auto it = std::sregex_iterator(src->begin(), src->end(), decl); it != std::sregex_iterator();
         ++it)
      EXPECT_TRUE(meta.count((*it)[1].str())) << (*it)[1].str();
  // Attribute locations are 0..n-1 and written into the source.
  for (std::size_t i = 0; i < p.attributes.size(); ++i) {
    EXPECT_EQ(p.attributes[i].location, static_cast<int>(i));
    EXPECT_TRUE(contains(p.vertex_source, "layout(location = " + std::to_string(i) + ") in "))
        << p.attributes[i].name;
  }
  // Sampler units are distinct.
  std::set<int> units;
  for (const auto& s : p.samplers) units.insert(s.unit);
  EXPECT_EQ(units.size(), p.samplers.size());
  EXPECT_EQ(p.samplers.size(), 6u);
  EXPECT_TRUE(compiles(p));
}

TEST(Generate, OutputIsLinearAndScaledByExposure) {
  const Program p = generate(lit_pbr());
  EXPECT_TRUE(contains(p.fragment_source, "o_color = vec4(color * u_exposure, 1.0)"));
  // No sRGB encode in the shader: the render target does it.
  EXPECT_FALSE(contains(p.fragment_source, "pow(color"));
  EXPECT_FALSE(contains(p.fragment_source, "1.0 / 2.2"));
}

// A sweep over shading model x alpha x precision x a handful of flags: everything compiles, and
// program_key() separates exactly the programs whose sources differ.
TEST(Generate, SweepCompilesAndKeysMatchSources) {
  std::map<std::string, std::string> by_key;
  std::map<std::string, std::string> by_source;
  int programs = 0;
  for (int m = 0; m <= static_cast<int>(ShadingModel::PbrMetallicRoughness); ++m)
    for (int a = 0; a < 3; ++a)
      for (int prec = 0; prec < 2; ++prec)
        for (int flags = 0; flags < 16; ++flags) {
          MaterialFeatures f;
          f.shading = static_cast<ShadingModel>(m);
          f.alpha = static_cast<AlphaMode>(a);
          f.precision = prec ? Precision::Mediump : Precision::Highp;
          f.base_color_texture = flags & 1;
          f.vertex_colors = flags & 2;
          f.double_sided = flags & 4;
          f.lights = (flags & 8) ? LightCounts{1, 1, 1} : LightCounts{};
          f.skin_joints = (flags & 3) == 3 ? 4 : 0;
          const Program p = generate(f);
          ASSERT_TRUE(compiles(p)) << meter::shadergen::program_key(f);
          const std::string key = meter::shadergen::program_key(f);
          const std::string src = p.vertex_source + "\n//FS\n" + p.fragment_source;
          auto [it, inserted] = by_key.emplace(key, src);
          if (!inserted) {
            EXPECT_EQ(it->second, src) << "same key, different program: " << key;
          }
          auto [it2, inserted2] = by_source.emplace(src, key);
          if (!inserted2) {
            EXPECT_EQ(it2->second, key) << "same program, two keys";
          }
          ++programs;
        }
  EXPECT_EQ(programs, 5 * 3 * 2 * 16);
  // Unlit ignores lights, so its light variants collapse: fewer keys than feature sets.
  EXPECT_LT(by_key.size(), static_cast<std::size_t>(programs));
  EXPECT_GT(by_key.size(), static_cast<std::size_t>(programs) / 2);
}

TEST(Key, CanonicalDropsWhatTheModelIgnores) {
  MaterialFeatures a = with(ShadingModel::Unlit);
  MaterialFeatures b = a;
  b.lights = {2, 1, 0};
  EXPECT_EQ(meter::shadergen::program_key(a), meter::shadergen::program_key(b));
  MaterialFeatures c = pbr();
  MaterialFeatures d = c;
  d.has_tangents = true;  // no normal map: tangents unused
  EXPECT_EQ(meter::shadergen::program_key(c), meter::shadergen::program_key(d));
  d.normal_texture = c.normal_texture = true;
  EXPECT_NE(meter::shadergen::program_key(c), meter::shadergen::program_key(d));
}

TEST(Key, EveryFieldThatChangesCodeChangesTheKey) {
  const MaterialFeatures base = lit_pbr();
  std::vector<std::function<void(MaterialFeatures&)>> edits = {
      [](auto& f) { f.shading = ShadingModel::BlinnPhong; },
      [](auto& f) { f.alpha = AlphaMode::Mask; },
      [](auto& f) { f.alpha = AlphaMode::Blend; },
      [](auto& f) { f.precision = Precision::Mediump; },
      [](auto& f) { f.base_color_texture = true; },
      [](auto& f) { f.metallic_roughness_texture = true; },
      [](auto& f) { f.normal_texture = true; },
      [](auto& f) { f.emissive_texture = true; },
      [](auto& f) { f.occlusion_texture = true; },
      [](auto& f) { f.base_color_texture = true; f.texcoord1_slots = 1; },
      [](auto& f) { f.base_color_texture = true; f.texture_transform = true; },
      [](auto& f) { f.vertex_colors = true; },
      [](auto& f) { f.vertex_alpha = true; },
      [](auto& f) { f.double_sided = true; },
      [](auto& f) { f.skin_joints = 1; },
      [](auto& f) { f.skin_joints = 2; },
      [](auto& f) { f.morph_targets = 1; },
      [](auto& f) { f.morph_targets = 1; f.morph_normals = true; },
      [](auto& f) { f.lights.directional = 2; },
      [](auto& f) { f.lights.point = 1; },
      [](auto& f) { f.lights.spot = 1; },
      [](auto& f) { f.environment_map_2d = true; },
      [](auto& f) { f.normal_texture = true; f.has_tangents = true; },
  };
  std::set<std::string> keys{meter::shadergen::program_key(base)};
  for (std::size_t i = 0; i < edits.size(); ++i) {
    MaterialFeatures f = base;
    edits[i](f);
    EXPECT_TRUE(keys.insert(meter::shadergen::program_key(f)).second) << "edit " << i << " gives a duplicate key " << meter::shadergen::program_key(f);
  }
}

TEST(Invalid, ImpossibleSetsThrowNamingTheField) {
  struct Bad {
    std::function<void(MaterialFeatures&)> edit;
    const char* mentions;
  };
  const std::vector<Bad> bad = {
      {[](auto& f) { f.skin_joints = -1; }, "skin_joints"},
      {[](auto& f) { f.skin_joints = kMaxSkinJoints + 1; }, "skin_joints"},
      {[](auto& f) { f.morph_targets = kMaxMorphTargets + 1; }, "morph_targets"},
      {[](auto& f) { f.morph_normals = true; }, "morph_normals"},
      {[](auto& f) { f.lights.point = -1; }, "light"},
      {[](auto& f) { f.lights.point = kMaxLights + 1; }, "lights"},
      {[](auto& f) { f.shading = ShadingModel::BlinnPhong; f.metallic_roughness_texture = true; },
       "metallic_roughness_texture"},
      {[](auto& f) { f.shading = ShadingModel::Gouraud; f.normal_texture = true; }, "normal_texture"},
      {[](auto& f) { f.shading = ShadingModel::Unlit; f.normal_texture = true; }, "normal_texture"},
      {[](auto& f) { f.shading = ShadingModel::Flat; f.environment_map_2d = true; },
       "environment_map_2d"},
      {[](auto& f) { f.shading = ShadingModel::Unlit; f.occlusion_texture = true; },
       "occlusion_texture"},
      {[](auto& f) { f.shading = ShadingModel::Unlit; f.emissive_texture = true; },
       "emissive_texture"},
      {[](auto& f) { f.texture_transform = true; }, "texture_transform"},
      {[](auto& f) { f.texcoord1_slots = 1; }, "texcoord1_slots"},
      {[](auto& f) { f.environment_map_2d = true; f.texcoord1_slots = 1u << 5; }, "texcoord1_slots"},
      {[](auto& f) { f.texcoord1_slots = 1u << 9; }, "texcoord1_slots"},
      {[](auto& f) {
         f.morph_targets = 8;
         f.morph_normals = true;  // 1 + 1 + 16 attributes > 16
       },
       "vertex attributes"},
      {[](auto& f) { f.lights.directional = 1; f.lights.shadows = 0b10; }, "shadows"},
      {[](auto& f) { f.lights.point = 1; f.lights.shadows = 0b1; }, "point light"},
      {[](auto& f) { f.lights.directional = 5; f.lights.shadows = 0b11111; }, "shadow maps"},
  };
  for (std::size_t i = 0; i < bad.size(); ++i) {
    MaterialFeatures f = pbr();
    bad[i].edit(f);
    try {
      generate(f);
      ADD_FAILURE() << "case " << i << " did not throw";
    } catch (const std::invalid_argument& e) {
      EXPECT_TRUE(contains(e.what(), bad[i].mentions)) << "case " << i << ": " << e.what();
    }
    EXPECT_THROW(meter::shadergen::program_key(f), std::invalid_argument) << "case " << i;
  }
}

TEST(Limits, LargestValidProgramsCompile) {
  MaterialFeatures f = lit_pbr();
  f.skin_joints = kMaxSkinJoints;
  f.lights = {kMaxLights / 2, kMaxLights / 4, kMaxLights / 4};
  f.base_color_texture = f.normal_texture = f.metallic_roughness_texture = true;
  EXPECT_TRUE(compiles(generate(f)));
  MaterialFeatures m = pbr();
  m.morph_targets = 7;  // 1 position + 1 normal + 7 + 7 = 16 attributes
  m.morph_normals = true;
  const Program p = generate(m);
  EXPECT_EQ(p.attributes.size(), 16u);
  EXPECT_TRUE(compiles(p));
}

// One joint / one morph target: still GLSL arrays, because the body indexes them. A scalar
// declaration (`uniform float u_morph_weights;`) once broke scenes/features/morphing.
TEST(Limits, SingleJointAndSingleMorphTargetAreArrays) {
  for (const bool morph_normals : {false, true}) {
    MaterialFeatures m = lit_pbr();
    m.morph_targets = 1;
    m.morph_normals = morph_normals;
    const Program p = generate(m);
    EXPECT_TRUE(compiles(p));
    EXPECT_TRUE(contains(p.vertex_source, "uniform float u_morph_weights[1];")) << p.vertex_source;
    const UniformInfo* w = p.find_uniform(UniformSemantic::MorphWeights);
    ASSERT_NE(w, nullptr);
    EXPECT_EQ(w->array_size, 1);
    EXPECT_TRUE(w->is_array());
  }
  MaterialFeatures s = lit_pbr();
  s.skin_joints = 1;
  const Program p = generate(s);
  EXPECT_TRUE(compiles(p));
  EXPECT_TRUE(contains(p.vertex_source, "uniform mat4 u_joint_matrices[1];")) << p.vertex_source;
  EXPECT_TRUE(contains(p.vertex_source, "ivec4(0)")) << p.vertex_source;  // clamp to the only joint
  const UniformInfo* j = p.find_uniform(UniformSemantic::JointMatrices);
  ASSERT_NE(j, nullptr);
  EXPECT_TRUE(j->is_array());
  MaterialFeatures both = lit_pbr();
  both.skin_joints = 1;
  both.morph_targets = 1;
  EXPECT_TRUE(compiles(generate(both)));
}

TEST(Uber, CompilesAndCarriesEveryFeature) {
  const Program p = generate_uber();
  EXPECT_TRUE(p.uber);
  EXPECT_TRUE(compiles(p));
  EXPECT_EQ(p.samplers.size(), 5u);
  EXPECT_NE(p.find_uniform(UniformSemantic::UberSwitches, 1), nullptr);
  EXPECT_NE(p.find_uniform(UniformSemantic::JointMatrices), nullptr);
  // The generated programs are what the uber shader is compared against: it must be larger.
  EXPECT_GT(p.fragment_source.size(), generate(lit_pbr()).fragment_source.size());
}

}  // namespace
}  // namespace meter::shadergen
