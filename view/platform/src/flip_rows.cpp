#include "meter/platform/flip_rows.hpp"

#include <cstdint>
#include <cstring>
#include <vector>

namespace meter::platform {

void flip_rows(Image& image) {
  const std::size_t row = static_cast<std::size_t>(image.width) * 4;
  std::vector<std::uint8_t> tmp(row);
  for (int y = 0; y < image.height / 2; ++y) {
    std::uint8_t* a = image.rgba.data() + static_cast<std::size_t>(y) * row;
    std::uint8_t* b = image.rgba.data() + static_cast<std::size_t>(image.height - 1 - y) * row;
    std::memcpy(tmp.data(), a, row);
    std::memcpy(a, b, row);
    std::memcpy(b, tmp.data(), row);
  }
}

}  // namespace meter::platform
