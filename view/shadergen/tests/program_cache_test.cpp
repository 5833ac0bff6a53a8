// ProgramCache: a hit is the program and report a fresh optimize() gives, byte for byte; anything
// optimize() reads (a material feature, a constant's bits, a table entry) makes a different key.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>

#include "meter/shadergen/program_cache.hpp"
#include "test_util.hpp"

namespace meter::shadergen {
namespace {

using test::pbr;

MaterialFeatures textured_lit_pbr() {
  MaterialFeatures f = pbr();
  f.base_color_texture = true;
  f.lights = {1, 1, 0};
  return f;
}

ConstantValues constants(float roughness) {
  ConstantValues c;
  c.set(UniformSemantic::MetallicFactor, {1.0f});
  c.set(UniformSemantic::RoughnessFactor, {roughness});
  c.set(UniformSemantic::EmissiveFactor, {0.0f, 0.0f, 0.0f});
  c.set(UniformSemantic::Exposure, {1.0f});
  return c;
}

void expect_same_report(const OptimizeReport& a, const OptimizeReport& b) {
  EXPECT_EQ(a.source_bytes_before, b.source_bytes_before);
  EXPECT_EQ(a.source_bytes_after, b.source_bytes_after);
  EXPECT_EQ(a.spirv_instructions_before, b.spirv_instructions_before);
  EXPECT_EQ(a.spirv_instructions_after, b.spirv_instructions_after);
  EXPECT_EQ(a.uniforms_before, b.uniforms_before);
  EXPECT_EQ(a.uniforms_after, b.uniforms_after);
  EXPECT_EQ(a.varyings_before, b.varyings_before);
  EXPECT_EQ(a.varyings_after, b.varyings_after);
  EXPECT_EQ(a.samplers_before, b.samplers_before);
  EXPECT_EQ(a.samplers_after, b.samplers_after);
  EXPECT_EQ(a.folded, b.folded);
}

TEST(ProgramCache, AHitEqualsAFreshOptimizeByteForByte) {
  const Program generated = generate(textured_lit_pbr());
  OptimizeReport fresh_report;
  const Program fresh = optimize(generated, constants(0.4f), &fresh_report);
  ProgramCache cache;
  OptimizeReport first_report, hit_report;
  const Program first = cache.optimize(generated, constants(0.4f), &first_report);
  const Program hit = cache.optimize(generate(textured_lit_pbr()), constants(0.4f), &hit_report);
  EXPECT_EQ(cache.misses(), 1u);
  EXPECT_EQ(cache.hits(), 1u);
  EXPECT_EQ(cache.size(), 1u);
  for (const Program* p : {&first, &hit}) {
    EXPECT_EQ(p->vertex_source, fresh.vertex_source);
    EXPECT_EQ(p->fragment_source, fresh.fragment_source);
    EXPECT_EQ(describe(*p), describe(fresh));  // every table entry, the features and the flags
  }
  expect_same_report(first_report, fresh_report);
  expect_same_report(hit_report, fresh_report);
}

TEST(ProgramCache, AChangedMaterialFeatureMisses) {
  ProgramCache cache;
  const Program plain = cache.optimize(generate(textured_lit_pbr()), constants(0.4f));
  MaterialFeatures normal_mapped = textured_lit_pbr();
  normal_mapped.normal_texture = true;
  const Program mapped = cache.optimize(generate(normal_mapped), constants(0.4f));
  EXPECT_EQ(cache.misses(), 2u);
  EXPECT_EQ(cache.hits(), 0u);
  EXPECT_NE(describe(mapped), describe(plain));
  EXPECT_EQ(describe(mapped), describe(optimize(generate(normal_mapped), constants(0.4f))));
  // The same features again is a hit on the right entry.
  EXPECT_EQ(describe(cache.optimize(generate(normal_mapped), constants(0.4f))), describe(mapped));
  EXPECT_EQ(cache.hits(), 1u);
}

TEST(ProgramCache, AChangedConstantMissesDownToItsBits) {
  ProgramCache cache;
  const Program generated = generate(textured_lit_pbr());
  const Program rough = cache.optimize(generated, constants(0.4f));
  const Program smoother = cache.optimize(generated, constants(0.3f));
  EXPECT_EQ(cache.misses(), 2u);
  EXPECT_NE(smoother.fragment_source, rough.fragment_source);
  EXPECT_EQ(describe(smoother), describe(optimize(generated, constants(0.3f))));
  // -0 and +0 are one printed number but two keys: the key never trusts a rounding.
  EXPECT_NE(ProgramCache::key(generated, constants(0.0f)), ProgramCache::key(generated, constants(-0.0f)));
  // A constant at another light index is another key.
  ConstantValues a = constants(0.4f), b = constants(0.4f);
  a.set(UniformSemantic::LightRange, 0, {0.0f});
  b.set(UniformSemantic::LightRange, 1, {0.0f});
  EXPECT_NE(ProgramCache::key(generated, a), ProgramCache::key(generated, b));
}

TEST(ProgramCache, EveryFieldOfTheGeneratedProgramIsInTheKey) {
  const Program base = generate(textured_lit_pbr());
  const std::string k = ProgramCache::key(base, {});
  auto differs = [&](auto change) {
    Program p = base;
    change(p);
    return ProgramCache::key(p, {}) != k;
  };
  EXPECT_TRUE(differs([](Program& p) { p.vertex_source += " "; }));
  EXPECT_TRUE(differs([](Program& p) { p.fragment_source += " "; }));
  EXPECT_TRUE(differs([](Program& p) { p.attributes[0].location += 1; }));
  EXPECT_TRUE(differs([](Program& p) { p.uniforms[0].name += "x"; }));
  EXPECT_TRUE(differs([](Program& p) { p.uniforms.back().array_size += 1; }));
  EXPECT_TRUE(differs([](Program& p) { p.samplers[0].unit += 1; }));
  EXPECT_TRUE(differs([](Program& p) { p.features.double_sided = !p.features.double_sided; }));
  EXPECT_TRUE(differs([](Program& p) { p.features.precision = Precision::Mediump; }));
  EXPECT_TRUE(differs([](Program& p) { p.blend = !p.blend; }));
  EXPECT_TRUE(differs([](Program& p) { p.cull_back_faces = !p.cull_back_faces; }));
  // Moving text from one source to the other is not the same program either.
  EXPECT_TRUE(differs([](Program& p) {
    p.fragment_source = p.vertex_source.substr(p.vertex_source.size() - 1) + p.fragment_source;
    p.vertex_source.pop_back();
  }));
}

TEST(ProgramCache, AFailingOptimizeThrowsEveryTimeAndCachesNothing) {
  ProgramCache cache;
  ConstantValues wrong;
  wrong.set(UniformSemantic::EmissiveFactor, {1.0f, 0.0f});  // a vec3 given two values
  const Program generated = generate(textured_lit_pbr());
  EXPECT_THROW(cache.optimize(generated, wrong), std::invalid_argument);
  EXPECT_THROW(cache.optimize(generated, wrong), std::invalid_argument);
  EXPECT_EQ(cache.size(), 0u);
  EXPECT_EQ(cache.hits(), 0u);
}

TEST(ProgramCache, TheLeastRecentlyUsedProgramLeavesFirst) {
  ProgramCache cache(2);
  const Program generated = generate(textured_lit_pbr());
  cache.optimize(generated, constants(0.1f));
  cache.optimize(generated, constants(0.2f));
  cache.optimize(generated, constants(0.1f));  // hit: 0.1 is now the most recent
  cache.optimize(generated, constants(0.3f));  // evicts 0.2
  EXPECT_EQ(cache.size(), 2u);
  EXPECT_EQ(cache.hits(), 1u);
  cache.optimize(generated, constants(0.1f));
  EXPECT_EQ(cache.hits(), 2u);
  cache.optimize(generated, constants(0.2f));
  EXPECT_EQ(cache.hits(), 2u);
  EXPECT_EQ(cache.misses(), 4u);
}

}  // namespace
}  // namespace meter::shadergen
