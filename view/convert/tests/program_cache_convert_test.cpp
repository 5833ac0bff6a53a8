// The converter with a program cache kept across conversions (as meter-preview keeps one across
// reloads): the package is byte for byte the one a conversion without it writes, unchanged
// materials hit, and a recoloured material (other folded constants) is optimized afresh.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "meter/config/scene_config_parser.hpp"
#include "meter/convert/converter.hpp"
#include "meter/convert/package_writer.hpp"
#include "meter/shadergen/program_cache.hpp"
#include "test_scenes.hpp"

namespace meter::convert {
namespace {

using config::load_scene_config;
using config::parse_scene_config;

std::vector<std::uint8_t> package(const std::string& gltf, const SceneConfig& config, shadergen::ProgramCache* cache) {
  ConvertOptions o;
  o.program_cache = cache;
  return serialize_scene(convert_gltf(gltf, config, o).scene);
}

TEST(ConverterProgramCache, TheClusterReconvertedThroughTheCacheIsByteIdentical) {
  const std::string dir = std::string(METER_SOURCE_DIR) + "/scenes/cluster/";
  const SceneConfig config = meter::config::load_scene_config(dir + "cluster.scene.json");
  const auto fresh = package(dir + "cluster.glb", config, nullptr);
  shadergen::ProgramCache cache;
  const auto first = package(dir + "cluster.glb", config, &cache);
  const std::size_t programs = cache.size();
  EXPECT_GT(programs, 1u);
  EXPECT_EQ(cache.hits(), 0u);
  const auto again = package(dir + "cluster.glb", config, &cache);
  EXPECT_EQ(cache.hits(), programs);  // every program of the unchanged scene
  EXPECT_EQ(cache.misses(), programs);
  EXPECT_TRUE(first == fresh);
  EXPECT_TRUE(again == fresh);
}

TEST(ConverterProgramCache, ARecolouredMaterialMissesAndTheRestHits) {
  const std::string dir = engine::test::scratch_dir("convert_program_cache");
  const std::string gltf = engine::test::write_dial_scene(dir);
  const SceneConfig config = meter::config::parse_scene_config(engine::test::dial_config_json());
  shadergen::ProgramCache cache;
  package(gltf, config, &cache);
  const std::size_t programs = cache.size();
  // The needle's (unlit, unbound) base colour: a folded constant of its program only.
  nlohmann::json doc;
  std::ifstream(gltf) >> doc;
  bool recoloured = false;
  for (auto& m : doc["materials"]) {
    if (m.value("name", "") != "NeedleMat") continue;
    m["pbrMetallicRoughness"]["baseColorFactor"] = {0.2, 0.6, 0.3, 1.0};
    recoloured = true;
  }
  ASSERT_TRUE(recoloured) << "the dial has no material NeedleMat";
  const std::string edited = dir + "/dial-recoloured.gltf";
  std::ofstream(edited) << doc.dump();
  const auto cached = package(edited, config, &cache);
  EXPECT_EQ(cache.misses(), programs + 1);
  EXPECT_EQ(cache.hits(), programs - 1);
  EXPECT_TRUE(cached == package(edited, config, nullptr));
}

}  // namespace
}  // namespace meter::convert
