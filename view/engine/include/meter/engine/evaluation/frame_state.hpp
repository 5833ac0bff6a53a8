// The evaluated frame: what the scene looks like for one set of binding outputs, as plain data.
// Scene evaluation (scene_evaluator.hpp) fills it, the frame plan compares two of them (what
// changed, hence what to redraw) and the GL execution draws from it. No GL types.
#pragma once

#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/platform/render_target.hpp"

namespace meter::engine {

// What one draw looks like: a change between two frames means its old and new screen boxes are
// damaged. `deform` holds joint world matrices and morph weights (with their overrides): geometry
// that leaves the primitive's bounds.
struct DrawState {
  bool visible = false;
  glm::mat4 world{0.0f};
  glm::vec4 base{0.0f};      // base colour factor (binding override or the material's)
  glm::vec3 emissive{0.0f};  // emissive factor (binding override or the material's)
  float exposure = 1.0f;     // 2^stops the shader scales by (the config's, or the brightness's)
  std::vector<float> deform;
  // Morph target weights as the shader gets them: the pose's, then the morph bindings' overrides
  // (index = target). Empty for a primitive without morph targets. A function of `deform`.
  std::vector<float> morph_weights;
  // The quality level it is drawn at (Renderer::set_quality): index into its DrawLevels' shadings
  // (0 = its own program) and its primitive's LOD (0 = Primitive::indices, k = Primitive::lods[k-1]).
  int shading = 0, lod = 0;
  bool operator==(const DrawState&) const = default;
};

// A drawable text (its node effectively visible, non-empty) with its anchor and inked box.
struct TextState {
  TextItem item;
  int x = 0, y = 0;           // anchor in pixels, origin top-left (baseline for y)
  platform::PixelRegion box;  // inked pixels, padded, GL window coordinates (origin bottom-left)
  // Two texts look the same when their item and inked box are (the anchor is in the box).
  bool operator==(const TextState& o) const { return item == o.item && box == o.box; }
};

struct FrameState {
  glm::mat4 view_projection{1.0f};
  glm::vec3 eye{0.0f};                          // camera position (world)
  std::vector<glm::mat4> world;                 // per node
  std::vector<char> visible;                    // per node, effective (a hidden node hides its subtree)
  std::vector<DrawState> draws;                 // per Scene::draws entry
  std::vector<std::pair<int, glm::mat4>> lights;  // light node and its world matrix, in light_order
  std::vector<TextState> texts;                 // drawable texts, in binding order
};

}  // namespace meter::engine
