// The display features without GL: unit conversion and formatting, the theme transition curve,
// brightness, page switching, and the start-up sweep timeline with values arriving during it.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#include "meter/config/scene_config_parser.hpp"
#include "meter/convert/converter.hpp"
#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/evaluation/scene_features.hpp"
#include "meter/protocol/catalog.hpp"
#include "test_scenes.hpp"

using namespace meter::engine;
using namespace meter::convert;
using meter::protocol::SignalStatus;
using meter::protocol::SignalTable;

namespace {

// The dial test scene with every feature: the dial and the fuel bar are the two pages, the dial
// material turns into the fuel bar's at night, TT_ABS is a "km/h only" print, the needle sweeps.
std::string features_config() {
  std::string c = meter::engine::test::dial_config_json();
  const std::string bindings_start = "\"bindings\": [";
  c.replace(c.find(bindings_start), bindings_start.size(), bindings_start + R"(
    {"signal": "Vehicle.Speed", "kind": "text", "node": "Text_Status", "format": "%.0f km/h",
     "quantity": "speed", "imperial": {"format": "%.0f mph"}, "failsafe": {"text": "--"}},)");
  const std::string anim = R"("input": [0, 260], "time": [0.0, 10.8333333], "smoothing_ms": 80,)";
  c.replace(c.find(anim), anim.size(), anim + R"( "quantity": "speed", "imperial": {"input": [0, 160]},)");
  const std::string tail = "\"link_loss\"";
  c.replace(c.find(tail), tail.size(), R"("pages": {"signal": "Cluster.Page", "nodes": ["Dial", "FuelBar"]},
  "theme": {"signal": "Vehicle.Cabin.Infotainment.HMI.DayNightMode", "transition_ms": 1000,
            "pairs": [{"day": "Dial", "night": "FuelBarMat"}],
            "brightness_signal": "Vehicle.Cabin.Infotainment.HMI.Brightness", "brightness_min_stops": -3},
  "units": {"distance_signal": "Vehicle.Cabin.Infotainment.HMI.DistanceUnit", "metric_nodes": ["TT_ABS"]},
  "sweep": {"signal": "Vehicle.LowVoltageSystemState", "rise_ms": 1000, "hold_ms": 200, "fall_ms": 1000,
            "animations": ["SpeedNeedle"]},
  "link_loss")");
  return c;
}

meter::protocol::SignalId id(const char* name) {
  return static_cast<meter::protocol::SignalId>(meter::protocol::active_catalog()->find(name)->id);
}

struct Features : ::testing::Test {
  static Scene& scene() {
    static Scene s = [] {
      auto dir = meter::engine::test::scratch_dir("features");
      ConvertOptions o;
      o.optimize = false;
      return convert_gltf(meter::engine::test::write_dial_scene(dir), meter::config::parse_scene_config(features_config()), o).scene;
    }();
    return s;
  }
  SignalTable values;
  void set(const char* name, double v) { values.set(id(name), {v, SignalStatus::Valid, ""}); }
  double needle_time(const BindingEvaluator& ev) {
    return ev.outputs().animation_time[static_cast<std::size_t>(scene().find_animation("SpeedNeedle"))];
  }
  std::string readout(const BindingEvaluator& ev) {
    for (const auto& t : ev.outputs().texts)
      if (t.node == scene().find_node("Text_Status")) return t.text;
    return "(none)";
  }
};

constexpr double kFullTime = 10.8333333;  // the needle's time at full scale

}  // namespace

// ---- units

TEST(Units, ConvertByTheExactDefinitions) {
  EXPECT_DOUBLE_EQ(to_imperial(Quantity::Speed, 160.9344), 100.0);  // 1 mi = 1.609344 km
  EXPECT_DOUBLE_EQ(to_imperial(Quantity::Distance, 1.609344), 1.0);
  EXPECT_DOUBLE_EQ(to_imperial(Quantity::Temperature, 100.0), 212.0);
  EXPECT_DOUBLE_EQ(to_imperial(Quantity::Temperature, -40.0), -40.0);
  EXPECT_DOUBLE_EQ(to_imperial(Quantity::None, 7.0), 7.0);
  for (double v : {-40.0, 0.0, 18.5, 130.0, 9999.9})
    for (Quantity q : {Quantity::Speed, Quantity::Distance, Quantity::Temperature})
      EXPECT_NEAR(to_metric(q, to_imperial(q, v)), v, 1e-9 * (1 + std::abs(v)));
}

