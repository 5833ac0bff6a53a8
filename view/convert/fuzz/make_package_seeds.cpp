// Writes the seed packages of the package reader's fuzz target, from the current writer: converts
// each glTF given (with the scene config beside it, NAME.scene.json or scene.json, else an empty
// config), with the draw levels as meter-convert writes them, and writes OUT_DIR/<n>.msp. The build
// runs it (view/convert/fuzz/CMakeLists.txt) whenever the converter or an input changes, so the
// seeds are always of the format the reader reads:
//   meter_fuzz_package_seeds [--max-bytes N] OUT_DIR GLTF...
// Every seed is read back with the runtime's reader first: one it refuses (or one that makes it
// skip a chunk) fails the run, and with it the build. Packages over N bytes (the target's MAX_LEN)
// are left out: libFuzzer would cut them short. Earlier seeds in OUT_DIR are removed.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include "meter/config/scene_config_parser.hpp"
#include "meter/convert/converter.hpp"
#include "meter/convert/levels.hpp"
#include "meter/convert/package_writer.hpp"
#include "meter/engine/package_reader.hpp"

namespace fs = std::filesystem;

namespace {

meter::bridge::SceneConfig config_beside(const fs::path& gltf) {
  for (const fs::path& c : {fs::path(gltf).replace_extension(".scene.json"), gltf.parent_path() / "scene.json"})
    if (fs::exists(c)) return meter::config::load_scene_config(c.string());
  return meter::config::parse_scene_config(R"({"format": "meter-scene-config/1"})");
}

}  // namespace

int main(int argc, char** argv) {
  int first = 1;
  std::size_t max_bytes = SIZE_MAX;
  if (argc > 2 && std::string(argv[1]) == "--max-bytes") max_bytes = std::stoul(argv[2]), first = 3;
  if (argc < first + 2) {
    std::cerr << "usage: meter_fuzz_package_seeds [--max-bytes N] OUT_DIR GLTF...\n";
    return 2;
  }
  const fs::path out = argv[first];
  fs::create_directories(out);
  for (const auto& old : fs::directory_iterator(out))
    if (old.path().extension() == ".msp") fs::remove(old.path());
  int written = 0;
  for (int i = first + 1; i < argc; ++i) {
    const fs::path gltf = argv[i];
    std::vector<std::uint8_t> bytes;
    try {
      auto r = meter::convert::convert_gltf(gltf.string(), config_beside(gltf), {.optimize = true});
      meter::convert::make_levels(r.scene);
      bytes = meter::convert::serialize_scene(r.scene);
    } catch (const std::exception& e) {
      std::cerr << gltf << ": skipped: " << e.what() << "\n";
      continue;
    }
    if (bytes.size() > max_bytes) {
      std::cerr << gltf << ": skipped: its package is " << bytes.size() << " bytes, over the target's " << max_bytes << "\n";
      continue;
    }
    try {
      meter::engine::PackageNotes notes;
      meter::engine::deserialize_scene(bytes, gltf.string() + " (seed)", &notes);
      if (!notes.empty()) throw meter::bridge::SceneError(notes.front());
    } catch (const std::exception& e) {
      std::cerr << "meter_fuzz_package_seeds: the reader refuses the writer's package of " << gltf << ": " << e.what() << "\n";
      return 1;
    }
    std::ofstream file(out / (std::to_string(written++) + ".msp"), std::ios::binary);
    file.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    if (!file) {
      std::cerr << "meter_fuzz_package_seeds: cannot write into " << out << "\n";
      return 1;
    }
  }
  if (written == 0) {
    std::cerr << "meter_fuzz_package_seeds: no seed written\n";
    return 1;
  }
  std::cout << written << " seed package(s) in " << out << "\n";
  return 0;
}
