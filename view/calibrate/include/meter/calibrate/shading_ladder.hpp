// Keio's shading ladder as measured (none < flat < Gouraud < Phong in cost): the whole frame at
// each rung (CostMeasurements::shading_rungs) with the PSNR it loses and its cost against the rung
// above, then per draw unit the time of the unit alone at each shading model of its ladder (LOD 0,
// node scale 1, over the frame with nothing drawn) with the PSNR the frame loses with that unit at
// that model. Printed by meter-calibrate.
#pragma once

#include <string>

#include "meter/calibrate/cost_samples.hpp"

namespace meter::calibrate {

// Pure: the whole-frame rungs (and how many cost less than the rung above), then one row per
// non-safety unit with more than one shading that was timed above 0 at its own.
std::string shading_ladder_table(const CostMeasurements& m);

}  // namespace meter::calibrate
