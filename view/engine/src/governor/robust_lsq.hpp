// Robust least squares of y ~ c1 x u + c2 x v, the one solver behind the calibration fit
// (u = pixels, v = 1: a line with intercept) and the online estimate (u = predicted pixel part,
// v = predicted fixed part: two scales). Internal to the governor.
#pragma once

#include <optional>
#include <span>
#include <vector>

namespace meter::engine::governor::robust {

struct Row {
  double u, v, y;
};

struct Coefs {
  double c1 = 0.0, c2 = 0.0;
};

// Median of the values (they are reordered); 0 for none.
double median(std::vector<double>& values);

// Ordinary least squares over the rows whose keep flag is set. Empty when fewer than 2 rows are
// kept or the normal equations are singular: 1 - (u.v)^2 / (u.u v.v) below min_independence.
std::optional<Coefs> least_squares(std::span<const Row> rows, const std::vector<char>& keep,
                                   double min_independence);

// The same for one common coefficient: y ~ c x (u + v). Empty when no kept row has u + v != 0.
std::optional<double> common_scale(std::span<const Row> rows, const std::vector<char>& keep);

struct Trimmed {
  Coefs coefs;
  std::vector<char> keep;
  int rejected = 0;
};

// Iteratively trimmed least squares from `start`: rows whose residual exceeds 3 robust standard
// deviations (1.4826 x the median absolute residual, at least sigma_floor) are dropped and the
// rest refitted, until the kept set is stable (at most 20 rounds). one_scale: fit c1 = c2.
Trimmed trimmed_fit(std::span<const Row> rows, Coefs start, double sigma_floor, bool one_scale,
                    double min_independence);

}  // namespace meter::engine::governor::robust
