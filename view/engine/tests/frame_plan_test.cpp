// The frame plan without a GL context: a small hand-built scene is evaluated (SceneEvaluator, with
// fixed text metrics), and the plan between two evaluated frames is checked: which regions are
// damaged, when the whole target is redrawn, which passes run and in which order draws go.
#include <gtest/gtest.h>

#include <algorithm>

#include <glm/gtc/quaternion.hpp>

#include "meter/engine/evaluation/scene_evaluator.hpp"
#include "meter/engine/frame_plan/draw_classes.hpp"
#include "meter/engine/frame_plan/draw_units.hpp"
#include "meter/engine/frame_plan/frame_plan.hpp"
#include "meter/engine/frame_plan/screen_regions.hpp"

using namespace meter::engine;

namespace {

constexpr int kWidth = 200, kHeight = 100;

// Draws of the scene, by index.
enum Draw { kFace = 0, kNeedle = 1, kTelltale = 2, kGlass = 3, kLamp = 4, kFarGlass = 5 };
constexpr int kTextAnchorNode = 8, kLampNode = 9;

// Root -> Camera (z 10), Face (z -1, wide), Pivot (animated rotation) -> Needle, Telltale
// (emissive binding), Glass (blended, z 0.5), Light, TextAnchor, Lamp (visibility binding),
// FarGlass (blended, z -0.5).
Scene test_scene() {
  Scene s;
  auto node = [&](const std::string& name, int parent, glm::vec3 t, float scale = 1.0f) {
    Node n;
    n.name = name, n.parent = parent, n.translation = t, n.scale = glm::vec3(scale);
    s.nodes.push_back(n);
    const int i = static_cast<int>(s.nodes.size()) - 1;
    if (parent >= 0) s.nodes[static_cast<std::size_t>(parent)].children.push_back(i);
    else s.roots.push_back(i);
    return i;
  };
  Primitive quad;
  quad.material = 0, quad.vertex_count = 4, quad.indices = {0, 1, 2, 0, 2, 3};
  quad.bounds_min = {-1, -1, 0}, quad.bounds_max = {1, 1, 0};
  Primitive telltale_quad = quad;
  telltale_quad.material = 1;
  s.meshes.push_back({"quad", {quad, telltale_quad}, {}});
  s.materials.resize(2);
  s.materials[0].name = "Paint", s.materials[1].name = "Tell";
  s.programs.resize(2);
  s.programs[1].program.blend = true;
  auto draw = [&](int n, int primitive = 0, int program = 0) { s.draws.push_back({n, 0, primitive, program}); };

  const int root = node("Root", -1, {0, 0, 0});
  const int camera = node("Camera", root, {0, 0, 10});
  s.nodes[static_cast<std::size_t>(camera)].camera = 0;
  s.cameras.push_back({"Camera", true, 0.8f, 0.1f, 100.0f, 1.0f, 1.0f});
  draw(node("Face", root, {0, 0, -1}, 6.0f));
  const int pivot = node("Pivot", root, {0, 0, 0});
  draw(node("Needle", pivot, {1, 0, 0}, 0.2f));
  draw(node("Telltale", root, {-2, 0, 0}, 0.3f), 1);
  draw(node("Glass", root, {0, 0, 0.5f}, 0.5f), 0, 1);
  const int light = node("Light", root, {0, 5, 5});
  s.nodes[static_cast<std::size_t>(light)].light = 0;
  s.lights.push_back({});
  node("TextAnchor", root, {0, -1, 0});
  draw(node("Lamp", root, {2, 1, 0}, 0.3f));
  draw(node("FarGlass", root, {0, 0, -0.5f}, 0.5f), 0, 1);

  Animation a;
  a.name = "Needle";
  AnimSampler rot;
  rot.components = 4, rot.input = {0.0f, 1.0f};
  const glm::quat q = glm::angleAxis(glm::radians(90.0f), glm::vec3(0, 0, 1));
  rot.output = {0, 0, 0, 1, q.x, q.y, q.z, q.w};
  a.samplers.push_back(rot);
  a.channels.push_back({0, pivot, TargetPath::Rotation});
  a.end = 1.0f;
  s.animations.push_back(a);

  Binding tell;
  tell.kind = BindingKind::Emissive, tell.material = "Tell";
  Binding lamp;
  lamp.kind = BindingKind::Visibility, lamp.node = "Lamp";
  s.config.bindings = {tell, lamp};
  s.config.size = {kWidth, kHeight};
  return s;
}

// Text metrics: 10 px per character, 12 px high above the baseline.
struct FixedMeasure final : TextMeasure {
  PixelRegion ink(const TextItem& t, int x, int y) override {
    return {x, y - 12, 10 * static_cast<int>(t.text.size()), 12};
  }
};

const Primitive& quad(const Scene& s) { return s.meshes[0].primitives[0]; }

bool contains(const PixelRegion& outer, const PixelRegion& inner) {
  return inner.x >= outer.x && inner.y >= outer.y && inner.x + inner.width <= outer.x + outer.width &&
         inner.y + inner.height <= outer.y + outer.height;
}
bool covered(const std::vector<PixelRegion>& regions, const PixelRegion& box) {
  const PixelRegion clipped = meter::platform::clip(box, kWidth, kHeight);
  return std::any_of(regions.begin(), regions.end(), [&](const PixelRegion& r) { return contains(r, clipped); });
}

class FramePlanTest : public ::testing::Test {
 protected:
  FramePlanTest() : scene_(test_scene()), evaluator_(scene_), classes_(classify_draws(scene_, false, 1)) {
    outputs_ = resting_outputs(scene_);
    drawn_ = frame();
    record_ = drawn_frame(drawn_);
  }
  FrameState frame() {
    evaluator_.apply(outputs_);
    evaluator_.update_world();
    return evaluator_.evaluate(kWidth, kHeight, measure_);
  }
  FramePlan plan(const FrameState& now, PlanSettings settings = {}) {
    settings.width = kWidth, settings.height = kHeight;
    return plan_frame(scene_, classes_, now, record_, layer_, settings);
  }
  PixelRegion box(Draw d, const FrameState& f) const {
    const auto node = static_cast<std::size_t>(scene_.draws[d].node);
    return *screen_box(quad(scene_), f.world[node], f.view_projection, kWidth, kHeight);
  }

