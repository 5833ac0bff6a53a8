// Flat lists: each face's provoking vertex carries the face normal (meter/convert/flat_geometry.hpp).
#include "meter/convert/flat_geometry.hpp"

#include <algorithm>
#include <unordered_map>

namespace meter::convert {

namespace {

// The face normal of (a, b, c), on the side its corners' normals point to; zero when degenerate.
glm::vec3 face_normal(std::span<const glm::vec3> pos, std::span<const glm::vec3> nrm, std::uint32_t a, std::uint32_t b,
                      std::uint32_t c) {
  const glm::vec3 n = glm::cross(pos[b] - pos[a], pos[c] - pos[a]);
  const float len = glm::length(n);
  if (!(len > 1e-12f)) return glm::vec3(0.0f);
  const glm::vec3 u = n / len;
  return glm::dot(u, nrm[a] + nrm[b] + nrm[c]) < 0.0f ? -u : u;
}

}  // namespace

FlatFaces flat_faces(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                     const std::vector<std::span<const std::uint32_t>>& lists) {
  FlatFaces out;
  const auto base = static_cast<std::uint32_t>(positions.size());
  std::unordered_map<std::uint32_t, std::vector<std::uint32_t>> copies;  // vertex -> its copies (indices)
  auto normal_of = [&](std::uint32_t v) { return v < base ? normals[v] : out.copy_normals[v - base]; };
  for (const auto& list : lists) {
    std::vector<std::uint32_t> flat(list.begin(), list.end());
    for (std::size_t t = 0; t + 2 < flat.size(); t += 3) {
      std::uint32_t* tri = &flat[t];
      const glm::vec3 n = face_normal(positions, normals, tri[0], tri[1], tri[2]);
      if (n == glm::vec3(0.0f)) continue;
      // The corner (or a copy of one) whose normal is closest to the face's.
      int corner = -1;
      std::uint32_t vertex = 0;
      float best = kFlatNormalCos;
      for (int k = 0; k < 3; ++k) {
        auto consider = [&](std::uint32_t v) {
          const float d = glm::dot(normal_of(v), n);
          if (d >= best) best = d, corner = k, vertex = v;
        };
        consider(tri[k]);
        if (const auto it = copies.find(tri[k]); it != copies.end())
          for (std::uint32_t c : it->second) consider(c);
      }
      if (corner < 0) {
        corner = 2;
        vertex = base + static_cast<std::uint32_t>(out.copied_from.size());
        out.copied_from.push_back(tri[2]);
        out.copy_normals.push_back(n);
        copies[tri[2]].push_back(vertex);
      }
      tri[corner] = vertex;
      // Rotate (winding kept) so the chosen vertex is the last, provoking one.
      std::rotate(tri, tri + (corner + 1) % 3, tri + 3);
    }
    out.lists.push_back(std::move(flat));
  }
  return out;
}

std::uint32_t prepare_flat_geometry(Primitive& prim) {
  auto find = [&](AttributeSemantic s) {
    return std::find_if(prim.layout.begin(), prim.layout.end(), [&](const VertexAttribute& a) { return a.semantic == s; });
  };
  const auto pos = find(AttributeSemantic::Position), nrm = find(AttributeSemantic::Normal);
  if (pos == prim.layout.end() || nrm == prim.layout.end() || pos->components < 3 || nrm->components < 3 ||
      find(AttributeSemantic::Joints0) != prim.layout.end())
    return 0;
  std::vector<std::span<const std::uint32_t>> lists;
  std::vector<std::vector<std::uint32_t>*> targets;
  if (prim.flat_indices.empty()) lists.emplace_back(prim.indices), targets.push_back(&prim.flat_indices);
  for (LodLevel& l : prim.lods)
    if (l.flat_indices.empty()) lists.emplace_back(l.indices), targets.push_back(&l.flat_indices);
  if (lists.empty()) return 0;
  const auto stride = static_cast<std::size_t>(prim.stride);
  std::vector<glm::vec3> positions(prim.vertex_count), normals(prim.vertex_count);
  for (std::size_t v = 0; v < prim.vertex_count; ++v) {
    const float* r = prim.vertices.data() + v * stride;
    positions[v] = glm::vec3(r[pos->offset], r[pos->offset + 1], r[pos->offset + 2]);
    const glm::vec3 n(r[nrm->offset], r[nrm->offset + 1], r[nrm->offset + 2]);
    normals[v] = glm::length(n) > 0.0f ? glm::normalize(n) : n;  // as the vertex shader normalizes it
  }
  FlatFaces f = flat_faces(positions, normals, lists);
  for (std::size_t k = 0; k < targets.size(); ++k) *targets[k] = std::move(f.lists[k]);
  prim.vertices.reserve(prim.vertices.size() + f.copied_from.size() * stride);
  for (std::size_t c = 0; c < f.copied_from.size(); ++c) {
    const std::size_t from = std::size_t(f.copied_from[c]) * stride;
    for (std::size_t i = 0; i < stride; ++i) prim.vertices.push_back(prim.vertices[from + i]);
    float* r = prim.vertices.data() + prim.vertices.size() - stride;
    r[nrm->offset] = f.copy_normals[c].x, r[nrm->offset + 1] = f.copy_normals[c].y, r[nrm->offset + 2] = f.copy_normals[c].z;
  }
  const auto added = static_cast<std::uint32_t>(f.copied_from.size());
  prim.vertex_count += added;
  return added;
}

FlatGeometryReport prepare_flat_draws(Scene& s) {
  std::vector<std::vector<char>> flat(s.meshes.size());
  for (std::size_t m = 0; m < s.meshes.size(); ++m) flat[m].assign(s.meshes[m].primitives.size(), 0);
  auto is_flat = [&](int program) {
    return s.programs[static_cast<std::size_t>(program)].program.features.shading == ShadingModel::Flat;
  };
  for (std::size_t i = 0; i < s.draws.size(); ++i) {
    const DrawItem& d = s.draws[i];
    bool any = is_flat(d.program);
    if (i < s.draw_levels.size())
      for (const auto& l : s.draw_levels[i].shadings) any = any || is_flat(l.program);
    if (any) flat[static_cast<std::size_t>(d.mesh)][static_cast<std::size_t>(d.primitive)] = 1;
  }
  FlatGeometryReport r;
  for (std::size_t m = 0; m < s.meshes.size(); ++m)
    for (std::size_t p = 0; p < s.meshes[m].primitives.size(); ++p) {
      if (!flat[m][p]) continue;
      Primitive& prim = s.meshes[m].primitives[p];
      const std::uint32_t before = prim.vertex_count;
      r.added += prepare_flat_geometry(prim);
      if (!prim.flat_indices.empty()) ++r.primitives, r.vertices += before;
    }
  return r;
}

}  // namespace meter::convert
