#include "meter/calibrate/calibrate_tool.hpp"

#include <chrono>
#include <filesystem>
#include <fstream>

#include "meter/calibrate/calibration.hpp"
#include "meter/calibrate/shading_ladder.hpp"
#include "meter/engine/package_reader.hpp"
#include "meter/runner/governed_frame.hpp"
#include "meter/runner/option_units.hpp"

namespace meter::calibrate {

namespace {

// Every timed point, for a look at the fits: level rows (unit alone minus nothing drawn) and rung
// rows (the whole frame), per node scale.
void write_samples(const std::string& path, const CostMeasurements& m, const CalibrationOptions& o) {
  std::ofstream out(path);
  out << "kind,unit,level,node_scale,pixels,ms\n";
  for (const auto& l : m.levels) {
    const auto& ladder = m.ladders.at(static_cast<std::size_t>(l.unit));
    for (std::size_t k = 0; k < l.samples.size(); ++k)
      out << "level," << ladder.name << "," << bridge::to_string(ladder.shadings.at(static_cast<std::size_t>(l.level.shading)))
          << "/lod" << l.level.lod << "," << o.node_scales.at(k) << "," << l.samples[k].pixels << "," << l.samples[k].ms << "\n";
  }
  for (const auto& r : m.rungs)
    for (std::size_t k = 0; k < r.frame_ms.size(); ++k)
      out << "rung,,msaa" << r.level.msaa << "/scale" << r.level.scale << "," << o.node_scales.at(k) << ",," << r.frame_ms[k] << "\n";
  out << "empty,,,1,," << m.empty_ms << "\n";
  out.close();
  if (!out) throw std::runtime_error(path + ": cannot write the samples (--samples)");
}

}  // namespace

int run_calibrate_tool(const CalibrateToolOptions& options, std::ostream& out, std::ostream& err) {
  try {
    const auto began = std::chrono::steady_clock::now();
    const auto kind = platform::parse_backend_kind(options.backend);
    if (!kind) throw std::invalid_argument("--backend: unknown backend \"" + options.backend + "\" (egl or osmesa)");
    const engine::Scene scene = engine::read_package(options.package);
    auto backend = platform::create_backend(*kind);
    CalibrationOptions co;
    co.frames = options.frames;
    co.msaa = options.msaa;
    if (!options.size.empty()) std::tie(co.width, co.height) = runner::parse_size(options.size);
    CostMeasurements m = measure_costs(*backend, scene, co, &out);
    m.package = std::filesystem::path(options.package).filename().string();
    if (!options.samples.empty()) write_samples(options.samples, m, co);
    const std::string path = options.out.empty() ? runner::default_costs_path(options.package) : options.out;
    const std::string text = engine::governor::write_costs(cost_file(m));
    // Checked as meter-view will read it: a file this tool cannot parse back is never left behind.
    engine::governor::parse_costs(text, path);
    std::ofstream file(path);
    file << text;
    file.close();
    if (!file) throw std::runtime_error(path + ": cannot write the cost file");
    out << shading_ladder_table(m);
    if (m.concatenation)
      out << "concatenation costs (DENSO eq. 1-3): oh = " << m.concatenation->draw_ms << " ms/draw, m = " << m.concatenation->vertex_ms
          << " ms/vertex, s = " << m.concatenation->transform_ms << " ms/merged vertex moved\n";
    std::size_t levels = m.levels.size();
    out << "meter-calibrate: " << m.ladders.size() << " draw units, " << levels << " unit levels, " << m.rungs.size()
        << " global rungs measured on " << backend->renderer_info() << " in "
        << std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count() << " s -> " << path << "\n";
    return 0;
  } catch (const std::exception& e) {
    err << "meter-calibrate: error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace meter::calibrate