  Scene scene_;
  SceneEvaluator evaluator_;
  DrawClasses classes_;
  FixedMeasure measure_;
  BindingOutputs outputs_;
  FrameState drawn_;
  DrawnFrame record_, layer_;
};

}  // namespace

TEST_F(FramePlanTest, UnchangedFramePlansNothing) {
  const FramePlan p = plan(frame());
  EXPECT_FALSE(p.draw);
  EXPECT_TRUE(p.passes.empty());
}

TEST_F(FramePlanTest, NothingDrawnYetMeansAFullFrame) {
  record_ = {};
  const FramePlan p = plan(frame());
  EXPECT_TRUE(p.draw && p.full);
  ASSERT_EQ(p.passes.size(), 1u);
  EXPECT_FALSE(p.passes[0].scissor);
  EXPECT_EQ(p.passes[0].set, DrawSet::Everything);
  EXPECT_EQ(p.passes[0].draws.size(), scene_.draws.size());
}

TEST_F(FramePlanTest, MovedNeedleDamagesItsOldAndNewBox) {
  outputs_.animation_time[0] = 1.0;
  const FrameState now = frame();
  const FramePlan p = plan(now);
  ASSERT_TRUE(p.draw);
  EXPECT_FALSE(p.full);
  EXPECT_TRUE(covered(p.regions, box(kNeedle, drawn_)));
  EXPECT_TRUE(covered(p.regions, box(kNeedle, now)));
  EXPECT_FALSE(covered(p.regions, box(kTelltale, now)));
  ASSERT_EQ(p.passes.size(), p.regions.size());
  for (std::size_t k = 0; k < p.passes.size(); ++k) EXPECT_EQ(p.passes[k].scissor, p.regions[k]);
}

