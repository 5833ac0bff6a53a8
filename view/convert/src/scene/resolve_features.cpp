// The scene config's display features checked against the converted scene: page roots, unit
// nodes and swatches, theme materials and the transition clips must exist, so the runtime never
// looks up a name that is not there.
#include "meter/convert/converter.hpp"

namespace meter::convert {

void resolve_features(const Scene& s, const SceneConfig& c, const std::string& origin) {
  auto fail = [&](const std::string& key, const std::string& what) {
    throw SceneError(origin + ": scene config " + key + ": " + what);
  };
  auto nodes = [&](const std::string& key, const std::vector<std::string>& names) {
    for (const auto& n : names)
      if (s.find_node(n) < 0) fail(key, "no node named \"" + n + "\" in the scene");
  };
  const auto& f = c.features;
  if (f.pages) {
    nodes("$.pages.nodes", f.pages->nodes);
    for (const auto& t : f.pages->transitions)
      if (!t.animation.empty() && s.find_animation(t.animation) < 0) {
        fail("$.pages.transitions", "no animation named \"" + t.animation + "\" in the scene");
      }
  }
  if (f.theme) {
    for (const auto& p : f.theme->pairs) {
      for (const auto* m : {&p.day, &p.night})
        if (s.find_material(*m) < 0) fail("$.theme.pairs", "no material named \"" + *m + "\" in the scene");
      for (const auto& b : c.bindings)
        if ((b.kind == BindingKind::Emissive || b.kind == BindingKind::Color) && b.material == p.day) {
          fail("$.theme.pairs", "material \"" + p.day + "\" is also driven by a " + to_string(b.kind) +
                                    " binding; a themed material takes its colours from its night pair only");
        }
    }
    nodes("$.theme.swatch_nodes", f.theme->swatch_nodes);
  }
  if (f.units) {
    nodes("$.units.metric_nodes", f.units->metric_nodes);
    nodes("$.units.imperial_nodes", f.units->imperial_nodes);
    nodes("$.units.celsius_nodes", f.units->celsius_nodes);
    nodes("$.units.fahrenheit_nodes", f.units->fahrenheit_nodes);
  }
}

}  // namespace meter::convert
