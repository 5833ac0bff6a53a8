// view_bench: everything measured side by side in one run on llvmpipe.
//  1. per program of the cluster and the twelve feature scenes, generated (--optimize=off) vs
//     optimized: source bytes, SPIR-V instructions, uniforms, varyings, compile+link ms on EGL and
//     OSMesa (median of 5; llvmpipe JITs the variant at first draw, counted in "first frame");
//  2. per scene: renderer start-up (compile + upload) + first frame, and the median forced-redraw
//     frame time, off vs on, on EGL; the uber shader's compile+link against the scene's programs;
//  3. the cluster at 1280x480 MSAA 4: median / p99 frame time vs a same-run fill floor
//     (one full-screen flat-shaded pass), process start -> first PNG on disk, peak RSS of meter-view;
//  5. (--integrity, also at the end of a full run) the integrity monitor's cost per frame
//     (integrity_bench.cpp).
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "integrity_bench.hpp"
#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/package_reader.hpp"
#include "meter/config/scene_config_parser.hpp"
#include "meter/engine/pipeline/frame_pipeline.hpp"
#include "meter/convert/converter.hpp"
#include "meter/convert/package_writer.hpp"
#include "meter/convert/scene_font.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/backend.hpp"
#include "meter/platform/render_target.hpp"
#include "meter/platform/text.hpp"
#include "meter/shadergen/shadergen.hpp"

namespace {

using namespace meter;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}
double percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  const std::size_t i = std::min(v.size() - 1, static_cast<std::size_t>(p * double(v.size() - 1) + 0.5));
  return v[i];
}

struct SceneFiles {
  std::string name, glb, config;
};
std::vector<SceneFiles> scenes() {
  const fs::path root = fs::path(METER_SOURCE_DIR) / "scenes";
  std::vector<SceneFiles> s = {{"cluster", (root / "cluster/cluster.glb").string(),
                                (root / "cluster/cluster.scene.json").string()}};
  for (const char* f : {"ambient", "diffuse", "specular", "shininess", "emission", "bump",
                        "reflection", "envmap2d", "skinning", "morphing", "spot", "omni"})
    s.push_back({f, (root / "features" / f / (std::string(f) + ".glb")).string(),
                 (root / "features" / f / "scene.json").string()});
  return s;
}
// Scenes as they ship, concatenation groups included (the frame times of section 3 are the
// product's; concatenation on/off is compared in bench/concatenation).
engine::SceneConfig load_config(const std::string& path) { return meter::config::load_scene_config(path); }

// Compile + link one program on the current context; returns ms (throws on failure).
double compile_link_ms(const platform::Gl& gl, const shadergen::Program& p) {
  const auto t = Clock::now();
  auto shader = [&](GLenum type, const std::string& src) {
    GLuint s = gl.CreateShader(type);
    const char* text = src.c_str();
    gl.ShaderSource(s, 1, &text, nullptr);
    gl.CompileShader(s);
    return s;
  };
  GLuint vs = shader(GL_VERTEX_SHADER, p.vertex_source), fs = shader(GL_FRAGMENT_SHADER, p.fragment_source);
  GLuint prog = gl.CreateProgram();
  gl.AttachShader(prog, vs);
  gl.AttachShader(prog, fs);
  gl.LinkProgram(prog);
  GLint ok = 0;
  gl.GetProgramiv(prog, GL_LINK_STATUS, &ok);
  const double ms = ms_since(t);
  gl.DeleteShader(vs);
  gl.DeleteShader(fs);
  gl.DeleteProgram(prog);
  if (!ok) throw std::runtime_error("program " + meter::shadergen::program_key(p.features) + " does not link");
  return ms;
}
double median_compile_ms(const platform::Gl& gl, const shadergen::Program& p) {
  std::vector<double> v;
  for (int i = 0; i < 5; ++i) v.push_back(compile_link_ms(gl, p));
  return percentile(v, 0.5);
}

