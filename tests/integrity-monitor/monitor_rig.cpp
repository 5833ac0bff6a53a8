#include "monitor_rig.hpp"

#include <stdexcept>

#include "bound_signals.hpp"
#include "process.hpp"

namespace fs = std::filesystem;

namespace meter::testing {

fs::path converted_cluster() {
  static const fs::path msp = [] {
    const fs::path dir = fs::path(METER_BINARY_DIR) / "integrity-monitor";
    fs::create_directories(dir);
    const fs::path out = dir / "cluster.msp";
    const std::string src = METER_SOURCE_DIR;
    ChildProcess convert({built_executable("meter-convert"), src + "/scenes/cluster/cluster.glb", "--config",
                          src + "/scenes/cluster/cluster.scene.json", "-o", out.string()},
                         (dir / "convert.log").string());
    const auto rc = convert.wait_for(std::chrono::seconds(300));
    if (!rc || *rc != 0) throw std::runtime_error("meter-convert of the cluster failed:\n" + convert.log());
    return out;
  }();
  return msp;
}

MonitorRig::MonitorRig(const fs::path& package, platform::BackendKind kind, int msaa)
    : scene(engine::read_package(package.string())), backend(platform::create_backend(kind)) {
  engine::RendererOptions ro;
  ro.msaa = msaa;
  renderer = std::make_unique<engine::Renderer>(*backend, scene, ro);
  evaluator = std::make_unique<engine::BindingEvaluator>(scene);
  monitor = std::make_unique<view::IntegrityMonitor>(scene, renderer->width(), renderer->height());
}

std::vector<view::IntegrityFault> MonitorRig::frame(const protocol::SignalTable& table, double dt) {
  evaluator->update(table, true, dt);
  renderer->apply(evaluator->outputs());
  const auto timing = renderer->render();
  return monitor->check(*renderer, *evaluator, timing.drawn);
}

protocol::SignalTable MonitorRig::at(double fraction) const { return bound_signals_at(scene.config, fraction); }

const bridge::SafetyRegion* first_region(const bridge::IntegrityTable& table, bridge::SafetyKind kind) {
  for (const auto& r : table.regions)
    if (r.kind == kind) return &r;
  return nullptr;
}

}  // namespace meter::testing
