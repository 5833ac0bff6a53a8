#include <gtest/gtest.h>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/convert/converter.hpp"
#include "meter/config/scene_config_parser.hpp"
#include "test_scenes.hpp"

using namespace meter::engine;
using namespace meter::convert;
using meter::protocol::SignalStatus;
using meter::protocol::SignalTable;

namespace {

struct Fixture : ::testing::Test {
  static Scene& scene() {
    static Scene s = [] {
      auto dir = test::scratch_dir("bindings");
      ConvertOptions o;
      o.optimize = false;
      return convert_gltf(test::write_dial_scene(dir), meter::config::parse_scene_config(test::dial_config_json()), o).scene;
    }();
    return s;
  }
  SignalTable values;
  void set(meter::protocol::SignalId id, double v, SignalStatus st = SignalStatus::Valid) { values.set(id, {v, st, ""}); }
};

}  // namespace

TEST_F(Fixture, ValueMapsLinearlyToAnimationTimeAndClamps) {
  BindingEvaluator ev(scene());
  const int anim = scene().find_animation("SpeedNeedle");
  set(1, 130.0);
  EXPECT_TRUE(ev.update(values, true, -1.0));
  EXPECT_NEAR(ev.outputs().animation_time[static_cast<std::size_t>(anim)], 10.8333333 / 2, 1e-9);
  set(1, 400.0);  // above the range: clamped to the end
  ev.update(values, true, -1.0);
  EXPECT_NEAR(ev.outputs().animation_time[static_cast<std::size_t>(anim)], 10.8333333, 1e-9);
}

TEST_F(Fixture, UnchangedInputsReportNoChange) {
  BindingEvaluator ev(scene());
  set(1, 50.0);
  EXPECT_TRUE(ev.update(values, true, -1.0));
  EXPECT_FALSE(ev.update(values, true, 0.033));
  set(1, 51.0);
  EXPECT_TRUE(ev.update(values, true, -1.0));
}

TEST_F(Fixture, SmoothingApproachesTheTargetAndSettles) {
  BindingEvaluator ev(scene());
  set(1, 0.0);
  ev.update(values, true, -1.0);
  set(1, 100.0);
  ev.update(values, true, 0.080);  // one time constant: 1 - 1/e of the way
  EXPECT_NEAR(ev.states()[0].value, 100.0 * (1.0 - std::exp(-1.0)), 1e-9);
  EXPECT_TRUE(ev.animating());
  for (int i = 0; i < 200 && ev.animating(); ++i) ev.update(values, true, 0.033);
  EXPECT_FALSE(ev.animating());
  EXPECT_DOUBLE_EQ(ev.states()[0].value, 100.0);
  EXPECT_FALSE(ev.update(values, true, 0.033));  // settled: no new frame needed
}

TEST_F(Fixture, InvalidStatusAppliesFailsafe) {
  BindingEvaluator ev(scene());
  const auto abs_mat = static_cast<std::size_t>(scene().find_material("TT_ABS_On"));
  set(1, 120.0);
  set(27, 0.0);
  ev.update(values, true, -1.0);
  EXPECT_EQ(*ev.outputs().emissive[abs_mat], glm::vec3(0.0f));
  ASSERT_EQ(ev.outputs().texts.size(), 1u);
  EXPECT_EQ(ev.outputs().texts[0].text, "120");
  set(1, 120.0, SignalStatus::TimedOut);
  set(27, 0.0, SignalStatus::Invalid);
  ev.update(values, true, -1.0);
  EXPECT_TRUE(ev.states()[0].failsafe);
  EXPECT_DOUBLE_EQ(ev.states()[0].value, 0.0);  // needle at rest
  EXPECT_EQ(ev.outputs().texts[0].text, "---");
  EXPECT_EQ(*ev.outputs().emissive[abs_mat], glm::vec3(1.0f, 0.6f, 0.0f));  // lamp on as failsafe
}

TEST_F(Fixture, LinkLossAppliesEveryFailsafeAndShowsTheLinkLossText) {
  BindingEvaluator ev(scene());
  set(1, 80.0);
  ev.update(values, false, -1.0);
  EXPECT_TRUE(ev.outputs().link_lost);
  bool found = false;
  for (const auto& t : ev.outputs().texts) found = found || t.text == "NO SIGNAL";
  EXPECT_TRUE(found);
  EXPECT_DOUBLE_EQ(ev.states()[0].value, 0.0);
  ev.update(values, true, -1.0);  // recovery
  EXPECT_DOUBLE_EQ(ev.states()[0].value, 80.0);
  for (const auto& t : ev.outputs().texts) EXPECT_NE(t.text, "NO SIGNAL");
}

TEST_F(Fixture, MorphWeightFollowsTheValue) {
  BindingEvaluator ev(scene());
  set(3, 25.0);
  ev.update(values, true, -1.0);
  ASSERT_EQ(ev.outputs().morph.size(), 1u);
  EXPECT_FLOAT_EQ(ev.outputs().morph[0].weight, 0.25f);
}

