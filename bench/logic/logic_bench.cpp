// logic_bench: what the scene scripts cost per frame, next to the frame they are part of, in one
// run. The shipped cluster (1280x480, MSAA 4, EGL) with four cluster scripts added (bench/logic/
// scripts: a gear-dependent shift light, a two-signal coolant warning, a needle turning red above
// a limit, the gear readout), driven through a synthetic drive in which every script input
// changes every frame (the worst case: each script runs each frame). Per frame, side by side:
//   bindings only   BindingEvaluator::update on the same scene without its scripts;
//   with scripts    the same update with the four scripts (bindings + scripts);
//   scripts         the scripts' own measured run time (ScriptStats, summed);
//   frame           apply + render of the scripted frame (GPU wait included, no readback).
// Usage: logic_bench [frames]   (default 600)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "meter/config/scene_config_parser.hpp"
#include "meter/convert/converter.hpp"
#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/logic/scripts.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/backend.hpp"

namespace {

using namespace meter;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
namespace sig = protocol::sig;

double us_since(Clock::time_point t) { return std::chrono::duration<double, std::micro>(Clock::now() - t).count(); }

struct Summary {
  double median = 0, p99 = 0, mean = 0;
};
Summary summarise(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  Summary s;
  auto at = [&](double p) { return v[std::min(v.size() - 1, static_cast<std::size_t>(p * double(v.size() - 1) + 0.5))]; };
  s.median = at(0.5), s.p99 = at(0.99);
  for (double x : v) s.mean += x / double(v.size());
  return s;
}

// The shipped cluster config with the four scripts (files under bench/logic/scripts).
std::string scripted_config() {
  const fs::path root(METER_SOURCE_DIR);
  std::ifstream in(root / "scenes/cluster/cluster.scene.json");
  std::stringstream ss;
  ss << in.rdbuf();
  nlohmann::json c = nlohmann::json::parse(ss.str());
  c["scripts"] = nlohmann::json::parse(R"([
    {"name": "shift_light", "file": "scripts/shift_light.lua",
     "inputs": {"rpm": "Vehicle.Powertrain.CombustionEngine.Speed", "gear": "Vehicle.Powertrain.Transmission.CurrentGear"},
     "outputs": {"glow": {"property": "emissive", "material": "RedZone"}}},
    {"name": "coolant_warning", "file": "scripts/coolant_warning.lua",
     "inputs": {"coolant": "Vehicle.Powertrain.CombustionEngine.ECT", "rpm": "Vehicle.Powertrain.CombustionEngine.Speed"},
     "outputs": {"lamp": {"property": "visible", "node": "TT_CoolantTemp"}}},
    {"name": "needle_red", "file": "scripts/needle_red.lua", "inputs": {"speed": "Vehicle.Speed"},
     "outputs": {"colour": {"property": "color", "material": "Needle"}}},
    {"name": "gear_text", "file": "scripts/gear_text.lua", "inputs": {"gear": "Vehicle.Powertrain.Transmission.CurrentGear"},
     "outputs": {"gear": {"property": "text", "node": "Text_Gear", "size_px": 40, "align": "center", "failsafe": "-"}}}
  ])");
  return c.dump();
}

// A drive: speed swings 20..180 km/h, the gear follows the speed, the engine speed the gear's
// ratio (with a little noise so it changes every frame), the coolant warms from 80 to 120 C.
void drive(protocol::SignalTable& v, int frame, int frames) {
  const double t = frame / 60.0;
  const double speed = 100.0 + 80.0 * std::sin(t / 2.0) + 0.01 * frame;
  const int gear = std::clamp(1 + static_cast<int>(speed / 30.0), 1, 6);
  const double ratio[] = {0, 120, 75, 52, 40, 33, 28};
  const double rpm = 800.0 + speed * ratio[gear] + 3.0 * std::sin(frame * 1.7);
  const double coolant = 80.0 + 40.0 * frame / frames;
  auto set = [&](protocol::SignalId id, double x) { v.set(id, {x, protocol::SignalStatus::Valid, ""}); };
  set(sig::kSpeed, speed);
  set(sig::kCurrentGear, gear);
  set(sig::kEngineSpeed, rpm);
  set(sig::kCoolantTemp, coolant);
  set(sig::kFuelLevel, 60.0);
}

}  // namespace

