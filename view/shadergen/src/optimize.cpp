// The shader optimizer of the DENSO paper's Fig. 7, built from Debian's shader tools.
//   1. fold: uniforms the scene never changes become `const` declarations in the GLSL text
//   2. glslang: GLSL ES (as 3.10) -> SPIR-V with OpenGL semantics
//   3. spirv-opt performance passes: inlining, constant folding, dead-branch and dead-code removal
//   4. SPIRV-Cross: SPIR-V -> GLSL ES 3.00 (names and attribute locations survive)
// The fragment shader goes first: vertex outputs it no longer reads are demoted to plain globals
// before the vertex shader is compiled, so spirv-opt removes their computation too.
#include <spirv-tools/optimizer.hpp>
#include <spirv_cross_c.h>

#include <cmath>
#include <cstring>
#include <cstdio>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "meter/shadergen/glsl.hpp"
#include "meter/shadergen/shadergen.hpp"

namespace meter::shadergen {

namespace {

// ---------------------------------------------------------------- constant folding in the text

struct GlslType {
  int components = 0;
  bool integer = false;
};

GlslType type_info(const std::string& t) {
  if (t == "float") return {1, false};
  if (t == "vec2") return {2, false};
  if (t == "vec3") return {3, false};
  if (t == "vec4") return {4, false};
  if (t == "mat3") return {9, false};
  if (t == "mat4") return {16, false};
  if (t == "int") return {1, true};
  if (t == "ivec2") return {2, true};
  if (t == "ivec3") return {3, true};
  if (t == "ivec4") return {4, true};
  return {};
}

std::string number(float v, bool integer) {
  if (integer) return std::to_string(static_cast<long long>(v));
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(v));
  std::string s = buf;
  // GLSL needs a float literal to look like one ("1" is an int and would not convert in a ctor
  // of a const array).
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

std::string constructor(const std::string& type, const std::vector<float>& v, std::size_t first,
                        int components, bool integer) {
  std::string s = type + "(";
  for (int i = 0; i < components; ++i) {
    if (i) s += ", ";
    s += number(v[first + static_cast<std::size_t>(i)], integer);
  }
  return s + ")";
}

std::string fold_initializer(const UniformInfo& u, const std::vector<float>& v) {
  const GlslType t = type_info(u.glsl_type);
  if (t.components == 0)
    throw std::invalid_argument("shadergen: cannot fold uniform " + u.name + " of type " +
                                u.glsl_type);
  const std::size_t expected = static_cast<std::size_t>(t.components) *
                               static_cast<std::size_t>(u.array_size);
  if (v.size() != expected)
    throw std::invalid_argument("shadergen: constant for " + u.name + " (" +
                                to_string(u.semantic) + ", index " + std::to_string(u.index) +
                                ") has " + std::to_string(v.size()) + " values, expected " +
                                std::to_string(expected));
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v[i]))
      throw std::invalid_argument("shadergen: constant for " + u.name + " value " +
                                  std::to_string(i) + " is not finite");
    if (t.integer && v[i] != std::floor(v[i]))
      throw std::invalid_argument("shadergen: constant for integer uniform " + u.name +
                                  " value " + std::to_string(i) + " is not an integer");
  }
  if (!u.is_array()) return constructor(u.glsl_type, v, 0, t.components, t.integer);
  std::string s = u.glsl_type + "[" + std::to_string(u.array_size) + "](";
  for (int i = 0; i < u.array_size; ++i) {
    if (i) s += ", ";
    s += constructor(u.glsl_type, v, static_cast<std::size_t>(i * t.components), t.components,
                     t.integer);
  }
  return s + ")";
}

// Replaces the declaration line of `u` (as GlslBuilder wrote it) in `source`; false if absent.
bool replace_uniform_declaration(std::string& source, const UniformInfo& u,
                                 const std::string& initializer) {
  std::string decl = "uniform " + u.glsl_type + " " + u.name;
  if (u.is_array()) decl += "[" + std::to_string(u.array_size) + "]";
  decl += ";\n";
  const auto pos = source.find("\n" + decl);
  if (pos == std::string::npos) return false;
  std::string repl = "const " + u.glsl_type + " " + u.name;
  if (u.is_array()) repl += "[" + std::to_string(u.array_size) + "]";
  repl += " = " + initializer + ";\n";
  source.replace(pos + 1, decl.size(), repl);
  return true;
}

// ---------------------------------------------------------------- SPIR-V reflection

