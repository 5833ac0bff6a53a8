#include "meter/platform/flip_rows.hpp"

#include <algorithm>
#include <cstdint>

namespace meter::platform {

void flip_rows(Image& image) {
  const std::size_t row = static_cast<std::size_t>(image.width) * 4;
  for (int y = 0; y < image.height / 2; ++y) {
    std::uint8_t* a = image.rgba.data() + static_cast<std::size_t>(y) * row;
    std::uint8_t* b = image.rgba.data() + static_cast<std::size_t>(image.height - 1 - y) * row;
    std::swap_ranges(a, a + row, b);  // in place: no scratch row per call (per safety region, per frame)
  }
}

}  // namespace meter::platform
