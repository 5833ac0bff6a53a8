#include "scene/vertex_layout.hpp"

#include <limits>

namespace meter::convert {

using bridge::AttributeSemantic;

std::vector<std::uint32_t> triangle_list(const std::vector<std::uint32_t>& src, TriangleMode mode) {
  std::vector<std::uint32_t> tris;
  auto push = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    if (a != b && a != c && b != c) tris.insert(tris.end(), {a, b, c});
  };
  if (mode == TriangleMode::Strip) {
    for (std::size_t k = 0; k + 2 < src.size(); ++k) (k % 2) ? push(src[k + 1], src[k], src[k + 2]) : push(src[k], src[k + 1], src[k + 2]);
  } else if (mode == TriangleMode::Fan) {
    for (std::size_t k = 1; k + 1 < src.size(); ++k) push(src[0], src[k], src[k + 1]);
  } else {
    for (std::size_t k = 0; k + 2 < src.size(); k += 3) push(src[k], src[k + 1], src[k + 2]);
  }
  return tris;
}

RawPrimitive with_flat_normals(const RawPrimitive& raw, const std::vector<std::uint32_t>& tris) {
  RawPrimitive flat;
  flat.vcount = tris.size();
  for (const auto& [key, val] : raw.attrs) {
    std::vector<float> d;
    d.reserve(tris.size() * std::size_t(val.first));
    for (auto v : tris) d.insert(d.end(), val.second.begin() + std::ptrdiff_t(v) * val.first, val.second.begin() + std::ptrdiff_t(v + 1) * val.first);
    flat.attrs[key] = {val.first, std::move(d)};
  }
  const auto& p = flat.attrs[{int(AttributeSemantic::Position), -1}].second;
  std::vector<float> n(tris.size() * 3);
  for (std::size_t t = 0; t < tris.size(); t += 3) {
    glm::vec3 a(p[t * 3], p[t * 3 + 1], p[t * 3 + 2]), b(p[t * 3 + 3], p[t * 3 + 4], p[t * 3 + 5]), c(p[t * 3 + 6], p[t * 3 + 7], p[t * 3 + 8]);
    glm::vec3 fn = glm::cross(b - a, c - a);
    fn = glm::length(fn) > 0 ? glm::normalize(fn) : glm::vec3(0, 0, 1);
    for (int k = 0; k < 3; ++k) n[(t + std::size_t(k)) * 3] = fn.x, n[(t + std::size_t(k)) * 3 + 1] = fn.y, n[(t + std::size_t(k)) * 3 + 2] = fn.z;
  }
  flat.attrs[{int(AttributeSemantic::Normal), -1}] = {3, std::move(n)};
  for (std::size_t k = 0; k < tris.size(); ++k) flat.indices.push_back(static_cast<std::uint32_t>(k));
  return flat;
}

Primitive interleave(RawPrimitive raw, int material_index, int morph_targets) {
  Primitive out;
  out.material = material_index;
  out.vertex_count = static_cast<std::uint32_t>(raw.vcount);
  out.morph_targets = morph_targets;
  // Interleave in map order (Position, Normal, Tangent, TexCoord0, ...; morph targets last).
  for (auto& [key, val] : raw.attrs) {
    out.layout.push_back({static_cast<AttributeSemantic>(key.first), key.second, val.first, out.stride});
    out.stride += val.first;
  }
  out.vertices.resize(raw.vcount * std::size_t(out.stride));
  for (const auto& l : out.layout) {
    const auto& d = raw.attrs[{int(l.semantic), l.index}].second;
    for (std::size_t v = 0; v < raw.vcount; ++v) {
      for (int k = 0; k < l.components; ++k) out.vertices[v * std::size_t(out.stride) + std::size_t(l.offset + k)] = d[v * std::size_t(l.components) + std::size_t(k)];
    }
  }
  out.indices = std::move(raw.indices);
  const auto& p = raw.attrs[{int(AttributeSemantic::Position), -1}].second;
  out.bounds_min = glm::vec3(std::numeric_limits<float>::max());
  out.bounds_max = glm::vec3(-std::numeric_limits<float>::max());
  for (std::size_t v = 0; v < raw.vcount; ++v) {
    glm::vec3 x(p[v * 3], p[v * 3 + 1], p[v * 3 + 2]);
    out.bounds_min = glm::min(out.bounds_min, x);
    out.bounds_max = glm::max(out.bounds_max, x);
  }
  if (raw.vcount == 0) out.bounds_min = out.bounds_max = glm::vec3(0.0f);
  return out;
}

}  // namespace meter::convert
