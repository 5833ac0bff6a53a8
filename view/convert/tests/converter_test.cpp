#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

#include "meter/shadergen/shadergen.hpp"
#include "meter/convert/converter.hpp"
#include "meter/convert/package_writer.hpp"
#include "meter/convert/quality_ladder.hpp"
#include "meter/config/scene_config_parser.hpp"
#include "meter/engine/package_reader.hpp"
#include "test_scenes.hpp"

using namespace meter::engine;
using namespace meter::convert;
namespace fs = std::filesystem;

namespace {

const fs::path kGltf = fs::path(METER_SHARED_DIR) / "data" / "gltf";

SceneConfig empty_config() { return meter::config::parse_scene_config(R"({"format": "meter-scene-config/1"})"); }

// "/meshes/0/primitives/0/attributes/NORMAL" -> "meshes[0].primitives[0].attributes.NORMAL"
std::string pointer_to_path(const std::string& pointer) {
  std::string out, seg;
  std::stringstream ss(pointer);
  while (std::getline(ss, seg, '/')) {
    if (seg.empty()) continue;
    if (std::all_of(seg.begin(), seg.end(), ::isdigit)) out += "[" + seg + "]";
    else out += (out.empty() ? "" : ".") + seg;
  }
  return out;
}

}  // namespace

// Every negative case of the Khronos validator: a clear error naming the element or a documented
// repair, never a crash. Each error the validator reports (severity 0) must be matched by one of
// our diagnostics at the same element (or at the array that holds the element it points into).
TEST(ConverterValidation, KhronosValidatorNegativeCases) {
  std::size_t cases = 0;
  for (const auto& entry : fs::recursive_directory_iterator(kGltf / "gltf-validator-tests")) {
    if (entry.path().extension() != ".gltf") continue;
    ++cases;
    const std::string file = entry.path().string();
    SCOPED_TRACE(file);
    std::vector<Diagnostic> diags;
    bool failed = false;
    std::string message;
    try {
      auto r = convert_gltf(file, empty_config(), ConvertOptions{false});
      diags = r.repairs;
    } catch (const ConvertError& e) {
      diags = e.errors;
      diags.insert(diags.end(), e.repairs.begin(), e.repairs.end());
      failed = true;
      message = e.what();
    } catch (const SceneError& e) {
      failed = true;
      message = e.what();
    }
    if (failed) {
      EXPECT_NE(message.find(file), std::string::npos) << "error must name the file: " << message;
    }
    std::ifstream in(file + ".report.json");
    auto report = nlohmann::json::parse(in);
    for (const auto& m : report["issues"]["messages"]) {
      if (m["severity"].get<int>() != 0) continue;
      const std::string want = pointer_to_path(m["pointer"].get<std::string>());
      bool matched = false;
      for (const auto& d : diags) {
        if (d.path == want) matched = true;
        // The validator points at a component ("translation/0"); we may name the field.
        if (want.rfind(d.path + "[", 0) == 0 && want.find_first_of(".[", d.path.size() + 1) == std::string::npos) matched = true;
      }
      if (!matched && !diags.empty()) {
        ADD_FAILURE() << "validator error at " << want << " (" << m["code"].get<std::string>() << ") not matched; we said:\n" << message;
      } else if (!matched) {
        // tinygltf refused the file before validation: the message must still be specific.
        EXPECT_TRUE(failed) << "validator error at " << want << " was silently accepted";
        EXPECT_GT(message.size(), file.size() + 20) << message;
      }
    }
  }
  EXPECT_EQ(cases, 17u);
}

// An out-of-memory of the glTF fuzz target (meter_fuzz_gltf -rss_limit_mb=512, input written by
// hand): a 68-byte PNG whose header claims 16000 x 16000 pixels made the image decoder allocate
// 1 GB before finding the data missing. The converter now reads an image's size from its header
// and refuses it before decoding.
TEST(ConverterValidation, FuzzOversizedImageHeaderIsRefusedBeforeDecoding) {
  const std::string png_16000 =
      "iVBORw0KGgoAAAANSUhEUgAAPoAAAD6ACAYAAABBft/eAAAAC0lEQVR4nGNgQAUAABAAATm9j2UAAAAASUVORK5CYII=";
  const std::string file = meter::engine::test::scratch_dir("oversized_image") + "/claim.gltf";
  std::ofstream(file) << R"({"asset":{"version":"2.0"},"images":[{"uri":"data:image/png;base64,)" << png_16000 << R"("}]})";
  try {
    convert_gltf(file, empty_config(), ConvertOptions{false});
    FAIL() << "a 16000 x 16000 image was accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("images[0]: 16000 x 16000 pixels, more than the 4096 x 4096 a texture may have"),
              std::string::npos) << e.what();
  }
}

