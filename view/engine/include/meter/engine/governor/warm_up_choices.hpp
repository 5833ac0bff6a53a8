// The choices a renderer draws once at load so the governor's levels cost nothing extra the first
// time it takes them (Renderer::warm_up): per global rung, the frames that together use every
// level of every unit. Pure.
#pragma once

#include <vector>

#include "meter/engine/governor/cost_model.hpp"

namespace meter::engine::governor {

// For each rung of model.globals in order, steps k = K-1 ... 0 (K = the most shadings or LODs any
// unit has) with every non-safety unit at shading min(k, shadings - 1) and LOD min(k, lods - 1);
// safety units stay at level 0. Every (rung, unit shading) and (rung, unit LOD) pair is drawn by
// one of them, and each rung ends at full quality (its static layer then holds what a governed
// frame starts from); consecutive equal choices appear once. A model of R rungs yields at most R x K.
std::vector<QualityChoice> warm_up_choices(const CostModel& model);

}  // namespace meter::engine::governor
