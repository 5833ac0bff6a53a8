#include <gtest/gtest.h>

#include "meter/config/scene_config_parser.hpp"
#include "test_scenes.hpp"

using namespace meter::bridge;

namespace {
std::string error_of(const std::string& json) {
  try {
    meter::config::parse_scene_config(json, "t.json");
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(SceneConfig, ParsesTheDocumentedShape) {
  auto c = meter::config::parse_scene_config(meter::engine::test::dial_config_json(), "dial.json");
  EXPECT_EQ(c.size[0], 320);
  EXPECT_EQ(c.camera, "Camera");
  ASSERT_EQ(c.bindings.size(), 4u);
  EXPECT_EQ(c.bindings[0].kind, BindingKind::Animation);
  EXPECT_EQ(c.bindings[0].signal_id, 1);
  EXPECT_DOUBLE_EQ(c.bindings[0].time[1], 10.8333333);
  EXPECT_EQ(c.bindings[0].failsafe_value.value(), 0.0);
  EXPECT_EQ(c.bindings[3].kind, BindingKind::Text);
  EXPECT_EQ(c.bindings[3].align, TextAlign::Center);
  EXPECT_EQ(*c.bindings[3].failsafe_text, "---");
  EXPECT_EQ(c.link_loss.text_node, "Text_Status");
}

TEST(SceneConfig, ErrorsNameTheFileAndJsonPath) {
  EXPECT_NE(error_of(R"({"format": "meter-scene-config/2"})").find("t.json: $.format: unsupported format"), std::string::npos);
  EXPECT_NE(error_of(R"({"format": "meter-scene-config/1", "bindings": [{"signal": "Vehicle.Nope", "kind": "text", "node": "x"}]})")
                .find("$.bindings[0].signal: \"Vehicle.Nope\" is not in the signal catalog"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"format": "meter-scene-config/1", "bindings": [{"signal": "Vehicle.Speed", "kind": "animation", "animation": "A", "input": [0, 0], "time": [0, 1]}]})")
                .find("$.bindings[0].input: the two ends of the range must differ"),
            std::string::npos);
  EXPECT_NE(error_of(R"({"format": "meter-scene-config/1", "sise": [1, 2]})").find("$.sise: unknown key"), std::string::npos);
  EXPECT_NE(error_of(R"({"format": "meter-scene-config/1", "size": [1280]})").find("$.size"), std::string::npos);
  EXPECT_NE(error_of("{not json").find("t.json: not valid JSON"), std::string::npos);
  EXPECT_NE(error_of(R"({"format": "meter-scene-config/1", "bindings": [{"signal": "Vehicle.Speed", "kind": "text", "node": "T", "format": "%s"}]})")
                .find("$.bindings[0].format"),
            std::string::npos);
}

TEST(SceneConfig, NumberFormatsAreCheckedSoFormattingCannotBeUndefined) {
  EXPECT_TRUE(valid_number_format("%.0f km"));
  EXPECT_TRUE(valid_number_format("%+5.1f%%"));
  EXPECT_FALSE(valid_number_format("%d"));
  EXPECT_FALSE(valid_number_format("%f %f"));
  EXPECT_FALSE(valid_number_format("no conversion"));
  EXPECT_FALSE(valid_number_format("%999f"));
  EXPECT_EQ(format_number("%.1f km", 12.34), "12.3 km");
}

TEST(SceneConfig, BindingsAreCheckedAgainstTheCatalogGiven) {
  const std::string config = R"({"format": "meter-scene-config/1", "bindings": [
      {"signal": "Vehicle.Powertrain.TractionBattery.StateOfCharge.Displayed", "kind": "visibility", "node": "N"}]})";
  auto ev = meter::protocol::parse_catalog(
      R"({"Vehicle": {"type": "branch", "children": {"Powertrain": {"type": "branch", "children": {
           "TractionBattery": {"type": "branch", "children": {"StateOfCharge": {"type": "branch", "children": {
             "Displayed": {"type": "sensor", "datatype": "float", "min": 0, "max": 100, "meter_id": 100}}}}}}}}}})",
      "ev.vss.json");
  ASSERT_TRUE(ev.catalog) << ev.error;
  const auto c = meter::config::parse_scene_config(config, *ev.catalog, "ev.scene.json");
  ASSERT_EQ(c.bindings.size(), 1u);
  EXPECT_EQ(c.bindings[0].signal_id, 100);
  try {
    meter::config::parse_scene_config(config, *meter::protocol::default_catalog(), "ev.scene.json");
    ADD_FAILURE() << "the shipped catalog has no state of charge";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "ev.scene.json: $.bindings[0].signal: \"Vehicle.Powertrain.TractionBattery.StateOfCharge."
                           "Displayed\" is not in the signal catalog protocol/catalog/signals.vss.json (built in)");
  }
}