TEST(Units, TheR39BandConvertsWithItsOffsetScaled) {
  // The controller keeps 0 <= shown - true <= 0.1 true + 4 km/h. Converted, the band's edges are
  // shown_mph = true_mph and shown_mph = 1.1 true_mph + 4 / 1.609344 mph: the lower edge (never
  // under-read) is kept exactly, the 4 km/h offset becomes 2.4855 mph.
  for (double v = 0; v <= 260; v += 0.5) {
    const double upper = 1.1 * v + 4.0;
    EXPECT_NEAR(to_imperial(Quantity::Speed, upper), 1.1 * to_imperial(Quantity::Speed, v) + 4.0 / 1.609344, 1e-9);
    EXPECT_DOUBLE_EQ(to_imperial(Quantity::Speed, v) - to_imperial(Quantity::Speed, v), 0.0);
  }
  EXPECT_NEAR(4.0 / 1.609344, 2.4855, 1e-4);
}

TEST(Units, ImperialBindingConvertsInputsFormatsAndFailsafe) {
  Binding b;
  b.kind = BindingKind::Text;
  b.format = "%.0f km";
  b.failsafe_value = 100.0;
  b.input = {0, 260};
  b.units.quantity = Quantity::Distance;
  b.units.imperial.format = "%.1f mi";
  b.units.imperial.failsafe_text = "--- mi";
  const Binding i = imperial_binding(b);
  EXPECT_EQ(i.format, "%.1f mi");
  EXPECT_EQ(*i.failsafe_text, "--- mi");
  EXPECT_NEAR(*i.failsafe_value, 62.137119, 1e-6);
  EXPECT_NEAR(i.input[1], 161.557, 1e-3);  // no imperial input: the metric one converted
  EXPECT_EQ(binding_text(i, to_imperial(Quantity::Distance, 12.0)), "7.5 mi");
  b.units.imperial.input = std::array<double, 2>{0, 160};
  EXPECT_EQ(imperial_binding(b).input[1], 160.0);
}

TEST_F(Features, ReadoutAndNeedleFollowTheUnitSignal) {
  BindingEvaluator ev(scene());
  set("Vehicle.Speed", 100.0);
  ev.update(values, true, -1.0);
  EXPECT_EQ(readout(ev), "100 km/h");
  EXPECT_NEAR(needle_time(ev), 100.0 / 260.0 * kFullTime, 1e-9);
  EXPECT_EQ(ev.outputs().node_visible[static_cast<std::size_t>(scene().find_node("TT_ABS"))], 1);
  set("Vehicle.Cabin.Infotainment.HMI.DistanceUnit", 1);
  ev.update(values, true, 0.02);  // a live step: the switch is not smoothed
  EXPECT_EQ(readout(ev), "62 mph");
  // On the mph scale (0..160 over the same sweep) 62.137 mph is drawn where it is printed.
  EXPECT_NEAR(needle_time(ev), 100.0 / 1.609344 / 160.0 * kFullTime, 1e-9);
  EXPECT_EQ(ev.outputs().node_visible[static_cast<std::size_t>(scene().find_node("TT_ABS"))], 0);
  EXPECT_TRUE(ev.features().state().units.imperial_distance);
  // A unit signal that is lost shows the scene as authored (metric).
  values.set(id("Vehicle.Cabin.Infotainment.HMI.DistanceUnit"), {1, SignalStatus::TimedOut, ""});
  ev.update(values, true, 0.02);
  EXPECT_EQ(readout(ev), "100 km/h");
}

// ---- theme and brightness

TEST(Theme, CurveIsSmoothstepFromDayToNight) {
  EXPECT_EQ(theme_curve(0.0), 0.0);
  EXPECT_EQ(theme_curve(1.0), 1.0);
  EXPECT_DOUBLE_EQ(theme_curve(0.5), 0.5);
  EXPECT_DOUBLE_EQ(theme_curve(0.25), 0.15625);
  EXPECT_EQ(theme_curve(-1.0), 0.0);
  EXPECT_EQ(theme_curve(2.0), 1.0);
  double last = -1;
  for (int i = 0; i <= 100; ++i) {
    const double m = theme_curve(i / 100.0);
    EXPECT_GT(m, last);
    last = m;
  }
}

