// Fitting time = A x pixels + B to measured (pixels, ms) pairs, robust to outliers: a Theil-Sen
// start (median of pairwise slopes) refined by iteratively trimmed least squares (points whose
// residual exceeds 3 robust standard deviations are dropped, the rest refitted, until the kept
// set no longer changes). Pure; used by the calibration and by the tests.
#pragma once

#include <span>

namespace meter::engine::governor {

struct CostSample {
  double pixels = 0.0;
  double ms = 0.0;
};

struct CostFit {
  double a_ms_per_pixel = 0.0;
  double b_ms = 0.0;
  double r2 = 0.0;          // of the kept points (1 when they lie on the line exactly)
  int points_used = 0;
  int points_rejected = 0;  // outliers dropped (non-finite samples are not counted here: they throw)
};

// Throws std::invalid_argument (naming the sample index) for a non-finite or negative sample, and
// for degenerate input: fewer than 2 distinct pixel counts. Never returns NaN.
CostFit fit_cost(std::span<const CostSample> samples);

}  // namespace meter::engine::governor
