// Quality levels drawn (Renderer::set_quality, a choice between plan() and draw(), the global rungs) on the cluster
// converted with its levels, on both backends: every changed level draws a different image, a
// level change redrawn partially gives the image a full redraw at that level gives, and back at
// level 0 the frame is bit for bit the one a renderer that never changed level draws.
#include <gtest/gtest.h>

#include <glm/gtc/quaternion.hpp>

#include <array>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>

#include "meter/convert/flat_geometry.hpp"
#include "meter/convert/levels.hpp"
#include "meter/engine/evaluation/bindings.hpp"
#include "meter/engine/frame_plan/draw_units.hpp"
#include "meter/engine/renderer.hpp"
#include "meter/platform/image.hpp"
#include "meter/protocol/catalog.hpp"
#include "meter/shadergen/shadergen.hpp"
#include "test_scenes.hpp"

using namespace meter;
using namespace meter::engine;
namespace fs = std::filesystem;

namespace {

constexpr int kWidth = 640, kHeight = 240;

const Scene& cluster() {
  static const Scene s = [] {
    Scene c = test::cluster_scene();
    convert::make_levels(c);
    return c;
  }();
  return s;
}

// A moment of a drive: needles off their rest, a telltale lit.
BindingOutputs driving(const Scene& scene, double speed = 87) {
  BindingEvaluator ev(scene);
  protocol::SignalTable values;
  const std::map<std::string, double> v = {{"Vehicle.Speed", speed}, {"Vehicle.Powertrain.CombustionEngine.Speed", 3100},
                                           {"Vehicle.Powertrain.FuelSystem.RelativeLevel", 55},
                                           {"Cluster.Telltale.TurnLeft", 1}};
  for (const auto& [name, x] : v)
    if (const auto* info = protocol::find_signal(name)) values.set(info->id, {x, protocol::SignalStatus::Valid, ""});
  ev.update(values, true, -1.0);
  return ev.outputs();
}

std::size_t differing_pixels(const platform::Image& a, const platform::Image& b) {
  if (a.rgba.size() != b.rgba.size()) return std::max(a.rgba.size(), b.rgba.size()) / 4;
  std::size_t n = 0;
  for (std::size_t p = 0; p < a.rgba.size(); p += 4)
    if (std::memcmp(&a.rgba[p], &b.rgba[p], 4) != 0) ++n;
  return n;
}

// Every movable unit at `pick(ladder)` (a shading or LOD index), the rest at 0.
template <typename Pick>
governor::QualityChoice every_unit(std::span<const governor::UnitLadder> units, Pick pick) {
  governor::QualityChoice c;
  for (const auto& l : units) c.units.push_back(l.safety ? governor::UnitLevel{} : pick(l));
  return c;
}

class LevelsRender : public ::testing::TestWithParam<platform::BackendKind> {
 protected:
  void SetUp() override { backend_ = platform::create_backend(GetParam()); }

  RendererOptions options(bool partial = true) const {
    RendererOptions o;
    o.width = kWidth, o.height = kHeight, o.msaa = 4, o.partial_redraw = partial;
    return o;
  }
  void save(const platform::Image& img, const std::string& name) const {
    const std::string dir = test::scratch_dir("levels_" + std::string(platform::to_string(GetParam())));
    platform::write_png(img, fs::path(dir) / (name + ".png"));
  }

  std::unique_ptr<platform::GpuBackend> backend_;
};

}  // namespace

