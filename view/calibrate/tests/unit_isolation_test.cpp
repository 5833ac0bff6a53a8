// Which nodes a draw unit holds and the outputs that draw one unit alone.
#include <gtest/gtest.h>

#include "meter/calibrate/unit_isolation.hpp"

namespace {

using meter::calibrate::shown_alone;
using meter::calibrate::unit_nodes;

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

TEST(UnitNodes, EachDrawsNodeOnce) {
  auto s = little_scene();
  s.draws.push_back({2, 0, 1, 0});  // b's second primitive
  const std::vector<int> group{0, 3};
  EXPECT_EQ(unit_nodes(s, group), (std::vector<int>{1, 4}));
  const std::vector<int> two_primitives{1, 4};
  EXPECT_EQ(unit_nodes(s, two_primitives), (std::vector<int>{2}));
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
