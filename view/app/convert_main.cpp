// meter-convert IN.gltf|IN.glb --config SCENE.json -o OUT.msp [--report] [--optimize=off|on]
#include <cstdio>
#include <iostream>

#include <CLI/CLI.hpp>

#include "meter/engine/converter.hpp"
#include "meter/engine/package.hpp"

int main(int argc, char** argv) {
  CLI::App app{"meter-convert: glTF 2.0 + scene config -> meter scene package (.msp) with generated shaders"};
  std::string input, config_path, output, optimize = "on";
  bool report = false, quiet = false;
  app.add_option("input", input, "glTF 2.0 scene (.gltf or .glb)")->required()->check(CLI::ExistingFile);
  app.add_option("--config,-c", config_path, "scene config JSON (meter-scene-config/1, docs/scene-config.md)")
      ->required()->check(CLI::ExistingFile);
  app.add_option("-o,--output", output, "output scene package (.msp)")->required();
  app.add_flag("--report", report, "list each generated program: features, SPIR-V instruction and uniform counts");
  app.add_option("--optimize", optimize, "fold scene constants into the programs (shadergen::optimize)")
      ->check(CLI::IsMember({"on", "off"}));
  app.add_flag("-q,--quiet", quiet, "do not print repairs (warnings)");
  bool propose_groups = false;
  app.add_flag("--propose-groups", propose_groups,
               "merge ungrouped objects automatically (same material and blend state, no overlap; docs/concatenation.md)");
  CLI11_PARSE(app, argc, argv);
  try {
    const auto config = meter::engine::load_scene_config(config_path);
    meter::engine::ConvertOptions opt;
    opt.optimize = optimize == "on";
    opt.propose_groups = propose_groups;
    auto result = meter::engine::convert_gltf(input, config, opt);
    if (!quiet) {
      for (const auto& r : result.repairs) std::cerr << input << ": warning: " << r.path << ": " << r.message << "\n";
    }
    meter::engine::write_package(result.scene, output);
    if (report) std::cout << meter::engine::program_report(result.scene) << result.concat_report;
    std::cerr << "meter-convert: wrote " << output << " (" << result.scene.draws.size() << " draws, "
              << result.scene.programs.size() << " programs, " << result.scene.groups.size() << " merged groups, " << result.repairs.size() << " repairs)\n";
  } catch (const std::exception& e) {
    std::cerr << "meter-convert: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
