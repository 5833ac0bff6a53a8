// meter_readback_bench: what reading a few small boxes back from a multisample frame costs, the
// integrity monitor's readback, measured side by side in one run on both backends. The frame is a
// partial redraw at 1280x480 MSAA 4 (one dial-sized box cleared and shaded again, as when a needle
// moves); each case adds one way of getting five monitor-sized boxes (a lamp, two needle windows, a
// readout, a small lamp; 7,116 pixels in all) onto the CPU:
//   shader resolve   the boxes resolved by RenderTarget's shader pass, then glReadPixels (meter's way)
//   blit resolve     the same by glBlitFramebuffer per box (the box resolve before the shader pass)
//   resolve only     the shader resolve of the boxes without reading them (what the reads cost
//                    is the difference from the row above)
//   atlas resolve    the boxes resolved by a shader pass into one small target, packed side by side,
//                    and read back with one glReadPixels: a pass over a target the size of what is
//                    read instead of one the size of the frame
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
#include "bench_stats.hpp"

using meter::bench::median;

namespace mp = meter::platform;
using Clock = std::chrono::steady_clock;

namespace {

double cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
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

// The box resolve (mean of the samples) of the frame pixel at this atlas pixel plus the box's offset.
constexpr const char* kAtlasResolve = R"(#version 310 es
precision highp float;
uniform highp sampler2DMS u_samples;
uniform ivec2 u_offset;  // frame pixel minus atlas pixel
out vec4 o_color;
void main() {
  ivec2 p = ivec2(gl_FragCoord.xy) + u_offset;
  o_color = 0.25 * (texelFetch(u_samples, p, 0) + texelFetch(u_samples, p, 1) +
                    texelFetch(u_samples, p, 2) + texelFetch(u_samples, p, 3));
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
  // The frame's work after its framebuffer is bound: one dial-sized box cleared and shaded again.
  auto shade_box = [&] {
    gl.Enable(GL_SCISSOR_TEST);
    gl.Scissor(67, 48, 392, 393);
    gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    gl.UseProgram(shade);
    gl.BindVertexArray(vao);
    gl.Uniform4f(color, 0.2f, float(n % 9) / 9.0f, 0.4f, 1.0f);
    gl.DrawArrays(GL_TRIANGLES, 0, 3);
    gl.Disable(GL_SCISSOR_TEST);
  };
  auto draw_frame = [&](mp::RenderTarget& t) {
    t.bind();
    shade_box();
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
  cases.push_back({"+ shader resolve only", [&] {
                     draw_frame(shader);
                     shader.resolve(boxes);
                   }, {}, {}});
  // A frame of its own over a multisample texture, and the atlas the boxes are packed into.
  GLuint ms_tex = 0, ms_depth = 0, ms_fbo = 0, atlas_tex = 0, atlas_fbo = 0, full_tex = 0, full_fbo = 0,
         atlas_prog = 0;
  GLint offset_loc = -1, samples_loc = -1;
  int atlas_w = 0, atlas_h = 0;
  for (const auto& b : boxes) atlas_w += b.width, atlas_h = std::max(atlas_h, b.height);
  std::vector<std::uint8_t> atlas_pixels(std::size_t(atlas_w) * std::size_t(atlas_h) * 4);
  if (gl.info.has_multisample_texture) {
    gl.GenTextures(1, &ms_tex);
    gl.BindTexture(GL_TEXTURE_2D_MULTISAMPLE, ms_tex);
    gl.TexStorage2DMultisample(GL_TEXTURE_2D_MULTISAMPLE, 4, GL_SRGB8_ALPHA8, w, h, GL_TRUE);
    gl.GenRenderbuffers(1, &ms_depth);
    gl.BindRenderbuffer(GL_RENDERBUFFER, ms_depth);
    gl.RenderbufferStorageMultisample(GL_RENDERBUFFER, 4, GL_DEPTH_COMPONENT24, w, h);
    gl.GenFramebuffers(1, &ms_fbo);
    gl.BindFramebuffer(GL_FRAMEBUFFER, ms_fbo);
    gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D_MULTISAMPLE, ms_tex, 0);
    gl.FramebufferRenderbuffer(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, ms_depth);
    gl.GenTextures(1, &atlas_tex);
    gl.BindTexture(GL_TEXTURE_2D, atlas_tex);
    gl.TexStorage2D(GL_TEXTURE_2D, 1, GL_SRGB8_ALPHA8, atlas_w, atlas_h);
    gl.GenFramebuffers(1, &atlas_fbo);
    gl.BindFramebuffer(GL_FRAMEBUFFER, atlas_fbo);
    gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, atlas_tex, 0);
    gl.GenTextures(1, &full_tex);
    gl.BindTexture(GL_TEXTURE_2D, full_tex);
    gl.TexStorage2D(GL_TEXTURE_2D, 1, GL_SRGB8_ALPHA8, w, h);
    gl.GenFramebuffers(1, &full_fbo);
    gl.BindFramebuffer(GL_FRAMEBUFFER, full_fbo);
    gl.FramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, full_tex, 0);
    atlas_prog = mp::compile_program(gl, std::string("#version 310 es") + kTriangle, kAtlasResolve, "readback bench atlas");
    offset_loc = gl.GetUniformLocation(atlas_prog, "u_offset");
    samples_loc = gl.GetUniformLocation(atlas_prog, "u_samples");
    mp::check_gl(gl, "readback bench atlas set-up");
    auto bind_own = [&] {
      gl.BindFramebuffer(GL_FRAMEBUFFER, ms_fbo);
      gl.Viewport(0, 0, w, h);
      if (gl.info.needs_framebuffer_srgb_enable) gl.Enable(GL_FRAMEBUFFER_SRGB);
    };
    auto own_frame = [&, bind_own] {  // copies: the cases outlive this block
      bind_own();
      shade_box();
    };
    cases.push_back({"own frame (MS texture)", own_frame, {}, {}});
    // The same resolve program either into the atlas (one read) or into a frame-sized target at the
    // boxes' own places (one read per box): what the size of the pass's target costs.
    auto resolve_into = [&, own_frame](bool atlas) {
      own_frame();
      gl.BindFramebuffer(GL_FRAMEBUFFER, atlas ? atlas_fbo : full_fbo);
      gl.Viewport(0, 0, atlas ? atlas_w : w, atlas ? atlas_h : h);
      gl.UseProgram(atlas_prog);
      gl.ActiveTexture(GL_TEXTURE0);
      gl.BindTexture(GL_TEXTURE_2D_MULTISAMPLE, ms_tex);
      gl.Uniform1i(samples_loc, 0);
      gl.Enable(GL_SCISSOR_TEST);
      int x = 0;
      for (const auto& b : boxes) {
        const int to_x = atlas ? x : b.x, to_y = atlas ? 0 : b.y;
        gl.Scissor(to_x, to_y, b.width, b.height);
        gl.Uniform2i(offset_loc, b.x - to_x, b.y - to_y);
        gl.DrawArrays(GL_TRIANGLES, 0, 3);
        x += b.width;
      }
      gl.Disable(GL_SCISSOR_TEST);
      gl.PixelStorei(GL_PACK_ALIGNMENT, 1);
      if (atlas) {
        gl.ReadPixels(0, 0, atlas_w, atlas_h, GL_RGBA, GL_UNSIGNED_BYTE, atlas_pixels.data());
      } else {
        for (const auto& b : boxes) gl.ReadPixels(b.x, b.y, b.width, b.height, GL_RGBA, GL_UNSIGNED_BYTE, atlas_pixels.data());
      }
    };
    cases.push_back({"+ frame-size resolve", [resolve_into] { resolve_into(false); }, {}, {}});
    cases.push_back({"+ atlas resolve, 1 read", [resolve_into] { resolve_into(true); }, {}, {}});
  }
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
  if (atlas_prog) gl.DeleteProgram(atlas_prog);
  for (GLuint f : {ms_fbo, atlas_fbo, full_fbo})
    if (f) gl.DeleteFramebuffers(1, &f);
  for (GLuint t : {ms_tex, atlas_tex, full_tex})
    if (t) gl.DeleteTextures(1, &t);
  if (ms_depth) gl.DeleteRenderbuffers(1, &ms_depth);
  if (fetch) gl.DeleteProgram(fetch);
  gl.DeleteVertexArrays(1, &vao);
  gl.DeleteProgram(shade);
}

}  // namespace

int main(int argc, char** argv) {
  return meter::bench::run_on_both_backends(argc, argv, 400, "meter_readback_bench", run_backend);
}
