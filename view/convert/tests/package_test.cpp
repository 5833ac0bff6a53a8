#include <gtest/gtest.h>

#include <cstring>

#include "meter/convert/converter.hpp"
#include "meter/convert/package_writer.hpp"
#include "meter/config/scene_config_parser.hpp"
#include "meter/engine/package_reader.hpp"
#include "test_scenes.hpp"

using namespace meter::engine;
using namespace meter::convert;

namespace {
std::vector<std::uint8_t> dial_package() {
  static std::vector<std::uint8_t> bytes = [] {
    auto dir = test::scratch_dir("package");
    auto r = convert_gltf(test::write_dial_scene(dir), meter::config::parse_scene_config(test::dial_config_json()), ConvertOptions{false});
    return serialize_scene(r.scene);
  }();
  return bytes;
}
std::string load_error(const std::vector<std::uint8_t>& b) {
  try {
    deserialize_scene(b, "p.msp");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Package, RoundTripKeepsEverything) {
  auto bytes = dial_package();
  Scene s = deserialize_scene(bytes, "p.msp");
  EXPECT_EQ(serialize_scene(s), bytes);  // byte-identical after a round trip
  EXPECT_EQ(s.config.bindings.size(), 4u);
  EXPECT_GE(s.find_animation("SpeedNeedle"), 0);
}

TEST(Package, OtherVersionIsRefusedWithBothVersionsNamed) {
  auto bytes = dial_package();
  const std::uint32_t v = kPackageVersion + 1;
  std::memcpy(bytes.data() + 8, &v, 4);
  const auto msg = load_error(bytes);
  EXPECT_NE(msg.find("format version " + std::to_string(v) + " is not supported"), std::string::npos) << msg;
  EXPECT_NE(msg.find("reads version " + std::to_string(kPackageVersion)), std::string::npos) << msg;
}

TEST(Package, BadMagicTruncationAndCorruptionAreRefused) {
  auto bytes = dial_package();
  auto bad = bytes;
  bad[0] = 'X';
  EXPECT_NE(load_error(bad).find("not a meter scene package"), std::string::npos);
  auto cut = bytes;
  cut.resize(cut.size() / 2);
  EXPECT_NE(load_error(cut).find("truncated"), std::string::npos);
  auto flip = bytes;
  flip[flip.size() - 10] ^= 0x40;
  EXPECT_NE(load_error(flip).find("checksum"), std::string::npos);
  EXPECT_NE(load_error({}).find("p.msp"), std::string::npos);
}
