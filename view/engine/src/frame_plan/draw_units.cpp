#include "meter/engine/frame_plan/draw_units.hpp"

#include <algorithm>
#include <cmath>
#include <span>
#include <stdexcept>

namespace meter::engine {

namespace {
const Primitive& primitive_of(const Scene& scene, int draw) {
  const DrawItem& d = scene.draws[static_cast<std::size_t>(draw)];
  return scene.meshes[static_cast<std::size_t>(d.mesh)].primitives[static_cast<std::size_t>(d.primitive)];
}
const DrawLevels* levels_of(const Scene& scene, int draw) {
  return scene.draw_levels.empty() ? nullptr : &scene.draw_levels[static_cast<std::size_t>(draw)];
}
// The index list a draw uses at its LOD `lod` (0 = the primitive's own).
std::size_t triangles_at(const Primitive& p, int lod) {
  return (lod == 0 ? p.indices.size() : p.lods[static_cast<std::size_t>(lod - 1)].indices.size()) / 3;
}
// The share of the triangles of its LOD before that a unit's LOD must drop (the converter's
// default for one primitive's levels, meter/convert/levels.hpp).
constexpr double kMinUnitLodSaving = 0.25;
}  // namespace

DrawUnits make_draw_units(const Scene& scene, const DrawClasses& classes, bool shading_levels) {
  DrawUnits u;
  u.unit_of.assign(scene.draws.size(), -1);
  for (std::size_t i = 0; i < scene.draws.size(); ++i) {
    const int g = classes.group[i];
    if (g >= 0 && !classes.representative(i, scene)) continue;
    std::vector<int> members;
    if (g >= 0) members = scene.groups[static_cast<std::size_t>(g)].draws;
    else members = {static_cast<int>(i)};
    governor::UnitLadder l;
    l.name = g >= 0 ? scene.groups[static_cast<std::size_t>(g)].name : scene.nodes[static_cast<std::size_t>(scene.draws[i].node)].name;
    l.shadings = {scene.programs[static_cast<std::size_t>(scene.draws[i].program)].program.features.shading};
    l.lod_errors = {0.0f};
    l.lod_triangle_fractions = {1.0f};
    int lods = 0;
    for (int m : members) {
      const DrawLevels* dl = levels_of(scene, m);
      if (dl && dl->safety) l.safety = true;
      if (dl) lods = std::max(lods, dl->lods);
    }
    const DrawLevels* rep = levels_of(scene, members.front());
    std::vector<int> steps{0};
    if (!l.safety && rep) {
      if (shading_levels)
        for (const auto& s : rep->shadings) l.shadings.push_back(s.shading);
      std::size_t full = 0;
      for (int m : members) full += triangles_at(primitive_of(scene, m), 0);
      for (int k = 1; k <= lods; ++k) {
        float error = 0.0f;
        std::size_t kept = 0;
        for (int m : members) {
          const Primitive& p = primitive_of(scene, m);
          const int own = std::min(k, levels_of(scene, m)->lods);
          if (own > 0) error = std::max(error, p.lods[static_cast<std::size_t>(own - 1)].error);
          kept += triangles_at(p, own);
        }
        const float fraction = full ? float(double(kept) / double(full)) : 1.0f;
        // A group where few members simplify saves little: as for one primitive, a unit's LOD
        // is offered only when it drops a quarter of the triangles of the one before.
        if (double(fraction) > (1.0 - kMinUnitLodSaving) * double(l.lod_triangle_fractions.back())) continue;
        l.lod_errors.push_back(error);
        l.lod_triangle_fractions.push_back(fraction);
        steps.push_back(k);
      }
    }
    const int unit = static_cast<int>(u.ladders.size());
    for (int m : members) u.unit_of[static_cast<std::size_t>(m)] = unit;
    u.ladders.push_back(std::move(l));
    u.members.push_back(std::move(members));
    u.lod_steps.push_back(std::move(steps));
  }
  return u;
}

std::string check_draw_levels(const Scene& scene) {
  if (scene.draw_levels.empty()) return "";
  if (scene.draw_levels.size() != scene.draws.size())
    return "draw_levels: " + std::to_string(scene.draw_levels.size()) + " entries for " + std::to_string(scene.draws.size()) +
           " draws (expected one per draw)";
  for (std::size_t i = 0; i < scene.draws.size(); ++i) {
    const DrawLevels& dl = scene.draw_levels[i];
    const std::string at = "draw_levels[" + std::to_string(i) + "]";
    const Primitive& p = primitive_of(scene, static_cast<int>(i));
    if (dl.lods < 0 || static_cast<std::size_t>(dl.lods) > p.lods.size())
      return at + ".lods: " + std::to_string(dl.lods) + ", expected 0.." + std::to_string(p.lods.size()) +
             " (the LOD levels of its primitive)";
    if (dl.safety && (dl.lods != 0 || !dl.shadings.empty())) return at + ": a safety item with levels (expected none)";
    const bridge::Program& own = scene.programs[static_cast<std::size_t>(scene.draws[i].program)].program;
    for (std::size_t k = 0; k < dl.shadings.size(); ++k) {
      const ShadingLevel& s = dl.shadings[k];
      const std::string lk = at + ".shadings[" + std::to_string(k) + "]";
      if (s.program < 0 || static_cast<std::size_t>(s.program) >= scene.programs.size())
        return lk + ".program: " + std::to_string(s.program) + " out of range (" + std::to_string(scene.programs.size()) + " programs)";
      const bridge::Program& v = scene.programs[static_cast<std::size_t>(s.program)].program;
      if (v.features.shading != s.shading)
        return lk + ".program: its shading model " + std::string(bridge::to_string(v.features.shading)) + " is not the level's " +
               bridge::to_string(s.shading);
      if (int(s.shading) >= int(own.features.shading))
        return lk + ".shading: " + std::string(bridge::to_string(s.shading)) + " is not cheaper than the draw's own " +
               bridge::to_string(own.features.shading);
      if (v.blend != own.blend || v.cull_back_faces != own.cull_back_faces)
        return lk + ".program: blend / cull state differs from the draw's own program";
      if (v.features.vertex_alpha != own.features.vertex_alpha)
        return lk + ".program: vertex_alpha differs from the draw's own program (merged groups need it)";
      if (!(s.base_scale >= 0.0f && s.base_scale <= 1.0f) || !(s.shininess >= 0.0f) || !std::isfinite(s.shininess))
        return lk + ": base_scale must be in [0, 1] and shininess finite and >= 0";
    }
  }
  for (std::size_t g = 0; g < scene.groups.size(); ++g) {
    const auto& members = scene.groups[g].draws;
    const DrawLevels& first = scene.draw_levels[static_cast<std::size_t>(members.front())];
    for (int m : members) {
      const DrawLevels& dl = scene.draw_levels[static_cast<std::size_t>(m)];
      bool same = dl.shadings.size() == first.shadings.size();
      for (std::size_t k = 0; same && k < dl.shadings.size(); ++k) same = dl.shadings[k].program == first.shadings[k].program;
      if (!same)
        return "groups[" + std::to_string(g) + "] (\"" + scene.groups[g].name + "\"): draw_levels[" + std::to_string(m) +
               "].shadings differ from the first member's (a merged draw has one program per level)";
    }
  }
  return "";
}

governor::QualityChoice checked_choice(const DrawUnits& units, const governor::QualityChoice& c, int current_msaa) {
  const auto& g = c.global;
  if (g.msaa != 1 && g.msaa != 2 && g.msaa != 4 && g.msaa != current_msaa)
    throw std::invalid_argument("quality: global.msaa = " + std::to_string(g.msaa) + ", expected 1, 2 or 4");
  if (!(g.scale > 0.0f && g.scale <= 1.0f))
    throw std::invalid_argument("quality: global.scale = " + std::to_string(g.scale) + ", expected a value in (0, 1]");
  if (!c.units.empty() && c.units.size() != units.ladders.size())
    throw std::invalid_argument("quality: " + std::to_string(c.units.size()) + " unit levels for " +
                                std::to_string(units.ladders.size()) + " draw units (expected one per unit, or none)");
  governor::QualityChoice out = c;
  out.units.resize(units.ladders.size());
  for (std::size_t i = 0; i < c.units.size(); ++i) {
    const auto& l = units.ladders[i];
    const auto& u = c.units[i];
    const std::string who = "quality: unit " + std::to_string(i) + " (\"" + l.name + "\")";
    if (u.shading < 0 || static_cast<std::size_t>(u.shading) >= l.shadings.size())
      throw std::invalid_argument(who + ": shading level " + std::to_string(u.shading) + ", expected 0.." +
                                  std::to_string(l.shadings.size() - 1) + (l.safety ? " (a safety unit stays at 0)" : ""));
    if (u.lod < 0 || static_cast<std::size_t>(u.lod) >= l.lod_errors.size())
      throw std::invalid_argument(who + ": lod level " + std::to_string(u.lod) + ", expected 0.." +
                                  std::to_string(l.lod_errors.size() - 1) + (l.safety ? " (a safety unit stays at 0)" : ""));
  }
  return out;
}

void apply_levels(const Scene& scene, const DrawUnits& units, const governor::QualityChoice& choice, FrameState& frame) {
  for (std::size_t u = 0; u < units.members.size(); ++u) {
    const governor::UnitLevel level = u < choice.units.size() ? choice.units[u] : governor::UnitLevel{};
    for (int m : units.members[u]) {
      DrawState& s = frame.draws[static_cast<std::size_t>(m)];
      const DrawLevels* dl = levels_of(scene, m);
      s.shading = level.shading;
      const auto& steps = units.lod_steps[u];
      const int step = level.lod >= 0 && static_cast<std::size_t>(level.lod) < steps.size() ? steps[static_cast<std::size_t>(level.lod)] : 0;
      s.lod = dl ? std::min(step, dl->lods) : 0;
    }
  }
}

governor::FrameLoad frame_load(const Scene& scene, const DrawClasses& classes, const DrawUnits& units,
                               const FrameState& now, const FramePlan& plan, int width, int height, float scale) {
  governor::FrameLoad load;
  load.drawn = plan.draw;
  load.full_frame = plan.full;
  load.unit_pixels.assign(units.ladders.size(), 0.0);
  const double to_output = 1.0 / (double(scale) * double(scale));
  const PixelRegion all{0, 0, width, height};
  if (!plan.draw) return load;
  long long redrawn = 0;
  if (plan.full) redrawn = area(all);
  for (const auto& r : plan.regions) redrawn += area(r);
  load.redrawn_pixels = double(redrawn) * to_output;
  auto count = [&](const Pass& pass) {
    const PixelRegion clip_to = pass.scissor ? *pass.scissor : all;
    for (int d : pass.draws) {
      const auto ud = static_cast<std::size_t>(d);
      const std::span<const int> members = classes.group[ud] >= 0
                                               ? std::span<const int>(scene.groups[static_cast<std::size_t>(classes.group[ud])].draws)
                                               : std::span<const int>(&d, 1);
      long long pixels = 0;
      for (int m : members) {
        const auto node = static_cast<std::size_t>(scene.draws[static_cast<std::size_t>(m)].node);
        if (!now.visible[node]) continue;
        const auto box = screen_box(primitive_of(scene, m), now.world[node], now.view_projection, width, height);
        // No finite box (a corner behind the eye): it may cover all of the pass.
        const PixelRegion b = box ? *box : clip_to;
        const int x0 = std::max(b.x, clip_to.x), y0 = std::max(b.y, clip_to.y);
        const int x1 = std::min(b.x + b.width, clip_to.x + clip_to.width), y1 = std::min(b.y + b.height, clip_to.y + clip_to.height);
        if (x1 > x0 && y1 > y0) pixels += static_cast<long long>(x1 - x0) * (y1 - y0);
      }
      load.unit_pixels[static_cast<std::size_t>(units.unit_of[ud])] += double(pixels) * to_output;
    }
  };
  if (plan.layer_build) count(*plan.layer_build);
  for (const Pass& p : plan.passes) count(p);
  return load;
}

}  // namespace meter::engine
