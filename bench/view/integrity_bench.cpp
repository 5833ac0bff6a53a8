// view_bench --integrity: the display-integrity monitor's cost (meter/view/integrity_monitor.hpp)
// against the frame it checks, measured side by side in one run: the cluster at 1280x480 MSAA 4
// on llvmpipe (EGL) through the 3b drive (needles moving, an indicator blinking, partial redraw as
// meter-view draws), each frame's render and the monitor's check timed apart; and the same scene
// and drive without safety regions, where the monitor is off and must cost nothing.
#include "integrity_bench.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/view/integrity_monitor.hpp"

namespace meter::bench {

namespace {

using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }
double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

struct Cost {
  double frame_ms = 0, monitor_ms = 0;
  std::size_t regions = 0;
  std::uint64_t faults = 0;
};

Cost measure(platform::GpuBackend& backend, const engine::Scene& scene, int frames) {
  engine::RendererOptions o;
  o.width = 1280, o.height = 480, o.msaa = 4;
  engine::Renderer r(backend, scene, o);
  engine::BindingEvaluator ev(scene);
  view::IntegrityMonitor monitor(scene, r.width(), r.height());
  protocol::SignalTable values;
  auto set = [&](std::string_view name, double v) {
    if (const auto* info = protocol::find_signal(name)) values.set(info->id, {v, protocol::SignalStatus::Valid, ""});
  };
  std::vector<double> frame_ms, monitor_ms;
  for (int f = 0; f < frames; ++f) {
    const double t = f / 60.0;
    set("Vehicle.Speed", 20.0 + 12.0 * t);
    set("Vehicle.Powertrain.CombustionEngine.Speed", 1500.0 + 500.0 * std::fmod(t, 2.0));
    set("Vehicle.Powertrain.FuelSystem.RelativeLevel", 60.0 - 0.2 * t);
    set("Vehicle.Powertrain.CombustionEngine.ECT", 85.0 + t);
    set("Cluster.Telltale.TurnLeft", std::fmod(t, 0.666) < 0.333 ? 1.0 : 0.0);
    ev.update(values, true, f == 0 ? -1.0 : 1.0 / 60.0);
    r.apply(ev.outputs());
    const auto t0 = Clock::now();
    const auto timing = r.render(false, false);
    const double render_ms = ms_since(t0);
    const auto t1 = Clock::now();
    monitor.check(r, ev, timing.drawn);
    const double check_ms = ms_since(t1);
    if (f < 2) continue;  // JIT of every program at the first frames
    frame_ms.push_back(render_ms + check_ms);
    monitor_ms.push_back(check_ms);
  }
  return {median(frame_ms), median(monitor_ms), monitor.on() ? scene.integrity.regions.size() : 0, monitor.faults()};
}

}  // namespace

void integrity_cost(platform::GpuBackend& backend, const engine::Scene& cluster) {
  engine::Scene bare = cluster;
  bare.integrity = {};
  std::printf("\n## 5. integrity monitor, 1280x480 MSAA 4 on EGL, 300-frame drive (frame = render + check)\n");
  std::printf("%-22s %8s %14s %14s %10s %8s\n", "scene", "regions", "frame median", "check median", "ratio", "faults");
  const Cost c = measure(backend, cluster, 300);
  const Cost z = measure(backend, bare, 300);
  for (const auto& [name, k] : {std::pair<const char*, const Cost&>{"cluster", c}, {"cluster, no regions", z}})
    std::printf("%-22s %8zu %11.3f ms %11.4f ms %9.2f%% %8llu\n", name, k.regions, k.frame_ms, k.monitor_ms,
                100.0 * k.monitor_ms / k.frame_ms, static_cast<unsigned long long>(k.faults));
  std::printf("(goal: check <= 5 %% of the median frame; a scene without safety regions: nothing read)\n");
}

}  // namespace meter::bench