TEST_P(LevelsRender, EveryLevelDiffersAndLevelZeroIsBitIdentical) {
  const Scene& scene = cluster();
  const BindingOutputs outputs = driving(scene);
  Renderer a(*backend_, scene, options()), never(*backend_, scene, options());
  const auto units = a.draw_units();
  ASSERT_FALSE(units.empty());
  std::size_t listed = 0;
  for (std::size_t u = 0; u < units.size(); ++u) listed += a.unit_draws(u).size();
  EXPECT_EQ(listed, scene.draws.size()) << "every draw belongs to exactly one unit";
  a.apply(outputs), never.apply(outputs);
  a.render(false, true), never.render(false, true);
  const platform::Image full = a.last_image();
  ASSERT_EQ(differing_pixels(full, never.last_image()), 0u);

  // The static layer's draws (classify_draws), by unit.
  const DrawClasses classes = classify_draws(scene, true, find_camera_node(scene));
  const DrawUnits du = make_draw_units(scene, classes, true);
  auto in_layer = [&](std::size_t unit) {
    const auto rep = static_cast<std::size_t>(du.members[unit].front());
    return !classes.changeable[rep] && !scene.programs[std::size_t(scene.draws[rep].program)].program.blend;
  };
  // The smallest changeable unit on screen that has a cheaper shading: its change alone is a
  // partial frame.
  std::size_t small = units.size();
  for (std::size_t i = 0; i < units.size(); ++i)
    if (!in_layer(i) && units[i].shadings.size() > 1 && a.last_load().unit_pixels[i] > 0 &&
        (small == units.size() || a.last_load().unit_pixels[i] < a.last_load().unit_pixels[small]))
      small = i;
  ASSERT_LT(small, units.size());
  governor::QualityChoice one;
  one.units.assign(units.size(), {});
  one.units[small] = {int(units[small].shadings.size()) - 1, int(units[small].lod_errors.size()) - 1};
  // The same for the smallest unit the static layer holds: the layer is rebuilt, the target only
  // redrawn in that unit's boxes.
  std::size_t still = units.size();
  for (std::size_t i = 0; i < units.size(); ++i)
    if (in_layer(i) && units[i].shadings.size() > 1 && a.last_load().unit_pixels[i] > 0 &&
        (still == units.size() || a.last_load().unit_pixels[i] < a.last_load().unit_pixels[still]))
      still = i;
  ASSERT_LT(still, units.size());
  governor::QualityChoice one_static;
  one_static.units.assign(units.size(), {});
  one_static.units[still] = {int(units[still].shadings.size()) - 1, 0};
  const std::vector<std::pair<std::string, governor::QualityChoice>> choices = {
      {"one_unit", one},
      {"one_static_unit", one_static},
      {"next_shading", every_unit(units, [](const governor::UnitLadder& l) { return governor::UnitLevel{l.shadings.size() > 1 ? 1 : 0, 0}; })},
      {"cheapest_shading", every_unit(units, [](const governor::UnitLadder& l) { return governor::UnitLevel{int(l.shadings.size()) - 1, 0}; })},
      {"coarsest_lod", every_unit(units, [](const governor::UnitLadder& l) { return governor::UnitLevel{0, int(l.lod_errors.size()) - 1}; })},
  };
  for (const auto& [name, choice] : choices) {
    a.set_quality(choice);
    const std::uint64_t builds = a.stats().layer_builds;
    const FrameTiming t = a.render(false, true);
    // The static layer is drawn again only when a draw it holds changed level.
    if (name == "one_unit") {
      EXPECT_EQ(a.stats().layer_builds, builds) << "a changeable unit's level rebuilt the static layer";
    }
    if (name == "one_static_unit") {
      EXPECT_EQ(a.stats().layer_builds, builds + 1) << "a static unit's level change did not rebuild the layer";
      EXPECT_GT(t.regions, 0) << "a small static unit's level change redrew the whole frame";
    }
    EXPECT_TRUE(t.drawn) << name;
    // Only the changed unit's boxes are damaged.
    if (name == "one_unit") {
      EXPECT_GT(t.regions, 0) << "a small unit's level change redrew the whole frame";
    }
    EXPECT_EQ(a.quality().units, choice.units) << name;
    const std::size_t changed = differing_pixels(a.last_image(), full);
    if (changed == 0) save(a.last_image(), name);
    EXPECT_GT(changed, 0u) << name << ": the level drew the full-quality image";
    std::printf("[ levels   ] %s %s: %zu pixels differ from full quality, %.1f %% redrawn\n", std::string(platform::to_string(GetParam())).c_str(),
                name.c_str(), changed, 100.0 * t.redrawn_fraction);
    // The change was drawn over the last frame (damaged boxes only): it must be the image a
    // renderer drawing that level from scratch makes.
    Renderer fresh(*backend_, scene, options(false));
    fresh.set_quality(choice);
    fresh.apply(outputs);
    fresh.render(false, true);
    const std::size_t stale = differing_pixels(a.last_image(), fresh.last_image());
    if (stale) save(a.last_image(), name + "_partial"), save(fresh.last_image(), name + "_fresh");
    EXPECT_EQ(stale, 0u) << name << ": pixels the level change did not redraw (images in the build tree)";
  }
  a.set_quality(governor::QualityChoice{});
  EXPECT_TRUE(a.render(false, true).drawn);
  const std::size_t back = differing_pixels(a.last_image(), never.last_image());
  if (back) save(a.last_image(), "back_at_0"), save(never.last_image(), "never_changed");
  EXPECT_EQ(back, 0u) << "back at level 0 the frame differs from a renderer that never changed level";
}

