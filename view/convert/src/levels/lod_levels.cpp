// LOD levels: meshoptimizer's simplifier at stated error bounds (levels.hpp).
#include <algorithm>

#include <meshoptimizer.h>

#include "levels/level_stages.hpp"

namespace meter::convert {

std::vector<LodLevel> simplify_levels(const Primitive& p, const std::vector<float>& error_bounds, float min_saving) {
  std::vector<LodLevel> out;
  const auto pos = std::find_if(p.layout.begin(), p.layout.end(),
                                [](const VertexAttribute& v) { return v.semantic == AttributeSemantic::Position; });
  if (pos == p.layout.end() || p.indices.size() < 6 || p.morph_targets > 0) return out;
  const double full = double(p.indices.size() / 3);
  std::size_t previous = p.indices.size();
  std::vector<unsigned int> dst(p.indices.size());
  for (const float bound : error_bounds) {
    float error = 0.0f;
    // Target 3 indices: as far as the error bound allows. Simplifying the full mesh at each bound
    // (not the previous level) keeps every level's error measured against the original.
    const std::size_t n = meshopt_simplify(dst.data(), p.indices.data(), p.indices.size(), p.vertices.data() + pos->offset,
                                           p.vertex_count, std::size_t(p.stride) * sizeof(float), 3, bound, 0, &error);
    if (n < 3 || double(n) > double(previous) * (1.0 - double(min_saving))) continue;
    LodLevel l;
    l.error = error;
    l.triangle_fraction = float(double(n / 3) / full);
    l.indices.assign(dst.begin(), dst.begin() + static_cast<std::ptrdiff_t>(n));
    out.push_back(std::move(l));
    previous = n;
  }
  return out;
}

}  // namespace meter::convert
