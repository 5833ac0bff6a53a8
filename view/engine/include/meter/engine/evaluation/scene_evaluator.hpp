// Scene evaluation: binding outputs -> pose (animation times sampled), effective node
// visibility, world matrices, camera view-projection, per-draw material parameters and deform,
// drawable texts. Pure: no GL (text metrics come through TextMeasure), testable on plain data.
//
// What is computed when:
//   apply()       only animations whose time changed are re-sampled; visibility follows the
//                 overrides; the outputs are kept for evaluate();
//   update_world  world matrices recomputed only when some node moved;
//   evaluate()    the evaluated frame for a target of the given size.
#pragma once

#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "meter/engine/evaluation/animation.hpp"
#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/evaluation/frame_state.hpp"
#include "meter/engine/vocabulary.hpp"

namespace meter::engine {

// Inked box of a text anchored at (x, baseline y), origin top-left; empty when it has no ink.
// The GL side measures with the font it draws with; tests pass fixed boxes.
class TextMeasure {
 public:
  virtual ~TextMeasure() = default;
  virtual platform::PixelRegion ink(const TextItem& text, int x, int y) = 0;
};

// The camera the view uses: the configured one, else the first camera node; -1 when none.
int find_camera_node(const Scene& scene);

// Base colour and emissive factors of a material after the bindings' overrides.
glm::vec4 effective_base_color(const Scene& scene, const BindingOutputs& outputs, int material);
glm::vec3 effective_emissive(const Scene& scene, const BindingOutputs& outputs, int material);

// Morph weights of `node` as the shader gets them: `pose_weights`, then every override of the
// node (index = target; a target past the pose's weights extends them with zeros).
std::vector<float> morph_weights(const std::vector<float>& pose_weights, const std::vector<MorphOverride>& morph, int node);

// Effective visibility of every node: hidden when an override hides it or an ancestor.
std::vector<char> effective_visibility(const Scene& scene, const std::vector<signed char>& node_visible);

class SceneEvaluator {
 public:
  // Animations nobody drives sit at config.time from the start.
  explicit SceneEvaluator(const Scene& scene);

  // Takes new binding outputs. Returns the number of animations re-sampled (their time changed).
  int apply(const BindingOutputs& outputs);
  // Recomputes the world matrices when some node moved since the last call; true when it did.
  bool update_world();

  // View-projection for a width x height target; `eye` receives the camera position.
  glm::mat4 view_projection(int width, int height, glm::vec3* eye = nullptr) const;
  // Pixel position (origin top-left) of a node's world origin under `vp`.
  glm::vec2 project(int node, const glm::mat4& vp, int width, int height) const;
  // The evaluated frame (after update_world()). `measure` sizes the drawable texts.
  FrameState evaluate(int width, int height, TextMeasure& measure) const;

  const BindingOutputs& outputs() const { return outputs_; }
  const std::vector<glm::mat4>& world() const { return world_; }
  const std::vector<char>& visible() const { return visible_; }
  int camera_node() const { return camera_node_; }
  // Animations re-sampled since construction (the start at config.time included).
  std::uint64_t animation_samples() const { return animation_samples_; }
  const std::vector<int>& light_nodes() const { return light_nodes_; }

 private:
  DrawState draw_state(std::size_t draw) const;

  const Scene& scene_;
  NodeOrder order_;
  Pose pose_;
  std::vector<double> anim_time_;
  std::vector<glm::mat4> world_;
  std::vector<char> visible_;
  BindingOutputs outputs_;
  bool world_dirty_ = true;
  std::uint64_t animation_samples_ = 0;
  int camera_node_ = -1;
  std::vector<int> light_nodes_;  // light_order(scene)
};

}  // namespace meter::engine