TEST(ConverterValidation, ErrorMessageNamesElementAndValue) {
  const auto file = (kGltf / "gltf-validator-tests" / "node" / "rotation_non_unit.gltf").string();
  try {
    convert_gltf(file, empty_config());
    FAIL() << "non-unit rotation accepted";
  } catch (const ConvertError& e) {
    EXPECT_NE(std::string(e.what()).find("nodes[0].rotation: quaternion not unit length (|q| = "), std::string::npos) << e.what();
  }
}

TEST(ConverterSamples, KhronosSampleModelsConvertAndRoundTrip) {
  std::size_t n = 0;
  for (const auto& entry : fs::recursive_directory_iterator(kGltf / "khronos-sample-models")) {
    const auto ext = entry.path().extension();
    if (ext != ".gltf" && ext != ".glb") continue;
    ++n;
    SCOPED_TRACE(entry.path().string());
    for (bool optimize : {false, true}) {
      auto r = convert_gltf(entry.path().string(), empty_config(), ConvertOptions{optimize});
      EXPECT_FALSE(r.scene.draws.empty());
      EXPECT_FALSE(r.scene.programs.empty());
      auto back = deserialize_scene(serialize_scene(r.scene), "mem");
      EXPECT_EQ(back.draws.size(), r.scene.draws.size());
      EXPECT_EQ(back.programs.size(), r.scene.programs.size());
      EXPECT_EQ(back.programs[0].program.fragment_source, r.scene.programs[0].program.fragment_source);
    }
  }
  EXPECT_EQ(n, 5u);
}

TEST(ConverterSamples, SkinAndVertexColourFeaturesReachThePrograms) {
  auto skin = convert_gltf((kGltf / "khronos-sample-models" / "SimpleSkin" / "SimpleSkin.gltf").string(), empty_config(), ConvertOptions{false});
  ASSERT_EQ(skin.scene.programs.size(), 1u);
  EXPECT_EQ(skin.scene.programs[0].program.features.skin_joints, 2);
  EXPECT_FALSE(skin.scene.animations.empty());
  auto vc = convert_gltf((kGltf / "khronos-sample-models" / "BoxVertexColors" / "BoxVertexColors.glb").string(), empty_config(), ConvertOptions{false});
  bool colours = false;
  for (const auto& p : vc.scene.programs) colours = colours || p.program.features.vertex_colors;
  EXPECT_TRUE(colours);
}

TEST(ConverterDial, FeaturesPerMaterialAndOnlyWhatIsUsed) {
  auto dir = test::scratch_dir("converter_dial");
  auto r = convert_gltf(test::write_dial_scene(dir), meter::config::parse_scene_config(test::dial_config_json()), ConvertOptions{false});
  const auto& s = r.scene;
  std::set<std::string> keys;
  bool morph = false, lit = false;
  for (const auto& p : s.programs) {
    keys.insert(meter::shadergen::program_key(p.program.features));
    morph = morph || p.program.features.morph_targets == 2;
    if (p.program.features.shading == meter::shadergen::ShadingModel::PbrMetallicRoughness) {
      lit = true;
      EXPECT_EQ(p.program.features.lights.directional, 1);
      EXPECT_EQ(p.program.features.skin_joints, 0);
    }
  }
  EXPECT_TRUE(morph);
  EXPECT_TRUE(lit);
  EXPECT_EQ(keys.size(), s.programs.size());  // no duplicate programs without --optimize
  EXPECT_EQ(s.draws.size(), 4u);  // dial, needle, telltale, fuel bar
  // Flat normals were computed for the lit quad? No: it has NORMAL. Unlit quads need none.
  EXPECT_TRUE(r.repairs.empty());
  EXPECT_NE(program_report(s).find("SPIR-V instructions"), std::string::npos);
}

TEST(ConverterDial, ConfigNamesMustExistInTheScene) {
  auto dir = test::scratch_dir("converter_names");
  auto gltf = test::write_dial_scene(dir);
  auto cfg = meter::config::parse_scene_config(R"({"format": "meter-scene-config/1", "bindings": [
      {"signal": "Vehicle.Speed", "kind": "animation", "animation": "RpmNeedle", "input": [0, 1], "time": [0, 1]}]})");
  try {
    convert_gltf(gltf, cfg, ConvertOptions{false});
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("$.bindings[0].animation: no animation named \"RpmNeedle\" (the scene has: SpeedNeedle)"), std::string::npos) << e.what();
  }
}

