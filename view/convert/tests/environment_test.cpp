// Environment maps: the data converter reads `meter_environment` from the glTF scene extras,
// refuses a missing or malformed file by name, bakes the image's reflection probe, integrates its
// ambient cube, and gives the environment feature only to the programs that can use it, only in
// scenes that have one; the package keeps it.
#include <gtest/gtest.h>

#include <filesystem>
#include <functional>
#include <fstream>

#include <nlohmann/json.hpp>

#include "meter/shadergen/shadergen.hpp"
#include "meter/convert/converter.hpp"
#include "meter/convert/environment_probe.hpp"
#include "meter/convert/package_writer.hpp"
#include "meter/config/scene_config_parser.hpp"
#include "meter/engine/package_reader.hpp"
#include "meter/platform/image.hpp"
#include "test_scenes.hpp"

using namespace meter::engine;
using namespace meter::convert;
namespace fs = std::filesystem;
using meter::shadergen::ShadingModel;
using meter::shadergen::TextureSlot;

namespace {

// The dial scene with `extras` put on its scene (glTF "scenes[0].extras"), written next to it.
std::string dial_with_extras(const std::string& dir, const nlohmann::json& extras) {
  const std::string file = test::write_dial_scene(dir);
  nlohmann::json j;
  std::ifstream(file) >> j;
  j["scenes"][0]["extras"] = extras;
  std::ofstream(file) << j.dump();
  return file;
}

// 16 x 8 equirect: upper half (sky, +Y) pure blue, lower half pure red. sRGB 255 = linear 1.
void write_two_tone(const fs::path& file) {
  meter::platform::Image im(16, 8);
  for (int y = 0; y < im.height; ++y)
    for (int x = 0; x < im.width; ++x) {
      auto* p = im.pixel(x, y);
      p[0] = y < 4 ? 0 : 255, p[1] = 0, p[2] = y < 4 ? 255 : 0;
    }
  meter::platform::write_png(im, file);
}

Scene convert_dial(const std::string& gltf) {
  return convert_gltf(gltf, meter::config::parse_scene_config(test::dial_config_json()), ConvertOptions{false}).scene;
}

// The diagnostics of a conversion that must fail validation.
std::vector<Diagnostic> errors_of(const std::string& gltf) {
  try {
    convert_dial(gltf);
  } catch (const ConvertError& e) {
    return e.errors;
  }
  ADD_FAILURE() << gltf << " converted although it should not";
  return {};
}

bool has_error(const std::vector<Diagnostic>& errs, const std::string& path, const std::string& text) {
  for (const auto& d : errs)
    if (d.path == path && d.message.find(text) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST(Environment, SceneWithoutOneGetsNoEnvironmentCode) {
  const Scene s = convert_dial(test::write_dial_scene(test::scratch_dir("env_none")));
  EXPECT_FALSE(s.environment.present());
  for (const auto& p : s.programs) {
    EXPECT_FALSE(p.program.features.environment_map_2d) << meter::shadergen::program_key(p.program.features);
    for (const auto& smp : p.program.samplers) EXPECT_NE(smp.slot, TextureSlot::Environment);
  }
}

TEST(Environment, ExtrasArePackedIntegratedAndUsedByLitPerPixelPrograms) {
  const auto dir = test::scratch_dir("env_two_tone");
  write_two_tone(fs::path(dir) / "sky.png");
  const Scene s = convert_dial(dial_with_extras(dir, {{"meter_environment", "sky.png"}, {"meter_environment_strength", 2.0}}));
  ASSERT_TRUE(s.environment.present());
  EXPECT_FLOAT_EQ(s.environment.strength, 2.0f);
  // Baked into EEVEE's 512 px probe (environment_probe_test.cpp checks the bake); the image itself
  // is not packed.
  EXPECT_EQ(s.environment.probe.face_size, kEnvironmentProbeFaceSize);
  EXPECT_EQ(s.environment.probe.levels, 7);
  for (const Texture& t : s.textures) EXPECT_EQ(t.name.find("environment"), std::string::npos) << t.name;
  // Level 0: the middle texel of face +Y (index 2) is sky, of face -Y ground.
  const auto texel = [&](int face) {
    const std::size_t n = std::size_t(kEnvironmentProbeFaceSize);
    return &s.environment.probe.rgb[((std::size_t(face) * n + n / 2) * n + n / 2) * 3];
  };
  EXPECT_EQ(texel(2)[2], 255);
  EXPECT_EQ(texel(2)[0], 0);
  EXPECT_EQ(texel(3)[0], 255);
  EXPECT_EQ(texel(3)[2], 0);
  // Ambient cube: the hemisphere around +Y sees only sky, around -Y only ground; around a
  // horizontal axis half of each, symmetric, so exactly the mean. Strength 2 scales all.
  const auto& c = s.environment.irradiance;
  const float tol = 1e-4f;
  EXPECT_NEAR(c[2].b, 2.0f, tol);  // +Y: sky only
  EXPECT_NEAR(c[2].r, 0.0f, tol);
  EXPECT_NEAR(c[3].r, 2.0f, tol);  // -Y: ground only
  EXPECT_NEAR(c[3].b, 0.0f, tol);
  for (int a : {0, 1, 4, 5}) {
    EXPECT_NEAR(c[std::size_t(a)].r, 1.0f, tol) << a;
    EXPECT_NEAR(c[std::size_t(a)].b, 1.0f, tol) << a;
    EXPECT_NEAR(c[std::size_t(a)].g, 0.0f, tol) << a;
  }
  // Lit per-pixel programs (the PBR telltale) sample it; the unlit dial and needle do not.
  int with_env = 0, without_env = 0;
  for (const auto& p : s.programs) {
    const bool lit_pp = p.program.features.shading == ShadingModel::PbrMetallicRoughness ||
                        p.program.features.shading == ShadingModel::BlinnPhong;
    EXPECT_EQ(p.program.features.environment_map_2d, lit_pp) << meter::shadergen::program_key(p.program.features);
    (p.program.features.environment_map_2d ? with_env : without_env)++;
  }
  EXPECT_GT(with_env, 0);
  EXPECT_GT(without_env, 0);

  // The package keeps the environment (and round-trips byte for byte).
  const auto bytes = serialize_scene(s);
  const Scene back = deserialize_scene(bytes, "env.msp");
  EXPECT_EQ(back.environment.probe.face_size, s.environment.probe.face_size);
  EXPECT_EQ(back.environment.probe.levels, s.environment.probe.levels);
  EXPECT_EQ(back.environment.probe.rgb, s.environment.probe.rgb);
  EXPECT_FLOAT_EQ(back.environment.strength, 2.0f);
  EXPECT_EQ(back.environment.irradiance, s.environment.irradiance);
  EXPECT_EQ(serialize_scene(back), bytes);
}

TEST(Environment, BadExtrasAreNamedWithFileAndField) {
  const std::string file_field = "scenes[0].extras.meter_environment";
  const std::string strength_field = "scenes[0].extras.meter_environment_strength";
  {
    const auto dir = test::scratch_dir("env_missing");
    EXPECT_TRUE(has_error(errors_of(dial_with_extras(dir, {{"meter_environment", "nowhere.png"}})), file_field, "nowhere.png"));
  }
  {
    const auto dir = test::scratch_dir("env_not_png");
    std::ofstream(fs::path(dir) / "sky.png") << "not a png\n";
    EXPECT_TRUE(has_error(errors_of(dial_with_extras(dir, {{"meter_environment", "sky.png"}})), file_field, "sky.png"));
  }
  {
    const auto dir = test::scratch_dir("env_not_string");
    EXPECT_TRUE(has_error(errors_of(dial_with_extras(dir, {{"meter_environment", 3}})), file_field, "file name"));
  }
  {
    const auto dir = test::scratch_dir("env_negative");
    write_two_tone(fs::path(dir) / "sky.png");
    EXPECT_TRUE(has_error(errors_of(dial_with_extras(dir, {{"meter_environment", "sky.png"}, {"meter_environment_strength", -1}})),
                          strength_field, ">= 0"));
  }
  {
    const auto dir = test::scratch_dir("env_strength_alone");
    EXPECT_TRUE(has_error(errors_of(dial_with_extras(dir, {{"meter_environment_strength", 1.0}})), strength_field, "without"));
  }
  {
    const auto dir = test::scratch_dir("env_tiny");
    meter::platform::write_png(meter::platform::Image(1, 1), fs::path(dir) / "dot.png");
    EXPECT_TRUE(has_error(errors_of(dial_with_extras(dir, {{"meter_environment", "dot.png"}})), file_field, "2..16384"));
  }
}

// A corrupt package cannot hand the runtime a probe whose size and texels disagree.
TEST(Environment, PackageRefusesAProbeOfTheWrongShape) {
  const auto dir = test::scratch_dir("env_corrupt");
  const Scene good = convert_dial(test::write_dial_scene(dir));
  const auto refused = [&](const std::function<void(EnvironmentProbe&)>& damage, const std::string& expected) {
    Scene s = good;
    s.environment.probe = {.face_size = 8, .levels = 1, .rgb = std::vector<std::uint8_t>(EnvironmentProbe::byte_size(8, 1), 7)};
    damage(s.environment.probe);
    try {
      deserialize_scene(serialize_scene(s), "bad.msp");
      ADD_FAILURE() << "accepted a probe that should say: " << expected;
    } catch (const SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  refused([](EnvironmentProbe& p) { p.face_size = 12; }, "environment.probe: face size 12 with 1 levels");
  refused([](EnvironmentProbe& p) { p.levels = 2; }, "expected a power of two in 8..4096 and log2(face size) - 2 levels");
  refused([](EnvironmentProbe& p) { p.rgb.pop_back(); }, "environment.probe: 1151 bytes of texels; expected 1152");
  // The well-formed 8 px probe itself loads.
  Scene s = good;
  s.environment.probe = {.face_size = 8, .levels = 1, .rgb = std::vector<std::uint8_t>(EnvironmentProbe::byte_size(8, 1), 7)};
  EXPECT_EQ(deserialize_scene(serialize_scene(s), "ok.msp").environment.probe.rgb, s.environment.probe.rgb);
}
