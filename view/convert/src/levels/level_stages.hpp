// The parts of make_levels (meter/convert/levels.hpp), private to meter_convert: one job per file.
#pragma once

#include <vector>

#include "meter/convert/levels.hpp"

namespace meter::convert {

// LOD levels of one primitive (lod_levels.cpp): for each error bound in turn, the simplified index
// list, kept when it saves >= min_saving of the previous level's triangles.
std::vector<LodLevel> simplify_levels(const Primitive& prim, const std::vector<float>& error_bounds, float min_saving);

// Shading levels of every non-safety draw (shading_levels.cpp): `safety` per draw. Appends the
// programs to scene.programs; fills scene.draw_levels[i].shadings.
void make_shading_levels(Scene& scene, const std::vector<char>& safety, const LevelOptions& options, LevelsReport& report);

}  // namespace meter::convert