TEST_P(LevelsRender, GlobalRungKeepsTheOutputSize) {
  const Scene& scene = cluster();
  const BindingOutputs outputs = driving(scene);
  Renderer a(*backend_, scene, options()), never(*backend_, scene, options());
  a.apply(outputs), never.apply(outputs);
  a.render(false, true), never.render(false, true);
  governor::QualityChoice low;
  low.global = {1, 0.5f};
  a.set_quality(low);
  EXPECT_TRUE(a.render(false, true).drawn);
  EXPECT_EQ(a.last_image().width, kWidth);
  EXPECT_EQ(a.last_image().height, kHeight);
  EXPECT_EQ(a.width(), kWidth);
  EXPECT_GT(differing_pixels(a.last_image(), never.last_image()), 0u) << "half scale without MSAA drew the full image";
  const platform::Image first_low = a.last_image();
  // The integrity monitor's readback stays in output pixels.
  const platform::PixelRegion corner{kWidth - 8, kHeight - 8, 8, 8};
  const auto regions = a.read_regions(std::span<const platform::PixelRegion>(&corner, 1));
  ASSERT_EQ(regions.size(), 1u);
  EXPECT_EQ(regions[0].width, 8);
  // Back at full quality: the rung's targets were kept with the frame drawn there, which is this
  // frame (nothing changed since), so nothing is drawn and the image is that frame.
  a.set_quality(governor::QualityChoice{});
  EXPECT_FALSE(a.render(false, true).drawn) << "a rung visited again redrew a frame its targets hold";
  EXPECT_EQ(differing_pixels(a.last_image(), never.last_image()), 0u) << "back at full quality the frame differs";
  a.set_quality(low);
  EXPECT_FALSE(a.render(false, true).drawn);
  EXPECT_EQ(differing_pixels(a.last_image(), first_low), 0u) << "the rung visited again shows another frame";
  // The speed moves while at the low rung: only the damage is redrawn there, and back at full
  // quality only what differs from the frame that rung last drew; each image is a fresh
  // renderer's full frame at that rung.
  const BindingOutputs faster = driving(scene, 131);
  a.apply(faster);
  const FrameTiming low_t = a.render(false, true);
  EXPECT_TRUE(low_t.drawn);
  EXPECT_LT(low_t.redrawn_fraction, 1.0);
  Renderer fresh_low(*backend_, scene, options());
  fresh_low.set_quality(low);
  fresh_low.apply(faster);
  fresh_low.render(false, true);
  EXPECT_EQ(differing_pixels(a.last_image(), fresh_low.last_image()), 0u) << "partial redraw at a kept rung differs";
  a.set_quality(governor::QualityChoice{});
  const FrameTiming full_t = a.render(false, true);
  EXPECT_TRUE(full_t.drawn);
  EXPECT_LT(full_t.redrawn_fraction, 1.0);
  never.apply(faster);
  never.render(false, true);
  EXPECT_EQ(differing_pixels(a.last_image(), never.last_image()), 0u) << "back at full quality after a change, the frame differs";
}

