#include "meter/engine/evaluation/scene_evaluator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/gtc/matrix_transform.hpp>

namespace meter::engine {

int find_camera_node(const Scene& scene) {
  for (std::size_t i = 0; i < scene.nodes.size(); ++i) {
    const Node& n = scene.nodes[i];
    if (n.camera < 0) continue;
    if (scene.config.camera.empty() || n.name == scene.config.camera ||
        scene.cameras[static_cast<std::size_t>(n.camera)].name == scene.config.camera)
      return static_cast<int>(i);
  }
  return -1;
}

glm::vec4 effective_base_color(const Scene& scene, const BindingOutputs& outputs, int material) {
  const auto mi = static_cast<std::size_t>(material);
  return outputs.base_color.size() > mi && outputs.base_color[mi] ? *outputs.base_color[mi] : scene.materials[mi].base_color;
}

glm::vec3 effective_emissive(const Scene& scene, const BindingOutputs& outputs, int material) {
  const auto mi = static_cast<std::size_t>(material);
  return outputs.emissive.size() > mi && outputs.emissive[mi] ? *outputs.emissive[mi] : scene.materials[mi].emissive;
}

std::vector<float> morph_weights(const std::vector<float>& pose_weights, const std::vector<MorphOverride>& morph, int node) {
  std::vector<float> w = pose_weights;
  for (const auto& m : morph) {
    if (m.node != node || m.target < 0) continue;
    const auto t = static_cast<std::size_t>(m.target);
    if (t >= w.size()) w.resize(t + 1, 0.0f);
    w[t] = m.weight;
  }
  return w;
}

namespace {
std::vector<char> visibility_in(const NodeOrder& order, std::size_t nodes, const std::vector<signed char>& node_visible) {
  std::vector<char> visible(nodes, 1);
  for (int n : order.preorder) {
    const auto i = static_cast<std::size_t>(n);
    const int p = order.parent[i];
    const bool parent_visible = p < 0 || visible[static_cast<std::size_t>(p)];
    visible[i] = parent_visible && (i >= node_visible.size() || node_visible[i] != 0);
  }
  return visible;
}
}  // namespace

std::vector<char> effective_visibility(const Scene& scene, const std::vector<signed char>& node_visible) {
  return visibility_in(NodeOrder::of(scene), scene.nodes.size(), node_visible);
}

SceneEvaluator::SceneEvaluator(const Scene& scene)
    : scene_(scene), order_(NodeOrder::of(scene)), pose_(Pose::rest(scene)), camera_node_(find_camera_node(scene)),
      light_nodes_(light_order(scene)) {
  anim_time_.assign(scene.animations.size(), std::nan(""));
  visible_.assign(scene.nodes.size(), 1);
  apply(resting_outputs(scene));
}

int SceneEvaluator::apply(const BindingOutputs& o) {
  int sampled = 0;
  std::vector<int> touched;
  for (std::size_t a = 0; a < scene_.animations.size() && a < o.animation_time.size(); ++a) {
    if (anim_time_[a] == o.animation_time[a]) continue;
    anim_time_[a] = o.animation_time[a];
    apply_animation(scene_, static_cast<int>(a), anim_time_[a], pose_, &touched);
    ++sampled;
  }
  animation_samples_ += static_cast<std::uint64_t>(sampled);
  if (!touched.empty() || o.transforms != outputs_.transforms) world_dirty_ = true;
  visible_ = visibility_in(order_, scene_.nodes.size(), o.node_visible);
  outputs_ = o;
  return sampled;
}

bool SceneEvaluator::update_world() {
  if (!world_dirty_) return false;
  if (outputs_.transforms.empty()) {
    world_matrices(scene_, order_, pose_, world_);
  } else {  // scripts' translations / rotations replace the animated (or rest) local values
    Pose posed = pose_;
    for (const auto& t : outputs_.transforms) {
      if (t.node < 0 || static_cast<std::size_t>(t.node) >= posed.translation.size()) continue;
      if (t.translation) posed.translation[static_cast<std::size_t>(t.node)] = *t.translation;
      if (t.rotation) posed.rotation[static_cast<std::size_t>(t.node)] = *t.rotation;
    }
    world_matrices(scene_, order_, posed, world_);
  }
  world_dirty_ = false;
  return true;
}

glm::mat4 SceneEvaluator::view_projection(int width, int height, glm::vec3* eye) const {
  const float aspect = float(width) / float(height);
  if (camera_node_ >= 0) {
    const Camera& c = scene_.cameras[static_cast<std::size_t>(scene_.nodes[static_cast<std::size_t>(camera_node_)].camera)];
    glm::mat4 w = world_[static_cast<std::size_t>(camera_node_)];
    // Cameras ignore scale (glTF): orthonormalise the axes.
    for (int k = 0; k < 3; ++k) w[k] = glm::vec4(glm::normalize(glm::vec3(w[k])), 0.0f);
    if (eye) *eye = glm::vec3(w[3]);
    glm::mat4 view = glm::inverse(w);
    glm::mat4 proj;
    if (c.perspective) {
      proj = c.zfar > 0 ? glm::perspective(c.yfov, aspect, c.znear, c.zfar) : glm::infinitePerspective(c.yfov, aspect, c.znear);
    } else {
      proj = glm::ortho(-c.xmag, c.xmag, -c.ymag, c.ymag, c.znear, c.zfar);
    }
    return proj * view;
  }
  // No camera in the scene: frame the bounds of everything drawn, looking down -Z.
  glm::vec3 lo(std::numeric_limits<float>::max()), hi(-std::numeric_limits<float>::max());
  for (const auto& d : scene_.draws) {
    const Primitive& prim = scene_.meshes[static_cast<std::size_t>(d.mesh)].primitives[static_cast<std::size_t>(d.primitive)];
    const glm::mat4& w = world_[static_cast<std::size_t>(d.node)];
    for (int k = 0; k < 8; ++k) {
      glm::vec3 p((k & 1) ? prim.bounds_max.x : prim.bounds_min.x, (k & 2) ? prim.bounds_max.y : prim.bounds_min.y,
                  (k & 4) ? prim.bounds_max.z : prim.bounds_min.z);
      glm::vec3 q(w * glm::vec4(p, 1.0f));
      lo = glm::min(lo, q), hi = glm::max(hi, q);
    }
  }
  if (scene_.draws.empty()) lo = glm::vec3(-1.0f), hi = glm::vec3(1.0f);
  const glm::vec3 centre = (lo + hi) * 0.5f;
  const float radius = std::max(1e-3f, glm::length(hi - lo) * 0.5f);
  const float yfov = 0.8f;
  const float dist = radius / std::sin(yfov * 0.5f) * 1.05f;
  const glm::vec3 e = centre + glm::vec3(0.0f, 0.0f, dist);
  if (eye) *eye = e;
  return glm::perspective(yfov, aspect, std::max(1e-3f, dist - radius * 2.0f), dist + radius * 2.0f) *
         glm::lookAt(e, centre, glm::vec3(0.0f, 1.0f, 0.0f));
}

glm::vec2 SceneEvaluator::project(int node, const glm::mat4& vp, int width, int height) const {
  if (node < 0 || static_cast<std::size_t>(node) >= world_.size()) return glm::vec2(0.0f);
  glm::vec4 clip = vp * glm::vec4(glm::vec3(world_[static_cast<std::size_t>(node)][3]), 1.0f);
  if (std::abs(clip.w) < 1e-9f) return glm::vec2(-1e6f);
  glm::vec2 ndc(clip.x / clip.w, clip.y / clip.w);
  return glm::vec2((ndc.x * 0.5f + 0.5f) * float(width), (1.0f - (ndc.y * 0.5f + 0.5f)) * float(height));
}

DrawState SceneEvaluator::draw_state(std::size_t i) const {
  const DrawItem& d = scene_.draws[i];
  const Primitive& prim = scene_.meshes[static_cast<std::size_t>(d.mesh)].primitives[static_cast<std::size_t>(d.primitive)];
  const auto node_index = static_cast<std::size_t>(d.node);
  const Node& node = scene_.nodes[node_index];
  DrawState s;
  s.visible = visible_[node_index] != 0;
  s.world = world_[node_index];
  s.base = effective_base_color(scene_, outputs_, prim.material);
  s.emissive = effective_emissive(scene_, outputs_, prim.material);
  s.exposure = static_cast<float>(std::exp2(outputs_.exposure.value_or(scene_.config.exposure)));
  if (node.skin >= 0) {
    for (int j : scene_.skins[static_cast<std::size_t>(node.skin)].joints) {
      const glm::mat4& jw = world_[static_cast<std::size_t>(j)];
      s.deform.insert(s.deform.end(), &jw[0][0], &jw[0][0] + 16);
    }
  }
  if (prim.morph_targets > 0) {
    s.deform.insert(s.deform.end(), pose_.weights[node_index].begin(), pose_.weights[node_index].end());
    for (const auto& m : outputs_.morph)
      if (m.node == d.node) s.deform.insert(s.deform.end(), {float(m.target), m.weight});
    s.morph_weights = morph_weights(pose_.weights[node_index], outputs_.morph, d.node);
  }
  return s;
}

FrameState SceneEvaluator::evaluate(int width, int height, TextMeasure& measure) const {
  FrameState f;
  f.view_projection = view_projection(width, height, &f.eye);
  f.world = world_;
  f.visible = visible_;
  f.draws.reserve(scene_.draws.size());
  for (std::size_t i = 0; i < scene_.draws.size(); ++i) f.draws.push_back(draw_state(i));
  for (int n : light_nodes_) f.lights.emplace_back(n, world_[static_cast<std::size_t>(n)]);
  for (const auto& t : outputs_.texts) {
    const bool drawable = t.node >= 0 && static_cast<std::size_t>(t.node) < visible_.size() &&
                          visible_[static_cast<std::size_t>(t.node)] && !t.text.empty();
    if (!drawable) continue;
    const glm::vec2 p = project(t.node, f.view_projection, width, height);
    TextState s{t, static_cast<int>(std::lround(p.x)), static_cast<int>(std::lround(p.y)), {}};
    const platform::PixelRegion ink = measure.ink(t, s.x, s.y);
    // 2 px: glyph quads are placed at whole pixels but their edges are antialiased (linear filter).
    constexpr int kPad = 2;
    if (!ink.empty())
      s.box = {ink.x - kPad, height - (ink.y + ink.height) - kPad, ink.width + 2 * kPad, ink.height + 2 * kPad};
    f.texts.push_back(std::move(s));
  }
  return f;
}

}  // namespace meter::engine
