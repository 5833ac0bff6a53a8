#include "start_up_steps.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "meter/engine/gl/program_binary_cache.hpp"
#include "meter/engine/gl/texture_mips.hpp"
#include "meter/engine/package_reader.hpp"
#include "meter/engine/pipeline/frame_pipeline.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/backend.hpp"
#include "meter/platform/image.hpp"
#include "meter/runner/values_input.hpp"

namespace meter::bench {

namespace {

using Clock = std::chrono::steady_clock;

long status_kib(const char* field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(field, 0) == 0) return std::atol(line.c_str() + std::char_traits<char>::length(field));
  return -1;
}

double texture_bytes(const engine::Scene& scene) {
  double bytes = 0;
  for (const auto& t : scene.textures) bytes += double(t.rgba.size());
  return bytes;
}

void mips_side_by_side(const platform::Gl& gl, const engine::Scene& scene, StartUpSteps& r) {
  for (const auto& t : scene.textures) {
    if (!engine::box_mips_apply(t.width, t.height, t.srgb)) continue;
    GLuint tex = 0;
    gl.GenTextures(1, &tex);
    gl.BindTexture(GL_TEXTURE_2D, tex);
    gl.TexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, t.width, t.height, 0, GL_RGBA, GL_UNSIGNED_BYTE, t.rgba.data());
    gl.Finish();
    auto t0 = Clock::now();
    gl.GenerateMipmap(GL_TEXTURE_2D);
    gl.Finish();
    r.gl_mips_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    t0 = Clock::now();
    const auto levels = engine::box_mip_chain(t.rgba, t.width, t.height);
    for (std::size_t k = 0; k < levels.size(); ++k)
      gl.TexImage2D(GL_TEXTURE_2D, static_cast<GLint>(k + 1), GL_RGBA8, std::max(1, t.width >> (k + 1)),
                    std::max(1, t.height >> (k + 1)), 0, GL_RGBA, GL_UNSIGNED_BYTE, levels[k].data());
    gl.Finish();
    r.cpu_mips_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
    gl.DeleteTextures(1, &tex);
    return;
  }
}

void steps_in_child(const StartUpRun& run, StartUpSteps& r) {
  if (run.mesa_cache.empty()) setenv("MESA_SHADER_CACHE_DISABLE", "true", 1);
  else setenv("MESA_SHADER_CACHE_DIR", run.mesa_cache.c_str(), 1);
  r.rss_start_kib = status_kib("VmRSS:");
  auto t = Clock::now();
  auto mark = [&](int step) {
    const auto now = Clock::now();
    r.ms[step] = std::chrono::duration<double, std::milli>(now - t).count();
    r.rss_kib[step] = status_kib("VmRSS:");
    t = Clock::now();  // the RSS read is not counted
  };
  auto backend = platform::create_backend(*platform::parse_backend_kind(run.backend));
  mark(StartUpSteps::Backend);
  const engine::Scene scene = engine::read_package(run.package);
  mark(StartUpSteps::Package);
  std::ostringstream log;
  std::unique_ptr<engine::ProgramBinaryCache> binaries;
  if (!run.program_cache.empty()) binaries = std::make_unique<engine::ProgramBinaryCache>(run.program_cache, log);
  engine::RendererOptions ro;
  ro.msaa = run.msaa;
  ro.program_binaries = binaries.get();
  engine::Renderer renderer(*backend, scene, ro);
  mark(StartUpSteps::Renderer);
  r.program_ms = renderer.program_link_ms();
  r.programs = static_cast<int>(renderer.programs_linked());
  r.programs_loaded = binaries ? static_cast<int>(binaries->counts().loaded) : 0;
  engine::FramePipeline pipeline(scene, renderer);
  protocol::SignalTable values;
  runner::parse_set("Vehicle.Speed=100", values, "--set");
  pipeline.evaluate(values, true, -1.0);
  pipeline.render(engine::FrameRequest{0, 0.0, true, false, false, false});  // drawn, glFinish'ed
  mark(StartUpSteps::FirstFrame);
  renderer.resolved_framebuffer();
  backend->gl().Finish();
  mark(StartUpSteps::Resolve);
  const platform::Image& image = renderer.read();
  mark(StartUpSteps::Readback);
  platform::write_png(image, run.png);
  mark(StartUpSteps::Png);
  r.peak_kib = status_kib("VmHWM:");
  r.anon_kib = status_kib("RssAnon:"), r.file_kib = status_kib("RssFile:");
  mips_side_by_side(backend->gl(), scene, r);
  // Multisampled colour (sRGB8 or half float per sample) + depth-stencil (4 bytes), and the
  // resolved RGBA8 image; the static layer is a second target of the same kind.
  const bool half = scene.config.resolve.sample_format == bridge::ResolveConfig::SampleFormat::Rgba16f;
  const double px = double(renderer.width()) * renderer.height();
  r.target_bytes = px * run.msaa * ((half ? 8 : 4) + 4) + px * 4;
  r.texture_bytes = texture_bytes(scene);
  r.package_file_bytes = double(std::filesystem::file_size(run.package));
  r.ok = true;
}

}  // namespace

StartUpSteps run_start_up_steps(const StartUpRun& run) {
  int fds[2];
  if (pipe(fds) != 0) return {};
  const pid_t pid = fork();
  if (pid == 0) {
    close(fds[0]);
    StartUpSteps r;
    try {
      steps_in_child(run, r);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "start-up steps: %s\n", e.what());
    }
    const ssize_t n = write(fds[1], &r, sizeof r);
    _exit(n == static_cast<ssize_t>(sizeof r) ? 0 : 1);
  }
  close(fds[1]);
  StartUpSteps r;
  std::size_t got = 0;
  while (got < sizeof r) {
    const ssize_t n = read(fds[0], reinterpret_cast<char*>(&r) + got, sizeof r - got);
    if (n <= 0) break;
    got += static_cast<std::size_t>(n);
  }
  close(fds[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  if (got != sizeof r) r.ok = false;
  return r;
}

}  // namespace meter::bench
