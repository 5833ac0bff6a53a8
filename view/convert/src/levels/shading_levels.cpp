// Shading levels: each draw's program again with every lower shading model (levels.hpp).
#include <algorithm>
#include <map>

#include "levels/level_stages.hpp"
#include "meter/shadergen/shadergen.hpp"
#include "programs/program_features.hpp"

namespace meter::convert {

namespace {

using shadergen::ShadingModel;

// The lower models, most expensive first.
constexpr ShadingModel kLower[] = {ShadingModel::BlinnPhong, ShadingModel::Gouraud, ShadingModel::Flat, ShadingModel::Unlit};

bool same_code(const bridge::Program& a, const bridge::Program& b) {
  return a.vertex_source == b.vertex_source && a.fragment_source == b.fragment_source;
}

// The material parameters the level's model reads (draw_levels.hpp, ShadingLevel).
ShadingLevel level_for(const Material& mat, ShadingModel model, int program) {
  ShadingLevel l;
  l.shading = model;
  l.program = program;
  l.specular_color = mat.specular_color;
  l.shininess = mat.shininess;
  if (mat.shading == ShadingModel::PbrMetallicRoughness && model != ShadingModel::Unlit) {
    const PhongParameters p = pbr_as_phong(mat);
    l.specular_color = p.specular_color, l.shininess = p.shininess, l.base_scale = p.base_scale;
  }
  return l;
}

// A merged group draws every member with one program per level: members keep only the levels
// (from the top) whose programs all of them have.
void align_groups(Scene& s) {
  for (const auto& g : s.groups) {
    std::size_t common = s.draw_levels[static_cast<std::size_t>(g.draws.front())].shadings.size();
    const auto& first = s.draw_levels[static_cast<std::size_t>(g.draws.front())].shadings;
    for (int m : g.draws) {
      const auto& sh = s.draw_levels[static_cast<std::size_t>(m)].shadings;
      std::size_t k = 0;
      while (k < common && k < sh.size() && sh[k].program == first[k].program) ++k;
      common = k;
    }
    for (int m : g.draws) s.draw_levels[static_cast<std::size_t>(m)].shadings.resize(common);
  }
}

}  // namespace

void make_shading_levels(Scene& s, const std::vector<char>& safety, const LevelOptions& o, LevelsReport& report) {
  const std::vector<int> light_nodes = light_order(s);
  const std::vector<char> dyn = dynamic_nodes(s);
  shadergen::ProgramCache own_cache;
  shadergen::ProgramCache& optimized = o.program_cache ? *o.program_cache : own_cache;
  std::map<std::string, int> made;  // features key -> index into s.programs
  const std::size_t programs_before = s.programs.size();
  for (std::size_t i = 0; i < s.draws.size(); ++i) {
    if (safety[i]) continue;
    const DrawItem d = s.draws[i];
    const Primitive& prim = s.meshes[static_cast<std::size_t>(d.mesh)].primitives[static_cast<std::size_t>(d.primitive)];
    const Material& mat = s.materials[static_cast<std::size_t>(prim.material)];
    const bridge::MaterialFeatures stored = s.programs[static_cast<std::size_t>(d.program)].program.features;
    std::vector<int> kept{d.program};
    std::vector<ShadingLevel> levels;
    for (const ShadingModel model : kLower) {
      if (int(model) >= int(stored.shading)) continue;
      const shadergen::MaterialFeatures f = features_at(s, d, stored, model, stored.precision);
      const std::string key = shadergen::program_key(f);
      auto it = made.find(key);
      if (it == made.end()) {
        ProgramEntry e;
        try {
          e.program = shadergen::generate(f);
          // The material's values are uniforms (the level sets its own): only scene constants fold.
          if (o.optimize) e.program = optimized.optimize(e.program, folding_constants(s, mat, false, light_nodes, dyn), &e.optimize_report);
        } catch (const std::exception& ex) {
          throw SceneError(s.source_name + ": levels: node \"" + s.nodes[static_cast<std::size_t>(d.node)].name + "\" at " +
                           shadergen::to_string(model) + " (features " + key + "): " + ex.what());
        }
        it = made.emplace(key, static_cast<int>(s.programs.size())).first;
        s.programs.push_back(std::move(e));
      }
      const bridge::Program& p = s.programs[static_cast<std::size_t>(it->second)].program;
      const bridge::Program& base = s.programs[static_cast<std::size_t>(d.program)].program;
      // A model that draws exactly as one kept already (e.g. a material without lights' terms)
      // is no cheaper level; one that changes blending or culling is not the same draw.
      const bool identical = std::any_of(kept.begin(), kept.end(), [&](int k) {
        return same_code(p, s.programs[static_cast<std::size_t>(k)].program);
      });
      if (identical || p.blend != base.blend || p.cull_back_faces != base.cull_back_faces) {
        ++report.shadings_skipped_identical;
        continue;
      }
      kept.push_back(it->second);
      levels.push_back(level_for(mat, model, it->second));
    }
    s.draw_levels[i].shadings = std::move(levels);
  }
  align_groups(s);
  // Programs no level uses any more (a group's dropped levels) are not stored.
  std::vector<int> used(s.programs.size(), 0);
  for (const auto& dl : s.draw_levels)
    for (const auto& l : dl.shadings) used[static_cast<std::size_t>(l.program)] = 1;
  std::vector<int> renumber(s.programs.size(), -1);
  std::size_t next = programs_before;
  for (std::size_t p = programs_before; p < s.programs.size(); ++p) {
    if (!used[p]) continue;
    renumber[p] = static_cast<int>(next);
    if (next != p) s.programs[next] = std::move(s.programs[p]);
    ++next;
  }
  s.programs.resize(next);
  for (auto& dl : s.draw_levels)
    for (auto& l : dl.shadings) l.program = renumber[static_cast<std::size_t>(l.program)];
  report.programs_added = static_cast<int>(next - programs_before);
  for (const auto& dl : s.draw_levels) {
    report.draws_with_shadings += dl.shadings.empty() ? 0 : 1;
    report.shading_levels += static_cast<int>(dl.shadings.size());
  }
}

}  // namespace meter::convert