protocol::SignalTable mid_state(const engine::SceneConfig& c) {
  protocol::SignalTable values;
  for (const auto& b : c.bindings) {
    const auto* info = protocol::find_signal(b.signal);
    if (!info) continue;
    const double v = info->kind == protocol::SignalKind::Text ? 0.0 : b.input[0] + 0.6 * (b.input[1] - b.input[0]);
    values.set(info->id, {v, protocol::SignalStatus::Valid, "A12"});
  }
  return values;
}

struct FrameStats {
  double startup_ms = 0, first_frame_ms = 0, median_ms = 0, p99_ms = 0;
};
FrameStats frames(platform::GpuBackend& backend, const engine::Scene& scene,
                  const engine::SceneConfig& config, int n, int w = 0, int h = 0) {
  FrameStats s;
  auto t = Clock::now();
  engine::RendererOptions o;
  o.msaa = 4;
  o.width = w;
  o.height = h;
  engine::Renderer r(backend, scene, o);
  engine::BindingEvaluator ev(scene);
  ev.update(mid_state(config), true, -1.0);
  r.apply(ev.outputs());
  s.startup_ms = ms_since(t);
  t = Clock::now();
  r.render(true, false);
  s.first_frame_ms = ms_since(t);
  std::vector<double> v;
  for (int i = 0; i < n; ++i) {
    t = Clock::now();
    r.render(true, false);  // forced redraw: the cost of a frame whose inputs changed
    v.push_back(ms_since(t));
  }
  s.median_ms = percentile(v, 0.5);
  s.p99_ms = percentile(v, 0.99);
  return s;
}

// Resident set of this process (kB), from /proc/self/statm; -1 when unreadable.
long resident_kb() {
  long pages_total = 0, pages_resident = 0;
  FILE* f = std::fopen("/proc/self/statm", "r");
  if (!f) return -1;
  const int n = std::fscanf(f, "%ld %ld", &pages_total, &pages_resident);
  std::fclose(f);
  return n == 2 ? pages_resident * (sysconf(_SC_PAGESIZE) / 1024) : -1;
}

// What the static layer occupies: the resident-set growth over the frame that builds it (a forced
// frame first, so programs are JIT-compiled and the main target is touched before).
void layer_memory(platform::GpuBackend& backend, const engine::Scene& cluster) {
  engine::RendererOptions o;
  o.width = 1280, o.height = 480, o.msaa = 4;
  engine::Renderer r(backend, cluster, o);
  r.render(true, false);  // forced: drawn from scratch, no layer
  r.render(true, false);
  const long before = resident_kb();
  engine::BindingEvaluator ev(cluster);
  ev.update(protocol::SignalTable{}, true, -1.0);  // nothing known: every binding NotAvailable (its failsafe where it has one)
  r.apply(ev.outputs());
  r.render(false, false);  // the first unforced frame draws the layer
  const long after = resident_kb();
  std::printf("static layer, 1280x480 MSAA 4: %llu build(s), RSS +%.1f MiB over the frame that draws it "
              "(colour + depth of 4 samples: %.1f MiB)\n",
              static_cast<unsigned long long>(r.stats().layer_builds), double(after - before) / 1024.0,
              1280.0 * 480.0 * 4.0 * 8.0 / (1024.0 * 1024.0));
}

// One full-screen flat-shaded pass at 1280x480 MSAA 4, 200 times: the same-run floor every
// frame time is divided by (the machine is shared and noisy).
std::vector<double> fill_floor(platform::GpuBackend& backend) {
  std::vector<double> fill;
  platform::RenderTarget t(backend, {.width = 1280, .height = 480, .samples = 4});
  const bridge::SceneFont font = convert::read_font_file(METER_FONT_FILE);
  platform::TextRenderer text(backend, platform::FontData{font.name, font.data}, 24);
  for (int i = 0; i < 200; ++i) {
    const auto t0 = Clock::now();
    t.bind();
    backend.gl().Clear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    text.fill_rect(t, {0, 0, 1280, 480}, {0.2f, 0.3f, 0.4f, 1.0f});
    backend.gl().Finish();
    fill.push_back(ms_since(t0));
  }
  return fill;
}

