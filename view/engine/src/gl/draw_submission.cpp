#include "gl/draw_submission.hpp"

#include <algorithm>
#include <cmath>

#include <glm/gtc/type_ptr.hpp>

#include "gl/shadow_maps.hpp"
#include "meter/engine/evaluation/animation.hpp"
#include "meter/engine/evaluation/skinned_normals.hpp"
#include "meter/engine/renderer.hpp"

namespace meter::engine {

using bridge::UniformSemantic;

namespace {
// Runtime switches of shadergen::generate_uber() for a draw generated with `f` (the bit layout is
// uber.cpp's). Slot 0: vertex stage, slot 1: fragment stage.
glm::ivec4 uber_switches(const bridge::MaterialFeatures& f, int slot) {
  using bridge::ShadingModel;
  int textures = 0;
  const bool tex[5] = {f.base_color_texture, f.metallic_roughness_texture, f.normal_texture, f.emissive_texture,
                       f.occlusion_texture};
  for (int k = 0; k < 5; ++k) textures |= tex[k] ? 1 << k : 0;
  if (slot == 0) return {0, 0, (f.vertex_colors ? 1 : 0) | (f.skin_joints > 0 ? 2 : 0), 0};
  const int model = f.shading == ShadingModel::Unlit ? 0 : f.shading == ShadingModel::PbrMetallicRoughness ? 2 : 1;
  const int bits = (f.double_sided ? 4 : 0) | (f.has_tangents ? 8 : 0) | (f.texture_transform ? 16 : 0);
  return {model, textures, bits, static_cast<int>(f.alpha) | static_cast<int>(f.texcoord1_slots << 4)};
}
}  // namespace

DrawSubmission::DrawSubmission(const platform::Gl& gl, const Scene& scene, const GpuScene& gpu,
                               const std::vector<int>& light_nodes)
    : gl_(gl), scene_(scene), gpu_(gpu) {
  auto type = [&](int node) {
    return static_cast<int>(scene.lights[static_cast<std::size_t>(scene.nodes[static_cast<std::size_t>(node)].light)].type);
  };
  for (std::size_t k = 0; k < light_nodes.size(); ++k)
    if (light_count_[type(light_nodes[k])]++ == 0) light_first_[type(light_nodes[k])] = static_cast<int>(k);
}

void DrawSubmission::submit(platform::RenderTarget& target, const Pass& pass, const FrameState& frame,
                            RendererStats& stats) const {
  const auto& gl = gl_;
  target.bind();
  // The scissor clips the clear and every draw below (and the text after it) to the region.
  if (pass.scissor) {
    gl.Enable(GL_SCISSOR_TEST);
    gl.Scissor(pass.scissor->x, pass.scissor->y, pass.scissor->width, pass.scissor->height);
  } else {
    gl.Disable(GL_SCISSOR_TEST);
  }
  const auto& cc = scene_.config.clear_color;
  gl.ClearColor(float(cc[0]), float(cc[1]), float(cc[2]), float(cc[3]));
  gl.ClearDepthf(1.0f);
  gl.DepthMask(GL_TRUE);
  // Over the static layer the region already holds its copy (colour and depth).
  if (pass.set != DrawSet::OverStatic) gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
  gl.Enable(GL_DEPTH_TEST);
  gl.DepthFunc(GL_LEQUAL);
  // Normal-mapped materials and mirrors shaded once per MSAA sample where the scene's
  // "sample_shading" asks: their shading varies inside a pixel, and EEVEE averages many shading
  // samples per pixel.
  const bool per_sample = scene_.config.sample_shading.any() && gl.MinSampleShading && target.samples() > 1;
  if (per_sample) gl.MinSampleShading(1.0f);
  bool sample_shading_on = false;
  std::vector<float> scratch;
  const GpuProgram* current = nullptr;
  for (int i : pass.draws) {
    if (per_sample) {
      const bool want = shades_per_sample(static_cast<std::size_t>(i), frame);
      if (want != sample_shading_on) {
        if (want) gl.Enable(GL_SAMPLE_SHADING);
        else gl.Disable(GL_SAMPLE_SHADING);
        sample_shading_on = want;
      }
    }
    draw_one(static_cast<std::size_t>(i), frame, current, scratch);
    ++stats.draw_calls;
  }
  if (sample_shading_on) gl.Disable(GL_SAMPLE_SHADING);
  gl.BindVertexArray(0);
  gl.DepthMask(GL_TRUE);
  gl.Disable(GL_BLEND);
  gl.UseProgram(0);
}

void DrawSubmission::submit_depth(const std::vector<int>& draws, const FrameState& frame, const glm::mat4& light_view_projection,
                                  RendererStats& stats) const {
  const auto& gl = gl_;
  gl.Enable(GL_DEPTH_TEST);
  gl.DepthFunc(GL_LEQUAL);
  gl.Disable(GL_BLEND);
  gl.Disable(GL_CULL_FACE);
  std::vector<float> scratch;
  const GpuProgram* current = nullptr;
  for (int i : draws) {
    draw_one(static_cast<std::size_t>(i), frame, current, scratch, &light_view_projection);
    ++stats.draw_calls;
  }
  gl.BindVertexArray(0);
  gl.UseProgram(0);
}

bool DrawSubmission::shades_per_sample(std::size_t index, const FrameState& frame) const {
  const GpuDraw* d = gpu_.draws()[index].get();
  const auto shading = std::min(static_cast<std::size_t>(frame.draws[index].shading), d->shadings.size() - 1);
  const Material& mat = scene_.materials[static_cast<std::size_t>(d->prim->material)];
  return scene_.config.sample_shading.shades_per_sample(d->shadings[shading].shape->features, mat.roughness);
}

// What one draw's uniforms read, gathered once per draw.
struct DrawSubmission::DrawValues {
  const FrameState& frame;
  const DrawState& state;
  const GpuProgram& program;
  const bridge::Program& shape;  // the program's metadata at the draw's shading level
  const Node& node;
  const Material& material;
  const glm::mat4& model;            // object -> world (identity for merged, world-space vertices)
  const glm::mat4& view_projection;  // the camera's, or the light's for a shadow map
  // A cheaper model's own material parameters (a PBR material mapped for Blinn-Phong-style models).
  glm::vec4 base;
  glm::vec3 specular;
  float shininess;
};

void DrawSubmission::draw_one(std::size_t index, const FrameState& frame, const GpuProgram*& current,
                              std::vector<float>& scratch, const glm::mat4* light_view_projection) const {
  const GpuDraw* d = gpu_.draws()[index].get();
  const DrawState& state = frame.draws[index];
  // The draw's quality level (Renderer::set_quality); the frame's levels are within range.
  const auto shading = std::min(static_cast<std::size_t>(state.shading), d->shadings.size() - 1);
  const GpuShading& sh = d->shadings[shading];
  const bool depth_only = light_view_projection != nullptr;
  const GpuProgram* gp = depth_only ? gpu_.depth_program(sh.program) : sh.program;
  if (!gp) return;
  const auto node_index = static_cast<std::size_t>(d->item->node);
  const Material& mat = scene_.materials[static_cast<std::size_t>(d->prim->material)];
  static const glm::mat4 kIdentity(1.0f);
  // Merged vertices are already in world space.
  const glm::mat4& model = d->group ? kIdentity : frame.world[node_index];
  if (gp != current) {
    gl_.UseProgram(gp->program);
    current = gp;
  }
  set_raster_state(*sh.shape, depth_only, model);
  const ShadingLevel* level = sh.level;
  const DrawValues values{frame, state, *gp, *sh.shape, scene_.nodes[node_index], mat, model,
                          depth_only ? *light_view_projection : frame.view_projection,
                          level ? glm::vec4(glm::vec3(state.base) * level->base_scale, state.base.a) : state.base,
                          level ? level->specular_color : mat.specular_color,
                          level ? level->shininess : mat.shininess};
  for (const auto& u : gp->uniforms) set_uniform(u, values, scratch);
  bind_samplers(*gp, mat);
  const GpuVertexInput& input = d->group ? d->group->inputs[shading] : sh.input;
  gl_.BindVertexArray(input.vao);
  for (const auto& [loc, v] : input.constant_attributes) gl_.VertexAttrib4f(loc, v.x, v.y, v.z, v.w);
  if (d->group) {
    gl_.DrawElements(GL_TRIANGLES, d->group->index_count, GL_UNSIGNED_INT, nullptr);
  } else {
    const auto& lists = d->lists(sh);
    const auto& [offset, count] = lists[std::min(static_cast<std::size_t>(state.lod), lists.size() - 1)];
    gl_.DrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT, reinterpret_cast<const void*>(offset));
  }
}