int main(int argc, char** argv) {
  const int frames = argc > 1 ? std::max(10, std::atoi(argv[1])) : 600;
  const fs::path root(METER_SOURCE_DIR);
  // Script files resolve next to the config's origin: bench/logic.
  const auto config = meter::config::parse_scene_config(scripted_config(), (root / "bench/logic/cluster+scripts.json").string());
  const engine::Scene scripted =
      convert::convert_gltf((root / "scenes/cluster/cluster.glb").string(), config, convert::ConvertOptions{}).scene;
  engine::Scene plain = scripted;  // the same scene without its scripts
  plain.config.scripts.clear();

  auto backend = platform::create_backend(platform::BackendKind::Egl);
  engine::RendererOptions ro;
  ro.width = 1280, ro.height = 480, ro.msaa = 4;
  engine::Renderer renderer(*backend, scripted, ro);
  engine::BindingEvaluator with_scripts(scripted), bindings_only(plain);
  renderer.render(true, false);  // programs JIT-compiled before the measured frames

  protocol::SignalTable values;
  std::vector<double> plain_us, scripted_us, script_us, frame_us;
  const std::size_t n_scripts = with_scripts.scripts()->stats().size();
  std::vector<std::vector<double>> run_us(n_scripts);  // each script's runs, for their medians
  std::vector<std::uint64_t> runs_seen(n_scripts, 0);
  double scripts_before = 0;
  for (int f = 0; f < frames; ++f) {
    drive(values, f, frames);
    auto t = Clock::now();
    bindings_only.update(values, true, 1.0 / 60.0);
    plain_us.push_back(us_since(t));
    t = Clock::now();
    with_scripts.update(values, true, 1.0 / 60.0);
    scripted_us.push_back(us_since(t));
    double scripts_total = 0;
    for (std::size_t k = 0; k < n_scripts; ++k) {
      const auto& st = with_scripts.scripts()->stats()[k];
      scripts_total += st.total_ms;
      if (st.runs != runs_seen[k]) run_us[k].push_back(st.last_ms * 1000.0), runs_seen[k] = st.runs;
    }
    script_us.push_back((scripts_total - scripts_before) * 1000.0);
    scripts_before = scripts_total;
    t = Clock::now();
    renderer.apply(with_scripts.outputs());
    renderer.render(false, false);
    frame_us.push_back(us_since(t));
  }
  for (const auto& m : with_scripts.scripts()->take_messages()) std::printf("script message: %s\n", m.c_str());

  const Summary p = summarise(plain_us), w = summarise(scripted_us), s = summarise(script_us), fr = summarise(frame_us);
  std::printf("logic_bench: the cluster at 1280x480 MSAA 4 on %s, %d frames, every script input changing every frame\n",
              renderer.backend_info().c_str(), frames);
  std::printf("%-34s %10s %10s %10s\n", "per frame (us)", "median", "p99", "mean");
  std::printf("%-34s %10.1f %10.1f %10.1f\n", "bindings only (update)", p.median, p.p99, p.mean);
  std::printf("%-34s %10.1f %10.1f %10.1f\n", "bindings + 4 scripts (update)", w.median, w.p99, w.mean);
  std::printf("%-34s %10.1f %10.1f %10.1f\n", "  of which the scripts' runs", s.median, s.p99, s.mean);
  std::printf("%-34s %10.1f %10.1f %10.1f\n", "frame (apply + render)", fr.median, fr.p99, fr.mean);
  std::printf("scripts / frame: %.3f %% (median), update with / without scripts: %.2fx (median)\n",
              100.0 * s.median / (fr.median + w.median), w.median / std::max(1e-9, p.median));
  for (std::size_t k = 0; k < n_scripts; ++k) {
    const auto& st = with_scripts.scripts()->stats()[k];
    std::printf("  %-16s median run %5.1f us, p99 %7.1f us; %s\n", st.name.c_str(), summarise(run_us[k]).median,
                summarise(run_us[k]).p99, engine::describe(st).c_str());
  }
  return 0;
}
