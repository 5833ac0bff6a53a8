// Fuzzes the glTF converter the way meter-convert and meter-view use it, GL aside: the input is
// the artist's file (a .glb when it starts with the binary magic "glTF", else .gltf JSON), loaded
// by tinygltf and validated by the import stage, converted to a scene with its programs
// generated (the shader optimizer off: it only rewrites programs the generator already produced),
// written as a package in memory, read back by the runtime's package reader and evaluated for a
// few frames. A rejection must be a SceneError (ConvertError included); a scene the converter
// wrote must load.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>

#include "exercise_scene.hpp"
#include "meter/config/scene_config_parser.hpp"
#include "meter/convert/converter.hpp"
#include "meter/convert/package_writer.hpp"
#include "meter/engine/package_reader.hpp"

namespace {

// The converter reads a path; each fuzzing process writes its inputs into a directory of its own.
const std::filesystem::path& scratch_dir() {
  static const std::filesystem::path dir = [] {
    const char* tmp = std::getenv("TMPDIR");
    std::string tmpl = std::string(tmp && *tmp ? tmp : "/tmp") + "/meter-gltf-fuzz-XXXXXX";
    if (!mkdtemp(tmpl.data())) std::abort();
    std::atexit([] { std::filesystem::remove_all(scratch_dir()); });
    return std::filesystem::path(tmpl);
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const meter::bridge::SceneConfig config =
      meter::config::parse_scene_config(R"({"format": "meter-scene-config/1", "size": [64, 32]})", "fuzz-config");
  const bool binary = size >= 4 && std::memcmp(data, "glTF", 4) == 0;
  const std::string path = (scratch_dir() / (binary ? "fuzz.glb" : "fuzz.gltf")).string();
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    if (!out) std::abort();
  }
  meter::convert::ConvertResult converted;
  try {
    converted = meter::convert::convert_gltf(path, config, {.optimize = false});
  } catch (const meter::bridge::SceneError&) {
    return 0;
  }
  const std::vector<std::uint8_t> package = meter::convert::serialize_scene(converted.scene);
  // What the converter wrote, the runtime must read: a SceneError here escapes and is a finding.
  const meter::engine::Scene loaded = meter::engine::deserialize_scene(package, "fuzz.msp");
  meter::engine::fuzz::exercise_scene(loaded, std::span<const std::uint8_t>(data, std::min<std::size_t>(size, 64)));
  return 0;
}
