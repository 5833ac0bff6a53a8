// The film filter's resolve pass (film_resolve.hpp).
#include "film_resolve.hpp"

#include <string>

namespace meter::platform {
namespace {

// One triangle over the whole target (its corners past two edges); the scissor picks the region.
constexpr const char* kVertex = R"(#version 310 es
const vec2 corner[3] = vec2[3](vec2(-1.0, -1.0), vec2(3.0, -1.0), vec2(-1.0, 3.0));
void main() { gl_Position = vec4(corner[gl_VertexID], 0.0, 1.0); }
)";

// The weighted mean of every sample of the (2K + 1)^2 pixels around this one, pixels outside the
// target clamped to its edge. An sRGB texture's samples are decoded to linear by texelFetch and the
// sum is encoded on write: the filter works in linear light.
std::string fragment_source(int reach, int samples) {
  const int vectors = (samples + 3) / 4;
  const int side = 2 * reach + 1;
  std::string s = "#version 310 es\nprecision highp float;\nprecision highp int;\n"
                  "uniform highp sampler2DMS u_samples;\n";
  s += "uniform vec4 u_weights[" + std::to_string(side * side * vectors) + "];\n";
  s += "out vec4 o_color;\nvoid main() {\n"
       "  ivec2 p = ivec2(gl_FragCoord.xy);\n"
       "  ivec2 last = textureSize(u_samples) - 1;\n"
       "  vec4 sum = vec4(0.0);\n"
       "  int i = 0;\n";
  s += "  for (int dy = -" + std::to_string(reach) + "; dy <= " + std::to_string(reach) + "; ++dy) {\n";
  s += "    for (int dx = -" + std::to_string(reach) + "; dx <= " + std::to_string(reach) + "; ++dx) {\n";
  s += "      ivec2 q = clamp(p + ivec2(dx, dy), ivec2(0), last);\n";
  static const char* lane[4] = {"x", "y", "z", "w"};
  for (int k = 0; k < samples; ++k)
    s += "      sum += u_weights[i + " + std::to_string(k / 4) + "]." + lane[k % 4] + " * texelFetch(u_samples, q, " +
         std::to_string(k) + ");\n";
  s += "      i += " + std::to_string(vectors) + ";\n    }\n  }\n  o_color = sum;\n}\n";
  return s;
}

}  // namespace

FilmResolve::FilmResolve(const Gl& gl, const ResolveFilter& filter, int samples, GLuint msaa_fbo)
    : gl_(gl), samples_(samples), reach_(filter_reach_px(filter)) {
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

  const std::vector<float> w = resolve_weights(filter, positions_);
  const int vectors = (samples_ + 3) / 4, side = 2 * reach_ + 1;
  weights_.assign(static_cast<std::size_t>(side * side * vectors * 4), 0.0f);
  for (int p = 0; p < side * side; ++p)
    for (int s = 0; s < samples_; ++s)
      weights_[static_cast<std::size_t>((p * vectors + s / 4) * 4 + s % 4)] = w[static_cast<std::size_t>(p * samples_ + s)];

  program_ = compile_program(gl_, kVertex, fragment_source(reach_, samples_),
                             std::string("film filter resolve (") + to_string(filter.kind) + ", " +
                                 std::to_string(filter.width_px) + " px, " + std::to_string(samples_) + " samples)");
  samples_loc_ = gl_.GetUniformLocation(program_, "u_samples");
  weights_loc_ = gl_.GetUniformLocation(program_, "u_weights");
  gl_.GenVertexArrays(1, &vao_);
  check_gl(gl_, "film filter resolve: creating the program");
}

FilmResolve::~FilmResolve() {
  if (vao_) gl_.DeleteVertexArrays(1, &vao_);
  if (program_) gl_.DeleteProgram(program_);
}

void FilmResolve::run(GLuint ms_texture, GLuint dst_fbo, int width, int height, std::span<const PixelRegion> regions) const {
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
  gl_.Uniform4fv(weights_loc_, static_cast<GLsizei>(weights_.size() / 4), weights_.data());
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
