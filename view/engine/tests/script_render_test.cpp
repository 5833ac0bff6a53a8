// Scene scripts rendered: the dial test scene with three scripts (a needle that turns red above a
// limit, a shift light that depends on the gear, a gear readout), in named states on BOTH
// backends against committed goldens (golden/scripts_*.png; METER_UPDATE_GOLDEN=1 rewrites them).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include <nlohmann/json.hpp>

#include "meter/config/scene_config_parser.hpp"
#include "meter/convert/converter.hpp"
#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/logic/scripts.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/image.hpp"
#include "test_scenes.hpp"

using namespace meter;
using namespace meter::engine;
using meter::protocol::SignalStatus;
namespace fs = std::filesystem;
namespace sig = meter::protocol::sig;

namespace {

// Both backends are llvmpipe (EGL GLES 3.2, OSMesa desktop 4.5): MSAA edges and glyph blending may
// differ by a level or two. 40 dB PSNR allows an RMS error of ~2.6 levels, far above that noise
// and far below any script effect here (a needle recoloured, the lamp lit, a digit changed each
// drop PSNR under 30 dB at this size).
constexpr double kPsnrDb = 40.0;

const char* kScripts = R"([
  {"name": "needle_red", "inputs": {"speed": "Vehicle.Speed"},
   "code": "function run(IN, OUT)\n  local fast = IN.speed.valid and IN.speed.value > 200\n  OUT.needle = fast and {1, 0.05, 0.02} or {0.9, 0.9, 0.9}\nend",
   "outputs": {"needle": {"property": "color", "material": "NeedleMat", "failsafe": [0.9, 0.9, 0.9]}}},
  {"name": "shift_light", "inputs": {"rpm": "Vehicle.Powertrain.CombustionEngine.Speed", "gear": "Vehicle.Powertrain.Transmission.CurrentGear"},
   "code": "local limit = {5500, 6000, 6200, 6300}\nfunction run(IN, OUT)\n  local on = IN.rpm.valid and IN.gear.valid and IN.rpm.value >= (limit[IN.gear.value] or 6500)\n  OUT.lamp = on and {0, 1, 0} or {0, 0, 0}\nend",
   "outputs": {"lamp": {"property": "emissive", "material": "TT_ABS_On", "failsafe": [0, 0, 0]}}},
  {"name": "gear", "inputs": {"gear": "Vehicle.Powertrain.Transmission.CurrentGear"},
   "code": "function run(IN, OUT)\n  OUT.gear = string.format('%d', IN.gear.value)\nend",
   "outputs": {"gear": {"property": "text", "node": "Text_Status", "size_px": 16, "color": [0.4, 0.8, 1, 1], "align": "center", "failsafe": "-"}}},
  {"name": "frost", "inputs": {"air": "Vehicle.Exterior.AirTemperature"},
   "code": "function run(IN, OUT)\n  local icy = IN.air.valid and IN.air.value < 3\n  OUT.turn = icy and {0, 0, 45} or nil\n  OUT.at = icy and {0.6, -0.6, 0} or nil\nend",
   "outputs": {"turn": {"property": "rotation", "node": "TT_ABS"}, "at": {"property": "translation", "node": "TT_ABS"}}}
])";

const Scene& scripted_dial() {
  static Scene s = [] {
    nlohmann::json c = nlohmann::json::parse(test::dial_config_json());
    c["scripts"] = nlohmann::json::parse(kScripts);
    const auto dir = test::scratch_dir("script_render");
    return convert::convert_gltf(test::write_dial_scene(dir), meter::config::parse_scene_config(c.dump(), "scripted_dial.json"),
                                 convert::ConvertOptions{true})
        .scene;
  }();
  return s;
}

