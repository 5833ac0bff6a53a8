#include <gtest/gtest.h>

#include <map>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/convert/converter.hpp"
#include "meter/bridge/scene_config_parser.hpp"
#include "test_scenes.hpp"

using namespace meter::engine;
using namespace meter::convert;
using meter::protocol::SignalStatus;

namespace {

struct Fixture : ::testing::Test {
  static Scene& scene() {
    static Scene s = [] {
      auto dir = test::scratch_dir("bindings");
      ConvertOptions o;
      o.optimize = false;
      return convert_gltf(test::write_dial_scene(dir), parse_scene_config(test::dial_config_json()), o).scene;
    }();
    return s;
  }
  std::map<int, SignalValue> values;
  SignalLookup lookup() {
    return [this](int id) -> const SignalValue* {
      auto it = values.find(id);
      return it == values.end() ? nullptr : &it->second;
    };
  }
  void set(int id, double v, SignalStatus st = SignalStatus::Valid) { values[id] = {v, st, ""}; }
};

}  // namespace

TEST_F(Fixture, ValueMapsLinearlyToAnimationTimeAndClamps) {
  BindingEvaluator ev(scene());
  const int anim = scene().find_animation("SpeedNeedle");
  set(1, 130.0);
  EXPECT_TRUE(ev.update(lookup(), true, -1.0));
  EXPECT_NEAR(ev.outputs().animation_time[static_cast<std::size_t>(anim)], 10.8333333 / 2, 1e-9);
  set(1, 400.0);  // above the range: clamped to the end
  ev.update(lookup(), true, -1.0);
  EXPECT_NEAR(ev.outputs().animation_time[static_cast<std::size_t>(anim)], 10.8333333, 1e-9);
}

TEST_F(Fixture, UnchangedInputsReportNoChange) {
  BindingEvaluator ev(scene());
  set(1, 50.0);
  EXPECT_TRUE(ev.update(lookup(), true, -1.0));
  EXPECT_FALSE(ev.update(lookup(), true, 0.033));
  set(1, 51.0);
  EXPECT_TRUE(ev.update(lookup(), true, -1.0));
}

TEST_F(Fixture, SmoothingApproachesTheTargetAndSettles) {
  BindingEvaluator ev(scene());
  set(1, 0.0);
  ev.update(lookup(), true, -1.0);
  set(1, 100.0);
  ev.update(lookup(), true, 0.080);  // one time constant: 1 - 1/e of the way
  EXPECT_NEAR(ev.states()[0].value, 100.0 * (1.0 - std::exp(-1.0)), 1e-9);
  EXPECT_TRUE(ev.animating());
  for (int i = 0; i < 200 && ev.animating(); ++i) ev.update(lookup(), true, 0.033);
  EXPECT_FALSE(ev.animating());
  EXPECT_DOUBLE_EQ(ev.states()[0].value, 100.0);
  EXPECT_FALSE(ev.update(lookup(), true, 0.033));  // settled: no new frame needed
}

TEST_F(Fixture, InvalidStatusAppliesFailsafe) {
  BindingEvaluator ev(scene());
  const auto abs_mat = static_cast<std::size_t>(scene().find_material("TT_ABS_On"));
  set(1, 120.0);
  set(27, 0.0);
  ev.update(lookup(), true, -1.0);
  EXPECT_EQ(*ev.outputs().emissive[abs_mat], glm::vec3(0.0f));
  ASSERT_EQ(ev.outputs().texts.size(), 1u);
  EXPECT_EQ(ev.outputs().texts[0].text, "120");
  set(1, 120.0, SignalStatus::TimedOut);
  set(27, 0.0, SignalStatus::Invalid);
  ev.update(lookup(), true, -1.0);
  EXPECT_TRUE(ev.states()[0].failsafe);
  EXPECT_DOUBLE_EQ(ev.states()[0].value, 0.0);  // needle at rest
  EXPECT_EQ(ev.outputs().texts[0].text, "---");
  EXPECT_EQ(*ev.outputs().emissive[abs_mat], glm::vec3(1.0f, 0.6f, 0.0f));  // lamp on as failsafe
}

TEST_F(Fixture, LinkLossAppliesEveryFailsafeAndShowsTheLinkLossText) {
  BindingEvaluator ev(scene());
  set(1, 80.0);
  ev.update(lookup(), false, -1.0);
  EXPECT_TRUE(ev.outputs().link_lost);
  bool found = false;
  for (const auto& t : ev.outputs().texts) found = found || t.text == "NO SIGNAL";
  EXPECT_TRUE(found);
  EXPECT_DOUBLE_EQ(ev.states()[0].value, 0.0);
  ev.update(lookup(), true, -1.0);  // recovery
  EXPECT_DOUBLE_EQ(ev.states()[0].value, 80.0);
  for (const auto& t : ev.outputs().texts) EXPECT_NE(t.text, "NO SIGNAL");
}

TEST_F(Fixture, MorphWeightFollowsTheValue) {
  BindingEvaluator ev(scene());
  set(3, 25.0);
  ev.update(lookup(), true, -1.0);
  ASSERT_EQ(ev.outputs().morph.size(), 1u);
  EXPECT_FLOAT_EQ(ev.outputs().morph[0].weight, 0.25f);
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
