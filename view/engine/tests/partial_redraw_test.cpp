// Partial redraw (RendererOptions::partial_redraw, with and without the static layer): a renderer
// that redraws only the damaged regions of each frame must produce exactly the image of a renderer
// that redraws everything,
// through a drive sequence with needles moving, telltales switching, texts changing and the link
// dropping and coming back, on both backends.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <map>

#include "meter/engine/evaluation/bindings.hpp"
#include "meter/convert/converter.hpp"
#include "meter/config/scene_config_parser.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/image.hpp"
#include "meter/protocol/catalog.hpp"
#include "test_scenes.hpp"

using namespace meter;
using namespace meter::engine;
using namespace meter::convert;
namespace fs = std::filesystem;

namespace {

// Tolerance: none. The scissor test is a per-fragment operation (GL ES 3.2 §13.8.2): it discards
// fragments outside the box but changes neither which fragments inside are produced nor their
// values, and the cleared region is redrawn by the same draws in the same order. With the static
// layer, the region starts as a bit copy of what clear + the static draws wrote (every sample's
// colour and depth), then the remaining draws follow in that same order. So any differing pixel
// means a damaged region was missed (a stale needle ghost, a half-old text) or the layer is stale.
constexpr int kMaxLevelDifference = 0;

const Scene& cluster() { return test::cluster_scene(); }

const Scene& dial() {
  static Scene s = [] {
    const std::string dir = test::scratch_dir("partial_dial");
    return convert_gltf(test::write_dial_scene(dir), meter::config::parse_scene_config(test::dial_config_json()), ConvertOptions{}).scene;
  }();
  return s;
}

struct Step {
  std::string name;
  std::map<std::string, double> values;  // catalog name -> value (Valid)
  bool link_up = true;
};

// A drive in small steps, as the view sees it at 30-60 fps, plus the events that change texts
// and telltales.
std::vector<Step> drive() {
  std::vector<Step> steps;
  std::map<std::string, double> v = {{"Vehicle.Speed", 0}, {"Vehicle.Powertrain.CombustionEngine.Speed", 800},
                                     {"Vehicle.Powertrain.FuelSystem.RelativeLevel", 70},
                                     {"Vehicle.Powertrain.CombustionEngine.ECT", 40}};
  steps.push_back({"idle", v});
  for (int k = 1; k <= 6; ++k) {
    v["Vehicle.Speed"] = 4.0 * k;
    v["Vehicle.Powertrain.CombustionEngine.Speed"] = 800 + 350.0 * k;
    steps.push_back({"accelerate_" + std::to_string(k), v});
  }
  v["Cluster.Telltale.TurnLeft"] = 1;
  steps.push_back({"indicator_on", v});
  v["Vehicle.Speed"] = 25.4;  // needle and readout (24 -> 25) both change
  steps.push_back({"indicator_speed", v});
  v["Cluster.Telltale.TurnLeft"] = 0;
  v["Vehicle.Powertrain.CombustionEngine.ECT"] = 41;
  steps.push_back({"indicator_off_coolant", v});
  v["Cluster.Telltale.ABS"] = 1;
  v["Vehicle.Powertrain.FuelSystem.RelativeLevel"] = 69;
  steps.push_back({"abs_fuel", v});
  steps.push_back({"link_lost", v, false});
  steps.push_back({"link_back", v, true});
  v["Vehicle.Speed"] = 250;
  v["Vehicle.Powertrain.CombustionEngine.Speed"] = 7900;
  steps.push_back({"jump_to_redline", v});
  v["Vehicle.Speed"] = 251;
  steps.push_back({"creep", v});
  return steps;
}

class PartialRedraw : public ::testing::TestWithParam<platform::BackendKind> {
 protected:
  void SetUp() override { backend_ = platform::create_backend(GetParam()); }

  // Runs the drive through a partial and a full renderer; returns the partial renderer's stats.
  // `layer`: the partial renderer keeps its static layer (RendererOptions::static_layer).
  RendererStats run(const Scene& scene, int width, int height, int msaa, bool layer = true) {
    RendererOptions partial, full;
    partial.width = full.width = width, partial.height = full.height = height;
    partial.msaa = full.msaa = msaa;
    partial.static_layer = layer;
    full.partial_redraw = false;
    Renderer a(*backend_, scene, partial), b(*backend_, scene, full);
    BindingEvaluator ev(scene);
    for (const Step& st : drive()) {
      protocol::SignalTable values;
      for (const auto& [name, x] : st.values) {
        const auto* info = protocol::find_signal(name);
        EXPECT_NE(info, nullptr) << name;
        if (info) values.set(info->id, {x, protocol::SignalStatus::Valid, ""});
      }
      ev.update(values, st.link_up, -1.0);
      a.apply(ev.outputs());
      b.apply(ev.outputs());
      // Not forced: the partial renderer decides what to redraw, as in the live loop.
      a.render(false, true);
      b.render(false, true);
      const auto& ia = a.last_image();
      const auto& ib = b.last_image();
      EXPECT_EQ(ia.rgba.size(), ib.rgba.size());
      if (ia.rgba.size() != ib.rgba.size()) break;
      std::size_t differing = 0;
      int max_level = 0;
      for (std::size_t p = 0; p < ia.rgba.size(); p += 4) {
        int m = 0;
        for (std::size_t c = 0; c < 4; ++c) m = std::max(m, std::abs(int(ia.rgba[p + c]) - int(ib.rgba[p + c])));
        if (m) ++differing, max_level = std::max(max_level, m);
      }
      if (max_level > kMaxLevelDifference) {
        const std::string out = test::scratch_dir("partial_" + st.name + "_" + std::string(platform::to_string(GetParam())));
        platform::write_png(ia, fs::path(out) / "partial.png");
        platform::write_png(ib, fs::path(out) / "full.png");
      }
      EXPECT_LE(max_level, kMaxLevelDifference) << st.name << ": " << differing << " pixels differ (images in the build tree)";
    }
    return a.stats();
  }

