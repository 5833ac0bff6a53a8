// meter_platform_bench: what the platform layer costs per frame at cluster resolution, measured
// side by side in one run, on both backends, so results read as ratios against a "fill floor"
// (one full-screen flat-shaded pass into a single-sample target, resolved and read back).
//
// Rows (each: median and p99 wall time per frame, including glFinish so GPU work is counted):
//   clear+read      clear only, resolve and read back 1280x480 (the PNG-dump overhead)
//   fill MSAA n     the fill floor with n samples (n = 1, 2, 4) incl. resolve + readback
//   fill linear     the n=1 floor into an RGBA8 (non-sRGB) target: the cost of the sRGB encode
//   MSAA 4 linear   4 samples into RGBA8: separates the sRGB (linear-space) resolve cost
//   MSAA 4 no read  4-sample draw without resolve/readback: separates draw from resolve
//   fill MSAA 4 blit  as fill MSAA 4, the box resolved by glBlitFramebuffer instead of the shader
//                   pass (the same bytes): what the pass costs against the driver's own resolve
//   fill MSAA 4 film  as fill MSAA 4, resolved with the film filter (Blackman-Harris 1.5 px, 36
//                   samples per pixel) instead of the box (the same shader pass with the pixel's
//                   own 4 samples): the filter's cost is the difference
//   fill MSAA 4 RGBA16F / film 16F  as fill MSAA 4 / film, the samples in half float (light above
//                   white kept until the filter has run): the cost of 8-byte samples
//   text x5         fill floor + five overlay strings and a banner (the HUD cost)
// Cases are interleaved frame by frame (A B C A B C ...) so machine noise hits all alike.
// Also prints backend start-up time (create_backend to first usable context).
// Usage: meter_platform_bench [frames]   (default 60 frames per case)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include "meter/platform/backend.hpp"
#include "on_both_backends.hpp"
#include "meter/platform/render_target.hpp"
#include "meter/platform/text.hpp"

namespace mp = meter::platform;
using Clock = std::chrono::steady_clock;

namespace {

struct Case {
  std::string name;
  std::function<void()> frame;
  std::vector<double> ms;
};

double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  const std::size_t i = std::min(v.size() - 1, static_cast<std::size_t>(p * double(v.size() - 1) + 0.5));
  return v[i];
}

class FlatPass {
 public:
  explicit FlatPass(const mp::Gl& gl) : gl_(gl) {
    program_ = mp::compile_program(gl, R"(#version 300 es
const vec2 p[3] = vec2[3](vec2(-1.0, -1.0), vec2(3.0, -1.0), vec2(-1.0, 3.0));
void main() { gl_Position = vec4(p[gl_VertexID], 0.0, 1.0); }
)",
                                   R"(#version 300 es
precision mediump float;
uniform vec4 u_color;
out vec4 o;
void main() { o = u_color; }
)",
                                   "bench flat pass");
    gl.GenVertexArrays(1, &vao_);
    color_ = gl.GetUniformLocation(program_, "u_color");
  }
  ~FlatPass() {
    gl_.DeleteVertexArrays(1, &vao_);
    gl_.DeleteProgram(program_);
  }
  void draw(float shade) {
    gl_.UseProgram(program_);
    gl_.Uniform4f(color_, 0.1f, shade, 0.3f, 1.0f);
    gl_.BindVertexArray(vao_);
    gl_.DrawArrays(GL_TRIANGLES, 0, 3);  // one triangle covering the viewport
  }

 private:
  const mp::Gl& gl_;
  GLuint program_ = 0, vao_ = 0;
  GLint color_ = -1;
};

