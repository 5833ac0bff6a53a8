// meter_readback_bench: what reading a few small boxes back from a multisample frame costs, the
// integrity monitor's readback, measured side by side in one run on both backends. The frame is a
// partial redraw at 1280x480 MSAA 4 (one dial-sized box cleared and shaded again, as when a needle
// moves); each case adds one way of getting five monitor-sized boxes (a lamp, two needle windows, a
// readout, a small lamp; 7,116 pixels in all) onto the CPU:
//   shader resolve   the boxes resolved by RenderTarget's shader pass, then glReadPixels (meter's way)
//   blit resolve     the same by glBlitFramebuffer per box (the box resolve before the shader pass)
//   empty pass       no readback: one flat triangle into a 16x16 target after the frame, the fixed
//                    cost of any second pass (on llvmpipe each is a scene of its own for its threads)
//   fb fetch         no second pass: the frame's own pass reads each sample of the boxes with
//                    EXT_shader_framebuffer_fetch into a shader storage buffer, the CPU averages
//                    the samples and encodes sRGB (GLES with that extension only)
// Each row: median wall and process CPU time per frame (llvmpipe's threads included), including
// glFinish, and the difference from the frame alone. Cases are interleaved frame by frame.
// Usage: meter_readback_bench [frames]   (default 400 per case)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <string>
#include <vector>

#include "meter/platform/backend.hpp"
#include "meter/platform/render_target.hpp"
#include "on_both_backends.hpp"

namespace mp = meter::platform;
using Clock = std::chrono::steady_clock;

namespace {

double cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

constexpr const char* kTriangle = R"(
const vec2 p[3] = vec2[3](vec2(-1.0, -1.0), vec2(3.0, -1.0), vec2(-1.0, 3.0));
void main() { gl_Position = vec4(p[gl_VertexID], 0.0, 1.0); }
)";

// The frame's shading: a few dependent operations per pixel, so the redrawn box costs like a dial.
constexpr const char* kShade = R"(#version 300 es
precision highp float;
uniform vec4 u_color;
out vec4 o;
void main() {
  vec2 q = gl_FragCoord.xy * 0.01;
  o = vec4(u_color.rgb * (0.6 + 0.4 * sin(q.x) * cos(q.y)), 1.0);
}
)";

// Each sample of the box this draw covers, in linear light, stored at its slot.
constexpr const char* kFetch = R"(#version 320 es
#extension GL_EXT_shader_framebuffer_fetch : require
precision highp float;
layout(std430, binding = 0) writeonly buffer Samples { vec4 samples[]; };
uniform ivec4 u_box;  // x, y, width, first slot
inout highp vec4 o_color;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy) - u_box.xy;
  samples[u_box.w + (p.y * u_box.z + p.x) * 4 + gl_SampleID] = o_color;
}
)";

struct Case {
  std::string name;
  std::function<void()> frame;
  std::vector<double> wall, cpu;
};

