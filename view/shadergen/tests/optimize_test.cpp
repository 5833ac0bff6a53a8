// optimize(): output compiles as GLSL ES 3.00, never grows the uniform list or the SPIR-V, folded
// constants disappear from the metadata and the sources, and what the runtime binds stays true.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "test_util.hpp"

namespace meter::shadergen {
namespace {

using test::compiles;
using test::contains;
using test::declares_any_uniform;
using test::pbr;

MaterialFeatures rich_pbr() {
  MaterialFeatures f = pbr();
  f.base_color_texture = f.normal_texture = f.metallic_roughness_texture = true;
  f.occlusion_texture = f.emissive_texture = true;
  f.lights = {1, 1, 1};
  return f;
}

// The material values a typical cluster scene never animates.
ConstantValues material_constants() {
  ConstantValues c;
  c.set(UniformSemantic::MetallicFactor, {1.0f});
  c.set(UniformSemantic::RoughnessFactor, {0.4f});
  c.set(UniformSemantic::EmissiveFactor, {0.0f, 0.0f, 0.0f});
  c.set(UniformSemantic::NormalScale, {1.0f});
  c.set(UniformSemantic::OcclusionStrength, {1.0f});
  c.set(UniformSemantic::Exposure, {1.0f});
  c.set(UniformSemantic::LightRange, 1, {0.0f});  // point light without range: no window
  c.set(UniformSemantic::LightRange, 2, {0.0f});
  return c;
}

void expect_metadata_true(const Program& p) {
  for (const auto& u : p.uniforms) EXPECT_TRUE(declares_any_uniform(p, u.name)) << u.name;
  for (const auto& s : p.samplers) EXPECT_TRUE(declares_any_uniform(p, s.name)) << s.name;
  for (const auto& a : p.attributes)
    EXPECT_TRUE(contains(p.vertex_source,
                         "layout(location = " + std::to_string(a.location) + ") in "))
        << a.name;
  for (const auto& a : p.attributes) EXPECT_TRUE(contains(p.vertex_source, " " + a.name + ";"));
}

TEST(Optimize, WithoutConstantsCompilesAndNeverGrows) {
  std::vector<MaterialFeatures> sets;
  for (int m = 0; m <= static_cast<int>(ShadingModel::PbrMetallicRoughness); ++m) {
    MaterialFeatures f;
    f.shading = static_cast<ShadingModel>(m);
    f.base_color_texture = true;
    f.lights = {1, 1, 0};
    sets.push_back(f);
  }
  sets.push_back(rich_pbr());
  for (const auto& f : sets) {
    SCOPED_TRACE(meter::shadergen::program_key(f));
    const Program p = generate(f);
    OptimizeReport r;
    const Program o = optimize(p, {}, &r);
    EXPECT_TRUE(o.optimized);
    EXPECT_TRUE(compiles(o));
    EXPECT_TRUE(contains(o.vertex_source, "#version 300 es"));
    EXPECT_LE(r.uniforms_after, r.uniforms_before);
    EXPECT_LE(r.spirv_instructions_after, r.spirv_instructions_before);
    EXPECT_LT(r.spirv_instructions_after, r.spirv_instructions_before);  // inlining alone shrinks
    EXPECT_EQ(r.uniforms_before, p.uniforms.size());
    EXPECT_EQ(r.uniforms_after, o.uniforms.size());
    EXPECT_TRUE(r.folded.empty());
    expect_metadata_true(o);
  }
}

TEST(Optimize, FoldedConstantsLeaveTheUniformList) {
  const Program p = generate(rich_pbr());
  OptimizeReport r;
  const Program o = optimize(p, material_constants(), &r);
  ASSERT_TRUE(compiles(o));
  for (const char* name : {"u_metallic_factor", "u_roughness_factor", "u_emissive_factor",
                           "u_normal_scale", "u_occlusion_strength", "u_exposure",
                           "u_light1_range", "u_light2_range"}) {
    EXPECT_FALSE(declares_any_uniform(o, name)) << name;
    for (const auto& u : o.uniforms) EXPECT_NE(u.name, name);
    EXPECT_NE(std::find(r.folded.begin(), r.folded.end(), name), r.folded.end()) << name;
  }
  EXPECT_EQ(r.uniforms_after, r.uniforms_before - 8);
  // Values nobody folded are still there for the runtime to set.
  EXPECT_NE(o.find_uniform(UniformSemantic::BaseColorFactor), nullptr);
  EXPECT_NE(o.find_uniform(UniformSemantic::LightColor, 0), nullptr);
  EXPECT_NE(o.find_uniform(UniformSemantic::ModelMatrix), nullptr);
  // The range test of folded lights is gone; the unfolded spot keeps nothing of it either.
  EXPECT_FALSE(contains(o.fragment_source, "u_light1_range"));
  expect_metadata_true(o);
}

TEST(Optimize, FoldingShrinksTheCodeBeyondPlainOptimisation) {
  const Program p = generate(rich_pbr());
  OptimizeReport plain, folded;
  optimize(p, {}, &plain);
  optimize(p, material_constants(), &folded);
  EXPECT_LT(folded.spirv_instructions_after, plain.spirv_instructions_after);
  EXPECT_LT(folded.uniforms_after, plain.uniforms_after);
}

TEST(Optimize, DeadVaryingsAndAttributesAreRemoved) {
  // Blinn-Phong whose only light is switched off for good and no ambient: the normal, the view
  // vector and the world position no longer matter, so their varyings and the NORMAL attribute go.
  MaterialFeatures f;
  f.shading = ShadingModel::BlinnPhong;
  f.lights.directional = 1;
  const Program p = generate(f);
  ConstantValues c;
  c.set(UniformSemantic::LightIntensity, 0, {0.0f});
  c.set(UniformSemantic::LightColor, 0, {0.0f, 0.0f, 0.0f});
  c.set(UniformSemantic::AmbientLight, {0.0f, 0.0f, 0.0f});
  OptimizeReport r;
  const Program o = optimize(p, c, &r);
  ASSERT_TRUE(compiles(o));
  EXPECT_EQ(r.varyings_before, 2u);  // v_world_position, v_normal
  EXPECT_EQ(r.varyings_after, 0u);
  EXPECT_FALSE(contains(o.vertex_source, "v_normal"));
  EXPECT_FALSE(contains(o.vertex_source, "u_normal_matrix"));
  EXPECT_EQ(o.find_attribute(AttributeSemantic::Normal), nullptr);
  EXPECT_NE(o.find_attribute(AttributeSemantic::Position), nullptr);
  EXPECT_EQ(o.find_uniform(UniformSemantic::NormalMatrix), nullptr);
  EXPECT_EQ(o.find_uniform(UniformSemantic::CameraPosition), nullptr);
  expect_metadata_true(o);
}

TEST(Optimize, AttributeLocationsAndNamesStayStable) {
  MaterialFeatures f = rich_pbr();
  f.vertex_colors = true;
  f.has_tangents = true;
  f.texcoord1_slots = 1u << static_cast<unsigned>(TextureSlot::Occlusion);
  const Program p = generate(f);
  const Program o = optimize(p, {});
  ASSERT_TRUE(compiles(o));
  ASSERT_EQ(o.attributes.size(), p.attributes.size());
  for (std::size_t i = 0; i < p.attributes.size(); ++i) {
    EXPECT_EQ(o.attributes[i].location, p.attributes[i].location);
    EXPECT_TRUE(contains(o.vertex_source, "layout(location = " +
                                              std::to_string(p.attributes[i].location) + ") in " +
                                              (p.attributes[i].components == 2 ? "vec2 " :
                                               p.attributes[i].components == 3 ? "vec3 " : "vec4 ") +
                                              p.attributes[i].name + ";"))
        << p.attributes[i].name << "\n" << o.vertex_source;
  }
  for (const auto& s : p.samplers) EXPECT_TRUE(declares_any_uniform(o, s.name)) << s.name;
}

TEST(Optimize, ArraysSkinningAndMorphFold) {
  MaterialFeatures f = pbr();
  f.skin_joints = 2;
  f.morph_targets = 2;
  f.morph_normals = true;
  const Program p = generate(f);
  ConstantValues c;
  std::vector<float> joints(32, 0.0f);
  for (int j = 0; j < 2; ++j)
    for (int d = 0; d < 4; ++d) joints[static_cast<std::size_t>(j * 16 + d * 5)] = 1.0f;  // identity
  c.set(UniformSemantic::JointMatrices, joints);
  c.set(UniformSemantic::MorphWeights, {0.25f, 0.0f});
  OptimizeReport r;
  const Program o = optimize(p, c, &r);
  ASSERT_TRUE(compiles(o));
  EXPECT_EQ(o.find_uniform(UniformSemantic::JointMatrices), nullptr);
  EXPECT_EQ(o.find_uniform(UniformSemantic::MorphWeights), nullptr);
  // Weight 0 makes target 1 dead: its attributes go.
  EXPECT_EQ(o.find_attribute(AttributeSemantic::MorphPosition, 1), nullptr);
  EXPECT_NE(o.find_attribute(AttributeSemantic::MorphPosition, 0), nullptr);
  EXPECT_LT(r.spirv_instructions_after, r.spirv_instructions_before);
  expect_metadata_true(o);
}

// One-element arrays go through both paths: kept dynamic (the morphing feature scene animates its
// single weight) and folded (a const float[1] initializer).
TEST(Optimize, SingleElementArraysStayArraysAndFold) {
  MaterialFeatures f = pbr();
  f.skin_joints = 1;
  f.morph_targets = 1;
  f.morph_normals = true;
  const Program p = generate(f);
  const Program dynamic = optimize(p, {});
  ASSERT_TRUE(compiles(dynamic));
  const UniformInfo* w = dynamic.find_uniform(UniformSemantic::MorphWeights);
  ASSERT_NE(w, nullptr);
  EXPECT_EQ(w->array_size, 1);
  EXPECT_TRUE(declares_any_uniform(dynamic, "u_morph_weights")) << dynamic.vertex_source;
  EXPECT_NE(dynamic.find_uniform(UniformSemantic::JointMatrices), nullptr);
  expect_metadata_true(dynamic);

  ConstantValues c;
  std::vector<float> identity(16, 0.0f);
  for (int d = 0; d < 4; ++d) identity[static_cast<std::size_t>(d * 5)] = 1.0f;
  c.set(UniformSemantic::JointMatrices, identity);
  c.set(UniformSemantic::MorphWeights, {0.5f});
  OptimizeReport r;
  const Program folded = optimize(p, c, &r);
  ASSERT_TRUE(compiles(folded));
  EXPECT_EQ(folded.find_uniform(UniformSemantic::MorphWeights), nullptr);
  EXPECT_EQ(folded.find_uniform(UniformSemantic::JointMatrices), nullptr);
  EXPECT_NE(folded.find_attribute(AttributeSemantic::MorphPosition, 0), nullptr);
  EXPECT_EQ(r.folded.size(), 2u);
  expect_metadata_true(folded);
}

TEST(Optimize, MediumPrecisionProgramsStayValid) {
  MaterialFeatures f = rich_pbr();
  f.precision = Precision::Mediump;
  const Program o = optimize(generate(f), material_constants());
  EXPECT_TRUE(compiles(o));
  EXPECT_TRUE(contains(o.fragment_source, "precision mediump float"));
}

TEST(Optimize, UberShaderSpecialisesWhenItsSwitchesFold) {
  const Program u = generate_uber();
  OptimizeReport plain, specialised;
  const Program o1 = optimize(u, {}, &plain);
  ConstantValues c;
  c.set(UniformSemantic::UberSwitches, 0, {0, 0, 0, 0});  // no skinning, no vertex colours
  c.set(UniformSemantic::UberSwitches, 1, {1, 0, 0, 0});  // Blinn-Phong, no textures, opaque
  c.set(UniformSemantic::UberLightCounts, {1, 0, 0});
  const Program o2 = optimize(u, c, &specialised);
  EXPECT_TRUE(compiles(o1));
  EXPECT_TRUE(compiles(o2));
  EXPECT_LT(specialised.spirv_instructions_after, plain.spirv_instructions_after);
  EXPECT_LT(specialised.samplers_after, plain.samplers_after);
  EXPECT_EQ(specialised.samplers_after, 0u);
}

TEST(Optimize, BadConstantsAreRejected) {
  const Program p = generate(rich_pbr());
  ConstantValues wrong_count;
  wrong_count.set(UniformSemantic::EmissiveFactor, {1.0f, 0.0f});
  try {
    optimize(p, wrong_count);
    ADD_FAILURE() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(contains(e.what(), "u_emissive_factor")) << e.what();
    EXPECT_TRUE(contains(e.what(), "expected 3")) << e.what();
  }
  ConstantValues nan;
  nan.set(UniformSemantic::MetallicFactor, {std::numeric_limits<float>::quiet_NaN()});
  EXPECT_THROW(optimize(p, nan), std::invalid_argument);
  ConstantValues inf;
  inf.set(UniformSemantic::RoughnessFactor, {std::numeric_limits<float>::infinity()});
  EXPECT_THROW(optimize(p, inf), std::invalid_argument);
  ConstantValues fractional_switch;
  fractional_switch.set(UniformSemantic::UberLightCounts, {0.5f, 0.0f, 0.0f});
  EXPECT_THROW(optimize(generate_uber(), fractional_switch), std::invalid_argument);
  EXPECT_THROW(optimize(optimize(p, {}), {}), std::invalid_argument);
  Program empty;
  EXPECT_THROW(optimize(empty, {}), std::invalid_argument);
}

TEST(Optimize, ConstantsForAbsentUniformsAreIgnored) {
  // One ConstantValues per scene is applied to every program: values a program lacks are skipped.
  const Program p = generate(pbr());
  ConstantValues c;
  c.set(UniformSemantic::Shininess, {32.0f});
  c.set(UniformSemantic::LightColor, 7, {1.0f, 1.0f, 1.0f});
  OptimizeReport r;
  const Program o = optimize(p, c, &r);
  EXPECT_TRUE(r.folded.empty());
  EXPECT_TRUE(compiles(o));
}

TEST(Spirv, InstructionCountRejectsGarbage) {
  EXPECT_THROW(spirv_instruction_count({1, 2, 3}), std::invalid_argument);
  EXPECT_THROW(spirv_instruction_count({0x07230203u, 0, 0, 0, 0, 0}), std::invalid_argument);
  EXPECT_THROW(spirv_instruction_count({0x07230203u, 0, 0, 0, 0, (5u << 16) | 1u}),
               std::invalid_argument);
  const auto words = compile_to_spirv(generate(pbr()).fragment_source, ShaderStage::Fragment);
  EXPECT_GT(spirv_instruction_count(words), 20u);
  EXPECT_THROW(compile_to_spirv("#version 300 es\nvoid main() { undefined_fn(); }\n",
                                ShaderStage::Fragment),
               std::runtime_error);
  EXPECT_THROW(compile_to_spirv("#version 100\nvoid main() {}\n", ShaderStage::Fragment),
               std::runtime_error);
}

TEST(Check, ReportsBrokenSources) {
  Program p = generate(pbr());
  p.fragment_source += "this is not glsl\n";
  const CompileCheck c = check_compiles(p);
  EXPECT_FALSE(c.ok);
  EXPECT_TRUE(contains(c.log, "fragment")) << c.log;
}

}  // namespace
}  // namespace meter::shadergen

