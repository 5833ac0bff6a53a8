// A signal state that exercises every binding of a scene config: what the integration tests render
// when they compare two ways of drawing the same scene.
#pragma once

#include "meter/bridge/scene_config.hpp"
#include "meter/protocol/signal_table.hpp"

namespace meter::testing {

// Every catalog signal the config binds, Valid, at `fraction` of its binding's input range
// (needles part-way, morph weights and colour blends between their ends); visibility bindings on
// from fraction 0.5 up, off below; text signals "A12". A signal bound twice takes its last binding.
protocol::SignalTable bound_signals_at(const bridge::SceneConfig& config, double fraction);

}  // namespace meter::testing
