// The shadow maps of the lights that cast shadows in the scene (Light::cast_shadow: directional
// and spot lights, at most kMaxShadowMaps, the first in light order, as the converter gave their
// programs a lookup): one square depth texture each, drawn from the light by every visible opaque
// draw with its depth-only program. A map is drawn again only when its light, the scene's bounds
// or a caster's geometry changed: a scene whose casters never move draws each map once.
// A scene with no such light has no maps, no textures and no pass.
#pragma once

#include <functional>
#include <vector>

#include <glm/glm.hpp>

#include "meter/engine/evaluation/frame_state.hpp"
#include "meter/engine/evaluation/shadow_projection.hpp"
#include "meter/engine/vocabulary.hpp"
#include "meter/platform/gl_api.hpp"

namespace meter::engine {

class DrawSubmission;
struct RendererStats;

class ShadowMaps {
 public:
  // Texels per side. 1024 came closest to EEVEE on the shadow scene, and is cheaper than 2048
  // (docs/engine.md, "Shadows": 512 / 1024 / 2048 measured side by side).
  static constexpr int kSize = 1024;

  // `light_nodes`: the scene's light_order (the list index a program's shadow lookups name).
  ShadowMaps(const platform::Gl& gl, const Scene& scene, const std::vector<int>& light_nodes);
  ~ShadowMaps();
  ShadowMaps(const ShadowMaps&) = delete;
  ShadowMaps& operator=(const ShadowMaps&) = delete;

  bool empty() const { return maps_.empty(); }
  // Brings every map to `frame`. `casters` lists the draws that cast (visible, not blended, in any
  // order); it is called only when a map is drawn.
  void update(const FrameState& frame, const std::function<std::vector<int>()>& casters, const DrawSubmission& submission,
              RendererStats& stats);

  // The map of light `light` (its light_order index) and the world -> map texture-space matrix; a
  // light without a map, or with nothing to cover, gets texture 0 and the zero matrix (the shader
  // then finds the point outside the map: lit).
  GLuint texture(int light) const;
  const glm::mat4& matrix(int light) const;

 private:
  struct Map {
    int light = -1;  // light_order index
    GLuint texture = 0, framebuffer = 0;
    glm::mat4 view_projection{0.0f}, matrix{0.0f};
    bool drawn = false;
  };
  const platform::Gl& gl_;
  const Scene& scene_;
  std::vector<int> light_nodes_;
  std::vector<Map> maps_;
  std::vector<DrawState> drawn_draws_;  // the draws the maps were last drawn from
  WorldBounds bounds_;                  // their drawn bounds
};

}  // namespace meter::engine