void drive(platform::GpuBackend& backend, const engine::Scene& cluster, double fill_p99) {
  // 3b. What a live view really draws: a drive at 60 fps, needles smoothed towards moving values,
  // readouts changing, an indicator blinking; the uber-shader baseline vs the generated programs,
  // full redraw vs partial redraw (without and with the static layer), MSAA 4 vs 1.
  std::printf("\n## 3b. cluster 1280x480 on EGL through a 5 s drive at 60 fps (300 frames, not forced)\n");
  std::printf("%-22s %10s %10s %10s %12s %14s\n", "mode", "median ms", "p99 ms", "p99/fill", "drawn", "mean redrawn");
  struct Mode {
    int msaa;
    bool partial, uber, layer;
  };
  for (const Mode m : {Mode{4, false, true, false}, Mode{4, false, false, false}, Mode{4, true, false, false},
                       Mode{4, true, false, true}, Mode{1, false, false, false}, Mode{1, true, false, false},
                       Mode{1, true, false, true}}) {
    {
      const int msaa = m.msaa;
      const bool partial = m.partial;
      engine::RendererOptions o;
      o.width = 1280, o.height = 480, o.msaa = msaa, o.partial_redraw = partial, o.static_layer = m.layer;
      const shadergen::Program uber = shadergen::generate_uber();
      if (m.uber) o.uber_shader = &uber;
      engine::Renderer r(backend, cluster, o);
      engine::FramePipeline pipeline(cluster, r);
      protocol::SignalTable values;
      auto set = [&](std::string_view name, double v) {
        if (const auto* info = protocol::find_signal(name)) values.set(info->id, {v, protocol::SignalStatus::Valid, ""});
      };
      std::vector<double> v;
      double worst_ms = 0.0, worst_fraction = 0.0;
      int worst_regions = 0;
      engine::FrameTiming worst{};
      for (int f = 0; f < 300; ++f) {
        const double t = f / 60.0;
        set("Vehicle.Speed", 20.0 + 12.0 * t);  // 20 -> 80 km/h
        set("Vehicle.Powertrain.CombustionEngine.Speed", 1500.0 + 500.0 * std::fmod(t, 2.0));  // gear changes
        set("Vehicle.Powertrain.FuelSystem.RelativeLevel", 60.0 - 0.2 * t);
        set("Vehicle.Powertrain.CombustionEngine.ECT", 85.0 + t);
        set("Cluster.Telltale.TurnLeft", std::fmod(t, 0.666) < 0.333 ? 1.0 : 0.0);  // 1.5 Hz
        pipeline.evaluate(values, true, f == 0 ? -1.0 : 1.0 / 60.0);  // as meter-view's frame pipeline
        const auto t0 = Clock::now();
        const engine::FrameTiming ft = pipeline.render(engine::FrameRequest{}).timing;
        if (f >= 2) {  // frames 0-1: JIT of every program (start-up, section 4)
          v.push_back(ms_since(t0));
          if (v.back() > worst_ms) worst_ms = v.back(), worst_fraction = ft.redrawn_fraction, worst_regions = ft.regions, worst = ft;
        }
      }
      const auto& st = r.stats();
      const double p99 = percentile(v, 0.99);
      char mode[32];
      std::snprintf(mode, sizeof mode, "MSAA %d %s%s%s", msaa, partial ? "partial" : "full", m.uber ? " uber" : "",
                    m.layer ? "+layer" : "");
      std::printf("%-22s %10.2f %10.2f %9.2fx %6llu/%-5llu %13.1f%%\n", mode, percentile(v, 0.5), p99, p99 / fill_p99,
                  static_cast<unsigned long long>(st.drawn), static_cast<unsigned long long>(st.frames),
                  100.0 * st.redrawn_fraction_sum / double(std::max<std::uint64_t>(1, st.drawn)));
      if (partial)
        std::printf("%-22s slowest frame %.2f ms: %.1f %% redrawn in %d region(s); update %.2f, submit %.2f, GPU %.2f ms\n",
                    "", worst_ms, 100.0 * worst_fraction, worst_regions, worst.update_ms, worst.submit_ms,
                    worst.gpu_readback_ms);
    }
  }
  std::printf("(fill floor: the MSAA 4 full-screen pass; goal p99 < 16.7 ms)\n");
}