void run_backend(mp::BackendKind kind, int frames) {
  const auto t0 = Clock::now();
  auto backend = mp::create_backend(kind);
  const double startup_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
  std::printf("\n== %s ==\n%s\nstart-up (create_backend): %.1f ms\n", std::string(backend->name()).c_str(),
              backend->renderer_info().c_str(), startup_ms);
  const mp::Gl& gl = backend->gl();
  const int w = 1280, h = 480;
  mp::RenderTarget t1(*backend, {.width = w, .height = h, .samples = 1});
  mp::RenderTarget t2(*backend, {.width = w, .height = h, .samples = 2});
  mp::RenderTarget t4(*backend, {.width = w, .height = h, .samples = 4});
  mp::RenderTarget tlin(*backend, {.width = w, .height = h, .samples = 1, .srgb = false});
  mp::RenderTarget t4lin(*backend, {.width = w, .height = h, .samples = 4, .srgb = false});
  mp::RenderTarget t4blit(*backend, {.width = w, .height = h, .samples = 4, .box_resolve_by_blit = true});
  mp::RenderTarget t4film(*backend, {.width = w, .height = h, .samples = 4,
                                     .resolve = {mp::ResolveFilter::Kind::BlackmanHarris, 1.5}});
  mp::RenderTarget t4half(*backend, {.width = w, .height = h, .samples = 4, .sample_format = mp::SampleFormat::Rgba16f});
  mp::RenderTarget t4filmhalf(*backend, {.width = w, .height = h, .samples = 4,
                                         .resolve = {mp::ResolveFilter::Kind::BlackmanHarris, 1.5},
                                         .sample_format = mp::SampleFormat::Rgba16f});
  FlatPass flat(gl);
  const auto t_text = Clock::now();
  std::ifstream font_in(METER_FONT_FILE, std::ios::binary);
  const std::vector<std::uint8_t> font((std::istreambuf_iterator<char>(font_in)), std::istreambuf_iterator<char>());
  mp::TextRenderer text(*backend, mp::FontData{"DejaVuSans.ttf", font}, 48);
  const double text_init_ms = std::chrono::duration<double, std::milli>(Clock::now() - t_text).count();
  std::printf("text atlas (DejaVu Sans 48 px) + program: %.1f ms\n", text_init_ms);

  int n = 0;
  auto fill = [&](mp::RenderTarget& t) {
    t.bind();
    gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    flat.draw(float(n % 7) / 7.0f);
    (void)t.resolve_and_read();
  };
  std::vector<Case> cases;
  cases.push_back({"clear+read", [&] {
                     t1.bind();
                     gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
                     (void)t1.resolve_and_read();
                   }, {}});
  cases.push_back({"fill MSAA 1 (floor)", [&] { fill(t1); }, {}});
  cases.push_back({"fill MSAA 2", [&] { fill(t2); }, {}});
  cases.push_back({"fill MSAA 4", [&] { fill(t4); }, {}});
  cases.push_back({"fill MSAA 4 blit", [&] { fill(t4blit); }, {}});
  cases.push_back({"fill MSAA 4 film", [&] { fill(t4film); }, {}});
  cases.push_back({"fill MSAA 4 RGBA16F", [&] { fill(t4half); }, {}});
  cases.push_back({"fill MSAA 4 film 16F", [&] { fill(t4filmhalf); }, {}});
  cases.push_back({"fill linear RGBA8", [&] { fill(tlin); }, {}});
  cases.push_back({"fill MSAA 4 linear", [&] { fill(t4lin); }, {}});
  cases.push_back({"MSAA 4 draw, no read", [&] {
                     t4.bind();
                     gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
                     flat.draw(float(n % 7) / 7.0f);
                   }, {}});
  cases.push_back({"fill + text x5", [&] {
                     t1.bind();
                     gl.Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
                     flat.draw(0.2f);
                     text.draw(t1, std::to_string(n % 261), 640, 300, mp::Align::Center, {1, 1, 1, 1});
                     text.draw(t1, "km/h", 640, 360, mp::Align::Center, {0.8f, 0.8f, 0.8f, 1});
                     text.draw(t1, "ODO 123456 km", 40, 460, mp::Align::Left, {1, 1, 1, 1});
                     text.draw(t1, "21\xC2\xB0" "C", 1240, 460, mp::Align::Right, {1, 1, 1, 1});
                     text.fill_rect(t1, {440, 40, 400, 70}, {0.7f, 0.05f, 0.05f, 0.85f});
                     text.draw(t1, "NO SIGNAL", 640, 95, mp::Align::Center, {1, 1, 1, 1});
                     (void)t1.resolve_and_read();
                   }, {}});
  for (int i = 0; i < 5; ++i)
    for (auto& c : cases) c.frame();  // warm-up: shader JIT, first-touch of buffers
  for (n = 0; n < frames; ++n) {
    for (auto& c : cases) {
      const auto s = Clock::now();
      c.frame();
      gl.Finish();
      c.ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - s).count());
    }
  }
  const double floor = percentile(cases[1].ms, 0.5);
  std::printf("%-22s %10s %10s %10s\n", "case (1280x480)", "median ms", "p99 ms", "x floor");
  for (const auto& c : cases) {
    const double med = percentile(c.ms, 0.5);
    std::printf("%-22s %10.2f %10.2f %10.2f\n", c.name.c_str(), med, percentile(c.ms, 0.99), med / floor);
  }
}

}  // namespace

int main(int argc, char** argv) {
  return meter::bench::run_on_both_backends(argc, argv, 60, "meter_platform_bench", run_backend);
}
