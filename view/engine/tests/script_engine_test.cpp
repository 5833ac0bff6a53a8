// Scene scripts without GL: outputs of every kind, precedence over bindings, runs only on an
// input change (counted), failsafe, error isolation, rate-limited messages.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/evaluation/scene_evaluator.hpp"
#include "meter/engine/frame_plan/draw_classes.hpp"
#include "meter/engine/logic/scripts.hpp"
#include "script_scene.hpp"

using namespace meter::engine;
using meter::protocol::SignalStatus;
using meter::protocol::SignalTable;
using nlohmann::json;
namespace sig = meter::protocol::sig;

namespace {

json script(const std::string& name, const std::string& code, json inputs, json outputs) {
  return {{"name", name}, {"code", code}, {"inputs", std::move(inputs)}, {"outputs", std::move(outputs)}};
}

const json kRpmGear = {{"rpm", "Vehicle.Powertrain.CombustionEngine.Speed"}, {"gear", "Vehicle.Powertrain.Transmission.CurrentGear"}};

// The shift light of docs/scene-logic.md: on above a gear-dependent rpm.
const char* kShiftLight = R"(
local limit = {[1] = 5500, [2] = 6000, [3] = 6200}
function run(IN, OUT)
  if not (IN.rpm.valid and IN.gear.valid) then OUT.lamp = false return end
  OUT.lamp = IN.rpm.value >= (limit[IN.gear.value] or 6500)
end
)";

struct Scripts : ::testing::Test {
  SignalTable values;
  void set(meter::protocol::SignalId id, double v, SignalStatus st = SignalStatus::Valid) { values.set(id, {v, st, ""}); }
};

int node(const Scene& s, const char* name) { return s.find_node(name); }
signed char visible(const BindingOutputs& o, const Scene& s, const char* name) { return o.node_visible[static_cast<std::size_t>(node(s, name))]; }

}  // namespace

TEST_F(Scripts, RunsOnlyWhenOneOfItsInputsChanges) {
  const Scene s = test::script_scene(json::array({script("shift", kShiftLight, kRpmGear, {{"lamp", {{"property", "visible"}, {"node", "Lamp"}}}})}).dump());
  ScriptEngine eng(s);
  auto update = [&] {
    BindingOutputs out = resting_outputs(s);
    eng.update(values, true, out);
    return visible(out, s, "Lamp");
  };
  set(sig::kEngineSpeed, 5000), set(sig::kCurrentGear, 1);
  EXPECT_EQ(update(), 0);
  EXPECT_EQ(eng.stats()[0].runs, 1u);
  for (int i = 0; i < 10; ++i) EXPECT_EQ(update(), 0);  // same inputs: the last outputs stand
  set(sig::kSpeed, 80);  // not an input
  update();
  EXPECT_EQ(eng.stats()[0].runs, 1u);
  EXPECT_EQ(eng.stats()[0].updates, 12u);
  set(sig::kEngineSpeed, 5600);
  EXPECT_EQ(update(), 1);  // above gear 1's limit
  set(sig::kCurrentGear, 2);
  EXPECT_EQ(update(), 0);  // gear 2 shifts higher
  set(sig::kCurrentGear, 2, SignalStatus::TimedOut);  // a status change is a change
  EXPECT_EQ(update(), 0);
  EXPECT_EQ(eng.stats()[0].runs, 4u);
  EXPECT_EQ(eng.stats()[0].failures, 0u);
  EXPECT_GT(eng.stats()[0].total_ms, 0.0);
  EXPECT_GE(eng.stats()[0].max_ms, eng.stats()[0].last_ms);
  EXPECT_GT(eng.stats()[0].memory_bytes, 0u);
}

TEST_F(Scripts, InputsCarryValueStatusAndValidity) {
  const char* code = R"(function run(IN, OUT) OUT.t = IN.v.status .. " " .. tostring(IN.v.valid) .. " " .. tostring(IN.v.value) end)";
  const Scene s = test::script_scene(
      json::array({script("st", code, {{"v", "Vehicle.Speed"}}, {{"t", {{"property", "text"}, {"node", "Text_Gear"}}}})}).dump());
  ScriptEngine eng(s);
  auto text = [&] {
    BindingOutputs out = resting_outputs(s);
    eng.update(values, true, out);
    return out.texts.empty() ? std::string("(none)") : out.texts[0].text;
  };
  EXPECT_EQ(text(), "not-available false nil");
  set(sig::kSpeed, 42.5);
  EXPECT_EQ(text(), "valid true 42.5");
  set(sig::kSpeed, 42.5, SignalStatus::TimedOut);
  EXPECT_EQ(text(), "timed-out false nil");  // the value is only given while valid
  set(sig::kSpeed, 1.0, SignalStatus::Invalid);
  EXPECT_EQ(text(), "invalid false nil");
}

