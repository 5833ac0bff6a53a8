// The integrity monitor in process, frame by frame: the cluster scene converted by meter-convert
// (its safety regions measured there), a Renderer on one backend, the binding evaluator and the
// monitor, driven by signal tables. Used by the detection-latency and false-alarm GL tests.
#pragma once

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/package_reader.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/backend.hpp"
#include "meter/protocol/signal_table.hpp"
#include "meter/runner/integrity_monitor.hpp"

namespace meter::testing {

// scenes/cluster converted once per test process into the build tree; returns the package path.
std::filesystem::path converted_cluster();

struct MonitorRig {
  MonitorRig(const std::filesystem::path& package, platform::BackendKind backend, int msaa);
  // One frame: the table's values applied (dt < 0: straight to the targets, no smoothing), the
  // frame rendered and checked. Returns that frame's faults.
  std::vector<runner::IntegrityFault> frame(const protocol::SignalTable& table, double dt = -1.0);
  // The frame's state at `fraction` of every binding's range (bound_signals_at; every needle at
  // that fraction of its own dial).
  protocol::SignalTable at(double fraction) const;
  static void set(protocol::SignalTable& table, const std::string& signal, double value);

  engine::Scene scene;
  std::unique_ptr<platform::GpuBackend> backend;
  std::unique_ptr<engine::Renderer> renderer;
  std::unique_ptr<engine::BindingEvaluator> evaluator;
  std::unique_ptr<runner::IntegrityMonitor> monitor;
};

// The first region of that kind in the table (nullptr when none).
const bridge::SafetyRegion* first_region(const bridge::IntegrityTable& table, bridge::SafetyKind kind);

}  // namespace meter::testing
