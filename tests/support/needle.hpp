// Reading a needle angle back from a rendered frame: the end-to-end tests judge pixels, not files.
#pragma once

#include <optional>

#include "meter/platform/image.hpp"

namespace meter::testing {

struct NeedleProbe {
  double pivot_x, pivot_y;   // pixel coordinates, y down, of the rotation axis
  double r_min, r_max;       // annulus that sees only the needle over the dial face
  // A pixel belongs to the needle when it is saturated red.
  int min_red = 180, max_green = 90, max_blue = 90;
};

// Angle in degrees, clockwise from straight up, of the centroid of the needle pixels inside the
// annulus; nullopt if fewer than min_pixels qualify (no needle visible).
std::optional<double> needle_angle_deg(const platform::Image& image, const NeedleProbe& probe,
                                       int min_pixels = 20);

}  // namespace meter::testing
