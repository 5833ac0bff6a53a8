// What meter-view does with a loaded scene each frame, GL aside, for the fuzz targets that load
// one (package, glTF, scene config): bindings over signal states, scene evaluation, the frame.
#pragma once

#include <cstdint>
#include <span>

#include "meter/engine/vocabulary.hpp"

namespace meter::engine::fuzz {

// Steps the bindings over a few signal tables whose values and statuses come from `values`
// (cycled; every catalog signal set), then applies the outputs, updates the world matrices and
// evaluates the frame at the configured size. Throws what the engine throws for a scene it
// rejects (SceneError); aborts on a broken invariant (a non-finite world matrix entry from finite
// inputs is not checked: the scene may be degenerate by design).
void exercise_scene(const Scene& scene, std::span<const std::uint8_t> values);

}  // namespace meter::engine::fuzz
