// Submits one pass of the frame plan: binds the target, sets the scissor, clears (unless the pass
// draws over a copy of the static layer) and issues the pass's draws with their uniforms (matrices,
// material parameters, lights, joints, morph weights) from the evaluated frame.
#pragma once

#include <vector>

#include "gl/gpu_scene.hpp"
#include "meter/engine/evaluation/frame_state.hpp"
#include "meter/engine/frame_plan/frame_plan.hpp"
#include "meter/platform/render_target.hpp"

namespace meter::engine {

struct RendererStats;
class ShadowMaps;

class DrawSubmission {
 public:
  // `light_nodes`: the scene's light_order (the index light uniforms use).
  DrawSubmission(const platform::Gl& gl, const Scene& scene, const GpuScene& gpu, const std::vector<int>& light_nodes);

  void submit(platform::RenderTarget& target, const Pass& pass, const FrameState& frame, RendererStats& stats) const;
  // Draws `draws` into the bound depth target as the light sees them (`light_view_projection`),
  // each with its depth-only program, both faces (EEVEE's shadow maps ignore back-face culling).
  void submit_depth(const std::vector<int>& draws, const FrameState& frame, const glm::mat4& light_view_projection,
                    RendererStats& stats) const;
  // The shadow maps the lit programs sample (none: the scene has no shadow-casting light).
  void use_shadow_maps(const ShadowMaps* maps) { shadow_maps_ = maps; }

 private:
  // `light_view_projection` set: the depth-only draw of a shadow map.
  void draw_one(std::size_t index, const FrameState& frame, const GpuProgram*& current, std::vector<float>& scratch,
                const glm::mat4* light_view_projection = nullptr) const;
  // The stages of one draw: its blend, cull and winding state, each uniform (the lights' and the
  // joints' apart), the textures, then the draw call.
  struct DrawValues;
  void set_raster_state(const bridge::Program& shape, bool depth_only, const glm::mat4& model) const;
  void set_uniform(const GpuProgram::Uniform& u, const DrawValues& v, std::vector<float>& scratch) const;
  void set_light_uniform(const GpuProgram::Uniform& u, const DrawValues& v) const;
  void set_joint_matrices(const GpuProgram::Uniform& u, const DrawValues& v, std::vector<float>& scratch) const;
  void bind_samplers(const GpuProgram& gp, const Material& mat) const;
  // Whether the draw's program at its current shading level samples a normal map.
  bool shades_per_sample(std::size_t index, const FrameState& frame) const;

  const platform::Gl& gl_;
  const Scene& scene_;
  const GpuScene& gpu_;
  const ShadowMaps* shadow_maps_ = nullptr;
  // First index and count of each light type (directional, point, spot) in light_order.
  int light_first_[3] = {0, 0, 0}, light_count_[3] = {0, 0, 0};
};

}  // namespace meter::engine
