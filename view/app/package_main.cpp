// meter-package dump PACKAGE: every record of a scene package as text (meter/engine/package_dump.hpp),
// read with the runtime's own package reader.
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>

#include "meter/engine/package_dump.hpp"
#include "meter/engine/package_reader.hpp"

int main(int argc, char** argv) {
  CLI::App app{"meter-package: look into a scene package (.msp) written by meter-convert"};
  app.require_subcommand(1);
  std::string package;
  CLI::App* dump = app.add_subcommand("dump", "print every field of every record, one \"path = value\" line each");
  dump->add_option("package", package, "scene package (.msp)")->required();
  CLI11_PARSE(app, argc, argv);
  try {
    std::cout << meter::engine::dump_scene(meter::engine::read_package(package));
  } catch (const std::exception& e) {
    std::cerr << "meter-package: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