TEST(Theme, ProgressMovesAtTheTransitionRateBothWays) {
  double p = 0;
  for (int i = 0; i < 4; ++i) p = theme_progress(p, 1.0, 0.8, 0.1);
  EXPECT_NEAR(p, 0.5, 1e-12);
  for (int i = 0; i < 10; ++i) p = theme_progress(p, 1.0, 0.8, 0.1);
  EXPECT_EQ(p, 1.0);  // clamped at the target
  p = theme_progress(p, 0.0, 0.8, 0.2);
  EXPECT_NEAR(p, 0.75, 1e-12);
  EXPECT_EQ(theme_progress(0.3, 1.0, 0.8, -1.0), 1.0);  // offline: the state itself
  EXPECT_EQ(theme_progress(0.3, 0.0, 0.0, 0.01), 0.0);  // no transition time: at once
}

TEST(Theme, BrightnessScalesExposureInStops) {
  EXPECT_EQ(brightness_stops(100, -3), 0.0);
  EXPECT_EQ(brightness_stops(0, -3), -3.0);
  EXPECT_DOUBLE_EQ(brightness_stops(50, -3), -1.5);
  EXPECT_EQ(brightness_stops(250, -3), 0.0);  // clamped to 0..100 %
}

TEST_F(Features, NightBlendsTheMaterialPairAndBrightnessDims) {
  BindingEvaluator ev(scene());
  const auto dial = static_cast<std::size_t>(scene().find_material("Dial"));
  const auto night = scene().materials[static_cast<std::size_t>(scene().find_material("FuelBarMat"))];
  const auto day = scene().materials[dial];
  ev.update(values, true, 0.0);
  EXPECT_FALSE(ev.outputs().base_color[dial].has_value());  // day: the scene as authored
  set("Vehicle.Cabin.Infotainment.HMI.DayNightMode", 1);
  ev.update(values, true, 0.5);  // half of the 1 s transition: mix = smoothstep(0.5) = 0.5
  ASSERT_TRUE(ev.outputs().base_color[dial].has_value());
  const glm::vec4 mid = *ev.outputs().base_color[dial];
  EXPECT_NEAR(mid.g, 0.5f * (day.base_color.g + night.base_color.g), 1e-6);
  EXPECT_TRUE(ev.animating());
  ev.update(values, true, 0.6);
  EXPECT_NEAR(ev.outputs().base_color[dial]->g, night.base_color.g, 1e-6);
  EXPECT_FALSE(ev.features().active());
  EXPECT_FALSE(ev.outputs().exposure.has_value());
  set("Vehicle.Cabin.Infotainment.HMI.Brightness", 50);
  ev.update(values, true, 0.02);
  ASSERT_TRUE(ev.outputs().exposure.has_value());
  EXPECT_DOUBLE_EQ(*ev.outputs().exposure, -1.5);
}

// ---- pages

TEST(Pages, TransitionShowsBothPagesUntilItsClipHasPlayed) {
  PageSwitcher p(3, 0, {0.0, 0.5, 0.0});
  EXPECT_TRUE(p.shown(0));
  EXPECT_FALSE(p.shown(1));
  p.update(1, 0.02);
  EXPECT_EQ(p.current(), 1);
  EXPECT_TRUE(p.shown(0) && p.shown(1));
  ASSERT_TRUE(p.transition());
  EXPECT_EQ(*p.transition(), 0.0);
  p.update(1, 0.25);
  EXPECT_NEAR(*p.transition(), 0.5, 1e-12);
  p.update(1, 0.25);
  EXPECT_FALSE(p.transition());
  EXPECT_FALSE(p.shown(0));
  p.update(7, 0.02);  // no such page: ignored
  p.update(std::nullopt, 0.02);
  EXPECT_EQ(p.current(), 1);
  p.update(2, 0.02);  // no clip: at once
  EXPECT_FALSE(p.transition());
  EXPECT_TRUE(p.shown(2) && !p.shown(1));
  p.update(1, -1.0);  // offline: the page itself, no transition
  EXPECT_FALSE(p.transition());
  EXPECT_TRUE(p.shown(1) && !p.shown(2));
}

