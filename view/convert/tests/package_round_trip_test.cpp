// The package writer (convert) and the package reader (engine) agree on the format of
// meter/bridge/package_format.hpp: a hand-built scene touching every section comes back field for
// field, the header is the one the format defines, and a second write gives the same bytes. A
// package whose draw levels point anywhere they must not is refused with a message naming the field.
#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <filesystem>
#include <thread>
#include <vector>

#include "meter/bridge/package_format.hpp"
#include "meter/convert/package_writer.hpp"
#include "meter/engine/package_reader.hpp"
#include "every_section_scene.hpp"
#include "test_scenes.hpp"

using namespace meter;
using namespace meter::convert;
using engine::test::quad_primitive;

using meter::convert::test::every_section;

TEST(PackageRoundTrip, HeaderIsTheOneTheFormatDefines) {
  const auto bytes = serialize_scene(every_section());
  ASSERT_GT(bytes.size(), kPackageHeaderSize);
  EXPECT_EQ(std::memcmp(bytes.data(), kPackageMagic, 8), 0);
  std::uint32_t version = 0, reserved = 1;
  std::uint64_t size = 0, checksum = 0;
  std::memcpy(&version, bytes.data() + 8, 4);
  std::memcpy(&reserved, bytes.data() + 12, 4);
  std::memcpy(&size, bytes.data() + 16, 8);
  std::memcpy(&checksum, bytes.data() + 24, 8);
  EXPECT_EQ(version, kPackageVersion);
  EXPECT_EQ(reserved, 0u);
  EXPECT_EQ(size, bytes.size() - kPackageHeaderSize);
  EXPECT_EQ(checksum, package_checksum(std::span(bytes).subspan(kPackageHeaderSize)));
}