// The cluster as meter-convert writes it (with its safety regions) into `dir`, read back.
engine::Scene cluster_package(const fs::path& dir) {
  fs::create_directories(dir);
  const std::string pkg = (dir / "cluster-integrity.msp").string();
  const auto s = scenes().front();
  const std::string cmd = std::string(METER_CONVERT_EXE) + " " + s.glb + " --config " + s.config + " -o " + pkg + " -q";
  if (std::system(cmd.c_str()) != 0) throw std::runtime_error("view_bench: " + cmd + " failed");
  return engine::read_package(pkg);
}

using Converted = std::map<std::string, std::pair<engine::Scene, engine::Scene>>;  // off, on
using CompileMs = std::map<std::string, std::vector<double>>;  // key scene/program -> off..., on...

// 1. Per program (EGL compile+link here; OSMesa below).
CompileMs program_compiles(platform::GpuBackend& egl, Converted& converted) {
  CompileMs egl_ms;
  std::printf("\n## 1. per program: generated -> optimized\n");
  std::printf("%-10s %-44s %13s %11s %8s %8s %8s %15s\n", "scene", "program (key)", "src bytes",
              "SPIR-V", "unif", "vary", "samp", "EGL c+l ms");
  for (const auto& s : scenes()) {
    const auto& [off, on] = converted[s.name];
    for (const auto& e : on.programs) {
      const auto& r = e.optimize_report;
      // The generated program with the same features (what --optimize=off stores for it).
      const shadergen::Program gen = shadergen::generate(e.program.features);
      const double before = median_compile_ms(egl.gl(), gen);
      const double after = median_compile_ms(egl.gl(), e.program);
      egl_ms[s.name + "/" + meter::shadergen::program_key(e.program.features)] = {before, after};
      std::printf("%-10s %-44s %6zu->%-6zu %5zu->%-5zu %3zu->%-3zu %3zu->%-3zu %3zu->%-3zu %6.2f->%-6.2f\n",
                  s.name.c_str(), meter::shadergen::program_key(e.program.features).substr(0, 44).c_str(),
                  r.source_bytes_before, r.source_bytes_after, r.spirv_instructions_before,
                  r.spirv_instructions_after, r.uniforms_before, r.uniforms_after,
                  r.varyings_before, r.varyings_after, r.samplers_before, r.samplers_after, before, after);
    }
  }
  return egl_ms;
}

