#include "needle.hpp"

#include <cmath>

namespace meter::testing {

std::optional<double> needle_angle_deg(const platform::Image& image, const NeedleProbe& probe,
                                       int min_pixels) {
  double sx = 0.0, sy = 0.0;
  int n = 0;
  for (int y = 0; y < image.height; ++y) {
    for (int x = 0; x < image.width; ++x) {
      const double dx = x + 0.5 - probe.pivot_x;
      const double dy = y + 0.5 - probe.pivot_y;
      const double r = std::hypot(dx, dy);
      if (r < probe.r_min || r > probe.r_max) continue;
      const std::uint8_t* p = &image.rgba[(static_cast<std::size_t>(y) * image.width + x) * 4];
      if (p[0] >= probe.min_red && p[1] <= probe.max_green && p[2] <= probe.max_blue) {
        sx += dx;
        sy += dy;
        ++n;
      }
    }
  }
  if (n < min_pixels) return std::nullopt;
  // Screen direction (sin t, -cos t) for angle t clockwise from up, with y pointing down.
  return std::atan2(sx / n, -sy / n) * 180.0 / M_PI;
}

}  // namespace meter::testing
