// Robust least squares of y ~ c1 x u + c2 x v (robust_lsq.hpp).
#include "governor/robust_lsq.hpp"

#include <algorithm>
#include <cmath>

namespace meter::engine::governor::robust {

double median(std::vector<double>& values) {
  if (values.empty()) return 0.0;
  const std::size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(mid), values.end());
  const double upper = values[mid];
  if (values.size() % 2 == 1) return upper;
  const double lower = *std::max_element(values.begin(), values.begin() + std::ptrdiff_t(mid));
  return 0.5 * (lower + upper);
}

std::optional<Coefs> least_squares(std::span<const Row> rows, const std::vector<char>& keep,
                                   double min_independence) {
  double suu = 0, suv = 0, svv = 0, suy = 0, svy = 0;
  int n = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (!keep[i]) continue;
    const Row& r = rows[i];
    suu += r.u * r.u;
    suv += r.u * r.v;
    svv += r.v * r.v;
    suy += r.u * r.y;
    svy += r.v * r.y;
    ++n;
  }
  if (n < 2 || !(suu > 0) || !(svv > 0)) return std::nullopt;
  const double det = suu * svv - suv * suv;
  if (!(det / (suu * svv) >= min_independence)) return std::nullopt;
  Coefs c{(suy * svv - svy * suv) / det, (svy * suu - suy * suv) / det};
  if (!std::isfinite(c.c1) || !std::isfinite(c.c2)) return std::nullopt;
  return c;
}

std::optional<double> common_scale(std::span<const Row> rows, const std::vector<char>& keep) {
  double sxx = 0, sxy = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (!keep[i]) continue;
    const double x = rows[i].u + rows[i].v;
    sxx += x * x;
    sxy += x * rows[i].y;
  }
  if (!(sxx > 0)) return std::nullopt;
  const double c = sxy / sxx;
  if (!std::isfinite(c)) return std::nullopt;
  return c;
}

Trimmed trimmed_fit(std::span<const Row> rows, Coefs start, double sigma_floor, bool one_scale,
                    double min_independence) {
  Trimmed t{start, std::vector<char>(rows.size(), 1), 0};
  std::vector<double> residuals(rows.size());
  std::vector<double> scratch;
  for (int round = 0; round < 20; ++round) {
    for (std::size_t i = 0; i < rows.size(); ++i)
      residuals[i] = std::abs(rows[i].y - t.coefs.c1 * rows[i].u - t.coefs.c2 * rows[i].v);
    scratch = residuals;
    const double sigma = std::max(1.4826 * median(scratch), sigma_floor);
    std::vector<char> keep(rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) keep[i] = residuals[i] <= 3.0 * sigma ? 1 : 0;
    if (round > 0 && keep == t.keep) break;
    Coefs next;
    if (one_scale) {
      const auto c = common_scale(rows, keep);
      if (!c) break;
      next = {*c, *c};
    } else {
      const auto c = least_squares(rows, keep, min_independence);
      if (!c) break;
      next = *c;
    }
    t.coefs = next;
    t.keep = std::move(keep);
  }
  t.rejected = int(std::count(t.keep.begin(), t.keep.end(), char(0)));
  return t;
}

}  // namespace meter::engine::governor::robust
