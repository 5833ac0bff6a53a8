// A small accumulator for the two stages of a program and their metadata. Every declaration is
// emitted on its own line in a fixed form (`uniform <type> <name>;`, `out <type> <name>;`) because
// optimize() rewrites those lines to fold constants and drop dead varyings.
#pragma once

#include <string>

#include "meter/shadergen/shadergen.hpp"

namespace meter::shadergen::detail {

enum class Stage { Vertex, Fragment };

class GlslBuilder {
 public:
  explicit GlslBuilder(Precision fragment_precision) : precision_(fragment_precision) {}

  // Declares `uniform <type> <name>[array];` in one stage and records its metadata.
  void uniform(Stage stage, const std::string& name, const std::string& type,
               UniformSemantic semantic, int index = -1, int array_size = 1) {
    const UniformInfo info{name, type, semantic, index, array_size};
    std::string line = "uniform " + type + " " + name;
    if (info.is_array()) line += "[" + std::to_string(array_size) + "]";
    line += ";\n";
    (stage == Stage::Vertex ? vs_uniforms_ : fs_uniforms_) += line;
    program_.uniforms.push_back(info);
  }

  // A fragment-stage sampler on the next texture unit. A shadow map is a depth-compare sampler
  // (highp: depths need full precision) and names its light (`index`); the environment is the
  // world's reflection probe, a cube map.
  void sampler(const std::string& name, TextureSlot slot, int index = -1) {
    const char* type = slot == TextureSlot::ShadowMap     ? "uniform highp sampler2DShadow "
                       : slot == TextureSlot::Environment ? "uniform samplerCube "
                                                          : "uniform sampler2D ";
    fs_uniforms_ += type + name + ";\n";
    const int unit = static_cast<int>(program_.samplers.size());
    program_.samplers.push_back({name, slot, unit, index});
  }

  // `layout(location = n) in <type> <name>;` with locations assigned in declaration order.
  void attribute(const std::string& name, const std::string& type, AttributeSemantic semantic,
                 int components, int index = -1) {
    const int location = static_cast<int>(program_.attributes.size());
    vs_inputs_ += "layout(location = " + std::to_string(location) + ") in " + type + " " + name +
                  ";\n";
    program_.attributes.push_back({name, semantic, index, location, components});
  }

  // A vertex output / fragment input pair. `highp` forces full precision in a mediump fragment
  // shader (world positions and texture coordinates need it).
  void varying(const std::string& name, const std::string& type, bool highp = false) {
    const std::string t = (highp ? "highp " : "") + type;
    vs_outputs_ += "out " + t + " " + name + ";\n";
    fs_inputs_ += "in " + t + " " + name + ";\n";
  }

  // A vertex output every fragment of a primitive takes from its provoking (last) vertex.
  void flat_varying(const std::string& name, const std::string& type) {
    vs_outputs_ += "flat out " + type + " " + name + ";\n";
    fs_inputs_ += "flat in " + type + " " + name + ";\n";
  }

  std::string vs_functions, vs_body, fs_functions, fs_body;
  Program& program() { return program_; }

  Program finish(const std::string& banner) {
    program_.vertex_source = "#version 300 es\n// " + banner + "\n" + vs_inputs_ + vs_uniforms_ +
                             vs_outputs_ + vs_functions + "void main() {\n" + vs_body + "}\n";
    program_.fragment_source =
        "#version 300 es\n// " + banner + "\nprecision " +
        (precision_ == Precision::Highp ? "highp" : "mediump") + " float;\n" + fs_inputs_ +
        fs_uniforms_ + "layout(location = 0) out vec4 o_color;\n" + fs_functions +
        "void main() {\n" + fs_body + "}\n";
    return program_;
  }

 private:
  Precision precision_;
  Program program_;
  std::string vs_inputs_, vs_uniforms_, vs_outputs_, fs_inputs_, fs_uniforms_;
};

}  // namespace meter::shadergen::detail
