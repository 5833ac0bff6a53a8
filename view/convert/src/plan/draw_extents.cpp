// Where each would-be draw can be on screen and in depth over the whole range of every animation:
// the input of the mesh concatenation planner's overlap and draw-order checks.
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include <glm/gtc/matrix_transform.hpp>

#include "meter/convert/concat_plan.hpp"
#include "meter/engine/evaluation/animation.hpp"
#include "meter/engine/evaluation/scene_evaluator.hpp"

namespace meter::convert {

using bridge::AlphaMode;
using engine::Pose;

namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// The runtime's camera (engine::find_camera_node) with the projection of
// SceneEvaluator::view_projection at the config's size (a scene without a camera gets no screen
// test: the 3D x/y extents are compared instead, which is stricter for a front view).
bool camera_vp(const Scene& s, const std::vector<glm::mat4>& world, glm::mat4& vp) {
  const int node = engine::find_camera_node(s);
  if (node < 0) return false;
  const auto i = static_cast<std::size_t>(node);
  const Camera& c = s.cameras[static_cast<std::size_t>(s.nodes[i].camera)];
  glm::mat4 w = world[i];
  for (int k = 0; k < 3; ++k) w[k] = glm::vec4(glm::normalize(glm::vec3(w[k])), 0.0f);
  const float aspect = float(s.config.size[0]) / float(s.config.size[1]);
  glm::mat4 proj = c.perspective ? (c.zfar > 0 ? glm::perspective(c.yfov, aspect, c.znear, c.zfar) : glm::infinitePerspective(c.yfov, aspect, c.znear))
                                 : glm::ortho(-c.xmag, c.xmag, -c.ymag, c.ymag, c.znear, c.zfar);
  vp = proj * glm::inverse(w);
  return true;
}

// The sample times of animation a: every key and 8 steps inside each key interval.
std::vector<double> sample_times(const Animation& a) {
  std::set<double> t;
  for (const auto& sm : a.samplers) {
    for (std::size_t k = 0; k < sm.input.size(); ++k) {
      t.insert(sm.input[k]);
      if (k + 1 < sm.input.size()) {
        for (int j = 1; j < 8; ++j) t.insert(sm.input[k] + (sm.input[k + 1] - sm.input[k]) * j / 8.0);
      }
    }
  }
  return {t.begin(), t.end()};
}

}  // namespace