struct Interface {
  std::set<std::string> uniforms, inputs, outputs;  // named OpVariables (built-ins excluded)
};

Interface reflect(const std::vector<std::uint32_t>& words) {
  constexpr std::uint32_t kOpName = 5, kOpVariable = 59;
  constexpr std::uint32_t kUniformConstant = 0, kInput = 1, kOutput = 3;
  std::vector<std::string> names;
  std::vector<std::pair<std::uint32_t, std::uint32_t>> variables;  // id, storage class
  for (std::size_t i = 5; i < words.size();) {
    const std::uint32_t count = words[i] >> 16, op = words[i] & 0xffffu;
    if (count == 0 || i + count > words.size())
      throw std::runtime_error("shadergen: malformed SPIR-V while reflecting");
    if (op == kOpName && count >= 3) {
      const std::uint32_t id = words[i + 1];
      const char* text = reinterpret_cast<const char*>(&words[i + 2]);
      std::string s(text, strnlen(text, (count - 2) * 4));
      if (id >= names.size()) names.resize(id + 1);
      names[id] = s;
    } else if (op == kOpVariable && count >= 4) {
      variables.emplace_back(words[i + 2], words[i + 3]);
    }
    i += count;
  }
  Interface out;
  for (const auto& [id, storage] : variables) {
    if (id >= names.size() || names[id].empty() || names[id].rfind("gl_", 0) == 0) continue;
    if (storage == kUniformConstant) out.uniforms.insert(names[id]);
    if (storage == kInput) out.inputs.insert(names[id]);
    if (storage == kOutput) out.outputs.insert(names[id]);
  }
  return out;
}

// ---------------------------------------------------------------- spirv-opt and SPIRV-Cross

std::vector<std::uint32_t> run_spirv_opt(const std::vector<std::uint32_t>& in, const char* stage) {
  spvtools::Optimizer optimizer(SPV_ENV_UNIVERSAL_1_0);
  std::string messages;
  optimizer.SetMessageConsumer([&messages](spv_message_level_t level, const char*,
                                           const spv_position_t& pos, const char* text) {
    if (level <= SPV_MSG_ERROR)
      messages += "at word " + std::to_string(pos.index) + ": " + text + "\n";
  });
  // -O: merge/inline functions, fold constants, eliminate dead branches, code and variables.
  optimizer.RegisterPerformancePasses();
  std::vector<std::uint32_t> out;
  if (!optimizer.Run(in.data(), in.size(), &out))
    throw std::runtime_error(std::string("shadergen: spirv-opt failed on the ") + stage +
                             " shader: " + messages);
  return out;
}

// SPIR-V -> GLSL: ES 3.00 (`es`, the package's dialect) or desktop GLSL `version` (to_desktop_glsl).
std::string spirv_to_glsl(const std::vector<std::uint32_t>& spirv, int version, bool es,
                          bool highp_default, const char* stage) {
  spvc_context context = nullptr;
  if (spvc_context_create(&context) != SPVC_SUCCESS)
    throw std::runtime_error("shadergen: SPIRV-Cross: cannot create a context");
  std::string error;
  spvc_context_set_error_callback(
      context, [](void* user, const char* text) { *static_cast<std::string*>(user) += text; },
      &error);
  std::string result;
  bool ok = false;
  spvc_parsed_ir ir = nullptr;
  spvc_compiler compiler = nullptr;
  spvc_compiler_options options = nullptr;
  const char* text = nullptr;
  if (spvc_context_parse_spirv(context, spirv.data(), spirv.size(), &ir) == SPVC_SUCCESS &&
      spvc_context_create_compiler(context, SPVC_BACKEND_GLSL, ir,
                                   SPVC_CAPTURE_MODE_TAKE_OWNERSHIP, &compiler) == SPVC_SUCCESS &&
      spvc_compiler_create_compiler_options(compiler, &options) == SPVC_SUCCESS) {
    spvc_compiler_options_set_uint(options, SPVC_COMPILER_OPTION_GLSL_VERSION,
                                   static_cast<unsigned>(version));
    spvc_compiler_options_set_bool(options, SPVC_COMPILER_OPTION_GLSL_ES, es ? SPVC_TRUE : SPVC_FALSE);
    spvc_compiler_options_set_bool(options, SPVC_COMPILER_OPTION_GLSL_VULKAN_SEMANTICS, SPVC_FALSE);
    spvc_compiler_options_set_bool(options,
                                   SPVC_COMPILER_OPTION_GLSL_ES_DEFAULT_FLOAT_PRECISION_HIGHP,
                                   highp_default ? SPVC_TRUE : SPVC_FALSE);
    spvc_compiler_options_set_bool(options,
                                   SPVC_COMPILER_OPTION_GLSL_ES_DEFAULT_INT_PRECISION_HIGHP,
                                   SPVC_TRUE);
    if (spvc_compiler_install_compiler_options(compiler, options) == SPVC_SUCCESS &&
        spvc_compiler_compile(compiler, &text) == SPVC_SUCCESS && text) {
      result = text;
      ok = true;
    }
  }
  spvc_context_destroy(context);
  if (!ok)
    throw std::runtime_error(std::string("shadergen: SPIRV-Cross failed on the ") + stage +
                             " shader: " + error);
  return result;
}