TEST_F(Scripts, EveryOutputKindReachesTheFrameOutputs) {
  const char* code = R"(function run(IN, OUT)
    local v = IN.v.value
    OUT.time = v / 10
    OUT.shown = v > 50
    OUT.at = {1, 2, v}
    OUT.turn = {0, 0, 90}
    OUT.bar = v / 100
    OUT.paint = {1, 0, 0}
    OUT.glow = {0, v / 100, 0}
    OUT.label = string.format("%.0f", v)
  end)";
  json outputs = {{"time", {{"property", "time"}, {"animation", "Sweep"}}},
                  {"shown", {{"property", "visible"}, {"node", "Warn"}}},
                  {"at", {{"property", "translation"}, {"node", "Bar"}}},
                  {"turn", {{"property", "rotation"}, {"node", "Needle"}}},
                  {"bar", {{"property", "morph"}, {"node", "Bar"}, {"target", 1}}},
                  {"paint", {{"property", "color"}, {"material", "NeedleMat"}}},
                  {"glow", {{"property", "emissive"}, {"material", "LampMat"}}},
                  {"label", {{"property", "text"}, {"node", "Text_Gear"}, {"size_px", 30}, {"align", "right"}}}};
  const Scene s = test::script_scene(json::array({script("all", code, {{"v", "Vehicle.Speed"}}, outputs)}).dump());
  ScriptEngine eng(s);
  set(sig::kSpeed, 60);
  BindingOutputs out = resting_outputs(s);
  eng.update(values, true, out);
  ASSERT_FALSE(eng.stats()[0].failed) << eng.stats()[0].last_error;
  EXPECT_DOUBLE_EQ(out.animation_time[0], 6.0);
  EXPECT_EQ(visible(out, s, "Warn"), 1);
  ASSERT_EQ(out.transforms.size(), 2u);
  EXPECT_EQ(out.transforms[0].node, node(s, "Bar"));
  EXPECT_EQ(*out.transforms[0].translation, glm::vec3(1, 2, 60));
  EXPECT_EQ(out.transforms[1].node, node(s, "Needle"));
  // 90 degrees about +Z turns +X into +Y.
  const glm::vec3 x_turned = *out.transforms[1].rotation * glm::vec3(1, 0, 0);
  EXPECT_NEAR(x_turned.x, 0.0f, 1e-6f);
  EXPECT_NEAR(x_turned.y, 1.0f, 1e-6f);
  ASSERT_EQ(out.morph.size(), 1u);
  EXPECT_EQ(out.morph[0].target, 1);
  EXPECT_FLOAT_EQ(out.morph[0].weight, 0.6f);
  EXPECT_EQ(*out.base_color[1], glm::vec4(1, 0, 0, 1));  // alpha 1 when only rgb is given
  EXPECT_EQ(*out.emissive[0], glm::vec3(0, 0.6f, 0));
  ASSERT_EQ(out.texts.size(), 1u);
  EXPECT_EQ(out.texts[0].text, "60");
  EXPECT_EQ(out.texts[0].size_px, 30);
  EXPECT_EQ(out.texts[0].align, TextAlign::Right);
}

TEST_F(Scripts, AScriptOutputWinsOverABindingAndNilHandsTheProperty) {
  // Binding: Warn shown while ABS is on. Script: hides Warn above 100 km/h, else leaves it (nil).
  const char* code = R"(function run(IN, OUT) if IN.v.valid and IN.v.value > 100 then OUT.warn = false else OUT.warn = nil end end)";
  const Scene s = test::script_scene(
      json::array({script("hide", code, {{"v", "Vehicle.Speed"}}, {{"warn", {{"property", "visible"}, {"node", "Warn"}}}})}).dump(),
      R"([{"signal": "Cluster.Telltale.ABS", "kind": "visibility", "node": "Warn"}])");
  BindingEvaluator ev(s);
  set(sig::kAbs, 1), set(sig::kSpeed, 50);
  ev.update(values, true, -1.0);
  EXPECT_EQ(visible(ev.outputs(), s, "Warn"), 1);  // the binding's
  set(sig::kSpeed, 120);
  EXPECT_TRUE(ev.update(values, true, -1.0));
  EXPECT_EQ(visible(ev.outputs(), s, "Warn"), 0);  // the script's
  set(sig::kSpeed, 90);
  ev.update(values, true, -1.0);
  EXPECT_EQ(visible(ev.outputs(), s, "Warn"), 1);  // nil: the binding's again
}

