// Each committed scene (cluster, minimal-gauge, the twelve feature scenes) converted with
// --optimize=on and --optimize=off through the converter's API (what meter-convert does), rendered in one
// non-trivial state on EGL and on OSMesa, and compared:
//   on vs off (EGL), on vs off (OSMesa), on EGL vs on OSMesa, and on OSMesa: ES 3.00 text vs the
//   same optimized programs as desktop GLSL 330 (shadergen::to_desktop_glsl).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/config/scene_config_parser.hpp"
#include "meter/convert/converter.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/backend.hpp"
#include "meter/platform/image.hpp"
#include "meter/protocol/catalog.hpp"
#include "meter/shadergen/shadergen.hpp"
#include "bound_signals.hpp"

namespace {

using namespace meter;
namespace fs = std::filesystem;

// Tolerance. The optimizer changes arithmetic, not the formula: constants are folded by glslang and
// spirv-opt (in 32-bit float, the same precision llvmpipe uses), expressions are re-associated,
// `pow`/`normalize` sequences are rewritten. That moves a result by ulps, which changes an 8-bit
// sRGB level only where a value sits on a rounding boundary: isolated +-1 levels, plus MSAA edge
// pixels where a vertex position moved by an ulp. 45 dB = RMS error 1.4 levels over the image.
// Any real mistake (a folded value wrong, a light dropped, a texture lost, a morph weight frozen)
// changes whole surfaces by many levels; the sensitivity check below shows a moved state falls
// far below it.
constexpr double kSameImagePsnrDb = 45.0;
// Across backends (EGL GLES 3.2 vs OSMesa desktop 4.5, both llvmpipe) rasterisation of MSAA edges
// and text quads can differ by a level or two on edge pixels: the 40 dB the engine goldens use.
constexpr double kCrossBackendPsnrDb = 40.0;

struct SceneFiles {
  std::string name, glb, config;
};
void PrintTo(const SceneFiles& s, std::ostream* os) { *os << s.name; }

// Each scene as it ships, concatenation groups included: merged draws get their own program
// variants (vertex alpha), and those must survive the optimizer like every other.
engine::SceneConfig load_config(const std::string& path) { return meter::config::load_scene_config(path); }

std::vector<SceneFiles> all_scenes() {
  const fs::path root = fs::path(METER_SOURCE_DIR) / "scenes";
  std::vector<SceneFiles> s = {
      {"cluster", (root / "cluster/cluster.glb").string(), (root / "cluster/cluster.scene.json").string()},
      {"minimal_gauge", (root / "minimal-gauge/minimal-gauge.glb").string(),
       (root / "minimal-gauge/minimal-gauge.scene.json").string()}};
  for (const char* f : {"ambient", "diffuse", "specular", "shininess", "emission", "bump", "reflection",
                        "envmap2d", "skinning", "morphing", "spot", "omni", "shadow"})
    s.push_back({f, (root / "features" / f / (std::string(f) + ".glb")).string(),
                 (root / "features" / f / "scene.json").string()});
  return s;
}

platform::Image render(platform::GpuBackend& backend, const engine::Scene& scene,
                       const protocol::SignalTable& values) {
  backend.make_current();
  engine::RendererOptions o;
  o.msaa = 4;
  engine::Renderer r(backend, scene, o);
  engine::BindingEvaluator ev(scene);
  ev.update(values, true, -1.0);
  r.apply(ev.outputs());
  r.render(true, true);
  return r.last_image();
}

// Fraction of pixels that differ from the top-left pixel (the background) by more than 8 levels:
// proves the comparison is between images with content, not two empty clears.
double content_fraction(const platform::Image& img) {
  const auto* bg = img.pixel(0, 0);
  std::size_t n = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x) {
      const auto* p = img.pixel(x, y);
      for (int c = 0; c < 3; ++c)
        if (std::abs(int(p[c]) - int(bg[c])) > 8) {
          ++n;
          break;
        }
    }
  return double(n) / (double(img.width) * img.height);
}

// One backend alive at a time: with an EGL and an OSMesa context both alive in one process, the
// first EGL frame came out without its sRGB encode (19 dB off the same frame rendered alone, found by
// this test); the two Mesa front ends share libglapi's current-context state.
std::unique_ptr<platform::GpuBackend> backend(platform::BackendKind kind) {
  return platform::create_backend(kind);
}

