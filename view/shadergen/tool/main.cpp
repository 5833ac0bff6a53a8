// meter-shadergen: prints the generated program for a feature set (sources and metadata) and,
// with --optimize, the optimizer's report. meter-convert --report uses the same library calls.
//
//   meter-shadergen --shading pbr --textures base_color,normal --lights 1,2,0 --optimize
//     --const MetallicFactor=0 --const LightColor:0=1,1,1
#include <CLI/CLI.hpp>

#include <cstdio>
#include <iostream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "meter/shadergen/glsl.hpp"
#include "meter/shadergen/shadergen.hpp"

using namespace meter::shadergen;

namespace {

template <typename E>
E parse_enum(const std::string& text, E last, const char* what) {
  for (int i = 0; i <= static_cast<int>(last); ++i)
    if (text == to_string(static_cast<E>(i))) return static_cast<E>(i);
  throw std::invalid_argument(std::string("unknown ") + what + " '" + text + "'");
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, sep);)
    if (!item.empty()) out.push_back(item);
  return out;
}

// "Semantic[:index]=v1,v2,..."
void parse_constant(const std::string& spec, ConstantValues& c) {
  const auto eq = spec.find('=');
  if (eq == std::string::npos)
    throw std::invalid_argument("--const '" + spec + "': expected Semantic[:index]=v1,v2,...");
  std::string name = spec.substr(0, eq);
  int index = -1;
  if (const auto colon = name.find(':'); colon != std::string::npos) {
    index = std::stoi(name.substr(colon + 1));
    name = name.substr(0, colon);
  }
  const auto semantic = parse_enum(name, UniformSemantic::UberLightCounts, "uniform semantic");
  std::vector<float> values;
  for (const auto& v : split(spec.substr(eq + 1), ',')) {
    std::size_t used = 0;
    const float f = std::stof(v, &used);
    if (used != v.size()) throw std::invalid_argument("--const '" + spec + "': bad number '" + v + "'");
    values.push_back(f);
  }
  c.set(semantic, index, std::move(values));
}