void DrawSubmission::set_raster_state(const bridge::Program& shape, bool depth_only, const glm::mat4& model) const {
  const auto& gl = gl_;
  // A shadow map's draw keeps submit_depth's state: no blending, both faces.
  if (!depth_only) {
    if (shape.blend) {
      gl.Enable(GL_BLEND);
      gl.BlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ONE, GL_ONE_MINUS_SRC_ALPHA);
      gl.DepthMask(GL_FALSE);
    } else {
      gl.Disable(GL_BLEND);
      gl.DepthMask(GL_TRUE);
    }
    if (shape.cull_back_faces) {
      gl.Enable(GL_CULL_FACE);
      gl.CullFace(GL_BACK);
    } else {
      gl.Disable(GL_CULL_FACE);
    }
  }
  // A mirroring transform flips the winding.
  gl.FrontFace(glm::determinant(glm::mat3(model)) < 0 ? GL_CW : GL_CCW);
}

void DrawSubmission::set_uniform(const GpuProgram::Uniform& u, const DrawValues& v, std::vector<float>& scratch) const {
  const auto& gl = gl_;
  const Material& mat = v.material;
  const GLint l = u.location;
  switch (u.semantic) {
    case UniformSemantic::ModelMatrix: gl.UniformMatrix4fv(l, 1, GL_FALSE, glm::value_ptr(v.model)); break;
    case UniformSemantic::ViewProjection: gl.UniformMatrix4fv(l, 1, GL_FALSE, glm::value_ptr(v.view_projection)); break;
    case UniformSemantic::NormalMatrix: {
      const glm::mat3 n = normal_matrix(v.model);  // finite even for a zero scale
      gl.UniformMatrix3fv(l, 1, GL_FALSE, glm::value_ptr(n));
      break;
    }
    case UniformSemantic::CameraPosition: gl.Uniform3f(l, v.frame.eye.x, v.frame.eye.y, v.frame.eye.z); break;
    case UniformSemantic::BaseColorFactor: gl.Uniform4f(l, v.base.r, v.base.g, v.base.b, v.base.a); break;
    case UniformSemantic::EmissiveFactor: gl.Uniform3f(l, v.state.emissive.r, v.state.emissive.g, v.state.emissive.b); break;
    case UniformSemantic::MetallicFactor: gl.Uniform1f(l, mat.metallic); break;
    case UniformSemantic::RoughnessFactor: gl.Uniform1f(l, mat.roughness); break;
    case UniformSemantic::NormalScale: gl.Uniform1f(l, mat.normal_scale); break;
    case UniformSemantic::OcclusionStrength: gl.Uniform1f(l, mat.occlusion_strength); break;
    case UniformSemantic::AlphaCutoff: gl.Uniform1f(l, mat.alpha_cutoff); break;
    case UniformSemantic::SpecularColor: gl.Uniform3f(l, v.specular.r, v.specular.g, v.specular.b); break;
    case UniformSemantic::Shininess: gl.Uniform1f(l, v.shininess); break;
    case UniformSemantic::AmbientLight: gl.Uniform3f(l, scene_.ambient.r, scene_.ambient.g, scene_.ambient.b); break;
    case UniformSemantic::Exposure: gl.Uniform1f(l, v.state.exposure); break;
    case UniformSemantic::EnvironmentIntensity: gl.Uniform1f(l, scene_.environment.strength); break;
    case UniformSemantic::EnvironmentIrradiance:
      if (u.index >= 0 && u.index < 6) {
        const glm::vec3& e = scene_.environment.irradiance[static_cast<std::size_t>(u.index)];
        gl.Uniform3f(l, e.r, e.g, e.b);
      }
      break;
    case UniformSemantic::LightColor:
    case UniformSemantic::LightIntensity:
    case UniformSemantic::LightPosition:
    case UniformSemantic::LightDirection:
    case UniformSemantic::LightRange:
    case UniformSemantic::LightInnerConeCos:
    case UniformSemantic::LightOuterConeCos: set_light_uniform(u, v); break;
    case UniformSemantic::LightShadowMatrix: {
      const glm::mat4 m = shadow_maps_ ? shadow_maps_->matrix(u.index) : glm::mat4(0.0f);
      gl.UniformMatrix4fv(l, 1, GL_FALSE, glm::value_ptr(m));
      break;
    }
    case UniformSemantic::JointMatrices: set_joint_matrices(u, v, scratch); break;
    case UniformSemantic::MorphWeights: {
      scratch.assign(static_cast<std::size_t>(u.array_size), 0.0f);
      const auto& w = v.state.morph_weights;
      for (std::size_t k = 0; k < w.size() && k < scratch.size(); ++k) scratch[k] = w[k];
      gl.Uniform1fv(l, u.array_size, scratch.data());
      break;
    }
    case UniformSemantic::TextureTransform:
      if (u.index >= 0 && u.index < 6) gl.UniformMatrix3fv(l, 1, GL_FALSE, glm::value_ptr(mat.uv_transform[static_cast<std::size_t>(u.index)]));
      break;
    case UniformSemantic::UberSwitches: {  // uber baseline only; never in a package
      const glm::ivec4 sw = uber_switches(v.shape.features, u.index);
      gl.Uniform4i(l, sw.x, sw.y, sw.z, sw.w);
      break;
    }
    case UniformSemantic::UberLightCounts: {
      const auto& c = v.shape.features.lights;
      gl.Uniform3i(l, std::min(c.directional, 2), std::min(c.point, 2), std::min(c.spot, 2));
      break;
    }
  }
}

