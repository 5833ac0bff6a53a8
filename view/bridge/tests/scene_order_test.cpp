// The scene's traversal order and light order: the converter generates programs for them and
// the runtime sets uniforms and sorts draws by them, so both sides must agree exactly.
#include <gtest/gtest.h>

#include "meter/bridge/scene.hpp"

namespace {

using namespace meter::bridge;

// Adds a node under `parent` (-1 = a root) and returns its index.
int add(Scene& s, int parent, int light = -1) {
  const int n = static_cast<int>(s.nodes.size());
  Node node;
  node.parent = parent;
  node.light = light;
  s.nodes.push_back(node);
  if (parent < 0)
    s.roots.push_back(n);
  else
    s.nodes[static_cast<std::size_t>(parent)].children.push_back(n);
  return n;
}

TEST(NodePreorder, VisitsEachRootDepthFirstParentsBeforeChildrenInGltfOrder) {
  Scene s;
  const int a = add(s, -1), a1 = add(s, a), a11 = add(s, a1), a2 = add(s, a);
  const int b = add(s, -1), b1 = add(s, b);
  EXPECT_EQ(node_preorder(s), (std::vector<int>{a, a1, a11, a2, b, b1}));
}

TEST(NodePreorder, LeavesOutNodesNoRootReachesAndSurvivesBadLinks) {
  Scene s;
  const int a = add(s, -1);
  add(s, -1);
  s.roots.pop_back();  // node 1 is no longer a root and has no parent
  s.nodes[0].children.push_back(0);  // a cycle onto itself
  s.nodes[0].children.push_back(99);  // an index past the end
  EXPECT_EQ(node_preorder(s), (std::vector<int>{a}));
  EXPECT_TRUE(node_preorder(Scene{}).empty());
}

TEST(LightOrder, GroupsLightsByTypeKeepingTraversalOrderWithinEachType) {
  Scene s;
  s.lights = {{"spot", LightType::Spot}, {"sun", LightType::Directional}, {"bulb", LightType::Point},
              {"sun2", LightType::Directional}};
  const int root = add(s, -1);
  const int spot = add(s, root, 0), bulb = add(s, spot, 2), sun = add(s, root, 1);
  add(s, root);  // not a light
  const int sun2 = add(s, -1, 3);
  EXPECT_EQ(light_order(s), (std::vector<int>{sun, sun2, bulb, spot}));
}

}  // namespace