// Found by fuzzing (meter_fuzz_scene_config: an uncaught exception): a number too large for a
// double ("-1e308480") made the JSON library throw its out_of_range, which escaped as neither the
// parser's std::invalid_argument nor a message naming the file.
TEST(SceneConfig, FuzzNumberOverflowIsAnErrorNamingTheFile) {
  try {
    meter::config::parse_scene_config(R"({"format": "meter-scene-config/1", "size": [-1e308480, 480]})", "overflow.json");
    FAIL() << "a number overflow was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("overflow.json: not valid JSON: "), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("number overflow parsing '-1e308480'"), std::string::npos) << e.what();
  } catch (const std::exception& e) {
    FAIL() << "escaped as another exception: " << e.what();
  }
}

TEST(SceneConfig, ResolveFilterDefaultsToTheBoxAndIsChecked) {
  const std::string head = R"({"format": "meter-scene-config/1")";
  EXPECT_EQ(meter::config::parse_scene_config(head + "}", "t.json").resolve, ResolveConfig{});
  EXPECT_EQ(ResolveConfig{}.filter, ResolveConfig::Filter::Box);
  const ResolveConfig film =
      meter::config::parse_scene_config(head + R"(, "resolve": {"filter": "blackman-harris", "width_px": 2.0}})", "t.json").resolve;
  EXPECT_EQ(film.filter, ResolveConfig::Filter::BlackmanHarris);
  EXPECT_EQ(film.width_px, 2.0);
  EXPECT_EQ(meter::config::parse_scene_config(head + R"(, "resolve": {"filter": "blackman-harris"}})", "t.json").resolve.width_px, 1.5);
  EXPECT_NE(error_of(head + R"(, "resolve": {"filter": "gauss"}})").find("t.json: $.resolve.filter: unknown filter \"gauss\""),
            std::string::npos);
  EXPECT_NE(error_of(head + R"(, "resolve": {"filter": "box", "width_px": 4}})").find("$.resolve.width_px: expected 0.5 .. 3"),
            std::string::npos);
  EXPECT_NE(error_of(head + R"(, "resolve": {"filtre": "box"}})").find("$.resolve.filtre: unknown key"), std::string::npos);
  EXPECT_NE(error_of(head + R"(, "resolve": "box"})").find("$.resolve: expected an object"), std::string::npos);
}

TEST(SceneConfig, SampleFormatDefaultsToEightBitAndIsChecked) {
  const std::string head = R"({"format": "meter-scene-config/1")";
  EXPECT_EQ(meter::config::parse_scene_config(head + "}", "t.json").resolve.sample_format, ResolveConfig::SampleFormat::Srgb8);
  const ResolveConfig half =
      meter::config::parse_scene_config(head + R"(, "resolve": {"filter": "blackman-harris", "sample_format": "rgba16f"}})", "t.json").resolve;
  EXPECT_EQ(half.sample_format, ResolveConfig::SampleFormat::Rgba16f);
  EXPECT_EQ(half.filter, ResolveConfig::Filter::BlackmanHarris);
  EXPECT_EQ(meter::config::parse_scene_config(head + R"(, "resolve": {"sample_format": "srgb8"}})", "t.json").resolve, ResolveConfig{});
  EXPECT_NE(error_of(head + R"(, "resolve": {"sample_format": "rgba32f"}})")
                .find("t.json: $.resolve.sample_format: unknown sample format \"rgba32f\" (expected srgb8 or rgba16f)"),
            std::string::npos);
  EXPECT_NE(error_of(head + R"(, "resolve": {"sample_format": 16}})").find("$.resolve.sample_format"), std::string::npos);
}

TEST(SceneConfig, SampleShadingDefaultsToOffAndIsChecked) {
  const std::string head = R"({"format": "meter-scene-config/1")";
  const auto kinds = [&](const std::string& value) {
    return meter::config::parse_scene_config(head + R"(, "sample_shading": )" + value + "}", "t.json").sample_shading;
  };
  EXPECT_FALSE(meter::config::parse_scene_config(head + "}", "t.json").sample_shading.any());
  EXPECT_FALSE(kinds(R"("off")").any());
  EXPECT_EQ(kinds(R"("normal-maps")"), (SampleShading{.normal_maps = true, .mirrors = false}));
  EXPECT_EQ(kinds(R"("mirrors")"), (SampleShading{.normal_maps = false, .mirrors = true}));
  EXPECT_EQ(kinds(R"(["normal-maps", "mirrors"])"), (SampleShading{.normal_maps = true, .mirrors = true}));
  EXPECT_FALSE(kinds("[]").any());
  EXPECT_NE(error_of(head + R"(, "sample_shading": "all"})").find("t.json: $.sample_shading: unknown value \"all\""),
            std::string::npos);
  // "off" is the whole value, not a kind in the list.
  EXPECT_NE(error_of(head + R"(, "sample_shading": ["mirrors", "off"]})").find("$.sample_shading[1]: unknown value \"off\""),
            std::string::npos);
  EXPECT_NE(error_of(head + R"(, "sample_shading": true})").find("$.sample_shading"), std::string::npos);
  EXPECT_NE(error_of(head + R"(, "sample_shading": [3]})").find("$.sample_shading[0]"), std::string::npos);
}
