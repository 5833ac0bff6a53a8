// The package writer (convert) and the package reader (engine) agree on the format of
// meter/bridge/package_format.hpp: a hand-built scene touching every section comes back field for
// field, the header is the one the format defines, and a second write gives the same bytes.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>

#include "meter/bridge/package_format.hpp"
#include "meter/convert/package_writer.hpp"
#include "meter/engine/package_reader.hpp"
#include "test_scenes.hpp"

using namespace meter;
using namespace meter::convert;
using engine::test::quad_primitive;

namespace {

Scene every_section() {
  Scene s;
  s.source_name = "hand-built";
  Node root;
  root.name = "Root";
  root.children = {1};
  root.translation = {1, 2, 3};
  root.rotation = glm::quat(0.5f, 0.5f, 0.5f, 0.5f);
  root.scale = {2, 2, 2};
  Node quad;
  quad.name = "Quad";
  quad.parent = 0;
  quad.mesh = 0;
  quad.light = 0;
  quad.camera = 0;
  quad.skin = 0;
  quad.weights = {0.25f};
  s.nodes = {root, quad};
  s.roots = {0};
  Mesh m;
  m.name = "QuadMesh";
  m.weights = {0.25f};
  m.primitives.push_back(quad_primitive(0, 2.0f));
  s.meshes.push_back(m);
  Material mat;
  mat.name = "Paint";
  mat.alpha = bridge::AlphaMode::Blend;
  mat.base_color = {0.1f, 0.2f, 0.3f, 0.4f};
  mat.texture[0] = 0;
  mat.uv_transform[0] = glm::mat3(2.0f);
  mat.has_uv_transform = true;
  s.materials.push_back(mat);
  Texture t;
  t.name = "Checker";
  t.width = t.height = 2;
  t.rgba = {255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 0};
  t.srgb = true;
  s.textures.push_back(t);
  s.cameras.push_back(engine::test::perspective_camera("Cam", 0.7f));
  Light l;
  l.name = "Sun";
  l.type = LightType::Spot;
  l.intensity = 3.0f;
  s.lights.push_back(l);
  Skin k;
  k.name = "Rig";
  k.joints = {0};
  k.inverse_bind = {glm::mat4(1.0f)};
  s.skins.push_back(k);
  Animation a;
  a.name = "Spin";
  a.samplers.push_back({Interpolation::Step, 3, {0.0f, 1.0f}, {0, 0, 0, 1, 1, 1}});
  a.channels.push_back({0, 1, TargetPath::Translation});
  a.end = 1.0f;
  s.animations.push_back(a);
  ProgramEntry pe;
  pe.program.vertex_source = "void main() {}";
  pe.program.fragment_source = "void main() { }";
  pe.program.attributes.push_back({"a_position", AttributeSemantic::Position, -1, 0, 3});
  pe.program.attributes.push_back({"a_vertex_alpha", AttributeSemantic::VertexAlpha, -1, 1, 1});
  pe.program.blend = true;
  pe.optimize_report.spirv_instructions_before = 120;
  pe.optimize_report.folded = {"u_base_color"};
  s.programs.push_back(pe);
  s.draws = {{1, 0, 0, 0}};
  s.environment.texture = 0;
  s.environment.strength = 0.5f;
  s.environment.irradiance[2] = {0.1f, 0.2f, 0.3f};
  s.config.source_json = R"({"format": "meter-scene-config/1"})";
  return s;
}

}  // namespace

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
  EXPECT_EQ(r.skins[0].joints, (std::vector<int>{0}));
  EXPECT_EQ(r.animations[0].samplers[0].interpolation, Interpolation::Step);
  EXPECT_EQ(r.animations[0].samplers[0].output, s.animations[0].samplers[0].output);
  ASSERT_EQ(r.programs.size(), 1u);
  EXPECT_EQ(r.programs[0].program.fragment_source, "void main() { }");
  EXPECT_EQ(r.programs[0].program.attributes.size(), 2u);
  EXPECT_TRUE(r.programs[0].program.blend);
  EXPECT_EQ(r.programs[0].optimize_report.spirv_instructions_before, 120u);
  EXPECT_EQ(r.programs[0].optimize_report.folded, (std::vector<std::string>{"u_base_color"}));
  EXPECT_EQ(r.draws.size(), 1u);
  EXPECT_EQ(r.environment.texture, 0);
  EXPECT_FLOAT_EQ(r.environment.strength, 0.5f);
  EXPECT_EQ(r.environment.irradiance[2], glm::vec3(0.1f, 0.2f, 0.3f));
  EXPECT_EQ(r.config.source_json, s.config.source_json);
  EXPECT_EQ(serialize_scene(r), bytes);  // byte-identical after a round trip
}

TEST(PackageRoundTrip, WritePackageThenReadPackage) {
  const std::string path = engine::test::scratch_dir("package_round_trip") + "/hand.msp";
  write_package(every_section(), path);
  EXPECT_FALSE(std::filesystem::exists(path + ".tmp"));
  const Scene r = engine::read_package(path);
  EXPECT_EQ(serialize_scene(r), serialize_scene(every_section()));
}