TEST_F(FramePlanTest, ToggledTelltaleDamagesExactlyItsBox) {
  outputs_.emissive[1] = glm::vec3(1, 0, 0);
  const FrameState now = frame();
  const FramePlan p = plan(now);
  ASSERT_TRUE(p.draw);
  ASSERT_EQ(p.regions.size(), 1u);
  EXPECT_EQ(p.regions[0], meter::platform::clip(box(kTelltale, now), kWidth, kHeight));
  // Only what can touch the region is drawn: the telltale, and the face behind it.
  const auto& draws = p.passes[0].draws;
  EXPECT_NE(std::find(draws.begin(), draws.end(), kTelltale), draws.end());
  EXPECT_NE(std::find(draws.begin(), draws.end(), kFace), draws.end());
  EXPECT_EQ(std::find(draws.begin(), draws.end(), kLamp), draws.end());
}

TEST_F(FramePlanTest, HiddenLampDamagesItsBoxAndIsNoLongerDrawn) {
  outputs_.node_visible[static_cast<std::size_t>(scene_.draws[kLamp].node)] = 0;
  const FrameState now = frame();
  EXPECT_FALSE(now.draws[kLamp].visible);
  const FramePlan p = plan(now);
  ASSERT_EQ(p.regions.size(), 1u);
  EXPECT_TRUE(covered(p.regions, box(kLamp, drawn_)));
  for (const auto& pass : p.passes)
    EXPECT_EQ(std::find(pass.draws.begin(), pass.draws.end(), kLamp), pass.draws.end());
}

TEST_F(FramePlanTest, ChangedTextDamagesItsOldAndNewInk) {
  outputs_.texts = {{kTextAnchorNode, "12", 24, glm::vec4(1), TextAlign::Left}};
  record_ = drawn_frame(frame());
  outputs_.texts = {{kTextAnchorNode, "123", 24, glm::vec4(1), TextAlign::Left}};
  const FrameState now = frame();
  ASSERT_EQ(now.texts.size(), 1u);
  const FramePlan p = plan(now);
  ASSERT_TRUE(p.draw);
  EXPECT_TRUE(covered(p.regions, record_.texts[0].box));
  EXPECT_TRUE(covered(p.regions, now.texts[0].box));
  // A text on a hidden node is not drawable: no pixel changes, the frame stands.
  outputs_.texts = {{kLampNode, "x", 24, glm::vec4(1), TextAlign::Left}};
  outputs_.node_visible[kLampNode] = 0;
  record_ = drawn_frame(frame());
  outputs_.texts[0].text = "y";
  EXPECT_FALSE(plan(frame()).draw);
}

TEST_F(FramePlanTest, CameraOrLightMoveMeansAFullFrame) {
  const FrameState now = frame();
  record_.view_projection[3][0] += 0.5f;
  EXPECT_TRUE(plan(now).full);
  record_ = drawn_frame(now);
  record_.lights[0].second[3][1] += 1.0f;
  EXPECT_TRUE(plan(now).full);
}

TEST_F(FramePlanTest, CornerBehindTheEyeHasNoBoxAndMeansAFullFrame) {
  glm::mat4 behind(1.0f);
  behind[3] = glm::vec4(0, 0, 20, 1);  // the camera is at z 10 looking down -Z
  const FrameState now = frame();
  EXPECT_FALSE(screen_box(quad(scene_), behind, now.view_projection, kWidth, kHeight));
  record_.draws[kTelltale].world = behind;
  const FramePlan p = plan(now);
  EXPECT_TRUE(p.draw && p.full);
}

TEST_F(FramePlanTest, DamageOverHalfTheTargetMeansAFullFrame) {
  outputs_.base_color[0] = glm::vec4(0.5f);  // the face fills most of the target
  EXPECT_TRUE(plan(frame()).full);
}

