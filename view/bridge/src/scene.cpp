// Name lookups on the scene model.
#include "meter/bridge/scene.hpp"

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

}  // namespace meter::bridge
