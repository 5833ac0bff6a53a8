// The scene config checked against the converted scene: every name a binding, the camera, the
// link-loss text or a concatenation group refers to must exist (and node names used by bindings
// must be unique), so the runtime never looks up a name that is not there.
#include "meter/convert/converter.hpp"

namespace meter::convert {

void resolve_config(const Scene& s, const SceneConfig& c, const std::string& origin) {
  auto fail = [&](std::size_t i, const std::string& field, const std::string& what) {
    throw SceneError(origin + ": scene config $.bindings[" + std::to_string(i) + "]." + field + ": " + what);
  };
  auto unique_node = [&](std::size_t i, const std::string& name, const std::string& field) {
    int found = -1, count = 0;
    for (std::size_t n = 0; n < s.nodes.size(); ++n) {
      if (s.nodes[n].name == name) found = static_cast<int>(n), ++count;
    }
    if (count == 0) fail(i, field, "no node named \"" + name + "\" in the scene");
    if (count > 1) fail(i, field, "node name \"" + name + "\" is not unique in the scene");
    return found;
  };
  for (std::size_t i = 0; i < c.bindings.size(); ++i) {
    const Binding& b = c.bindings[i];
    switch (b.kind) {
      case BindingKind::Animation: {
        int a = s.find_animation(b.animation);
        if (a < 0) {
          std::string list;
          for (const auto& an : s.animations) list += (list.empty() ? "" : ", ") + an.name;
          fail(i, "animation", "no animation named \"" + b.animation + "\" (the scene has: " + (list.empty() ? "none" : list) + ")");
        }
        break;
      }
      case BindingKind::Visibility:
      case BindingKind::Text: unique_node(i, b.node, "node"); break;
      case BindingKind::Morph: {
        int n = unique_node(i, b.node, "node");
        const Node& nd = s.nodes[static_cast<std::size_t>(n)];
        if (nd.mesh < 0 || s.meshes[static_cast<std::size_t>(nd.mesh)].primitives.empty() ||
            b.morph_target >= s.meshes[static_cast<std::size_t>(nd.mesh)].primitives[0].morph_targets) {
          fail(i, "target", "node \"" + b.node + "\" has no morph target " + std::to_string(b.morph_target));
        }
        break;
      }
      case BindingKind::Emissive:
      case BindingKind::Color:
        if (s.find_material(b.material) < 0) fail(i, "material", "no material named \"" + b.material + "\" in the scene");
        break;
    }
  }
  if (!c.camera.empty()) {
    bool ok = false;
    for (const auto& n : s.nodes) ok = ok || (n.camera >= 0 && (n.name == c.camera || s.cameras[static_cast<std::size_t>(n.camera)].name == c.camera));
    if (!ok) throw SceneError(origin + ": scene config $.camera: no camera node or camera named \"" + c.camera + "\"");
  }
  if (!c.link_loss.text_node.empty() && s.find_node(c.link_loss.text_node) < 0) {
    throw SceneError(origin + ": scene config $.link_loss.text_node: no node named \"" + c.link_loss.text_node + "\"");
  }
  for (std::size_t g = 0; g < c.groups.size(); ++g) {
    for (const auto& m : c.groups[g].members) {
      if (s.find_node(m) < 0) {
        throw SceneError(origin + ": scene config $.groups[" + std::to_string(g) + "].members: no node named \"" + m + "\"");
      }
    }
  }
  resolve_features(s, c, origin);
  resolve_scripts(s, c);
}

}  // namespace meter::convert
