// Which nodes each draw unit holds (the renderer's order: draws, a merged group at its
// representative's place) and the outputs that draw one unit alone.
#include <gtest/gtest.h>

#include "meter/calibrate/unit_isolation.hpp"

namespace {

using meter::calibrate::shown_alone;
using meter::calibrate::unit_nodes;
namespace gov = meter::engine::governor;

// root (no mesh) -> a (mesh), b (mesh) -> c (mesh, child of b); d (mesh). Draws a, b, c, d; a and d
// merged into group "ad".
meter::engine::Scene little_scene() {
  meter::engine::Scene s;
  const char* names[] = {"root", "a", "b", "c", "d"};
  for (const char* n : names) {
    s.nodes.emplace_back();
    s.nodes.back().name = n;
  }
  s.nodes[1].parent = 0, s.nodes[2].parent = 0, s.nodes[3].parent = 2, s.nodes[4].parent = 0;
  s.nodes[0].children = {1, 2, 4};
  s.nodes[2].children = {3};
  for (int i = 1; i < 5; ++i) {
    s.nodes[std::size_t(i)].mesh = 0;
    s.draws.push_back({i, 0, 0, 0});
  }
  s.groups.push_back({"ad", {0, 3}});
  return s;
}

std::vector<gov::UnitLadder> ladders(std::initializer_list<const char*> names) {
  std::vector<gov::UnitLadder> l;
  for (const char* n : names) l.push_back({n, false, {meter::bridge::ShadingModel::Unlit}, {0.0f}, {1.0f}});
  return l;
}

TEST(UnitNodes, AGroupIsOneUnitAtItsRepresentativesPlace) {
  const auto s = little_scene();
  const auto units = unit_nodes(s, ladders({"ad", "b", "c"}));
  ASSERT_EQ(units.size(), 3u);
  EXPECT_EQ(units[0], (std::vector<int>{1, 4}));
  EXPECT_EQ(units[1], (std::vector<int>{2}));
  EXPECT_EQ(units[2], (std::vector<int>{3}));
}

TEST(UnitNodes, ARendererThatListsOtherUnitsIsNamed) {
  const auto s = little_scene();
  try {
    unit_nodes(s, ladders({"ad", "c", "b"}));
    FAIL() << "a swapped order must be refused";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "draw unit 1 is \"c\" in the renderer, \"b\" in the scene's draw order");
  }
  EXPECT_THROW(unit_nodes(s, ladders({"ad", "b"})), std::invalid_argument);
}

TEST(ShownAlone, HidesEveryOtherMeshButKeepsTheShownNodesAncestors) {
  const auto s = little_scene();
  meter::engine::BindingOutputs base;
  base.node_visible.assign(5, -1);
  base.node_visible[3] = 0;  // a binding hides c: shown alone it is drawn anyway
  base.texts.push_back({});
  const auto out = shown_alone(s, base, {3});
  EXPECT_EQ(out.node_visible, (std::vector<signed char>{1, 0, 1, 1, 0}));  // b is c's parent: kept
  EXPECT_TRUE(out.texts.empty());
  const auto none = shown_alone(s, base, {});
  EXPECT_EQ(none.node_visible, (std::vector<signed char>{-1, 0, 0, 0, 0}));
}

}  // namespace