TEST_F(FramePlanTest, ForcedFrameIsFullWithoutTheLayer) {
  PlanSettings s;
  s.force = true, s.static_layer = true;
  const FramePlan p = plan(frame(), s);
  EXPECT_TRUE(p.draw && p.full);
  EXPECT_FALSE(p.layer_build);
  EXPECT_FALSE(p.copy_layer);
}

// Without partial redraw no damage is worked out: every planned frame is drawn whole (the
// renderer plans only after changed outputs were applied), changed or not.
TEST_F(FramePlanTest, WithoutPartialRedrawEveryPlannedFrameIsAFullFrame) {
  PlanSettings s;
  s.partial_redraw = false;
  FramePlan p = plan(frame(), s);
  EXPECT_TRUE(p.draw && p.full && p.regions.empty());
  outputs_.animation_time[0] = 0.5;
  p = plan(frame(), s);
  EXPECT_TRUE(p.draw && p.full && p.regions.empty());
  ASSERT_EQ(p.passes.size(), 1U);
  EXPECT_FALSE(p.passes[0].scissor);
}

TEST_F(FramePlanTest, DrawOrderIsStaticThenChangeableFrontToBackThenBlendedBackToFront) {
  record_ = {};
  const FramePlan p = plan(frame());
  // Face (static, farthest opaque) first; the changeable ones by depth; blended far to near.
  const std::vector<int> expected = {kFace, kNeedle, kTelltale, kLamp, kFarGlass, kGlass};
  EXPECT_EQ(p.passes[0].draws, expected);
}

TEST_F(FramePlanTest, StaticLayerIsBuiltOnceThenCopiedUnderDamagedRegions) {
  PlanSettings s;
  s.static_layer = true;
  record_ = {};
  FrameState now = frame();
  FramePlan p = plan(now, s);
  ASSERT_TRUE(p.layer_build);
  EXPECT_EQ(p.layer_build->set, DrawSet::StaticOpaque);
  EXPECT_EQ(p.layer_build->draws, std::vector<int>{kFace});
  EXPECT_TRUE(p.full && p.copy_layer);
  ASSERT_EQ(p.passes.size(), 1u);
  EXPECT_EQ(p.passes[0].set, DrawSet::OverStatic);
  EXPECT_EQ(std::find(p.passes[0].draws.begin(), p.passes[0].draws.end(), kFace), p.passes[0].draws.end());
  layer_ = drawn_frame(now);
  record_ = drawn_frame(now);
  EXPECT_TRUE(layer_current(classes_, now, layer_));

  outputs_.animation_time[0] = 1.0;
  p = plan(frame(), s);
  EXPECT_FALSE(p.full);
  EXPECT_FALSE(p.layer_build);
  EXPECT_TRUE(p.copy_layer);
  for (const auto& pass : p.passes) EXPECT_EQ(pass.set, DrawSet::OverStatic);

  // A static draw that changes anyway (misjudged) makes the layer stale: rebuilt (here a full frame:
  // the face covers more than half the target).
  outputs_.base_color[0] = glm::vec4(0.25f);
  now = frame();
  EXPECT_FALSE(layer_current(classes_, now, layer_));
  p = plan(now, s);
  EXPECT_TRUE(p.full && p.layer_build);
}

TEST(DrawClasses, AnimationBindingsAndAncestorsMakeDrawsChangeable) {
  const Scene s = test_scene();
  const DrawClasses c = classify_draws(s, false, 1);
  EXPECT_FALSE(c.changeable[kFace]);
  EXPECT_TRUE(c.changeable[kNeedle]);    // an ancestor has an animation channel
  EXPECT_TRUE(c.changeable[kTelltale]);  // emissive binding on its material
  EXPECT_TRUE(c.changeable[kLamp]);      // visibility binding
  EXPECT_FALSE(c.changeable[kGlass]);
  EXPECT_TRUE(c.layer_pays);
}

