// Robust fit of time = A x pixels + B (cost_fit.hpp).
#include "meter/engine/governor/cost_fit.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include "governor/robust_lsq.hpp"

namespace meter::engine::governor {
namespace {

// Theil-Sen: the median of the slopes between every two samples of different pixel counts (a
// deterministic subset of pairs for large inputs keeps it O(n x 500)), then the median intercept.
robust::Coefs theil_sen(std::span<const robust::Row> rows) {
  const std::size_t n = rows.size();
  constexpr std::size_t kAllPairsUpTo = 1000;
  std::vector<double> slopes;
  auto pair = [&](std::size_t i, std::size_t j) {
    const double dx = rows[j].u - rows[i].u;
    if (dx != 0) slopes.push_back((rows[j].y - rows[i].y) / dx);
  };
  if (n <= kAllPairsUpTo) {
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = i + 1; j < n; ++j) pair(i, j);
  } else {
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t k = 1; k <= kAllPairsUpTo / 2; ++k) pair(i, (i + k * (n / kAllPairsUpTo)) % n);
  }
  robust::Coefs c;
  c.c1 = robust::median(slopes);
  std::vector<double> intercepts(n);
  for (std::size_t i = 0; i < n; ++i) intercepts[i] = rows[i].y - c.c1 * rows[i].u;
  c.c2 = robust::median(intercepts);
  return c;
}

int distinct_pixels(std::span<const robust::Row> rows, const std::vector<char>& keep) {
  std::vector<double> xs;
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (keep[i]) xs.push_back(rows[i].u);
  std::sort(xs.begin(), xs.end());
  return int(std::unique(xs.begin(), xs.end()) - xs.begin());
}

}  // namespace

CostFit fit_cost(std::span<const CostSample> samples) {
  std::vector<robust::Row> rows;
  rows.reserve(samples.size());
  double max_ms = 0;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const CostSample& s = samples[i];
    if (!std::isfinite(s.pixels) || s.pixels < 0 || !std::isfinite(s.ms) || s.ms < 0)
      throw std::invalid_argument("cost fit: sample " + std::to_string(i) +
                                  ": expected finite pixels >= 0 and ms >= 0");
    rows.push_back({s.pixels, 1.0, s.ms});
    max_ms = std::max(max_ms, s.ms);
  }
  if (distinct_pixels(rows, std::vector<char>(rows.size(), 1)) < 2)
    throw std::invalid_argument("cost fit: expected samples at 2 or more distinct pixel counts, got " +
                                std::to_string(samples.size()) + " samples at fewer");
  // Independence of (pixels, 1) is 1 - mean(x)^2 / mean(x^2): > 0 for any 2 distinct counts; the
  // floor only guards against counts that differ in the last bits of a double.
  constexpr double kMinIndependence = 1e-12;
  // Residuals below a millionth of the largest time are rounding, not noise.
  const double sigma_floor = 1e-6 * max_ms + 1e-12;
  const robust::Coefs start = theil_sen(rows);
  robust::Trimmed t = robust::trimmed_fit(rows, start, sigma_floor, false, kMinIndependence);
  if (distinct_pixels(rows, t.keep) < 2) {
    // Trimming left one pixel count: the Theil-Sen line over every sample is the answer.
    t.coefs = start;
    t.keep.assign(rows.size(), 1);
  }
  CostFit fit;
  fit.a_ms_per_pixel = t.coefs.c1;
  fit.b_ms = t.coefs.c2;
  std::vector<double> kept_ms;
  for (std::size_t i = 0; i < rows.size(); ++i)
    if (t.keep[i]) kept_ms.push_back(rows[i].y);
  if (fit.a_ms_per_pixel < 0) {
    // Time cannot fall with more pixels: the measurements say the pixels cost nothing here.
    fit.a_ms_per_pixel = 0;
    fit.b_ms = robust::median(kept_ms);
  }
  double mean = 0;
  for (double y : kept_ms) mean += y;
  mean /= double(kept_ms.size());
  double ss_res = 0, ss_tot = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (!t.keep[i]) continue;
    const double r = rows[i].y - fit.a_ms_per_pixel * rows[i].u - fit.b_ms;
    ss_res += r * r;
    ss_tot += (rows[i].y - mean) * (rows[i].y - mean);
  }
  fit.r2 = ss_tot > 0 ? std::clamp(1.0 - ss_res / ss_tot, 0.0, 1.0) : (ss_res > 0 ? 0.0 : 1.0);
  fit.points_used = int(kept_ms.size());
  fit.points_rejected = int(rows.size()) - fit.points_used;
  return fit;
}

}  // namespace meter::engine::governor
