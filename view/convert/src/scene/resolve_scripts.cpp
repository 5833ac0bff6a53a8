// The scene config's scripts checked against the converted scene: each output's target exists
// (node names unique, the morph target present) and each script loads in the same sandbox the
// view runs it in, so a package never carries a script that cannot start.
#include <algorithm>

#include "meter/convert/converter.hpp"
#include "meter/engine/logic/scripts.hpp"

namespace meter::convert {

void resolve_scripts(const Scene& s, const SceneConfig& c) {
  using bridge::ScriptOutputKind;
  for (std::size_t i = 0; i < c.scripts.size(); ++i) {
    const bridge::Script& sc = c.scripts[i];
    const std::string at = c.origin + ": $.scripts[" + std::to_string(i) + "] (" + sc.name + ")";
    for (const auto& o : sc.outputs) {
      auto fail = [&](const char* key, const std::string& what) {
        throw SceneError(at + ".outputs." + o.name + "." + key + ": " + what + " in " + s.source_name);
      };
      if (o.kind == ScriptOutputKind::Animation) {
        if (s.find_animation(o.target) < 0) fail("animation", "no animation named \"" + o.target + "\"");
      } else if (bridge::targets_material(o.kind)) {
        if (s.find_material(o.target) < 0) fail("material", "no material named \"" + o.target + "\"");
      } else {
        const auto count = std::count_if(s.nodes.begin(), s.nodes.end(), [&](const Node& n) { return n.name == o.target; });
        if (count == 0) fail("node", "no node named \"" + o.target + "\"");
        if (count > 1) fail("node", "node name \"" + o.target + "\" is not unique");
        if (o.kind == ScriptOutputKind::Morph) {
          const Node& n = s.nodes[static_cast<std::size_t>(s.find_node(o.target))];
          const bool has = n.mesh >= 0 && !s.meshes[static_cast<std::size_t>(n.mesh)].primitives.empty() &&
                           o.morph_target < s.meshes[static_cast<std::size_t>(n.mesh)].primitives[0].morph_targets;
          if (!has) fail("target", "node \"" + o.target + "\" has no morph target " + std::to_string(o.morph_target));
        }
      }
    }
  }
  if (c.scripts.empty()) return;
  // Loading runs each chunk once (sandboxed, within its limits) and finds its run(IN, OUT).
  engine::ScriptEngine scripts(s);
  for (std::size_t i = 0; i < scripts.stats().size(); ++i) {
    const auto& st = scripts.stats()[i];
    if (st.failed) {
      const bridge::Script& sc = c.scripts[i];
      const std::string code = sc.file.empty() ? ".code" : ".file (" + sc.file + ")";
      throw SceneError(c.origin + ": $.scripts[" + std::to_string(i) + "]" + code + ": " + st.last_error);
    }
  }
}

}  // namespace meter::convert