TEST(DrawClasses, MorphTargetsAndMorphBindingsMakeDrawsChangeable) {
  Scene s = test_scene();
  s.meshes[0].primitives.push_back(s.meshes[0].primitives[0]);
  s.meshes[0].primitives.back().morph_targets = 1;
  s.draws[kGlass].primitive = 2;
  Binding morph;
  morph.kind = BindingKind::Morph, morph.node = "Face";
  s.config.bindings.push_back(morph);
  const DrawClasses c = classify_draws(s, false, 1);
  EXPECT_TRUE(c.changeable[kGlass]);
  EXPECT_TRUE(c.changeable[kFace]);
  EXPECT_FALSE(c.layer_pays);  // no static opaque draw is left
}

TEST(DrawClasses, MovingCameraOrLightOrNoCameraMeansNoLayer) {
  Scene s = test_scene();
  EXPECT_FALSE(classify_draws(s, false, -1).layer_pays);
  s.animations[0].channels.push_back({0, 1, TargetPath::Rotation});  // the camera
  EXPECT_FALSE(classify_draws(s, false, 1).layer_pays);
  s = test_scene();
  s.animations[0].channels.push_back({0, 7, TargetPath::Translation});  // the light
  EXPECT_FALSE(classify_draws(s, false, 1).layer_pays);
}

// A shadow-casting light with a caster that moves (the needle): its shadow can fall on any draw,
// so there is no static layer and a changed frame is drawn whole. Casters that cannot move, a
// light that casts no shadow, or a point light (no shadow map) keep the layer.
TEST(DrawClasses, MovingCasterUnderAShadowLightMeansNoLayerAndFullFrames) {
  Scene s = test_scene();
  EXPECT_TRUE(classify_draws(s, false, 1).layer_pays);
  s.lights[0].cast_shadow = true;
  const DrawClasses shadowed = classify_draws(s, false, 1);
  EXPECT_TRUE(shadowed.shadows_move);
  EXPECT_FALSE(shadowed.layer_pays);
  s.lights[0].type = LightType::Point;
  EXPECT_FALSE(classify_draws(s, false, 1).shadows_move);
  s.lights[0].type = LightType::Spot;
  s.animations.clear();  // the needle stays put; the lamp's visibility binding still changes it
  EXPECT_TRUE(classify_draws(s, false, 1).shadows_move);
  s.config.bindings.pop_back();
  const DrawClasses still = classify_draws(s, false, 1);
  EXPECT_FALSE(still.shadows_move);  // only the telltale's colour changes: no shadow moves
  EXPECT_TRUE(still.layer_pays);

  Scene moving = test_scene();
  moving.lights[0].cast_shadow = true;
  SceneEvaluator ev(moving);
  FixedMeasure measure;
  BindingOutputs out = resting_outputs(moving);
  auto frame = [&] {
    ev.apply(out);
    ev.update_world();
    return ev.evaluate(kWidth, kHeight, measure);
  };
  const DrawnFrame drawn = drawn_frame(frame());
  out.animation_time[0] = 1.0;
  PlanSettings settings;
  settings.width = kWidth, settings.height = kHeight, settings.static_layer = true;
  const FramePlan p = plan_frame(moving, classify_draws(moving, false, 1), frame(), drawn, DrawnFrame{}, settings);
  EXPECT_TRUE(p.draw);
  EXPECT_TRUE(p.full);
  EXPECT_FALSE(p.copy_layer);
  EXPECT_FALSE(p.layer_build.has_value());
}