// The governor's choice is a plain input between the frame's two halves: plan() gives the planned
// load, draw(choice) draws at the choice.
TEST_P(LevelsRender, ChoiceMadeOnThePlannedLoadIsDrawn) {
  const Scene& scene = cluster();
  const BindingOutputs outputs = driving(scene);
  Renderer a(*backend_, scene, options()), direct(*backend_, scene, options());
  const auto choice = every_unit(a.draw_units(), [](const governor::UnitLadder& l) {
    return governor::UnitLevel{int(l.shadings.size()) - 1, int(l.lod_errors.size()) - 1};
  });
  std::vector<governor::FrameLoad> seen;
  auto chooser = [&](const governor::FrameLoad& load) -> std::optional<governor::QualityChoice> {
    seen.push_back(load);
    return choice;
  };
  auto render_choosing = [](Renderer& r, bool read, const auto& choose) { return r.draw(choose(r.plan(false, read))); };
  a.apply(outputs);
  EXPECT_TRUE(render_choosing(a, true, chooser).drawn);
  ASSERT_EQ(seen.size(), 1u);
  const governor::FrameLoad& first = seen[0];
  EXPECT_TRUE(first.drawn);
  EXPECT_TRUE(first.full_frame);
  EXPECT_DOUBLE_EQ(first.redrawn_pixels, double(kWidth) * kHeight);
  EXPECT_TRUE(first.read_back) << "a frame rendered with read = true is a read-back frame for the governor";
  ASSERT_EQ(first.unit_pixels.size(), a.draw_units().size());
  double covered = 0;
  for (double p : first.unit_pixels) {
    EXPECT_GE(p, 0.0);
    EXPECT_LE(p, double(kWidth) * kHeight);  // a unit's box is clipped to the frame
    covered += p;
  }
  EXPECT_GT(covered, 0.0);
  EXPECT_EQ(a.quality(), choice);
  direct.set_quality(choice);
  direct.apply(outputs);
  direct.render(false, true);
  EXPECT_EQ(differing_pixels(a.last_image(), direct.last_image()), 0u) << "the chooser's choice was not what was drawn";
  // Nothing changed: the frame is skipped, the chooser still sees an empty load.
  EXPECT_FALSE(render_choosing(a, false, chooser).drawn);
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_FALSE(seen[1].drawn);
  EXPECT_FALSE(seen[1].read_back);
  // An idle frame whose chooser raises the quality draws what that changes, asking once.
  auto back_to_full = [&](const governor::FrameLoad& load) -> std::optional<governor::QualityChoice> {
    seen.push_back(load);
    return governor::QualityChoice{};
  };
  EXPECT_TRUE(render_choosing(a, true, back_to_full).drawn);
  EXPECT_EQ(seen.size(), 3u) << "the chooser was asked more than once in one frame";
  Renderer full(*backend_, scene, options());
  full.apply(outputs);
  full.render(false, true);
  EXPECT_EQ(differing_pixels(a.last_image(), full.last_image()), 0u) << "raised on an idle frame, the image is not full quality";
}

// The governor's warm-up at load: every level and rung drawn once, then nothing of it is left: the
// quality, the stats and the last image are as before, and the next frame (a full one) is bit for
// bit the frame of a renderer that never warmed up, both before the first frame and mid-drive.
TEST_P(LevelsRender, WarmUpDrawsEveryLevelAndLeavesNoTrace) {
  const Scene& scene = cluster();
  const BindingOutputs outputs = driving(scene);
  Renderer a(*backend_, scene, options()), never(*backend_, scene, options());
  std::vector<governor::QualityChoice> choices;
  for (const governor::GlobalLevel g : {governor::GlobalLevel{4, 1.0f}, governor::GlobalLevel{1, 0.5f}}) {
    for (int k = 2; k >= 0; --k) {  // as warm_up_choices: each rung ends at full quality
      auto c = every_unit(a.draw_units(), [k](const governor::UnitLadder& l) {
        return governor::UnitLevel{std::min(k, int(l.shadings.size()) - 1), std::min(k, int(l.lod_errors.size()) - 1)};
      });
      c.global = g;
      choices.push_back(c);
    }
  }
  const governor::QualityChoice initial = a.quality();
  EXPECT_EQ(a.warm_up(choices), 6);
  EXPECT_EQ(a.quality(), initial);
  EXPECT_EQ(a.stats().frames, 0u) << "the warm-up's frames were counted";
  EXPECT_TRUE(a.last_image().rgba.empty());
  a.apply(outputs), never.apply(outputs);
  EXPECT_TRUE(a.render(false, true).drawn);
  never.render(false, true);
  EXPECT_EQ(differing_pixels(a.last_image(), never.last_image()), 0u) << "warmed up before the first frame, it differs";
  // Mid-drive, with the partial-redraw and static-layer state of earlier frames.
  const governor::QualityChoice held = a.quality();
  const RendererStats before = a.stats();
  const platform::Image shown = a.last_image();
  EXPECT_EQ(a.warm_up(choices), 6);
  EXPECT_EQ(a.quality(), held);
  EXPECT_EQ(a.stats().drawn, before.drawn);
  EXPECT_EQ(differing_pixels(a.last_image(), shown), 0u) << "last_image() is a warm-up frame";
  // The held rung's target holds its last warm-up frame, full quality with these outputs: this
  // frame. Nothing needs drawing; then the drive goes on and only the damage is redrawn.
  EXPECT_FALSE(a.render(false, true).drawn) << "the frame after a warm-up redrew what its target holds";
  EXPECT_EQ(differing_pixels(a.last_image(), never.last_image()), 0u) << "warmed up mid-drive, the frame differs";
  const BindingOutputs faster = driving(scene, 131);
  a.apply(faster), never.apply(faster);
  const FrameTiming after = a.render(false, true);
  never.render(false, true);
  EXPECT_TRUE(after.drawn);
  EXPECT_LT(after.redrawn_fraction, 1.0);
  EXPECT_EQ(differing_pixels(a.last_image(), never.last_image()), 0u) << "warmed up mid-drive, the next frame differs";
  EXPECT_EQ(a.warm_up({}), 0);
}