// Makes `[flat ]out T name;` a private global so spirv-opt can delete everything that only feeds it.
void demote_vertex_output(std::string& vs, const std::string& name) {
  for (const std::string qualifier : {"\nout ", "\nflat out "}) {
    for (std::size_t pos = vs.find(qualifier); pos != std::string::npos; pos = vs.find(qualifier, pos + 1)) {
      const std::size_t end = vs.find(';', pos);
      if (end == std::string::npos) break;
      const std::string decl = vs.substr(pos + qualifier.size(), end - pos - qualifier.size());  // "[highp ]type name"
      const std::size_t space = decl.rfind(' ');
      if (space != std::string::npos && decl.substr(space + 1) == name) {
        vs.erase(pos + 1, qualifier.size() - 1);  // drop the qualifiers
        return;
      }
    }
  }
}

std::size_t count_fragment_inputs(const Interface& fs) { return fs.inputs.size(); }

}  // namespace

Program optimize(const Program& program, const ConstantValues& constants,
                 OptimizeReport* report) {
  if (program.vertex_source.empty() || program.fragment_source.empty())
    throw std::invalid_argument("shadergen: optimize() needs a program with both stages");
  if (program.optimized)
    throw std::invalid_argument("shadergen: program is already optimized (its sources are "
                                "SPIRV-Cross output, which the folder cannot rewrite)");

  // Before: the generated sources compiled without folding or optimisation.
  const auto vs_before = compile_to_spirv(program.vertex_source, ShaderStage::Vertex);
  const auto fs_before = compile_to_spirv(program.fragment_source, ShaderStage::Fragment);

  // 1. Fold.
  std::string vs = program.vertex_source, fs = program.fragment_source;
  std::set<std::string> folded;
  for (const UniformInfo& u : program.uniforms) {
    const std::vector<float>* values = constants.find(u.semantic, u.index);
    if (!values) continue;
    const std::string init = fold_initializer(u, *values);
    const bool in_vs = replace_uniform_declaration(vs, u, init);
    const bool in_fs = replace_uniform_declaration(fs, u, init);
    if (!in_vs && !in_fs)
      throw std::logic_error("shadergen: uniform " + u.name +
                             " is in the metadata but not declared in either stage");
    folded.insert(u.name);
  }

  // 2-4. Fragment first, then the vertex shader without the outputs the fragment no longer reads.
  const auto fs_opt = run_spirv_opt(compile_to_spirv(fs, ShaderStage::Fragment), "fragment");
  const Interface fs_if = reflect(fs_opt);
  const Interface vs_generated = reflect(vs_before);
  for (const std::string& out : vs_generated.outputs)
    if (!fs_if.inputs.count(out)) demote_vertex_output(vs, out);
  const auto vs_opt = run_spirv_opt(compile_to_spirv(vs, ShaderStage::Vertex), "vertex");
  const Interface vs_if = reflect(vs_opt);

  Program out = program;
  out.optimized = true;
  out.vertex_source = spirv_to_glsl(vs_opt, 300, true, true, "vertex");
  out.fragment_source = spirv_to_glsl(fs_opt, 300, true,
                                      program.features.precision == Precision::Highp, "fragment");

  // Metadata: exactly what the runtime still has to feed.
  out.uniforms.clear();
  for (const UniformInfo& u : program.uniforms)
    if (!folded.count(u.name) && (vs_if.uniforms.count(u.name) || fs_if.uniforms.count(u.name)))
      out.uniforms.push_back(u);
  out.samplers.clear();
  for (const SamplerInfo& s : program.samplers)
    if (fs_if.uniforms.count(s.name) || vs_if.uniforms.count(s.name)) out.samplers.push_back(s);
  out.attributes.clear();
  for (const AttributeInfo& a : program.attributes)
    if (vs_if.inputs.count(a.name)) out.attributes.push_back(a);

  if (report) {
    report->source_bytes_before = program.vertex_source.size() + program.fragment_source.size();
    report->source_bytes_after = out.vertex_source.size() + out.fragment_source.size();
    report->spirv_instructions_before =
        spirv_instruction_count(vs_before) + spirv_instruction_count(fs_before);
    report->spirv_instructions_after =
        spirv_instruction_count(vs_opt) + spirv_instruction_count(fs_opt);
    report->uniforms_before = program.uniforms.size();
    report->uniforms_after = out.uniforms.size();
    report->varyings_before = count_fragment_inputs(reflect(fs_before));
    report->varyings_after = count_fragment_inputs(fs_if);
    report->samplers_before = program.samplers.size();
    report->samplers_after = out.samplers.size();
    report->folded.assign(folded.begin(), folded.end());
  }
  return out;
}