// 2. Per scene frame times on EGL.
void scene_frames(platform::GpuBackend& egl, Converted& converted, std::map<std::string, engine::SceneConfig>& configs,
                  CompileMs& egl_ms, double uber_egl) {
  std::printf("\n## 2. per scene on EGL (MSAA 4, config size): off vs on\n");
  std::printf("%-10s %6s %22s %22s %20s %16s\n", "scene", "progs", "startup+1st frame ms",
              "median frame ms", "sum c+l ms (EGL)", "uber c+l x progs");
  std::map<std::string, FrameStats> cluster_stats;
  for (const auto& s : scenes()) {
    const auto& [off, on] = converted[s.name];
    const int n = s.name == "cluster" ? 20 : 30;
    const FrameStats a = frames(egl, off, configs[s.name], n);
    const FrameStats b = frames(egl, on, configs[s.name], n);
    double sum_off = 0, sum_on = 0;
    for (const auto& e : on.programs) {
      sum_off += egl_ms[s.name + "/" + meter::shadergen::program_key(e.program.features)][0];
      sum_on += egl_ms[s.name + "/" + meter::shadergen::program_key(e.program.features)][1];
    }
    std::printf("%-10s %2zu->%-3zu %9.1f->%-9.1f %9.2f->%-9.2f %8.1f->%-8.1f %8.1f\n", s.name.c_str(),
                off.programs.size(), on.programs.size(), a.startup_ms + a.first_frame_ms,
                b.startup_ms + b.first_frame_ms, a.median_ms, b.median_ms, sum_off, sum_on,
                uber_egl * double(on.programs.size()));
  }
  std::printf("uber shader compile+link on EGL: %.2f ms per program (one program, all switches)\n", uber_egl);
}

// 1b. OSMesa compile+link, same programs (the backend pays its own JIT).
void osmesa_compiles(Converted& converted, const shadergen::Program& uber) {
  auto osm = platform::create_backend(platform::BackendKind::OSMesa);
  std::printf("\n## 1b. compile+link on OSMesa (%s)\n", osm->renderer_info().c_str());
  double sum_gen = 0, sum_opt = 0, sum_desktop = 0;
  int count = 0;
  for (const auto& s : scenes())
    for (const auto& e : converted[s.name].second.programs) {
      sum_gen += median_compile_ms(osm->gl(), shadergen::generate(e.program.features));
      sum_opt += median_compile_ms(osm->gl(), e.program);
      sum_desktop += median_compile_ms(osm->gl(), shadergen::to_desktop_glsl(e.program, 330));
      ++count;
    }
  std::printf("%d programs: generated %.1f ms, optimized ES 3.00 %.1f ms, optimized GLSL 330 %.1f ms; "
              "uber %.2f ms each\n", count, sum_gen, sum_opt, sum_desktop, median_compile_ms(osm->gl(), uber));
}