// The governor visits many rungs (the warm-up every one); only the current rung and the one left
// last hold targets. A rung whose targets were released is drawn in full on return, the image a
// fresh renderer draws there; the held rung, drawn last by the warm-up, redraws nothing after it.
TEST_P(LevelsRender, OnlyTheCurrentAndLastRungKeepTheirTargets) {
  const Scene& scene = cluster();
  const BindingOutputs outputs = driving(scene);
  const auto at = [](const governor::GlobalLevel& g) {
    governor::QualityChoice c;
    c.global = g;
    return c;
  };
  const auto fresh_image = [&](const governor::QualityChoice& c) {
    Renderer fresh(*backend_, scene, options());
    fresh.set_quality(c);
    fresh.apply(outputs);
    fresh.render(false, true);
    return fresh.last_image();
  };
  Renderer a(*backend_, scene, options());
  a.apply(outputs);
  a.render(false, true);
  EXPECT_EQ(a.rungs_with_targets(), 1u);
  const governor::GlobalLevel full{4, 1.0f}, two{2, 1.0f}, half{1, 0.5f};
  const std::vector<governor::QualityChoice> choices{at(full), at(two), at(half)};
  EXPECT_EQ(a.warm_up(choices), 3);
  EXPECT_EQ(a.rungs_with_targets(), 2u) << "three rungs visited, more than two hold targets";
  EXPECT_FALSE(a.render(false, true).drawn) << "the held rung was not the warm-up's last";
  EXPECT_EQ(differing_pixels(a.last_image(), fresh_image(at(full))), 0u);
  // Kept now: full (current) and half (left last); two's targets were released.
  const auto visit = [&](const governor::GlobalLevel& g, bool kept) {
    a.set_quality(at(g));
    const FrameTiming t = a.render(false, true);
    EXPECT_EQ(t.drawn, !kept) << "MSAA " << g.msaa << " scale " << g.scale;
    if (!kept) {
      EXPECT_EQ(t.redrawn_fraction, 1.0) << "a released rung was not drawn in full";
    }
    EXPECT_EQ(a.rungs_with_targets(), 2u);
    EXPECT_EQ(differing_pixels(a.last_image(), fresh_image(at(g))), 0u) << "MSAA " << g.msaa << " scale " << g.scale;
  };
  visit(two, false);
  visit(full, true);
  visit(half, false);
}

