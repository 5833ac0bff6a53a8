#include "meter/engine/frame_plan/frame_plan.hpp"

#include <algorithm>

namespace meter::engine {

namespace {
const Primitive& primitive_of(const Scene& scene, std::size_t draw) {
  const DrawItem& d = scene.draws[draw];
  return scene.meshes[static_cast<std::size_t>(d.mesh)].primitives[static_cast<std::size_t>(d.primitive)];
}
bool blended(const Scene& scene, std::size_t draw) {
  return scene.programs[static_cast<std::size_t>(scene.draws[draw].program)].program.blend;
}
}  // namespace

std::optional<std::vector<PixelRegion>> damage(const Scene& scene, const FrameState& now, const DrawnFrame& drawn,
                                               int width, int height) {
  if (!drawn.valid || now.view_projection != drawn.view_projection) return std::nullopt;
  // A light that moved or changed lights every pixel.
  if (now.lights != drawn.lights) return std::nullopt;
  std::vector<PixelRegion> regions;
  // Screen box of a draw's bounds under `world`; false when a corner is at or behind the eye
  // (no finite box: redraw everything).
  auto box = [&](std::size_t draw, const glm::mat4& world) -> bool {
    const auto b = screen_box(primitive_of(scene, draw), world, now.view_projection, width, height);
    if (b) regions.push_back(*b);
    return b.has_value();
  };
  for (std::size_t i = 0; i < now.draws.size(); ++i) {
    const DrawState& is = now.draws[i];
    const DrawState& was = drawn.draws[i];
    if (is == was) continue;
    // Skinned or morphed geometry leaves the primitive's bounds.
    if (!is.deform.empty() && is.deform != was.deform) return std::nullopt;
    if (was.visible && !box(i, was.world)) return std::nullopt;
    if (is.visible && !box(i, is.world)) return std::nullopt;
  }
  for (const auto& t : drawn.texts)
    if (std::find(now.texts.begin(), now.texts.end(), t) == now.texts.end()) regions.push_back(t.box);
  for (const auto& t : now.texts)
    if (std::find(drawn.texts.begin(), drawn.texts.end(), t) == drawn.texts.end()) regions.push_back(t.box);

  normalise(regions, width, height);
  long long total = 0;
  for (const auto& r : regions) total += area(r);
  // Past half the target, scissored passes save little and cost extra passes: draw it all.
  if (2 * total > static_cast<long long>(width) * height) return std::nullopt;
  return regions;
}

bool layer_current(const DrawClasses& classes, const FrameState& now, const DrawnFrame& layer) {
  if (!layer.valid || now.view_projection != layer.view_projection || now.lights != layer.lights) return false;
  for (std::size_t i = 0; i < now.draws.size(); ++i)
    if (!classes.changeable[i] && !(now.draws[i] == layer.draws[i])) return false;
  return true;
}

std::vector<int> draw_list(const Scene& scene, const DrawClasses& classes, const FrameState& now, DrawSet set,
                           const PixelRegion* scissor, int width, int height) {
  const glm::mat4& vp = now.view_projection;
  auto visible = [&](std::size_t draw) { return now.visible[static_cast<std::size_t>(scene.draws[draw].node)] != 0; };
  // True when the draw's screen box misses the scissor; skinned and morphed draws have no known
  // bounds and never miss.
  auto misses = [&](std::size_t draw) {
    const Primitive& prim = primitive_of(scene, draw);
    const auto node = static_cast<std::size_t>(scene.draws[draw].node);
    if (scene.nodes[node].skin >= 0 || prim.morph_targets > 0) return false;
    const auto b = screen_box(prim, now.world[node], vp, width, height);
    return b && !overlap(*b, *scissor);
  };
  struct Sorted {
    int draw;
    float depth;
  };
  std::vector<Sorted> opaque, blend;
  for (std::size_t i = 0; i < scene.draws.size(); ++i) {
    const std::vector<int>* members = nullptr;
    if (classes.group[i] >= 0) {
      if (!classes.representative(i, scene)) continue;
      // Drawn when a member with triangles is visible (the representative itself may be hidden).
      members = &scene.groups[static_cast<std::size_t>(classes.group[i])].draws;
      const bool any = std::any_of(members->begin(), members->end(), [&](int m) {
        return visible(static_cast<std::size_t>(m)) && primitive_of(scene, static_cast<std::size_t>(m)).indices.size() >= 3;
      });
      if (!any) continue;
    } else if (!visible(i)) {
      continue;
    }
    const bool in_layer = !blended(scene, i) && !classes.changeable[i];
    if ((set == DrawSet::StaticOpaque && !in_layer) || (set == DrawSet::OverStatic && in_layer)) continue;
    // On llvmpipe leaving such a draw out saves its vertex work and triangle setup, which the
    // scissor alone does not. A merged group misses when every visible member does.
    if (scissor) {
      const bool outside = members ? std::all_of(members->begin(), members->end(), [&](int m) {
        return !visible(static_cast<std::size_t>(m)) || misses(static_cast<std::size_t>(m));
      }) : misses(i);
      if (outside) continue;
    }
    const Primitive& prim = primitive_of(scene, i);
    const glm::vec3 c = (prim.bounds_min + prim.bounds_max) * 0.5f;
    const glm::vec4 clip = vp * now.world[static_cast<std::size_t>(scene.draws[i].node)] * glm::vec4(c, 1.0f);
    (blended(scene, i) ? blend : opaque).push_back({static_cast<int>(i), clip.w});
  }
  std::stable_sort(opaque.begin(), opaque.end(), [](const Sorted& a, const Sorted& b) { return a.depth < b.depth; });
  // Static before changeable (the layer's order); each part stays front-to-back.
  std::stable_partition(opaque.begin(), opaque.end(),
                        [&](const Sorted& s) { return !classes.changeable[static_cast<std::size_t>(s.draw)]; });
  std::stable_sort(blend.begin(), blend.end(), [](const Sorted& a, const Sorted& b) { return a.depth > b.depth; });
  std::vector<int> out;
  out.reserve(opaque.size() + blend.size());
  for (const auto& s : opaque) out.push_back(s.draw);
  for (const auto& s : blend) out.push_back(s.draw);
  return out;
}

FramePlan plan_frame(const Scene& scene, const DrawClasses& classes, const FrameState& now, const DrawnFrame& drawn,
                     const DrawnFrame& layer, const PlanSettings& s) {
  FramePlan plan;
  // The static layer: used by unforced frames (a forced frame is drawn from scratch), where the
  // backend can copy multisample pixels and the scene makes it worth keeping (classify_draws).
  const bool layered = !s.force && s.partial_redraw && s.static_layer && classes.layer_pays;
  const bool layer_ok = layered && layer_current(classes, now, layer);
  // Without partial redraw every changed frame is drawn whole, and no damage is worked out.
  auto regions = s.force || !s.partial_redraw ? std::nullopt : damage(scene, now, drawn, s.width, s.height);
  // A moving caster's shadow can change pixels far outside its own boxes (classify_draws).
  if (regions && !regions->empty() && classes.shadows_move) regions = std::nullopt;
  // A stale layer is redrawn whole from `now`, so copying it under the damaged regions is right
  // even then: a static draw that changed (its quality level) damages its own boxes only, and the
  // rest of the target still holds what `now` shows there.
  auto layer_build = [&] {
    return Pass{DrawSet::StaticOpaque, std::nullopt, draw_list(scene, classes, now, DrawSet::StaticOpaque, nullptr, s.width, s.height)};
  };
  // Inputs changed but no pixel can have (e.g. a hidden node's text): the frame stands.
  if (regions && regions->empty()) return plan;
  plan.draw = true;
  const DrawSet over = layered ? DrawSet::OverStatic : DrawSet::Everything;
  if (!regions) {
    plan.full = true;
    if (layered && !layer_ok) plan.layer_build = layer_build();
    plan.copy_layer = layered;
    plan.passes.push_back({over, std::nullopt, draw_list(scene, classes, now, over, nullptr, s.width, s.height)});
    return plan;
  }
  plan.regions = std::move(*regions);
  if (layered && !layer_ok) plan.layer_build = layer_build();
  plan.copy_layer = layered;
  for (const auto& r : plan.regions) plan.passes.push_back({over, r, draw_list(scene, classes, now, over, &r, s.width, s.height)});
  return plan;
}

DrawnFrame drawn_frame(const FrameState& now) {
  return DrawnFrame{true, now.view_projection, now.draws, now.texts, now.lights};
}

DrawnFrame drawn_frame(FrameState&& now) {
  return DrawnFrame{true, now.view_projection, std::move(now.draws), std::move(now.texts), std::move(now.lights)};
}

}  // namespace meter::engine
