// Nodes: the hierarchy (one parent each, no loops), finite TRS or decomposable matrices, and the
// references to meshes, skins, cameras and lights. All nodes are converted (indices stay glTF
// indices); the roots are the default scene's.
#include <cmath>

#include <glm/gtc/quaternion.hpp>

#include "convert_context.hpp"

namespace meter::convert {

void validate_nodes(ConvertContext& ctx) {
  const std::size_t n = ctx.m.nodes.size();
  ctx.parent.assign(n, -1);
  std::vector<char> in_loop(n, 0);
  for (std::size_t i = 0; i < n; ++i) {
    const auto& nd = ctx.m.nodes[i];
    const std::string p = idx("nodes", i);
    for (std::size_t k = 0; k < nd.children.size(); ++k) {
      int c = nd.children[k];
      if (c < 0 || static_cast<std::size_t>(c) >= n) {
        ctx.error(p + ".children[" + std::to_string(k) + "]", "node index " + std::to_string(c) + " out of range");
      } else if (ctx.parent[static_cast<std::size_t>(c)] >= 0 || static_cast<std::size_t>(c) == i) {
        if (static_cast<std::size_t>(c) != i && ctx.parent[static_cast<std::size_t>(c)] != static_cast<int>(i)) {
          ctx.error(idx("nodes", static_cast<std::size_t>(c)), "node has more than one parent (nodes " +
                                                            std::to_string(ctx.parent[static_cast<std::size_t>(c)]) + " and " + std::to_string(i) + ")");
        } else if (static_cast<std::size_t>(c) == i) {
          in_loop[i] = 1;
        }
      } else {
        ctx.parent[static_cast<std::size_t>(c)] = static_cast<int>(i);
      }
    }
    auto finite_vec = [&](const std::vector<double>& v, std::size_t want, const char* field) {
      if (v.empty()) return true;
      if (v.size() != want) {
        ctx.error(p + "." + field, "expected " + std::to_string(want) + " numbers, got " + std::to_string(v.size()));
        return false;
      }
      bool ok = true;
      for (std::size_t k = 0; k < v.size(); ++k) {
        if (!std::isfinite(v[k])) ctx.error(p + "." + field + "[" + std::to_string(k) + "]", "value " + fmt(v[k]) + " is not finite"), ok = false;
      }
      return ok;
    };
    finite_vec(nd.translation, 3, "translation");
    finite_vec(nd.scale, 3, "scale");
    if (finite_vec(nd.rotation, 4, "rotation") && nd.rotation.size() == 4) {
      double len = std::sqrt(nd.rotation[0] * nd.rotation[0] + nd.rotation[1] * nd.rotation[1] +
                             nd.rotation[2] * nd.rotation[2] + nd.rotation[3] * nd.rotation[3]);
      if (std::abs(len - 1.0) > 1e-3) {
        ctx.error(p + ".rotation", "quaternion not unit length (|q| = " + fmt(len) + ")");
      } else if (std::abs(len - 1.0) > 1e-6) {
        ctx.repair(p + ".rotation", "quaternion |q| = " + fmt(len) + " renormalised (export rounding)");
      }
    }
    if (finite_vec(nd.matrix, 16, "matrix") && nd.matrix.size() == 16) {
      std::string why;
      glm::vec3 t, s;
      glm::quat r;
      if (!decompose(nd.matrix, t, r, s, why)) ctx.error(p + ".matrix", "matrix is not decomposable to TRS (" + why + ")");
    }
    if (nd.mesh >= 0 && static_cast<std::size_t>(nd.mesh) >= ctx.m.meshes.size()) ctx.error(p + ".mesh", "index out of range");
    if (nd.skin >= 0 && static_cast<std::size_t>(nd.skin) >= ctx.m.skins.size()) ctx.error(p + ".skin", "index out of range");
    if (nd.camera >= 0 && static_cast<std::size_t>(nd.camera) >= ctx.m.cameras.size()) ctx.error(p + ".camera", "index out of range");
    if (nd.skin >= 0 && nd.mesh < 0) ctx.error(p + ".skin", "a skin needs a mesh on the same node");
    int light = node_light(ctx.m, i);
    if (light < -1 || light >= static_cast<int>(ctx.m.lights.size())) ctx.error(p + ".extensions.KHR_lights_punctual.light", "index out of range");
    for (double w : nd.weights) {
      if (!std::isfinite(w)) ctx.error(p + ".weights", "non-finite morph weight");
    }
  }
  // Loops: walking up the parents from any node must end within n steps.
  for (std::size_t i = 0; i < n; ++i) {
    int cur = static_cast<int>(i);
    std::size_t steps = 0;
    while (cur >= 0 && steps <= n) cur = ctx.parent[static_cast<std::size_t>(cur)], ++steps;
    if (cur >= 0 || in_loop[i]) {
      in_loop[i] = 1;
      ctx.error(idx("nodes", i), "node is part of a node loop (a node is its own ancestor)");
    }
  }
}


int node_light(const tinygltf::Model& m, std::size_t i) {
  const auto& ext = m.nodes[i].extensions;
  auto it = ext.find("KHR_lights_punctual");
  if (it == ext.end() || !it->second.IsObject() || !it->second.Has("light")) return -1;
  const auto& l = it->second.Get("light");
  if (!l.IsNumber() && !l.IsInt()) return -2;
  return static_cast<int>(l.GetNumberAsInt());
}

bool decompose(const std::vector<double>& mm, glm::vec3& t, glm::quat& r, glm::vec3& s, std::string& why) {
  glm::dmat4 m;
  for (int c = 0; c < 4; ++c) {
    for (int k = 0; k < 4; ++k) m[c][k] = mm[std::size_t(c * 4 + k)];
  }
  if (std::abs(m[0][3]) > 1e-6 || std::abs(m[1][3]) > 1e-6 || std::abs(m[2][3]) > 1e-6 || std::abs(m[3][3] - 1.0) > 1e-6) {
    why = "last row must be 0 0 0 1";
    return false;
  }
  t = glm::vec3(m[3]);
  glm::dvec3 cols[3] = {glm::dvec3(m[0]), glm::dvec3(m[1]), glm::dvec3(m[2])};
  glm::dvec3 sc(glm::length(cols[0]), glm::length(cols[1]), glm::length(cols[2]));
  if (sc.x < 1e-12 || sc.y < 1e-12 || sc.z < 1e-12) {
    why = "zero scale axis";
    return false;
  }
  double det = glm::determinant(glm::dmat3(cols[0], cols[1], cols[2]));
  if (det < 0) sc.x = -sc.x;
  glm::dmat3 rot(cols[0] / sc.x, cols[1] / sc.y, cols[2] / sc.z);
  // Shear: the normalised axes must be orthogonal.
  if (std::abs(glm::dot(rot[0], rot[1])) > 1e-4 || std::abs(glm::dot(rot[0], rot[2])) > 1e-4 ||
      std::abs(glm::dot(rot[1], rot[2])) > 1e-4) {
    why = "axes are not orthogonal (shear)";
    return false;
  }
  s = glm::vec3(sc);
  r = glm::normalize(glm::quat(glm::quat_cast(rot)));
  return true;
}


// Nodes: all of them (indices stay glTF indices); the roots are the default scene's.
void convert_nodes(const ConvertContext& ctx, Scene& s) {
  for (std::size_t i = 0; i < ctx.m.nodes.size(); ++i) {
    const auto& nd = ctx.m.nodes[i];
    Node out;
    out.name = nd.name.empty() ? "node" + std::to_string(i) : nd.name;
    out.parent = ctx.parent[i];
    out.children = nd.children;
    if (nd.matrix.size() == 16) {
      std::string why;
      decompose(nd.matrix, out.translation, out.rotation, out.scale, why);
    } else {
      if (nd.translation.size() == 3) out.translation = glm::vec3(nd.translation[0], nd.translation[1], nd.translation[2]);
      if (nd.rotation.size() == 4) out.rotation = glm::normalize(glm::quat(float(nd.rotation[3]), float(nd.rotation[0]), float(nd.rotation[1]), float(nd.rotation[2])));
      if (nd.scale.size() == 3) out.scale = glm::vec3(nd.scale[0], nd.scale[1], nd.scale[2]);
    }
    out.mesh = nd.mesh;
    out.camera = nd.camera;
    out.light = node_light(ctx.m, i);
    out.skin = nd.skin;
    for (double w : nd.weights) out.weights.push_back(static_cast<float>(w));
    if (out.weights.empty() && out.mesh >= 0) out.weights = s.meshes[static_cast<std::size_t>(out.mesh)].weights;
    s.nodes.push_back(std::move(out));
  }
  if (!ctx.m.scenes.empty()) {
    s.roots = ctx.m.scenes[static_cast<std::size_t>(ctx.m.defaultScene >= 0 ? ctx.m.defaultScene : 0)].nodes;
  } else {
    for (std::size_t i = 0; i < ctx.m.nodes.size(); ++i) {
      if (ctx.parent[i] < 0) s.roots.push_back(static_cast<int>(i));
    }
  }
}

}  // namespace meter::convert
