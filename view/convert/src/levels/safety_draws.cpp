// Which draws are safety items and never get cheaper levels: what the integrity table measures
// (its regions' nodes and materials) and what the config's safety bindings drive, so a scene
// converted with --integrity=off keeps its telltales and needles at full quality too; and every
// draw that can be on screen where a telltale or a readout is (the window a lamp sits in, the
// panel under a text): those pixels are part of what their checks compare.
#include <algorithm>

#include "meter/convert/concat_plan.hpp"
#include "meter/convert/levels.hpp"

namespace meter::convert {

namespace {

struct ScreenBox {
  glm::vec2 min, max;  // pixels, origin bottom-left (as DrawExtent)
  bool overlaps(const ScreenBox& o) const {
    return min.x < o.max.x && o.min.x < max.x && min.y < o.max.y && o.min.y < max.y;
  }
};

// The boxes a lamp or a text check reads: the lamps' own draws (the safety draws a visibility,
// emissive or colour binding drives; a needle's sweep is left out, its check reads only the
// needle's colour) and the integrity table's telltale and readout rects.
std::vector<ScreenBox> checked_boxes(const Scene& s, const std::vector<DrawExtent>& extents,
                                     const std::vector<char>& lamp_draws) {
  std::vector<ScreenBox> boxes;
  for (std::size_t i = 0; i < extents.size(); ++i)
    if (lamp_draws[i] && extents[i].screen_min.x <= extents[i].screen_max.x)
      boxes.push_back({extents[i].screen_min, extents[i].screen_max});
  const float h = float(s.integrity.height);
  for (const auto& r : s.integrity.regions) {
    if (r.kind == SafetyKind::Needle) continue;
    // Integrity rects are top-left origin, y down.
    boxes.push_back({{float(r.rect.x), h - float(r.rect.y + r.rect.height)},
                     {float(r.rect.x + r.rect.width), h - float(r.rect.y)}});
  }
  return boxes;
}

}  // namespace

std::vector<char> safety_draws(const Scene& s) {
  std::vector<char> node(s.nodes.size(), 0), material(s.materials.size(), 0), needle(s.nodes.size(), 0);
  auto mark = [](std::vector<char>& v, int i) {
    if (i >= 0 && static_cast<std::size_t>(i) < v.size()) v[static_cast<std::size_t>(i)] = 1;
  };
  for (const auto& r : s.integrity.regions) {
    mark(node, s.find_node(r.node));
    for (const auto& m : r.materials) mark(material, s.find_material(m));
  }
  for (const auto& b : s.config.bindings) {
    if (!b.safety) continue;  // a driver aid (e.g. a shift light)
    switch (b.kind) {
      case BindingKind::Visibility:
      case BindingKind::Text:
      case BindingKind::Morph: mark(node, s.find_node(b.node)); break;
      case BindingKind::Emissive:
      case BindingKind::Color: mark(material, s.find_material(b.material)); break;
      case BindingKind::Animation: {
        // A needle: the nodes its animation rotates.
        const int a = s.find_animation(b.animation);
        if (a < 0) break;
        for (const auto& ch : s.animations[static_cast<std::size_t>(a)].channels)
          if (ch.path == TargetPath::Rotation) mark(node, ch.node), mark(needle, ch.node);
        break;
      }
    }
  }
  // What a safety node shows includes its subtree (a telltale's lamp under its visibility node).
  for (int n : node_preorder(s))
    for (int c : s.nodes[static_cast<std::size_t>(n)].children) {
      if (node[static_cast<std::size_t>(n)]) node[static_cast<std::size_t>(c)] = 1;
      if (needle[static_cast<std::size_t>(n)]) needle[static_cast<std::size_t>(c)] = 1;
    }
  std::vector<char> out(s.draws.size(), 0), lamp(s.draws.size(), 0);
  for (std::size_t i = 0; i < s.draws.size(); ++i) {
    const DrawItem& d = s.draws[i];
    const Primitive& p = s.meshes[static_cast<std::size_t>(d.mesh)].primitives[static_cast<std::size_t>(d.primitive)];
    out[i] = node[static_cast<std::size_t>(d.node)] || material[static_cast<std::size_t>(p.material)];
    lamp[i] = out[i] && !needle[static_cast<std::size_t>(d.node)];
  }
  // Extents come in the converter's draw order (node pre-order, primitives in order), which is
  // Scene::draws' order; a scene whose draws were built otherwise gets no overlap marking.
  const std::vector<DrawExtent> extents = draw_extents(s);
  if (extents.size() != s.draws.size()) return out;
  const std::vector<ScreenBox> checked = checked_boxes(s, extents, lamp);
  for (std::size_t i = 0; i < s.draws.size(); ++i) {
    if (out[i] || extents[i].screen_min.x > extents[i].screen_max.x) continue;
    const ScreenBox box{extents[i].screen_min, extents[i].screen_max};
    out[i] = std::any_of(checked.begin(), checked.end(), [&](const ScreenBox& c) { return box.overlaps(c); });
  }
  return out;
}

}  // namespace meter::convert