void print_metadata(const Program& p) {
  std::printf("program %s\n", p.uber ? "uber" : meter::shadergen::program_key(p.features).c_str());
  std::printf("  blend %s, cull back faces %s, optimized %s\n", p.blend ? "on" : "off",
              p.cull_back_faces ? "on" : "off", p.optimized ? "yes" : "no");
  std::printf("  attributes (%zu):\n", p.attributes.size());
  for (const auto& a : p.attributes)
    std::printf("    location %d  %-20s %s%s x%d\n", a.location, a.name.c_str(),
                to_string(a.semantic),
                a.index >= 0 ? ("[" + std::to_string(a.index) + "]").c_str() : "", a.components);
  std::printf("  uniforms (%zu):\n", p.uniforms.size());
  for (const auto& u : p.uniforms)
    std::printf("    %-6s %-28s %s%s%s\n", u.glsl_type.c_str(), u.name.c_str(),
                to_string(u.semantic),
                u.index >= 0 ? (" index " + std::to_string(u.index)).c_str() : "",
                u.is_array() ? (" [" + std::to_string(u.array_size) + "]").c_str() : "");
  std::printf("  samplers (%zu):\n", p.samplers.size());
  for (const auto& s : p.samplers)
    std::printf("    unit %d  %-28s %s\n", s.unit, s.name.c_str(), to_string(s.slot));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"meter-shadergen: generate (and optimize) the shader program of one feature set"};
  std::string shading = "pbr", alpha = "opaque", textures, texcoord1, lights = "0,0,0", print = "all";
  bool mediump = false, tt = false, vc = false, va = false, ds = false, morph_normals = false;
  bool env = false, tangents = false, uber = false, opt = false, check = false;
  int skin = 0, morph = 0;
  unsigned shadows = 0;
  std::vector<std::string> consts;
  app.add_option("--shading", shading, "unlit | flat | gouraud | blinn-phong | pbr");
  app.add_option("--alpha", alpha, "opaque | mask | blend");
  app.add_flag("--mediump", mediump, "mediump fragment precision");
  app.add_option("--textures", textures,
                 "comma list of base_color,metallic_roughness,normal,emissive,occlusion");
  app.add_option("--texcoord1", texcoord1, "comma list of textures that read TEXCOORD_1");
  app.add_flag("--texture-transform", tt, "KHR_texture_transform");
  app.add_flag("--vertex-colors", vc, "COLOR_0");
  app.add_flag("--vertex-alpha", va, "concatenated-mesh visibility attribute");
  app.add_flag("--double-sided", ds);
  app.add_option("--skin", skin, "number of joints (0 = no skinning)");
  app.add_option("--morph", morph, "number of morph targets");
  app.add_flag("--morph-normals", morph_normals);
  app.add_option("--lights", lights, "directional,point,spot counts");
  app.add_option("--shadows", shadows, "bit mask of the lights (in D,P,S order) that cast shadows");
  app.add_flag("--env", env, "equirectangular environment reflection");
  app.add_flag("--tangents", tangents, "mesh has TANGENT");
  app.add_flag("--uber", uber, "print the uber-shader baseline instead");
  app.add_flag("--optimize", opt, "run the optimizer and print its report");
  app.add_option("--const", consts, "fold a uniform: Semantic[:index]=v1,v2,... (repeatable)");
  app.add_option("--print", print, "all | meta | vertex | fragment | report | key");
  app.add_flag("--check", check, "compile both stages with glslang (ES 3.00) and link");
  CLI11_PARSE(app, argc, argv);

  try {
    Program p;
    if (uber) {
      p = generate_uber();
    } else {
      MaterialFeatures f;
      f.shading = parse_enum(shading, ShadingModel::PbrMetallicRoughness, "shading model");
      f.alpha = parse_enum(alpha, AlphaMode::Blend, "alpha mode");
      f.precision = mediump ? Precision::Mediump : Precision::Highp;
      for (const auto& t : split(textures, ',')) {
        switch (parse_enum(t, TextureSlot::Occlusion, "texture")) {
          case TextureSlot::BaseColor: f.base_color_texture = true; break;
          case TextureSlot::MetallicRoughness: f.metallic_roughness_texture = true; break;
          case TextureSlot::Normal: f.normal_texture = true; break;
          case TextureSlot::Emissive: f.emissive_texture = true; break;
          case TextureSlot::Occlusion: f.occlusion_texture = true; break;
          case TextureSlot::Environment: break;  // --env
          case TextureSlot::ShadowMap: break;    // --shadows
        }
      }
      for (const auto& t : split(texcoord1, ','))
        f.texcoord1_slots |= 1u << static_cast<unsigned>(parse_enum(t, TextureSlot::Occlusion, "texture"));
      f.texture_transform = tt;
      f.vertex_colors = vc;
      f.vertex_alpha = va;
      f.double_sided = ds;
      f.skin_joints = skin;
      f.morph_targets = morph;
      f.morph_normals = morph_normals;
      const auto counts = split(lights, ',');
      if (counts.size() != 3) throw std::invalid_argument("--lights: expected D,P,S");
      f.lights = {std::stoi(counts[0]), std::stoi(counts[1]), std::stoi(counts[2]), shadows};
      f.environment_map_2d = env;
      f.has_tangents = tangents;
      if (print == "key") {
        std::printf("%s\n", meter::shadergen::program_key(f).c_str());
        return 0;
      }
      p = generate(f);
    }
    OptimizeReport report;
    if (opt) {
      ConstantValues c;
      for (const auto& s : consts) parse_constant(s, c);
      p = optimize(p, c, &report);
    } else if (!consts.empty()) {
      throw std::invalid_argument("--const needs --optimize");
    }
    const bool all = print == "all";
    if (all || print == "meta") print_metadata(p);
    if (all || print == "vertex") std::printf("---- vertex shader\n%s", p.vertex_source.c_str());
    if (all || print == "fragment") std::printf("---- fragment shader\n%s", p.fragment_source.c_str());
    if (opt && (all || print == "report")) {
      std::printf("---- optimize report\n");
      std::printf("  source bytes       %6zu -> %6zu\n", report.source_bytes_before, report.source_bytes_after);
      std::printf("  SPIR-V instructions%6zu -> %6zu\n", report.spirv_instructions_before,
                  report.spirv_instructions_after);
      std::printf("  uniforms           %6zu -> %6zu\n", report.uniforms_before, report.uniforms_after);
      std::printf("  samplers           %6zu -> %6zu\n", report.samplers_before, report.samplers_after);
      std::printf("  varyings           %6zu -> %6zu\n", report.varyings_before, report.varyings_after);
      std::printf("  folded:");
      for (const auto& n : report.folded) std::printf(" %s", n.c_str());
      std::printf("\n");
    }
    if (check) {
      const CompileCheck c = check_compiles(p);
      std::printf("glslang ES 3.00 check: %s\n%s", c.ok ? "ok" : "FAILED", c.log.c_str());
      if (!c.ok) return 1;
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "meter-shadergen: %s\n", e.what());
    return 2;
  }
  return 0;
}
