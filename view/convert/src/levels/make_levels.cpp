// The levels stage: safety items, LOD levels per primitive, shading levels per draw, the report.
#include <chrono>
#include <cstdio>
#include <map>
#include <sstream>

#include "levels/level_stages.hpp"
#include "meter/convert/flat_geometry.hpp"

namespace meter::convert {

LevelsReport make_levels(Scene& s, const LevelOptions& o) {
  const auto t0 = std::chrono::steady_clock::now();
  for (std::size_t k = 0; k < o.lod_errors.size(); ++k)
    if (!(o.lod_errors[k] > 0.0f && o.lod_errors[k] < 1.0f) || (k > 0 && o.lod_errors[k] <= o.lod_errors[k - 1]))
      throw SceneError(s.source_name + ": levels: LOD error bounds must increase within (0, 1)");
  if (!(o.min_saving > 0.0f && o.min_saving < 1.0f)) throw SceneError(s.source_name + ": levels: min_saving must be in (0, 1)");
  LevelsReport r;
  const std::vector<char> safety = safety_draws(s);
  s.draw_levels.assign(s.draws.size(), DrawLevels{});
  // LODs per primitive, made once for all its draws; a primitive only safety draws use gets none.
  std::map<std::pair<int, int>, bool> wanted;
  for (std::size_t i = 0; i < s.draws.size(); ++i) {
    auto& w = wanted[{s.draws[i].mesh, s.draws[i].primitive}];
    w = w || !safety[i];
  }
  for (const auto& [key, want] : wanted) {
    Primitive& p = s.meshes[static_cast<std::size_t>(key.first)].primitives[static_cast<std::size_t>(key.second)];
    ++r.primitives;
    p.lods = want ? simplify_levels(p, o.lod_errors, o.min_saving) : std::vector<LodLevel>{};
    r.primitives_with_lods += p.lods.empty() ? 0 : 1;
    r.lod_levels += static_cast<int>(p.lods.size());
  }
  r.draws = static_cast<int>(s.draws.size());
  std::vector<std::size_t> tris_at;
  for (std::size_t i = 0; i < s.draws.size(); ++i) {
    DrawLevels& dl = s.draw_levels[i];
    if (safety[i]) {
      dl.safety = true;
      ++r.safety_draws;
      continue;
    }
    const Primitive& p = s.meshes[static_cast<std::size_t>(s.draws[i].mesh)].primitives[static_cast<std::size_t>(s.draws[i].primitive)];
    dl.lods = static_cast<int>(p.lods.size());
    r.triangles += p.indices.size() / 3;
    for (std::size_t k = 0; k < p.lods.size(); ++k) {
      if (r.draws_at_lod.size() <= k) r.draws_at_lod.push_back(0), tris_at.push_back(0), r.triangle_fraction_at_lod.push_back(0.0);
      ++r.draws_at_lod[k];
      tris_at[k] += p.lods[k].indices.size() / 3;
      r.triangle_fraction_at_lod[k] += double(p.indices.size() / 3);  // the full triangles of those draws, divided below
    }
  }
  for (std::size_t k = 0; k < tris_at.size(); ++k) r.triangle_fraction_at_lod[k] = double(tris_at[k]) / r.triangle_fraction_at_lod[k];
  if (o.shading) make_shading_levels(s, safety, o, r);
  // After the shading levels (which draws are Flat) and the LODs (every list gets its Flat one).
  const FlatGeometryReport flat = prepare_flat_draws(s);
  r.flat_primitives = flat.primitives, r.flat_vertices = flat.vertices, r.flat_vertices_added = flat.added;
  r.milliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return r;
}

std::string levels_report(const Scene& s, const LevelsReport& r) {
  std::ostringstream os;
  char buf[256];
  std::snprintf(buf, sizeof buf, "levels: %d draws (%d safety, no levels); %d of %d primitives with LODs, %d LOD levels; %d shading levels on %d draws (%d programs added, %d identical skipped); %.0f ms\n",
                r.draws, r.safety_draws, r.primitives_with_lods, r.primitives, r.lod_levels, r.shading_levels,
                r.draws_with_shadings, r.programs_added, r.shadings_skipped_identical, r.milliseconds);
  os << buf;
  if (r.flat_primitives > 0) {
    std::snprintf(buf, sizeof buf, "  flat: %d primitives drawn Flat, %llu face-normal vertices added to their %llu\n", r.flat_primitives,
                  static_cast<unsigned long long>(r.flat_vertices_added), static_cast<unsigned long long>(r.flat_vertices));
    os << buf;
  }
  for (std::size_t k = 0; k < r.draws_at_lod.size(); ++k) {
    std::snprintf(buf, sizeof buf, "  lod %zu: %d draws, %.3f of their triangles\n", k + 1, r.draws_at_lod[k], r.triangle_fraction_at_lod[k]);
    os << buf;
  }
  for (std::size_t i = 0; i < s.draws.size() && i < s.draw_levels.size(); ++i) {
    const DrawLevels& dl = s.draw_levels[i];
    const DrawItem& d = s.draws[i];
    os << "  draw " << i << " \"" << s.nodes[static_cast<std::size_t>(d.node)].name << "\":";
    if (dl.safety) {
      os << " safety\n";
      continue;
    }
    os << " shading " << shadergen::to_string(s.programs[static_cast<std::size_t>(d.program)].program.features.shading);
    for (const auto& l : dl.shadings) os << " > " << shadergen::to_string(l.shading) << " (program " << l.program << ")";
    const Primitive& p = s.meshes[static_cast<std::size_t>(d.mesh)].primitives[static_cast<std::size_t>(d.primitive)];
    os << "; lod " << p.indices.size() / 3 << " triangles";
    for (int k = 0; k < dl.lods; ++k) {
      const LodLevel& l = p.lods[static_cast<std::size_t>(k)];
      std::snprintf(buf, sizeof buf, " > %.3f (error %.4f)", double(l.triangle_fraction), double(l.error));
      os << buf;
    }
    os << "\n";
  }
  return os.str();
}

}  // namespace meter::convert
