// RGBA8 images and object masks.
#include "meter/platform/image.hpp"

#include <string>

namespace meter::platform {

Image::Image(int w, int h, std::uint8_t r, std::uint8_t g, std::uint8_t b, std::uint8_t a)
    : width(w), height(h) {
  if (w <= 0 || h <= 0) {
    throw std::invalid_argument("Image: size " + std::to_string(w) + "x" + std::to_string(h) +
                                " must be positive");
  }
  rgba.resize(static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 4);
  for (std::size_t i = 0; i < rgba.size(); i += 4) {
    rgba[i] = r;
    rgba[i + 1] = g;
    rgba[i + 2] = b;
    rgba[i + 3] = a;
  }
}

std::size_t Mask::count() const {
  std::size_t n = 0;
  for (auto v : on) n += v != 0;
  return n;
}

}  // namespace meter::platform