// 4. Start-up of the real process: start -> first PNG on disk, and its peak RSS. Returns false when
// meter-view failed.
bool process_startup(Converted& converted) {
  const fs::path dir = fs::temp_directory_path() / ("meter_view_bench_" + std::to_string(getpid()));
  fs::create_directories(dir);
  const std::string pkg = (dir / "cluster.msp").string();
  // The package meter-convert would write (converted above).
  convert::write_package(converted["cluster"].second, pkg);
  std::printf("\n## 4. meter-view process start -> first PNG (cluster package, 1280x480)\n");
  for (const char* backend : {"egl", "osmesa"}) {
    std::vector<double> v;
    long rss_kb = 0;
    for (int i = 0; i < 3; ++i) {
      const fs::path out = dir / (std::string(backend) + std::to_string(i));
      const auto t0 = Clock::now();
      const pid_t pid = fork();
      if (pid == 0) {
        execl(METER_VIEW_EXE, METER_VIEW_EXE, "--scene", pkg.c_str(), "--backend", backend, "--out",
              out.c_str(), "--set", "Vehicle.Speed=100", static_cast<char*>(nullptr));
        _exit(127);
      }
      double first_png = -1;
      int status = 0;
      struct rusage ru {};  // this child's own usage (not meter-convert's, run above)
      while (wait4(pid, &status, WNOHANG, &ru) == 0) {
        if (first_png < 0 && fs::exists(out / "frame.png")) first_png = ms_since(t0);
        usleep(1000);
      }
      if (first_png < 0 && fs::exists(out / "frame.png")) first_png = ms_since(t0);
      rss_kb = std::max(rss_kb, ru.ru_maxrss);
      if (!WIFEXITED(status) || WEXITSTATUS(status) != 0 || first_png < 0) {
        std::printf("%s: meter-view failed (status %d)\n", backend, status);
        return false;
      }
      v.push_back(first_png);
    }
    std::printf("%-6s start -> first PNG median %.0f ms (goal < 500 ms); peak RSS %.1f MiB\n", backend,
                percentile(v, 0.5), double(rss_kb) / 1024.0);
  }
  fs::remove_all(dir);
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  // --drive: only the fill floor and section 3b (the 60-fps frame-time goal: p99 under 16.7 ms), about 30 s.
  const bool drive_only = argc > 1 && std::string(argv[1]) == "--drive";
  // --integrity: only section 5 (the integrity monitor's cost), about 20 s.
  const bool integrity_only = argc > 1 && std::string(argv[1]) == "--integrity";
  if (argc > 1 && !drive_only && !integrity_only) {
    std::fprintf(stderr, "usage: view_bench [--drive | --integrity]\n");
    return 2;
  }
  std::printf("view_bench: llvmpipe, %s build\n", METER_BUILD_TYPE);
  auto egl = platform::create_backend(platform::BackendKind::Egl);
  std::printf("EGL: %s\n", egl->renderer_info().c_str());
  const fs::path integrity_dir = fs::temp_directory_path() / ("view_bench_integrity_" + std::to_string(::getpid()));
  if (integrity_only) {
    bench::integrity_cost(*egl, cluster_package(integrity_dir));
    fs::remove_all(integrity_dir);
    return 0;
  }
  if (drive_only) {
    const auto s = scenes().front();
    const auto cluster = convert::convert_gltf(s.glb, load_config(s.config), {true}).scene;
    const std::vector<double> fill = fill_floor(*egl);
    std::printf("fill floor median %.2f ms  p99 %.2f ms\n", percentile(fill, 0.5), percentile(fill, 0.99));
    drive(*egl, cluster, percentile(fill, 0.99));
    layer_memory(*egl, cluster);
    return 0;
  }
  Converted converted;
  std::map<std::string, engine::SceneConfig> configs;
  for (const auto& s : scenes()) {
    configs[s.name] = load_config(s.config);
    converted[s.name] = {convert::convert_gltf(s.glb, configs[s.name], {false}).scene,
                         convert::convert_gltf(s.glb, configs[s.name], {true}).scene};
  }

  CompileMs egl_ms = program_compiles(*egl, converted);
  const shadergen::Program uber = shadergen::generate_uber();
  const double uber_egl = median_compile_ms(egl->gl(), uber);

  scene_frames(*egl, converted, configs, egl_ms, uber_egl);

  // 3. Cluster 1280x480 vs the fill floor, same backend, same run.
  std::printf("\n## 3. cluster 1280x480 MSAA 4 on EGL, 200 forced frames\n");
  const auto& cluster = converted["cluster"].second;
  const FrameStats c = frames(*egl, cluster, configs["cluster"], 200, 1280, 480);
  const std::vector<double> fill = fill_floor(*egl);
  const double fill_med = percentile(fill, 0.5), fill_p99 = percentile(fill, 0.99);
  std::printf("cluster  median %.2f ms  p99 %.2f ms\n", c.median_ms, c.p99_ms);
  std::printf("fill     median %.2f ms  p99 %.2f ms\n", fill_med, fill_p99);
  std::printf("ratio    median %.2fx     p99 %.2fx   (goal p99 < 16.7 ms)\n", c.median_ms / fill_med,
              c.p99_ms / fill_p99);

  drive(*egl, cluster, fill_p99);
  layer_memory(*egl, cluster);
  egl.reset();

  osmesa_compiles(converted, uber);

  if (!process_startup(converted)) return 1;
  // The EGL backend was let go before the OSMesa compiles and the start-up runs; the integrity
  // cost is measured on a new one (calling into the released one dereferenced a null pointer).
  egl = platform::create_backend(platform::BackendKind::Egl);
  bench::integrity_cost(*egl, cluster_package(integrity_dir));
  fs::remove_all(integrity_dir);
  return 0;
}
