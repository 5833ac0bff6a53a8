// The frame-rate governor's cost model (pure): how long a frame takes to draw at a given quality.
//
// Per draw unit and per level (shading, lod) of its UnitLadder, the time to draw it is
//     A x pixels x pixel_factor(global rung) + B            (ms; pixels inside this frame's damage)
// and 0 when the unit is not drawn in this frame (0 pixels). Per global rung (MSAA, resolution
// scale) a factor on every pixel part and a fixed part (resolve, upscale); per frame an overhead
// (clear and resolve of the redrawn pixels, swap). The coefficients are measured on the machine
// (meter-calibrate, fit_cost), never assumed from a level's name, and stored in a `meter-costs/1`
// file (cost_file.hpp). Optionally each level and rung carries the PSNR of the frame drawn with it
// against the full-quality frame, so the greedy choice can compare trades per dB.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "meter/engine/governor/quality_choice.hpp"

namespace meter::engine::governor {

// time = a_ms_per_pixel x pixels + b_ms
struct LinearCost {
  double a_ms_per_pixel = 0.0;
  double b_ms = 0.0;
  bool operator==(const LinearCost&) const = default;
};

// One level of one unit, as calibrated.
struct LevelCost {
  bridge::ShadingModel shading = bridge::ShadingModel::PbrMetallicRoughness;
  int lod = 0;
  LinearCost cost;
  // PSNR (dB) of the config-size frame with this unit at this level (all else full) against the
  // full-quality frame; absent = not measured. Level 0 needs none (identical by definition).
  std::optional<double> psnr_db;
  bool operator==(const LevelCost&) const = default;
};

// One frame-wide rung: what it multiplies every unit's pixel part with, what it adds per frame.
struct GlobalCost {
  GlobalLevel level;
  double pixel_factor = 1.0;
  double fixed_ms = 0.0;
  std::optional<double> psnr_db;  // as LevelCost::psnr_db, for this rung with every unit at level 0
  bool operator==(const GlobalCost&) const = default;
};

// A cost model matched to the renderer's draw units (cost_file.hpp: bind_costs): units[i] is for
// UnitLadder i, and its levels are dense in ladder indices: levels[shading * lods + lod].
struct UnitCosts {
  std::string name;
  bool safety = false;
  int shadings = 1;
  int lods = 1;
  std::vector<LevelCost> levels;
  const LevelCost& at(const UnitLevel& l) const { return levels[std::size_t(l.shading * lods + l.lod)]; }
};

struct CostModel {
  LinearCost overhead;             // per drawn frame: a x redrawn output pixels + b
  std::vector<GlobalCost> globals; // [0] = full quality; the list is the rungs' quality order
  std::vector<UnitCosts> units;
};

// The online correction the governor applies to the calibrated model (online_estimate.hpp):
// predicted = pixel x (sum of pixel parts) + fixed x (sum of fixed parts).
struct ModelScale {
  double pixel = 1.0;
  double fixed = 1.0;
  bool operator==(const ModelScale&) const = default;
};

// A prediction split into the part proportional to pixels and the fixed part (both >= 0, finite).
struct PredictionParts {
  double pixel_ms = 0.0;
  double fixed_ms = 0.0;
  double total(const ModelScale& s = {}) const { return s.pixel * pixel_ms + s.fixed * fixed_ms; }
};

// Index of `level` in model.globals, or -1.
int global_rung(const CostModel& model, const GlobalLevel& level);

// The frame's predicted parts at `choice` (an empty choice.units = every unit at level 0).
// A frame that is not drawn costs 0. Pixel counts that are negative or NaN count as 0 and
// infinite ones as kMaxPixels, so the result is always finite. Throws std::invalid_argument when
// the choice or the load does not fit the model (unit count, level index, unknown global rung).
inline constexpr double kMaxPixels = 1e12;
PredictionParts predict_parts(const CostModel& model, const FrameLoad& load, const QualityChoice& choice);
double predict_ms(const CostModel& model, const FrameLoad& load, const QualityChoice& choice,
                  const ModelScale& scale = {});

// The cost of one unit at `level` under rung `global` with `pixels` of it redrawn (0 when pixels
// is 0): the pixel part and the fixed part.
PredictionParts unit_parts(const CostModel& model, int unit, const UnitLevel& level, int global,
                           double pixels);

// Pixel counts as the model reads them: negative / NaN -> 0, above kMaxPixels -> kMaxPixels.
double sane_pixels(double p);

// The frame's error relative to full quality implied by a PSNR: 10^(-psnr/10) (= MSE / peak^2).
// Errors of disjoint units add, which is how the greedy choice compares trades.
double relative_error(const std::optional<double>& psnr_db);

}  // namespace meter::engine::governor
