// Which scene nodes make up a draw unit, and the binding outputs that show one unit alone (every other drawn node hidden), so meter-calibrate can time a unit on its own.
// Pure: plain data in, plain data out.
#pragma once

#include <span>
#include <vector>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/governor/quality_choice.hpp"
#include "meter/engine/vocabulary.hpp"

namespace meter::calibrate {

// The nodes of a draw unit: the node of each of its draws (Renderer::unit_draws), each once.
std::vector<int> unit_nodes(const engine::Scene& scene, std::span<const int> draws);

// `base` with only `shown` drawn: those nodes and their ancestors visible, every other node that
// has a mesh hidden (a hidden node hides its subtree), no texts. An ancestor that has a mesh of
// its own stays drawn (a node cannot be shown without its parent). `shown` empty: nothing drawn.
engine::BindingOutputs shown_alone(const engine::Scene& scene, const engine::BindingOutputs& base,
                                   const std::vector<int>& shown);

// The state the calibration measures in: every bound lamp lit (visibility, emissive and colour
// bindings at their "on" side) and every other numeric binding at the middle of its input range,
// so each unit that a binding can show is drawn, needles stand mid-scale; texts as formatted.
engine::BindingOutputs calibration_state(const engine::Scene& scene);

}  // namespace meter::calibrate