void run_backend(mp::BackendKind kind, int frames) {
  auto backend = mp::create_backend(kind);
  const mp::Gl& gl = backend->gl();
  std::printf("\n== %s ==\n%s\n", std::string(backend->name()).c_str(), backend->renderer_info().c_str());
  const int w = 1280, h = 480;
  mp::RenderTarget shader(*backend, {.width = w, .height = h, .samples = 4});
  mp::RenderTarget blit(*backend, {.width = w, .height = h, .samples = 4, .box_resolve_by_blit = true});
  mp::RenderTarget tiny(*backend, {.width = 16, .height = 16, .samples = 1, .depth = mp::DepthFormat::None});
  const std::string vs = std::string("#version 300 es") + kTriangle;
  const GLuint shade = mp::compile_program(gl, vs, kShade, "readback bench frame");
  const GLint color = gl.GetUniformLocation(shade, "u_color");
  GLuint vao = 0;
  gl.GenVertexArrays(1, &vao);
  const std::vector<mp::PixelRegion> boxes = {{496, 15, 38, 30}, {180, 200, 64, 64}, {900, 210, 64, 64},
                                              {623, 143, 148, 21}, {1100, 420, 20, 20}};
  int n = 0;
  auto draw_frame = [&](mp::RenderTarget& t) {
    t.bind();
    gl.Enable(GL_SCISSOR_TEST);
    gl.Scissor(67, 48, 392, 393);
    gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    gl.UseProgram(shade);
    gl.BindVertexArray(vao);
    gl.Uniform4f(color, 0.2f, float(n % 9) / 9.0f, 0.4f, 1.0f);
    gl.DrawArrays(GL_TRIANGLES, 0, 3);
    gl.Disable(GL_SCISSOR_TEST);
  };

  std::vector<Case> cases;
  cases.push_back({"MSAA 4 partial frame", [&] { draw_frame(shader); }, {}, {}});
  cases.push_back({"+ shader resolve, read", [&] {
                     draw_frame(shader);
                     (void)shader.read_regions(boxes);
                   }, {}, {}});
  cases.push_back({"+ blit resolve, read", [&] {
                     draw_frame(blit);
                     (void)blit.read_regions(boxes);
                   }, {}, {}});
  cases.push_back({"+ empty pass", [&] {
                     draw_frame(shader);
                     tiny.bind();
                     gl.UseProgram(shade);
                     gl.DrawArrays(GL_TRIANGLES, 0, 3);
                   }, {}, {}});

  GLuint fetch = 0, storage = 0;
  GLint box_loc = -1;
  int slots = 0;
  for (const auto& b : boxes) slots += b.width * b.height * 4;
  std::vector<std::uint8_t> fetched(static_cast<std::size_t>(slots));  // RGBA8 per pixel: 4 bytes = 4 sample slots
  if (gl.info.is_gles && gl.MemoryBarrier && mp::has_extension(gl, "GL_EXT_shader_framebuffer_fetch")) {
    fetch = mp::compile_program(gl, std::string("#version 320 es") + kTriangle, kFetch, "readback bench fetch");
    box_loc = gl.GetUniformLocation(fetch, "u_box");
    gl.GenBuffers(1, &storage);
    gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, storage);
    gl.BufferData(GL_SHADER_STORAGE_BUFFER, GLsizeiptr(slots) * 16, nullptr, GL_DYNAMIC_READ);
    cases.push_back({"+ fb fetch, same pass", [&] {
                       draw_frame(shader);
                       gl.Enable(GL_SCISSOR_TEST);
                       gl.ColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
                       gl.Disable(GL_DEPTH_TEST);
                       gl.UseProgram(fetch);
                       gl.BindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, storage);
                       int first = 0;
                       for (const auto& b : boxes) {
                         gl.Scissor(b.x, b.y, b.width, b.height);
                         gl.Uniform4i(box_loc, b.x, b.y, b.width, first);
                         gl.DrawArrays(GL_TRIANGLES, 0, 3);
                         first += b.width * b.height * 4;
                       }
                       gl.ColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
                       gl.Disable(GL_SCISSOR_TEST);
                       gl.MemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
                       gl.BindBuffer(GL_SHADER_STORAGE_BUFFER, storage);
                       const auto* s = static_cast<const float*>(
                           gl.MapBufferRange(GL_SHADER_STORAGE_BUFFER, 0, GLsizeiptr(slots) * 16, GL_MAP_READ_BIT));
                       for (int p = 0; s && p < slots / 4; ++p)
                         for (int c = 0; c < 4; ++c) {
                           const double mean = 0.25 * (double(s[p * 16 + c]) + s[p * 16 + 4 + c] + s[p * 16 + 8 + c] + s[p * 16 + 12 + c]);
                           fetched[std::size_t(p) * 4 + std::size_t(c)] = static_cast<std::uint8_t>(
                               c == 3 ? std::lround(std::clamp(mean, 0.0, 1.0) * 255.0) : mp::linear_to_srgb8(mean));
                         }
                       gl.UnmapBuffer(GL_SHADER_STORAGE_BUFFER);
                     }, {}, {}});
  }
  mp::check_gl(gl, "readback bench set-up");

  for (int i = 0; i < 10; ++i)
    for (auto& c : cases) c.frame(), gl.Finish();  // shader JIT, first touch of every buffer
  for (n = 0; n < frames; ++n)
    for (auto& c : cases) {
      const double c0 = cpu_ms();
      const auto t0 = Clock::now();
      c.frame();
      gl.Finish();
      c.wall.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
      c.cpu.push_back(cpu_ms() - c0);
    }
  mp::check_gl(gl, "readback bench frames");
  const double wall0 = median(cases[0].wall), cpu0 = median(cases[0].cpu);
  std::printf("%-24s %11s %11s %13s %13s\n", "case (1280x480, 5 boxes)", "wall ms", "CPU ms", "wall vs frame",
              "CPU vs frame");
  for (const auto& c : cases) {
    const double wm = median(c.wall), cm = median(c.cpu);
    std::printf("%-24s %11.3f %11.3f %+10.3f ms %+10.3f ms\n", c.name.c_str(), wm, cm, wm - wall0, cm - cpu0);
  }
  if (!fetch) std::printf("(fb fetch: not offered by this context)\n");
  if (storage) gl.DeleteBuffers(1, &storage);
  if (fetch) gl.DeleteProgram(fetch);
  gl.DeleteVertexArrays(1, &vao);
  gl.DeleteProgram(shade);
}

}  // namespace

int main(int argc, char** argv) {
  return meter::bench::run_on_both_backends(argc, argv, 400, "meter_readback_bench", run_backend);
}
