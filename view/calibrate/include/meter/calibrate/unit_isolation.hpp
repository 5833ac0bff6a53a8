// Which scene nodes make up each of the renderer's draw units, and the binding outputs that show
// one unit alone (every other drawn node hidden), so meter-calibrate can time a unit on its own.
// Pure: plain data in, plain data out.
#pragma once

#include <span>
#include <vector>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/governor/quality_choice.hpp"
#include "meter/engine/scene.hpp"

namespace meter::calibrate {

// Per draw unit, the nodes whose draws it holds. The units are listed as Renderer::draw_units()
// lists them: Scene::draws order, one per draw drawn on its own and one per merged group at its
// representative's (first member's) place. Throws std::invalid_argument when `ladders` does not
// follow that order (count or a name differs: the renderer and the calibration disagree).
std::vector<std::vector<int>> unit_nodes(const engine::Scene& scene, std::span<const engine::governor::UnitLadder> ladders);

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
