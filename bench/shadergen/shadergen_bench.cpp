// bench/shadergen: what the generator and optimizer cost at conversion time, and what they buy,
// measured side by side in one run against the uber-shader baseline.
//   1. a table per program: source bytes, SPIR-V instructions, uniforms, varyings before/after
//      optimize() (constants folded as a cluster scene would), and the ratio to the uber shader;
//   2. Google Benchmark timings: generate(), optimize() and the uber shader's optimize().
#include <benchmark/benchmark.h>

#include <cstdio>
#include <string>
#include <vector>

#include "meter/shadergen/shadergen.hpp"

using namespace meter::shadergen;

namespace {

struct Case {
  const char* name;
  MaterialFeatures features;
};

std::vector<Case> cases() {
  std::vector<Case> c;
  MaterialFeatures f;
  f.shading = ShadingModel::Unlit;
  f.base_color_texture = true;
  f.vertex_alpha = true;
  f.alpha = AlphaMode::Blend;
  c.push_back({"unlit_telltale", f});
  f = {};
  f.shading = ShadingModel::Flat;
  f.lights = {1, 0, 0};
  c.push_back({"flat_1dir", f});
  f = {};
  f.shading = ShadingModel::Gouraud;
  f.lights = {1, 2, 0};
  c.push_back({"gouraud_1dir_2pt", f});
  f = {};
  f.shading = ShadingModel::BlinnPhong;
  f.base_color_texture = true;
  f.lights = {1, 1, 0};
  c.push_back({"blinn_tex_1dir_1pt", f});
  f = {};
  f.lights = {1, 0, 0};
  c.push_back({"pbr_1dir", f});
  f = {};
  f.base_color_texture = f.metallic_roughness_texture = f.normal_texture = true;
  f.emissive_texture = f.occlusion_texture = true;
  f.lights = {1, 1, 1};
  c.push_back({"pbr_all_textures_3lights", f});
  f = {};
  f.skin_joints = 16;
  f.lights = {1, 0, 0};
  c.push_back({"pbr_skin16", f});
  f = {};
  f.morph_targets = 4;
  f.morph_normals = true;
  f.lights = {1, 0, 0};
  c.push_back({"pbr_morph4", f});
  f = {};
  f.environment_map_2d = true;
  f.base_color_texture = true;
  f.lights = {0, 0, 1};
  c.push_back({"pbr_env_spot", f});
  return c;
}

// What a cluster scene typically never changes: material factors, exposure, light ranges and cones.
ConstantValues scene_constants() {
  ConstantValues c;
  c.set(UniformSemantic::MetallicFactor, {0.8f});
  c.set(UniformSemantic::RoughnessFactor, {0.35f});
  c.set(UniformSemantic::EmissiveFactor, {0.0f, 0.0f, 0.0f});
  c.set(UniformSemantic::NormalScale, {1.0f});
  c.set(UniformSemantic::OcclusionStrength, {1.0f});
  c.set(UniformSemantic::Exposure, {1.0f});
  c.set(UniformSemantic::SpecularColor, {0.5f, 0.5f, 0.5f});
  c.set(UniformSemantic::Shininess, {32.0f});
  c.set(UniformSemantic::AmbientLight, {0.05f, 0.05f, 0.05f});
  for (int i = 0; i < kMaxLights; ++i) {
    c.set(UniformSemantic::LightRange, i, {0.0f});
    c.set(UniformSemantic::LightInnerConeCos, i, {0.95f});
    c.set(UniformSemantic::LightOuterConeCos, i, {0.85f});
    c.set(UniformSemantic::LightColor, i, {1.0f, 1.0f, 1.0f});
  }
  return c;
}

void print_table() {
  const ConstantValues constants = scene_constants();
  OptimizeReport uber_plain;
  optimize(generate_uber(), {}, &uber_plain);
  std::printf("%-26s %13s %13s %11s %9s %8s | %s\n", "program", "src bytes", "SPIR-V instr",
              "uniforms", "varyings", "samplers", "vs uber: SPIR-V after / uber's after");
  auto row = [&](const char* name, const OptimizeReport& r) {
    std::printf("%-26s %6zu->%6zu %6zu->%6zu %5zu->%5zu %4zu->%4zu %3zu->%3zu | %.3f\n", name,
                r.source_bytes_before, r.source_bytes_after, r.spirv_instructions_before,
                r.spirv_instructions_after, r.uniforms_before, r.uniforms_after, r.varyings_before,
                r.varyings_after, r.samplers_before, r.samplers_after,
                double(r.spirv_instructions_after) / double(uber_plain.spirv_instructions_after));
  };
  for (const Case& c : cases()) {
    OptimizeReport r;
    optimize(generate(c.features), constants, &r);
    row(c.name, r);
  }
  row("uber (no folding)", uber_plain);
  std::printf("\n");
}

void BM_Generate(benchmark::State& state, MaterialFeatures f) {
  for (auto _ : state) benchmark::DoNotOptimize(generate(f));
}

void BM_Optimize(benchmark::State& state, MaterialFeatures f) {
  const Program p = generate(f);
  const ConstantValues constants = scene_constants();
  for (auto _ : state) benchmark::DoNotOptimize(optimize(p, constants));
}

void BM_OptimizeUber(benchmark::State& state) {
  const Program p = generate_uber();
  for (auto _ : state) benchmark::DoNotOptimize(optimize(p, {}));
}

}  // namespace

int main(int argc, char** argv) {
  print_table();
  for (const Case& c : cases()) {
    benchmark::RegisterBenchmark((std::string("generate/") + c.name).c_str(), BM_Generate, c.features)
        ->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark((std::string("optimize/") + c.name).c_str(), BM_Optimize, c.features)
        ->Unit(benchmark::kMillisecond);
  }
  benchmark::RegisterBenchmark("optimize/uber", BM_OptimizeUber)->Unit(benchmark::kMillisecond);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
