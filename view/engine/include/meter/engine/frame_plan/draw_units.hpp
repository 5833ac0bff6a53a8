// Draw units and their quality levels: what the renderer submits as one draw (a draw drawn on its
// own, or a merged group), the levels each can take (from the package's draw levels,
// meter/bridge/draw_levels.hpp), a quality choice applied to an evaluated frame, and the frame's
// planned load per unit (what the frame-rate governor predicts from). Pure: no GL.
#pragma once

#include <string>
#include <vector>

#include "meter/engine/evaluation/frame_state.hpp"
#include "meter/engine/frame_plan/draw_classes.hpp"
#include "meter/engine/frame_plan/frame_plan.hpp"
#include "meter/engine/governor/quality_choice.hpp"
#include "meter/engine/vocabulary.hpp"

namespace meter::engine {

struct DrawUnits {
  // One per unit, in Scene::draws order: a draw drawn on its own, or a merged group at its
  // representative's (first member's) place.
  std::vector<governor::UnitLadder> ladders;
  std::vector<std::vector<int>> members;  // per unit: its draws (a group's in the group's order)
  std::vector<int> unit_of;               // per draw: its unit
  // Per unit, per LOD of its ladder: the LOD level its members are drawn at (each clamped to its
  // own count). [0] = 0.
  std::vector<std::vector<int>> lod_steps;
};

// `classes.group` says which draws are drawn merged. `shading_levels` false (the uber-shader
// baseline, which has one program for everything): every unit has only its own shading.
// A unit's shadings are its representative's (a group's members share their programs at every
// level: check_draw_levels); member LOD k draws each member at min(k, that member's lods), the
// error is the largest member's and the triangle fraction the members' total, and it is one of
// the unit's LODs only when it drops >= 25 % of the triangles of the unit's LOD before (lod_steps).
// A unit with a safety member is a safety unit: one shading, one LOD.
DrawUnits make_draw_units(const Scene& scene, const DrawClasses& classes, bool shading_levels);

// The package reader's check of Scene::draw_levels against the scene: sizes, program and LOD
// indices in range, a level's program of the same blend and cull state as the draw's own, a
// group's members with equal shading programs. Returns "" when fine, else what is wrong, naming
// the draw and the level ("draw_levels[3].shadings[1].program: 40 out of range (12 programs)").
std::string check_draw_levels(const Scene& scene);

// Throws std::invalid_argument naming the unit and the level when `choice` does not fit `units`
// (see Renderer::set_quality); returns the choice with units filled (an empty list: all level 0).
// `current_msaa` (the renderer's sample count, e.g. 8 from RendererOptions) is accepted besides 1, 2, 4.
governor::QualityChoice checked_choice(const DrawUnits& units, const governor::QualityChoice& choice, int current_msaa);

// Sets every draw's DrawState::shading / lod in `frame` to its unit's level in `choice`
// (choice.units has one entry per unit).
void apply_levels(const Scene& scene, const DrawUnits& units, const governor::QualityChoice& choice, FrameState& frame);

// The planned frame's load: per unit, the pixels of its members' screen boxes inside the passes'
// scissors (the whole target for a full pass), at scale 1 (pixel counts of a target drawn at
// `scale` are divided by scale^2). `width` x `height` is the target the plan is for.
governor::FrameLoad frame_load(const Scene& scene, const DrawClasses& classes, const DrawUnits& units,
                               const FrameState& now, const FramePlan& plan, int width, int height, float scale);

}  // namespace meter::engine
