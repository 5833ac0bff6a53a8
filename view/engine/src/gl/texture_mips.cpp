#include "meter/engine/gl/texture_mips.hpp"

#include <stdexcept>

namespace meter::engine {

namespace {
bool power_of_two(int n) { return n > 0 && (n & (n - 1)) == 0; }

// One level down: across first (a side already 1 stays), then down, each a rounded mean of two.
std::vector<std::uint8_t> half(const std::vector<std::uint8_t>& src, int w, int h) {
  const int nw = w > 1 ? w / 2 : 1, nh = h > 1 ? h / 2 : 1;
  const int dx = w > 1 ? 1 : 0, dy = h > 1 ? 1 : 0;
  std::vector<std::uint8_t> out(std::size_t(nw) * std::size_t(nh) * 4u);
  auto at = [&](int x, int y, int c) -> unsigned { return src[(std::size_t(y) * std::size_t(w) + std::size_t(x)) * 4u + std::size_t(c)]; };
  for (int y = 0; y < nh; ++y)
    for (int x = 0; x < nw; ++x)
      for (int c = 0; c < 4; ++c) {
        const int x0 = 2 * x, y0 = 2 * y;
        const unsigned top = (at(x0, y0, c) + at(x0 + dx, y0, c) + 1u) >> 1;
        const unsigned bottom = (at(x0, y0 + dy, c) + at(x0 + dx, y0 + dy, c) + 1u) >> 1;
        out[(std::size_t(y) * std::size_t(nw) + std::size_t(x)) * 4u + std::size_t(c)] = static_cast<std::uint8_t>((top + bottom + 1u) >> 1);
      }
  return out;
}
}  // namespace

bool box_mips_apply(int width, int height, bool srgb) { return !srgb && power_of_two(width) && power_of_two(height); }

std::vector<std::vector<std::uint8_t>> box_mip_chain(std::span<const std::uint8_t> rgba, int width, int height) {
  if (!box_mips_apply(width, height, false) || rgba.size() != std::size_t(width) * std::size_t(height) * 4u)
    throw std::invalid_argument("box_mip_chain: " + std::to_string(width) + "x" + std::to_string(height) +
                                " RGBA8 with power-of-two sides expected, got " + std::to_string(rgba.size()) + " bytes");
  std::vector<std::vector<std::uint8_t>> levels;
  std::vector<std::uint8_t> level(rgba.begin(), rgba.end());
  int w = width, h = height;
  while (w > 1 || h > 1) {
    level = half(level, w, h);
    w = w > 1 ? w / 2 : 1, h = h > 1 ? h / 2 : 1;
    levels.push_back(level);
  }
  return levels;
}

}  // namespace meter::engine