TEST(ConverterDial, OptimizeFoldsConstants) {
  auto dir = test::scratch_dir("converter_opt");
  auto r = convert_gltf(test::write_dial_scene(dir), meter::config::parse_scene_config(test::dial_config_json()), ConvertOptions{true});
  for (const auto& p : r.scene.programs) {
    EXPECT_TRUE(p.program.optimized);
    EXPECT_LE(p.optimize_report.uniforms_after, p.optimize_report.uniforms_before);
    EXPECT_LT(p.optimize_report.spirv_instructions_after, p.optimize_report.spirv_instructions_before);
  }
  // The emissive-bound material keeps its EmissiveFactor uniform.
  const int mat = r.scene.find_material("TT_ABS_On");
  bool found = false;
  for (const auto& d : r.scene.draws) {
    if (r.scene.meshes[static_cast<std::size_t>(d.mesh)].primitives[static_cast<std::size_t>(d.primitive)].material != mat) continue;
    found = r.scene.programs[static_cast<std::size_t>(d.program)].program.find_uniform(meter::shadergen::UniformSemantic::EmissiveFactor) != nullptr;
  }
  EXPECT_TRUE(found);
}

// Blender's use_shadow arrives as the light's extras.meter_cast_shadow (true / false or 1 / 0):
// lit programs then get a shadow lookup for that light and nothing else does; a wrong type is an
// error naming the field; a point light that casts is repaired to cast nothing (its map would be a
// cube map, which is not built); the quality key shadows=off takes the lookups out again.
TEST(ConverterLights, ShadowFlagComesFromTheLightExtras) {
  const auto dir = test::scratch_dir("converter_shadow_flag");
  const std::string original = test::write_dial_scene(dir);
  auto with_light = [&](const nlohmann::json& extras, const std::string& type, const std::string& name) {
    std::ifstream in(original);
    nlohmann::json j = nlohmann::json::parse(in);
    auto& light = j["extensions"]["KHR_lights_punctual"]["lights"][0];
    light["extras"] = extras;
    light["type"] = type;
    const std::string path = dir + "/" + name + ".gltf";
    std::ofstream(path) << j.dump();
    return path;
  };
  const SceneConfig cfg = meter::config::parse_scene_config(test::dial_config_json());
  auto shadow_masks = [](const Scene& s) {
    std::set<unsigned> masks;
    for (const auto& p : s.programs)
      if (p.program.features.shading != meter::shadergen::ShadingModel::Unlit) masks.insert(p.program.features.lights.shadows);
    return masks;
  };

  const auto plain = convert_gltf(original, cfg, ConvertOptions{false});
  EXPECT_FALSE(plain.scene.lights[0].cast_shadow);
  EXPECT_EQ(shadow_masks(plain.scene), (std::set<unsigned>{0u}));

  for (const auto& flag : {nlohmann::json(true), nlohmann::json(1)}) {
    const auto r = convert_gltf(with_light({{"meter_cast_shadow", flag}}, "directional", "cast"), cfg, ConvertOptions{false});
    EXPECT_TRUE(r.scene.lights[0].cast_shadow) << flag;
    EXPECT_EQ(shadow_masks(r.scene), (std::set<unsigned>{1u})) << flag;
    for (const auto& p : r.scene.programs) {
      const bool samples_map = std::any_of(p.program.samplers.begin(), p.program.samplers.end(),
                                           [](const auto& s) { return s.slot == meter::bridge::TextureSlot::ShadowMap; });
      EXPECT_EQ(samples_map, p.program.features.lights.shadows != 0);
    }
    Scene off = r.scene;
    const QualityReport q = apply_quality(off, parse_quality("shadows=off"));
    EXPECT_EQ(q.shadow_maps_dropped, 1);
    for (const auto& d : off.draws) EXPECT_EQ(off.programs[std::size_t(d.program)].program.features.lights.shadows, 0u);
  }
  const auto no = convert_gltf(with_light({{"meter_cast_shadow", false}}, "directional", "no"), cfg, ConvertOptions{false});
  EXPECT_FALSE(no.scene.lights[0].cast_shadow);

  try {
    convert_gltf(with_light({{"meter_cast_shadow", "yes"}}, "directional", "bad"), cfg, ConvertOptions{false});
    FAIL() << "a string shadow flag was accepted";
  } catch (const ConvertError& e) {
    EXPECT_NE(std::string(e.what()).find("extensions.KHR_lights_punctual.lights[0].extras.meter_cast_shadow: expected true / false"),
              std::string::npos) << e.what();
  }

  const auto point = convert_gltf(with_light({{"meter_cast_shadow", true}}, "point", "point"), cfg, ConvertOptions{false});
  EXPECT_FALSE(point.scene.lights[0].cast_shadow);
  EXPECT_EQ(shadow_masks(point.scene), (std::set<unsigned>{0u}));
  ASSERT_EQ(point.repairs.size(), 1u);
  EXPECT_NE(point.repairs[0].message.find("point-light shadows"), std::string::npos) << point.repairs[0].message;
}
