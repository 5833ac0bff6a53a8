// Which control each bound signal gets: sliders over the catalog range, toggles for telltales,
// choices for enums labelled by the config's text map, one control per signal.
#include "meter/preview/signal_controls.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "meter/config/scene_config_parser.hpp"

namespace meter::preview {
namespace {

std::vector<bridge::Binding> bindings_of(const std::string& bindings_json) {
  const std::string text = R"({"format": "meter-scene-config/1", "bindings": [)" + bindings_json + "]}";
  return meter::config::parse_scene_config(text, *protocol::default_catalog(), "test.scene.json").bindings;
}

TEST(SignalControls, OnePerBoundSignalByItsCatalogKind) {
  const auto controls = controls_for(
      bindings_of(R"({"signal": "Vehicle.Speed", "kind": "animation", "animation": "A", "input": [0, 260], "time": [0, 1]},
                     {"signal": "Vehicle.Speed", "kind": "text", "node": "T"},
                     {"signal": "Cluster.Telltale.ABS", "kind": "visibility", "node": "L"},
                     {"signal": "Vehicle.Powertrain.Transmission.CurrentGear", "kind": "text", "node": "G",
                      "map": {"-1": "R", "0": "N", "126": "P"}})"),
      *protocol::default_catalog());
  ASSERT_EQ(controls.size(), 3u) << "the speed is bound twice but gets one control";
  EXPECT_EQ(controls[0].name, "Vehicle.Speed");
  EXPECT_EQ(controls[0].kind, ControlKind::Slider);
  EXPECT_EQ(controls[0].min, 0.0);
  EXPECT_EQ(controls[0].max, 300.0) << "the catalog's range, not the binding's input";
  EXPECT_EQ(controls[0].unit, "km/h");
  EXPECT_EQ(controls[1].kind, ControlKind::Toggle);
  EXPECT_EQ(controls[1].id, protocol::sig::kAbs);
  const auto& gear = controls[2];
  EXPECT_EQ(gear.kind, ControlKind::Choice);
  ASSERT_EQ(gear.choices.size(), static_cast<std::size_t>(kMaxChoices) + 1) << "-1..62 and the mapped 126";
  EXPECT_EQ(gear.choices.front(), (ChoiceItem{-1, "R (-1)"}));
  EXPECT_EQ(gear.choices[1], (ChoiceItem{0, "N (0)"}));
  EXPECT_EQ(gear.choices[5], (ChoiceItem{4, "4"}));
  EXPECT_EQ(gear.choices.back(), (ChoiceItem{126, "P (126)"}));
}

TEST(SignalControls, ASmallEnumListsItsWholeRange) {
  const auto controls = controls_for(bindings_of(R"({"signal": "Vehicle.LowVoltageSystemState", "kind": "text", "node": "T"})"),
                                     *protocol::default_catalog());
  ASSERT_EQ(controls.size(), 1u);
  ASSERT_EQ(controls[0].kind, ControlKind::Choice);
  ASSERT_EQ(controls[0].choices.size(), 6u);
  EXPECT_EQ(controls[0].choices.back(), (ChoiceItem{5, "5"}));
}

}  // namespace
}  // namespace meter::preview
