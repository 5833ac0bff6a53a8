// Name lookups on the scene model.
#include "meter/bridge/scene.hpp"

#include <algorithm>
#include <cstddef>

namespace meter::bridge {

int Scene::find_node(std::string_view name) const {
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].name == name) return static_cast<int>(i);
  }
  return -1;
}
int Scene::find_material(std::string_view name) const {
  for (std::size_t i = 0; i < materials.size(); ++i) {
    if (materials[i].name == name) return static_cast<int>(i);
  }
  return -1;
}
int Scene::find_animation(std::string_view name) const {
  for (std::size_t i = 0; i < animations.size(); ++i) {
    if (animations[i].name == name) return static_cast<int>(i);
  }
  return -1;
}


std::vector<int> node_preorder(const Scene& scene) {
  std::vector<int> order;
  order.reserve(scene.nodes.size());
  std::vector<char> seen(scene.nodes.size(), 0);
  std::vector<int> stack(scene.roots.rbegin(), scene.roots.rend());
  while (!stack.empty()) {
    const int n = stack.back();
    stack.pop_back();
    if (n < 0 || static_cast<std::size_t>(n) >= scene.nodes.size() || seen[static_cast<std::size_t>(n)]) continue;
    seen[static_cast<std::size_t>(n)] = 1;
    order.push_back(n);
    const auto& children = scene.nodes[static_cast<std::size_t>(n)].children;
    stack.insert(stack.end(), children.rbegin(), children.rend());
  }
  return order;
}


std::vector<int> light_order(const Scene& scene) {
  std::vector<int> lights;
  for (int n : node_preorder(scene))
    if (scene.nodes[static_cast<std::size_t>(n)].light >= 0) lights.push_back(n);
  auto type = [&](int n) {
    return static_cast<int>(scene.lights[static_cast<std::size_t>(scene.nodes[static_cast<std::size_t>(n)].light)].type);
  };
  std::stable_sort(lights.begin(), lights.end(), [&](int a, int b) { return type(a) < type(b); });
  return lights;
}

unsigned shadow_map_lights(const Scene& scene, const std::vector<int>& light_nodes) {
  unsigned mask = 0;
  int maps = 0;
  for (std::size_t i = 0; i < light_nodes.size() && i < 32 && maps < kMaxShadowMaps; ++i) {
    const Light& l = scene.lights[static_cast<std::size_t>(scene.nodes[static_cast<std::size_t>(light_nodes[i])].light)];
    if (l.cast_shadow && l.type != LightType::Point) mask |= 1u << i, ++maps;
  }
  return mask;
}

}  // namespace meter::bridge
