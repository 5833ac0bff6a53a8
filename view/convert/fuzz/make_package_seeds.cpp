// Writes seed packages for the package reader's fuzz target: converts each glTF given (with the
// scene config beside it, NAME.scene.json or scene.json, else an empty config) and writes
// OUT_DIR/<n>.msp. Run it after a package-format change, then minimise into view/engine/fuzz/corpus:
//   meter_fuzz_package_seeds /tmp/seeds scenes/minimal-gauge/minimal-gauge.glb ...
//   scripts/fuzz --minimise package /tmp/seeds
#include <filesystem>
#include <iostream>
#include <string>

#include "meter/config/scene_config_parser.hpp"
#include "meter/convert/converter.hpp"
#include "meter/convert/levels.hpp"
#include "meter/convert/package_writer.hpp"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  if (argc < 3) {
    std::cerr << "usage: meter_fuzz_package_seeds OUT_DIR GLTF...\n";
    return 2;
  }
  const fs::path out = argv[1];
  fs::create_directories(out);
  int written = 0;
  for (int i = 2; i < argc; ++i) {
    const fs::path gltf = argv[i];
    meter::bridge::SceneConfig config = meter::bridge::parse_scene_config(R"({"format": "meter-scene-config/1"})");
    for (const fs::path& c : {fs::path(gltf).replace_extension(".scene.json"), gltf.parent_path() / "scene.json"}) {
      if (fs::exists(c)) {
        config = meter::bridge::load_scene_config(c.string());
        break;
      }
    }
    try {
      auto r = meter::convert::convert_gltf(gltf.string(), config, {.optimize = true});
      // With the draw levels (format 5), as meter-convert writes packages by default.
      meter::convert::make_levels(r.scene);
      meter::convert::write_package(r.scene, (out / (std::to_string(written++) + ".msp")).string());
    } catch (const std::exception& e) {
      std::cerr << gltf << ": skipped: " << e.what() << "\n";
    }
  }
  std::cout << written << " package(s) in " << out << "\n";
  return 0;
}
