// Mesh concatenation planning: group checks and proposals on hand-built scenes, and the package
// round trip of groups (writer -> reader, with the reader's group check).
#include <gtest/gtest.h>

#include "meter/convert/concat_plan.hpp"
#include "meter/convert/package_writer.hpp"
#include "meter/engine/merged_draws.hpp"
#include "meter/engine/package_reader.hpp"
#include "test_scenes.hpp"

using namespace meter;
using namespace meter::convert;
using engine::check_groups;
using engine::deserialize_scene;
using engine::test::quad_primitive;
using bridge::AttributeSemantic;

namespace {

// Camera at z = 10 looking down -Z (perspective), quads laid out on z = 0 by `positions`, each
// with its own mesh; materials "A" (opaque), "B" (opaque), "G" (blend).
Scene scene_with(const std::vector<std::pair<std::string, glm::vec3>>& objects, const std::vector<int>& materials) {
  Scene s;
  s.config.size = {400, 400};
  for (const char* name : {"A", "B", "G"}) {
    Material m;
    m.name = name;
    if (std::string(name) == "G") m.alpha = bridge::AlphaMode::Blend;
    s.materials.push_back(m);
  }
  s.cameras.push_back(engine::test::perspective_camera("Cam", 0.9f));
  Node c;
  c.name = "Camera";
  c.camera = 0;
  c.translation = glm::vec3(0, 0, 10);
  s.nodes.push_back(c);
  s.roots.push_back(0);
  for (std::size_t i = 0; i < objects.size(); ++i) {
    Mesh m;
    m.name = objects[i].first;
    m.primitives.push_back(quad_primitive(materials[i]));
    s.meshes.push_back(m);
    Node n;
    n.name = objects[i].first;
    n.mesh = static_cast<int>(i);
    n.translation = objects[i].second;
    s.roots.push_back(static_cast<int>(s.nodes.size()));
    s.nodes.push_back(n);
  }
  return s;
}

// An animation `name` moving node `node` from `from` to `to` over one second.
Animation translation(const char* name, int node, glm::vec3 from, glm::vec3 to) {
  Animation an;
  an.name = name;
  AnimSampler sm;
  sm.components = 3;
  sm.input = {0.0f, 1.0f};
  sm.output = {from.x, from.y, from.z, to.x, to.y, to.z};
  an.samplers.push_back(sm);
  an.channels.push_back({0, node, TargetPath::Translation});
  an.end = 1.0f;
  return an;
}

std::string error_of(const Scene& s, const std::vector<Group>& g) {
  try {
    plan_groups(s, g, false, "test.json");
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(ConcatPlan, AcceptsSeparateObjectsWithOneMaterial) {
  Scene s = scene_with({{"a", {-3, 0, 0}}, {"b", {0, 0, 0}}, {"c", {3, 0, 0}}}, {0, 0, 0});
  auto plan = plan_groups(s, {{"row", {"c", "a", "b"}}}, false, "test.json");
  ASSERT_EQ(plan.groups.size(), 1u);
  // Members come back in draw order; "a" (first drawn) is the representative.
  EXPECT_EQ(plan.groups[0].members, (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_NE(concat_report(plan).find("group row (merged, 3 objects)"), std::string::npos);
}

TEST(ConcatPlan, RejectsMixedMaterialsNamingTheObjects) {
  Scene s = scene_with({{"a", {-3, 0, 0}}, {"b", {0, 0, 0}}}, {0, 1});
  const std::string e = error_of(s, {{"row", {"a", "b"}}});
  EXPECT_NE(e.find("test.json: scene config $.groups[0] (\"row\")"), std::string::npos) << e;
  EXPECT_NE(e.find("\"b\" uses material \"B\" but \"a\" uses \"A\""), std::string::npos) << e;
}

TEST(ConcatPlan, RejectsCoplanarOverlapButNotOverlapAtDifferentDepths) {
  // Same depth, overlapping on screen: LEQUAL makes the order visible.
  Scene s = scene_with({{"a", {0, 0, 0}}, {"b", {0.5f, 0, 0}}}, {0, 0});
  std::string e = error_of(s, {{"g", {"a", "b"}}});
  EXPECT_NE(e.find("\"a\" and \"b\" overlap on screen at intersecting depths"), std::string::npos) << e;
  // One clearly in front: the depth test decides, order cannot matter.
  Scene t = scene_with({{"a", {0, 0, 0}}, {"b", {0.5f, 0, 1}}}, {0, 0});
  EXPECT_EQ(error_of(t, {{"g", {"a", "b"}}}), "");
  // Blended: any screen overlap matters.
  Scene u = scene_with({{"a", {0, 0, 0}}, {"b", {0.5f, 0, 1}}}, {2, 2});
  e = error_of(u, {{"g", {"a", "b"}}});
  EXPECT_NE(e.find("\"a\" and \"b\" overlap on screen,"), std::string::npos) << e;
}

TEST(ConcatPlan, RejectsADrawOrderChangeAgainstANonMember) {
  // Blended a (far) ... x (middle) ... b (near), x overlaps b. Unmerged back-to-front: a, x, b.
  // Merged at a's place: {a, b}, x -> x would be drawn over b.
  Scene s = scene_with({{"a", {-3, 0, -2}}, {"x", {0.2f, 0, -1}}, {"b", {0, 0, 0}}}, {2, 2, 2});
  const std::string e = error_of(s, {{"g", {"a", "b"}}});
  EXPECT_NE(e.find("\"x\" overlaps \"b\" and their draw order would change"), std::string::npos) << e;
}

TEST(ConcatPlan, ChecksOverTheAnimationRange) {
  // b slides from x = 3 to x = 0.3 (onto a) over one second: the rest pose alone would pass.
  Scene s = scene_with({{"a", {0, 0, 0}}, {"b", {3, 0, 0}}}, {0, 0});
  s.animations.push_back(translation("slide", 2, {3, 0, 0}, {0.3f, 0, 0}));
  const std::string e = error_of(s, {{"g", {"a", "b"}}});
  EXPECT_NE(e.find("overlap on screen"), std::string::npos) << e;
}

TEST(ConcatPlan, RejectsUnknownDuplicateAndMeshlessMembers) {
  Scene s = scene_with({{"a", {-3, 0, 0}}, {"b", {0, 0, 0}}, {"c", {3, 0, 0}}}, {0, 0, 0});
  EXPECT_NE(error_of(s, {{"g", {"a", "nope"}}}).find("no node named \"nope\""), std::string::npos);
  EXPECT_NE(error_of(s, {{"g", {"a", "Camera"}}}).find("\"Camera\" has no mesh"), std::string::npos);
  EXPECT_NE(error_of(s, {{"g", {"a", "b"}}, {"h", {"b", "c"}}}).find("\"b\" is already a member of another group"), std::string::npos);
  EXPECT_NE(error_of(s, {{"g", {"a"}}}).find("at least two members"), std::string::npos);
}

TEST(ConcatPlan, ProposesGroupsPerMaterialAndExplainsLeftOuts) {
  // a, b, c material A in a row; d material A on top of c (coplanar); e material B alone.
  Scene s = scene_with({{"a", {-3, 0, 0}}, {"b", {0, 0, 0}}, {"c", {3, 0, 0}}, {"d", {3.4f, 0, 0}}, {"e", {0, 3, 0}}}, {0, 0, 0, 0, 1});
  auto plan = plan_groups(s, {}, true, "test.json");
  ASSERT_EQ(plan.groups.size(), 1u);
  EXPECT_EQ(plan.groups[0].members, (std::vector<std::string>{"a", "b", "c"}));
  const std::string r = concat_report(plan);
  EXPECT_NE(r.find("\"d\" left out: \"c\" and \"d\" overlap"), std::string::npos) << r;
  EXPECT_NE(r.find("(not proposed): e"), std::string::npos) << r;
}

TEST(ConcatPackage, GroupsRoundTripAndBadGroupsAreRefused) {
  Scene s = scene_with({{"a", {-3, 0, 0}}, {"b", {0, 0, 0}}}, {0, 0});
  ProgramEntry pe;
  pe.program.attributes.push_back({"a_position", AttributeSemantic::Position, -1, 0, 3});
  pe.program.attributes.push_back({"a_vertex_alpha", AttributeSemantic::VertexAlpha, -1, 1, 1});
  s.programs.push_back(pe);
  s.draws = {{1, 0, 0, 0}, {2, 1, 0, 0}};
  s.config.source_json = R"({"format": "meter-scene-config/1"})";
  s.groups = {{"g", {0, 1}}};
  Scene r = deserialize_scene(serialize_scene(s), "x.msp");
  ASSERT_EQ(r.groups.size(), 1u);
  EXPECT_EQ(r.groups[0].name, "g");
  EXPECT_EQ(r.groups[0].draws, (std::vector<int>{0, 1}));
  s.groups = {{"g", {0, 5}}};
  try {
    deserialize_scene(serialize_scene(s), "x.msp");
    FAIL() << "out-of-range group draw accepted";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("draw index 5 out of range"), std::string::npos) << e.what();
  }
  s.groups = {{"g", {0, 1}}};
  s.programs[0].program.attributes.pop_back();  // no vertex alpha: the runtime could not hide members
  EXPECT_NE(check_groups(s).find("no vertex alpha attribute"), std::string::npos);
}

// The paper's eq. 1-3 with our k = 0 (indexed triangle lists) and s only on moving members.
TEST(MergeBreakEven, FollowsThePapersEquations) {
  const ConcatenationCosts c{0.16, 0.00077, 0.0035};  // SH7776 (paper sec. 5.2)
  const MergePrediction moving = predict_merge(c, 40, 4000, 4000);
  EXPECT_DOUBLE_EQ(moving.before_ms, 0.16 * 40 + 0.00077 * 4000);
  EXPECT_DOUBLE_EQ(moving.after_ms, 0.16 + 0.0035 * 4000 + 0.00077 * 4000);
  EXPECT_FALSE(moving.pays());
  EXPECT_DOUBLE_EQ(moving.break_even_objects, 1.0 + 0.0035 * 4000 / 0.16);  // 88.5 objects
  EXPECT_TRUE(predict_merge(c, 89, 4000, 4000).pays());
  EXPECT_FALSE(predict_merge(c, 88, 4000, 4000).pays());
  // Nothing moves: no CPU transform after the first upload, two objects already pay.
  EXPECT_TRUE(predict_merge(c, 2, 4000, 0).pays());
  EXPECT_FALSE(predict_merge(c, 1, 4000, 0).pays());
  EXPECT_NE(describe(moving).find("does not pay, stays unmerged"), std::string::npos) << describe(moving);
}

// With costs, a group that would not pay stays unmerged (configured or proposed) and the report
// says why; without, the same groups are merged as before.
TEST(MergeBreakEven, AGroupThatWouldNotPayStaysUnmerged) {
  Scene s = scene_with({{"a", {-3, 0, 0}}, {"b", {0, 0, 0}}, {"c", {3, 0, 0}}}, {0, 0, 0});
  // "c" moves: its 4 vertices are transformed again every frame once merged.
  s.animations.push_back(translation("bob", 3, {3, 0, 0}, {3, 0.5f, 0}));
  const ConcatenationCosts cheap_draws{0.001, 0.0001, 0.01};  // s x 4 = 0.04 ms > one draw saved
  const ConcatPlan without = plan_groups(s, {{"row", {"a", "b", "c"}}}, false, "test.json");
  ASSERT_EQ(without.groups.size(), 1u);
  const ConcatPlan with = plan_groups(s, {{"row", {"a", "b", "c"}}}, false, "test.json", &cheap_draws);
  EXPECT_TRUE(with.groups.empty());
  const std::string report = concat_report(with);
  EXPECT_NE(report.find("predicted before 0.0042 ms, after 0.0422 ms (3 draws, 12 vertices, 4 moving"), std::string::npos) << report;
  EXPECT_NE(report.find("stays unmerged"), std::string::npos) << report;
  // Proposed: the two still quads pay (one draw saved, nothing to transform); "c" would cost more
  // to transform than the draw it saves, so it is left out.
  const ConcatPlan proposed = plan_groups(s, {}, true, "test.json", &cheap_draws);
  ASSERT_EQ(proposed.groups.size(), 1u) << concat_report(proposed);
  EXPECT_EQ(proposed.groups[0].members, (std::vector<std::string>{"a", "b"}));
  EXPECT_NE(concat_report(proposed).find("pays, merged"), std::string::npos) << concat_report(proposed);
}
