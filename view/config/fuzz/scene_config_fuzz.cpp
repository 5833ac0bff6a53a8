// Fuzzes the scene-config parser the way the converter and meter-view use a config: parse the
// JSON, resolve it against a fixed scene (scenes/minimal-gauge, converted once per process) as
// meter-convert does, then run that scene with the fuzzed config through the bindings and scene
// evaluation for a few frames. Every rejection must be std::invalid_argument (parse) or
// SceneError (a name the scene lacks), naming the file.
#include <cstdlib>
#include <cstring>
#include <span>
#include <stdexcept>
#include <string>

#include "exercise_scene.hpp"
#include "meter/config/scene_config_parser.hpp"
#include "meter/convert/converter.hpp"

namespace {

const meter::bridge::Scene& gauge_scene() {
  static const meter::bridge::Scene scene = [] {
    const std::string dir = std::string(METER_SOURCE_DIR) + "/scenes/minimal-gauge/";
    const auto config = meter::config::load_scene_config(dir + "minimal-gauge.scene.json");
    return meter::convert::convert_gltf(dir + "minimal-gauge.glb", config, {.optimize = false}).scene;
  }();
  return scene;
}

}  // namespace

// The scene is converted before fuzzing starts, so its conversion does not count against the
// first input's time limit.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  (void)gauge_scene();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  meter::bridge::Scene scene = gauge_scene();
  try {
    scene.config = meter::config::parse_scene_config(text, "fuzz.scene.json");
    meter::convert::resolve_config(scene, scene.config, "fuzz.scene.json");
  } catch (const std::invalid_argument& e) {
    if (!std::strstr(e.what(), "fuzz.scene.json")) std::abort();
    return 0;
  } catch (const meter::bridge::SceneError& e) {
    if (!std::strstr(e.what(), "fuzz.scene.json")) std::abort();
    return 0;
  }
  meter::engine::fuzz::exercise_scene(scene, std::span<const std::uint8_t>(data, std::min<std::size_t>(size, 64)));
  return 0;
}
