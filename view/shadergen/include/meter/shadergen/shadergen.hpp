// meter::shadergen — the offline shader generator and optimizer (the DENSO engine's "shader
// generator" and "shader optimizer"). A pure library: it turns a material's feature set into GLSL
// ES 3.00 source plus the metadata the runtime needs (meter/bridge/program.hpp). No GL context is
// involved; the runtime never links this library (the converter stores the programs in the scene
// package).
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "meter/bridge/program.hpp"

namespace meter::shadergen {

// The program vocabulary, under the generator's own names.
using bridge::AlphaMode;
using bridge::AttributeInfo;
using bridge::AttributeSemantic;
using bridge::kMaxLights;
using bridge::kMaxShadowMaps;
using bridge::kMaxMorphTargets;
using bridge::kMaxSkinJoints;
using bridge::LightCounts;
using bridge::MaterialFeatures;
using bridge::OptimizeReport;
using bridge::Precision;
using bridge::Program;
using bridge::SamplerInfo;
using bridge::ShadingModel;
using bridge::TextureSlot;
using bridge::UniformInfo;
using bridge::UniformSemantic;
using bridge::to_string;

// The same features with the fields the shading model never reads cleared (lights on Unlit, ...),
// so equal programs share one key. Validates: throws std::invalid_argument naming the field.
MaterialFeatures canonical(const MaterialFeatures& features);
// Canonical, unique per distinct generated program (program cache / dedup key).
std::string program_key(const MaterialFeatures& features);

// Throws std::invalid_argument naming the field for impossible sets (negative counts, a texture
// the shading model cannot use, limits exceeded, texture_transform without textures, ...).
Program generate(const MaterialFeatures& features);

// Constants the scene never changes are folded into the code; only uniforms the runtime still
// changes remain.
// Key = (semantic, index) exactly as in UniformInfo; value = the uniform's floats in GLSL
// column-major order (vec3 -> 3, mat3 -> 9, float[N] -> N, mat4[N] -> 16 N).
struct ConstantValues {
  std::map<std::pair<UniformSemantic, int>, std::vector<float>> values;

  void set(UniformSemantic semantic, int index, std::vector<float> v) {
    values[{semantic, index}] = std::move(v);
  }
  void set(UniformSemantic semantic, std::vector<float> v) { set(semantic, -1, std::move(v)); }
  const std::vector<float>* find(UniformSemantic semantic, int index = -1) const {
    auto it = values.find({semantic, index});
    return it == values.end() ? nullptr : &it->second;
  }
  bool empty() const { return values.empty(); }
};

// GLSL ES -> SPIR-V (glslang) -> spirv-opt -> GLSL ES 3.00 (SPIRV-Cross). Uniforms whose
// (semantic, index) appear in `constants` become `const` values; wrong value counts or non-finite
// values throw std::invalid_argument. Throws std::runtime_error with the compiler log if a stage fails.
Program optimize(const Program& program, const ConstantValues& constants,
                 OptimizeReport* report = nullptr);

// The same program as desktop GLSL (`#version 330|410|450` core, through glslang ->
// SPIR-V -> SPIRV-Cross, no optimisation: a dialect change only; metadata unchanged). Not stored in
// scene packages: both backends run the GLSL ES 3.00 text (OSMesa's core context through
// ARB_ES3_compatibility); the bench and tests/shader-optimizer use this to measure and check that
// choice (docs/shader-optimizer.md). Throws std::invalid_argument for other versions.
Program to_desktop_glsl(const Program& program, int version = 330);

// ONE shader with runtime switches (all textures, up to 2 lights per type, Blinn-Phong or PBR,
// skinning with kMaxSkinJoints joints): only as a benchmark baseline.
Program generate_uber();

}  // namespace meter::shadergen
