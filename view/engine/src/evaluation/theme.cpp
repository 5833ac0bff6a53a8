// Day/night theme transition and brightness: pure curves on the render clock.
#include <algorithm>
#include <cmath>

#include "meter/engine/evaluation/scene_features.hpp"

namespace meter::engine {

double theme_curve(double p) {
  const double x = std::clamp(p, 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

double theme_progress(double progress, double target, double duration_s, double dt) {
  if (dt < 0 || duration_s <= 0) return target;
  const double step = dt / duration_s;
  return target > progress ? std::min(target, progress + step) : std::max(target, progress - step);
}

double brightness_stops(double percent, double min_stops) {
  const double u = std::clamp(percent, 0.0, 100.0) / 100.0;
  return (1.0 - u) * min_stops;
}

}  // namespace meter::engine