namespace meter::shadergen {
namespace {
using namespace test;

// Desktop GLSL: a dialect change of either the generated or the optimized program that
// desktop glslang accepts, with the same interface names and attribute locations.
TEST(DesktopGlsl, GeneratedAndOptimizedProgramsTranslate) {
  MaterialFeatures f = rich_pbr();
  f.skin_joints = 1;
  f.morph_targets = 1;
  f.precision = Precision::Mediump;
  const Program p = generate(f);
  for (const Program& src : {p, optimize(p, material_constants())}) {
    for (const int version : {330, 450}) {
      const Program d = to_desktop_glsl(src, version);
      SCOPED_TRACE(std::to_string(version) + (src.optimized ? " optimized" : " generated"));
      const std::string banner = "#version " + std::to_string(version) + "\n";
      EXPECT_EQ(d.vertex_source.rfind(banner, 0), 0u) << d.vertex_source;
      EXPECT_EQ(d.fragment_source.rfind(banner, 0), 0u) << d.fragment_source;
      EXPECT_FALSE(contains(d.fragment_source, "precision ")) << d.fragment_source;
      EXPECT_TRUE(compiles(d));
      for (const auto& u : src.uniforms) EXPECT_TRUE(declares_any_uniform(d, u.name)) << u.name;
      for (const auto& s : src.samplers) EXPECT_TRUE(declares_any_uniform(d, s.name)) << s.name;
      for (const auto& a : src.attributes)
        EXPECT_TRUE(contains(d.vertex_source,
                             "layout(location = " + std::to_string(a.location) + ") in "))
            << a.name << "\n" << d.vertex_source;
      EXPECT_EQ(d.uniforms.size(), src.uniforms.size());
    }
  }
  EXPECT_THROW(to_desktop_glsl(p, 300), std::invalid_argument);
  EXPECT_THROW(to_desktop_glsl(Program{}, 330), std::invalid_argument);
}

}  // namespace
}  // namespace meter::shadergen
