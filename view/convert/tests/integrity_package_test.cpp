// The integrity table's package section (format version 4): written by the converter's writer,
// read back field for field by the runtime's reader, and every cross-reference checked on load.
#include <gtest/gtest.h>

#include "meter/config/scene_config_parser.hpp"
#include "meter/convert/converter.hpp"
#include "meter/convert/package_writer.hpp"
#include "meter/engine/package_reader.hpp"
#include "test_scenes.hpp"

using namespace meter;
using meter::bridge::Scene;
using meter::bridge::SceneError;

namespace {

Scene dial_with_table() {
  convert::ConvertOptions o;
  o.optimize = false;
  Scene s = convert::convert_gltf(engine::test::write_dial_scene(engine::test::scratch_dir("integrity_package")),
                                  meter::config::parse_scene_config(engine::test::dial_config_json()), o).scene;
  s.integrity.width = 320, s.integrity.height = 160;
  bridge::SafetyRegion tt;
  tt.name = "TT_ABS", tt.kind = bridge::SafetyKind::Telltale, tt.signal = "Cluster.Telltale.ABS";
  tt.bindings = {1}, tt.node = "TT_ABS", tt.materials = {"TT_ABS_On"};
  tt.rect = {200, 20, 3, 2};
  tt.telltale.mask = {0, 1, 1, 0, 1, 0};
  tt.telltale.looks = {{"on", true, {255, 153, 0.5}}, {"unlit", false, {12, 12, 13}}};
  tt.telltale.tolerance = 9.5;
  bridge::SafetyRegion nd;
  nd.name = "Needle", nd.kind = bridge::SafetyKind::Needle, nd.signal = "Vehicle.Speed", nd.bindings = {0};
  nd.node = "Needle", nd.rect = {100, 20, 120, 120};
  nd.needle = {"SpeedNeedle", 160.25, 80.5, 12.0, 55.0, {200, 0, 0}, {255, 90, 90}, 25, 0.5, 140.0,
               {{0.0, 0.0, -130.0}, {5.0, 120.0, -10.0}, {10.8, 259.2, 129.2}}, 1.25};
  bridge::SafetyRegion tx;
  tx.name = "Text_Speed", tx.kind = bridge::SafetyKind::Readout, tx.signal = "Vehicle.Speed", tx.bindings = {3};
  tx.node = "Text_Speed", tx.rect = {140, 100, 40, 24};
  tx.readout = {160, 120, 20, bridge::TextAlign::Center, "%.0f", 6};
  s.integrity.regions = {tt, nd, tx};
  return s;
}

std::string load_error(const Scene& s) {
  try {
    engine::deserialize_scene(convert::serialize_scene(s), "t.msp");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(IntegrityPackage, TableComesBackFieldForField) {
  const Scene s = dial_with_table();
  const auto bytes = convert::serialize_scene(s);
  const Scene r = engine::deserialize_scene(bytes, "t.msp");
  EXPECT_EQ(r.integrity, s.integrity);
  EXPECT_EQ(convert::serialize_scene(r), bytes);
}

TEST(IntegrityPackage, ASceneWithoutRegionsHasAnEmptyTable) {
  Scene s = dial_with_table();
  s.integrity = {};
  EXPECT_TRUE(engine::deserialize_scene(convert::serialize_scene(s), "t.msp").integrity.empty());
}

TEST(IntegrityPackage, BadCrossReferencesAreNamedOnLoad) {
  Scene s = dial_with_table();
  s.integrity.regions[1].bindings = {7};
  EXPECT_NE(load_error(s).find("integrity region Needle names binding 7 of 4"), std::string::npos) << load_error(s);
  s = dial_with_table();
  s.integrity.regions[2].rect.x = 300;
  EXPECT_NE(load_error(s).find("region Text_Speed: rect outside the integrity table's frame"), std::string::npos)
      << load_error(s);
  s = dial_with_table();
  s.integrity.regions[0].telltale.mask.pop_back();
  EXPECT_NE(load_error(s).find("region TT_ABS: telltale mask or looks incomplete"), std::string::npos) << load_error(s);
  s = dial_with_table();
  std::swap(s.integrity.regions[1].needle.samples[0], s.integrity.regions[1].needle.samples[1]);
  EXPECT_NE(load_error(s).find("needle samples not in increasing time"), std::string::npos) << load_error(s);
  s = dial_with_table();
  s.integrity.width = 0;
  EXPECT_NE(load_error(s).find("integrity table without a frame size"), std::string::npos) << load_error(s);
}

// A rect whose far edge lies past INT_MAX must be refused, not wrap to a negative edge that then
// passes the frame check (found by the package fuzz target).
TEST(IntegrityPackage, FuzzRectWhoseFarEdgeOverflowsIsRefused) {
  Scene s = dial_with_table();
  s.integrity.regions[2].rect = {2147483000, 20, 1000, 24};
  EXPECT_NE(load_error(s).find("region Text_Speed: rect outside the integrity table's frame"), std::string::npos)
      << load_error(s);
  s = dial_with_table();
  s.integrity.regions[2].rect = {140, 2147483000, 40, 1000};
  EXPECT_NE(load_error(s).find("region Text_Speed: rect outside the integrity table's frame"), std::string::npos)
      << load_error(s);
}