void DrawSubmission::set_light_uniform(const GpuProgram::Uniform& u, const DrawValues& v) const {
  const auto& gl = gl_;
  const GLint l = u.location;
  int index = u.index;
  if (v.program.info->uber) {
    // Uber arrays: index = 2 * type + k (k-th light of that type); generated programs
    // index the type-sorted list directly.
    const int type = index / 2, k = index % 2;
    index = k < light_count_[type] ? light_first_[type] + k : -1;
  }
  if (index < 0 || static_cast<std::size_t>(index) >= v.frame.lights.size()) return;
  const auto& [ln, lw] = v.frame.lights[static_cast<std::size_t>(index)];
  const Light& li = scene_.lights[static_cast<std::size_t>(scene_.nodes[static_cast<std::size_t>(ln)].light)];
  if (u.semantic == UniformSemantic::LightColor) gl.Uniform3f(l, li.color.r, li.color.g, li.color.b);
  if (u.semantic == UniformSemantic::LightIntensity) gl.Uniform1f(l, li.intensity);
  if (u.semantic == UniformSemantic::LightRange) gl.Uniform1f(l, li.range);
  if (u.semantic == UniformSemantic::LightInnerConeCos) gl.Uniform1f(l, std::cos(li.inner_cone));
  if (u.semantic == UniformSemantic::LightOuterConeCos) gl.Uniform1f(l, std::cos(li.outer_cone));
  if (u.semantic == UniformSemantic::LightPosition) gl.Uniform3f(l, lw[3].x, lw[3].y, lw[3].z);
  if (u.semantic == UniformSemantic::LightDirection) {
    glm::vec3 dir = glm::normalize(glm::vec3(lw * glm::vec4(0.0f, 0.0f, -1.0f, 0.0f)));
    gl.Uniform3f(l, dir.x, dir.y, dir.z);
  }
}

