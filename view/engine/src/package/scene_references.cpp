// Cross-section checks of a loaded package (scene_references.hpp).
#include "scene_references.hpp"

#include <stdexcept>

#include "meter/config/scene_config_parser.hpp"
#include "meter/engine/frame_plan/draw_units.hpp"
#include "meter/engine/merged_draws.hpp"

namespace meter::engine {
namespace {

struct References {
  const std::string& origin;
  void index(int v, std::size_t size, bool allow_none, const char* what) const {
    if ((v == -1 && allow_none) || (v >= 0 && static_cast<std::size_t>(v) < size)) return;
    fail(std::string(what) + " index " + std::to_string(v) + " out of range (" + std::to_string(size) + ")");
  }
  [[noreturn]] void fail(const std::string& what) const { throw SceneError(origin + ": corrupt package: " + what); }
};

void check_nodes(const Scene& s, const References& r) {
  const auto nn = s.nodes.size();
  for (const auto& nd : s.nodes) {
    r.index(nd.parent, nn, true, "node.parent");
    for (int c : nd.children) r.index(c, nn, false, "node.children");
    r.index(nd.mesh, s.meshes.size(), true, "node.mesh");
    r.index(nd.camera, s.cameras.size(), true, "node.camera");
    r.index(nd.light, s.lights.size(), true, "node.light");
    r.index(nd.skin, s.skins.size(), true, "node.skin");
  }
  for (int root : s.roots) r.index(root, nn, false, "roots");
  for (const auto& k : s.skins)
    for (int j : k.joints) r.index(j, nn, false, "skin.joints");
  for (const auto& a : s.animations)
    for (const auto& ch : a.channels) {
      r.index(ch.sampler, a.samplers.size(), false, "channel.sampler");
      r.index(ch.node, nn, false, "channel.node");
    }
}

}  // namespace

void check_references(const Scene& s, const std::string& origin) {
  const References r{origin};
  check_nodes(s, r);
  for (const auto& m : s.meshes)
    for (const auto& p : m.primitives) r.index(p.material, s.materials.size(), false, "primitive.material");
  for (const auto& m : s.materials)
    for (int t : m.texture) r.index(t, s.textures.size(), true, "material.texture");
  for (const auto& d : s.draws) {
    r.index(d.node, s.nodes.size(), false, "draw.node");
    r.index(d.mesh, s.meshes.size(), false, "draw.mesh");
    r.index(d.primitive, s.meshes[std::size_t(d.mesh)].primitives.size(), false, "draw.primitive");
    r.index(d.program, s.programs.size(), false, "draw.program");
  }
  if (const std::string why = check_groups(s); !why.empty()) r.fail(why);
  if (const std::string why = check_draw_levels(s); !why.empty()) r.fail(why);
}

void load_config(Scene& s, const std::string& origin) {
  try {
    s.config = meter::config::parse_scene_config(s.config.source_json, origin + " (embedded scene config)");
  } catch (const std::invalid_argument& e) {
    throw SceneError(e.what());
  }
  s.ambient = glm::vec3(s.config.ambient[0], s.config.ambient[1], s.config.ambient[2]);
  for (const auto& g : s.integrity.regions)
    for (int b : g.bindings)
      if (b < 0 || std::size_t(b) >= s.config.bindings.size())
        throw SceneError(origin + ": corrupt package: integrity region " + g.name + " names binding " + std::to_string(b) +
                         " of " + std::to_string(s.config.bindings.size()));
}

}  // namespace meter::engine
