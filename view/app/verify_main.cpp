// meter-verify SCENE.msp RUN_DIR [--junit FILE] [--backend egl|osmesa] [--msaa N]
#include <iostream>

#include <CLI/CLI.hpp>

#include "meter/verify/verify.hpp"

int main(int argc, char** argv) {
  meter::verify::VerifyOptions o;
  CLI::App app{"meter-verify: check every dumped frame of a meter-view run against the scene package's integrity table"};
  app.add_option("package", o.package, "scene package (.msp) the run was drawn from, written by meter-convert")->required();
  app.add_option("run", o.run_dir, "run folder: frames.csv and the PNGs meter-view dumped (live or offline)")->required();
  app.add_option("--junit", o.junit, "write JUnit XML here: one test case per frame and safety region");
  app.add_option("--backend", o.backend, "GL backend for the readouts' reference renders")
      ->check(CLI::IsMember({"egl", "osmesa"}));
  app.add_option("--msaa", o.msaa, "the run's meter-view --msaa (the reference renders use it too)")
      ->check(CLI::IsMember({1, 2, 4, 8}));
  CLI11_PARSE(app, argc, argv);
  return meter::verify::run_verify_tool(o, std::cout, std::cerr);
}
