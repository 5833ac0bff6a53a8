// glslang front end: ES 3.00 validation and GLSL -> SPIR-V.
#include "meter/shadergen/glsl.hpp"

#include <glslang/Public/ResourceLimits.h>
#include <glslang/Public/ShaderLang.h>
#include <glslang/SPIRV/GlslangToSpv.h>

#include <memory>
#include <mutex>
#include <stdexcept>

namespace meter::shadergen {

namespace {

// glslang keeps process-wide tables; InitializeProcess must run once before any TShader exists.
// It is never finalized: programs may generate shaders until exit.
void ensure_glslang() {
  static std::once_flag once;
  std::call_once(once, [] { glslang::InitializeProcess(); });
}

EShLanguage language(ShaderStage stage) {
  return stage == ShaderStage::Vertex ? EShLangVertex : EShLangFragment;
}

const char* stage_name(ShaderStage stage) {
  return stage == ShaderStage::Vertex ? "vertex" : "fragment";
}

// Replaces the first line's "#version 300 es" by "#version 310 es".
std::string as_es310(const std::string& source) {
  const std::string from = "#version 300 es";
  if (source.compare(0, from.size(), from) != 0)
    throw std::runtime_error("shadergen: source does not start with \"#version 300 es\"");
  return "#version 310 es" + source.substr(from.size());
}

}  // namespace

CompileCheck check_compiles(const Program& program) {
  ensure_glslang();
  CompileCheck result;
  const ShaderStage stages[] = {ShaderStage::Vertex, ShaderStage::Fragment};
  std::unique_ptr<glslang::TShader> shaders[2];
  glslang::TProgram linked;
  for (int i = 0; i < 2; ++i) {
    const std::string& src = i == 0 ? program.vertex_source : program.fragment_source;
    shaders[i] = std::make_unique<glslang::TShader>(language(stages[i]));
    const char* text = src.c_str();
    shaders[i]->setStrings(&text, 1);
    // Default version 100 is only used when the source has no #version; ours always has one.
    if (!shaders[i]->parse(GetDefaultResources(), 100, ENoProfile, false, false, EShMsgDefault)) {
      result.log = std::string(stage_name(stages[i])) + " shader: " + shaders[i]->getInfoLog();
      return result;
    }
    linked.addShader(shaders[i].get());
  }
  if (!linked.link(EShMsgDefault)) {
    result.log = std::string("link: ") + linked.getInfoLog();
    return result;
  }
  result.ok = true;
  return result;
}

std::vector<std::uint32_t> compile_to_spirv(const std::string& glsl_es, ShaderStage stage) {
  ensure_glslang();
  const std::string src = as_es310(glsl_es);
  const EShLanguage lang = language(stage);
  glslang::TShader shader(lang);
  const char* text = src.c_str();
  shader.setStrings(&text, 1);
  shader.setEnvInput(glslang::EShSourceGlsl, lang, glslang::EShClientOpenGL, 100);
  shader.setEnvClient(glslang::EShClientOpenGL, glslang::EShTargetOpenGL_450);
  shader.setEnvTarget(glslang::EShTargetSpv, glslang::EShTargetSpv_1_0);
  // OpenGL-semantics SPIR-V wants explicit locations on plain uniforms and varyings.
  shader.setAutoMapLocations(true);
  shader.setAutoMapBindings(true);
  const auto messages = static_cast<EShMessages>(EShMsgSpvRules);
  if (!shader.parse(GetDefaultResources(), 310, EEsProfile, false, false, messages))
    throw std::runtime_error(std::string("shadergen: glslang (") + stage_name(stage) +
                             " shader, as ES 3.10): " + shader.getInfoLog());
  glslang::TProgram program;
  program.addShader(&shader);
  if (!program.link(messages) || !program.mapIO())
    throw std::runtime_error(std::string("shadergen: glslang link (") + stage_name(stage) +
                             "): " + program.getInfoLog());
  std::vector<std::uint32_t> spirv;
  spv::SpvBuildLogger logger;
  glslang::SpvOptions options;
  options.disableOptimizer = true;  // spirv-opt runs separately so the report can compare
  glslang::GlslangToSpv(*program.getIntermediate(lang), spirv, &logger, &options);
  if (spirv.empty())
    throw std::runtime_error(std::string("shadergen: SPIR-V generation failed (") +
                             stage_name(stage) + "): " + logger.getAllMessages());
  return spirv;
}

std::size_t spirv_instruction_count(const std::vector<std::uint32_t>& words) {
  constexpr std::size_t kHeaderWords = 5;
  if (words.size() < kHeaderWords || words[0] != 0x07230203u)
    throw std::invalid_argument("shadergen: not a SPIR-V module (bad magic or too short)");
  std::size_t count = 0;
  for (std::size_t i = kHeaderWords; i < words.size();) {
    const std::uint32_t word_count = words[i] >> 16;
    if (word_count == 0 || i + word_count > words.size())
      throw std::invalid_argument("shadergen: malformed SPIR-V instruction at word " +
                                  std::to_string(i));
    i += word_count;
    ++count;
  }
  return count;
}

}  // namespace meter::shadergen
