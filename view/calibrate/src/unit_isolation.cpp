#include "meter/calibrate/unit_isolation.hpp"

#include <algorithm>

#include "meter/protocol/catalog.hpp"
#include "meter/protocol/signal_table.hpp"

namespace meter::calibrate {

std::vector<int> unit_nodes(const engine::Scene& scene, std::span<const int> draws) {
  std::vector<int> nodes;
  for (int d : draws) {
    const int n = scene.draws.at(static_cast<std::size_t>(d)).node;
    if (std::find(nodes.begin(), nodes.end(), n) == nodes.end()) nodes.push_back(n);
  }
  return nodes;
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
