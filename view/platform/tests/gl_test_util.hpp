// Shared helpers for the GL tests: both backends as a test parameter and a tiny coloured-triangle
// program in GLSL ES 3.00 (the dialect the engine's generated shaders use on both backends).
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include "meter/platform/backend.hpp"
#include "meter/platform/gl_api.hpp"
#include "meter/platform/render_target.hpp"

namespace meter::platform {
// Readable test parameters in gtest output ("egl" instead of "4-byte object <00-00 00-00>").
inline void PrintTo(BackendKind kind, std::ostream* os) { *os << to_string(kind); }
}  // namespace meter::platform

namespace meter::platform::test {

inline std::string backend_param_name(const ::testing::TestParamInfo<BackendKind>& info) {
  return std::string(to_string(info.param));
}

// A GL test run once per backend (INSTANTIATE_TEST_SUITE_P with both kinds and backend_param_name).
class GlBackendTest : public ::testing::TestWithParam<BackendKind> {
 protected:
  void SetUp() override { backend_ = create_backend(GetParam()); }
  const Gl& gl() const { return backend_->gl(); }
  std::unique_ptr<GpuBackend> backend_;
};

// Draws triangles given as x, y (NDC) + r, g, b, a (written straight to the fragment output).
class ColorProgram {
 public:
  explicit ColorProgram(const Gl& gl) : gl_(gl) {
    program_ = compile_program(gl, R"(#version 300 es
layout(location = 0) in vec2 a_pos;
layout(location = 1) in vec4 a_color;
out vec4 v_color;
void main() { v_color = a_color; gl_Position = vec4(a_pos, 0.0, 1.0); }
)",
                               R"(#version 300 es
precision highp float;
in vec4 v_color;
out vec4 o_color;
void main() { o_color = v_color; }
)",
                               "test ColorProgram");
    gl.GenVertexArrays(1, &vao_);
    gl.GenBuffers(1, &vbo_);
  }
  ~ColorProgram() {
    gl_.DeleteBuffers(1, &vbo_);
    gl_.DeleteVertexArrays(1, &vao_);
    gl_.DeleteProgram(program_);
  }
  ColorProgram(const ColorProgram&) = delete;
  ColorProgram& operator=(const ColorProgram&) = delete;

  // 6 floats per vertex: x, y, r, g, b, a.
  void draw(const std::vector<float>& vertices) {
    gl_.UseProgram(program_);
    gl_.BindVertexArray(vao_);
    gl_.BindBuffer(GL_ARRAY_BUFFER, vbo_);
    gl_.BufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vertices.size() * sizeof(float)),
                   vertices.data(), GL_STREAM_DRAW);
    gl_.EnableVertexAttribArray(0);
    gl_.VertexAttribPointer(0, 2, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
    gl_.EnableVertexAttribArray(1);
    gl_.VertexAttribPointer(1, 4, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                            reinterpret_cast<const void*>(2 * sizeof(float)));
    gl_.DrawArrays(GL_TRIANGLES, 0, static_cast<GLsizei>(vertices.size() / 6));
    gl_.BindVertexArray(0);
    check_gl(gl_, "ColorProgram::draw");
  }

  // Axis-aligned rectangle in target pixels (origin top-left) of a w x h target.
  void rect_pixels(int w, int h, int x0, int y0, int x1, int y1, float r, float g, float b, float a) {
    auto nx = [&](int x) { return 2.0f * float(x) / float(w) - 1.0f; };
    auto ny = [&](int y) { return 1.0f - 2.0f * float(y) / float(h); };
    const float l = nx(x0), rr = nx(x1), t = ny(y0), bo = ny(y1);
    draw({l, t, r, g, b, a, rr, t, r, g, b, a, rr, bo, r, g, b, a,
          l, t, r, g, b, a, rr, bo, r, g, b, a, l, bo, r, g, b, a});
  }

 private:
  const Gl& gl_;
  GLuint program_ = 0, vao_ = 0, vbo_ = 0;
};

// The positions the driver rasterizes a target's samples at (origin bottom-left of the pixel).
inline std::vector<std::array<float, 2>> sample_positions(const Gl& gl, const RenderTarget& target) {
  gl.BindFramebuffer(GL_DRAW_FRAMEBUFFER, target.draw_framebuffer());
  std::vector<std::array<float, 2>> out;
  for (int s = 0; s < target.samples(); ++s) {
    GLfloat xy[2] = {0, 0};
    gl.GetMultisamplefv(GL_SAMPLE_POSITION, static_cast<GLuint>(s), xy);
    out.push_back({xy[0], xy[1]});
  }
  check_gl(gl, "GL_SAMPLE_POSITION");
  return out;
}

}  // namespace meter::platform::test
