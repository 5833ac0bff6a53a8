// meter-convert IN.gltf|IN.glb --config SCENE.json -o OUT.msp [--report] [--optimize=off|on] [--integrity=egl|osmesa|off] [--levels=on|off] [--costs FILE]
#include <iostream>

#include <CLI/CLI.hpp>

#include "meter/convert/convert_tool.hpp"

int main(int argc, char** argv) {
  meter::convert::ToolOptions o;
  CLI::App app{"meter-convert: glTF 2.0 + scene config -> meter scene package (.msp) with generated shaders"};
  app.add_option("input", o.input, "glTF 2.0 scene (.gltf or .glb)")->required()->check(CLI::ExistingFile);
  app.add_option("--config,-c", o.config, "scene config JSON (meter-scene-config/1, docs/scene-config.md)")
      ->required()->check(CLI::ExistingFile);
  app.add_option("-o,--output", o.output, "output scene package (.msp)")->required();
  app.add_flag("--report", o.report, "list each generated program: features, SPIR-V instruction and uniform counts; the merged groups, safety regions and levels");
  app.add_option("--optimize", o.optimize, "fold scene constants into the programs (shadergen::optimize)")
      ->check(CLI::IsMember({"on", "off"}));
  app.add_option("--catalog", o.catalog,
                 "signal catalog (VSS JSON, docs/catalog.md) the bindings must name; default: the built-in one")
      ->check(CLI::ExistingFile);
  app.add_option("--integrity", o.integrity,
                 "GL backend the safety regions (telltales, needles, readouts) are measured on, or off (docs/integrity.md)")
      ->check(CLI::IsMember({"egl", "osmesa", "off"}));
  app.add_option("--levels", o.levels,
                 "store cheaper LOD and shading levels of every non-safety draw for the frame-rate governor (docs/engine.md)")
      ->check(CLI::IsMember({"on", "off"}));
  app.add_flag("-q,--quiet", o.quiet, "do not print repairs (warnings)");
  app.add_flag("--propose-groups", o.propose_groups,
               "merge ungrouped objects automatically (same material and blend state, no overlap; docs/concatenation.md)");
  app.add_option("--costs", o.costs,
                 "meter-calibrate's cost file (meter-costs/1): merge a group only where the DENSO break-even test says it pays "
                 "(docs/concatenation.md); without it every allowed group is merged")
      ->check(CLI::ExistingFile);
  CLI11_PARSE(app, argc, argv);
  return meter::convert::run_convert_tool(o, std::cout, std::cerr);
}