TEST(DrawClasses, MergedGroupIsChangeableWhenAMemberIs) {
  Scene s = test_scene();
  s.groups.push_back({"g", {kFace, kLamp}});
  const DrawClasses merged = classify_draws(s, true, 1);
  EXPECT_EQ(merged.group[kFace], 0);
  EXPECT_EQ(merged.group[kLamp], 0);
  EXPECT_TRUE(merged.representative(kFace, s));
  EXPECT_TRUE(merged.changeable[kFace]);
  EXPECT_FALSE(classify_draws(s, false, 1).changeable[kFace]);

  // The group is drawn once, at its representative's place, while a member is visible.
  SceneEvaluator ev(s);
  FixedMeasure m;
  BindingOutputs o = resting_outputs(s);
  ev.update_world();
  auto list = [&] {
    ev.apply(o);
    return draw_list(s, merged, ev.evaluate(kWidth, kHeight, m), DrawSet::Everything, nullptr, kWidth, kHeight);
  };
  std::vector<int> l = list();
  EXPECT_EQ(std::count(l.begin(), l.end(), kFace), 1);
  EXPECT_EQ(std::count(l.begin(), l.end(), kLamp), 0);
  o.node_visible[static_cast<std::size_t>(s.draws[kFace].node)] = 0;
  l = list();
  EXPECT_EQ(std::count(l.begin(), l.end(), kFace), 1);  // the lamp still shows
  o.node_visible[static_cast<std::size_t>(s.draws[kLamp].node)] = 0;
  l = list();
  EXPECT_EQ(std::count(l.begin(), l.end(), kFace), 0);
}

TEST(ScreenRegions, NormaliseClipsMergesOverlapsAndCapsTheCount) {
  std::vector<PixelRegion> r = {{-5, -5, 10, 10}, {195, 95, 10, 10}, {300, 10, 5, 5}};
  normalise(r, kWidth, kHeight);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[0], (PixelRegion{0, 0, 5, 5}));
  EXPECT_EQ(r[1], (PixelRegion{195, 95, 5, 5}));

  r = {{10, 10, 10, 10}, {15, 15, 10, 10}};
  normalise(r, kWidth, kHeight);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0], (PixelRegion{10, 10, 15, 15}));

  r.clear();
  for (int k = 0; k < 6; ++k) r.push_back({k * 30, 0, 5, 5});
  normalise(r, kWidth, kHeight);
  EXPECT_EQ(r.size(), kMaxRegions);
  for (std::size_t i = 0; i < r.size(); ++i)
    for (std::size_t j = i + 1; j < r.size(); ++j) EXPECT_FALSE(overlap(r[i], r[j]));
}

TEST(SceneEvaluation, VisibilityIsInheritedAndWorldMatricesFollowTheTree) {
  const Scene s = test_scene();
  std::vector<signed char> overrides(s.nodes.size(), -1);
  overrides[0] = 0;  // the root
  const auto v = effective_visibility(s, overrides);
  EXPECT_TRUE(std::all_of(v.begin(), v.end(), [](char c) { return c == 0; }));
  SceneEvaluator ev(s);
  ev.update_world();
  EXPECT_FLOAT_EQ(ev.world()[4][3].x, 1.0f);  // needle at rest, under the pivot
  BindingOutputs o = resting_outputs(s);
  o.animation_time[0] = 1.0;
  EXPECT_EQ(ev.apply(o), 1);
  EXPECT_EQ(ev.apply(o), 0);  // the same time is not sampled again
  EXPECT_TRUE(ev.update_world());
  EXPECT_FALSE(ev.update_world());
  EXPECT_NEAR(ev.world()[4][3].y, 1.0f, 1e-6f);  // turned 90 degrees
}

TEST(SceneEvaluation, MorphWeightsTakeTheOverrides) {
  const std::vector<MorphOverride> morph = {{3, 2, 0.5f}, {4, 0, 1.0f}};
  EXPECT_EQ(morph_weights({0.1f}, morph, 3), (std::vector<float>{0.1f, 0.0f, 0.5f}));
  EXPECT_EQ(morph_weights({0.1f}, morph, 5), (std::vector<float>{0.1f}));
}