TEST_F(Scripts, AFailingScriptIsIsolatedAndGoesToFailsafe) {
  // "bad" compares a nil (IN.v.value while not valid) on line 2; "good" and the binding go on.
  const char* bad = "function run(IN, OUT)\n  OUT.lamp = IN.v.value > 10\nend";
  const char* good = "function run(IN, OUT) OUT.label = tostring(IN.v.value) end";
  json scripts = json::array(
      {script("bad", bad, {{"v", "Vehicle.Speed"}}, {{"lamp", {{"property", "visible"}, {"node", "Lamp"}, {"failsafe", true}}}}),
       script("good", good, {{"v", "Vehicle.Speed"}}, {{"label", {{"property", "text"}, {"node", "Text_Gear"}}}})});
  const Scene s = test::script_scene(scripts.dump(), R"([{"signal": "Cluster.Telltale.ABS", "kind": "visibility", "node": "Warn"}])");
  BindingEvaluator ev(s);
  set(sig::kSpeed, 20), set(sig::kAbs, 1);
  ev.update(values, true, -1.0);
  EXPECT_EQ(visible(ev.outputs(), s, "Lamp"), 1);
  set(sig::kSpeed, 0, SignalStatus::TimedOut);
  ev.update(values, true, -1.0);
  const auto& st = ev.scripts()->stats();
  EXPECT_TRUE(st[0].failed);
  EXPECT_EQ(st[0].last_error, "bad:2: attempt to compare number with nil");
  EXPECT_EQ(visible(ev.outputs(), s, "Lamp"), 1);  // failsafe: lamp check look
  EXPECT_FALSE(st[1].failed);
  ASSERT_EQ(ev.outputs().texts.size(), 1u);
  EXPECT_EQ(ev.outputs().texts[0].text, "nil");      // the other script ran
  EXPECT_EQ(visible(ev.outputs(), s, "Warn"), 1);    // the binding still works
  auto messages = ev.scripts()->take_messages();
  ASSERT_EQ(messages.size(), 1u);
  EXPECT_EQ(messages[0], "bad:2: attempt to compare number with nil (outputs in failsafe; tried again when an input changes)");
  // Tried again at the next change: it recovers.
  set(sig::kSpeed, 5);
  ev.update(values, true, -1.0);
  EXPECT_FALSE(st[0].failed);
  EXPECT_EQ(visible(ev.outputs(), s, "Lamp"), 0);
  messages = ev.scripts()->take_messages();
  ASSERT_EQ(messages.size(), 1u);
  EXPECT_EQ(messages[0], "bad: runs again after 1 failed runs");
}

TEST_F(Scripts, OutputsWithoutAFailsafeHoldAndLinkLossShowsFailsafe) {
  const char* code = "function run(IN, OUT) OUT.lamp = true OUT.label = 'ok' end";
  json outputs = {{"lamp", {{"property", "visible"}, {"node", "Lamp"}}},
                  {"label", {{"property", "text"}, {"node", "Text_Gear"}, {"failsafe", "---"}}}};
  const Scene s = test::script_scene(json::array({script("s", code, {{"v", "Vehicle.Speed"}}, outputs)}).dump());
  ScriptEngine eng(s);
  set(sig::kSpeed, 1);
  BindingOutputs out = resting_outputs(s);
  eng.update(values, true, out);
  EXPECT_EQ(out.texts.at(0).text, "ok");
  out = resting_outputs(s);
  eng.update(values, false, out);  // link down: failsafe, no run
  EXPECT_EQ(eng.stats()[0].runs, 1u);
  EXPECT_EQ(out.texts.at(0).text, "---");
  EXPECT_EQ(visible(out, s, "Lamp"), 1);  // no failsafe: holds
  out = resting_outputs(s);
  eng.update(values, true, out);  // link back: runs again though no value changed
  EXPECT_EQ(eng.stats()[0].runs, 2u);
  EXPECT_EQ(out.texts.at(0).text, "ok");
}