TEST(PackageRoundTrip, WriterToReaderKeepsEverySection) {
  const Scene s = every_section();
  const auto bytes = serialize_scene(s);
  const Scene r = engine::deserialize_scene(bytes, "hand.msp");
  EXPECT_EQ(r.source_name, "hand-built");
  ASSERT_EQ(r.nodes.size(), 2u);
  EXPECT_EQ(r.nodes[0].children, (std::vector<int>{1}));
  EXPECT_EQ(r.nodes[0].translation, glm::vec3(1, 2, 3));
  EXPECT_EQ(r.nodes[0].rotation, glm::quat(0.5f, 0.5f, 0.5f, 0.5f));
  EXPECT_EQ(r.nodes[1].weights, (std::vector<float>{0.25f}));
  EXPECT_EQ(r.roots, (std::vector<int>{0}));
  ASSERT_EQ(r.meshes.size(), 1u);
  EXPECT_EQ(r.meshes[0].primitives[0].vertices, s.meshes[0].primitives[0].vertices);
  EXPECT_EQ(r.meshes[0].primitives[0].indices, s.meshes[0].primitives[0].indices);
  EXPECT_EQ(r.meshes[0].primitives[0].bounds_max, glm::vec3(1, 1, 0));
  EXPECT_EQ(r.materials[0].alpha, bridge::AlphaMode::Blend);
  EXPECT_EQ(r.materials[0].base_color, glm::vec4(0.1f, 0.2f, 0.3f, 0.4f));
  EXPECT_EQ(r.materials[0].uv_transform[0], glm::mat3(2.0f));
  EXPECT_EQ(r.textures[0].rgba, s.textures[0].rgba);
  EXPECT_TRUE(r.textures[0].srgb);
  EXPECT_FLOAT_EQ(r.cameras[0].yfov, 0.7f);
  EXPECT_EQ(r.lights[0].type, LightType::Spot);
  EXPECT_TRUE(r.lights[0].cast_shadow);
  EXPECT_EQ(r.skins[0].joints, (std::vector<int>{0}));
  EXPECT_EQ(r.animations[0].samplers[0].interpolation, Interpolation::Step);
  EXPECT_EQ(r.animations[0].samplers[0].output, s.animations[0].samplers[0].output);
  ASSERT_EQ(r.programs.size(), 2u);
  EXPECT_EQ(r.programs[0].program.fragment_source, "void main() { }");
  EXPECT_EQ(r.programs[0].program.attributes.size(), 2u);
  EXPECT_TRUE(r.programs[0].program.blend);
  EXPECT_EQ(r.programs[0].program.features.lights.shadows, 1u);
  ASSERT_EQ(r.programs[0].program.samplers.size(), 1u);
  EXPECT_EQ(r.programs[0].program.samplers[0].slot, bridge::TextureSlot::ShadowMap);
  EXPECT_EQ(r.programs[0].program.samplers[0].index, 0);
  EXPECT_EQ(r.programs[0].optimize_report.spirv_instructions_before, 120u);
  EXPECT_EQ(r.programs[0].optimize_report.folded, (std::vector<std::string>{"u_base_color"}));
  EXPECT_EQ(r.draws.size(), 1u);
  EXPECT_EQ(r.environment.probe.face_size, 8);
  EXPECT_EQ(r.environment.probe.levels, 1);
  EXPECT_EQ(r.environment.probe.rgb, s.environment.probe.rgb);
  EXPECT_FLOAT_EQ(r.environment.strength, 0.5f);
  EXPECT_EQ(r.environment.irradiance[2], glm::vec3(0.1f, 0.2f, 0.3f));
  EXPECT_EQ(r.config.source_json, s.config.source_json);
  // The draw levels, field for field.
  ASSERT_EQ(r.meshes[0].primitives[0].lods.size(), 1u);
  const LodLevel& lod = r.meshes[0].primitives[0].lods[0];
  EXPECT_FLOAT_EQ(lod.error, 0.01f);
  EXPECT_FLOAT_EQ(lod.triangle_fraction, 0.5f);
  EXPECT_EQ(lod.indices, (std::vector<std::uint32_t>{0, 1, 2}));
  ASSERT_EQ(r.draw_levels.size(), 1u);
  EXPECT_FALSE(r.draw_levels[0].safety);
  EXPECT_EQ(r.draw_levels[0].lods, 1);
  ASSERT_EQ(r.draw_levels[0].shadings.size(), 1u);
  const ShadingLevel& sl = r.draw_levels[0].shadings[0];
  EXPECT_EQ(sl.shading, bridge::ShadingModel::Unlit);
  EXPECT_EQ(sl.program, 1);
  EXPECT_EQ(sl.specular_color, glm::vec3(0.04f, 0.05f, 0.06f));
  EXPECT_FLOAT_EQ(sl.shininess, 12.0f);
  EXPECT_FLOAT_EQ(sl.base_scale, 0.25f);
  EXPECT_EQ(r.draw_levels, s.draw_levels);
  EXPECT_EQ(serialize_scene(r), bytes);  // byte-identical after a round trip
}

namespace {
// The writer's temporary files (`NAME.tmp...`) left in the folder of `path`, by file name: the
// folder's own path may hold anything, wherever the checkout lives.
std::vector<std::string> temporaries_beside(const std::string& path) {
  std::vector<std::string> left;
  for (const auto& entry : std::filesystem::directory_iterator(std::filesystem::path(path).parent_path())) {
    const std::string name = entry.path().filename().string();
    if (name.find(".tmp") != std::string::npos) left.push_back(name);
  }
  return left;
}
}  // namespace

TEST(PackageRoundTrip, WritePackageThenReadPackage) {
  const std::string path = engine::test::scratch_dir("package_round_trip") + "/hand.msp";
  write_package(every_section(), path);
  EXPECT_EQ(temporaries_beside(path), std::vector<std::string>{});
  const Scene r = engine::read_package(path);
  EXPECT_EQ(serialize_scene(r), serialize_scene(every_section()));
}

