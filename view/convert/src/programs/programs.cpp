// Program generation: one program per distinct draw (the shader generator's features, plus the
// material when the shader optimizer folds its constants), in draw order = node_preorder with the
// primitives of each mesh in order. The scene-wide light set is light_order.
#include <map>
#include <set>

#include "convert_context.hpp"
#include "meter/shadergen/glsl.hpp"
#include "meter/shadergen/program_cache.hpp"
#include "programs/program_features.hpp"

namespace meter::convert {

namespace {

// Without the optimizer: the same measurements optimize() reports, so --report compares like with like.
void measure_unoptimized(ProgramEntry& e) {
  auto& r = e.optimize_report;
  r.spirv_instructions_before = r.spirv_instructions_after =
      shadergen::spirv_instruction_count(shadergen::compile_to_spirv(e.program.vertex_source, shadergen::ShaderStage::Vertex)) +
      shadergen::spirv_instruction_count(shadergen::compile_to_spirv(e.program.fragment_source, shadergen::ShaderStage::Fragment));
  r.uniforms_before = r.uniforms_after = e.program.uniforms.size();
  r.samplers_before = r.samplers_after = e.program.samplers.size();
  r.source_bytes_before = r.source_bytes_after = e.program.vertex_source.size() + e.program.fragment_source.size();
}

}  // namespace

void generate_programs(const ConvertContext& ctx, Scene& s) {
  const std::vector<int> light_nodes = light_order(s);
  const shadergen::LightCounts lights = count_lights(s, light_nodes);
  if (lights.total() > shadergen::kMaxLights) {
    throw SceneError(ctx.file + ": extensions.KHR_lights_punctual: the scene uses " + std::to_string(lights.total()) +
                     " lights; at most " + std::to_string(shadergen::kMaxLights) + " are supported");
  }
  std::set<int> bound_materials;
  for (const auto& b : ctx.cfg.bindings) {
    if (b.kind == BindingKind::Emissive || b.kind == BindingKind::Color) bound_materials.insert(s.find_material(b.material));
  }
  for (const auto& sc : ctx.cfg.scripts)  // scripts' colour / emissive outputs: not folded either
    for (const auto& o : sc.outputs)
      if (targets_material(o.kind)) bound_materials.insert(s.find_material(o.target));
  // The theme mixes its day materials' colours at runtime: they stay uniforms too.
  if (ctx.cfg.features.theme)
    for (const auto& p : ctx.cfg.features.theme->pairs) bound_materials.insert(s.find_material(p.day));
  const auto dyn = dynamic_nodes(s);
  // Draws of one feature set (and folded material) share a program; programs equal to one
  // optimized before (another material with the same constants, an earlier conversion) come
  // from the optimizer's cache.
  shadergen::ProgramCache own_cache;
  shadergen::ProgramCache& optimized = ctx.opt.program_cache ? *ctx.opt.program_cache : own_cache;
  std::map<std::string, int> cache;
  for (const int n : node_preorder(s)) {
    const Node& node = s.nodes[static_cast<std::size_t>(n)];
    if (node.mesh < 0) continue;
    const Mesh& mesh = s.meshes[static_cast<std::size_t>(node.mesh)];
    for (std::size_t pi = 0; pi < mesh.primitives.size(); ++pi) {
      const Primitive& prim = mesh.primitives[pi];
      const Material& mat = s.materials[static_cast<std::size_t>(prim.material)];
      // Concatenated members: visibility becomes vertex alpha. The unmerged draw of the same
      // node feeds a constant 1 (Renderer), so one program serves both ways of drawing.
      const shadergen::MaterialFeatures f = shadergen::canonical(draw_features(s, node, prim, lights, ctx.group_members.count(n) > 0));
      const bool fold_material = ctx.opt.optimize && !bound_materials.count(prim.material);
      std::string key = shadergen::program_key(f);
      if (ctx.opt.optimize) key += fold_material ? "|mat" + std::to_string(prim.material) : "|dynmat";
      auto it = cache.find(key);
      int program = -1;
      if (it != cache.end()) {
        program = it->second;
      } else {
        ProgramEntry e;
        try {
          e.program = shadergen::generate(f);
          if (ctx.opt.optimize) {
            const shadergen::ConstantValues cv = folding_constants(s, mat, fold_material, light_nodes, dyn);
            e.program = optimized.optimize(e.program, cv, &e.optimize_report);
          } else {
            measure_unoptimized(e);
          }
        } catch (const std::exception& ex) {
          throw SceneError(ctx.file + ": " + idx("meshes", static_cast<std::size_t>(node.mesh)) + idx(".primitives", pi) + " (material \"" + mat.name +
                           "\", features " + shadergen::program_key(f) + "): shader generation failed: " + ex.what());
        }
        program = static_cast<int>(s.programs.size());
        s.programs.push_back(std::move(e));
        cache[key] = program;
      }
      s.draws.push_back({n, node.mesh, static_cast<int>(pi), program});
    }
  }
}

}  // namespace meter::convert
