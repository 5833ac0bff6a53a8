#include "meter/platform/frame_blit.hpp"

namespace meter::platform {
namespace {

// One triangle covering the viewport.
constexpr const char* kVertex = R"(#version 300 es
void main() {
  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
)";

// texelFetch: one texel per window pixel, no filtering. The decoded linear value of an 8-bit sRGB
// texel encodes back to the same 8-bit value (the IEC 61966-2-1 curve in float is far inside half
// a step of 1/255), so the copy is exact.
constexpr const char* kFragment = R"(#version 300 es
precision highp float;
precision highp int;
uniform highp sampler2D frame;
uniform ivec2 origin;
uniform int encode_srgb;
out vec4 color;
vec3 to_srgb(vec3 c) {
  c = clamp(c, 0.0, 1.0);
  return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}
void main() {
  vec4 c = texelFetch(frame, ivec2(gl_FragCoord.xy) - origin, 0);
  color = vec4(encode_srgb != 0 ? to_srgb(c.rgb) : c.rgb, 1.0);
}
)";

}  // namespace

FrameBlit::FrameBlit(const Gl& gl) : gl_(gl) {
  program_ = compile_program(gl_, kVertex, kFragment, "the frame copy to a window");
  origin_loc_ = gl_.GetUniformLocation(program_, "origin");
  encode_loc_ = gl_.GetUniformLocation(program_, "encode_srgb");
  frame_loc_ = gl_.GetUniformLocation(program_, "frame");
  gl_.GenVertexArrays(1, &vao_);
  check_gl(gl_, "creating the frame copy to a window");
}

FrameBlit::~FrameBlit() {
  gl_.DeleteVertexArrays(1, &vao_);
  gl_.DeleteProgram(program_);
}

void FrameBlit::draw(const RenderTarget& frame, int x, int y, int framebuffer_height,
                     std::span<const PixelRegion> only) {
  const int gl_y = framebuffer_height - y - frame.height();
  gl_.BindFramebuffer(GL_FRAMEBUFFER, 0);
  gl_.Viewport(x, gl_y, frame.width(), frame.height());
  gl_.Disable(GL_SCISSOR_TEST);
  gl_.Disable(GL_DEPTH_TEST);
  gl_.Disable(GL_BLEND);
  gl_.Disable(GL_CULL_FACE);
  gl_.Disable(GL_STENCIL_TEST);
  gl_.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  gl_.UseProgram(program_);
  gl_.ActiveTexture(GL_TEXTURE0);
  gl_.BindTexture(GL_TEXTURE_2D, frame.color_texture());
  gl_.BindSampler(0, 0);
  gl_.Uniform1i(frame_loc_, 0);
  gl_.Uniform2i(origin_loc_, x, gl_y);
  gl_.Uniform1i(encode_loc_, frame.srgb() ? 1 : 0);
  gl_.BindVertexArray(vao_);
  if (only.empty()) gl_.DrawArrays(GL_TRIANGLES, 0, 3);
  for (const PixelRegion& r : only) {
    gl_.Enable(GL_SCISSOR_TEST);
    gl_.Scissor(r.x, r.y, r.width, r.height);
    gl_.DrawArrays(GL_TRIANGLES, 0, 3);
  }
  gl_.Disable(GL_SCISSOR_TEST);
  gl_.BindVertexArray(0);
  gl_.UseProgram(0);
  check_gl(gl_, "copying the frame into the window");
}

}  // namespace meter::platform