// Two conversions writing the same package at once (two test processes, two build jobs) must
// both succeed and leave one whole package: each writes its own temporary file and renames it.
TEST(PackageRoundTrip, ConcurrentWritersOfOnePathBothSucceed) {
  const std::string path = engine::test::scratch_dir("package_round_trip") + "/shared.msp";
  const Scene s = every_section();
  std::atomic<int> failures{0};
  std::string first_error;  // written only by the thread that counts the first failure
  std::vector<std::thread> writers;
  for (int t = 0; t < 8; ++t)
    writers.emplace_back([&] {
      for (int i = 0; i < 25; ++i) {
        try {
          write_package(s, path);
        } catch (const std::exception& e) {
          if (failures++ == 0) first_error = e.what();
        }
      }
    });
  for (auto& w : writers) w.join();
  EXPECT_EQ(failures.load(), 0) << first_error;
  EXPECT_EQ(serialize_scene(engine::read_package(path)), serialize_scene(s));
  EXPECT_EQ(temporaries_beside(path), std::vector<std::string>{});
}

namespace {
// The reader's message for `s` written as a package ("" when it reads).
std::string read_error(const Scene& s) {
  try {
    engine::deserialize_scene(serialize_scene(s), "bad.msp");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(PackageRoundTrip, BadDrawLevelsAreRefusedNamingTheField) {
  ASSERT_EQ(read_error(every_section()), "");
  {
    Scene s = every_section();
    s.draw_levels[0].shadings[0].program = 7;
    EXPECT_NE(read_error(s).find("draw_levels[0].shadings[0].program: 7 out of range (2 programs)"), std::string::npos) << read_error(s);
  }
  {
    Scene s = every_section();
    s.draw_levels[0].lods = 2;
    EXPECT_NE(read_error(s).find("draw_levels[0].lods: 2, expected 0..1"), std::string::npos) << read_error(s);
  }
  {
    Scene s = every_section();
    s.meshes[0].primitives[0].lods[0].indices = {0, 1, 4};  // the quad has 4 vertices
    EXPECT_NE(read_error(s).find("meshes[0].primitives[0].lods[0].indices: index 4 out of range of the 4 vertices"), std::string::npos)
        << read_error(s);
  }
  {
    Scene s = every_section();
    s.meshes[0].primitives[0].lods[0].indices = {0, 1};
    EXPECT_NE(read_error(s).find("lods[0].indices: expected whole triangles"), std::string::npos) << read_error(s);
  }
  {
    Scene s = every_section();
    s.meshes[0].primitives[0].lods[0].triangle_fraction = 1.0f;
    EXPECT_NE(read_error(s).find("lods[0].triangle_fraction: expected a value in (0, 1)"), std::string::npos) << read_error(s);
  }
  {
    Scene s = every_section();
    s.draw_levels[0].shadings[0].shading = bridge::ShadingModel::Flat;  // the program is unlit
    EXPECT_NE(read_error(s).find("draw_levels[0].shadings[0].program: its shading model unlit is not the level's flat"), std::string::npos)
        << read_error(s);
  }
  {
    Scene s = every_section();
    s.programs[1].program.features.shading = bridge::ShadingModel::PbrMetallicRoughness;
    s.draw_levels[0].shadings[0].shading = bridge::ShadingModel::PbrMetallicRoughness;
    EXPECT_NE(read_error(s).find("draw_levels[0].shadings[0].shading: pbr is not cheaper than the draw's own pbr"), std::string::npos)
        << read_error(s);
  }
  {
    Scene s = every_section();
    s.programs[1].program.blend = false;
    EXPECT_NE(read_error(s).find("draw_levels[0].shadings[0].program: blend / cull state differs"), std::string::npos) << read_error(s);
  }
  {
    Scene s = every_section();
    s.draw_levels.push_back(s.draw_levels[0]);
    EXPECT_NE(read_error(s).find("draw_levels: 2 entries for 1 draws"), std::string::npos) << read_error(s);
  }
  {
    Scene s = every_section();
    s.draw_levels[0].safety = true;
    EXPECT_NE(read_error(s).find("draw_levels[0]: a safety item with levels"), std::string::npos) << read_error(s);
  }
}
