// Vertex data between the glTF accessors and the interleaved runtime record (private to
// meter_convert). Pure functions on plain data.
#pragma once

#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include "meter/convert/vocabulary.hpp"

namespace meter::convert {

// One primitive's attributes before interleaving.
struct RawPrimitive {
  std::map<std::pair<int, int>, std::pair<int, std::vector<float>>> attrs;  // (semantic, index) -> (components, data)
  std::vector<std::uint32_t> indices;
  std::size_t vcount = 0;
};

// glTF indices (`mode`: TRIANGLES, TRIANGLE_STRIP or TRIANGLE_FAN) as a triangle list with the
// degenerate triangles dropped; strips keep a consistent winding.
enum class TriangleMode { List, Strip, Fan };
std::vector<std::uint32_t> triangle_list(const std::vector<std::uint32_t>& src, TriangleMode mode);

// Lit shading without NORMAL: glTF says compute flat normals, which needs unshared vertices.
// Returns `raw` with one vertex per corner of `tris` and each triangle's face normal.
RawPrimitive with_flat_normals(const RawPrimitive& raw, const std::vector<std::uint32_t>& tris);

// Interleaves the attributes in map order (Position, Normal, Tangent, TexCoord0, ...; morph targets
// last) and computes the bounds of POSITION.
Primitive interleave(RawPrimitive raw, int material_index, int morph_targets);

}  // namespace meter::convert