TEST_F(Features, PageSignalShowsOnePageSubtree) {
  BindingEvaluator ev(scene());
  const auto dial = static_cast<std::size_t>(scene().find_node("Dial"));
  const auto bar = static_cast<std::size_t>(scene().find_node("FuelBar"));
  ev.update(values, true, -1.0);
  EXPECT_EQ(ev.outputs().node_visible[dial], 1);
  EXPECT_EQ(ev.outputs().node_visible[bar], 0);
  set("Cluster.Page", 1);
  ev.update(values, true, -1.0);
  EXPECT_EQ(ev.outputs().node_visible[dial], 0);
  EXPECT_EQ(ev.outputs().node_visible[bar], 1);
  EXPECT_EQ(ev.features().state().page, 1);
}

TEST_F(Features, AScriptCanSetThePageInsteadOfTheSignal) {
  BindingEvaluator ev(scene());
  set("Cluster.Page", 0);
  FeatureOverrides o;
  o.page = 1;
  ev.set_feature_overrides(o);
  ev.update(values, true, -1.0);
  EXPECT_EQ(ev.features().state().page, 1);
  EXPECT_EQ(ev.outputs().node_visible[static_cast<std::size_t>(scene().find_node("FuelBar"))], 1);
  ev.set_feature_overrides({});
  ev.update(values, true, -1.0);
  EXPECT_EQ(ev.features().state().page, 0);
}

// ---- sweep

TEST(Sweep, PositionRisesHoldsAndFalls) {
  meter::bridge::SweepConfig s;  // 1 s up, 0.2 s hold, 1 s down
  EXPECT_EQ(*sweep_position(s, 0.0), 0.0);
  EXPECT_DOUBLE_EQ(*sweep_position(s, 0.5), 0.5);
  EXPECT_EQ(*sweep_position(s, 1.0), 1.0);
  EXPECT_EQ(*sweep_position(s, 1.1), 1.0);
  EXPECT_DOUBLE_EQ(*sweep_position(s, 1.7), 0.5);
  EXPECT_FALSE(sweep_position(s, 2.2).has_value());
}

TEST(Sweep, StartsAtIgnitionOnOnlyOnARisingEdgeAndLiveOnly) {
  meter::bridge::SweepConfig s;
  SweepTimeline t(s);
  t.update(2.0, 0.02);  // OFF
  EXPECT_FALSE(t.running());
  t.update(4.0, 0.02);  // ON
  EXPECT_TRUE(t.running());
  for (int i = 0; i < 120; ++i) t.update(4.0, 0.02);
  EXPECT_FALSE(t.running());
  t.update(std::nullopt, 0.02);  // ignition lost and back: still on, no second sweep
  t.update(4.0, 0.02);
  EXPECT_FALSE(t.running());
  SweepTimeline offline(s);
  offline.update(4.0, -1.0);
  EXPECT_FALSE(offline.running());
}

TEST_F(Features, ValuesArrivingDuringTheSweepAreShownRightAfterIt) {
  BindingEvaluator ev(scene());
  set("Vehicle.LowVoltageSystemState", 4);
  ev.update(values, true, 0.02);
  EXPECT_NEAR(needle_time(ev), 0.0, 1e-9);  // the sweep starts at rest
  double t = 0;
  for (; t < 1.1; t += 0.02) ev.update(values, true, 0.02);
  EXPECT_NEAR(needle_time(ev), kFullTime, 1e-9);  // held at full scale
  set("Vehicle.Speed", 80.0);  // arrives during the sweep: the sweep goes on
  for (; t < 1.6; t += 0.02) ev.update(values, true, 0.02);
  EXPECT_LT(needle_time(ev), kFullTime);
  EXPECT_GT(needle_time(ev), 50.0 / 260.0 * kFullTime);
  set("Vehicle.Speed", 90.0);
  for (; t < 2.3; t += 0.02) ev.update(values, true, 0.02);
  EXPECT_FALSE(ev.features().state().sweep.has_value());
  // After the sweep the needle rises from rest to the newest value with its smoothing (80 ms):
  // 1 s later it is there.
  for (int i = 0; i < 50; ++i) ev.update(values, true, 0.02);
  EXPECT_NEAR(needle_time(ev), 90.0 / 260.0 * kFullTime, 1e-9);
  EXPECT_EQ(readout(ev), "90 km/h");
}

// ---- config errors

