// Keio's shading ladder as measured (none < flat < Gouraud < Phong in cost): per draw unit, the
// time of the unit alone at each shading model of its ladder (full mesh, node scale 1, over the
// frame with nothing drawn) and the PSNR the frame loses with that unit at that model, and the
// totals over the units that have every model. Printed by meter-calibrate.
#pragma once

#include <string>

#include "meter/calibrate/cost_samples.hpp"

namespace meter::calibrate {

// Pure: the table (one row per non-safety unit with more than one shading, a total row, and the
// count of rungs that cost more than the rung above them).
std::string shading_ladder_table(const CostMeasurements& m);

}  // namespace meter::calibrate
