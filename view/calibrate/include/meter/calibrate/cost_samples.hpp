// What meter-calibrate measured, as plain data, and the cost file made from it (pure: the fits
// and the rung order; tested without GL).
//
// The measurement (calibration.hpp) draws the package at several node scales (every mesh node's
// scale times s, so each unit covers fewer pixels at the same level) with partial redraw off:
//   - per unit and level: the unit alone (every other unit hidden) minus the frame with nothing
//     drawn, against the unit's screen pixels at that scale -> time = A x pixels + B (fit_cost);
//   - rung 0's whole frame at level 0 -> the units' A and B rescaled so that their sum predicts it
//     (time - overhead = alpha x sum of A x pixels + c: A times alpha, B times c / sum of B);
//   - every other rung: the whole frame at level 0 -> its pixel factor and fixed part against that
//     (time - overhead - c = factor x sum of A x pixels + fixed);
//   - the frame with no unit drawn (clear, texts, resolve of the target) -> the frame overhead;
//   - PSNR of the config-size frame with one unit at one level (or at one rung) against full quality.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "meter/engine/governor/cost_file.hpp"
#include "meter/engine/governor/cost_fit.hpp"
#include "meter/engine/governor/quality_choice.hpp"

namespace meter::calibrate {

// PSNR written for a frame identical to full quality (the cost file needs a finite value).
inline constexpr double kIdenticalPsnrDb = 100.0;

struct LevelSamples {
  int unit = 0;
  engine::governor::UnitLevel level;
  std::vector<engine::governor::CostSample> samples;  // (unit pixels, ms alone minus nothing drawn), per node scale
  std::optional<double> psnr_db;                       // level 0: none
};

struct RungSamples {
  engine::governor::GlobalLevel level;
  std::vector<double> frame_ms;  // the whole frame at level 0, per node scale
  std::optional<double> psnr_db; // rung 0: none
};

// Keio's shading ladder on the whole frame: every unit at the most expensive of its shadings that
// is not above `model` (safety units and units with none at their own), at LOD 0.
struct ShadingRungSamples {
  bridge::ShadingModel model{};
  double frame_ms = 0.0;          // node scale 1, the median
  // The median over the rounds of this rung's frame / the rung above's frame drawn just before it
  // (paired: a load swing between rounds cancels); the top rung: 1.
  double vs_above = 1.0;
  std::optional<double> psnr_db;  // the top rung (every unit at its own): none
};

struct CostMeasurements {
  std::string backend, package;
  std::vector<engine::governor::UnitLadder> ladders;
  double empty_ms = 0.0;                         // a full frame with no unit drawn (texts drawn)
  std::vector<std::vector<double>> unit_pixels;  // per node scale: each unit's pixels in the full frame
  std::vector<LevelSamples> levels;              // every unit at every level its ladder has
  std::vector<RungSamples> rungs;                // [0] = the renderer's own (full quality)
  std::optional<engine::governor::ConcatenationCosts> concatenation{};  // oh, m, s (merge_costs.hpp)
  std::vector<ShadingRungSamples> shading_rungs;  // most expensive model first (shading_ladder.hpp)
};

// The median of `v` (0 for none).
double median(std::vector<double> v);

// The level's time = A x pixels + B: fit_cost when the samples have two distinct pixel counts,
// else A = 0 and B = their median; A and B are never negative (a negative fit is timing noise on a
// unit too small to time: A = 0, B = the median).
engine::governor::LinearCost level_cost(const std::vector<engine::governor::CostSample>& samples);

// The cost file: units keyed by ladder name, levels by (shading, lod); overhead = the empty frame;
// rung 0 (factor 1, fixed 0) first, the others fitted as above and ordered by PSNR, best first (an unmeasured
// PSNR last). Units of one name (a node drawn as several draws) are listed in unit order, as
// bind_costs matches them. Throws std::invalid_argument when the measurements are incomplete (a
// ladder level without samples, a rung without one time per node scale).
engine::governor::CostFile cost_file(const CostMeasurements& m);

}  // namespace meter::calibrate