// Quality levels (meter/engine/frame_plan/draw_units.hpp): a draw's level is part of its state, so
// a level change damages exactly that draw's box, and the frame's load counts each unit's box
// inside the damage only.
class DrawLevelsPlanTest : public FramePlanTest {
 protected:
  DrawLevelsPlanTest() {
    // One LOD of the quad (half its triangles) for every draw of it; the telltale is a safety item.
    scene_.meshes[0].primitives[0].lods = {LodLevel{0.01f, 0.5f, {0, 1, 2}}};
    scene_.draw_levels.assign(scene_.draws.size(), DrawLevels{false, {}, 1});
    scene_.draw_levels[kTelltale] = DrawLevels{true, {}, 0};
    units_ = make_draw_units(scene_, classes_, true);
  }
  DrawUnits units_;
};

TEST_F(DrawLevelsPlanTest, UnitsFollowTheDrawsAndSafetyUnitsCannotMove) {
  ASSERT_EQ(units_.ladders.size(), scene_.draws.size());  // no merged groups here
  EXPECT_EQ(check_draw_levels(scene_), "");
  EXPECT_EQ(units_.ladders[kLamp].name, "Lamp");
  EXPECT_EQ(units_.ladders[kLamp].lod_errors, (std::vector<float>{0.0f, 0.01f}));
  EXPECT_EQ(units_.ladders[kLamp].lod_triangle_fractions, (std::vector<float>{1.0f, 0.5f}));
  EXPECT_TRUE(units_.ladders[kTelltale].safety);
  EXPECT_EQ(units_.ladders[kTelltale].lod_errors.size(), 1u);
  governor::QualityChoice c;
  c.units.assign(units_.ladders.size(), {});
  c.units[kTelltale].lod = 1;
  try {
    checked_choice(units_, c, 4);
    ADD_FAILURE() << "a safety unit's LOD 1 was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("unit 2 (\"Telltale\"): lod level 1, expected 0..0 (a safety unit stays at 0)"), std::string::npos)
        << e.what();
  }
}

TEST_F(DrawLevelsPlanTest, LevelChangeDamagesExactlyThatDrawAndTheLoadCountsItsBox) {
  governor::QualityChoice c;
  c.units.assign(units_.ladders.size(), {});
  c.units[kLamp].lod = 1;
  FrameState now = frame();
  apply_levels(scene_, units_, checked_choice(units_, c, 4), now);
  EXPECT_EQ(now.draws[kLamp].lod, 1);
  EXPECT_EQ(now.draws[kNeedle].lod, 0);
  const FramePlan p = plan(now);
  ASSERT_TRUE(p.draw);
  EXPECT_FALSE(p.full);
  EXPECT_TRUE(covered(p.regions, box(kLamp, now)));
  EXPECT_FALSE(covered(p.regions, box(kNeedle, now)));
  const governor::FrameLoad load = frame_load(scene_, classes_, units_, now, p, kWidth, kHeight, 1.0f);
  EXPECT_TRUE(load.drawn);
  EXPECT_FALSE(load.full_frame);
  long long damaged = 0;
  for (const auto& r : p.regions) damaged += area(r);
  EXPECT_DOUBLE_EQ(load.redrawn_pixels, double(damaged));
  // The lamp's whole (clipped) box lies in the damage; the needle is not drawn in it.
  EXPECT_DOUBLE_EQ(load.unit_pixels[kLamp], double(area(meter::platform::clip(box(kLamp, now), kWidth, kHeight))));
  EXPECT_DOUBLE_EQ(load.unit_pixels[kNeedle], 0.0);
  // The face under the lamp is redrawn in the damaged region only, never more than it.
  EXPECT_GT(load.unit_pixels[kFace], 0.0);
  EXPECT_LE(load.unit_pixels[kFace], double(damaged));
  // At half scale the same boxes stand for four times the output pixels.
  const governor::FrameLoad half = frame_load(scene_, classes_, units_, now, p, kWidth, kHeight, 0.5f);
  EXPECT_DOUBLE_EQ(half.unit_pixels[kLamp], 4.0 * load.unit_pixels[kLamp]);
}
