// Shadow maps on both backends, on the shadow feature scene (a teapot on a floor under a sun and a
// spot that both cast): each light's map is drawn once while nothing moves, shadows only take
// light away (never add any), they darken a large part of the floor, and a scene whose lights cast
// nothing has no map and no pass. (How close the shadows come to Blender's: tests/fidelity.)
#include <gtest/gtest.h>

#include <filesystem>

#include "meter/config/scene_config_parser.hpp"
#include "meter/convert/converter.hpp"
#include "meter/convert/quality_ladder.hpp"
#include "meter/engine/renderer.hpp"
#include "test_scenes.hpp"

using namespace meter;
using namespace meter::engine;
namespace fs = std::filesystem;

namespace {

Scene shadow_scene(const std::string& quality) {
  const fs::path dir = fs::path(METER_SOURCE_DIR) / "scenes/features/shadow";
  Scene s = convert::convert_gltf((dir / "shadow.glb").string(), meter::config::load_scene_config((dir / "scene.json").string()),
                                  convert::ConvertOptions{}).scene;
  convert::apply_quality(s, convert::parse_quality(quality));
  return s;
}

class ShadowRender : public ::testing::TestWithParam<platform::BackendKind> {
 protected:
  void SetUp() override { backend_ = platform::create_backend(GetParam()); }
  std::unique_ptr<platform::GpuBackend> backend_;
};

}  // namespace

TEST_P(ShadowRender, MapsAreDrawnOnceAndOnlyTakeLightAway) {
  const Scene shadowed = shadow_scene("default"), unshadowed = shadow_scene("shadows=off");
  RendererOptions o;
  o.msaa = 4;
  Renderer with(*backend_, shadowed, o);
  with.render(true, true);
  EXPECT_EQ(with.stats().shadow_map_draws, 2u);  // the sun's and the spot's
  with.render(true, true);                        // nothing moved: the maps stand
  EXPECT_EQ(with.stats().shadow_map_draws, 2u);
  const platform::Image a = with.last_image();
  Renderer without(*backend_, unshadowed, o);
  without.render(true, true);
  EXPECT_EQ(without.stats().shadow_map_draws, 0u);
  const platform::Image& b = without.last_image();
  ASSERT_EQ(a.width, b.width);
  ASSERT_EQ(a.height, b.height);
  int brighter = 0;
  long darker = 0;
  for (int y = 0; y < a.height; ++y)
    for (int x = 0; x < a.width; ++x)
      for (int c = 0; c < 3; ++c) {
        const int d = int(a.pixel(x, y)[c]) - int(b.pixel(x, y)[c]);
        // One level: sRGB rounding of the same light through a different program.
        brighter += d > 1;
        if (c == 1 && d < -20) ++darker;
      }
  EXPECT_EQ(brighter, 0);
  // The two floor shadows and the self-shadow: measured 10.7 % of the frame; 5 % would already
  // mean a map that misses most of its casters.
  EXPECT_GT(double(darker) / (double(a.width) * a.height), 0.05);
}

TEST_P(ShadowRender, SceneWithoutCastingLightsHasNoShadowPass) {
  const auto dir = test::scratch_dir("shadow_render_dial");
  const Scene dial = convert::convert_gltf(test::write_dial_scene(dir), meter::config::parse_scene_config(test::dial_config_json()),
                                           convert::ConvertOptions{}).scene;
  for (const auto& p : dial.programs)
    for (const auto& s : p.program.samplers) EXPECT_NE(s.slot, bridge::TextureSlot::ShadowMap);
  RendererOptions o;
  o.msaa = 4;
  Renderer r(*backend_, dial, o);
  r.render(true, true);
  EXPECT_EQ(r.stats().shadow_map_draws, 0u);
}

INSTANTIATE_TEST_SUITE_P(Backends, ShadowRender, ::testing::Values(platform::BackendKind::Egl, platform::BackendKind::OSMesa),
                         [](const auto& info) { return std::string(platform::to_string(info.param)); });