TEST(FeatureConfig, ErrorsNameTheKey) {
  auto fails = [](const std::string& text, const std::string& expected) {
    try {
      (void)meter::config::parse_scene_config(text, "f.json");
      ADD_FAILURE() << "accepted: " << text;
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()), expected);
    }
  };
  const std::string head = R"({"format": "meter-scene-config/1", )";
  fails(head + R"("pages": {"signal": "Cluster.Page", "nodes": ["A"]}})",
        "f.json: $.pages.nodes: expected 2..16 page root nodes");
  fails(head + R"("pages": {"signal": "Cluster.Pages", "nodes": ["A", "B"]}})",
        "f.json: $.pages.signal: \"Cluster.Pages\" is not in the signal catalog " +
            meter::protocol::active_catalog()->source());
  fails(head + R"("sweep": {"signal": "Vehicle.LowVoltageSystemState", "animations": ["RpmNeedle"]}})",
        "f.json: $.sweep.animations[0]: \"RpmNeedle\" is not the animation of an animation binding");
  fails(head + R"("bindings": [{"signal": "Vehicle.Speed", "kind": "text", "node": "T", "imperial": {"format": "%.0f"}}]})",
        "f.json: $.bindings[0].imperial: needs \"quantity\" (what the value measures)");
  fails(head + R"("bindings": [{"signal": "Vehicle.Speed", "kind": "text", "node": "T", "quantity": "speed", "imperial": {"format": "%d"}}]})",
        "f.json: $.bindings[0].imperial.format: only %f %e %g (with flags, width, precision) and %% are allowed in \"%d\"");
  fails(head + R"("theme": {"signal": "Vehicle.Cabin.Infotainment.HMI.DayNightMode", "pairs": [{"day": "A", "night": "B"}], "transition_ms": -5}})",
        "f.json: $.theme.transition_ms: expected a duration 0..60000 ms");
}

TEST(FeatureConfig, ConverterRefusesNamesTheSceneLacks) {
  auto dir = meter::engine::test::scratch_dir("features_bad");
  std::string c = features_config();
  c.replace(c.find("\"FuelBar\"]"), 10, "\"Trip\"]");
  ConvertOptions o;
  o.optimize = false;
  try {
    (void)convert_gltf(meter::engine::test::write_dial_scene(dir), meter::config::parse_scene_config(c, "f.json"), o);
    ADD_FAILURE() << "accepted a page root the scene does not have";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("$.pages.nodes: no node named \"Trip\" in the scene"), std::string::npos) << e.what();
  }
}

// ---- programs of themed materials

TEST(FeaturePrograms, ProgramsSharedByMaterialsKeepTheirDifferingParametersAsUniforms) {
  // Themed materials keep their colours as uniforms, so the converter shares one program between
  // materials with equal features: a material parameter in which they differ (the chrome's
  // metallic 1 / roughness 0.12 against the print's 0 / 0.6) must then be a uniform set per draw,
  // never a constant folded from whichever material made the program first.
  using meter::bridge::UniformSemantic;
  const Scene& s = meter::engine::test::cluster_scene();
  std::map<int, std::set<int>> materials_of_program;
  for (const auto& d : s.draws) {
    const auto& prim = s.meshes[static_cast<std::size_t>(d.mesh)].primitives[static_cast<std::size_t>(d.primitive)];
    materials_of_program[d.program].insert(prim.material);
  }
  int shared = 0;
  for (const auto& [program, mats] : materials_of_program) {
    if (mats.size() < 2) continue;
    ++shared;
    const auto& p = s.programs[static_cast<std::size_t>(program)].program;
    const auto& first = s.materials[static_cast<std::size_t>(*mats.begin())];
    for (int m : mats) {
      const auto& mat = s.materials[static_cast<std::size_t>(m)];
      const bool metallic_used = p.features.shading == meter::bridge::ShadingModel::PbrMetallicRoughness;
      if (metallic_used && mat.metallic != first.metallic) {
        EXPECT_NE(p.find_uniform(UniformSemantic::MetallicFactor), nullptr) << mat.name << " vs " << first.name;
      }
      if (metallic_used && mat.roughness != first.roughness) {
        EXPECT_NE(p.find_uniform(UniformSemantic::RoughnessFactor), nullptr) << mat.name << " vs " << first.name;
      }
    }
  }
  EXPECT_GT(shared, 0);  // the cluster's themed and lamp materials do share programs
}
