// The state each committed Blender reference shows, so that a render compared with it is drawn in
// the same state: meter-bench's fidelity table and the fidelity test's floors use the same one.
#pragma once

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/vocabulary.hpp"

namespace meter::testing {

// Feature scenes (scenes/features/*/reference.png): no signals, animations at config.time.
engine::BindingOutputs feature_reference_state(const engine::Scene& scene);
// The cluster (scenes/cluster/preview-blender.png, rendered by scenes/cluster/build.py): frame 100
// (speed needle at 100 km/h, every other needle at its frame-100 key or its end key), every
// telltale lit, no text (the text is drawn by the engine, not in the .glb).
engine::BindingOutputs cluster_reference_state(const engine::Scene& scene);

}  // namespace meter::testing
