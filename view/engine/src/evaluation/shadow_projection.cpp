#include "meter/engine/evaluation/shadow_projection.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace meter::engine {

namespace {
std::array<glm::vec3, 8> corners(const glm::vec3& lo, const glm::vec3& hi) {
  std::array<glm::vec3, 8> c;
  for (int k = 0; k < 8; ++k) c[static_cast<std::size_t>(k)] = {k & 1 ? hi.x : lo.x, k & 2 ? hi.y : lo.y, k & 4 ? hi.z : lo.z};
  return c;
}

bool finite(const glm::mat4& m) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

// An up vector not parallel to `dir` (unit).
glm::vec3 up_for(const glm::vec3& dir) {
  return std::abs(dir.y) < 0.99f ? glm::vec3(0.0f, 1.0f, 0.0f) : glm::vec3(1.0f, 0.0f, 0.0f);
}
}  // namespace

void WorldBounds::add(const glm::vec3& p) {
  if (!(std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))) return;
  if (empty) min = max = p, empty = false;
  min = glm::min(min, p), max = glm::max(max, p);
}

WorldBounds drawn_bounds(const Scene& scene, const FrameState& frame) {
  WorldBounds b;
  for (std::size_t i = 0; i < scene.draws.size() && i < frame.draws.size(); ++i) {
    if (!frame.draws[i].visible) continue;
    const DrawItem& d = scene.draws[i];
    const Primitive& p = scene.meshes[static_cast<std::size_t>(d.mesh)].primitives[static_cast<std::size_t>(d.primitive)];
    const glm::mat4& w = frame.world[static_cast<std::size_t>(d.node)];
    for (const glm::vec3& c : corners(p.bounds_min, p.bounds_max)) b.add(glm::vec3(w * glm::vec4(c, 1.0f)));
  }
  return b;
}

std::optional<glm::mat4> shadow_view_projection(const Light& light, const glm::mat4& light_world, const WorldBounds& bounds) {
  if (bounds.empty || light.type == LightType::Point) return std::nullopt;
  const glm::vec3 axis(light_world * glm::vec4(0.0f, 0.0f, -1.0f, 0.0f));  // lights shine down local -Z
  if (!(glm::length(axis) > 1e-6f)) return std::nullopt;
  const glm::vec3 dir = glm::normalize(axis);
  const auto box = corners(bounds.min, bounds.max);
  // A margin keeps the scene's outermost surfaces off the map's edge texels and out of its clip planes.
  const float extent = std::max(glm::length(bounds.max - bounds.min), 1e-3f);
  std::optional<glm::mat4> vp;
  if (light.type == LightType::Directional) {
    const glm::vec3 centre = (bounds.min + bounds.max) * 0.5f;
    const glm::mat4 view = glm::lookAt(centre - dir * extent, centre, up_for(dir));
    glm::vec3 lo(INFINITY), hi(-INFINITY);
    for (const glm::vec3& c : box) {
      const glm::vec3 v(view * glm::vec4(c, 1.0f));
      lo = glm::min(lo, v), hi = glm::max(hi, v);
    }
    const float pad = 0.01f * extent;
    // View space looks down -Z: the near plane is at -hi.z, the far one at -lo.z.
    vp = glm::ortho(lo.x - pad, hi.x + pad, lo.y - pad, hi.y + pad, -hi.z - pad, -lo.z + pad) * view;
  } else {
    const glm::vec3 eye(light_world[3]);
    float near_d = INFINITY, far_d = 0.0f;
    for (const glm::vec3& c : box) {
      const float d = glm::dot(c - eye, dir);
      near_d = std::min(near_d, d), far_d = std::max(far_d, d);
    }
    if (!(far_d > 0.0f)) return std::nullopt;  // the whole scene behind the light
    far_d *= 1.01f;
    // Depth precision lives near the near plane: as far out as the scene allows, never closer than
    // 1/1000 of the far plane.
    near_d = std::clamp(near_d * 0.99f, far_d * 1e-3f, far_d * 0.5f);
    // The cone plus a texel-sized margin, so the lookup's tent at the cone's edge stays inside.
    const float fov = std::min(2.0f * light.outer_cone * 1.02f, glm::radians(170.0f));
    vp = glm::perspective(fov, 1.0f, near_d, far_d) * glm::lookAt(eye, eye + dir, up_for(dir));
  }
  if (!finite(*vp)) return std::nullopt;
  return vp;
}

glm::mat4 shadow_texture_matrix(const glm::mat4& light_view_projection) {
  const glm::mat4 bias = glm::translate(glm::mat4(1.0f), glm::vec3(0.5f)) * glm::scale(glm::mat4(1.0f), glm::vec3(0.5f));
  return bias * light_view_projection;
}

}  // namespace meter::engine