TEST_P(LevelsRender, BadChoicesAreRefusedNamingTheUnitAndLevel) {
  Renderer a(*backend_, cluster(), options());
  const auto units = a.draw_units();
  auto message = [&](const governor::QualityChoice& c) {
    try {
      a.set_quality(c);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  governor::QualityChoice c;
  c.units.assign(units.size(), {});
  c.units[0].shading = 99;
  EXPECT_NE(message(c).find("unit 0 (\"" + units[0].name + "\"): shading level 99"), std::string::npos) << message(c);
  c.units[0] = {0, -1};
  EXPECT_NE(message(c).find("lod level -1"), std::string::npos) << message(c);
  c.units.pop_back();
  c.units[0] = {};
  EXPECT_NE(message(c).find("unit levels for"), std::string::npos) << message(c);
  governor::QualityChoice g;
  g.global.msaa = 3;
  EXPECT_NE(message(g).find("global.msaa = 3"), std::string::npos) << message(g);
  g.global = {4, 0.0f};
  EXPECT_NE(message(g).find("global.scale"), std::string::npos) << message(g);
  // A safety unit has one shading and one LOD: any other level names it.
  std::size_t safety = units.size();
  for (std::size_t i = 0; i < units.size(); ++i)
    if (units[i].safety) safety = i;
  ASSERT_LT(safety, units.size()) << "the cluster has telltales: some unit is a safety unit";
  EXPECT_EQ(units[safety].shadings.size(), 1u);
  EXPECT_EQ(units[safety].lod_errors.size(), 1u);
  governor::QualityChoice s;
  s.units.assign(units.size(), {});
  s.units[safety].shading = 1;
  EXPECT_NE(message(s).find("unit " + std::to_string(safety)), std::string::npos) << message(s);
  EXPECT_EQ(a.quality().units, std::vector<governor::UnitLevel>(units.size()));  // nothing applied
}

// A cushion: one quad whose corner normals lean outwards (a smooth surface's), lit by one sun,
// with one program of `model`; `flat_lists`: the converter's Flat geometry prepared.
Scene cushion(bridge::ShadingModel model, bool lean, bool flat_lists) {
  Scene s;
  s.config.size = {64, 64};
  s.config.camera = "Camera";
  Material mat;
  mat.name = "Cushion";
  mat.shading = model;
  s.materials.push_back(mat);
  s.cameras.push_back(test::perspective_camera("Camera", 0.9f));
  Light sun;
  sun.intensity = 2000.0f;  // lux: about 1 in the output after the Lambert term
  s.lights.push_back(sun);
  Primitive p = test::quad_primitive(0, 1.6f);
  for (std::size_t v = 0; lean && v < 4; ++v)
    p.vertices[v * 6 + 3] = v == 1 || v == 2 ? 0.5f : -0.5f, p.vertices[v * 6 + 4] = v < 2 ? -0.5f : 0.5f;
  if (flat_lists) convert::prepare_flat_geometry(p);
  s.meshes.push_back({"Cushion", {p}, {}});
  Node cam, light, mesh;
  cam.name = "Camera", cam.camera = 0, cam.translation = glm::vec3(0, 0, 2);
  light.name = "Sun", light.light = 0, light.rotation = glm::angleAxis(-0.4f, glm::vec3(1, 0.3f, 0));
  mesh.name = "Cushion", mesh.mesh = 0;
  s.nodes = {cam, light, mesh};
  s.roots = {0, 1, 2};
  s.draws.push_back({2, 0, 0, 0});
  bridge::MaterialFeatures f;
  f.shading = model;
  f.lights.directional = 1;
  ProgramEntry e;
  e.program = shadergen::generate(f);
  s.programs.push_back(e);
  return s;
}

// The colours at 16 points inside each of the quad's two triangles (either side of its diagonal
// from the bottom-left to the top-right corner: x + y = 64 in the top-down image).
std::vector<std::array<std::uint8_t, 4>> face_samples(const platform::Image& img, int face) {
  std::vector<std::array<std::uint8_t, 4>> out;
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b) {
      const int x = (face ? 16 : 38) + 3 * a, y = (face ? 16 : 38) + 3 * b;
      const std::size_t i = (std::size_t(y) * std::size_t(img.width) + std::size_t(x)) * 4;
      out.push_back({img.rgba[i], img.rgba[i + 1], img.rgba[i + 2], img.rgba[i + 3]});
    }
  return out;
}

// Keio's flat rung: one lighting per face. With the converter's Flat lists every pixel of a face
// has the colour of the face lit at its own normal (here that of the same quad with hard normals),
// where Gouraud over the leaning corner normals varies across the face, and the Flat program
// without the lists lights each face at one leaning corner instead.
TEST_P(LevelsRender, FlatRungDrawsOneColourPerFace) {
  auto draw = [&](const Scene& s) {
    RendererOptions o;
    o.msaa = 1;
    Renderer r(*backend_, s, o);
    r.render(true, true);
    return r.last_image();
  };
  using bridge::ShadingModel;
  const platform::Image flat = draw(cushion(ShadingModel::Flat, true, true));
  const platform::Image hard = draw(cushion(ShadingModel::Flat, false, true));
  const platform::Image gouraud = draw(cushion(ShadingModel::Gouraud, true, false));
  const platform::Image unprepared = draw(cushion(ShadingModel::Flat, true, false));
  for (int face = 0; face < 2; ++face) {
    const auto f = face_samples(flat, face), h = face_samples(hard, face), g = face_samples(gouraud, face), u = face_samples(unprepared, face);
    for (const auto& px : f) EXPECT_EQ(px, f.front()) << "face " << face << ": one colour";
    EXPECT_EQ(f, h) << "face " << face << ": lit at the face normal";
    EXPECT_GT(f.front()[0], 40) << "face " << face << ": lit";
    EXPECT_NE(g.front(), g.back()) << "face " << face << ": Gouraud varies over the leaning normals";
    EXPECT_NE(u.front(), f.front()) << "face " << face << ": without the lists a corner's normal lights it";
  }
}

INSTANTIATE_TEST_SUITE_P(Backends, LevelsRender,
                         ::testing::Values(platform::BackendKind::Egl, platform::BackendKind::OSMesa),
                         [](const auto& info) { return std::string(platform::to_string(info.param)); });
