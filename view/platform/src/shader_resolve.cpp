// The MSAA resolve's shader pass (shader_resolve.hpp).
#include "shader_resolve.hpp"

#include <cstdio>
#include <string>

namespace meter::platform {
namespace {

// One triangle over the whole target (its corners past two edges); the scissor picks the region.
constexpr const char* kVertex = R"(#version 310 es
const vec2 corner[3] = vec2[3](vec2(-1.0, -1.0), vec2(3.0, -1.0), vec2(-1.0, 3.0));
void main() { gl_Position = vec4(corner[gl_VertexID], 0.0, 1.0); }
)";

// The weighted mean of the samples of the (2K + 1)^2 pixels around this one, pixels outside the
// target clamped to its edge. The weights are constants of the program, unrolled, and a sample of
// weight 0 is not fetched. An sRGB texture's samples are decoded to linear by texelFetch and the sum
// is encoded on write: the filter works in linear light.
std::string fragment_source(int reach, int samples, const std::vector<float>& weights) {
  std::string s = "#version 310 es\nprecision highp float;\nprecision highp int;\n"
                  "uniform highp sampler2DMS u_samples;\n"
                  "out vec4 o_color;\nvoid main() {\n"
                  "  ivec2 p = ivec2(gl_FragCoord.xy);\n"
                  "  ivec2 last = textureSize(u_samples) - 1;\n"
                  "  vec4 sum = vec4(0.0);\n"
                  "  ivec2 q;\n";
  const int side = 2 * reach + 1;
  for (int dy = -reach; dy <= reach; ++dy)
    for (int dx = -reach; dx <= reach; ++dx) {
      const std::size_t first = static_cast<std::size_t>(((dy + reach) * side + dx + reach) * samples);
      bool any = false;
      for (int k = 0; k < samples; ++k) any = any || weights[first + std::size_t(k)] > 0.0f;
      if (!any) continue;
      s += "  q = clamp(p + ivec2(" + std::to_string(dx) + ", " + std::to_string(dy) + "), ivec2(0), last);\n";
      for (int k = 0; k < samples; ++k) {
        const float w = weights[first + std::size_t(k)];
        if (!(w > 0.0f)) continue;
        char literal[32];
        std::snprintf(literal, sizeof literal, "%.9e", double(w));  // always a float literal in GLSL
        s += std::string("  sum += ") + literal + " * texelFetch(u_samples, q, " + std::to_string(k) + ");\n";
      }
    }
  s += "  o_color = sum;\n}\n";
  return s;
}

}  // namespace

ShaderResolve::ShaderResolve(const Gl& gl, const ResolveFilter& filter, int samples, GLuint msaa_fbo, ProgramCache* programs)
    : gl_(gl), samples_(samples), reach_(filter_reach_px(filter)), programs_(programs) {
  // The driver's own sample positions (the ones it rasterizes with), of the multisample framebuffer.
  GLint previous_draw = 0;
  gl_.GetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previous_draw);
  gl_.BindFramebuffer(GL_DRAW_FRAMEBUFFER, msaa_fbo);
  for (int s = 0; s < samples_; ++s) {
    GLfloat xy[2] = {-1.0f, -1.0f};
    gl_.GetMultisamplefv(GL_SAMPLE_POSITION, static_cast<GLuint>(s), xy);
    if (!(xy[0] >= 0.0f && xy[0] <= 1.0f && xy[1] >= 0.0f && xy[1] <= 1.0f))
      throw GlError("film filter resolve: glGetMultisamplefv(GL_SAMPLE_POSITION, " + std::to_string(s) + ") gave (" +
                    std::to_string(xy[0]) + ", " + std::to_string(xy[1]) + "), expected a position in [0, 1]^2");
    positions_.push_back({xy[0], xy[1]});
  }
  gl_.BindFramebuffer(GL_DRAW_FRAMEBUFFER, static_cast<GLuint>(previous_draw));
  check_gl(gl_, "film filter resolve: querying the " + std::to_string(samples_) + " sample positions");

  const std::string fragment = fragment_source(reach_, samples_, resolve_weights(filter, positions_));
  const std::string label = std::string("film filter resolve (") + to_string(filter.kind) + ", " +
                            std::to_string(filter.width_px) + " px, " + std::to_string(samples_) + " samples)";
  program_ = acquire_program(programs_, gl_, kVertex, fragment, label);
  try {
    samples_loc_ = gl_.GetUniformLocation(program_, "u_samples");
    gl_.GenVertexArrays(1, &vao_);
    check_gl(gl_, "film filter resolve: creating the program");
  } catch (...) {
    release();  // no destructor runs for a constructor that throws
    throw;
  }
}

ShaderResolve::~ShaderResolve() { release(); }

void ShaderResolve::release() {
  if (vao_) gl_.DeleteVertexArrays(1, &vao_);
  release_program(programs_, gl_, program_);
  vao_ = program_ = 0;
}

void ShaderResolve::run(GLuint ms_texture, GLuint dst_fbo, int width, int height, std::span<const PixelRegion> regions) const {
  GLint program = 0, vao = 0, active = 0, bound = 0;
  gl_.GetIntegerv(GL_CURRENT_PROGRAM, &program);
  gl_.GetIntegerv(GL_VERTEX_ARRAY_BINDING, &vao);
  gl_.GetIntegerv(GL_ACTIVE_TEXTURE, &active);
  gl_.ActiveTexture(GL_TEXTURE0);
  gl_.GetIntegerv(GL_TEXTURE_BINDING_2D_MULTISAMPLE, &bound);
  const GLenum caps[] = {GL_BLEND, GL_DEPTH_TEST, GL_STENCIL_TEST, GL_CULL_FACE, GL_DITHER};
  GLboolean was[std::size(caps)];
  for (std::size_t i = 0; i < std::size(caps); ++i) {
    was[i] = gl_.IsEnabled(caps[i]);
    gl_.Disable(caps[i]);
  }

  gl_.BindFramebuffer(GL_DRAW_FRAMEBUFFER, dst_fbo);
  gl_.Viewport(0, 0, width, height);
  gl_.UseProgram(program_);
  gl_.BindTexture(GL_TEXTURE_2D_MULTISAMPLE, ms_texture);
  gl_.Uniform1i(samples_loc_, 0);
  gl_.BindVertexArray(vao_);
  gl_.Enable(GL_SCISSOR_TEST);
  for (const PixelRegion& region : regions) {
    const PixelRegion inside = clip(region, width, height);  // first: keeps the growth below from overflowing
    if (inside.empty()) continue;
    const PixelRegion r = clip({inside.x - reach_, inside.y - reach_, inside.width + 2 * reach_, inside.height + 2 * reach_},
                               width, height);
    gl_.Scissor(r.x, r.y, r.width, r.height);
    gl_.DrawArrays(GL_TRIANGLES, 0, 3);
  }
  gl_.Disable(GL_SCISSOR_TEST);

  gl_.BindVertexArray(static_cast<GLuint>(vao));
  gl_.BindTexture(GL_TEXTURE_2D_MULTISAMPLE, static_cast<GLuint>(bound));
  gl_.ActiveTexture(static_cast<GLenum>(active));
  gl_.UseProgram(static_cast<GLuint>(program));
  for (std::size_t i = 0; i < std::size(caps); ++i)
    if (was[i]) gl_.Enable(caps[i]);
}

}  // namespace meter::platform
