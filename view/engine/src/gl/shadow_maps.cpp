#include "gl/shadow_maps.hpp"

#include <optional>

#include "gl/draw_submission.hpp"
#include "meter/engine/evaluation/shadow_projection.hpp"
#include "meter/engine/renderer.hpp"

namespace meter::engine {

namespace {
// Only what moves a shadow: visibility, place and shape (a colour change leaves the maps alone).
bool same_geometry(const DrawState& a, const DrawState& b) {
  return a.visible == b.visible && a.world == b.world && a.deform == b.deform && a.morph_weights == b.morph_weights &&
         a.lod == b.lod;
}
bool same_casters(const std::vector<DrawState>& a, const std::vector<DrawState>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!same_geometry(a[i], b[i])) return false;
  return true;
}
}  // namespace

ShadowMaps::ShadowMaps(const platform::Gl& gl, const Scene& scene, const std::vector<int>& light_nodes)
    : gl_(gl), scene_(scene), light_nodes_(light_nodes) {
  const unsigned mask = shadow_map_lights(scene, light_nodes);
  for (std::size_t g = 0; g < light_nodes.size() && g < 32; ++g) {
    if (!(mask >> g & 1u)) continue;
    const Light& l = scene.lights[static_cast<std::size_t>(scene.nodes[static_cast<std::size_t>(light_nodes[g])].light)];
    Map m;
    m.light = static_cast<int>(g);
    gl.GenTextures(1, &m.texture);
    gl.BindTexture(GL_TEXTURE_2D, m.texture);
    gl.TexStorage2D(GL_TEXTURE_2D, 1, GL_DEPTH_COMPONENT24, kSize, kSize);
    // Depth comparison in the sampler; LINEAR filtering makes each lookup a bilinear blend of
    // four compared texels (GLES 3.0, 8.17).
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_MODE, GL_COMPARE_REF_TO_TEXTURE);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_COMPARE_FUNC, GL_LEQUAL);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    gl.TexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    gl.GenFramebuffers(1, &m.framebuffer);
    gl.BindFramebuffer(GL_FRAMEBUFFER, m.framebuffer);
    gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, m.texture, 0);
    const GLenum none = GL_NONE;
    gl.DrawBuffers(1, &none);
    gl.ReadBuffer(GL_NONE);
    if (gl.CheckFramebufferStatus(GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw platform::GlError(scene.source_name + ": the shadow map of light \"" + l.name + "\" is not a complete framebuffer");
    maps_.push_back(m);
  }
  gl.BindFramebuffer(GL_FRAMEBUFFER, 0);
  platform::check_gl(gl, scene.source_name + ": creating shadow maps");
}

ShadowMaps::~ShadowMaps() {
  for (auto& m : maps_) {
    gl_.DeleteFramebuffers(1, &m.framebuffer);
    gl_.DeleteTextures(1, &m.texture);
  }
}

void ShadowMaps::update(const FrameState& frame, const std::function<std::vector<int>()>& casters,
                        const DrawSubmission& submission, RendererStats& stats) {
  if (maps_.empty()) return;
  // The bounds (and the caster list) follow the draws; a frame whose draws kept their geometry
  // costs one comparison here, however the colours changed.
  const bool casters_moved = !same_casters(frame.draws, drawn_draws_);
  if (casters_moved) {
    drawn_draws_ = frame.draws;
    bounds_ = drawn_bounds(scene_, frame);
  }
  std::optional<std::vector<int>> drawn;  // the casters, listed at the first map drawn
  for (Map& m : maps_) {
    const auto& [node, world] = frame.lights[static_cast<std::size_t>(m.light)];
    const Light& light = scene_.lights[static_cast<std::size_t>(scene_.nodes[static_cast<std::size_t>(node)].light)];
    const auto vp = shadow_view_projection(light, world, bounds_);
    const glm::mat4 view_projection = vp ? *vp : glm::mat4(0.0f);
    if (m.drawn && !casters_moved && view_projection == m.view_projection) continue;
    m.view_projection = view_projection;
    m.matrix = vp ? shadow_texture_matrix(*vp) : glm::mat4(0.0f);
    m.drawn = true;
    if (!vp) continue;
    gl_.BindFramebuffer(GL_FRAMEBUFFER, m.framebuffer);
    gl_.Viewport(0, 0, kSize, kSize);
    gl_.Disable(GL_SCISSOR_TEST);
    gl_.DepthMask(GL_TRUE);
    gl_.ClearDepthf(1.0f);
    gl_.Clear(GL_DEPTH_BUFFER_BIT);
    // Slope-scaled bias: a lit surface must not shadow itself where its depth varies across a texel.
    gl_.Enable(GL_POLYGON_OFFSET_FILL);
    gl_.PolygonOffset(2.0f, 4.0f);
    if (!drawn) drawn = casters();
    submission.submit_depth(*drawn, frame, *vp, stats);
    gl_.Disable(GL_POLYGON_OFFSET_FILL);
    ++stats.shadow_map_draws;
  }
  platform::check_gl(gl_, scene_.source_name + ": drawing shadow maps");
}

GLuint ShadowMaps::texture(int light) const {
  for (const auto& m : maps_)
    if (m.light == light) return m.texture;
  return 0;
}

const glm::mat4& ShadowMaps::matrix(int light) const {
  static const glm::mat4 kNone(0.0f);
  for (const auto& m : maps_)
    if (m.light == light) return m.matrix;
  return kNone;
}

}  // namespace meter::engine
