// The states of the committed Blender references: see reference_state.hpp.
#include "reference_state.hpp"

#include "meter/protocol/catalog.hpp"
#include "meter/protocol/signal_table.hpp"

namespace meter::testing {

namespace {
constexpr double kPreviewFrame = 100.0, kPreviewFps = 24.0;  // scenes/cluster/build.py's preview
}

engine::BindingOutputs feature_reference_state(const engine::Scene& scene) {
  engine::BindingEvaluator ev(scene);
  ev.update(protocol::SignalTable{}, true, -1.0);
  return ev.outputs();
}

engine::BindingOutputs cluster_reference_state(const engine::Scene& scene) {
  protocol::SignalTable values;
  for (const auto& b : scene.config.bindings) {
    const auto* info = protocol::find_signal(b.signal);
    if (!info || info->kind == protocol::SignalKind::Text) continue;
    const bool lamp = b.kind == engine::BindingKind::Visibility || b.kind == engine::BindingKind::Emissive ||
                      b.kind == engine::BindingKind::Color;
    const double lit = b.has_input ? (b.invert ? b.input[0] : b.input[1]) : (b.invert ? b.threshold - 1.0 : b.threshold + 1.0);
    values.set(info->id, {lamp ? lit : b.input[0], protocol::SignalStatus::Valid, ""});
  }
  engine::BindingEvaluator ev(scene);
  ev.update(values, true, -1.0);
  engine::BindingOutputs out = ev.outputs();
  out.animation_time.assign(scene.animations.size(), kPreviewFrame / kPreviewFps);
  out.texts.clear();
  return out;
}

}  // namespace meter::testing
