// view_bench --integrity: the display-integrity monitor's cost (meter/runner/integrity_monitor.hpp)
// against the frame it checks, measured side by side in one run: the cluster at 1280x480 MSAA 4
// on llvmpipe (EGL) through the 3b drive (needles moving, an indicator blinking, partial redraw as
// meter-view draws), each frame's render and the monitor's check timed apart; and the same scene
// and drive without safety regions, where the monitor is off and must cost nothing.
#include "integrity_bench.hpp"

#include <algorithm>
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/runner/integrity_monitor.hpp"
#include "bench_stats.hpp"

namespace meter::bench {

namespace {

using Clock = std::chrono::steady_clock;

// CPU time of the whole process (llvmpipe's rasterizer threads included), ms: what a frame costs
// the machine, less sensitive than wall time to other processes' load.
double cpu_ms() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return double(ts.tv_sec) * 1e3 + double(ts.tv_nsec) * 1e-6;
}

struct Cost {
  double frame_ms = 0, monitor_ms = 0, frame_cpu_ms = 0;
  std::size_t regions = 0;
  std::uint64_t faults = 0, regions_read = 0, needles_whole = 0;
};

// One scene's renderer, evaluator and monitor (safe path off: this measures the checking; a
// faulty frame's recovery, a full redraw, is not the monitor's steady cost).
struct Rig {
  Rig(platform::GpuBackend& backend, const engine::Scene& scene, int msaa, bool blit)
      : scene(scene), renderer(backend, scene, options(msaa, blit)), evaluator(scene),
        monitor(scene, renderer.width(), renderer.height(), true, false) {}
  static engine::RendererOptions options(int msaa, bool blit) {
    engine::RendererOptions o;
    o.width = 1280, o.height = 480, o.msaa = msaa, o.box_resolve_by_blit = blit;
    return o;
  }
  void frame(const protocol::SignalTable& values, double dt, bool keep) {
    if (evaluator.update(values, true, dt)) renderer.apply(evaluator.outputs());  // changes detected once
    // As meter-view's live loop: the monitor names what it will read before the frame renders
    // (the resolve of those boxes joins the frame's flush and is timed as render time), checks
    // after it.
    const double c0 = cpu_ms();
    const auto t0 = Clock::now();
    monitor.prepare(renderer, evaluator);
    const double prepare_ms = ms_since(t0);
    const auto t1 = Clock::now();
    renderer.render(false, false);
    const double render_ms = ms_since(t1);
    const auto t2 = Clock::now();
    monitor.check(renderer, evaluator);
    const double check_ms = ms_since(t2);
    const double cpu = cpu_ms() - c0;
    if (!keep) return;
    frame_cpu_ms.push_back(cpu);
    frame_ms.push_back(prepare_ms + render_ms + check_ms);
    monitor_ms.push_back(prepare_ms + check_ms);
  }
  Cost cost() const {
    return {median(frame_ms), median(monitor_ms), median(frame_cpu_ms), monitor.on() ? scene.integrity.regions.size() : 0, monitor.faults(),
            monitor.regions_read(), monitor.needles_read_whole()};
  }
  const engine::Scene& scene;
  engine::Renderer renderer;
  engine::BindingEvaluator evaluator;
  runner::IntegrityMonitor monitor;
  std::vector<double> frame_ms, monitor_ms, frame_cpu_ms;
};

// The 3b drive, the scene with and the scene without regions drawn in turn frame by frame.
std::pair<Cost, Cost> measure(platform::GpuBackend& backend, const engine::Scene& with, const engine::Scene& without,
                              int msaa, bool blit, int frames) {
  Rig a(backend, with, msaa, blit), b(backend, without, msaa, blit);
  protocol::SignalTable values;
  auto set = [&](std::string_view name, double v) {
    if (const auto* info = protocol::find_signal(name)) values.set(info->id, {v, protocol::SignalStatus::Valid, ""});
  };
  for (int f = 0; f < frames; ++f) {
    const double t = f / 60.0;
    set("Vehicle.Speed", 20.0 + 12.0 * t);
    set("Vehicle.Powertrain.CombustionEngine.Speed", 1500.0 + 500.0 * std::fmod(t, 2.0));
    set("Vehicle.Powertrain.FuelSystem.RelativeLevel", 60.0 - 0.2 * t);
    set("Vehicle.Powertrain.CombustionEngine.ECT", 85.0 + t);
    set("Cluster.Telltale.TurnLeft", std::fmod(t, 0.666) < 0.333 ? 1.0 : 0.0);
    const double dt = f == 0 ? -1.0 : 1.0 / 60.0;
    a.frame(values, dt, f >= 2);  // frames 0-1: JIT of every program
    b.frame(values, dt, f >= 2);
  }
  return {a.cost(), b.cost()};
}

}  // namespace

void integrity_cost(platform::GpuBackend& backend, const engine::Scene& cluster) {
  engine::Scene bare = cluster;
  bare.integrity = {};
  // A blit resolves only the box of 8-bit samples: the blit row draws the cluster resolved so.
  engine::Scene boxed = cluster, boxed_bare = bare;
  boxed.config.resolve = {}, boxed_bare.config.resolve = {};
  std::printf("\n## 5. integrity monitor, 1280x480 on EGL, 300-frame drive, with and without regions in turn\n");
  std::printf("%-31s %7s %13s %13s %7s %10s %11s %13s %12s %11s %6s\n", "scene", "regions", "frame median", "check median",
              "ratio", "read/frame", "whole/frame", "frame CPU", "wall vs none", "CPU vs none", "faults");
  // MSAA 4 twice: resolved by the shader pass (meter-view's), and by glBlitFramebuffer (the
  // baseline: llvmpipe runs each blit as a rasterizer pass of its own).
  for (const auto& [msaa, blit] : {std::pair{4, false}, std::pair{4, true}, std::pair{1, false}}) {
    const auto [c, z] = blit ? measure(backend, boxed, boxed_bare, msaa, blit, 300) : measure(backend, cluster, bare, msaa, blit, 300);
    const std::string config = "cluster MSAA " + std::to_string(msaa) + (blit ? " blit" : "");
    for (const auto& [name, k] : {std::pair<std::string, const Cost&>{config, c}, {config + ", no regions", z}})
      std::printf("%-31s %7zu %10.3f ms %10.4f ms %6.2f%% %10.1f %11.2f %10.3f ms %11.2f%% %10.2f%% %6llu\n", name.c_str(),
                  k.regions, k.frame_ms, k.monitor_ms, 100.0 * k.monitor_ms / k.frame_ms, double(k.regions_read) / 298.0,
                  double(k.needles_whole) / 298.0, k.frame_cpu_ms, 100.0 * (k.frame_ms - z.frame_ms) / z.frame_ms,
                  100.0 * (k.frame_cpu_ms - z.frame_cpu_ms) / z.frame_cpu_ms, static_cast<unsigned long long>(k.faults));
  }
  std::printf("(frame = prepare + render + check, wall time; ratio = (prepare + check) / frame, medians; read/frame:\n"
              " regions read back per frame; whole/frame: needle regions read whole, not through their window;\n"
              " wall / CPU vs none: the frame's median wall time / process CPU time (llvmpipe's threads included)\n"
              " against the same drive without regions, which also counts the resolve of the monitor's boxes that\n"
              " render() does with the frame; MSAA 4 blit: the box of 8-bit samples resolved by glBlitFramebuffer\n"
              " instead of the scene's own resolve, a shader pass; goal: at most 5 %% at MSAA 4 and 1)\n");
}

}  // namespace meter::bench