// A table holds every catalog signal, NotAvailable until set: such an entry must look exactly like
// "nothing known", whatever value and text it carries, on every path (failsafe, hold, text).
TEST_F(Fixture, NotAvailableEntryReadsAsNothingKnownWhateverItCarries) {
  BindingEvaluator resting(scene());
  resting.update(SignalTable{}, true, -1.0);
  BindingEvaluator ev(scene());
  values.set(1, {120.0, SignalStatus::NotAvailable, "stale"});
  values.set(27, {0.0, SignalStatus::NotAvailable, "stale"});
  values.set(3, {90.0, SignalStatus::NotAvailable, "stale"});
  ev.update(values, true, -1.0);
  EXPECT_EQ(ev.outputs(), resting.outputs());
  EXPECT_TRUE(ev.states()[0].failsafe);
  EXPECT_EQ(ev.states()[0].status, SignalStatus::NotAvailable);
  ASSERT_EQ(ev.outputs().texts.size(), 1u);
  EXPECT_EQ(ev.outputs().texts[0].text, "---");  // the failsafe text, never the entry's value 120
  EXPECT_TRUE(ev.outputs().morph.empty()) << "no failsafe and nothing held yet: the fuel bar is not driven";
}

TEST_F(Fixture, NotAvailableAfterAValueHoldsTheLastValue) {
  BindingEvaluator ev(scene());
  set(3, 25.0);
  ev.update(values, true, -1.0);
  set(3, 90.0, SignalStatus::NotAvailable);
  ev.update(values, true, -1.0);
  ASSERT_EQ(ev.outputs().morph.size(), 1u);
  EXPECT_FLOAT_EQ(ev.outputs().morph[0].weight, 0.25f) << "the fuel binding has no failsafe: it holds";
  ev.update(SignalTable{}, true, -1.0);  // back to a resting entry: the same hold
  ASSERT_EQ(ev.outputs().morph.size(), 1u);
  EXPECT_FLOAT_EQ(ev.outputs().morph[0].weight, 0.25f);
}

// A binding whose id is unresolved, not in the catalog or beyond the SignalId range reads nothing:
// 65537 must not wrap onto 1 (Vehicle.Speed), -1 not onto 65535.
TEST_F(Fixture, UnknownOrOutOfRangeSignalIdsReadAsNotAvailable) {
  set(1, 120.0);
  for (int id : {-1, 1000, 65535, 65537, 1 << 20}) {
    Scene s = scene();
    for (auto& b : s.config.bindings)
      if (b.signal_id == 1) b.signal_id = id;
    BindingEvaluator ev(s);
    ev.update(values, true, -1.0);
    EXPECT_TRUE(ev.states()[0].failsafe) << id;
    EXPECT_DOUBLE_EQ(ev.states()[0].value, 0.0) << id;
    EXPECT_EQ(ev.states()[0].status, SignalStatus::NotAvailable) << id;
    ASSERT_EQ(ev.outputs().texts.size(), 1u) << id;
    EXPECT_EQ(ev.outputs().texts[0].text, "---") << id;
  }
  EXPECT_EQ(bound_signal_id(Binding{}), std::nullopt);
}

TEST(BoundSignalId, ChecksTheRangeBeforeConverting) {
  Binding b;
  b.signal_id = 0;
  EXPECT_EQ(bound_signal_id(b), std::optional<meter::protocol::SignalId>(0));
  b.signal_id = 65535;
  EXPECT_EQ(bound_signal_id(b), std::optional<meter::protocol::SignalId>(65535));
  b.signal_id = 65536;
  EXPECT_EQ(bound_signal_id(b), std::nullopt);
  b.signal_id = -2;
  EXPECT_EQ(bound_signal_id(b), std::nullopt);
}

TEST(BindingText, MapWinsForIntegralValuesElseFormat) {
  Binding b;
  b.kind = BindingKind::Text;
  b.format = "%.0f";
  b.map = {{-1, "R"}, {0, "N"}, {126, "P"}};
  EXPECT_EQ(binding_text(b, -1.0), "R");
  EXPECT_EQ(binding_text(b, 126.0), "P");
  EXPECT_EQ(binding_text(b, 3.0), "3");
  EXPECT_EQ(binding_text(b, 0.4), "0");  // not integral: formatted, not mapped
}

// A view that takes its controller's catalog looks every binding up again by name: the speed
// needle follows Vehicle.Speed under the controller's id, and a signal the new catalog lacks reads
// as not-available (its failsafe), reported by name.
TEST_F(Fixture, RebindFollowsTheNewCatalogsIdsByName) {
  auto parsed = meter::protocol::parse_catalog(
      R"({"Vehicle": {"type": "branch", "children": {"Speed": {"type": "sensor", "datatype": "float", "min": 0, "max": 300, "meter_id": 700}}},
          "Cluster": {"type": "branch", "children": {"Telltale": {"type": "branch", "children": {
             "ABS": {"type": "sensor", "datatype": "boolean", "meter_id": 701}}}}}})",
      "controller.vss.json");
  ASSERT_TRUE(parsed.catalog) << parsed.error;
  BindingEvaluator ev(scene());
  const auto missing = ev.rebind(*parsed.catalog);
  EXPECT_EQ(missing, std::vector<std::string>{"Vehicle.Powertrain.FuelSystem.RelativeLevel"});
  SignalTable table(parsed.catalog);
  table.set(700, 130.0, SignalStatus::Valid);
  ev.update(table, true, -1.0);
  const int anim = scene().find_animation("SpeedNeedle");
  EXPECT_NEAR(ev.outputs().animation_time[static_cast<std::size_t>(anim)], 10.8333333 / 2, 1e-9);
  for (std::size_t i = 0; i < ev.bindings().size(); ++i) {
    if (ev.bindings()[i].signal == "Vehicle.Powertrain.FuelSystem.RelativeLevel") {
      EXPECT_EQ(ev.states()[i].status, SignalStatus::NotAvailable);
      EXPECT_TRUE(ev.states()[i].failsafe);
    }
  }
}