TEST_F(Scripts, OutputsOfTheWrongTypeOrNotFiniteAreErrorsNamingTheOutput) {
  const test::LuaCase cases[] = {
      {"function run(IN, OUT) OUT.lamp = 1 end", "s: output lamp: expected true, false or nil, got number"},
      {"function run(IN, OUT) OUT.time = 0/0 end", "s: output time: expected a finite number, got NaN or infinity"},
      {"function run(IN, OUT) OUT.time = '3' end", "s: output time: expected a number or nil, got string"},
      {"function run(IN, OUT) OUT.paint = {1, 'x', 0} end", "s: output paint: expected a number in each component, got string"},
      {"function run(IN, OUT) OUT.label = string.rep('x', 300) end", "s: output label: a text of 300 bytes (at most 256)"},
  };
  json outputs = {{"lamp", {{"property", "visible"}, {"node", "Lamp"}}},
                  {"time", {{"property", "time"}, {"animation", "Sweep"}}},
                  {"paint", {{"property", "color"}, {"material", "NeedleMat"}}},
                  {"label", {{"property", "text"}, {"node", "Text_Gear"}}}};
  for (const auto& c : cases) {
    const Scene s = test::script_scene(json::array({script("s", c.code, {{"v", "Vehicle.Speed"}}, outputs)}).dump());
    ScriptEngine eng(s);
    BindingOutputs out = resting_outputs(s);
    eng.update(values, true, out);
    EXPECT_EQ(eng.stats()[0].last_error, c.error) << c.code;
  }
}

TEST_F(Scripts, MessagesAreRateLimitedAndCountWhatTheyLeftOut) {
  const char* code = "function run(IN, OUT) error('broken sensor ' .. tostring(IN.v.value)) end";
  const Scene s = test::script_scene(
      json::array({script("noisy", code, {{"v", "Vehicle.Speed"}}, {{"lamp", {{"property", "visible"}, {"node", "Lamp"}}}})}).dump());
  for (auto [interval, expected] : {std::pair{std::chrono::milliseconds(3600 * 1000), 1u}, std::pair{std::chrono::milliseconds(0), 5u}}) {
    ScriptEngine eng(s, interval);
    for (int i = 0; i < 5; ++i) {
      set(sig::kSpeed, i);
      BindingOutputs out = resting_outputs(s);
      eng.update(values, true, out);
    }
    const auto m = eng.take_messages();
    ASSERT_EQ(m.size(), expected);
    EXPECT_EQ(m[0], "noisy:1: broken sensor 0.0 (outputs in failsafe; tried again when an input changes)");
    EXPECT_EQ(eng.stats()[0].failures, 5u);
  }
}

TEST_F(Scripts, AScriptThatDoesNotLoadStaysOffWithItsMessage) {
  const Scene s = test::script_scene(json::array({script("norun", "local x = 1", {{"v", "Vehicle.Speed"}},
                                                         {{"lamp", {{"property", "visible"}, {"node", "Lamp"}, {"failsafe", false}}}})})
                                         .dump());
  ScriptEngine eng(s);
  BindingOutputs out = resting_outputs(s);
  eng.update(values, true, out);
  EXPECT_EQ(eng.stats()[0].runs, 0u);
  EXPECT_EQ(visible(out, s, "Lamp"), 0);
  const auto m = eng.take_messages();
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0], "norun: the script defines no function run(IN, OUT) (the script did not load: its outputs stay in failsafe)");
}

TEST_F(Scripts, AnUnknownTargetIsASceneErrorNamingScriptAndOutput) {
  Scene s = test::script_scene(
      json::array({script("s", "function run() end", {{"v", "Vehicle.Speed"}}, {{"lamp", {{"property", "visible"}, {"node", "Nope"}}}})}).dump());
  try {
    ScriptEngine eng(s);
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_STREQ(e.what(), "logic.gltf: script s output lamp: no node named \"Nope\"");
  }
}

TEST_F(Scripts, EnumAndTelltaleSignalsArriveAsIntegers) {
  const char* code = "function run(IN, OUT) OUT.t = tostring(IN.gear.value) .. ' ' .. math.type(IN.gear.value) .. ' ' .. math.type(IN.rpm.value) end";
  const Scene s = test::script_scene(json::array({script("ints", code, kRpmGear, {{"t", {{"property", "text"}, {"node", "Text_Gear"}}}})}).dump());
  ScriptEngine eng(s);
  set(sig::kCurrentGear, 3), set(sig::kEngineSpeed, 2000);
  BindingOutputs out = resting_outputs(s);
  eng.update(values, true, out);
  EXPECT_EQ(out.texts.at(0).text, "3 integer float");
}

