#include "bound_signals.hpp"

namespace meter::testing {

protocol::SignalTable bound_signals_at(const bridge::SceneConfig& config, double fraction) {
  protocol::SignalTable values;
  for (const auto& b : config.bindings) {
    const auto* info = protocol::find_signal(b.signal);
    if (!info) continue;
    protocol::SignalState v{0.0, protocol::SignalStatus::Valid, ""};
    if (info->kind == protocol::SignalKind::Text) {
      v.text = "A12";
    } else if (b.kind == bridge::BindingKind::Visibility) {
      v.value = fraction >= 0.5 ? b.threshold + 1.0 : b.threshold - 1.0;
    } else {
      v.value = b.input[0] + fraction * (b.input[1] - b.input[0]);
    }
    values.set(info->id, std::move(v));
  }
  return values;
}

}  // namespace meter::testing