class ScriptRender : public ::testing::TestWithParam<platform::BackendKind> {
 protected:
  void SetUp() override {
    backend_ = platform::create_backend(GetParam());
    renderer_ = std::make_unique<Renderer>(*backend_, scripted_dial(), RendererOptions{});
    evaluator_ = std::make_unique<BindingEvaluator>(scripted_dial());
  }
  const platform::Image& draw(double speed, double rpm, double gear, SignalStatus gear_status = SignalStatus::Valid, double air = 20) {
    values_.set(sig::kOutsideTemp, {air, SignalStatus::Valid, ""});
    values_.set(sig::kSpeed, {speed, SignalStatus::Valid, ""});
    values_.set(sig::kEngineSpeed, {rpm, SignalStatus::Valid, ""});
    values_.set(sig::kCurrentGear, {gear, gear_status, ""});
    values_.set(sig::kAbs, {0.0, SignalStatus::Valid, ""});
    evaluator_->update(values_, true, -1.0);
    renderer_->apply(evaluator_->outputs());
    renderer_->render(false, true);
    return renderer_->last_image();
  }
  void expect_golden(const platform::Image& img, const std::string& name) {
    const std::string backend(platform::to_string(GetParam()));
    const fs::path golden = fs::path(METER_SOURCE_DIR) / "view/engine/tests/golden" / (name + ".png");
    const fs::path actual = fs::path(test::scratch_dir("script_render_" + name + "_" + backend)) / "actual.png";
    platform::write_png(img, actual);
    if (std::getenv("METER_UPDATE_GOLDEN") && GetParam() == platform::BackendKind::Egl) platform::write_png(img, golden);
    ASSERT_TRUE(fs::exists(golden)) << golden << " missing (run with METER_UPDATE_GOLDEN=1)";
    EXPECT_GE(platform::psnr(platform::read_png(golden), img), kPsnrDb) << name << " on " << backend << "; actual in " << actual;
  }
  const ScriptStats& stats(std::size_t i) const { return evaluator_->scripts()->stats()[i]; }

  protocol::SignalTable values_;
  std::unique_ptr<platform::GpuBackend> backend_;
  std::unique_ptr<Renderer> renderer_;
  std::unique_ptr<BindingEvaluator> evaluator_;
};

// Pixel probes (320x160): the needle straight up at 130 km/h passes (160, 45); the ABS quad
// (lit by the shift light here) is centred at (207, 127).
const std::uint8_t* needle_px(const platform::Image& img) { return img.pixel(160, 45); }
const std::uint8_t* lamp_px(const platform::Image& img) { return img.pixel(207, 127); }

}  // namespace

TEST_P(ScriptRender, CruiseShowsAWhiteNeedleADarkLampAndTheGear) {
  const auto& img = draw(130, 2500, 4);
  EXPECT_GT(needle_px(img)[1], 150);  // white, not red: green channel high
  EXPECT_LT(lamp_px(img)[1], 60);
  expect_golden(img, "scripts_cruise");
}

TEST_P(ScriptRender, ShiftPointLightsTheLampAndFastTurnsTheNeedleRed) {
  const auto& img = draw(210, 6400, 3);
  EXPECT_GT(lamp_px(img)[1], 150);  // green lamp
  EXPECT_LT(lamp_px(img)[0], 100);
  expect_golden(img, "scripts_shift");
  // The same rpm in 4th is below its shift point: dark again.
  EXPECT_LT(lamp_px(draw(210, 6200, 4))[1], 60);
}

TEST_P(ScriptRender, AFailedScriptShowsItsFailsafeAndTheRestKeepsWorking) {
  // The gear is timed out: the gear script fails on its nil value (its text shows "-"); the needle
  // and shift-light scripts and the bindings (needle angle, speed text) go on.
  const auto& img = draw(130, 2500, 4, SignalStatus::TimedOut);
  EXPECT_TRUE(stats(2).failed);
  EXPECT_EQ(stats(2).last_error, "gear:2: bad argument #2 to 'format' (number expected, got nil)");
  EXPECT_FALSE(stats(0).failed);
  EXPECT_FALSE(stats(1).failed);
  EXPECT_GT(needle_px(img)[1], 150);
  expect_golden(img, "scripts_gear_failed");
}

TEST_P(ScriptRender, FrostTurnsAndMovesTheLampAndThePartialRedrawKeepsUp) {
  draw(210, 6400, 3);  // the lamp lit where it belongs
  const platform::Image moved = draw(210, 6400, 3, SignalStatus::Valid, -2.0);  // turned 45 degrees, moved in
  EXPECT_LT(lamp_px(moved)[1], 60);  // no longer at its own place
  expect_golden(moved, "scripts_frost");
  // Drawn as a partial redraw over the previous frame: the same pixels as a fresh full frame (no
  // stale lamp left behind; the static layer knows the script moves the node). 60 dB: the two are
  // the same draws of the same state, so only exact-equal pixels are expected.
  RendererOptions full;
  full.partial_redraw = false;
  Renderer fresh(*backend_, scripted_dial(), full);
  fresh.apply(evaluator_->outputs());
  fresh.render(true, true);
  EXPECT_GE(platform::psnr(fresh.last_image(), moved), 60.0);
  // Warmer again: nil hands the node back to the scene, and the lamp is where it was.
  EXPECT_GT(lamp_px(draw(210, 6400, 3))[1], 150);
}

INSTANTIATE_TEST_SUITE_P(Backends, ScriptRender, ::testing::Values(platform::BackendKind::Egl, platform::BackendKind::OSMesa),
                         [](const auto& info) { return std::string(platform::to_string(info.param)); });
