#include "meter/convert/convert_tool.hpp"

#include <fstream>
#include <sstream>

#include "meter/convert/converter.hpp"
#include "meter/convert/integrity.hpp"
#include "meter/convert/levels.hpp"
#include "meter/convert/package_writer.hpp"
#include "meter/config/scene_config_parser.hpp"
#include "meter/protocol/catalog.hpp"

namespace meter::convert {

namespace {

// The break-even test's costs from a meter-calibrate cost file; a file without them is refused.
ConcatenationCosts merge_costs_from(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  if (!in) throw SceneError(path + ": cannot read the cost file (--costs)");
  const engine::governor::CostFile file = engine::governor::parse_costs(text.str(), path);
  if (!file.concatenation)
    throw SceneError(path + ": $.concatenation: expected the concatenation costs (draw_ms, vertex_ms, transform_ms); "
                     "recalibrate with this build's meter-calibrate");
  return *file.concatenation;
}

}  // namespace

int run_convert_tool(const ToolOptions& o, std::ostream& out, std::ostream& err) {
  try {
    const auto catalog = protocol::use_catalog_option(o.catalog);
    const auto config = meter::config::load_scene_config(o.config, *catalog);
    ConvertOptions opt;
    opt.optimize = o.optimize == "on";
    opt.propose_groups = o.propose_groups;
    if (!o.costs.empty()) opt.merge_costs = merge_costs_from(o.costs);
    auto result = convert_gltf(o.input, config, opt);
    if (!o.quiet) {
      for (const auto& r : result.repairs) err << o.input << ": warning: " << r.path << ": " << r.message << "\n";
    }
    IntegrityMeasurement integrity;
    if (o.integrity != "off") {
      const auto kind = platform::parse_backend_kind(o.integrity);
      if (!kind) throw SceneError("--integrity: unknown backend \"" + o.integrity + "\" (egl, osmesa or off)");
      try {
        const auto backend = platform::create_backend(*kind);
        integrity = measure_integrity(result.scene, *backend);
      } catch (const std::exception& e) {
        throw SceneError(std::string("measuring the safety regions on ") + o.integrity + ": " + e.what() +
                         " (--integrity=osmesa measures in software, --integrity=off writes no integrity table)");
      }
      result.scene.integrity = integrity.table;
      if (!o.quiet) {
        for (const auto& s : integrity.skipped) err << o.input << ": warning: not monitored: " << s << "\n";
      }
    }
    // After the integrity table: the safety regions it names get no levels.
    LevelsReport levels;
    if (o.levels == "on") {
      LevelOptions lo;
      lo.optimize = opt.optimize;
      levels = make_levels(result.scene, lo);
    } else if (o.levels != "off") {
      throw SceneError("--levels: \"" + o.levels + "\", expected on or off");
    }
    write_package(result.scene, o.output);
    if (o.report) out << program_report(result.scene) << result.concat_report << integrity_report(integrity);
    if (o.report && o.levels == "on") out << levels_report(result.scene, levels);
    err << "meter-convert: wrote " << o.output << " (" << result.scene.draws.size() << " draws, "
        << result.scene.programs.size() << " programs, " << result.scene.groups.size() << " merged groups, " << result.scene.integrity.regions.size() << " safety regions, "
        << levels.lod_levels << " LOD levels, " << levels.shading_levels << " shading levels, "
        << result.repairs.size() << " repairs)\n";
  } catch (const std::exception& e) {
    err << "meter-convert: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace meter::convert
