// Skinned normals recomputed from the deformed surface (skinned_normals.hpp).
#include "meter/engine/evaluation/skinned_normals.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <map>

namespace meter::engine {
namespace {

int offset_of(const Primitive& prim, bridge::AttributeSemantic semantic, int components) {
  for (const auto& a : prim.layout)
    if (a.semantic == semantic && a.components >= components) return a.offset;
  return -1;
}

glm::vec3 read3(const float* v) { return {v[0], v[1], v[2]}; }
void write3(const glm::vec3& n, float* v) { v[0] = n.x, v[1] = n.y, v[2] = n.z; }

// The interior angle of a triangle at corner a (0 for a degenerate corner).
float corner_angle(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) {
  const glm::vec3 u = b - a, w = c - a;
  const float lu = glm::length(u), lw = glm::length(w);
  if (!(lu > 0.0f && lw > 0.0f)) return 0.0f;
  return std::acos(std::clamp(glm::dot(u, w) / (lu * lw), -1.0f, 1.0f));
}

}  // namespace

bool has_skinned_normals(const Primitive& prim) {
  using S = bridge::AttributeSemantic;
  return prim.morph_targets == 0 && prim.stride > 0 && offset_of(prim, S::Position, 3) >= 0 &&
         offset_of(prim, S::Normal, 3) >= 0 && offset_of(prim, S::Joints0, 4) >= 0 && offset_of(prim, S::Weights0, 4) >= 0;
}

SkinnedNormalsLayout skinned_normals_layout(const Primitive& prim) {
  using S = bridge::AttributeSemantic;
  SkinnedNormalsLayout out;
  out.position = offset_of(prim, S::Position, 3);
  out.normal = offset_of(prim, S::Normal, 3);
  out.joints = offset_of(prim, S::Joints0, 4);
  out.weights = offset_of(prim, S::Weights0, 4);
  // One surface point per distinct (rest position, rest normal), compared bit for bit: a seam's
  // copies were written from the same values; a hard edge's copies differ in their normal and stay
  // apart, each side with its own faces.
  std::map<std::array<std::uint32_t, 6>, std::uint32_t> points;
  out.point.resize(prim.vertex_count);
  const auto stride = static_cast<std::size_t>(prim.stride);
  for (std::size_t v = 0; v < prim.vertex_count; ++v) {
    std::array<std::uint32_t, 6> key{};
    std::memcpy(key.data(), prim.vertices.data() + v * stride + std::size_t(out.position), 3 * sizeof(float));
    std::memcpy(key.data() + 3, prim.vertices.data() + v * stride + std::size_t(out.normal), 3 * sizeof(float));
    out.point[v] = points.try_emplace(key, static_cast<std::uint32_t>(points.size())).first->second;
  }
  out.points = static_cast<std::uint32_t>(points.size());
  return out;
}

glm::mat4 joint_matrix(const Skin& skin, std::size_t j, std::span<const glm::mat4> world, const glm::mat4& inverse_model) {
  const auto node = static_cast<std::size_t>(skin.joints[j]);
  const glm::mat4 bind = j < skin.inverse_bind.size() ? skin.inverse_bind[j] : glm::mat4(1.0f);
  return node < world.size() ? inverse_model * world[node] * bind : glm::mat4(1.0f);
}

std::vector<glm::mat4> joint_matrices(const Skin& skin, std::span<const glm::mat4> world, const glm::mat4& model) {
  const glm::mat4 inv_model = glm::inverse(model);
  std::vector<glm::mat4> out;
  out.reserve(skin.joints.size());
  for (std::size_t j = 0; j < skin.joints.size(); ++j) out.push_back(joint_matrix(skin, j, world, inv_model));
  return out;
}

std::size_t skin_normals(const Primitive& prim, const SkinnedNormalsLayout& layout, std::span<const glm::mat4> joints,
                         std::span<float> vertices) {
  const auto stride = static_cast<std::size_t>(prim.stride);
  const std::size_t n = prim.vertex_count;
  // The blended matrix and deformed position of every vertex, as the vertex shader computes them
  // (joint indices clamped to the array, as there).
  std::vector<glm::mat4> blended(n);
  std::vector<glm::vec3> deformed(n);
  const int last = static_cast<int>(joints.size()) - 1;
  for (std::size_t v = 0; v < n; ++v) {
    const float* rec = prim.vertices.data() + v * stride;
    glm::mat4 s(0.0f);
    for (int k = 0; k < 4 && last >= 0; ++k) {
      const float jf = rec[layout.joints + k];
      const int j = std::isfinite(jf) ? std::clamp(static_cast<int>(jf), 0, last) : 0;
      s += rec[layout.weights + k] * joints[static_cast<std::size_t>(j)];
    }
    blended[v] = s;
    deformed[v] = glm::vec3(s * glm::vec4(read3(rec + layout.position), 1.0f));
  }
  // Each face's unit normal, weighted by its angle at the corner, summed per surface point.
  std::vector<glm::vec3> sum(layout.points, glm::vec3(0.0f));
  for (std::size_t t = 0; t + 2 < prim.indices.size(); t += 3) {
    const std::uint32_t i[3] = {prim.indices[t], prim.indices[t + 1], prim.indices[t + 2]};
    if (i[0] >= n || i[1] >= n || i[2] >= n) continue;
    const glm::vec3 &a = deformed[i[0]], &b = deformed[i[1]], &c = deformed[i[2]];
    const glm::vec3 face = glm::cross(b - a, c - a);
    const float len = glm::length(face);
    if (!(len > 0.0f) || !std::isfinite(len)) continue;
    const glm::vec3 unit = face / len;
    sum[layout.point[i[0]]] += corner_angle(a, b, c) * unit;
    sum[layout.point[i[1]]] += corner_angle(b, c, a) * unit;
    sum[layout.point[i[2]]] += corner_angle(c, a, b) * unit;
  }
  std::size_t kept = 0;
  for (std::size_t v = 0; v < n; ++v) {
    float* out = vertices.data() + v * stride + std::size_t(layout.normal);
    const glm::vec3 rest = read3(prim.vertices.data() + v * stride + std::size_t(layout.normal));
    const glm::mat3 m(blended[v]);
    const float det = glm::determinant(m);
    glm::vec3 target = sum[layout.point[v]];
    const float len = glm::length(target);
    if (!(len > 0.0f) || !std::isfinite(len) || !(std::abs(det) > 1e-12f) || !std::isfinite(det)) {
      write3(rest, out);
      ++kept;
      continue;
    }
    target /= len;
    // The winding decides the face normals' side; the rest normal, carried as LBS carries it, says
    // which side is out (a mirroring joint flips the winding, not the surface).
    if (glm::dot(target, m * rest) < 0.0f) target = -target;
    glm::vec3 carried = glm::inverse(m) * target;
    const float cl = glm::length(carried);
    if (!(cl > 0.0f) || !std::isfinite(cl)) {
      write3(rest, out);
      ++kept;
      continue;
    }
    carried /= cl;
    write3(carried, out);
  }
  return kept;
}

}  // namespace meter::engine
