#include "monitor_rig.hpp"

#include <unistd.h>

#include <stdexcept>
#include <string>

#include "bound_signals.hpp"
#include "process.hpp"

namespace fs = std::filesystem;

namespace meter::testing {

fs::path converted_cluster() {
  static const fs::path msp = [] {
    const fs::path dir = fs::path(METER_BINARY_DIR) / "integrity-monitor";
    fs::create_directories(dir);
    // Every test process of this folder converts into this one package at once; the converter's
    // write-then-rename makes that safe, and each process keeps its own log.
    const fs::path out = dir / "cluster.msp";
    const std::string src = METER_SOURCE_DIR;
    ChildProcess convert({built_executable("meter-convert"), src + "/scenes/cluster/cluster.glb", "--config",
                          src + "/scenes/cluster/cluster.scene.json", "-o", out.string()},
                         (dir / ("convert." + std::to_string(::getpid()) + ".log")).string());
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
  monitor = std::make_unique<runner::IntegrityMonitor>(scene, renderer->width(), renderer->height());
}

std::vector<runner::IntegrityFault> MonitorRig::frame(const protocol::SignalTable& table, double dt) {
  evaluator->update(table, true, dt);
  renderer->apply(evaluator->outputs());
  renderer->render();
  return monitor->check(*renderer, *evaluator);
}

protocol::SignalTable MonitorRig::at(double fraction) const {
  protocol::SignalTable t = bound_signals_at(scene.config, fraction);
  // A needle's signal bound twice (the speed: needle and readout) takes the needle's range here,
  // so every needle really turns over `fraction` of its dial.
  for (const auto& r : scene.integrity.regions) {
    if (r.kind != bridge::SafetyKind::Needle || r.bindings.empty()) continue;
    const auto& b = scene.config.bindings.at(static_cast<std::size_t>(r.bindings.front()));
    if (const auto* info = protocol::find_signal(b.signal))
      t.set(info->id, b.input[0] + fraction * (b.input[1] - b.input[0]), protocol::SignalStatus::Valid);
  }
  return t;
}

void MonitorRig::set(protocol::SignalTable& table, const std::string& signal, double value) {
  const auto* info = protocol::find_signal(signal);
  if (!info) throw std::runtime_error("no catalog signal " + signal);
  table.set(info->id, value, protocol::SignalStatus::Valid);
}

const bridge::SafetyRegion* first_region(const bridge::IntegrityTable& table, bridge::SafetyKind kind) {
  for (const auto& r : table.regions)
    if (r.kind == kind) return &r;
  return nullptr;
}

}  // namespace meter::testing
