// meter-calibrate PACKAGE [--out FILE] [--backend egl|osmesa] [--frames N] [--size WxH] [--msaa N] [--samples CSV]:
// the cost of every draw unit at every level and of each global rung, measured on this machine,
// written as the meter-costs/1 file meter-view --target-ms reads (docs/uniform-frame-rate.md).
#include <iostream>

#include <CLI/CLI.hpp>

#include "meter/calibrate/calibrate_tool.hpp"

int main(int argc, char** argv) {
  meter::calibrate::CalibrateToolOptions o;
  CLI::App app{"meter-calibrate: measure a scene package's draw costs per level on this machine (meter-costs/1)"};
  app.add_option("package", o.package, "scene package written by meter-convert (.msp)")->required()->check(CLI::ExistingFile);
  app.add_option("--out,-o", o.out, "cost file to write (default: PACKAGE.costs.json beside the package)");
  app.add_option("--backend", o.backend, "egl or osmesa: the backend meter-view will draw with")
      ->check(CLI::IsMember({"egl", "osmesa"}))->capture_default_str();
  app.add_option("--frames", o.frames, "timed frames per point (their median is used)")->check(CLI::Range(1, 1000))->capture_default_str();
  app.add_option("--size", o.size, "render size WxH (default: the scene config's size), as meter-view --size");
  app.add_option("--msaa", o.msaa, "MSAA samples of full quality, as meter-view --msaa")->check(CLI::IsMember({1, 2, 4}))->capture_default_str();
  app.add_option("--samples", o.samples, "also write every timed point to this CSV (kind, unit, level, node scale, pixels, ms)");
  CLI11_PARSE(app, argc, argv);
  return meter::calibrate::run_calibrate_tool(o, std::cout, std::cerr);
}
