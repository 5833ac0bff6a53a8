// Offline checks on generated programs with glslang (no GL context): used by the unit tests, the
// meter-shadergen tool and optimize().
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "meter/shadergen/shadergen.hpp"

namespace meter::shadergen {

struct CompileCheck {
  bool ok = false;
  std::string log;  // glslang's info log, prefixed with the failing stage
};

// Parses both stages exactly as written ("#version 300 es", ES profile) and links them.
CompileCheck check_compiles(const Program& program);

enum class ShaderStage { Vertex, Fragment };

// One stage's GLSL ES source -> SPIR-V 1.0 with OpenGL semantics. The `#version 300 es` line is
// raised to `310 es` because glslang only emits SPIR-V for ES >= 310; locations are auto-mapped.
// Throws std::runtime_error with glslang's log on failure.
std::vector<std::uint32_t> compile_to_spirv(const std::string& glsl_es, ShaderStage stage);

// Number of instructions in a SPIR-V module (header excluded).
std::size_t spirv_instruction_count(const std::vector<std::uint32_t>& words);

}  // namespace meter::shadergen
