// Where a shadow-casting light looks from: the view-projection its shadow map is drawn with, and
// the matrix a shader turns a world position into the map's texture coordinates with. Pure: no GL.
//
// A directional light's map is an orthographic box along its direction around everything the
// scene draws (so every receiver in view can be shadowed); a spot light's is a perspective frustum
// from its position, as wide as its outer cone, deep enough for the scene's far side. Both are
// square. The scene's bounds are the drawn primitives' POSITION bounds at this frame.
#pragma once

#include <optional>

#include <glm/glm.hpp>

#include "meter/engine/evaluation/frame_state.hpp"
#include "meter/engine/vocabulary.hpp"

namespace meter::engine {

struct WorldBounds {
  glm::vec3 min{0.0f}, max{0.0f};
  bool empty = true;
  void add(const glm::vec3& p);
};

// The world box around every visible draw's primitive bounds (each box's 8 corners transformed).
WorldBounds drawn_bounds(const Scene& scene, const FrameState& frame);

// World -> clip of the light's shadow map; nullopt when it has nothing to cover (empty bounds, a
// point light, the scene entirely behind a spot light) or its world matrix is degenerate.
std::optional<glm::mat4> shadow_view_projection(const Light& light, const glm::mat4& light_world, const WorldBounds& bounds);

// Clip -> the map's texture space: x, y and depth from [-1, 1] to [0, 1].
glm::mat4 shadow_texture_matrix(const glm::mat4& light_view_projection);

}  // namespace meter::engine
