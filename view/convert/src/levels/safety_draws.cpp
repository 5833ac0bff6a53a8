// Which draws are safety items and never get cheaper levels: what the integrity table measures
// (its regions' nodes and materials) and what the config's safety bindings drive, so a scene
// converted with --integrity=off keeps its telltales and needles at full quality too.
#include "meter/convert/levels.hpp"

namespace meter::convert {

std::vector<char> safety_draws(const Scene& s) {
  std::vector<char> node(s.nodes.size(), 0), material(s.materials.size(), 0);
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
          if (ch.path == TargetPath::Rotation) mark(node, ch.node);
        break;
      }
    }
  }
  // What a safety node shows includes its subtree (a telltale's lamp under its visibility node).
  for (int n : node_preorder(s))
    if (node[static_cast<std::size_t>(n)])
      for (int c : s.nodes[static_cast<std::size_t>(n)].children) node[static_cast<std::size_t>(c)] = 1;
  std::vector<char> out(s.draws.size(), 0);
  for (std::size_t i = 0; i < s.draws.size(); ++i) {
    const DrawItem& d = s.draws[i];
    const Primitive& p = s.meshes[static_cast<std::size_t>(d.mesh)].primitives[static_cast<std::size_t>(d.primitive)];
    out[i] = node[static_cast<std::size_t>(d.node)] || material[static_cast<std::size_t>(p.material)];
  }
  return out;
}

}  // namespace meter::convert