class ShaderOptimizer : public ::testing::TestWithParam<SceneFiles> {
 protected:
  void save(const platform::Image& img, const std::string& what) {
    const fs::path dir = fs::path(METER_BINARY_DIR) / "tests/shader-optimizer/out";
    fs::create_directories(dir);
    platform::write_png(img, dir / (GetParam().name + "." + what + ".png"));
  }
};

TEST_P(ShaderOptimizer, OptimizedAndGeneratedProgramsRenderTheSame) {
  const SceneFiles& s = GetParam();
  const engine::SceneConfig config = load_config(s.config);
  const engine::Scene on = convert::convert_gltf(s.glb, config, convert::ConvertOptions{true}).scene;
  const engine::Scene off = convert::convert_gltf(s.glb, config, convert::ConvertOptions{false}).scene;

  // The scene really went through the optimizer, and it paid off.
  // (Folding makes programs material-specific, so `on` usually holds more programs than `off`.)
  ASSERT_FALSE(on.programs.empty());
  ASSERT_FALSE(off.programs.empty());
  std::size_t before = 0, after = 0;
  for (const auto& p : on.programs) {
    EXPECT_TRUE(p.program.optimized);
    before += p.optimize_report.spirv_instructions_before;
    after += p.optimize_report.spirv_instructions_after;
  }
  for (const auto& p : off.programs) EXPECT_FALSE(p.program.optimized);
  EXPECT_LT(after, before) << s.name;

  // The same optimized programs in the desktop dialect, run on OSMesa's core context.
  engine::Scene desktop = on;
  for (auto& p : desktop.programs) p.program = shadergen::to_desktop_glsl(p.program, 330);

  const auto values = meter::testing::bound_signals_at(config, 0.6);
  platform::Image egl_on, egl_off, os_on, os_off, os_desktop;
  {
    auto egl = backend(platform::BackendKind::Egl);
    egl_on = render(*egl, on, values);
    egl_off = render(*egl, off, values);
  }
  {
    auto osmesa = backend(platform::BackendKind::OSMesa);
    os_on = render(*osmesa, on, values);
    os_off = render(*osmesa, off, values);
    os_desktop = render(*osmesa, desktop, values);
  }
  save(egl_on, "egl.on");
  save(egl_off, "egl.off");
  save(os_on, "osmesa.on");
  save(os_off, "osmesa.off");
  save(os_desktop, "osmesa.desktop330");

  EXPECT_GT(content_fraction(egl_off), 0.01) << s.name << ": the reference frame is empty";
  const double egl = platform::psnr(egl_on, egl_off);
  const double osm = platform::psnr(os_on, os_off);
  const double cross = platform::psnr(egl_on, os_on);
  const double dialect = platform::psnr(os_on, os_desktop);
  std::printf("%-14s PSNR on/off EGL %6.1f dB, on/off OSMesa %6.1f dB, EGL/OSMesa %6.1f dB, "
              "ES300/GLSL330 %6.1f dB\n", s.name.c_str(), egl, osm, cross, dialect);
  EXPECT_GE(egl, kSameImagePsnrDb) << s.name << " on EGL (images in " << METER_BINARY_DIR
                                   << "/tests/shader-optimizer/out)";
  EXPECT_GE(osm, kSameImagePsnrDb) << s.name << " on OSMesa";
  EXPECT_GE(dialect, kSameImagePsnrDb) << s.name << ": desktop GLSL 330 vs ES 3.00 on OSMesa";
  EXPECT_GE(cross, kCrossBackendPsnrDb) << s.name << ": optimized, EGL vs OSMesa";
}

// The tolerance can fail: on scenes whose bound values move the picture, the same optimized package
// in another state falls well under it.
TEST_F(ShaderOptimizer, ToleranceDetectsAChangedState) {
  const SceneFiles s = all_scenes()[0];  // cluster: needles move with the values
  const engine::SceneConfig config = load_config(s.config);
  const engine::Scene on = convert::convert_gltf(s.glb, config, convert::ConvertOptions{true}).scene;
  auto egl = backend(platform::BackendKind::Egl);
  const platform::Image a = render(*egl, on, meter::testing::bound_signals_at(config, 0.6));
  const platform::Image b = render(*egl, on, meter::testing::bound_signals_at(config, 0.62));
  EXPECT_LT(platform::psnr(a, b), kSameImagePsnrDb);
}

INSTANTIATE_TEST_SUITE_P(Scenes, ShaderOptimizer, ::testing::ValuesIn(all_scenes()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
