#include "meter/engine/frame_plan/screen_regions.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace meter::engine {

long long area(const PixelRegion& r) { return r.empty() ? 0 : static_cast<long long>(r.width) * r.height; }

PixelRegion unite(const PixelRegion& a, const PixelRegion& b) {
  const int x0 = std::min(a.x, b.x), y0 = std::min(a.y, b.y);
  const int x1 = std::max(a.x + a.width, b.x + b.width), y1 = std::max(a.y + a.height, b.y + b.height);
  return {x0, y0, x1 - x0, y1 - y0};
}

bool contains(const PixelRegion& outer, const PixelRegion& inner) {
  return inner.x >= outer.x && inner.y >= outer.y && inner.x + inner.width <= outer.x + outer.width &&
         inner.y + inner.height <= outer.y + outer.height;
}

bool overlap(const PixelRegion& a, const PixelRegion& b) {
  return a.x < b.x + b.width && b.x < a.x + a.width && a.y < b.y + b.height && b.y < a.y + a.height;
}

void normalise(std::vector<PixelRegion>& regions, int width, int height) {
  for (auto& r : regions) r = platform::clip(r, width, height);
  std::erase_if(regions, [](const PixelRegion& r) { return r.empty(); });
  for (;;) {
    bool merged = false;
    for (std::size_t i = 0; i < regions.size() && !merged; ++i)
      for (std::size_t j = i + 1; j < regions.size() && !merged; ++j)
        if (overlap(regions[i], regions[j])) {
          regions[i] = unite(regions[i], regions[j]);
          regions.erase(regions.begin() + static_cast<std::ptrdiff_t>(j));
          merged = true;
        }
    if (merged) continue;
    if (regions.size() <= kMaxRegions) return;
    std::size_t bi = 0, bj = 1;
    long long best = std::numeric_limits<long long>::max();
    for (std::size_t i = 0; i < regions.size(); ++i)
      for (std::size_t j = i + 1; j < regions.size(); ++j) {
        const long long cost = area(unite(regions[i], regions[j])) - area(regions[i]) - area(regions[j]);
        if (cost < best) best = cost, bi = i, bj = j;
      }
    regions[bi] = unite(regions[bi], regions[bj]);
    regions.erase(regions.begin() + static_cast<std::ptrdiff_t>(bj));
  }
}

std::optional<PixelRegion> screen_box(const Primitive& prim, const glm::mat4& world, const glm::mat4& vp, int width,
                                      int height) {
  const glm::mat4 m = vp * world;
  float x0 = std::numeric_limits<float>::max(), y0 = x0, x1 = -x0, y1 = -x0;
  for (int k = 0; k < 8; ++k) {
    const glm::vec3 p((k & 1) ? prim.bounds_max.x : prim.bounds_min.x, (k & 2) ? prim.bounds_max.y : prim.bounds_min.y,
                      (k & 4) ? prim.bounds_max.z : prim.bounds_min.z);
    const glm::vec4 c = m * glm::vec4(p, 1.0f);
    if (!(c.w > 1e-6f)) return std::nullopt;
    const float sx = (c.x / c.w * 0.5f + 0.5f) * float(width), sy = (c.y / c.w * 0.5f + 0.5f) * float(height);
    if (!std::isfinite(sx) || !std::isfinite(sy)) return std::nullopt;
    x0 = std::min(x0, sx), x1 = std::max(x1, sx), y0 = std::min(y0, sy), y1 = std::max(y1, sy);
  }
  // Pixels are covered by their centre (and MSAA samples inside them): floor/ceil plus 1 px.
  const float lim = 4.0f * float(std::max(width, height));
  x0 = std::clamp(x0, -lim, lim), x1 = std::clamp(x1, -lim, lim), y0 = std::clamp(y0, -lim, lim), y1 = std::clamp(y1, -lim, lim);
  const int ix0 = int(std::floor(x0)) - 1, iy0 = int(std::floor(y0)) - 1;
  const int ix1 = int(std::ceil(x1)) + 1, iy1 = int(std::ceil(y1)) + 1;
  return PixelRegion{ix0, iy0, ix1 - ix0, iy1 - iy0};
}

}  // namespace meter::engine
