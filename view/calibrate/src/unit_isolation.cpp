#include "meter/calibrate/unit_isolation.hpp"

#include <map>
#include <stdexcept>

#include "meter/protocol/catalog.hpp"
#include "meter/protocol/signal_table.hpp"

namespace meter::calibrate {

std::vector<std::vector<int>> unit_nodes(const engine::Scene& scene, std::span<const engine::governor::UnitLadder> ladders) {
  std::map<int, int> group_of;  // draw -> merged group
  for (std::size_t g = 0; g < scene.groups.size(); ++g)
    for (int d : scene.groups[g].draws) group_of[d] = static_cast<int>(g);
  std::vector<std::vector<int>> units;
  std::vector<std::string> names;
  for (std::size_t d = 0; d < scene.draws.size(); ++d) {
    const auto it = group_of.find(static_cast<int>(d));
    if (it == group_of.end()) {
      units.push_back({scene.draws[d].node});
      names.push_back(scene.nodes.at(static_cast<std::size_t>(scene.draws[d].node)).name);
      continue;
    }
    const auto& group = scene.groups[static_cast<std::size_t>(it->second)];
    if (group.draws.front() != static_cast<int>(d)) continue;  // a member: drawn with its representative
    std::vector<int> nodes;
    for (int m : group.draws) nodes.push_back(scene.draws.at(static_cast<std::size_t>(m)).node);
    units.push_back(std::move(nodes));
    names.push_back(group.name);
  }
  if (units.size() != ladders.size())
    throw std::invalid_argument("the renderer has " + std::to_string(ladders.size()) + " draw units, the scene's draws and merged groups make " +
                                std::to_string(units.size()));
  for (std::size_t u = 0; u < units.size(); ++u) {
    if (ladders[u].name != names[u])
      throw std::invalid_argument("draw unit " + std::to_string(u) + " is \"" + ladders[u].name + "\" in the renderer, \"" + names[u] +
                                  "\" in the scene's draw order");
  }
  return units;
}

engine::BindingOutputs shown_alone(const engine::Scene& scene, const engine::BindingOutputs& base, const std::vector<int>& shown) {
  engine::BindingOutputs out = base;
  out.texts.clear();
  out.node_visible.assign(scene.nodes.size(), -1);
  std::vector<char> keep(scene.nodes.size(), 0);  // a shown node or an ancestor of one
  for (int n : shown) {
    for (int k = n; k >= 0; k = scene.nodes.at(static_cast<std::size_t>(k)).parent) keep[static_cast<std::size_t>(k)] = 1;
  }
  for (std::size_t n = 0; n < scene.nodes.size(); ++n) {
    if (keep[n]) out.node_visible[n] = 1;
    else if (scene.nodes[n].mesh >= 0) out.node_visible[n] = 0;
  }
  return out;
}

engine::BindingOutputs calibration_state(const engine::Scene& scene) {
  protocol::SignalTable values;
  for (const auto& b : scene.config.bindings) {
    const auto* info = protocol::find_signal(b.signal);
    if (info == nullptr || info->kind == protocol::SignalKind::Text) continue;
    double v = 0.5 * (b.input[0] + b.input[1]);
    if (b.kind == engine::BindingKind::Visibility || b.kind == engine::BindingKind::Emissive ||
        b.kind == engine::BindingKind::Color) {
      if (b.has_input) v = b.invert ? b.input[0] : b.input[1];
      else v = b.invert ? b.threshold - 1.0 : b.threshold + 1.0;
    }
    values.set(info->id, {v, protocol::SignalStatus::Valid, ""});
  }
  engine::BindingEvaluator evaluator(scene);
  evaluator.update(values, true, -1.0);
  return evaluator.outputs();
}

}  // namespace meter::calibrate
