// Render tests: the dial test scene in named states on BOTH backends, compared with committed
// goldens (golden/*.png). Set METER_UPDATE_GOLDEN=1 to rewrite them after an intended change.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/convert/converter.hpp"
#include "meter/config/scene_config_parser.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/image.hpp"
#include "meter/platform/program_cache.hpp"
#include "test_scenes.hpp"

using namespace meter;
using namespace meter::engine;
using namespace meter::convert;
namespace fs = std::filesystem;

namespace {

// Tolerance: both backends are llvmpipe but EGL runs GLES 3.2 and OSMesa desktop 4.5, so
// rasterisation of MSAA edges and FreeType-quad blending may differ by a level or two on edge
// pixels. 40 dB PSNR allows an RMS error of ~2.6 levels: far below a needle moved by one degree
// (that drops PSNR under 30 dB at this size), far above edge noise.
constexpr double kGoldenPsnrDb = 40.0;

const Scene& dial() {
  static Scene s = [] {
    auto dir = test::scratch_dir("render");
    return convert_gltf(test::write_dial_scene(dir), meter::config::parse_scene_config(test::dial_config_json()), ConvertOptions{true}).scene;
  }();
  return s;
}

struct State {
  protocol::SignalTable values;
  bool link_up = true;
};

class RenderTest : public ::testing::TestWithParam<platform::BackendKind> {
 protected:
  void SetUp() override {
    backend_ = platform::create_backend(GetParam());
    RendererOptions o;
    o.msaa = 4;
    renderer_ = std::make_unique<Renderer>(*backend_, dial(), o);
    evaluator_ = std::make_unique<BindingEvaluator>(dial());
  }
  const platform::Image& render(const State& st) {
    evaluator_->update(st.values, st.link_up, -1.0);
    renderer_->apply(evaluator_->outputs());
    renderer_->render(false, true);
    return renderer_->last_image();
  }
  void compare_golden(const platform::Image& img, const std::string& name) {
    const fs::path golden = fs::path(METER_SOURCE_DIR) / "view/engine/tests/golden" / (name + ".png");
    const fs::path actual = fs::path(test::scratch_dir("render_out_" + name + "_" + std::string(platform::to_string(GetParam())))) / "actual.png";
    platform::write_png(img, actual);
    if (std::getenv("METER_UPDATE_GOLDEN") && GetParam() == platform::BackendKind::Egl) platform::write_png(img, golden);
    ASSERT_TRUE(fs::exists(golden)) << golden << " missing (run with METER_UPDATE_GOLDEN=1)";
    const double p = platform::psnr(platform::read_png(golden), img);
    EXPECT_GE(p, kGoldenPsnrDb) << name << " on " << platform::to_string(GetParam()) << ": PSNR " << p << " dB; actual in " << actual;
  }
  std::unique_ptr<platform::GpuBackend> backend_;
  std::unique_ptr<Renderer> renderer_;
  std::unique_ptr<BindingEvaluator> evaluator_;
};

bool reddish(const platform::Image& img, int x, int y) {
  const auto* p = img.pixel(x, y);
  return p[0] > 150 && p[1] < 90 && p[2] < 90;
}

State valid(std::initializer_list<std::pair<protocol::SignalId, double>> kv) {
  State s;
  for (auto [id, v] : kv) s.values.set(id, {v, protocol::SignalStatus::Valid, ""});
  return s;
}

}  // namespace

TEST_P(RenderTest, Speed130PointsStraightUpAndMatchesGolden) {
  const auto& img = render(valid({{1, 130.0}, {27, 1.0}, {3, 50.0}}));
  ASSERT_EQ(img.width, 320);
  ASSERT_EQ(img.height, 160);
  EXPECT_TRUE(reddish(img, 160, 45));   // needle tip region, straight above the hub
  EXPECT_FALSE(reddish(img, 120, 45));  // not tilted left
  compare_golden(img, "dial_speed130");
}

TEST_P(RenderTest, Speed0RestsLeftAndMatchesGolden) {
  const auto& img = render(valid({{1, 0.0}, {27, 0.0}, {3, 0.0}}));
  EXPECT_FALSE(reddish(img, 160, 45));
  compare_golden(img, "dial_speed0");
}

// The texts drawn from the font in the package (its FONT chunk, read by FreeType from memory) are
// today's pixels bit for bit: golden/dial_text_*_exact.png were written by meter-view before the
// font travelled with the scene, when it read DejaVuSans.ttf from its file (the dial converted by
// that meter-convert; `meter-view --set Vehicle.Speed=130 --set Cluster.Telltale.ABS=1 --set
// Vehicle.Powertrain.FuelSystem.RelativeLevel=50` and `--link-lost`; EGL and OSMesa wrote the same).
namespace {
// Each the first frame of its renderer, as meter-view's one offline frame is.
void expect_equal_to_golden(const platform::Image& img, const std::string& name) {
  const fs::path golden = fs::path(METER_SOURCE_DIR) / "view/engine/tests/golden" / (name + ".png");
  EXPECT_TRUE(std::isinf(platform::psnr(platform::read_png(golden), img))) << name << ": not the image drawn from the font file";
}
}  // namespace

TEST_P(RenderTest, ASpeedTextFromThePackageFontEqualsTheImageDrawnFromTheFontFile) {
  ASSERT_FALSE(dial().font.data.empty());
  expect_equal_to_golden(render(valid({{1, 130.0}, {27, 1.0}, {3, 50.0}})), "dial_text_speed130_exact");  // "130"
}

