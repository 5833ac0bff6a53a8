// The film filter's kernel and per-sample weights (resolve_filter.hpp).
#include "meter/platform/resolve_filter.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace meter::platform {

const char* to_string(ResolveFilter::Kind kind) {
  return kind == ResolveFilter::Kind::Box ? "box" : "blackman-harris";
}

double blackman_harris(double offset, double radius) {
  if (!(radius > 0.0) || !(std::abs(offset) < radius)) return 0.0;
  // EEVEE's window on u in [-1/2, 1/2]: 0.35875 - 0.48829 cos(x) + 0.14128 cos(2x) - 0.01168 cos(3x),
  // x = 2 pi (u + 1/2); u = offset / (2 radius).
  const double x = 2.0 * std::numbers::pi * (offset / (2.0 * radius) + 0.5);
  return 0.35875 - 0.48829 * std::cos(x) + 0.14128 * std::cos(2.0 * x) - 0.01168 * std::cos(3.0 * x);
}

int filter_reach_px(const ResolveFilter& filter) {
  if (filter.kind == ResolveFilter::Kind::Box) return 0;
  // The nearest sample of a neighbour k pixels away lies just over k - 1/2 from the centre.
  return static_cast<int>(std::ceil(filter.width_px + 0.5)) - 1;
}

std::vector<float> resolve_weights(const ResolveFilter& filter, std::span<const std::array<float, 2>> positions) {
  if (positions.empty()) throw std::invalid_argument("resolve_weights: no sample positions");
  const std::size_t n = positions.size();
  const int k = filter_reach_px(filter);
  const int side = 2 * k + 1;
  std::vector<double> w(static_cast<std::size_t>(side * side) * n, 0.0);
  double sum = 0.0;
  for (int dy = -k; dy <= k; ++dy)
    for (int dx = -k; dx <= k; ++dx)
      for (std::size_t s = 0; s < n; ++s) {
        double v = 1.0;
        if (filter.kind == ResolveFilter::Kind::BlackmanHarris) {
          // The sample's offset from the output pixel's centre (both in pixels).
          const double ox = dx + double(positions[s][0]) - 0.5, oy = dy + double(positions[s][1]) - 0.5;
          v = blackman_harris(ox, filter.width_px) * blackman_harris(oy, filter.width_px);
        }
        w[static_cast<std::size_t>((dy + k) * side + dx + k) * n + s] = v;
        sum += v;
      }
  if (!(sum > 0.0))
    throw std::invalid_argument("resolve_weights: a " + std::string(to_string(filter.kind)) + " filter " +
                                std::to_string(filter.width_px) + " px wide covers no sample");
  // The kernel's far corners: dropped, the rest renormalized (a flat area still resolves exactly).
  double kept = 0.0;
  for (double& v : w) {
    if (v < kNegligibleWeight * sum) v = 0.0;
    kept += v;
  }
  std::vector<float> out(w.size());
  for (std::size_t i = 0; i < w.size(); ++i) out[i] = static_cast<float>(w[i] / kept);
  return out;
}

}  // namespace meter::platform