std::vector<DrawExtent> draw_extents(const Scene& s) {
  // Draw order = node_preorder, primitives in order (as generate_programs emits the draws).
  std::vector<DrawExtent> out;
  for (const int n : node_preorder(s)) {
    const Node& node = s.nodes[static_cast<std::size_t>(n)];
    if (node.mesh < 0) continue;
    const Mesh& mesh = s.meshes[static_cast<std::size_t>(node.mesh)];
    for (std::size_t p = 0; p < mesh.primitives.size(); ++p) {
      DrawExtent e;
      e.node = n, e.primitive = static_cast<int>(p);
      e.blend = s.materials[static_cast<std::size_t>(mesh.primitives[p].material)].alpha == AlphaMode::Blend;
      e.screen_min = glm::vec2(kInf), e.screen_max = glm::vec2(-kInf);
      e.depth_min = e.key_min = kInf, e.depth_max = e.key_max = -kInf;
      out.push_back(e);
    }
  }
  // Poses to evaluate: rest + every animation at its start, then each animation swept with the
  // others at their start and at their end.
  const std::size_t na = s.animations.size();
  std::vector<double> start(na), end(na);
  for (std::size_t a = 0; a < na; ++a) start[a] = s.animations[a].start, end[a] = s.animations[a].end;
  const engine::NodeOrder order = engine::NodeOrder::of(s);  // the same for every pose
  std::vector<glm::mat4> world, last_world;  // a pose's world matrices; the last accumulated pose's
  glm::mat4 last_vp(1.0f);
  bool last_cam = false;
  auto accumulate = [&](const std::vector<glm::mat4>& world) {
    glm::mat4 vp(1.0f);
    const bool cam = camera_vp(s, world, vp);
    const float w = float(s.config.size[0]), h = float(s.config.size[1]);
    // A draw whose world matrix and camera are bit for bit those of the pose accumulated last adds
    // exactly the points it added then (min/max of the same values): skipped. An animation sweep
    // moves a few nodes, so most draws are skipped (NaN never compares equal, so it is never skipped).
    const bool same_camera = !last_world.empty() && cam == last_cam && vp == last_vp;
    for (auto& e : out) {
      const Primitive& prim = s.meshes[static_cast<std::size_t>(s.nodes[static_cast<std::size_t>(e.node)].mesh)].primitives[static_cast<std::size_t>(e.primitive)];
      const glm::mat4 m = world[static_cast<std::size_t>(e.node)];
      if (same_camera && m == last_world[static_cast<std::size_t>(e.node)]) continue;
      for (int k = 0; k < 8; ++k) {
        glm::vec3 p((k & 1) ? prim.bounds_max.x : prim.bounds_min.x, (k & 2) ? prim.bounds_max.y : prim.bounds_min.y,
                    (k & 4) ? prim.bounds_max.z : prim.bounds_min.z);
        glm::vec4 wp = m * glm::vec4(p, 1.0f);
        glm::vec2 sp;
        float depth;
        if (cam) {
          glm::vec4 c = vp * wp;
          // Behind the eye: the projection is meaningless, take the whole screen.
          if (c.w <= 1e-6f) {
            sp = glm::vec2(-kInf);
            e.screen_min = glm::vec2(-kInf), e.screen_max = glm::vec2(kInf);
          } else {
            sp = glm::vec2((c.x / c.w * 0.5f + 0.5f) * w, (c.y / c.w * 0.5f + 0.5f) * h);
          }
          depth = c.w;
        } else {
          sp = glm::vec2(wp.x, wp.y);
          depth = -wp.z;
        }
        if (std::isfinite(sp.x)) e.screen_min = glm::min(e.screen_min, sp), e.screen_max = glm::max(e.screen_max, sp);
        e.depth_min = std::min(e.depth_min, depth), e.depth_max = std::max(e.depth_max, depth);
      }
      const glm::vec3 c = (prim.bounds_min + prim.bounds_max) * 0.5f;
      const float key = cam ? (vp * m * glm::vec4(c, 1.0f)).w : 0.0f;
      e.key_min = std::min(e.key_min, key), e.key_max = std::max(e.key_max, key);
    }
    last_world = world;
    last_vp = vp, last_cam = cam;
  };
  // World matrices of a pose that differs from `base` (whose matrices are base_world) only in the
  // nodes animation a moves: those nodes and their descendants are recomputed as world_matrices
  // computes them (parent first, the same products), the rest are base_world's.
  std::vector<glm::mat4> base_world;
  std::vector<char> moved;  // per node: animation a moves it or an ancestor
  auto mark_moved = [&](std::size_t a) {
    moved.assign(s.nodes.size(), 0);
    for (const auto& ch : s.animations[a].channels) {
      if (ch.node >= 0) moved[static_cast<std::size_t>(ch.node)] = 1;
    }
    for (const int n : order.preorder) {
      const int parent = order.parent[static_cast<std::size_t>(n)];
      if (parent >= 0 && moved[static_cast<std::size_t>(parent)]) moved[static_cast<std::size_t>(n)] = 1;
    }
  };
  auto moved_world = [&](const Pose& pose) -> const std::vector<glm::mat4>& {
    world = base_world;
    for (const int n : order.preorder) {
      const auto i = static_cast<std::size_t>(n);
      if (!moved[i]) continue;
      const int parent = order.parent[i];
      const glm::mat4 local = engine::local_matrix(pose.translation[i], pose.rotation[i], pose.scale[i]);
      world[i] = parent >= 0 ? world[static_cast<std::size_t>(parent)] * local : glm::mat4(1.0f) * local;
    }
    return world;
  };
  for (int others = 0; others < 2; ++others) {
    Pose base = Pose::rest(s);
    for (std::size_t a = 0; a < na; ++a) engine::apply_animation(s, static_cast<int>(a), others ? end[a] : start[a], base);
    engine::world_matrices(s, order, base, base_world);
    if (na == 0 || others == 0) accumulate(base_world);
    for (std::size_t a = 0; a < na; ++a) {
      mark_moved(a);
      for (double t : sample_times(s.animations[a])) {
        Pose p = base;
        engine::apply_animation(s, static_cast<int>(a), t, p);
        accumulate(moved_world(p));
      }
    }
  }
  // Half a pixel of margin: anti-aliased edges and MSAA samples reach that far past the geometry.
  for (auto& e : out) e.screen_min -= glm::vec2(0.5f), e.screen_max += glm::vec2(0.5f);
  return out;
}

}  // namespace meter::convert
