// The greedy quality choice of the uniform-frame-rate algorithm (Keio), pure.
//
// Quality order: a unit's screen size first, then its LOD, then its shading. Within one unit the
// levels rank lod x shadings + shading (lower = better): the shading drops first, then the LOD
// with the shading back to the best, as in the paper. Costs are measured, so a step down goes to
// the next rank that is predicted CHEAPER for this frame (a rank that costs more, e.g. flat where
// it is slower than Gouraud, is skipped), a step up to the best rank that still fits.
//
// Over the trigger (prediction of the current choice > trigger_ms): lower the smallest drawn unit
// (fewest pixels) one step at a time until it has no cheaper level, then the next smallest, until
// the prediction is <= budget_ms. Then (always) raise: the largest unit first, each to the best
// level that keeps the prediction <= budget_ms; a unit that cannot rise is passed over and the
// next one tried, until no unit or rung can rise.
//
// Global rungs (GlobalCost, in their file's quality order) are one more ladder: a step down moves
// to the next rung predicted cheaper, a step up to the best rung that fits. When both the unit
// step and the rung step have PSNR estimates, the rung is taken instead of the unit step when it
// buys more ms per unit of added error (relative_error differences; a step that adds no error is
// worth any saving); on raising, when it buys back more error per ms spent. Without estimates the
// rungs go down last (after every unit is at its cheapest) and come back up first.
//
// Ties: units of equal size go in index order (lower first, on both directions); between a unit
// step and a rung step of equal trade the unit step (the paper's order) wins.
//
// Safety units never move: they are held at level 0. Units with 0 pixels in this frame are not
// moved (changing one would redraw its box, work the load does not describe) unless the last
// full frame's load is given: then a moved unit counts with its pixels of that frame (its whole
// box), and a rung change (which forces a full redraw) is judged on that full load. Without it a
// rung change is judged on this load.
//
// Cost: O(steps x units) predictions of one unit each, plus one sort; no allocation but the
// result and the order.
#pragma once

#include "meter/engine/governor/cost_model.hpp"

namespace meter::engine::governor {

struct GreedyBudget {
  double trigger_ms = 0.0;  // lower only when the current choice is predicted above this
  double budget_ms = 0.0;   // what a lowered or raised choice must be predicted within
};

struct GreedyResult {
  QualityChoice choice;     // units has one entry per model unit
  double predicted_ms = 0.0;
  bool lowered = false;     // some step down was taken
  bool raised = false;      // some step up was taken
};

// full_load: the last full frame's load (or nullptr). current: the choice the renderer holds
// (empty units = all at level 0; a global not in the model = rung 0). Throws
// std::invalid_argument when the load or the current choice does not fit the model.
GreedyResult greedy_choice(const CostModel& model, const FrameLoad& load, const QualityChoice& current,
                           const GreedyBudget& budget, const ModelScale& scale = {},
                           const FrameLoad* full_load = nullptr);

// The full-quality choice of the model: rung 0, every unit at level 0.
QualityChoice full_quality(const CostModel& model);

// The cheapest choice by the measured costs (a fixed-quality reference for benchmarks): the rung
// with the smallest pixel factor (ties: smaller fixed part, then the later rung), every
// non-safety unit at its level of smallest A (ties: smaller B, then the later level in the
// quality order). Measured, so it need not be the last level: flat may cost more than Gouraud.
QualityChoice cheapest_quality(const CostModel& model);

}  // namespace meter::engine::governor