TEST_F(Scripts, TranslationAndRotationMoveTheNodeAndLetGoAtNil) {
  const char* code = "function run(IN, OUT) if IN.v.value > 0 then OUT.at = {1, 2, 3} OUT.turn = {0, 0, 90} else OUT.at = nil OUT.turn = nil end end";
  json outputs = {{"at", {{"property", "translation"}, {"node", "Bar"}}}, {"turn", {{"property", "rotation"}, {"node", "Bar"}}}};
  const Scene s = test::script_scene(json::array({script("mover", code, {{"v", "Vehicle.Speed"}}, outputs)}).dump());
  BindingEvaluator ev(s);
  SceneEvaluator scene_eval(s);
  const auto bar = static_cast<std::size_t>(node(s, "Bar"));
  set(sig::kSpeed, 1);
  ev.update(values, true, -1.0);
  scene_eval.apply(ev.outputs());
  EXPECT_TRUE(scene_eval.update_world());
  const glm::mat4& w = scene_eval.world()[bar];
  EXPECT_EQ(glm::vec3(w[3]), glm::vec3(1, 2, 3));
  EXPECT_NEAR(w[0][1], 1.0f, 1e-6f);  // +X turned onto +Y
  set(sig::kSpeed, 0);
  ev.update(values, true, -1.0);
  scene_eval.apply(ev.outputs());
  EXPECT_TRUE(scene_eval.update_world());
  EXPECT_EQ(scene_eval.world()[bar], glm::mat4(1.0f));  // back to the rest pose
}

TEST_F(Scripts, NodesAndMaterialsAScriptWritesAreNeverStaticLayerMaterial) {
  const char* code = "function run(IN, OUT) OUT.at = {0, 0, 1} OUT.paint = {1, 0, 0} end";
  json outputs = {{"at", {{"property", "translation"}, {"node", "Bar"}}}, {"paint", {{"property", "color"}, {"material", "LampMat"}}}};
  Scene s = test::script_scene(json::array({script("w", code, {{"v", "Vehicle.Speed"}}, outputs)}).dump());
  Primitive needle_paint, lamp_paint;
  needle_paint.material = 1, lamp_paint.material = 0;
  s.meshes.push_back({"quad", {needle_paint, lamp_paint}, {}});
  s.programs.resize(1);
  s.draws = {{node(s, "Warn"), 0, 0, 0}, {node(s, "Bar"), 0, 0, 0}, {node(s, "Needle"), 0, 1, 0}};
  const DrawClasses c = classify_draws(s, false, -1);
  EXPECT_FALSE(c.changeable[0]);  // nothing writes Warn or NeedleMat
  EXPECT_TRUE(c.changeable[1]);   // the script moves Bar
  EXPECT_TRUE(c.changeable[2]);   // the script paints LampMat
}

TEST_F(Scripts, TheClusterShiftLightLightsNearEachGearsShiftPoint) {
  // bench/logic/scripts/shift_light.lua, the file docs/scene-logic.md gives the cluster.
  json sc = {{"name", "shift_light"}, {"file", "scripts/shift_light.lua"}, {"inputs", kRpmGear},
             {"outputs", {{"lamp", {{"property", "visible"}, {"node", "Lamp"}, {"failsafe", false}}},
                          {"glow", {{"property", "emissive"}, {"material", "LampMat"}, {"failsafe", {0, 0, 0}}}}}}};
  Scene s = test::script_scene("[]");
  s.config = meter::config::parse_scene_config(
      json{{"format", "meter-scene-config/1"}, {"scripts", json::array({sc})}}.dump(), std::string(METER_SOURCE_DIR) + "/bench/logic/cluster.json");
  ScriptEngine eng(s);
  auto lit = [&](double gear, double rpm, SignalStatus gear_status = SignalStatus::Valid) {
    set(sig::kCurrentGear, gear, gear_status), set(sig::kEngineSpeed, rpm);
    BindingOutputs out = resting_outputs(s);
    eng.update(values, true, out);
    EXPECT_FALSE(eng.stats()[0].failed) << eng.stats()[0].last_error;
    EXPECT_EQ(visible(out, s, "Lamp") == 1, out.emissive[0]->x > 0.5f);
    return visible(out, s, "Lamp") == 1;
  };
  EXPECT_TRUE(lit(1, 2124));    // 1st just before its upshift at 18 km/h
  EXPECT_FALSE(lit(2, 2124));   // the same rpm in 2nd is short of its point
  EXPECT_TRUE(lit(2, 2380));
  EXPECT_FALSE(lit(6, 2940));   // 6th cruising below 130 km/h
  EXPECT_TRUE(lit(6, 3055));    // 130 km/h in 6th
  EXPECT_FALSE(lit(126, 4000)); // park: no shift point
  EXPECT_FALSE(lit(6, 3055, SignalStatus::TimedOut));  // gear unknown: dark
}
