#include "meter/engine/frame_plan/draw_classes.hpp"

namespace meter::engine {

DrawClasses classify_draws(const Scene& scene, bool merged, int camera_node) {
  DrawClasses c;
  c.group.assign(scene.draws.size(), -1);
  if (merged)
    for (std::size_t g = 0; g < scene.groups.size(); ++g)
      for (int d : scene.groups[g].draws) c.group[static_cast<std::size_t>(d)] = static_cast<int>(g);
  // What the scene's animations and bindings can reach. An animation nobody drives stays at
  // config.time, but it is counted as moving anyway: this decides what may be cached, so it errs
  // towards drawing more, never towards a stale layer (the plan also checks the layer each frame).
  std::vector<char> node_moves(scene.nodes.size(), 0), material_changes(scene.materials.size(), 0);
  auto mark = [](std::vector<char>& v, int i) {
    if (i >= 0 && static_cast<std::size_t>(i) < v.size()) v[static_cast<std::size_t>(i)] = 1;
  };
  for (const auto& a : scene.animations)
    for (const auto& ch : a.channels) mark(node_moves, ch.node);
  for (const auto& b : scene.config.bindings) {
    if (b.kind == BindingKind::Visibility || b.kind == BindingKind::Morph) mark(node_moves, scene.find_node(b.node));
    if (b.kind == BindingKind::Emissive || b.kind == BindingKind::Color) mark(material_changes, scene.find_material(b.material));
  }
  for (const auto& s : scene.config.scripts)
    for (const auto& o : s.outputs) {
      if (o.kind != ScriptOutputKind::Text && targets_node(o.kind)) mark(node_moves, scene.find_node(o.target));
      if (targets_material(o.kind)) mark(material_changes, scene.find_material(o.target));
    }
  // The display features switch pages, unit scales and theme materials.
  const auto& f = scene.config.features;
  auto mark_nodes = [&](const std::vector<std::string>& names) {
    for (const auto& n : names) mark(node_moves, scene.find_node(n));
  };
  if (f.pages) mark_nodes(f.pages->nodes);
  if (f.units) {
    for (const auto* list : {&f.units->metric_nodes, &f.units->imperial_nodes, &f.units->celsius_nodes, &f.units->fahrenheit_nodes})
      mark_nodes(*list);
  }
  if (f.theme)
    for (const auto& p : f.theme->pairs) mark(material_changes, scene.find_material(p.day));
  // Transforms and visibility are inherited: below a moving node everything moves.
  for (int n : node_preorder(scene))
    if (node_moves[static_cast<std::size_t>(n)])
      for (int ch : scene.nodes[static_cast<std::size_t>(n)].children) node_moves[static_cast<std::size_t>(ch)] = 1;
  c.changeable.assign(scene.draws.size(), 0);
  for (std::size_t i = 0; i < scene.draws.size(); ++i) {
    const DrawItem& d = scene.draws[i];
    const Primitive& prim = scene.meshes[static_cast<std::size_t>(d.mesh)].primitives[static_cast<std::size_t>(d.primitive)];
    const auto node = static_cast<std::size_t>(d.node);
    c.changeable[i] = node_moves[node] || material_changes[static_cast<std::size_t>(prim.material)] ||
                      scene.nodes[node].skin >= 0 || prim.morph_targets > 0;
  }
  if (merged)
    for (const auto& g : scene.groups) {
      char& rep = c.changeable[static_cast<std::size_t>(g.draws.front())];
      for (int m : g.draws) rep = rep || c.changeable[static_cast<std::size_t>(m)];
    }
  bool any_static_opaque = false;
  for (std::size_t i = 0; i < scene.draws.size(); ++i) {
    const bool drawn_alone_or_for_group = c.group[i] < 0 || c.representative(i, scene);
    const bool blend = scene.programs[static_cast<std::size_t>(scene.draws[i].program)].program.blend;
    if (drawn_alone_or_for_group && !c.changeable[i] && !blend) any_static_opaque = true;
  }
  bool view_fixed = camera_node >= 0 && !node_moves[static_cast<std::size_t>(camera_node)];
  for (std::size_t n = 0; n < scene.nodes.size(); ++n)
    if (scene.nodes[n].light >= 0 && node_moves[n]) view_fixed = false;
  const bool shadow_light = shadow_map_lights(scene, light_order(scene)) != 0;
  for (std::size_t i = 0; i < scene.draws.size() && shadow_light; ++i) {
    const DrawItem& d = scene.draws[i];
    const Primitive& prim = scene.meshes[static_cast<std::size_t>(d.mesh)].primitives[static_cast<std::size_t>(d.primitive)];
    const auto node = static_cast<std::size_t>(d.node);
    const bool blend = scene.programs[static_cast<std::size_t>(d.program)].program.blend;
    const bool geometry_changes = node_moves[node] || scene.nodes[node].skin >= 0 || prim.morph_targets > 0;
    if (!blend && geometry_changes) c.shadows_move = true;
  }
  c.layer_pays = any_static_opaque && view_fixed && !c.shadows_move;
  return c;
}

}  // namespace meter::engine