namespace {

// glslang's auto-mapping gives every plain uniform a location and binding (SPIR-V with OpenGL
// semantics needs them). ES 3.00 output cannot express them and SPIRV-Cross drops them, but desktop
// output would print `layout(binding = N) uniform float x;`, which GLSL rejects for non-opaque types
// (and which would pin sampler units the runtime sets itself). Stripping them keeps both dialects
// identical in interface: uniforms found by name, samplers bound by glUniform1i. Varyings lose their
// auto-mapped locations too (they differ per stage, so a 4.x link would fail); they match by name,
// as in ES 3.00. Attribute and fragment-output locations stay.
std::vector<std::uint32_t> strip_auto_mapped_layouts(const std::vector<std::uint32_t>& words,
                                                  ShaderStage stage) {
  constexpr std::uint32_t kOpVariable = 59, kOpDecorate = 71, kUniformConstant = 0;
  constexpr std::uint32_t kInput = 1, kOutput = 3;
  const std::uint32_t varying = stage == ShaderStage::Vertex ? kOutput : kInput;
  constexpr std::uint32_t kLocation = 30, kBinding = 33, kDescriptorSet = 34;
  std::set<std::uint32_t> uniforms;
  for (std::size_t i = 5; i < words.size();) {
    const std::uint32_t count = words[i] >> 16, op = words[i] & 0xffffu;
    if (count == 0 || i + count > words.size())
      throw std::runtime_error("shadergen: malformed SPIR-V while stripping bindings");
    if (op == kOpVariable && count >= 4 &&
        (words[i + 3] == kUniformConstant || words[i + 3] == varying))
      uniforms.insert(words[i + 2]);
    i += count;
  }
  std::vector<std::uint32_t> out(words.begin(), words.begin() + 5);
  for (std::size_t i = 5; i < words.size();) {
    const std::uint32_t count = words[i] >> 16, op = words[i] & 0xffffu;
    const bool drop = op == kOpDecorate && count >= 3 && uniforms.count(words[i + 1]) &&
                      (words[i + 2] == kLocation || words[i + 2] == kBinding ||
                       words[i + 2] == kDescriptorSet);
    if (!drop) out.insert(out.end(), words.begin() + static_cast<std::ptrdiff_t>(i),
                          words.begin() + static_cast<std::ptrdiff_t>(i + count));
    i += count;
  }
  return out;
}

}  // namespace

Program to_desktop_glsl(const Program& program, int version) {
  if (version != 330 && version != 410 && version != 450)
    throw std::invalid_argument("shadergen: desktop GLSL version must be 330, 410 or 450, got " +
                                std::to_string(version));
  if (program.vertex_source.empty() || program.fragment_source.empty())
    throw std::invalid_argument("shadergen: to_desktop_glsl() needs a program with both stages");
  // A pure dialect change: no spirv-opt, so the code is what the ES source says (precision
  // qualifiers disappear; desktop GLSL computes at full precision anyway).
  Program out = program;
  out.vertex_source = spirv_to_glsl(
      strip_auto_mapped_layouts(compile_to_spirv(program.vertex_source, ShaderStage::Vertex),
                             ShaderStage::Vertex),
      version,
      false, true, "vertex");
  out.fragment_source = spirv_to_glsl(
      strip_auto_mapped_layouts(compile_to_spirv(program.fragment_source, ShaderStage::Fragment),
                             ShaderStage::Fragment),
      version, false, true, "fragment");
  return out;
}

}  // namespace meter::shadergen