  std::unique_ptr<platform::GpuBackend> backend_;
};

}  // namespace

TEST_P(PartialRedraw, ClusterMsaa4EqualsFullRedraw) {
  const RendererStats s = run(cluster(), 640, 240, 4);
  // The equivalence above would hold trivially if every frame were full: most steps of this drive
  // move a needle or change one text, so they must be partial and small.
  std::printf("[ partial  ] cluster %s: %llu of %llu drawn frames partial, mean redrawn %.1f %%\n",
              std::string(platform::to_string(GetParam())).c_str(), static_cast<unsigned long long>(s.partial_frames),
              static_cast<unsigned long long>(s.drawn), 100.0 * s.redrawn_fraction_sum / double(std::max<std::uint64_t>(1, s.drawn)));
  EXPECT_GE(s.partial_frames, 8u);
  EXPECT_LT(s.redrawn_fraction_sum / double(s.drawn), 0.5);
  // The static layer is drawn once: the camera and lights stay put and everything the drive
  // changes (needles, telltales, the failsafe look) is classified as changeable. A draw baked into
  // the layer by mistake would still give the right image (the layer is checked every frame) but
  // would rebuild it, so this count is what proves the classification.
  EXPECT_EQ(s.layer_builds, 1u);
}

TEST_P(PartialRedraw, ClusterWithoutStaticLayerEqualsFullRedraw) {
  // Scissored passes that redraw everything in their region (GLES < 3.2 without copy_image).
  const RendererStats s = run(cluster(), 640, 240, 4, false);
  EXPECT_GE(s.partial_frames, 8u);
  EXPECT_EQ(s.layer_builds, 0u);
}

TEST_P(PartialRedraw, ClusterWithoutMsaaEqualsFullRedraw) {
  const RendererStats s = run(cluster(), 640, 240, 1);
  EXPECT_GE(s.partial_frames, 8u);
  EXPECT_EQ(s.layer_builds, 1u);
}

TEST_P(PartialRedraw, ClusterWithTheFilmFilterResolveEqualsFullRedraw) {
  // The film filter resolve reads the samples of each pixel's neighbourhood: a change drawn in a
  // region changes resolved pixels outside it, which the resolve of that region must cover
  // (RenderTarget::resolve grows it by resolve_margin_px()). At the default 1.5 px the reach (1 px)
  // stays inside the damage boxes' own 1 px pad; the widest filter (3 px, reach 3 px) does not.
  Scene film = cluster();
  film.config.resolve.filter = ResolveConfig::Filter::BlackmanHarris;
  film.config.resolve.width_px = 3.0;
  const RendererStats s = run(film, 640, 240, 4);
  EXPECT_GE(s.partial_frames, 8u);
}

TEST_P(PartialRedraw, WrittenBoxesGrowByTheResolveFiltersReach) {
  // The integrity monitor re-reads a safety region when a written box meets it: under the film
  // filter a box's change reaches resolve_margin_px() beyond it, so the boxes say so.
  Scene boxed = cluster(), film = cluster();
  boxed.config.resolve.filter = ResolveConfig::Filter::Box;  // no reach: the plan's own boxes
  film.config.resolve.filter = ResolveConfig::Filter::BlackmanHarris;
  film.config.resolve.width_px = 3.0;  // reach 3 px
  RendererOptions o;
  o.width = 640, o.height = 240;
  Renderer box(*backend_, boxed, o), wide(*backend_, film, o);
  BindingEvaluator ev(cluster());
  int partial_boxes = 0;
  for (const Step& st : drive()) {
    protocol::SignalTable values;
    for (const auto& [name, x] : st.values)
      if (const auto* info = protocol::find_signal(name)) values.set(info->id, {x, protocol::SignalStatus::Valid, ""});
    ev.update(values, st.link_up, -1.0);
    box.apply(ev.outputs()), wide.apply(ev.outputs());
    box.render(false, false), wide.render(false, false);
    const auto a = box.take_written(), b = wide.take_written();
    ASSERT_EQ(a.size(), b.size()) << st.name << ": the plan does not depend on the resolve";
    for (std::size_t i = 0; i < a.size(); ++i) {
      const platform::PixelRegion grown =
          platform::clip({a[i].x - 3, a[i].y - 3, a[i].width + 6, a[i].height + 6}, 640, 240);
      EXPECT_EQ(b[i], grown) << st.name << " box " << i;
      partial_boxes += a[i].width < 640;
    }
  }
  EXPECT_GT(partial_boxes, 4);
  // No display took its list: none was kept for it, and its first take is the whole target.
  EXPECT_EQ(box.take_written(Renderer::WrittenReader::Display),
            (std::vector<platform::PixelRegion>{platform::PixelRegion{0, 0, 640, 240}}));
}

TEST_P(PartialRedraw, MorphingSceneEqualsFullRedraw) {
  // The dial's fuel bar morphs: its bounds are not the primitive's, so such frames are full.
  run(dial(), 320, 160, 4);
}

INSTANTIATE_TEST_SUITE_P(Backends, PartialRedraw,
                         ::testing::Values(platform::BackendKind::Egl, platform::BackendKind::OSMesa),
                         [](const auto& info) { return std::string(platform::to_string(info.param)); });
