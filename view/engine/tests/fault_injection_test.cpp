// Injected display faults on plain data: what the GL execution is given instead of the evaluated
// frame and the plan (meter/engine/integrity/fault_injection.hpp), on a hand-built scene.
#include <gtest/gtest.h>

#include "meter/engine/integrity/fault_injection.hpp"

using namespace meter::engine;

namespace {

// Root(0) -> Face(1), Pivot(2) -> Needle(3), Lamp(4); draws: Face, Needle, Lamp (Lamp merged
// with Face in group 0 when `merged`).
struct Fixture {
  Scene scene;
  DrawClasses classes;
  FrameState frame;
  explicit Fixture(bool merged) {
    auto node = [&](const std::string& name, int parent) {
      Node n;
      n.name = name, n.parent = parent;
      scene.nodes.push_back(n);
      const int i = static_cast<int>(scene.nodes.size()) - 1;
      if (parent >= 0) scene.nodes[static_cast<std::size_t>(parent)].children.push_back(i);
      return i;
    };
    const int root = node("Root", -1);
    node("Face", root);
    const int pivot = node("Pivot", root);
    node("Needle", pivot);
    node("Lamp", root);
    scene.draws = {{1, 0, 0, 0}, {3, 0, 0, 0}, {4, 0, 0, 0}};
    classes.group = {merged ? 0 : -1, -1, merged ? 0 : -1};
    classes.changeable = {0, 1, 1};
    frame.world.assign(5, glm::mat4(1.0f));
    frame.visible.assign(5, 1);
    frame.draws.resize(3);
    for (auto& d : frame.draws) {
      d.visible = true;
      d.base = {0.1f, 0.2f, 0.3f, 1.0f};
      d.emissive = {0.0f, 0.9f, 0.12f};
    }
  }
};

FramePlan plan_of_all() {
  FramePlan p;
  p.draw = p.full = true;
  p.passes.push_back({DrawSet::Everything, std::nullopt, {0, 1, 2}});
  return p;
}

TEST(FaultInjection, KindsParseByName) {
  for (const char* name : {"drop", "colour", "cover", "text", "stuck", "needle"}) {
    const auto k = parse_fault_kind(name);
    ASSERT_TRUE(k.has_value()) << name;
    EXPECT_STREQ(fault_kind_name(*k), name);
  }
  EXPECT_FALSE(parse_fault_kind("color").has_value());
}

TEST(FaultInjection, SubtreeListsTheNodeAndItsDescendants) {
  Fixture f(false);
  EXPECT_EQ(subtree(f.scene, 2), (std::vector<int>{2, 3}));
  EXPECT_TRUE(subtree(f.scene, 9).empty());
}

TEST(FaultInjection, ADroppedDrawIsHiddenAndLeftOutOfEveryPassUnlessMerged) {
  Fixture f(false);
  const FaultInjection drop{FaultKind::DropDraw, 2, {}};
  const FrameState g = faulty_frame(f.scene, drop, f.frame, {});
  EXPECT_FALSE(g.visible[2]);
  EXPECT_FALSE(g.visible[3]);
  EXPECT_TRUE(g.visible[1]);
  EXPECT_FALSE(g.draws[1].visible);
  EXPECT_TRUE(g.draws[0].visible);
  EXPECT_EQ(faulty_plan(f.scene, f.classes, drop, plan_of_all()).passes[0].draws, (std::vector<int>{0, 2}));
  // A merged member stays in the list (its group is drawn) and is left out through its visibility.
  Fixture m(true);
  const FaultInjection lamp{FaultKind::DropDraw, 4, {}};
  EXPECT_EQ(faulty_plan(m.scene, m.classes, lamp, plan_of_all()).passes[0].draws, (std::vector<int>{0, 1, 2}));
  EXPECT_FALSE(faulty_frame(m.scene, lamp, m.frame, {}).visible[4]);
}

TEST(FaultInjection, AWrongColourRotatesTheItemsChannelsOnly) {
  Fixture f(false);
  const FrameState g = faulty_frame(f.scene, {FaultKind::WrongColour, 4, {}}, f.frame, {});
  EXPECT_EQ(g.draws[2].emissive, glm::vec3(0.9f, 0.12f, 0.0f));
  EXPECT_EQ(g.draws[2].base, glm::vec4(0.2f, 0.3f, 0.1f, 1.0f));
  EXPECT_EQ(g.draws[0], f.frame.draws[0]);
}

TEST(FaultInjection, AStaleNeedleKeepsTheHeldTransformOfItsSubtree) {
  Fixture f(false);
  std::vector<glm::mat4> held(5, glm::mat4(2.0f));
  const FrameState g = faulty_frame(f.scene, {FaultKind::StaleNeedle, 2, {}}, f.frame, held);
  EXPECT_EQ(g.world[2], glm::mat4(2.0f));
  EXPECT_EQ(g.world[3], glm::mat4(2.0f));
  EXPECT_EQ(g.draws[1].world, glm::mat4(2.0f));
  EXPECT_EQ(g.world[1], glm::mat4(1.0f));
}

TEST(FaultInjection, CoverAndStuckLeaveTheFrameAndPlanAsEvaluated) {
  Fixture f(false);
  for (FaultKind k : {FaultKind::CoverDraw, FaultKind::CoverText, FaultKind::StuckFrame}) {
    const FaultInjection x{k, 4, {1, 1, 2, 2}};
    EXPECT_EQ(faulty_frame(f.scene, x, f.frame, {}).draws, f.frame.draws);
    EXPECT_EQ(faulty_plan(f.scene, f.classes, x, plan_of_all()).passes[0].draws, (std::vector<int>{0, 1, 2}));
  }
}

}  // namespace