TEST_P(RenderTest, TheLinkLossTextsFromThePackageFontEqualTheImageDrawnFromTheFontFile) {
  State lost = valid({{1, 200.0}});
  lost.link_up = false;
  expect_equal_to_golden(render(lost), "dial_text_link_lost_exact");  // "---" and "NO SIGNAL"
}

TEST_P(RenderTest, LinkLossShowsFailsafeLook) {
  State s = valid({{1, 200.0}});
  s.link_up = false;
  const auto& img = render(s);
  compare_golden(img, "dial_link_lost");
  // Same pixels as speed 0 around the needle (failsafe value 0), different where NO SIGNAL is drawn.
  const platform::Image lost = img;
  const auto& normal = render(valid({{1, 0.0}, {27, 1.0}}));
  EXPECT_LT(platform::psnr(lost, normal), 60.0);
}

TEST_P(RenderTest, UnchangedInputsSkipTheFrame) {
  render(valid({{1, 42.0}}));
  const auto drawn = renderer_->stats().drawn;
  render(valid({{1, 42.0}}));
  EXPECT_EQ(renderer_->stats().drawn, drawn);
  EXPECT_EQ(renderer_->stats().skipped, 1u);
  render(valid({{1, 43.0}}));
  EXPECT_EQ(renderer_->stats().drawn, drawn + 1);
}

// A renderer made again on the same context with a program cache (meter-preview's reload) links no
// program the first one linked, and draws the same pixels as a renderer that linked its own.
TEST_P(RenderTest, ARendererMadeAgainTakesItsProgramsFromTheCache) {
  const State st = valid({{1, 130.0}, {27, 1.0}});
  const platform::Image own = render(st);
  platform::ProgramCache cache(backend_->gl());
  RendererOptions o;
  o.msaa = 4;
  o.programs = &cache;
  auto draw = [&] {
    Renderer renderer(*backend_, dial(), o);
    BindingEvaluator evaluator(dial());
    evaluator.update(st.values, st.link_up, -1.0);
    renderer.apply(evaluator.outputs());
    renderer.render(false, true);
    return renderer.last_image();
  };
  const platform::Image first = draw();
  const std::size_t linked = cache.compiles();
  EXPECT_GT(linked, 1u);  // the scene's programs and the resolve's
  EXPECT_EQ(cache.trim(), linked);  // the renderer gave every program back
  EXPECT_EQ(cache.size(), 0u);
  const platform::Image trimmed = draw();
  EXPECT_EQ(cache.compiles(), 2 * linked);  // linked anew after the trim
  const platform::Image again = draw();  // after the last renderer, before any trim
  EXPECT_EQ(cache.compiles(), 2 * linked);
  EXPECT_TRUE(std::isinf(platform::psnr(first, own)));  // equal bit for bit
  EXPECT_TRUE(std::isinf(platform::psnr(trimmed, own)));  // equal bit for bit
  EXPECT_TRUE(std::isinf(platform::psnr(again, own)));  // equal bit for bit
}

// A sub-pixel offset (a film's jittered pass) moves the whole drawn scene by that many pixels. A
// whole-pixel offset samples the scene at the same points as before, so the image is the
// unshifted one moved: (3, 2) px right and up. Rows 5..74 hold the needle's tip and the dial's top
// edge, away from the speed text, which is placed at whole pixels and does not move.
TEST_P(RenderTest, ASubpixelOffsetMovesTheDrawnScene) {
  RendererOptions o;
  o.msaa = 1;  // each pixel one sample at its centre: a whole-pixel move is exact
  Renderer renderer(*backend_, dial(), o);
  BindingEvaluator evaluator(dial());
  evaluator.update(valid({{1, 130.0}, {27, 1.0}}).values, true, -1.0);
  renderer.apply(evaluator.outputs());
  renderer.render(true, true);
  const platform::Image still = renderer.last_image();
  EXPECT_THROW(renderer.set_subpixel_offset({std::nanf(""), 0.0f}), std::invalid_argument);
  renderer.set_subpixel_offset({3.0f, 2.0f});
  const auto t = renderer.render(false, true);  // a changed offset alone redraws
  EXPECT_TRUE(t.drawn);
  const platform::Image& moved = renderer.last_image();
  // Share of the band's pixels whose moved copy matches within 2 levels, for a shift (dx, dy) in
  // top-down image rows.
  auto matching = [&](int dx, int dy) {
    int same = 0, n = 0;
    for (int y = 5; y < 75; ++y)
      for (int x = 5; x < still.width - 5; ++x, ++n) {
        const auto* a = still.pixel(x, y);
        const auto* b = moved.pixel(x + dx, y + dy);
        bool close = true;
        for (int c = 0; c < 3; ++c) close = close && std::abs(int(a[c]) - int(b[c])) <= 2;
        same += close;
      }
    return double(same) / n;
  };
  EXPECT_GE(matching(3, -2), 0.999);  // up 2 px is 2 rows nearer the top
  EXPECT_LT(matching(0, 0), 0.98);    // it did move: the needle and the dial's rim differ in place
  renderer.set_subpixel_offset({0.0f, 0.0f});
  renderer.render(false, true);
  EXPECT_TRUE(std::isinf(platform::psnr(renderer.last_image(), still)));  // back where it was, bit for bit
}

INSTANTIATE_TEST_SUITE_P(Backends, RenderTest, ::testing::Values(platform::BackendKind::Egl, platform::BackendKind::OSMesa),
                         [](const auto& info) { return std::string(platform::to_string(info.param)); });