void DrawSubmission::set_joint_matrices(const GpuProgram::Uniform& u, const DrawValues& v,
                                        std::vector<float>& scratch) const {
  if (v.node.skin < 0) return;
  const Skin& skin = scene_.skins[static_cast<std::size_t>(v.node.skin)];
  const glm::mat4 inv_model = glm::inverse(v.model);
  scratch.assign(static_cast<std::size_t>(u.array_size) * 16, 0.0f);
  for (std::size_t j = 0; j < skin.joints.size() && j < static_cast<std::size_t>(u.array_size); ++j) {
    const glm::mat4 jm = joint_matrix(skin, j, v.frame.world, inv_model);
    std::copy(glm::value_ptr(jm), glm::value_ptr(jm) + 16, scratch.begin() + static_cast<std::ptrdiff_t>(j * 16));
  }
  gl_.UniformMatrix4fv(u.location, u.array_size, GL_FALSE, scratch.data());
}

void DrawSubmission::bind_samplers(const GpuProgram& gp, const Material& mat) const {
  const auto& gl = gl_;
  for (const auto& s : gp.samplers) {
    gl.ActiveTexture(static_cast<GLenum>(GL_TEXTURE0 + s.unit));
    if (s.slot == bridge::TextureSlot::ShadowMap) {
      gl.BindTexture(GL_TEXTURE_2D, shadow_maps_ ? shadow_maps_->texture(s.index) : 0);
    } else if (s.slot == bridge::TextureSlot::Environment) {
      gl.BindTexture(GL_TEXTURE_CUBE_MAP, gpu_.environment_probe());
    } else {
      gl.BindTexture(GL_TEXTURE_2D, gpu_.texture(mat.texture[static_cast<std::size_t>(s.slot)]));
    }
    gl.Uniform1i(s.location, s.unit);
  }
}

}  // namespace meter::engine
